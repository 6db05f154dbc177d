//! A bound on what the shader's `#define`s can expand to, checked before
//! glslang preprocesses them: glslang has no bound of its own, and forty
//! lines of `#define A1 A0 A0`, `#define A2 A1 A1`, … expand to 2^40 tokens,
//! which it tries to build in memory. And a bound on the whole compile:
//! glslang took 2.35 GB and 10 s for a 16 MB include of straight-line
//! arithmetic, so the text of every file read, each macro use counted at
//! what it expands to, is held to `MAX_EXPANSION` (about 0.5 GB and 2.5 s of
//! glslang here at the bound).

use std::collections::HashMap;

/// The most bytes one compile's sources may expand to, and so one macro:
/// glint's own generic shader is about 150 KB, its largest macro a few
/// kilobytes.
pub const MAX_EXPANSION: u64 = 512 << 10;

/// The object- and function-like macros of the files read so far, each as
/// its body's identifiers and the bytes of everything else.
#[derive(Default)]
pub struct Macros {
    bodies: HashMap<String, (Vec<String>, u64)>,
    /// What the files read so far expand to, at most.
    expanded: u64,
}

impl Macros {
    /// Adds `text`'s `#define`s (a later one replaces an earlier one of its
    /// name, wherever conditionals would have taken it), and fails where one
    /// of them would expand past `MAX_EXPANSION`, naming it and `file`.
    pub fn add(&mut self, file: &str, text: &str) -> Result<(), String> {
        let joined = text.replace("\\\r\n", " ").replace("\\\n", " ");
        let mut added = Vec::new();
        for line in joined.lines() {
            let Some(rest) = line.trim_start().strip_prefix('#') else {
                continue;
            };
            let Some(rest) = rest.trim_start().strip_prefix("define") else {
                continue;
            };
            let (name, body) = split_define(rest);
            if name.is_empty() {
                continue;
            }
            let (idents, other) = tokens(body);
            self.bodies.insert(name.to_owned(), (idents, other));
            added.push(name.to_owned());
        }
        let mut memo = HashMap::new();
        for name in &added {
            let size = self.size(name, &mut memo, &mut Vec::new());
            if size > MAX_EXPANSION {
                return Err(format!(
                    "{file}: error: macro {} expands to {}, past the bound of {} KiB on what one \
                     macro may expand to",
                    crate::printable::text(name),
                    if size == u64::MAX {
                        "more than 2^64 bytes".to_owned()
                    } else {
                        format!("about {size} bytes")
                    },
                    MAX_EXPANSION >> 10
                ));
            }
        }
        // The text outside directives, each identifier at its expansion.
        drop(memo);
        let mut expanded = self.expanded;
        for line in joined.lines().filter(|l| !l.trim_start().starts_with('#')) {
            let (idents, other) = tokens(line);
            let mut memo = HashMap::new();
            let size = idents.iter().fold(other, |total, ident| {
                total.saturating_add(self.size(ident, &mut memo, &mut Vec::new()))
            });
            expanded = expanded.saturating_add(size);
        }
        self.expanded = expanded;
        if self.expanded > MAX_EXPANSION {
            return Err(format!(
                "{file}: error: the shader's sources, with this file, expand to about {} bytes, \
                 past the bound of {} KiB on one compile",
                self.expanded,
                MAX_EXPANSION >> 10
            ));
        }
        Ok(())
    }

    /// The bytes `name` expands to, its arguments taken as one byte each;
    /// a macro is not expanded within itself, as the preprocessor does not.
    fn size<'a>(
        &'a self,
        name: &'a str,
        memo: &mut HashMap<&'a str, u64>,
        open: &mut Vec<&'a str>,
    ) -> u64 {
        if let Some(&s) = memo.get(name) {
            return s;
        }
        let Some((idents, other)) = self.bodies.get(name) else {
            return name.len() as u64;
        };
        if open.contains(&name) {
            return name.len() as u64;
        }
        open.push(name);
        let mut total = *other;
        for ident in idents {
            total = total.saturating_add(self.size(ident, memo, open));
        }
        open.pop();
        memo.insert(name, total);
        total
    }
}

/// A `#define`'s name and body (past its parameter list, if any).
fn split_define(rest: &str) -> (&str, &str) {
    let rest = rest.trim_start();
    let end = rest
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .unwrap_or(rest.len());
    let (name, after) = rest.split_at(end);
    match after.strip_prefix('(') {
        Some(params) => (name, params.split_once(')').map_or("", |(_, b)| b)),
        None => (name, after),
    }
}

/// A body's identifiers, and the bytes of the rest.
fn tokens(body: &str) -> (Vec<String>, u64) {
    let mut idents = Vec::new();
    let mut other = 0u64;
    let mut word = String::new();
    for c in body.trim().chars().chain([' ']) {
        if c.is_ascii_alphanumeric() || c == '_' {
            word.push(c);
            continue;
        }
        if !word.is_empty() {
            if word.starts_with(|c: char| c.is_ascii_digit()) {
                other += word.len() as u64;
            } else {
                idents.push(std::mem::take(&mut word));
            }
            word.clear();
        }
        other += c.len_utf8() as u64;
    }
    (idents, other)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn doubling_defines_are_refused_and_ordinary_ones_pass() {
        let mut doubling = String::from("#define A0 x\n");
        for i in 1..=40 {
            doubling += &format!("#define A{i} A{} A{}\n", i - 1, i - 1);
        }
        let e = Macros::default().add("inc.glsl", &doubling).unwrap_err();
        assert!(e.starts_with("inc.glsl: error: macro A"), "{e}");
        assert!(e.contains("past the bound of 512 KiB"), "{e}");
        let mut ok = Macros::default();
        ok.add(
            "a.glsl",
            "#define SQ(x) ((x) * (x))\n#define TWO SQ(1) + SQ(2)\n",
        )
        .unwrap();
        // A macro that names itself is not expanded again.
        ok.add("b.glsl", "#define SELF SELF + 1\n").unwrap();
        // Across files: the second file's defines build on the first's.
        let half = doubling.find("#define A16 ").unwrap();
        let mut split = Macros::default();
        split.add("a.glsl", &doubling[..half]).unwrap();
        let e = split.add("b.glsl", &doubling[half..]).unwrap_err();
        assert!(e.starts_with("b.glsl: error: macro A"), "{e}");
    }
}
