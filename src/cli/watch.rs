use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, SystemTime};

use clap::Args;

use glint::gpu::Renderer;
use glint::raster::io;

use super::{DeviceArgs, SceneArgs};

#[derive(Args)]
pub struct WatchArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// The image to keep up to date (.png, .pfm or .exr).
    #[arg(short, long)]
    output: PathBuf,
    #[command(flatten)]
    device: DeviceArgs,
}

/// What a render depends on: the scene file and every shader file of the
/// user's, each with its modification time and size.
fn stamp(scene: &Path, device: &DeviceArgs) -> Vec<(PathBuf, Option<SystemTime>, u64)> {
    let mut files = vec![scene.to_owned()];
    files.extend(device.shader.iter().cloned());
    files.extend(glint::files::in_dirs(&device.include));
    files
        .into_iter()
        .map(|f| {
            let meta = std::fs::metadata(&f).ok();
            let modified = meta.as_ref().and_then(|m| m.modified().ok());
            let len = meta.map_or(0, |m| m.len());
            (f, modified, len)
        })
        .collect()
}

/// Re-renders whenever the scene or a shader file changes; a failed render
/// prints its error and leaves the last good image in place. Runs until
/// interrupted.
pub fn run(a: &WatchArgs) -> anyhow::Result<ExitCode> {
    io::Format::of(&a.output)?;
    let mut inputs = vec![a.scene.scene.as_path()];
    inputs.extend(a.device.shader.as_deref());
    io::refuse_input(&a.output, &inputs)?;
    let mut renderer = Renderer::new(&a.device.options()?)?;
    let mut last = None;
    eprintln!("watching {} (Ctrl-C to stop)", a.scene.scene.display());
    loop {
        let now = stamp(&a.scene.scene, &a.device);
        if last.as_ref() != Some(&now) {
            last = Some(now);
            match render_once(a, &mut renderer) {
                Ok(seconds) => eprintln!("rendered in {seconds:.3} s -> {}", a.output.display()),
                Err(e) => eprintln!("error: {e:#}\n(keeping the last good image)"),
            }
        }
        std::thread::sleep(Duration::from_millis(200));
    }
}

fn render_once(a: &WatchArgs, renderer: &mut Renderer) -> anyhow::Result<f64> {
    let scene = a.scene.load()?;
    let (image, times) = super::exit_on_timeout(renderer.render(&scene, &|_| {}))?;
    io::write(&a.output, &image, scene.srgb)?;
    Ok(times.total_s())
}
