use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::Context;
use clap::Args;

use glint::accel::Accel;
use glint::cpu::stats::RayCounts;
use glint::raster::{io, Image};
use glint::scene::Scene;
use glint::{cpu, gpu};

use super::{progress, Backend, DeviceArgs, Precision, SceneArgs};

#[derive(Args)]
pub struct RenderArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Output file: .png, .pfm or .exr [default: the scene's name with .png]
    #[arg(short, long)]
    output: Option<PathBuf>,
    #[arg(long, value_enum, default_value = "gpu")]
    backend: Backend,
    /// Arithmetic precision [default: f32 on the GPU, f64 on the CPU]
    #[arg(long, value_enum)]
    precision: Option<Precision>,
    /// Replace a read-only output file too.
    #[arg(long)]
    force: bool,
    /// Write the rays cast and the times to FILE as JSON (docs/spd.md); with --backend cpu.
    #[arg(long, value_name = "FILE")]
    stats: Option<PathBuf>,
    #[command(flatten)]
    device: DeviceArgs,
}

/// What `--stats` writes.
#[derive(serde::Serialize)]
struct Stats {
    rays: RayCounts,
    seconds: StatsSeconds,
}

#[derive(serde::Serialize)]
struct StatsSeconds {
    /// Reading and checking the scene file.
    input: f64,
    /// The scene in the renderer's precision and its BVH.
    setup: f64,
    trace: f64,
}

impl RenderArgs {
    /// Every file the render reads, none of which it may write.
    fn inputs(&self) -> Vec<&Path> {
        let mut v = vec![self.scene.scene.as_path()];
        v.extend(self.device.shader.as_deref());
        v
    }

    fn outputs(&self, image: &Path) -> Vec<PathBuf> {
        let mut v = vec![image.to_owned()];
        v.extend(self.stats.clone());
        v
    }
}

pub fn run(a: &RenderArgs) -> anyhow::Result<ExitCode> {
    let output = match &a.output {
        Some(o) => o.clone(),
        None => PathBuf::from(a.scene.scene.file_stem().unwrap_or_default()).with_extension("png"),
    };
    // Refuse a bad output name before spending time on the render.
    io::Format::of(&output)?;
    if a.stats.is_some() && a.backend != Backend::Cpu {
        anyhow::bail!(
            "--stats: the rays are counted by the CPU renderer so far; add --backend cpu"
        );
    }
    if a.stats.as_ref() == Some(&output) {
        anyhow::bail!("--stats names the image's own file {}", output.display());
    }
    for out in a.outputs(&output) {
        io::refuse_input(&out, &a.inputs())?;
        io::check_target(&out, a.force)?;
    }
    let loading = Instant::now();
    let scene = a.scene.load()?;
    let input_s = loading.elapsed().as_secs_f64();
    let mut stats = None;
    let (image, label, seconds) = match (a.backend, a.precision) {
        (Backend::Gpu, p) => render_gpu(&scene, &a.device, p.unwrap_or(Precision::F32))?,
        (Backend::Cpu, p) => {
            let (image, label, times, rays) =
                render_cpu_timed(&scene, p.unwrap_or(Precision::F64), a.device.accel.into());
            stats = Some(Stats {
                rays,
                seconds: StatsSeconds {
                    input: input_s,
                    setup: times.setup_s,
                    trace: times.render_s,
                },
            });
            (image, label, times.render_s)
        }
    };
    // glint's own shading stays finite for every scene it accepts; a shader
    // of the user's may not, and such an image is not written.
    let nonfinite = image
        .pixels
        .iter()
        .flatten()
        .filter(|c| !c.is_finite())
        .count();
    if let Some(i) = image
        .pixels
        .iter()
        .position(|p| p.iter().any(|c| !c.is_finite()))
    {
        anyhow::bail!(
            "the render has {nonfinite} non-finite values, the first at pixel ({}, {}); the image is not written",
            i % image.width as usize,
            i / image.width as usize
        );
    }
    io::write_forced(&output, &image, scene.srgb, a.force)
        .with_context(|| "cannot write the image")?;
    if let (Some(path), Some(stats)) = (&a.stats, &stats) {
        let json = serde_json::to_string_pretty(stats)?;
        io::write_atomic(path, a.force, |out, p| {
            writeln!(out, "{json}").map_err(io::io_err(p))
        })
        .with_context(|| "cannot write the statistics")?;
    }
    eprintln!(
        "rendered {}x{} ({} spp, depth {}) with {label} in {seconds:.3} s -> {}",
        scene.width,
        scene.height,
        scene.samples * scene.samples,
        scene.max_depth,
        output.display()
    );
    Ok(ExitCode::SUCCESS)
}

pub fn render_gpu(
    scene: &Scene,
    device: &DeviceArgs,
    precision: Precision,
) -> anyhow::Result<(Image, String, f64)> {
    let (image, renderer, times, _) = render_gpu_timed(scene, device, precision)?;
    let name = if precision == Precision::F64 {
        "f64"
    } else {
        "f32"
    };
    Ok((
        image,
        format!("GPU {name} on {}", renderer.device_info().name),
        times.total_s(),
    ))
}

/// Renders on the GPU, returning the renderer too (for its device) and
/// the setup times of the scene's variant.
pub fn render_gpu_timed(
    scene: &Scene,
    device: &DeviceArgs,
    precision: Precision,
) -> anyhow::Result<(Image, gpu::Renderer, gpu::RenderTimes, gpu::SetupTimes)> {
    let mut options = device.options()?;
    options.settings.precision = match precision {
        Precision::F32 => gpu::Precision::F32,
        Precision::F64 => gpu::Precision::F64,
    };
    let mut renderer = gpu::Renderer::new(&options)?;
    let setup = renderer.prepare_for(scene)?;
    let bar = progress::bar(
        scene.pixel_count(),
        if precision == Precision::F64 {
            "gpu f64"
        } else {
            "gpu f32"
        },
    );
    let (image, times) = super::exit_on_timeout(renderer.render(scene, &|n| bar.inc(n)))?;
    bar.finish_and_clear();
    Ok((image, renderer, times, setup))
}

/// The CPU's setup (the scene in its precision, the BVH) and render times.
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct CpuTimes {
    pub setup_s: f64,
    pub render_s: f64,
}

pub fn render_cpu_timed(
    scene: &Scene,
    precision: Precision,
    accel: Accel,
) -> (Image, String, CpuTimes, RayCounts) {
    let bar = progress::bar(
        u64::from(scene.height),
        &format!("cpu {precision:?}").to_lowercase(),
    );
    let start = Instant::now();
    let ((image, rays), setup_s) = match precision {
        Precision::F32 => {
            let world = cpu::world::World::<f32>::new(scene, accel);
            let setup_s = start.elapsed().as_secs_f64();
            (cpu::render_counted(&world, &|n| bar.inc(n)), setup_s)
        }
        Precision::F64 => {
            let world = cpu::world::World::<f64>::new(scene, accel);
            let setup_s = start.elapsed().as_secs_f64();
            (cpu::render_counted(&world, &|n| bar.inc(n)), setup_s)
        }
    };
    let render_s = start.elapsed().as_secs_f64() - setup_s;
    bar.finish_and_clear();
    let threads = rayon::current_num_threads();
    (
        image,
        format!("CPU {precision:?} on {threads} threads").replace("F", "f"),
        CpuTimes { setup_s, render_s },
        rays,
    )
}
