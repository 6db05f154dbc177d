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
mod file;
mod model;
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

/// The table of light types: each type's variant of [`LightKind`], its
/// module (a file of this folder, declared by the table) and the module's
/// type. A type's code in the shader is its place here.
macro_rules! with_light_types {
    ($then:ident) => {
        $then! {
            Point: point::Point,
            Directional: directional::Directional,
            Spot: spot::Spot,
        }
    };
}

macro_rules! light_types {
    ($($variant:ident : $module:ident :: $ty:ident),* $(,)?) => {
        $(pub(crate) mod $module;)*
        $(use $module::$ty;)*

        /// A light's type: its place in the table.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum LightKind {
            $(#[doc = concat!("`", stringify!($ty), "`.")] $variant,)*
        }

        /// The light types, in the table's order.
        pub const LIGHT_TYPES: &[LightTypeInfo] =
            &[$(LightTypeInfo::of::<$ty>(LightKind::$variant),)*];

        impl LightKind {
            pub(super) fn check(self, at: &LightAt) -> Result<Placement, SceneError> {
                match self {
                    $(LightKind::$variant => <$ty>::check(at.own::<<$ty as LightType>::File>(<$ty>::NAME)?, at),)*
                }
            }

            /// How light `l` of this type reaches the point `p` of normal `n`.
            pub fn toward<R: Real>(self, l: &LightR<R>, p: Vec3<R>, n: Vec3<R>) -> Toward<R> {
                match self {
                    $(LightKind::$variant => <$ty>::toward(l, p, n),)*
                }
            }

            /// The share of light `l` of this type at `p` (normal `n`) in
            /// direction `to`.
            pub fn cone<R: Real>(self, l: &LightR<R>, p: Vec3<R>, n: Vec3<R>, to: Vec3<R>) -> R {
                match self {
                    $(LightKind::$variant => <$ty>::cone(l, p, n, to),)*
                }
            }

            fn attenuated(self, l: &Light) -> bool {
                match self {
                    $(LightKind::$variant => <$ty>::attenuated(l),)*
                }
            }

            fn peak_divisor(self, l: &Light) -> f64 {
                match self {
                    $(LightKind::$variant => <$ty>::peak_divisor(l),)*
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
