//! Renders a scene on the GPU (lavapipe where there is no GPU) and writes
//! it as a PNG: the library's path of `glint render`.
//!
//! cargo run --release --example render_to_png -- scenes/seed-fig5.toml out.png

use std::path::PathBuf;

use anyhow::{Context, Result};
use glint::gpu::{GpuOptions, Rendered, Renderer};
use glint::raster::io;
use glint::scene::{Overrides, Scene};

fn main() -> Result<()> {
    let mut args = std::env::args_os().skip(1).map(PathBuf::from);
    let scene_path = args
        .next()
        .unwrap_or_else(|| "scenes/seed-fig5.toml".into());
    let out = args.next().unwrap_or_else(|| "render_to_png.png".into());

    let scene = Scene::load(&scene_path, &Overrides::default())?;
    // GLINT_VALIDATION=1 turns the validation layer on, as the tests do.
    let mut gpu = Renderer::new(&GpuOptions::from_env(None)).context("opening a Vulkan device")?;
    // Two stages: the scene laid out, compiled and uploaded once, then
    // rendered (any region of it, as often as asked).
    let mut prepared = gpu.prepare(&scene, &gpu.settings())?;
    let Rendered { image, times, .. } = prepared.render(None, &|_pixels| {})?;
    io::write(&out, &image, scene.srgb)?;
    println!(
        "{}: {}x{} on {} in {:.3} s",
        out.display(),
        image.width,
        image.height,
        gpu.device_info().name,
        times.total_s()
    );
    Ok(())
}
