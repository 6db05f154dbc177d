use crate::cli::console::errln;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::mpsc;
use std::time::Duration;

use anyhow::Context;
use clap::Args;
use notify_debouncer_mini::{new_debouncer, notify::RecursiveMode};

use glint::files::Stamp;
use glint::gpu::{GpuError, Renderer};
use glint::output::Outputs;
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
/// user's, each with what says it changed.
fn stamp(scene: &Path, device: &DeviceArgs) -> Vec<(PathBuf, Option<Stamp>)> {
    let mut files = vec![scene.to_owned()];
    files.extend(device.shader.iter().cloned());
    files.extend(glint::files::in_dirs(&device.include));
    files
        .into_iter()
        .map(|f| {
            let stamp = Stamp::of_file(&f);
            (f, stamp)
        })
        .collect()
}

/// The directories to watch, and how: the scene's and each shader file's
/// own directory (editors often save by renaming a new file over the old,
/// which a watch on the file itself would lose), and each include
/// directory (the files directly in it, as the compile searches it).
fn watched(scene: &Path, device: &DeviceArgs) -> Vec<(PathBuf, RecursiveMode)> {
    let parent = |f: &Path| glint::files::folder_of(f).to_owned();
    let mut dirs: Vec<(PathBuf, RecursiveMode)> = Vec::new();
    let files = std::iter::once(scene).chain(device.shader.iter().map(PathBuf::as_path));
    for dir in files.map(parent) {
        if !dirs.iter().any(|(d, _)| *d == dir) {
            dirs.push((dir, RecursiveMode::NonRecursive));
        }
    }
    dirs.extend(
        device
            .include
            .iter()
            .map(|d| (d.clone(), RecursiveMode::NonRecursive)),
    );
    dirs
}

/// Re-renders whenever the scene or a shader file changes; a failed render
/// prints its error and leaves the last good image in place. Runs until
/// interrupted.
pub fn run(a: &WatchArgs) -> anyhow::Result<ExitCode> {
    io::Format::of_output(&a.output)?;
    let mut inputs = a.device.inputs();
    inputs.push(a.scene.scene.clone());
    Outputs::new(inputs, false).check(&a.output)?;
    let options = a.device.options()?;
    let mut renderer = Renderer::new(&options)?;
    // Editors write a file in bursts (truncate, write, rename): one render
    // for a burst, once it has been quiet this long.
    let (events, changes) = mpsc::channel();
    let mut debouncer = new_debouncer(Duration::from_millis(100), events)
        .context("cannot watch for file changes")?;
    let dirs = watched(&a.scene.scene, &a.device);
    let mut identities = Vec::new();
    for (dir, mode) in &dirs {
        debouncer
            .watcher()
            .watch(dir, *mode)
            .with_context(|| format!("cannot watch {}", glint::printable::path(dir)))?;
        identities.push(identity(dir));
    }
    errln!("watching {} (Ctrl-C to stop)", a.scene.scene.display());
    // An event is only a hint: the files' stamps decide whether a
    // render's inputs changed (the output, written beside the scene, and
    // other files in these directories change nothing).
    let mut last = None;
    loop {
        let now = stamp(&a.scene.scene, &a.device);
        if last.as_ref() != Some(&now) {
            last = Some(now);
            match render_once(a, &mut renderer) {
                Ok(seconds) => errln!("rendered in {seconds:.3} s -> {}", a.output.display()),
                Err(e) => {
                    errln!("error: {e:#}\n(keeping the last good image)");
                    // A timed-out render may run on, and its device takes no
                    // more work: the next change renders on a new one.
                    if e.downcast_ref::<GpuError>()
                        .is_some_and(GpuError::device_lost)
                    {
                        renderer = Renderer::new(&options)?;
                        errln!("(the device was opened again for the next change)");
                    }
                }
            }
        }
        match changes.recv_timeout(RECHECK) {
            Ok(Ok(_)) | Err(mpsc::RecvTimeoutError::Timeout) => {}
            Ok(Err(e)) => errln!("error: watching files: {e}"),
            Err(mpsc::RecvTimeoutError::Disconnected) => anyhow::bail!("the file watcher stopped"),
        }
        // A folder deleted and made again is a new folder, which the old
        // watch does not see: watch it afresh.
        for ((dir, mode), known) in dirs.iter().zip(identities.iter_mut()) {
            let now = identity(dir);
            if now != *known {
                let _ = debouncer.watcher().unwatch(dir);
                if now.is_some() && debouncer.watcher().watch(dir, *mode).is_err() {
                    continue;
                }
                *known = now;
            }
        }
    }
}

/// How often the files are looked at without an event: a deleted folder
/// sends none once it is made again.
const RECHECK: Duration = Duration::from_secs(1);

/// A folder's identity: its device and inode, None while it is missing.
fn identity(dir: &Path) -> Option<(u64, u64)> {
    use std::os::unix::fs::MetadataExt;
    std::fs::metadata(dir).ok().map(|m| (m.dev(), m.ino()))
}

fn render_once(a: &WatchArgs, renderer: &mut Renderer) -> anyhow::Result<f64> {
    let scene = a.scene.load()?;
    // Checked again each time: an edit may name the output as a mesh.
    let mut outputs = Outputs::new(super::inputs(&a.scene.scene, &scene, &a.device), false);
    outputs.check(&a.output)?;
    let (image, times) = renderer.render(&scene, &|_| {})?;
    io::stage(&mut outputs, &a.output, &image, scene.srgb)?;
    outputs.commit()?;
    Ok(times.total_s())
}
