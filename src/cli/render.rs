use crate::cli::console::errln;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::Context;
use clap::Args;

use glint::accel::Accel;
use glint::aov::Aov;
use glint::cpu;
use glint::output::{self, Outputs};
use glint::raster::{io, Image};
use glint::sampling::Sampled;
use glint::scene::Scene;
use glint::settings::Choice;
use glint::stats::{Counts, RayCounts, Work};
use glint::tiles;

use super::render_aov::AovFiles;
use super::render_gpu;
use super::tile::{self, TileArgs};
use super::whole::Want;
use super::{progress, Backend, DeviceArgs, Precision, SceneArgs};

#[derive(Args)]
pub struct RenderArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Output file: .png, .pfm or .exr [default: the scene's name with .png]
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Where to render: gpu (Vulkan), or cpu (the reference renderer).
    #[arg(long, value_enum, default_value = "gpu")]
    backend: Backend,
    /// Arithmetic precision [default: f32 on the GPU, f64 on the CPU]
    #[arg(long, value_parser = super::choice::of::<Precision>())]
    precision: Option<Precision>,
    /// Replace a read-only output file too.
    #[arg(long)]
    force: bool,
    /// Write the rays cast, the tests they cost and the times to FILE as JSON (docs/spd.md).
    #[arg(long, value_name = "FILE")]
    stats: Option<PathBuf>,
    /// Write an AOV (depth, normal, albedo, prim_id, rays) as .exr or .pfm:
    /// NAME to -o's file in place of the colour, NAME=FILE beside it. Repeatable.
    #[arg(long = "aov", value_name = "NAME[=FILE]")]
    aovs: Vec<String>,
    #[command(flatten)]
    tiles: TileArgs,
    #[command(flatten)]
    device: DeviceArgs,
}

/// What `--stats` writes.
#[derive(serde::Serialize)]
struct Stats {
    rays: RayCounts,
    /// Ray/primitive tests by kind, `bvh_nodes`: BVH nodes visited, and
    /// `table_cells`: cells of a light buffer or the eye's tiles read.
    tests: std::collections::BTreeMap<&'static str, u64>,
    /// The same by the type of ray that cost them, with the rays of each type.
    by_ray: std::collections::BTreeMap<&'static str, Work>,
    seconds: StatsSeconds,
}

impl Stats {
    fn new(counts: &Counts, input: f64, setup: f64, tables: f64, trace: f64) -> Self {
        Self {
            rays: counts.rays(),
            tests: counts.tests(),
            by_ray: counts.by_ray(),
            seconds: StatsSeconds {
                input,
                setup,
                tables,
                trace,
            },
        }
    }
}

#[derive(serde::Serialize)]
struct StatsSeconds {
    /// Reading and checking the scene file.
    input: f64,
    /// The scene in the renderer's precision and its BVH; on the GPU also
    /// opening the device and compiling the (counting) shader.
    setup: f64,
    /// Of the setup, building the light buffers and the eye's tiles
    /// (`--accel tables`; 0 without them).
    tables: f64,
    trace: f64,
}

impl RenderArgs {
    /// Every file the render reads, none of which it may write.
    fn inputs(&self, scene: &Scene) -> Vec<PathBuf> {
        super::inputs(&self.scene.scene, scene, &self.device)
    }

    fn outputs(&self, image: &Path, aovs: &AovFiles) -> Vec<PathBuf> {
        let mut v = if aovs.takes_output {
            Vec::new()
        } else {
            vec![image.to_owned()]
        };
        v.extend(aovs.files.iter().map(|(_, p)| p.clone()));
        v.extend(self.stats.clone());
        if self.tiles.is_set() {
            v.push(tiles::sidecar_path(image));
        }
        v
    }
}

