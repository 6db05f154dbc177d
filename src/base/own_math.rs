//! glint's own atan2 and asin in f32, as shaders/own_math.glsl computes
//! them, operation for operation: the CPU reference's f32 follows the
//! shader, and the f64 oracle takes the exact functions (`Real::atan2_shader`).
//! A driver's atan and asin may be 4096 ULP off (the Vulkan spec); these
//! are within about 4 ULP (docs/guarantees.md; tests/own_math.rs).

use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI};

/// tan(π/8), where atan's argument is reduced to.
const TAN_PI_8: f32 = 0.414_213_57;

/// atan(t) = t + t·s·P(s), s = t², |t| ≤ tan(π/8) (benches/own_math_fit.py).
fn atan_poly(s: f32) -> f32 {
    -0.333_333_3 + s * (0.199_995_49 + s * (-0.142_641_74 + s * (0.107_456_71 + s * -0.064_574_24)))
}

/// asin(a) = a + a·s·Q(s), s = a², a ≤ ½ (benches/own_math_fit.py).
fn asin_poly(s: f32) -> f32 {
    0.166_666_66
        + s * (0.075_000_99
            + s * (0.044_598_1 + s * (0.031_115_372 + s * (0.017_081_447 + s * 0.033_800_017))))
}

/// atan(y / x) in the quadrant of (x, y), signed zeros as `f32::atan2`.
pub fn atan2(y: f32, x: f32) -> f32 {
    let (ax, ay) = (x.abs(), y.abs());
    let (hi, lo) = (ax.max(ay), ax.min(ay));
    let (t, base) = if lo > TAN_PI_8 * hi {
        ((lo - hi) / (lo + hi), FRAC_PI_4)
    } else if hi > 0.0 {
        (lo / hi, 0.0)
    } else {
        (0.0, 0.0)
    };
    let s = t * t;
    let mut r = base + (t + t * s * atan_poly(s));
    if ay > ax {
        r = FRAC_PI_2 - r;
    }
    if x.is_sign_negative() {
        r = PI - r;
    }
    if y.is_sign_negative() {
        -r
    } else {
        r
    }
}

/// asin(y) for y in [−1, 1].
pub fn asin(y: f32) -> f32 {
    let a = y.abs();
    let r = if a <= 0.5 {
        let s = a * a;
        a + a * s * asin_poly(s)
    } else {
        // asin(a) = π/2 − 2·asin(w), w = √((1 − a)/2) ≤ ½; 1 − a is exact
        // here (Sterbenz).
        let s = (1.0 - a) * 0.5;
        let w = s.sqrt();
        FRAC_PI_2 - 2.0 * (w + w * s * asin_poly(s))
    };
    if y.is_sign_negative() {
        -r
    } else {
        r
    }
}

#[cfg(test)]
mod tests {
    /// The error in ULP of the f32 result against f64's: in units of the
    /// spacing of f32 at the exact value.
    fn ulps(got: f32, exact: f64) -> f64 {
        let e = exact.abs().max(f64::from(f32::MIN_POSITIVE)).log2().floor() as i32;
        (f64::from(got) - exact).abs() / 2f64.powi(e - 23)
    }

    fn sweep() -> impl Iterator<Item = f32> {
        // Every 4097th float of [-1, 1] and some edges.
        (0..=0x3f80_0000u32)
            .step_by(4097)
            .flat_map(|b| [f32::from_bits(b), -f32::from_bits(b)])
            .chain([0.5, -0.5, 1.0, -1.0, 0.499_999_97, 0.500_000_06])
    }

    #[test]
    fn asin_is_within_4_ulp_of_f64_over_its_range() {
        let worst = sweep()
            .map(|y| ulps(super::asin(y), f64::from(y).asin()))
            .fold(0.0, f64::max);
        assert!(worst <= 4.0, "asin is {worst} ULP off");
        assert!(worst > 0.0);
    }

    #[test]
    fn atan2_is_within_4_ulp_of_f64_around_the_circle() {
        let mut worst: f64 = 0.0;
        for i in 0..200_000u32 {
            let a = f64::from(i) / 200_000.0 * std::f64::consts::TAU;
            for scale in [1.0f64, 1e-30, 3e20] {
                let (y, x) = ((a.sin() * scale) as f32, (a.cos() * scale) as f32);
                let exact = f64::from(y).atan2(f64::from(x));
                worst = worst.max(ulps(super::atan2(y, x), exact));
            }
        }
        assert!(worst <= 4.0, "atan2 is {worst} ULP off");
    }

    #[test]
    fn atan2_keeps_the_signed_zeros_of_the_c_library() {
        for (y, x) in [
            (0.0f32, 0.0f32),
            (-0.0, 0.0),
            (0.0, -0.0),
            (-0.0, -0.0),
            (0.0, -1.0),
            (-0.0, -1.0),
        ] {
            assert_eq!(
                super::atan2(y, x).to_bits(),
                y.atan2(x).to_bits(),
                "atan2({y}, {x})"
            );
        }
    }
}
