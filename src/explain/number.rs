//! Numbers as an explanation prints them: seven significant digits, enough
//! to tell f32 neighbours apart.

/// `v` to seven significant digits.
pub fn show(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let a = v.abs();
    if (1e-4..1e7).contains(&a) {
        let decimals = (6 - a.log10().floor() as i32).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.6e}")
    }
}

/// Two numbers to as many significant digits as tell them apart (seven
/// at least, seventeen at most).
pub fn show_apart(a: f64, b: f64) -> (String, String) {
    for digits in 7..=17 {
        let (x, y) = (
            format!("{a:.*e}", digits - 1),
            format!("{b:.*e}", digits - 1),
        );
        if x != y || digits == 17 {
            return if digits == 7 {
                (show(a), show(b))
            } else {
                (x, y)
            };
        }
    }
    unreachable!("the loop returns at 17 digits")
}

/// One number, or a vector's in parentheses.
pub fn show_all(v: &[f64]) -> String {
    match v {
        [x] => show(*x),
        _ => format!(
            "({})",
            v.iter().map(|x| show(*x)).collect::<Vec<_>>().join(", ")
        ),
    }
}

/// The largest magnitude among `v`'s components.
pub fn largest(v: &[f64]) -> f64 {
    v.iter().map(|x| x.abs()).fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    #[test]
    fn seven_digits_whatever_the_size() {
        assert_eq!(super::show(3.0000012), "3.000001");
        assert_eq!(super::show(-0.25), "-0.2500000");
        assert_eq!(super::show(1.2e-7), "1.200000e-7");
        assert_eq!(
            super::show_all(&[1.0, 0.0, 2.5e8]),
            "(1.000000, 0, 2.500000e8)"
        );
        assert_eq!(
            super::show_apart(4.0024971, 4.00249712),
            ("4.00249710e0".to_owned(), "4.00249712e0".to_owned())
        );
        assert_eq!(
            super::show_apart(3.0, 2.5),
            ("3.000000".to_owned(), "2.500000".to_owned())
        );
    }
}
