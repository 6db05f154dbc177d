//! A `[textures.NAME]` table checked against its pattern's keys, and a
//! material's texture named.

use std::path::Path;

use glam::DVec3;

use super::{PatternInfo, Texture, TextureFile, PATTERNS};
use crate::input::error::SceneError;
use crate::input::field::{Validator, MAX_COORDINATE};
use crate::input::locate::KeyPath;
use crate::scene::images::Images;

type Result<T> = std::result::Result<T, SceneError>;

/// `whats` joined as a message lists them: `a, b or c`.
fn either(whats: &[&str]) -> String {
    match whats.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
        _ => whats.join(""),
    }
}

/// How messages name the patterns that take `key`, or do not.
fn whats(key: &str, taking: bool) -> String {
    let w: Vec<&str> = PATTERNS
        .iter()
        .filter(|p| p.keys.contains(&key) == taking)
        .map(|p| p.what)
        .collect();
    either(&w)
}

impl Validator<'_> {
    /// The pattern a texture's table names: by `pattern`, or its file's.
    fn pattern(&self, path: &KeyPath, t: &TextureFile) -> Result<&'static PatternInfo> {
        let named: Vec<&str> = PATTERNS
            .iter()
            .filter(|p| !p.file)
            .map(|p| p.name)
            .collect();
        let file = PATTERNS
            .iter()
            .find(|p| p.file)
            .expect("a pattern read from a file");
        match (t.pattern.as_deref(), &t.image) {
            (Some(_), Some(_)) => self.err(
                &path.key("image"),
                "a texture is a pattern or an image, not both",
            ),
            (None, None) => self.err(
                path,
                format!(
                    "a texture needs a pattern ({}) or an image",
                    named.join(", ")
                ),
            ),
            (None, Some(_)) => Ok(file),
            (Some(name), None) => match PATTERNS.iter().find(|p| !p.file && p.name == name) {
                Some(p) => Ok(p),
                None => self.err(
                    &path.key("pattern"),
                    format!(
                        "unknown pattern \"{}\" (known: {})",
                        crate::printable::text(name),
                        named.join(", ")
                    ),
                ),
            },
        }
    }

    /// A texture's table: a pattern, or an image read into `images`
    /// (relative to `dir`, the scene file's folder).
    pub(crate) fn texture(
        &self,
        path: &KeyPath,
        t: &TextureFile,
        dir: &Path,
        images: &mut Images,
    ) -> Result<Texture> {
        let p = self.pattern(path, t)?;
        let takes = |key: &str| p.keys.contains(&key);
        let size = match (t.size, p.default_size) {
            (Some(size), _) => self.finite(&path.key("size"), size)?,
            (None, Some(size)) => size,
            (None, None) => return self.err(path, "a pattern needs its size (size = ...)"),
        };
        // A point's coordinate over the size must stay finite in f32: from
        // 1/MAX_COORDINATE up (issue 31, defect 17: 1e-40 made NaN).
        let smallest = 1.0 / MAX_COORDINATE;
        if !(smallest..=MAX_COORDINATE).contains(&size) {
            return self.err(
                &path.key("size"),
                format!(
                    "must be at least {smallest:e} and at most {MAX_COORDINATE:e}, so that a \
                     coordinate over it stays finite in f32; got {size:e}"
                ),
            );
        }
        let colors = match t.colors {
            Some(_) if !takes("colors") => {
                return self.err(
                    &path.key("colors"),
                    format!("{} has no colors of its own", p.what),
                )
            }
            Some(c) => [
                self.colour(&path.key("colors").index(0), c[0])?,
                self.colour(&path.key("colors").index(1), c[1])?,
            ],
            None if !takes("colors") => [DVec3::ONE; 2],
            None => return self.err(path, "a pattern needs its two colors (colors = ...)"),
        };
        let mut rotation = [1.0, 0.0];
        if let Some(angle) = t.angle {
            if !takes("angle") {
                return self.err(
                    &path.key("angle"),
                    format!("only {} is turned by an angle", whats("angle", true)),
                );
            }
            let radians = self.finite(&path.key("angle"), angle)?.to_radians();
            rotation = [radians.cos(), radians.sin()];
        }
        let mut origin = DVec3::ZERO;
        if let Some(o) = t.origin {
            if !takes("origin") {
                return self.err(
                    &path.key("origin"),
                    format!(
                        "only {} has an origin ({} starts at its surface's own)",
                        whats("origin", true),
                        whats("origin", false)
                    ),
                );
            }
            origin = self.position(&path.key("origin"), o)?;
        }
        let texels = match &t.image {
            Some(file) => Some(
                images
                    .texels(&dir.join(file))
                    .or_else(|e| self.err(&path.key("image"), e))?,
            ),
            None => None,
        };
        Ok(Texture {
            pattern: p.pattern,
            size,
            colors,
            rotation,
            origin,
            texels,
        })
    }

    /// The index of the texture `name` of the material at `path`.
    pub(crate) fn texture_index(
        &self,
        path: &KeyPath,
        name: &str,
        names: &[String],
    ) -> Result<u32> {
        match names.binary_search_by(|n| n.as_str().cmp(name)) {
            Ok(i) => Ok(i as u32),
            Err(_) => {
                let defined: Vec<&str> = names.iter().map(|n| n.as_str()).collect();
                self.err(
                    path,
                    format!(
                        "unknown texture \"{}\" ({})",
                        crate::printable::text(name),
                        if defined.is_empty() {
                            "the scene defines no [textures]".to_owned()
                        } else {
                            format!("defined: {}", defined.join(", "))
                        }
                    ),
                )
            }
        }
    }
}
