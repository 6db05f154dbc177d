//! The checks of one value of an input file (docs/scene-format.md,
//! Validation): finite numbers, points within `MAX_COORDINATE`, directions
//! made unit length, and lengths; each error names the file, the line, the
//! column and the key. The primitive kinds check their own tables with
//! [`At`]; the scene checks the rest (`crate::scene`).

use std::path::Path;

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::error::SceneError;
use super::locate::{KeyPath, Locate};

type Result<T> = std::result::Result<T, SceneError>;

/// Three numbers, exactly: serde's own `[f64; 3]` takes the first three
/// elements of a longer array and ignores the rest.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Triple(pub [f64; 3]);

impl std::ops::Deref for Triple {
    type Target = [f64; 3];
    fn deref(&self) -> &[f64; 3] {
        &self.0
    }
}

impl Serialize for Triple {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        self.0.serialize(s)
    }
}

impl<'de> Deserialize<'de> for Triple {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let v = Vec::<f64>::deserialize(d)?;
        <[f64; 3]>::try_from(v.as_slice())
            .map(Triple)
            .map_err(|_| serde::de::Error::invalid_length(v.len(), &"exactly three numbers"))
    }
}

/// Where one table of the file is, for a primitive kind's checks
/// (`crate::prim::Kind::check`): its fields are checked and named from here.
pub struct At<'a> {
    pub(crate) check: &'a Validator<'a>,
    /// The materials' names, sorted.
    pub(crate) names: &'a [&'a String],
    pub(crate) path: KeyPath,
}

impl At<'_> {
    /// A point: finite and within ±`MAX_COORDINATE`.
    pub fn position(&self, key: &str, t: Triple) -> Result<DVec3> {
        self.check.position(&self.path.key(key), t)
    }

    /// A direction, returned at unit length.
    pub fn direction(&self, key: &str, t: Triple) -> Result<DVec3> {
        self.check.direction(&self.path.key(key), t)
    }

    /// The same table's array `key`, element `i`: `vertices[2]`.
    pub fn element(&self, key: &str, i: usize) -> At<'_> {
        At {
            check: self.check,
            names: self.names,
            path: self.path.key(key).index(i),
        }
    }

    /// A point given as this element itself (see [`At::element`]).
    pub fn position_here(&self, t: Triple) -> Result<DVec3> {
        self.check.position(&self.path, t)
    }

    /// A direction given as this element itself, returned at unit length.
    pub fn direction_here(&self, t: Triple) -> Result<DVec3> {
        self.check.direction(&self.path, t)
    }

    /// An error at this element itself (see [`At::element`]).
    pub fn invalid_here<T>(&self, message: impl Into<String>) -> Result<T> {
        self.check.err(&self.path, message)
    }

    /// An error at `key` of this table.
    pub fn invalid<T>(&self, key: &str, message: impl Into<String>) -> Result<T> {
        self.check.err(&self.path.key(key), message)
    }

    /// A length: finite, > 0 and at most `MAX_COORDINATE`.
    pub fn length(&self, key: &str, v: f64) -> Result<f64> {
        let path = self.path.key(key);
        let v = self.check.finite(&path, v)?;
        if v <= 0.0 {
            return self.check.err(
                &path,
                format!("must be > 0, got {}", crate::printable::number(v)),
            );
        }
        if v > MAX_COORDINATE {
            return self.check.err(
                &path,
                format!("must be at most {MAX_COORDINATE:e}, got {v:e}"),
            );
        }
        Ok(v)
    }

    /// A material's index, by its name.
    pub fn material(&self, key: &str, name: &str) -> Result<u32> {
        let path = self.path.key(key);
        // The names are sorted (a BTreeMap's keys): a binary search keeps
        // 200,000 spheres with as many materials linear-logarithmic.
        match self.names.binary_search_by(|n| n.as_str().cmp(name)) {
            Ok(i) => Ok(i as u32),
            Err(_) if self.names.is_empty() => self.check.err(
                &path,
                format!(
                    "unknown material \"{}\" (the scene defines no [materials])",
                    crate::printable::text(name)
                ),
            ),
            Err(_) => {
                const SHOWN: usize = 10;
                let mut listed: Vec<&str> =
                    self.names.iter().take(SHOWN).map(|n| n.as_str()).collect();
                if self.names.len() > SHOWN {
                    listed.push("…");
                }
                self.check.err(
                    &path,
                    format!(
                        "unknown material \"{}\" (defined: {})",
                        crate::printable::text(name),
                        listed.join(", ")
                    ),
                )
            }
        }
    }
}

