//! What a light type provides (`LightType`), and what the generated code
//! and the tables know of it (`LightTypeInfo`).

use serde::de::DeserializeOwned;
use serde::Serialize;

use super::{Light, LightAt, LightFile, LightR, LightTypeId, Placement, Toward};
use crate::base::real::{Real, Vec3};
use crate::input::error::SceneError;
use crate::input::keys::keys_of;
use crate::rng::Place;

/// What one light type provides.
pub trait LightType {
    /// Its keys in the scene file besides `type` and the colours, with
    /// serde's `deny_unknown_fields`: a key of another type is refused by
    /// name, any other as unknown. (TOML leaves a key that is `None` out
    /// when it writes one.)
    type File: DeserializeOwned + Serialize;
    /// Its `type` in the scene file, and the stem of its GLSL names:
    /// `<name>_toward` and, with a cone, `<name>_cone` in
    /// `shaders/light/<name>.glsl`.
    const NAME: &'static str;
    /// Its GLSL include.
    const GLSL: &'static str;
    /// Whether it has a position, at a finite distance from every point
    /// (its shadow rays end there; it has a light buffer's cube).
    const POSITIONED: bool;
    /// Whether it lights a cone alone: its include gives `<name>_cone`.
    const CONE: bool = false;

    /// Checks its keys (read from `at`'s table) and places the light: its
    /// position, direction and own numbers (`Light::own`).
    fn check(file: Self::File, at: &LightAt) -> Result<Placement, SceneError>;
    /// How light `l` reaches the point `p` of normal `n`; mirrors
    /// `<name>_toward`.
    fn toward<R: Real>(l: &LightR<R>, p: Vec3<R>, n: Vec3<R>) -> Toward<R>;
    /// The share of it at `p` (normal `n`) in direction `to` (unit, towards
    /// the light), in 0..=1; mirrors `<name>_cone`.
    fn cone<R: Real>(_l: &LightR<R>, _p: Vec3<R>, _n: Vec3<R>, _to: Vec3<R>) -> R {
        R::one()
    }
    /// Whether `l`'s intensity falls with distance (the shader's
    /// `HAS_ATTENUATION`).
    fn attenuated(_l: &Light) -> bool {
        false
    }
    /// What `l`'s intensity is divided by at its brightest, at least 1
    /// where it is attenuated (`Scene::light_peaks`).
    fn peak_divisor(_l: &Light) -> f64 {
        1.0
    }
    /// One light of this type, for the contract tests.
    #[cfg(test)]
    fn example() -> Self::File;
    /// One light of this type that lights `p.center` from about `p.size`
    /// away, as its keys: what `crate::generate` puts in a scene (it sets
    /// the colours).
    fn sample(p: &mut Place) -> Self::File;
}

/// What the generated code knows of a light type.
#[derive(Debug, Clone, Copy)]
pub struct LightTypeInfo {
    /// Its variant.
    pub kind: LightTypeId,
    /// `LightType::NAME`.
    pub name: &'static str,
    /// `LightType::GLSL`.
    pub glsl: &'static str,
    /// The keys of `LightType::File`.
    pub keys: fn() -> &'static [&'static str],
    /// `LightType::POSITIONED`.
    pub positioned: bool,
    /// `LightType::CONE`.
    pub cone: bool,
    /// `LightType::sample`.
    pub(crate) sample: fn(&mut Place) -> LightFile,
}

impl LightTypeInfo {
    pub(super) const fn of<T: LightType>(kind: LightTypeId) -> Self {
        Self {
            kind,
            name: T::NAME,
            glsl: T::GLSL,
            keys: keys_of::<T::File>,
            positioned: T::POSITIONED,
            cone: T::CONE,
            sample: sample_file::<T>,
        }
    }

    /// Its include's name: `light/point.glsl`.
    pub fn include(&self) -> String {
        format!("light/{}.glsl", self.name)
    }

    /// The uppercase stem of its defines: `POINT` in `HAS_POINT` and
    /// `LIGHT_POINT`.
    pub fn upper(&self) -> String {
        self.name.to_uppercase()
    }
}

/// `T::sample` as a light's table.
fn sample_file<T: LightType>(p: &mut Place) -> LightFile {
    LightFile::new(T::NAME, &T::sample(p))
}
