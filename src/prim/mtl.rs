//! Reading an OBJ's MTL files within the OBJ's needs: a file of a million
//! materials is parsed one material at a time, each checked, and only the
//! materials the OBJ uses (its `usemtl` names) are kept (such a file used
//! to peak at 34–67× its size); and each material's values, checked, as
//! the scene takes them.

use std::collections::HashSet;
use std::io::BufRead;
use std::path::{Path, PathBuf};

use glam::DVec3;

use crate::input::error::SceneError;
use crate::input::field::At;

/// The material names an OBJ's `usemtl` lines give, as tobj reads them
/// (the rest of the line after the first space, trimmed).
pub fn used_names(obj: impl BufRead) -> HashSet<String> {
    obj.split(b'\n')
        .map_while(Result::ok)
        .filter_map(|line| {
            let line = String::from_utf8(line).ok()?;
            let mut words = line.split_whitespace();
            (words.next() == Some("usemtl"))
                .then(|| line.split_once(' ').map(|(_, n)| n.trim().to_owned()))
                .flatten()
        })
        .filter(|n| !n.is_empty())
        .collect()
}

/// One material's lines of an MTL file: from its `newmtl` line to the
/// next; `name` None for the lines before the first `newmtl`.
pub struct Block<'a> {
    pub name: Option<String>,
    pub text: &'a [u8],
}

/// The blocks of an MTL file, in order, each a slice of `text` (so their
/// lines and line numbers are the file's), one at a time: a file of a
/// million materials never holds a million names.
pub fn blocks(text: &[u8]) -> impl Iterator<Item = Block<'_>> {
    let mut lines = text.split_inclusive(|&b| b == b'\n');
    // The current block's start and name; `at`, the end of what is read.
    let (mut start, mut name, mut at, mut ended) = (0, None, 0, false);
    std::iter::from_fn(move || loop {
        let Some(line) = lines.next() else {
            if ended || (at == start && name.is_none()) {
                return None;
            }
            ended = true;
            return Some(Block {
                name: name.take(),
                text: &text[start..at],
            });
        };
        let here = at;
        at += line.len();
        if let Some(next) = newmtl(line) {
            let previous = name.replace(next);
            let done = (here > start || previous.is_some()).then(|| Block {
                name: previous,
                text: &text[start..here],
            });
            start = here;
            if done.is_some() {
                return done;
            }
        }
    })
}

/// The material a `newmtl` line names, as tobj reads it.
fn newmtl(line: &[u8]) -> Option<String> {
    let line = std::str::from_utf8(line).ok()?.trim();
    let first = line.split_whitespace().next()?;
    (first == "newmtl").then(|| line[6..].trim().to_owned())
}

/// One material of an OBJ's MTL file, its values checked (finite, colours
/// and Ns ≥ 0, Ni > 0, d in [0, 1]); the scene maps it onto its own
/// (docs/scene-format.md, Meshes).
#[derive(Debug, Clone, PartialEq)]
pub struct MtlMaterial {
    /// The MTL file and the material's name in it, for messages.
    pub name: String,
    pub ka: DVec3,
    pub kd: DVec3,
    pub ks: DVec3,
    /// The specular exponent; 1 where not given.
    pub ns: f64,
    /// The index of refraction; 1 where not given.
    pub ni: f64,
    /// The dissolve (opacity): `d`, or 1 − `Tr`; 1 where neither is given.
    pub d: f64,
    /// The illumination model, 0..=10; 2 where not given.
    pub illum: u8,
    /// `map_Kd`, `map_Ka`: image files (relative to the MTL file's folder
    /// as written) whose texels, times Kd and Ka, give those colours.
    pub map_kd: Option<PathBuf>,
    pub map_ka: Option<PathBuf>,
}

/// The first line of an MTL file whose colour (Ka, Kd, Ks, Ke) has fewer
/// than three values, which tobj cannot take: its number (from 1), its key
/// and how many values it has.
pub(super) fn short_colour_line(text: &[u8]) -> Option<(usize, &'static str, usize)> {
    text.split(|&b| b == b'\n')
        .enumerate()
        .find_map(|(i, line)| {
            let mut words = line
                .split(|b| b.is_ascii_whitespace())
                .filter(|w| !w.is_empty());
            let first = words.next()?;
            let key = ["Ka", "Kd", "Ks", "Ke"]
                .into_iter()
                .find(|k| k.as_bytes() == first)?;
            let n = words.take(3).count();
            (n < 3).then_some((i + 1, key, n))
        })
}

