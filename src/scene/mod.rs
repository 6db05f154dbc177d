//! The scene: read from TOML (docs/scene-format.md), validated, and resolved into the
//! form both renderers consume (materials by index, unit normals, the camera
//! as an eye and a virtual screen).

mod corners;
mod error;
mod file;
mod locate;
pub mod nff;
mod rebase;
mod split;
mod validate;

use std::path::Path;

use glam::DVec3;

pub use error::SceneError;
pub use file::{Sampling, Triple};
pub use validate::{parse, parse_nff, unit_vector, At, Overrides, MAX_COORDINATE};

use crate::prim::Prims;

pub const MAX_SIZE: u32 = 16384;
pub const MAX_SAMPLES: u32 = 16;
pub const MAX_DEPTH: u32 = 64;

#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    pub width: u32,
    pub height: u32,
    pub samples: u32,
    pub sampling: Sampling,
    pub srgb: bool,
    pub max_depth: u32,
    pub shadows: bool,
    pub background: DVec3,
    pub camera: Camera,
    pub materials: Vec<Material>,
    /// Every primitive, a list for each kind (`crate::prim`).
    pub prims: Prims,
    pub lights: Vec<Light>,
}

/// The camera of form (a) in docs/scene-format.md: an eye and a virtual
/// screen. Form (b) is converted to
/// this on load.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    pub eye: DVec3,
    pub screen_center: DVec3,
    pub screen_right: DVec3,
    pub screen_up: DVec3,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    pub name: String,
    pub ambient: DVec3,
    pub diffuse: DVec3,
    pub specular: DVec3,
    pub shininess: f64,
    pub reflectivity: f64,
    /// The refraction ray's weight, 0..1 (docs/scene-format.md, Shading).
    pub transmittance: f64,
    /// Index of refraction, > 0: inside over outside.
    pub ior: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LightKind {
    Point,
    Directional,
    Spot,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Light {
    pub kind: LightKind,
    /// Point and spot lights; zero for directional ones.
    pub position: DVec3,
    /// Unit length: the way a directional light travels, a spot light's axis.
    pub direction: DVec3,
    pub ambient: DVec3,
    pub diffuse: DVec3,
    pub specular: DVec3,
    /// [c, l, q]: 1 / (c + l d + q d²).
    pub attenuation: DVec3,
    /// cos(cutoff) of a spot light.
    pub cos_cutoff: f64,
    pub exponent: f64,
}

impl Light {
    /// Whether the light has a diffuse or specular term: a shadow ray
    /// towards a light without one could change nothing.
    pub fn has_direct_term(&self) -> bool {
        self.diffuse != DVec3::ZERO || self.specular != DVec3::ZERO
    }
}

/// Whether `path` names an NFF file (by its extension, `.nff` in any case).
pub fn is_nff(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("nff"))
}

impl Scene {
    /// Reads and validates a scene file, then applies command-line overrides.
    pub fn load(path: &Path, overrides: &Overrides) -> Result<Scene, SceneError> {
        let text = std::fs::read_to_string(path).map_err(|cause| SceneError::Read {
            path: path.to_owned(),
            cause,
        })?;
        if is_nff(path) {
            validate::parse_nff(&text, path, overrides)
        } else {
            parse(&text, path, overrides)
        }
    }

    pub fn pixel_count(&self) -> u64 {
        u64::from(self.width) * u64::from(self.height)
    }

    /// Primary rays per image.
    pub fn ray_count(&self) -> u64 {
        self.pixel_count() * u64::from(self.samples * self.samples)
    }
}
