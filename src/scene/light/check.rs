//! Checking a light's table: its type, that type's keys alone, its
//! placement (the type's own check) and its colours.

use glam::DVec3;

use serde::de::DeserializeOwned;

use super::{Light, LightFile, LightTypeId, LIGHT_TYPES};
use crate::input::error::SceneError;
use crate::input::field::{Triple, Validator};
use crate::input::locate::KeyPath;

/// One light's table being checked: where it is, and what it holds.
pub struct LightAt<'a> {
    check: &'a Validator<'a>,
    path: &'a KeyPath,
    file: &'a LightFile,
}

impl LightAt<'_> {
    /// The table's own keys, read as `F`, the keys of the type named
    /// `name`: a key of another type is refused by name, any other as
    /// unknown.
    pub(super) fn own<F: DeserializeOwned>(&self, name: &str) -> Result<F, SceneError> {
        let shared = ["type", "ambient", "diffuse", "specular"];
        self.check
            .read_own(self.path, &self.file.own, &shared, |key| {
                let taken = LIGHT_TYPES.iter().any(|t| (t.keys)().contains(&key));
                taken.then(|| format!("does not apply to a {name} light"))
            })
    }

    /// The light's own key `key`, required.
    fn required(&self, key: &str, v: Option<Triple>) -> Result<Triple, SceneError> {
        match v {
            Some(v) => Ok(v),
            None => self.check.err(
                self.path,
                format!(
                    "missing key `{key}` (required for a {} light)",
                    self.file.kind
                ),
            ),
        }
    }

    /// `position` (`v`), required.
    pub(super) fn position(&self, v: Option<Triple>) -> Result<DVec3, SceneError> {
        let v = self.required("position", v)?;
        self.check.position(&self.path.key("position"), v)
    }

    /// `direction` (`v`), required, at unit length.
    pub(super) fn direction(&self, v: Option<Triple>) -> Result<DVec3, SceneError> {
        let v = self.required("direction", v)?;
        self.check.direction(&self.path.key("direction"), v)
    }

    /// `attenuation` (`v`), [1, 0, 0] by default, its constant term > 0.
    pub(super) fn attenuation(&self, v: Option<Triple>) -> Result<DVec3, SceneError> {
        let path = self.path.key("attenuation");
        let a = self
            .check
            .colour(&path, v.unwrap_or(Triple([1.0, 0.0, 0.0])))?;
        if a.x <= 0.0 {
            return self.check.err(
                &path.index(0),
                "the constant term c must be > 0, so that 1/(c + l*d + q*d^2) stays finite at the light",
            );
        }
        Ok(a)
    }

    /// A number key of the light, finite.
    pub(super) fn number(&self, key: &str, v: f64) -> Result<f64, SceneError> {
        self.check.finite(&self.path.key(key), v)
    }

    pub(super) fn err<T>(
        &self,
        key: Option<&str>,
        message: impl Into<String>,
    ) -> Result<T, SceneError> {
        match key {
            Some(key) => self.check.err(&self.path.key(key), message),
            None => self.check.err(self.path, message),
        }
    }
}

impl Validator<'_> {
    /// The light at `path`: its type, its type's keys alone, its placement
    /// and its colours.
    pub(crate) fn light(&self, path: &KeyPath, l: &LightFile) -> Result<Light, SceneError> {
        let Some(kind) = LightTypeId::from_name(&l.kind) else {
            let names: Vec<String> = LIGHT_TYPES
                .iter()
                .map(|t| format!("\"{}\"", t.name))
                .collect();
            let (last, rest) = names.split_last().expect("a light type");
            return self.err(
                &path.key("type"),
                format!(
                    "unknown light type \"{}\" (expected {} or {last})",
                    l.kind,
                    rest.join(", ")
                ),
            );
        };
        let placed = kind.check(&LightAt {
            check: self,
            path,
            file: l,
        })?;
        Ok(Light {
            kind,
            position: placed.position,
            direction: placed.direction,
            ambient: self.colour(&path.key("ambient"), l.ambient)?,
            diffuse: self.colour(&path.key("diffuse"), l.diffuse)?,
            specular: self.colour(&path.key("specular"), l.specular)?,
            own: placed.own,
        })
    }
}
