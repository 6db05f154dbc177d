//! The lights, as units (docs/scene-format.md, Lights). Each light type is
//! one Rust module here (its keys, its checks and the CPU reference's way
//! from a point to the light) and one GLSL include under shaders/light/
//! (the shader's), listed in the table below, as `crate::prim`'s kinds are.
//! Everything that treats the types alike is generated from that table: the
//! `type` names and their messages, the shader's `HAS_*` switches and
//! codes, its dispatch (src/gpu/generated.rs) and the CPU reference's.
//!
//! Adding a light type: its module, its include, and one line of the table.

mod directional;
mod point;
mod spot;

#[cfg(test)]
mod contract_tests;

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::base::real::{Real, Vec3};
use crate::input::error::SceneError;
use crate::input::field::{Check, Triple};
use crate::input::locate::KeyPath;
use crate::rng::Place;

/// The table of light types: each type's variant of [`LightKind`] and its
/// module's type. A type's code in the shader is its place here.
macro_rules! with_light_types {
    ($then:ident) => {
        $then! {
            Point: point::Point,
            Directional: directional::Directional,
            Spot: spot::Spot,
        }
    };
}

/// One flat table for every light type: `check` takes the keys of the
/// light's type alone and refuses the others by name.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct LightFile {
    /// `type`: a name of the table of light types.
    #[serde(rename = "type")]
    pub kind: String,
    /// Where a positioned light is.
    pub position: Option<Triple>,
    /// The way a directional light travels; a cone's axis.
    pub direction: Option<Triple>,
    /// Its ambient intensity (default 0).
    #[serde(default)]
    pub ambient: Triple,
    /// Its diffuse intensity (default 0).
    #[serde(default)]
    pub diffuse: Triple,
    /// Its specular intensity (default 0).
    #[serde(default)]
    pub specular: Triple,
    /// A positioned light's [c, l, q] (default [1, 0, 0]).
    pub attenuation: Option<Triple>,
    /// A cone's half-angle, in degrees.
    pub cutoff: Option<f64>,
    /// A cone's falloff exponent (default 0).
    pub exponent: Option<f64>,
}

impl LightFile {
    /// A light of type `kind` at `position` or along `direction`, white,
    /// with a little ambient, and its other keys left out.
    pub(crate) fn placed(
        kind: &str,
        position: Option<[f64; 3]>,
        direction: Option<[f64; 3]>,
    ) -> Self {
        LightFile {
            kind: kind.to_owned(),
            position: position.map(Triple),
            direction: direction.map(Triple),
            ambient: Triple([0.1; 3]),
            diffuse: Triple([1.0; 3]),
            specular: Triple([0.5; 3]),
            attenuation: None,
            cutoff: None,
            exponent: None,
        }
    }

    /// The keys a type may take (beside `type` and the three colours),
    /// each with whether this table has it.
    fn typed_keys(&self) -> [(&'static str, bool); 5] {
        [
            ("position", self.position.is_some()),
            ("direction", self.direction.is_some()),
            ("attenuation", self.attenuation.is_some()),
            ("cutoff", self.cutoff.is_some()),
            ("exponent", self.exponent.is_some()),
        ]
    }
}

/// A light (docs/scene-format.md, Lights).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Light {
    /// What type.
    pub kind: LightKind,
    /// Where a positioned light is; zero for the others.
    pub position: DVec3,
    /// Unit length: the way a directional light travels, a cone's axis;
    /// zero for the others.
    pub direction: DVec3,
    /// Its ambient intensity, per channel.
    pub ambient: DVec3,
    /// Its diffuse intensity, per channel.
    pub diffuse: DVec3,
    /// Its specular intensity, per channel.
    pub specular: DVec3,
    /// [c, l, q]: 1 / (c + l d + q d²); [1, 0, 0] where it has none.
    pub attenuation: DVec3,
    /// The cosine of a cone's half-angle; -1 without a cone.
    pub cos_cutoff: f64,
    /// A cone's falloff towards its edge: cos(angle)^exponent.
    pub exponent: f64,
}