/// An MTL material's values, checked; `file`: the MTL file, for messages;
/// `dir`: its folder, which its maps' files are relative to.
pub(super) fn material(
    m: &tobj::Material,
    file: &str,
    dir: &Path,
    at: &At,
) -> Result<MtlMaterial, SceneError> {
    let name = crate::printable::text(&m.name);
    let bad = |what: &str, why: String| {
        at.invalid::<MtlMaterial>("file", format!("{file}: material \"{name}\": {what} {why}"))
    };
    let map = |what: &str, v: &Option<String>| -> Result<Option<PathBuf>, SceneError> {
        match v.as_deref().map(str::trim) {
            None => Ok(None),
            Some(f) if f.is_empty() || f.starts_with('-') => at.invalid(
                "file",
                format!(
                    "{file}: material \"{name}\": {what} \"{}\": glint reads a map's file name \
                     alone, without options",
                    crate::printable::text(f)
                ),
            ),
            Some(f) => Ok(Some(dir.join(f))),
        }
    };
    let map_kd = map("map_Kd", &m.diffuse_texture)?;
    let map_ka = map("map_Ka", &m.ambient_texture)?;
    let colour = |what: &str, v: Option<[f64; 3]>| -> Result<DVec3, SceneError> {
        let v = DVec3::from_array(v.unwrap_or_default());
        if !v.is_finite() || v.min_element() < 0.0 {
            bad(
                what,
                format!(
                    "must be finite and >= 0, got {}",
                    crate::printable::numbers(&v.to_array())
                ),
            )?;
        }
        Ok(v)
    };
    let number = |what: &str, v: f64, ok: bool| -> Result<f64, SceneError> {
        if !v.is_finite() || !ok {
            bad(
                what,
                format!("is out of range: {}", crate::printable::number(v)),
            )?;
        }
        Ok(v)
    };
    let ns = m.shininess.unwrap_or(1.0);
    let ns = number("Ns", ns, ns >= 0.0)?;
    let ni = m.optical_density.unwrap_or(1.0);
    let ni = number("Ni", ni, (1e-6..=1e6).contains(&ni))?;
    let tr = m.unknown_param.get("Tr").map(|t| t.trim().parse::<f64>());
    let d = match (m.dissolve, tr) {
        (Some(d), _) => d,
        (None, Some(Ok(tr))) => 1.0 - tr,
        (None, Some(Err(_))) => return bad("Tr", "is not a number".to_owned()),
        (None, None) => 1.0,
    };
    let d = number("d (or 1 - Tr)", d, (0.0..=1.0).contains(&d))?;
    let illum = m.illumination_model.unwrap_or(2);
    if illum > 10 {
        return bad("illum", format!("must be in 0..=10, got {illum}"));
    }
    Ok(MtlMaterial {
        name: format!("{file}: {name}"),
        ka: colour("Ka", m.ambient)?,
        kd: colour("Kd", m.diffuse)?,
        ks: colour("Ks", m.specular)?,
        ns,
        ni,
        d,
        illum,
        map_kd,
        map_ka,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_split_at_each_newmtl_and_keep_every_byte() {
        let text = b"# top\nnewmtl a\nKd 1 0 0\n  newmtl  b c \nNs 3\n";
        let b: Vec<Block> = blocks(text).collect();
        let names: Vec<Option<&str>> = b.iter().map(|b| b.name.as_deref()).collect();
        assert_eq!(names, [None, Some("a"), Some("b c")]);
        let joined: Vec<u8> = b.iter().flat_map(|b| b.text.iter().copied()).collect();
        assert_eq!(joined, text);
        assert_eq!(blocks(b"").count(), 0);
        let names: Vec<Option<String>> = blocks(b"newmtl a\nKd 1 1 1\nnewmtl b\n")
            .map(|b| b.name)
            .collect();
        assert_eq!(names, [Some("a".to_owned()), Some("b".to_owned())]);
        assert_eq!(
            blocks(b"newmtl a").map(|b| b.text).collect::<Vec<_>>(),
            [b"newmtl a"]
        );
    }

    #[test]
    fn used_names_are_read_as_tobj_reads_them() {
        let obj = b"v 0 0 0\nusemtl red\nusemtl  two words \nusemtl\nf 1 1 1\n";
        let names = used_names(&obj[..]);
        let mut v: Vec<&str> = names.iter().map(String::as_str).collect();
        v.sort();
        assert_eq!(v, ["red", "two words"]);
    }
}
