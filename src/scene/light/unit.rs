//! What a light type provides (`LightType`), and what the generated code
//! and the tables know of it (`LightTypeInfo`).

use super::{LightAt, LightFile, LightKind, LightR, Placement, Toward};
use crate::base::real::{Real, Vec3};
use crate::input::error::SceneError;
use crate::rng::Place;

/// What one light type provides.
pub trait LightType {
    /// Its `type` in the scene file, and the stem of its GLSL names:
    /// `<name>_toward` and, with a cone, `<name>_cone` in
    /// `shaders/light/<name>.glsl`.
    const NAME: &'static str;
    /// Its GLSL include.
    const GLSL: &'static str;
    /// The keys it takes besides `type` and the colours; another type's key
    /// is refused by name.
    const KEYS: &'static [&'static str];
    /// Whether it has a position, at a finite distance from every point
    /// (its shadow rays end there; it has a light buffer's cube).
    const POSITIONED: bool;
    /// Whether it lights a cone alone: its include gives `<name>_cone`.
    const CONE: bool = false;

    /// Checks its keys of `at`'s table and places the light.
    fn check(at: &LightAt) -> Result<Placement, SceneError>;
    /// How light `l` reaches `p`; mirrors `<name>_toward`.
    fn toward<R: Real>(l: &LightR<R>, p: Vec3<R>) -> Toward<R>;
    /// The share of it in direction `to` (unit, towards the light), in
    /// 0..=1; mirrors `<name>_cone`.
    fn cone<R: Real>(_l: &LightR<R>, _to: Vec3<R>) -> R {
        R::one()
    }
    /// One light of this type, for the contract tests.
    #[cfg(test)]
    fn example() -> LightFile;
    /// One light of this type that lights `p.center` from about `p.size`
    /// away, as a scene file's table: what `crate::generate` puts in a
    /// scene (it sets the colours).
    fn sample(p: &mut Place) -> LightFile;
}

/// What the generated code knows of a light type.
#[derive(Debug, Clone, Copy)]
pub struct LightTypeInfo {
    /// Its variant.
    pub kind: LightKind,
    /// `LightType::NAME`.
    pub name: &'static str,
    /// `LightType::GLSL`.
    pub glsl: &'static str,
    /// `LightType::KEYS`.
    pub keys: &'static [&'static str],
    /// `LightType::POSITIONED`.
    pub positioned: bool,
    /// `LightType::CONE`.
    pub cone: bool,
    /// `LightType::sample`.
    pub(crate) sample: fn(&mut Place) -> LightFile,
}

impl LightTypeInfo {
    pub(super) const fn of<T: LightType>(kind: LightKind) -> Self {
        Self {
            kind,
            name: T::NAME,
            glsl: T::GLSL,
            keys: T::KEYS,
            positioned: T::POSITIONED,
            cone: T::CONE,
            sample: T::sample,
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
