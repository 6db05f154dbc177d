//! Procedural textures (docs/scene-format.md, Textures): a material's
//! diffuse colour, and by default its ambient colour, taken from a pattern
//! at the hit point instead of one colour. Both renderers evaluate them
//! alike (src/cpu/texture.rs, shaders/texture.glsl).

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::input::field::Triple;

/// `[textures.NAME]` as written.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TextureFile {
    /// `"checker"` or `"solid_checker"`.
    pub pattern: String,
    /// The side of a square (a cube for the solid checker), > 0.
    pub size: f64,
    /// The two colours, the first at the origin's square.
    pub colors: [Triple; 2],
    /// `"checker"`: the squares turned by this many degrees about the
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
}

impl Pattern {
    /// The pattern's code in the shader (`texture.glsl`).
    pub fn code(self) -> u32 {
        match self {
            Pattern::Checker => 1,
            Pattern::SolidChecker => 2,
        }
    }
}

/// One checked texture.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Texture {
    /// Its pattern.
    pub pattern: Pattern,
    /// The side of a square or cube.
    pub size: f64,
    /// The colour of the squares whose cell indices sum to an even number,
    /// then to an odd one.
    pub colors: [DVec3; 2],
    /// `Checker`: the cosine and sine of the angle the squares are turned by.
    pub rotation: [f64; 2],
    /// `SolidChecker`: a corner of the cubes, in the coordinates the scene
    /// is traced in (moved with it by `Scene::camera_relative`).
    pub origin: DVec3,
}
