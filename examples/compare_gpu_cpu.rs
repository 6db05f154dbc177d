//! A CPU-vs-GPU comparison test in a few lines: the GPU image against the
//! CPU f64 reference, held to the default tolerance; then a perturbed
//! scene, which the same check must reject.
//!
//! cargo run --release --example compare_gpu_cpu -- scenes/seed-fig4.toml

use std::path::PathBuf;

use anyhow::{bail, Result};
use glint::gpu::{GpuOptions, Renderer};
use glint::raster::diff::{figures, Tolerance};
use glint::scene::{Overrides, Scene};

fn main() -> Result<()> {
    let path: PathBuf = std::env::args_os()
        .nth(1)
        .map_or_else(|| "scenes/seed-fig4.toml".into(), PathBuf::from);
    let small = Overrides {
        width: Some(160),
        height: Some(120),
        ..Overrides::default()
    };
    let scene = Scene::load(&path, &small)?;
    let mut gpu = Renderer::new(&GpuOptions::from_env(None))?;
    let tolerance = Tolerance::default();

    let reference = glint::cpu::render::<f64>(&scene);
    let (image, _) = gpu.render(&scene, &|_| {})?;
    let error = figures(&image, &reference)?;
    println!(
        "GPU f32 against CPU f64: max_abs {:.2e}, rmse {:.2e}, {:.4}% over 1/255",
        error.max_abs,
        error.rmse,
        100.0 * error.frac_over_1_255
    );
    let violations = tolerance.violations(&error);
    if !violations.is_empty() {
        bail!("the GPU disagrees with the reference: {violations:?}");
    }

    // The check can fail: move the first sphere by a tenth of its radius.
    let mut moved = scene.clone();
    let Some(sphere) = moved.prims.spheres.first_mut() else {
        bail!("{}: no sphere to move", path.display());
    };
    sphere.center.x += 0.1 * sphere.radius;
    let (image, _) = gpu.render(&moved, &|_| {})?;
    let error = figures(&image, &reference)?;
    if tolerance.violations(&error).is_empty() {
        bail!("a moved sphere passed the check (rmse {:.2e})", error.rmse);
    }
    println!("a moved sphere fails it: rmse {:.2e}", error.rmse);
    Ok(())
}
