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
//! Adding a pattern: its module (or a type in one), its include, and one
//! line of the table.

mod check;
mod checker;
mod fit;
mod image;

#[cfg(test)]
mod contract_tests;

use glam::DVec3;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use crate::base::real::{Real, Vec3};
use crate::input::error::SceneError;
use crate::input::field::Triple;
use crate::input::keys::keys_of;
use crate::prim::Shape;
use crate::rng::Place;

pub use check::PatternAt;
pub use image::filtered;

/// The table of patterns: each pattern's variant of [`Pattern`] and its
/// type. A pattern's code in the shader is its place here + 1.
macro_rules! with_patterns {
    ($then:ident) => {
        $then! {
            Checker: checker::Checker,
            SolidChecker: checker::SolidChecker,
            Image: image::Image,
        }
    };
}

/// `[textures.NAME]` as written: a `pattern` or an `image`, and the rest
/// of its keys kept aside for its pattern, which reads them into its own
/// struct (`PatternType::File`) when it is checked (check.rs). (serde's
/// `flatten`, which takes them, cannot sit beside `deny_unknown_fields`;
/// the pattern's struct denies unknown keys instead.)
#[derive(Debug, Default, Deserialize, Serialize)]
pub struct TextureFile {
    /// A pattern's name (the table's patterns not read from a file).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pattern: Option<String>,
    /// A PNG, EXR or PFM file, relative to the scene file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub image: Option<String>,
    /// The keys of its pattern, as TOML.
    #[serde(flatten)]
    pub own: toml::Table,
}

impl TextureFile {
    /// A texture of pattern `P` (named, or read from `image`) with its own
    /// keys `own`.
    pub(crate) fn of<P: PatternType>(image: Option<String>, own: &P::File) -> Self {
        TextureFile {
            pattern: (!P::FILE).then(|| P::NAME.to_owned()),
            image,
            own: toml::Table::try_from(own).expect("a pattern's keys are a TOML table"),
        }
    }
}

/// What of the surface a pattern reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Needs {
    /// Nothing: the point in the scene's coordinates.
    Nothing,
    /// The surface's own coordinates (`crate::prim::Shape::frame`).
    Frame,
    /// uv coordinates (`crate::prim::Shape::uv`).
    Uv,
}

/// Where an image's texels lie in `Scene::texels`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Texels {
    /// The index of its top-left texel.
    pub first: u32,
    /// Its texels a row.
    pub width: u32,
    /// Its rows.
    pub height: u32,
    /// Its brightest value in each channel (for the scene's brightness
    /// bound).
    pub peak: DVec3,
}

/// One texture.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Texture {
    /// Its pattern.
    pub pattern: Pattern,
    /// The side of a square or cube; an image's repeat in uv.
    pub size: f64,
    /// A pattern's colour of the squares whose cell indices sum to an even
    /// number, then to an odd one. An image's: its tint (each texel is
    /// multiplied by the first, as an MTL file's Kd multiplies its
    /// map_Kd; 1 in a scene file), twice.
    pub colors: [DVec3; 2],
    /// The cosine and sine of the angle the squares, or the uv
    /// coordinates, are turned by.
    pub rotation: [f64; 2],
    /// A corner of a solid pattern's cubes, in the coordinates the scene
    /// is traced in (moved with it by `Scene::camera_relative`).
    pub origin: DVec3,
    /// Its pattern's own numbers, laid out by its module; 0 where it has
    /// none (no pattern of the table has any yet).
    pub own: [f64; 4],
    /// An image's texels.
    pub texels: Option<Texels>,
}

/// What a pattern's check gives: everything of a texture but its pattern
/// and texels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Look {
    /// `Texture::size`.
    pub size: f64,
    /// `Texture::colors`.
    pub colors: [DVec3; 2],
    /// `Texture::rotation`.
    pub rotation: [f64; 2],
    /// `Texture::origin`.
    pub origin: DVec3,
    /// `Texture::own`.
    pub own: [f64; 4],
}

impl Default for Look {
    /// Untinted, unturned, at the origin, of size 1.
    fn default() -> Self {
        Look {
            size: 1.0,
            colors: [DVec3::ONE; 2],
            rotation: [1.0, 0.0],
            origin: DVec3::ZERO,
            own: [0.0; 4],
        }
    }
}

