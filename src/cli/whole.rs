//! What `render` reports of a whole render, from either backend: made by
//! render.rs (the CPU) and render_gpu.rs (the GPU), so kept below both.

use glint::aov::Aov;
use glint::raster::Image;
use glint::stats::Counts;

/// What `render` reports of a whole render.
pub struct Whole {
    pub image: Image,
    pub label: String,
    /// The render's seconds, without its setup.
    pub seconds: f64,
    /// Opening the device, compiling, the BVH and the tables.
    pub setup_s: f64,
    /// Of the setup, building the tables (`--accel tables`).
    pub tables_s: f64,
    pub counts: Option<Counts>,
    /// The pixels' AOVs, where asked for.
    pub aovs: Option<Vec<Aov>>,
}

/// What a whole render gives besides its image.
#[derive(Debug, Clone, Copy, Default)]
pub struct Want {
    /// Its counts (`--stats`).
    pub count: bool,
    /// Its pixels' AOVs (`--aov`).
    pub aovs: bool,
}