pub fn run(a: &RenderArgs) -> anyhow::Result<ExitCode> {
    let output = match &a.output {
        Some(o) => o.clone(),
        None => PathBuf::from(a.scene.scene.file_stem().unwrap_or_default()).with_extension("png"),
    };
    if a.backend == Backend::Cpu {
        a.device.refuse_shader_options("--backend cpu")?;
    }
    // Refuse a bad output name before spending time on the render.
    let aov_files = AovFiles::parse(&a.aovs, &output)?;
    if !aov_files.takes_output {
        io::Format::of_output(&output)?;
    }
    if a.stats.as_ref() == Some(&output) {
        anyhow::bail!("--stats names the image's own file {}", output.display());
    }
    if a.tiles.is_set() {
        anyhow::ensure!(
            matches!(
                io::Format::of_output(&output)?,
                io::Format::Exr | io::Format::Pfm
            ),
            "{}: a tile is written as .exr or .pfm (a PNG would round it)",
            output.display()
        );
        anyhow::ensure!(a.stats.is_none(), "--stats counts whole renders, not tiles");
        anyhow::ensure!(!aov_files.any(), "--aov writes whole renders, not tiles");
    }
    let loading = Instant::now();
    let scene = a.scene.load()?;
    let input_s = loading.elapsed().as_secs_f64();
    aov_files.check(&scene)?;
    if a.backend == Backend::Cpu {
        cpu::bound::check(&scene)?;
    }
    // A whole render's images fit, or it is refused before they are
    // allocated (a tile's are its own, smaller).
    if !a.tiles.is_set() {
        glint::raster::memory::check_render(scene.width, scene.height)?;
    }
    // Every output can be written, and none is an input, before the render.
    let mut outputs = Outputs::new(a.inputs(&scene), a.force);
    for out in a.outputs(&output, &aov_files) {
        outputs.check(&out)?;
    }
    if a.tiles.is_set() {
        return render_tile(a, &output, &scene, outputs);
    }
    let want = Want {
        count: a.stats.is_some(),
        aovs: aov_files.any(),
    };
    let (image, label, seconds, stats, aovs) = match (a.backend, a.precision) {
        (Backend::Gpu, p) => {
            let precision = p.unwrap_or(Precision::F32);
            let r = render_gpu::whole(&scene, &a.device, precision, want)?;
            let stats = r
                .counts
                .map(|c| Stats::new(&c, input_s, r.setup_s, r.tables_s, r.seconds));
            (r.image, r.label, r.seconds, stats, r.aovs)
        }
        (Backend::Cpu, p) => {
            let precision = p.unwrap_or(Precision::F64);
            let r = render_cpu_timed(&scene, precision, a.device.accel, want)?;
            let (setup, trace) = (r.times.setup_s, r.times.render_s);
            let tables = r.times.tables_s;
            let stats = r
                .counts
                .map(|c| Stats::new(&c, input_s, setup, tables, trace));
            (r.image, r.label, trace, stats, r.aovs)
        }
    };
    refuse_nonfinite(&image)?;
    // The outputs are committed together, the image last.
    if let (Some(path), Some(stats)) = (&a.stats, &stats) {
        stage_json(&mut outputs, path, stats).with_context(|| "cannot write the statistics")?;
    }
    if let Some(aovs) = &aovs {
        aov_files
            .stage(&mut outputs, aovs, (scene.width, scene.height))
            .with_context(|| "cannot write the AOVs")?;
    }
    if !aov_files.takes_output {
        io::stage(&mut outputs, &output, &image, scene.srgb)
            .with_context(|| "cannot write the image")?;
    }
    outputs.commit()?;
    let written: Vec<String> = (!aov_files.takes_output)
        .then(|| output.display().to_string())
        .into_iter()
        .chain(
            aov_files
                .files
                .iter()
                .map(|(t, p)| format!("{} ({})", p.display(), t.name)),
        )
        .collect();
    errln!(
        "rendered {}x{} ({}, depth {}) with {label} in {seconds:.3} s -> {}",
        scene.width,
        scene.height,
        scene.sampling_summary(),
        scene.max_depth,
        written.join(", ")
    );
    Ok(ExitCode::SUCCESS)
}

/// Stages `value` as pretty JSON, one line break at its end.
pub fn stage_json(
    outputs: &mut Outputs,
    path: &Path,
    value: &impl serde::Serialize,
) -> anyhow::Result<()> {
    let json = serde_json::to_string_pretty(value)?;
    outputs.stage(path, |out: &mut dyn Write| {
        writeln!(out, "{json}").map_err(output::io_err(path))
    })?;
    Ok(())
}

/// glint's own shading stays finite for every scene it accepts; a shader
/// of the user's may not, and such an image is not written.
fn refuse_nonfinite(image: &Image) -> anyhow::Result<()> {
    if let Some((count, x, y)) = image.nonfinite() {
        anyhow::bail!(
            "the render has {count} non-finite values, the first at pixel ({x}, {y}); the image is not written"
        );
    }
    Ok(())
}