impl Texture {
    /// An image's texture, untinted, unturned, repeating at 1.
    pub fn image(texels: Texels) -> Texture {
        Texture {
            pattern: Pattern::Image,
            size: 1.0,
            colors: [DVec3::ONE; 2],
            rotation: [1.0, 0.0],
            origin: DVec3::ZERO,
            own: [0.0; 4],
            texels: Some(texels),
        }
    }

    /// The brightest colour it gives, per channel.
    pub fn brightest(&self) -> DVec3 {
        match self.texels {
            Some(t) => t.peak * self.colors[0],
            None => self.colors[0].max(self.colors[1]),
        }
    }

    /// Its struct in the shader's buffers, in coordinates moved by
    /// `-origin`.
    pub(crate) fn gpu(&self, origin: DVec3) -> gpu::Values {
        let xyz = |v: DVec3| [v.x, v.y, v.z, 0.0];
        let o = self.origin - origin;
        let code = self.pattern.code();
        gpu::Values {
            origin_size: [o.x, o.y, o.z, self.size],
            color0: xyz(self.colors[0]),
            color1: xyz(self.colors[1]),
            rotation: [self.rotation[0], self.rotation[1], 0.0, 0.0],
            own: self.own,
            meta: match self.texels {
                Some(i) => [code, i.first, i.width, i.height],
                None => [code, 0, 0, 0],
            },
        }
    }

    /// The texture in the CPU reference's arithmetic, moved by `-origin`.
    pub fn cpu<R: Real>(&self, origin: DVec3) -> TextureR<R> {
        TextureR {
            pattern: self.pattern,
            size: R::of(self.size),
            colors: self.colors.map(Vec3::of),
            rotation: self.rotation.map(R::of),
            origin: Vec3::of(self.origin - origin),
            own: self.own.map(R::of),
            texels: self.texels,
        }
    }
}

crate::base::interface::gpu_struct!(
    pub(crate) mod gpu: "Texture" {
        /// xyz a corner of a solid pattern's cubes, w the side
        origin_size: real4,
        /// rgb the colour of even cells
        color0: real4,
        /// rgb the colour of odd cells
        color1: real4,
        /// x cos, y sin of the angle
        rotation: real4,
        /// its pattern's own numbers (`Texture::own`)
        own: real4,
        /// x the pattern (PATTERN_*); an image's y first texel, z width,
        /// w height (its colour0 is its tint)
        meta: uvec4,
    }
);

/// A texture in the reference's arithmetic, in camera-relative
/// coordinates.
#[derive(Debug, Clone, Copy)]
pub struct TextureR<R> {
    /// `Texture::pattern`.
    pub pattern: Pattern,
    /// `Texture::size`.
    pub size: R,
    /// `Texture::colors`.
    pub colors: [Vec3<R>; 2],
    /// `Texture::rotation`.
    pub rotation: [R; 2],
    /// `Texture::origin`, moved.
    pub origin: Vec3<R>,
    /// `Texture::own`.
    pub own: [R; 4],
    /// An image's texels in `Scene::texels`.
    pub texels: Option<Texels>,
}

/// What one pattern provides.
pub trait PatternType {
    /// Its name: `pattern = "<name>"` in the scene file (but for a pattern
    /// read from a file), and the stem of `<name>_colour` in
    /// `shaders/texture/<include>.glsl`.
    const NAME: &'static str;
    /// How messages name one: `a "checker"`, `an image`.
    const WHAT: &'static str;
    /// Its GLSL include (shared by patterns of one module).
    const GLSL: &'static str;
    /// The include's name under shaders/texture/.
    const INCLUDE: &'static str;
    /// Whether it is read from an image file (`image = "..."`) rather than
    /// named by `pattern`.
    const FILE: bool = false;
    /// Its keys besides `pattern` and `image`, with serde's
    /// `deny_unknown_fields`: a key of another pattern is refused naming
    /// the patterns that take it, any other as unknown.
    type File: DeserializeOwned + Serialize;
    /// What of the surface it reads: its include reads it where the variant
    /// has it (`HAS_TEXTURES` a frame, `HAS_IMAGES` uvs).
    const NEEDS: Needs;

