//! glint: a headless Whitted-style ray tracer. A Vulkan compute shader
//! renders; a CPU reference in f64 (and f32) checks it pixel by pixel.
//!
//! The library serves three uses, each shown by a program in examples/:
//!
//! - **Rendering** (`render_to_png.rs`): [`scene::Scene::load`] reads a
//!   TOML or NFF scene; [`gpu::Renderer::prepare`] lays it out, compiles
//!   and uploads it for Vulkan (lavapipe where there is no GPU), and the
//!   [`gpu::Prepared`] scene renders any region of it; [`raster::io`]
//!   writes PNG, PFM or EXR.
//! - **CPU-vs-GPU comparison tests** (`compare_gpu_cpu.rs`): [`cpu::render`]
//!   is the reference, in f64 or f32; [`raster::diff::figures`] measures an
//!   image against it and [`raster::diff::Tolerance`] judges it. The scene
//!   is plain data, so a test can perturb it and see the check fail.
//! - **Shader experiments** (`custom_shader.rs`): [`gpu::GpuOptions`] takes
//!   directories searched before the built-in shader files, a replacement
//!   main shader and defines; [`gpu::Renderer::variant`] shows what a
//!   scene compiles with.
//!
//! [`settings`] names the choices both renderers take (precision, accel,
//! intersection forms, schedule); [`sampling`] holds how both place and
//! refine a pixel's samples. The other public modules are what
//! glint's commands are built from:
#![cfg_attr(
    feature = "gpu",
    doc = "[`report`] (error against run time), [`stability`] and [`condition`]
(the extreme scenes and the conditioning check), [`bench`](mod@bench),"
)]
#![cfg_attr(
    not(feature = "gpu"),
    doc = "[`condition`] (the conditioning check; `report`, `stability` and
`bench` are the default build's),"
)]
//! [`tiles`] (tiled renders and their assembly), [`stats`] (ray and test
//! counts), [`explain`] (one pixel's ray trees on every renderer),
//! [`drivers`] (a driver's verdict against the reference, and the
//! reproducer of its failure), [`files`] and [`printable`].
#![cfg_attr(
    not(feature = "gpu"),
    doc = r#"
## Without the GPU renderer

This build was made without the `gpu` feature (`--no-default-features`): it
has no `gpu`, `report`, `stability` or `bench` module, and the items named
above that live in them are in the default build alone.

[`gpu::Renderer::prepare`]: #without-the-gpu-renderer
[`gpu::Prepared`]: #without-the-gpu-renderer
[`gpu::GpuOptions`]: #without-the-gpu-renderer
[`gpu::Renderer::variant`]: #without-the-gpu-renderer
"#
)]
#![warn(missing_docs)]
#![warn(clippy::undocumented_unsafe_blocks, clippy::missing_safety_doc)]
// Without the GPU renderer the kinds' GPU structs and GLSL names, and the
// layout helpers they are declared with, have no reader. They stay built:
// a kind is one unit in both builds, and they are plain data, not Vulkan.
// The default build still reports any code that nothing uses.
#![cfg_attr(not(feature = "gpu"), allow(dead_code))]

pub mod accel;
pub(crate) mod base;
/// A render's AOVs, as both renderers give them.
pub use base::aov;
#[cfg(feature = "gpu")]
pub mod bench;
pub mod condition;
pub mod cpu;
pub mod drivers;
pub mod explain;
pub mod files;
pub mod fnv;
pub mod fuzz;
pub mod generate;
#[cfg(feature = "gpu")]
pub mod gpu;
pub mod input;
pub mod output;
pub(crate) mod prim;
pub mod printable;
pub mod raster;
#[cfg(feature = "gpu")]
pub mod report;
pub(crate) mod rng;
pub mod sampling;
pub mod scene;
pub mod settings;
pub mod spec_worst;
#[cfg(feature = "gpu")]
pub mod stability;
pub mod stats;
pub mod tiles;