/// `--tile` or `--region`: the region's pixels, bit for bit those of the
/// whole render, and the sidecar that says which render they belong to.
fn render_tile(
    a: &RenderArgs,
    output: &Path,
    scene: &Scene,
    mut outputs: Outputs,
) -> anyhow::Result<ExitCode> {
    let (region, tile) = a.tiles.resolve(scene.width, scene.height)?;
    let start = Instant::now();
    let (image, label, sidecar) = match a.backend {
        Backend::Gpu => {
            let precision = a.precision.unwrap_or(Precision::F32);
            render_gpu::tile(&a.scene.scene, scene, &a.device, precision, region, tile)?
        }
        Backend::Cpu => {
            let precision = a.precision.unwrap_or(Precision::F64);
            let accel = a.device.accel;
            let bar = progress::bar(u64::from(region.height), "cpu tile");
            let progress = |n| bar.inc(n);
            let image = match precision {
                Precision::F32 => cpu::render_region::<f32>(scene, accel, region, &progress),
                Precision::F64 => cpu::render_region::<f64>(scene, accel, region, &progress),
            };
            bar.finish_and_clear();
            let name = precision.name();
            scene.within(&image, name)?;
            let sidecar = tile::sidecar(&a.scene.scene, scene, name, None, region, tile, &image);
            (image, format!("CPU {name}"), sidecar)
        }
    };
    let seconds = start.elapsed().as_secs_f64();
    refuse_nonfinite(&image)?;
    // The sidecar is committed after the tile: a tile without its sidecar
    // is never taken for a whole one (assemble asks for both).
    io::stage(&mut outputs, output, &image, scene.srgb).with_context(|| "cannot write the tile")?;
    stage_json(&mut outputs, &tiles::sidecar_path(output), &sidecar)
        .with_context(|| "cannot write the tile's sidecar")?;
    outputs.commit()?;
    errln!(
        "rendered region {},{},{},{} of {}x{} with {label} in {seconds:.3} s -> {}",
        region.x,
        region.y,
        region.width,
        region.height,
        scene.width,
        scene.height,
        output.display()
    );
    Ok(ExitCode::SUCCESS)
}

/// The CPU's setup (the scene in its precision, the BVH) and render times.
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct CpuTimes {
    pub setup_s: f64,
    /// Of the setup, building the tables (`--accel tables`).
    pub tables_s: f64,
    pub render_s: f64,
}

/// A CPU render and what it cost.
pub struct CpuRender {
    pub image: Image,
    pub label: String,
    pub times: CpuTimes,
    pub counts: Option<Counts>,
    /// The pixels' AOVs, where asked for.
    pub aovs: Option<Vec<Aov>>,
    /// What adaptive or contrast sampling decided: `compare` replays the
    /// reference's, and the CPU-only build has no `compare`.
    #[cfg_attr(not(feature = "gpu"), allow(dead_code))]
    pub sampled: Option<Sampled>,
}

pub fn render_cpu_timed(
    scene: &Scene,
    precision: Precision,
    accel: Accel,
    want: Want,
) -> anyhow::Result<CpuRender> {
    let bar = progress::bar(
        u64::from(scene.height),
        &format!("cpu {precision:?}").to_lowercase(),
    );
    let start = Instant::now();
    /// What one precision's render gave.
    struct Gave {
        image: Image,
        counts: Option<Counts>,
        aovs: Option<Vec<Aov>>,
        sampled: Option<Sampled>,
        setup_s: f64,
        tables_s: f64,
    }
    fn go<R: cpu::Real>(
        scene: &Scene,
        accel: Accel,
        want: Want,
        start: Instant,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Gave {
        let prepared = progress::waiting("preparing the scene (BVH)", || {
            cpu::Prepared::<R>::new(scene, accel)
        });
        let setup_s = start.elapsed().as_secs_f64();
        let tables_s = prepared.tables_s();
        let gave = |image, counts, aovs, sampled| Gave {
            image,
            counts,
            aovs,
            sampled,
            setup_s,
            tables_s,
        };
        match (want.count, want.aovs) {
            (true, true) => {
                let (image, aovs, counts) = prepared.render_aovs_counted(None, progress);
                gave(image, Some(counts), Some(aovs), None)
            }
            (false, true) => {
                let (image, aovs) = prepared.render_aovs(None, progress);
                gave(image, None, Some(aovs), None)
            }
            (true, false) => {
                let (image, counts) = prepared.render_counted(progress);
                gave(image, Some(counts), None, None)
            }
            (false, false) => {
                let (image, sampled) = prepared.render_sampled(progress);
                gave(image, None, None, sampled)
            }
        }
    }
    let progress = |n| bar.inc(n);
    let g = match precision {
        Precision::F32 => go::<f32>(scene, accel, want, start, &progress),
        Precision::F64 => go::<f64>(scene, accel, want, start, &progress),
    };
    let render_s = start.elapsed().as_secs_f64() - g.setup_s;
    bar.finish_and_clear();
    let threads = rayon::current_num_threads();
    scene.within(&g.image, precision.name())?;
    Ok(CpuRender {
        image: g.image,
        label: format!("CPU {precision:?} on {threads} threads").replace("F", "f"),
        times: CpuTimes {
            setup_s: g.setup_s,
            tables_s: g.tables_s,
            render_s,
        },
        counts: g.counts,
        aovs: g.aovs,
        sampled: g.sampled,
    })
}
