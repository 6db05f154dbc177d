//! Textures (docs/scene-format.md, Textures), as units: a material's
//! diffuse colour, and by default its ambient colour, taken from a pattern
//! or an image at the hit point instead of one colour. Each pattern is one
//! Rust module here (its keys and the CPU reference's colour) and one GLSL
//! include under shaders/texture/ (the shader's), listed in the table
//! below, as `crate::prim`'s kinds are. Everything that treats the patterns
//! alike is generated from that table: the names in the scene file and
//! their messages, the checks of what a surface must have, the codes and
//! the shader's dispatch (src/gpu/entities.rs) and the CPU reference's.
//!
//! The model beside the patterns: a texture's table as read (file.rs), its
//! check and the shared keys' checks (check.rs), the checked texture with
//! its GPU and CPU forms (model.rs), what a pattern provides (unit.rs), and
//! the check that each textured primitive has what its pattern reads
//! (fit.rs).
//!
//! Adding a pattern: its module (or a type in one), its include, and one
//! line of the table.

mod check;
mod checker;
mod file;
mod fit;
mod image;
mod model;
mod unit;

#[cfg(test)]
mod contract_tests;

use crate::base::real::{Real, Vec3};
use crate::input::error::SceneError;
use crate::prim::Shape;

pub use check::PatternAt;
pub use file::TextureFile;
pub use image::filtered;
#[cfg(feature = "gpu")]
pub(crate) use model::gpu;
pub use model::{Look, Needs, Texels, Texture, TextureR};
pub(crate) use unit::sample_colors;
pub use unit::{PatternInfo, PatternType};

/// The table of patterns: each pattern's variant of [`PatternId`] and its
/// type. A pattern's code in the shader is its place here + 1.
macro_rules! with_patterns {
    ($then:path) => {
        $then! {
            Checker: checker::Checker,
            SolidChecker: checker::SolidChecker,
            Image: image::Image,
        }
    };
}

macro_rules! patterns {
    ($($variant:ident : $ty:ty),* $(,)?) => {
        /// What a texture's colour depends on: its place in the table.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum PatternId {
            $(#[doc = concat!("`", stringify!($ty), "`.")] $variant,)*
        }

        /// The patterns, in the table's order.
        pub const PATTERNS: &[PatternInfo] = &[$(PatternInfo::of::<$ty>(PatternId::$variant),)*];

        impl PatternId {
            pub(crate) fn check(self, at: &PatternAt) -> Result<Look, SceneError> {
                match self {
                    $(PatternId::$variant => <$ty>::check(at.own::<<$ty as PatternType>::File>()?, at),)*
                }
            }

            /// Its colour at `p` on `surface`.
            pub fn colour<R: Real>(
                self,
                t: &TextureR<R>,
                texels: &[[f32; 3]],
                surface: &dyn Shape<R>,
                p: Vec3<R>,
            ) -> Vec3<R> {
                match self {
                    $(PatternId::$variant => <$ty>::colour(t, texels, surface, p),)*
                }
            }
        }

        #[cfg(test)]
        fn every_pattern_problems() -> Vec<String> {
            let mut out = Vec::new();
            $(out.extend(contract_tests::problems::<$ty>(PatternId::$variant));)*
            out
        }
    };
}

with_patterns!(patterns);

impl PatternId {
    /// What the table says of it.
    pub fn info(self) -> &'static PatternInfo {
        &PATTERNS[self as usize]
    }

    /// The pattern's code in the shader (`PATTERN_*`): its place + 1.
    pub fn code(self) -> u32 {
        self as u32 + 1
    }

    /// What of a surface it reads.
    pub fn needs(self) -> Needs {
        self.info().needs
    }
}
