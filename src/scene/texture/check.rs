//! A `[textures.NAME]` table checked against its pattern's keys, and a
//! material's texture named.

use std::path::Path;

use glam::DVec3;

use serde::de::DeserializeOwned;

use super::{PatternId, Texture, TextureFile, PATTERNS};
use crate::input::error::SceneError;
use crate::input::field::{Triple, Validator, MAX_COORDINATE};
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
        .filter(|p| (p.keys)().contains(&key) == taking)
        .map(|p| p.what)
        .collect();
    either(&w)
}

impl Validator<'_> {
    /// The pattern a texture's table names: by `pattern`, or its file's.
    fn pattern(&self, path: &KeyPath, t: &TextureFile) -> Result<PatternId> {
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
            (None, Some(_)) => Ok(file.pattern),
            (Some(name), None) => match PATTERNS.iter().find(|p| !p.file && p.name == name) {
                Some(p) => Ok(p.pattern),
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
        let look = p.check(&PatternAt {
            check: self,
            path,
            file: t,
            pattern: p,
        })?;
        let texels = match &t.image {
            Some(file) => Some(
                images
                    .texels(&dir.join(file))
                    .or_else(|e| self.err(&path.key("image"), e))?,
            ),
            None => None,
        };
        Ok(Texture {
            pattern: p,
            size: look.size,
            colors: look.colors,
            rotation: look.rotation,
            origin: look.origin,
            own: look.own,
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

/// One texture's table being checked, as its pattern's: where it is, what
/// it holds, and the pattern it names.
pub struct PatternAt<'a> {
    check: &'a Validator<'a>,
    path: &'a KeyPath,
    file: &'a TextureFile,
    pattern: PatternId,
}

impl PatternAt<'_> {
    /// The table's own keys, read as `F`, the pattern's keys: a key of
    /// another pattern is refused naming those that take it, any other as
    /// unknown; the first in the file's order (the kept table is sorted).
    pub(super) fn own<F: DeserializeOwned>(&self) -> Result<F> {
        let what = self.pattern.info().what;
        self.check
            .read_own(self.path, &self.file.own, &["pattern", "image"], |key| {
                let taken = PATTERNS.iter().any(|p| (p.keys)().contains(&key));
                taken.then(|| format!("{what} takes no `{key}` (only {} does)", whats(key, true)))
            })
    }

    /// `size` (`v`; `default` where it is left out, else required): from
    /// 1/MAX_COORDINATE to MAX_COORDINATE.
    pub(super) fn size(&self, v: Option<f64>, default: Option<f64>) -> Result<f64> {
        let path = self.path.key("size");
        let size = match (v, default) {
            (Some(size), _) => self.check.finite(&path, size)?,
            (None, Some(size)) => size,
            (None, None) => {
                return self
                    .check
                    .err(self.path, "a pattern needs its size (size = ...)")
            }
        };
        // A point's coordinate over the size must stay finite in f32: from
        // 1/MAX_COORDINATE up (1e-40 made NaN).
        let smallest = 1.0 / MAX_COORDINATE;
        if !(smallest..=MAX_COORDINATE).contains(&size) {
            return self.check.err(
                &path,
                format!(
                    "must be at least {smallest:e} and at most {MAX_COORDINATE:e}, so that a \
                     coordinate over it stays finite in f32; got {size:e}"
                ),
            );
        }
        Ok(size)
    }

    /// `colors` (`v`), required.
    pub(super) fn colors(&self, v: Option<[Triple; 2]>) -> Result<[DVec3; 2]> {
        let Some(c) = v else {
            return self
                .check
                .err(self.path, "a pattern needs its two colors (colors = ...)");
        };
        let path = self.path.key("colors");
        Ok([
            self.check.colour(&path.index(0), c[0])?,
            self.check.colour(&path.index(1), c[1])?,
        ])
    }

    /// The cosine and sine of `angle` (`v`, degrees; 0 where left out).
    pub(super) fn rotation(&self, v: Option<f64>) -> Result<[f64; 2]> {
        let Some(angle) = v else {
            return Ok([1.0, 0.0]);
        };
        let radians = self
            .check
            .finite(&self.path.key("angle"), angle)?
            .to_radians();
        Ok([radians.cos(), radians.sin()])
    }

    /// `origin` (`v`), a position; 0 where left out.
    pub(super) fn origin(&self, v: Option<Triple>) -> Result<DVec3> {
        match v {
            Some(o) => self.check.position(&self.path.key("origin"), o),
            None => Ok(DVec3::ZERO),
        }
    }
}
