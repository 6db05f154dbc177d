//! Textures (docs/scene-format.md, Textures): a material's diffuse colour,
//! and by default its ambient colour, taken from a pattern or an image at
//! the hit point instead of one colour. Both renderers evaluate them alike
//! (src/cpu/texture.rs, shaders/texture.glsl).

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::input::field::Triple;

/// `[textures.NAME]` as written: a `pattern` or an `image`.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TextureFile {
    /// `"checker"` or `"solid_checker"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pattern: Option<String>,
    /// A PNG, EXR or PFM file, relative to the scene file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub image: Option<String>,
    /// The side of a square (a cube for the solid checker), > 0; for an
    /// image, the uv distance it repeats at (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub size: Option<f64>,
    /// A pattern's two colours, the first at the origin's square.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub colors: Option<[Triple; 2]>,
    /// `"checker"` and images: turned by this many degrees about the
    /// surface's normal, from its own u axis.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub angle: Option<f64>,
    /// `"solid_checker"`: a corner of the cubes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub origin: Option<Triple>,
}

/// What a texture's colour depends on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Pattern {
    /// Squares in the surface's own coordinates (planes and triangles:
    /// `crate::prim::Shape::frame`).
    Checker,
    /// Cubes in the scene's coordinates, on any surface.
    SolidChecker,
    /// An image's texels at the surface's uv coordinates
    /// (`crate::prim::Shape::uv`), filtered bilinearly, repeated.
    Image,
}

impl Pattern {
    /// The pattern's code in the shader (`texture.glsl`).
    pub fn code(self) -> u32 {
        match self {
            Pattern::Checker => 1,
            Pattern::SolidChecker => 2,
            Pattern::Image => 3,
        }
    }
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
    /// `Checker` and `Image`: the cosine and sine of the angle the squares,
    /// or the uv coordinates, are turned by.
    pub rotation: [f64; 2],
    /// `SolidChecker`: a corner of the cubes, in the coordinates the scene
    /// is traced in (moved with it by `Scene::camera_relative`).
    pub origin: DVec3,
    /// `Image`: its texels.
    pub texels: Option<Texels>,
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

    /// Whether it needs the surface's own frame (a checker) or uv
    /// coordinates (an image), which not every kind has.
    pub fn needs_surface(&self) -> Option<&'static str> {
        match self.pattern {
            Pattern::Checker => Some("frame"),
            Pattern::Image => Some("uv"),
            Pattern::SolidChecker => None,
        }
    }
}