/// `v` at unit length, or None where it is zero (or not finite). Scaled
/// first, so that tiny and huge (but finite) vectors normalize too.
pub fn unit_vector(v: DVec3) -> Option<DVec3> {
    let unit = (v / v.abs().max_element()).normalize_or_zero();
    (unit != DVec3::ZERO && unit.is_finite()).then_some(unit)
}

/// Coordinates and lengths at most this far from 0: squared distances
/// (about 1e36 each, three to a length) stay inside f32's 3.4e38.
pub const MAX_COORDINATE: f64 = 1e18;

/// The key path of the file itself.
pub(crate) fn root() -> KeyPath {
    KeyPath::default()
}

/// The validation of one input file: where its values are written, for
/// the errors that name them, and the checks of single values. Each layer
/// adds the checks of its own tables (`crate::scene`'s validation: the
/// scene file's).
pub(crate) struct Validator<'a> {
    /// The file, as messages name it.
    pub(crate) file: &'a Path,
    /// Where each key path was written.
    pub(crate) located: &'a dyn Locate,
}

impl Validator<'_> {
    pub(crate) fn err<T>(&self, path: &KeyPath, message: impl Into<String>) -> Result<T> {
        let at = self.located.find(path);
        Err(SceneError::Invalid {
            file: self.file.to_owned(),
            line: at.map_or(1, |a| a.line),
            column: at.map_or(1, |a| a.column),
            key: path.to_string(),
            message: message.into(),
        })
    }

    pub(crate) fn int_in(&self, path: &KeyPath, v: i64, lo: u32, hi: u32) -> Result<u32> {
        if v < i64::from(lo) || v > i64::from(hi) {
            return self.err(path, format!("must be in {lo}..={hi}, got {v}"));
        }
        Ok(v as u32)
    }

    pub(crate) fn finite(&self, path: &KeyPath, v: f64) -> Result<f64> {
        if !v.is_finite() {
            return self.err(
                path,
                format!(
                    "must be a finite number, got {}",
                    crate::printable::number(v)
                ),
            );
        }
        Ok(v)
    }

    /// A finite number, at least 0.
    pub(crate) fn non_negative(&self, path: &KeyPath, v: f64) -> Result<f64> {
        let v = self.finite(path, v)?;
        if v < 0.0 {
            return self.err(
                path,
                format!("must be >= 0, got {}", crate::printable::number(v)),
            );
        }
        Ok(v)
    }

    pub(crate) fn vector(&self, path: &KeyPath, t: Triple) -> Result<DVec3> {
        for (i, c) in t.iter().enumerate() {
            self.finite(&path.index(i), *c)?;
        }
        Ok(DVec3::from_array(t.0))
    }

    /// A point or a length vector: finite and within ±`MAX_COORDINATE`.
    pub(crate) fn position(&self, path: &KeyPath, t: Triple) -> Result<DVec3> {
        let v = self.vector(path, t)?;
        if let Some(i) = t.iter().position(|c| c.abs() > MAX_COORDINATE) {
            return self.err(
                &path.index(i),
                format!(
                    "must be within ±{MAX_COORDINATE:e}, so that squared distances stay finite in f32; got {:e}",
                    t[i]
                ),
            );
        }
        Ok(v)
    }

    /// A colour or coefficient triple: finite and non-negative.
    pub(crate) fn colour(&self, path: &KeyPath, t: Triple) -> Result<DVec3> {
        let v = self.vector(path, t)?;
        if let Some(i) = t.iter().position(|c| *c < 0.0) {
            return self.err(
                &path.index(i),
                format!("must be >= 0, got {}", crate::printable::number(t[i])),
            );
        }
        Ok(v)
    }

    /// A direction: finite, non-zero, returned at unit length.
    pub(crate) fn direction(&self, path: &KeyPath, t: Triple) -> Result<DVec3> {
        let v = self.vector(path, t)?;
        match unit_vector(v) {
            Some(unit) => Ok(unit),
            None => self.err(path, "must be a non-zero vector"),
        }
    }
}
