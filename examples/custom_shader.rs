//! A shader experiment from Rust: the built-in shader with one file
//! replaced by a directory searched first (as `glint render -I DIR`). Here
//! shaders/experiments/phong/specular.glsl swaps Blinn-Phong's (N·H)ⁿ for
//! Phong's (R·V)ⁿ; the image changes in the highlights and nowhere else
//! that matters. The variant's defines show what the scene compiled with.
//!
//! cargo run --release --example custom_shader -- [EXPERIMENT_DIR]

use std::path::PathBuf;

use anyhow::Result;
use glint::gpu::{GpuOptions, Renderer};
use glint::raster::diff::figures;
use glint::scene::{Overrides, Scene};

fn main() -> Result<()> {
    let dir: PathBuf = std::env::args_os()
        .nth(1)
        .map_or_else(|| "shaders/experiments/phong".into(), PathBuf::from);
    let small = Overrides {
        width: Some(160),
        height: Some(120),
        ..Overrides::default()
    };
    let scene = Scene::load("scenes/seed-fig5.toml".as_ref(), &small)?;

    let mut stock = Renderer::new(&GpuOptions::from_env(None))?;
    let mut experiment = Renderer::new(&GpuOptions {
        include_dirs: vec![dir.clone()],
        ..GpuOptions::from_env(None)
    })?;

    let (variant, defines) = experiment.variant(&scene, &experiment.settings());
    println!("variant {}:", variant.name());
    for (name, value) in &defines {
        println!(
            "  -D {name}{}",
            value.as_ref().map_or(String::new(), |v| format!("={v}"))
        );
    }

    let (before, _) = stock.render(&scene, &|_| {})?;
    let (after, _) = experiment.render(&scene, &|_| {})?;
    let change = figures(&after, &before)?;
    println!(
        "{} against the built-in shader: max_abs {:.3}, {:.2}% of channels over 1/255",
        dir.display(),
        change.max_abs,
        100.0 * change.frac_over_1_255
    );
    Ok(())
}