/// What a type's check gives: everything of a light but its colours.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// `Light::position`.
    pub position: DVec3,
    /// `Light::direction`.
    pub direction: DVec3,
    /// `Light::attenuation`.
    pub attenuation: DVec3,
    /// `Light::cos_cutoff`.
    pub cos_cutoff: f64,
    /// `Light::exponent`.
    pub exponent: f64,
}

impl Default for Placement {
    fn default() -> Self {
        Self {
            position: DVec3::ZERO,
            direction: DVec3::ZERO,
            attenuation: DVec3::X,
            cos_cutoff: -1.0,
            exponent: 0.0,
        }
    }
}

impl Light {
    /// Whether the light has a diffuse or specular term: a shadow ray
    /// towards a light without one could change nothing.
    pub fn has_direct_term(&self) -> bool {
        self.diffuse != DVec3::ZERO || self.specular != DVec3::ZERO
    }

    /// Its position, where its type has one.
    pub fn position(&self) -> Option<DVec3> {
        self.kind.info().positioned.then_some(self.position)
    }

    /// Its struct in the shader's buffers, in coordinates moved by
    /// `-origin`; meta's z and w (its light buffer) are the tables'.
    pub(crate) fn gpu(&self, origin: DVec3) -> gpu::Values {
        let xyz = |v: DVec3| [v.x, v.y, v.z, 0.0];
        gpu::Values {
            position: xyz(self.position - origin),
            direction: xyz(self.direction),
            ambient: xyz(self.ambient),
            diffuse: xyz(self.diffuse),
            specular: xyz(self.specular),
            attenuation: xyz(self.attenuation),
            cone: [self.cos_cutoff, self.exponent, 0.0, 0.0],
            meta: [self.kind as u32, u32::from(self.has_direct_term()), 0, 0],
        }
    }

    /// The light in the CPU reference's arithmetic, moved by `-origin`.
    pub fn cpu<R: Real>(&self, origin: DVec3) -> LightR<R> {
        LightR {
            kind: self.kind,
            position: Vec3::of(self.position - origin),
            direction: Vec3::of(self.direction),
            ambient: Vec3::of(self.ambient),
            diffuse: Vec3::of(self.diffuse),
            specular: Vec3::of(self.specular),
            attenuation: Vec3::of(self.attenuation),
            cos_cutoff: R::of(self.cos_cutoff),
            exponent: R::of(self.exponent),
            direct: self.has_direct_term(),
        }
    }
}

crate::base::interface::gpu_struct!(
    pub(crate) mod gpu: "Light" {
        /// xyz (positioned types)
        position: real4,
        /// xyz unit (directional: travel; a cone's axis)
        direction: real4,
        /// rgb Ia
        ambient: real4,
        /// rgb Id
        diffuse: real4,
        /// rgb Is
        specular: real4,
        /// xyz = c, l, q
        attenuation: real4,
        /// x cos(cutoff), y exponent of a cone
        cone: real4,
        /// x LIGHT_* (its type), y 1 if it has a diffuse or specular term,
        /// z its light buffer's first grid + 1 (0: none), w the buffer's
        /// reach (f32 bits)
        meta: uvec4,
    }
);

/// A light in the CPU reference's arithmetic, in camera-relative
/// coordinates; what the shader's `Light` holds.
#[derive(Debug, Clone, Copy)]
pub struct LightR<R> {
    /// `Light::kind`.
    pub kind: LightKind,
    /// `Light::position`, moved.
    pub position: Vec3<R>,
    /// `Light::direction`.
    pub direction: Vec3<R>,
    /// `Light::ambient`.
    pub ambient: Vec3<R>,
    /// `Light::diffuse`.
    pub diffuse: Vec3<R>,
    /// `Light::specular`.
    pub specular: Vec3<R>,
    /// `Light::attenuation`.
    pub attenuation: Vec3<R>,
    /// `Light::cos_cutoff`.
    pub cos_cutoff: R,
    /// `Light::exponent`.
    pub exponent: R,
    /// Whether it has a diffuse or specular term.
    pub direct: bool,
}

