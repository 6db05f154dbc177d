//! The ground floor: what every layer above shares and nothing here
//! imports from them. The real types and their exact sums, the ray, the
//! bounding box, the precision a renderer computes in, the host↔shader
//! struct layouts, the workgroup shape, and what a renderer counts and
//! records. The layers above, bottom up, are listed in docs/shaders.md
//! (Layers) and checked by tests/layers.rs.

pub mod aabb;
pub mod aov;
pub mod count;
pub mod exact;
pub mod interface;
pub mod own_math;
pub mod ray;
pub mod real;
pub mod record;
pub mod tally;

/// The arithmetic: the shader's, or the CPU reference's (`glint render
/// --precision`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Precision {
    /// Floats throughout, as the CPU reference's f32.
    #[default]
    F32,
    /// Doubles throughout, the scene uploaded in doubles; needs the device's
    /// shaderFloat64. GLSL has no double pow, so the specular power is f32.
    F64,
}

/// The compute workgroup's width and height, in pixels: the shader's
/// `local_size` (generated from this) and the height of the bands the CPU
/// renders and tiles split into (`crate::raster::region::BAND_ROWS`).
pub const WORKGROUP: u32 = 8;