    /// Checks its keys (read from `at`'s table) into its look.
    fn check(file: Self::File, at: &PatternAt) -> Result<Look, SceneError>;
    /// Its colour at `p` on `surface` (whose uv or frame it has, where it
    /// needs them); mirrors `<name>_colour`.
    fn colour<R: Real>(
        t: &TextureR<R>,
        texels: &[[f32; 3]],
        surface: &dyn Shape<R>,
        p: Vec3<R>,
    ) -> Vec3<R>;
    /// One texture of this pattern, of squares about `p.size`, as a scene
    /// file's table (an image's file added to `p.files`): what
    /// `crate::generate` gives a textured material.
    fn sample(p: &mut Place) -> TextureFile;
}

/// Two colours apart from each other, for a generated pattern.
pub(crate) fn sample_colors(p: &mut Place) -> [Triple; 2] {
    let a = [
        p.uniform(0.5, 1.0),
        p.uniform(0.0, 1.0),
        p.uniform(0.0, 0.5),
    ];
    let b = [
        p.uniform(0.0, 0.3),
        p.uniform(0.0, 0.3),
        p.uniform(0.3, 1.0),
    ];
    [Triple(a), Triple(b)]
}

impl Needs {
    /// Whether primitives of `kind` have what this asks of a surface.
    pub(crate) fn met_by(self, kind: &crate::prim::KindInfo) -> bool {
        match self {
            Needs::Frame => kind.frame,
            Needs::Uv => kind.uv,
            Needs::Nothing => true,
        }
    }
}

/// What the generated code knows of a pattern.
#[derive(Debug, Clone, Copy)]
pub struct PatternInfo {
    /// Its variant.
    pub pattern: Pattern,
    /// `PatternType::NAME`.
    pub name: &'static str,
    /// `PatternType::WHAT`.
    pub what: &'static str,
    /// `PatternType::GLSL`.
    pub glsl: &'static str,
    /// `PatternType::INCLUDE`.
    pub include: &'static str,
    /// `PatternType::FILE`.
    pub file: bool,
    /// The keys of `PatternType::File`.
    pub keys: fn() -> &'static [&'static str],
    /// `PatternType::NEEDS`.
    pub needs: Needs,
    /// `PatternType::sample`.
    pub(crate) sample: fn(&mut Place) -> TextureFile,
}

impl PatternInfo {
    const fn of<P: PatternType>(pattern: Pattern) -> Self {
        Self {
            pattern,
            name: P::NAME,
            what: P::WHAT,
            glsl: P::GLSL,
            include: P::INCLUDE,
            file: P::FILE,
            keys: keys_of::<P::File>,
            needs: P::NEEDS,
            sample: P::sample,
        }
    }

    /// Its include's name: `texture/checker.glsl`.
    pub fn include(&self) -> String {
        format!("texture/{}.glsl", self.include)
    }

    /// The uppercase stem of its code's name: `CHECKER` in
    /// `PATTERN_CHECKER`.
    pub fn upper(&self) -> String {
        self.name.to_uppercase()
    }
}

macro_rules! patterns {
    ($($variant:ident : $ty:ty),* $(,)?) => {
        /// What a texture's colour depends on: its place in the table.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum Pattern {
            $(#[doc = concat!("`", stringify!($ty), "`.")] $variant,)*
        }

        /// The patterns, in the table's order.
        pub const PATTERNS: &[PatternInfo] = &[$(PatternInfo::of::<$ty>(Pattern::$variant),)*];

        impl Pattern {
            pub(crate) fn check(self, at: &PatternAt) -> Result<Look, SceneError> {
                match self {
                    $(Pattern::$variant => <$ty>::check(at.own::<<$ty as PatternType>::File>()?, at),)*
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
                    $(Pattern::$variant => <$ty>::colour(t, texels, surface, p),)*
                }
            }
        }

        #[cfg(test)]
        fn every_pattern_problems() -> Vec<String> {
            let mut out = Vec::new();
            $(out.extend(contract_tests::problems::<$ty>(Pattern::$variant));)*
            out
        }
    };
}

with_patterns!(patterns);

impl Pattern {
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