/// How light reaches a point: the unit way towards the light, the distance
/// to it (infinite for a light without a position) and the attenuation.
pub type Toward<R> = (Vec3<R>, R, R);

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
    const fn of<T: LightType>(kind: LightKind) -> Self {
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

macro_rules! light_types {
    ($($variant:ident : $ty:ty),* $(,)?) => {
        /// A light's type: its place in the table.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum LightKind {
            $(#[doc = concat!("`", stringify!($ty), "`.")] $variant,)*
        }

        /// The light types, in the table's order.
        pub const LIGHT_TYPES: &[LightTypeInfo] =
            &[$(LightTypeInfo::of::<$ty>(LightKind::$variant),)*];

        impl LightKind {
            fn check(self, at: &LightAt) -> Result<Placement, SceneError> {
                match self {
                    $(LightKind::$variant => <$ty>::check(at),)*
                }
            }

            /// How light `l` of this type reaches `p`.
            pub fn toward<R: Real>(self, l: &LightR<R>, p: Vec3<R>) -> Toward<R> {
                match self {
                    $(LightKind::$variant => <$ty>::toward(l, p),)*
                }
            }

            /// The share of light `l` of this type in direction `to`.
            pub fn cone<R: Real>(self, l: &LightR<R>, to: Vec3<R>) -> R {
                match self {
                    $(LightKind::$variant => <$ty>::cone(l, to),)*
                }
            }
        }

        #[cfg(test)]
        fn every_type_problems() -> Vec<String> {
            let mut out = Vec::new();
            $(out.extend(contract_tests::problems::<$ty>(LightKind::$variant));)*
            out
        }
    };
}

with_light_types!(light_types);

impl LightKind {
    /// What the table says of it.
    pub fn info(self) -> &'static LightTypeInfo {
        &LIGHT_TYPES[self as usize]
    }

    /// The type a scene file names `name`.
    pub fn from_name(name: &str) -> Option<LightKind> {
        LIGHT_TYPES.iter().find(|t| t.name == name).map(|t| t.kind)
    }
}

/// One light's table being checked: where it is, and what it holds.
pub struct LightAt<'a> {
    check: &'a Check<'a>,
    path: &'a KeyPath,
    file: &'a LightFile,
}

impl LightAt<'_> {
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

    /// `position`, required.
    fn position(&self) -> Result<DVec3, SceneError> {
        let v = self.required("position", self.file.position)?;
        self.check.position(&self.path.key("position"), v)
    }

    /// `direction`, required, at unit length.
    fn direction(&self) -> Result<DVec3, SceneError> {
        let v = self.required("direction", self.file.direction)?;
        self.check.direction(&self.path.key("direction"), v)
    }

    /// `attenuation`, [1, 0, 0] by default, its constant term > 0.
    fn attenuation(&self) -> Result<DVec3, SceneError> {
        let path = self.path.key("attenuation");
        let a = self.check.colour(
            &path,
            self.file.attenuation.unwrap_or(Triple([1.0, 0.0, 0.0])),
        )?;
        if a.x <= 0.0 {
            return self.check.err(
                &path.index(0),
                "the constant term c must be > 0, so that 1/(c + l*d + q*d^2) stays finite at the light",
            );
        }
        Ok(a)
    }

    /// A number key of the light, finite.
    fn number(&self, key: &str, v: f64) -> Result<f64, SceneError> {
        self.check.finite(&self.path.key(key), v)
    }

    fn err<T>(&self, key: Option<&str>, message: impl Into<String>) -> Result<T, SceneError> {
        match key {
            Some(key) => self.check.err(&self.path.key(key), message),
            None => self.check.err(self.path, message),
        }
    }
}

impl Check<'_> {
    /// The light at `path`: its type, its type's keys alone, its placement
    /// and its colours.
    pub(crate) fn light(&self, path: &KeyPath, l: &LightFile) -> Result<Light, SceneError> {
        let Some(kind) = LightKind::from_name(&l.kind) else {
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
        // Keys that another light type uses are errors here, not silently ignored.
        for (key, present) in l.typed_keys() {
            if present && !kind.info().keys.contains(&key) {
                return self.err(
                    &path.key(key),
                    format!("does not apply to a {} light", l.kind),
                );
            }
        }
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
            attenuation: placed.attenuation,
            cos_cutoff: placed.cos_cutoff,
            exponent: placed.exponent,
        })
    }
}
