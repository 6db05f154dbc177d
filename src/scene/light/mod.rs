//! The lights, as units (docs/scene-format.md, Lights). Each light type is
//! one Rust module here (its keys, its checks and the CPU reference's way
//! from a point to the light) and one GLSL include under shaders/light/
//! (the shader's), listed in the table below, as `crate::prim`'s kinds are.
//! Everything that treats the types alike is generated from that table: the
//! `type` names and their messages, the shader's `HAS_*` switches and
//! codes, the lists its dispatch runs over (src/gpu/entities.rs,
//! shaders/light_dispatch.glsl) and the CPU reference's dispatch.
//!
//! The model beside the types: a light's table as read (file.rs), its
//! check (check.rs), the checked light with its GPU and CPU forms
//! (model.rs), and what a type provides (unit.rs).
//!
//! Adding a light type: its module, its include, and one line of the table.

mod check;
pub(crate) mod directional;
mod file;
mod model;
pub(crate) mod point;
pub(crate) mod spot;
mod unit;

#[cfg(test)]
mod contract_tests;

pub use check::LightAt;
pub use file::LightFile;
#[cfg(feature = "gpu")]
pub(crate) use model::gpu;
pub use model::{Light, LightR, Own, Placement, Toward, OWN};
pub use unit::{LightType, LightTypeInfo};

use crate::base::real::{Real, Vec3};
use crate::input::error::SceneError;

/// The table of light types: each type's variant of [`LightTypeId`] and its
/// type (a module of this folder each, declared above). A type's code in
/// the shader is its place here.
macro_rules! with_light_types {
    ($then:path) => {
        $then! {
            Point: point::Point,
            Directional: directional::Directional,
            Spot: spot::Spot,
        }
    };
}

macro_rules! light_types {
    ($($variant:ident : $ty:ty),* $(,)?) => {
        /// A light's type: its place in the table.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum LightTypeId {
            $(#[doc = concat!("`", stringify!($ty), "`.")] $variant,)*
        }

        /// The light types, in the table's order.
        pub const LIGHT_TYPES: &[LightTypeInfo] =
            &[$(LightTypeInfo::of::<$ty>(LightTypeId::$variant),)*];

        impl LightTypeId {
            pub(super) fn check(self, at: &LightAt) -> Result<Placement, SceneError> {
                match self {
                    $(LightTypeId::$variant => <$ty>::check(at.own::<<$ty as LightType>::File>(<$ty>::NAME)?, at),)*
                }
            }

            /// How light `l` of this type reaches the point `p` of normal `n`.
            pub fn toward<R: Real>(self, l: &LightR<R>, p: Vec3<R>, n: Vec3<R>) -> Toward<R> {
                match self {
                    $(LightTypeId::$variant => <$ty>::toward(l, p, n),)*
                }
            }

            /// The share of light `l` of this type at `p` (normal `n`) in
            /// direction `to`.
            pub fn cone<R: Real>(self, l: &LightR<R>, p: Vec3<R>, n: Vec3<R>, to: Vec3<R>) -> R {
                match self {
                    $(LightTypeId::$variant => <$ty>::cone(l, p, n, to),)*
                }
            }

            fn attenuated(self, l: &Light) -> bool {
                match self {
                    $(LightTypeId::$variant => <$ty>::attenuated(l),)*
                }
            }

            fn peak_divisor(self, l: &Light) -> f64 {
                match self {
                    $(LightTypeId::$variant => <$ty>::peak_divisor(l),)*
                }
            }
        }

        #[cfg(test)]
        fn every_type_problems() -> Vec<String> {
            let mut out = Vec::new();
            $(out.extend(contract_tests::problems::<$ty>(LightTypeId::$variant));)*
            out
        }
    };
}

with_light_types!(light_types);

impl LightTypeId {
    /// What the table says of it.
    pub fn info(self) -> &'static LightTypeInfo {
        &LIGHT_TYPES[self as usize]
    }

    /// The type a scene file names `name`.
    pub fn from_name(name: &str) -> Option<LightTypeId> {
        LIGHT_TYPES.iter().find(|t| t.name == name).map(|t| t.kind)
    }
}
