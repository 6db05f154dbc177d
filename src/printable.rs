//! User text as an error message shows it: on one line, with control
//! characters (newlines, terminal escapes) escaped, and cut short with "…".
//! A name or path comes from the user and may hold anything.

use std::path::Path;

/// Characters of one name or path that a message shows at most.
pub const MAX_CHARS: usize = 200;

/// Characters of a whole message line at most.
pub const MAX_MESSAGE_CHARS: usize = 1000;

/// `s` escaped and cut to `MAX_CHARS`.
pub fn text(s: &str) -> String {
    cut(s, MAX_CHARS)
}

fn cut(s: &str, max: usize) -> String {
    let mut out = String::new();
    for (i, c) in s.chars().enumerate() {
        if i == max {
            out.push('…');
            break;
        }
        if c.is_control() || reorders(c) {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    out
}

/// Whether `c` is one of Unicode's invisible direction marks and
/// overrides (U+061C, U+200E–U+200F, U+202A–U+202E, U+2066–U+2069), which
/// a terminal obeys: a name holding U+202E would print the rest of the
/// message backwards.
fn reorders(c: char) -> bool {
    matches!(c, '\u{061c}' | '\u{200e}'..='\u{200f}' | '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}')
}

/// A path as `text` shows it.
pub fn path(p: &Path) -> String {
    text(&p.to_string_lossy())
}

/// A number as a message shows it: as Rust writes it where that is short,
/// in exponent form past it (at or above 1e6, below 1e-4), so that a
/// `radius = -1e300` is "-1e300" in its error, not 301 digits.
pub fn number<T>(v: T) -> String
where
    T: Copy + Into<f64> + std::fmt::Display + std::fmt::LowerExp,
{
    let size = v.into().abs();
    if size.is_finite() && size != 0.0 && !(1e-4..1e6).contains(&size) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// Numbers as a message shows a list of them: `[1, -1e300, 0.5]`, each
/// as [`number`] writes it.
pub fn numbers(values: &[f64]) -> String {
    let shown: Vec<String> = values.iter().map(|&v| number(v)).collect();
    format!("[{}]", shown.join(", "))
}

/// A message that may span lines, on one line, cut to `MAX_MESSAGE_CHARS`:
/// the names and paths in it are already cut to `MAX_CHARS` each, so a long
/// name does not push out what the message says is wrong.
pub fn one_line(s: &str) -> String {
    cut(
        &s.trim()
            .lines()
            .map(str::trim)
            .collect::<Vec<_>>()
            .join("; "),
        MAX_MESSAGE_CHARS,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn control_characters_are_escaped_and_long_text_is_cut() {
        assert_eq!(text("a\nb\u{1b}[31m"), "a\\nb\\u{1b}[31m");
        assert_eq!(text("ab\u{202e}cd"), "ab\\u{202e}cd");
        assert_eq!(text("\u{2066}x\u{200f}"), "\\u{2066}x\\u{200f}");
        assert_eq!(text("résumé ✓"), "résumé ✓");
        let long = "x".repeat(1_000_000);
        let shown = text(&long);
        assert_eq!(shown.chars().count(), MAX_CHARS + 1);
        assert!(shown.ends_with('…'));
        assert_eq!(
            one_line("invalid table header\nexpected `.`, `]`\n"),
            "invalid table header; expected `.`, `]`"
        );
        let message = format!("material \"{}\": Kd must be finite", text(&long));
        assert!(one_line(&message).ends_with("\": Kd must be finite"));
        assert_eq!(one_line(&long).chars().count(), MAX_MESSAGE_CHARS + 1);
    }

    #[test]
    fn numbers_past_a_few_digits_are_in_exponent_form() {
        assert_eq!(number(-1e300), "-1e300");
        assert_eq!(number(-1e-300), "-1e-300");
        assert_eq!(number(1.5e7), "1.5e7");
        assert_eq!(number(0.25), "0.25");
        assert_eq!(number(-3.0), "-3");
        assert_eq!(number(0.0), "0");
        assert_eq!(number(123456.5), "123456.5");
        assert_eq!(number(f64::NAN), "NaN");
        assert_eq!(number(f64::NEG_INFINITY), "-inf");
        assert_eq!(number(1e30f32), "1e30");
        assert_eq!(number(0.1f32), "0.1");
        assert!(number(f64::MIN_POSITIVE / 3.0).len() < 30);
        assert_eq!(numbers(&[1.0, -1e300, 0.5]), "[1, -1e300, 0.5]");
    }
}
