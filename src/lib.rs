#![warn(missing_docs)]
//! glint: a headless Whitted-style ray tracer. A Vulkan compute shader
//! renders; a CPU reference in f64 (and f32) checks it pixel by pixel.

#![warn(clippy::undocumented_unsafe_blocks, clippy::missing_safety_doc)]

pub mod accel;
pub mod bench;
pub mod condition;
pub mod cpu;
pub mod files;
pub(crate) mod fnv;
pub mod gpu;
pub(crate) mod prim;
pub mod printable;
pub mod raster;
pub mod report;
pub(crate) mod rng;
pub mod scene;
pub mod stability;
pub mod stats;
pub mod tiles;
