use crate::cli::console::outln;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::Args;
use serde_json::json;

use glint::bench::{self, Ceiling};
use glint::cpu;
use glint::gpu::RenderSettings;
use glint::report::median;
use glint::scene::{Overrides, Scene};
use glint::stats::Counts;

use super::{progress, DeviceArgs};

#[derive(Args)]
pub struct BenchArgs {
    /// Scene files [default: scenes/*.toml and scenes/spd/*.nff]
    scenes: Vec<PathBuf>,
    /// Timed renders of each scene on each renderer (after a warm-up on the GPU); medians (1..=1000).
    #[arg(long, default_value_t = 3)]
    runs: usize,
    /// Print one JSON object on stdout.
    #[arg(long)]
    json: bool,
    /// Time the GPU renders alone (no ceiling, no CPU reference): for
    /// comparing builds and choices of the GPU path (benches/choices.py).
    #[arg(long)]
    gpu_only: bool,
    #[command(flatten)]
    device: DeviceArgs,
}

struct Row {
    scene: PathBuf,
    gpu_s: f64,
    /// The process's CPU seconds during a GPU render (`bench::process_cpu_s`).
    gpu_cpu_s: Option<f64>,
    cpu_s: f64,
    counts: Counts,
}

fn default_scenes() -> anyhow::Result<Vec<PathBuf>> {
    let mut v = super::scene_files("scenes")?;
    v.extend(super::scene_files("scenes/spd")?);
    Ok(v)
}

pub fn run(a: &BenchArgs) -> anyhow::Result<ExitCode> {
    anyhow::ensure!(
        (1..=super::MAX_RUNS).contains(&a.runs),
        "--runs {}: must be in 1..={}",
        a.runs,
        super::MAX_RUNS
    );
    let scenes = if a.scenes.is_empty() {
        default_scenes()?
    } else {
        a.scenes.clone()
    };
    let options = a.device.options()?;
    let ceiling = if a.gpu_only {
        None
    } else {
        Some(progress::waiting(
            "measuring the device's ceiling (ray-sphere tests a second)",
            || bench::ceiling(&options, 512, a.runs),
        )?)
    };
    let mut renderer = super::render_gpu::open(&options)?;
    let accel = a.device.accel;
    let bar = progress::bar(scenes.len() as u64, "scenes");
    let mut rows = Vec::new();
    for path in &scenes {
        let scene = Scene::load(path, &Overrides::default())?;
        cpu::bound::check(&scene)?;
        bar.set_message(path.display().to_string());
        let settings = renderer.settings();
        let mut prepared = renderer.prepare(&scene, &settings)?;
        prepared.render(None, &|_| {})?;
        let mut gpu = Vec::new();
        let mut gpu_cpu = Vec::new();
        for _ in 0..a.runs {
            let before = bench::process_cpu_s();
            gpu.push(prepared.render(None, &|_| {})?.times.total_s());
            if let (Some(b), Some(a)) = (before, bench::process_cpu_s()) {
                gpu_cpu.push(a - b);
            }
        }
        let mut cpu = Vec::new();
        for _ in 0..if a.gpu_only { 0 } else { a.runs } {
            let t = Instant::now();
            cpu::render_rows::<f32>(&scene, accel, &|_| {});
            cpu.push(t.elapsed().as_secs_f64());
        }
        let counting = RenderSettings {
            count: true,
            ..settings
        };
        let counts = renderer
            .prepare(&scene, &counting)?
            .render(None, &|_| {})?
            .counts
            .expect("a counting render counts");
        rows.push(Row {
            scene: path.clone(),
            gpu_s: median(&mut gpu),
            gpu_cpu_s: (!gpu_cpu.is_empty()).then(|| median(&mut gpu_cpu)),
            cpu_s: if cpu.is_empty() {
                f64::NAN
            } else {
                median(&mut cpu)
            },
            counts,
        });
        bar.inc(1);
    }
    bar.finish_and_clear();
    let info = renderer.device_info();
    if a.json {
        let scenes: Vec<_> = rows
            .iter()
            .map(|r| {
                json!({
                    "scene": r.scene,
                    "gpu_f32_s": r.gpu_s,
                    "gpu_f32_cpu_s": r.gpu_cpu_s,
                    "cpu_f32_s": r.cpu_s,
                    "rays": r.counts.rays(),
                    "tests": r.counts.tests(),
                    "by_ray": r.counts.by_ray(),
                })
            })
            .collect();
        outln!(
            "{}",
            json!({
                "device": info,
                "cpu_threads": rayon::current_num_threads(),
                "runs": a.runs,
                "intersect": format!("{:?}", options.settings.intersect).to_lowercase(),
                "ceiling": ceiling.map(|c| json!({ "tests": c.tests, "seconds": c.seconds, "tests_per_s": c.tests_per_s() })),
                "scenes": scenes,
            })
        );
        return Ok(ExitCode::SUCCESS);
    }
    let forms = format!("{:?}", options.settings.intersect).to_lowercase();
    print_table(&rows, ceiling.as_ref(), &info.name, &forms, a.runs);
    Ok(ExitCode::SUCCESS)
}

fn print_table(rows: &[Row], ceiling: Option<&Ceiling>, device: &str, forms: &str, runs: usize) {
    outln!(
        "device {device}, CPU {} threads; medians of {runs}; GPU f32 with its warm-up apart",
        rayon::current_num_threads()
    );
    if let Some(ceiling) = ceiling {
        outln!(
            "ceiling: {:.2} G {forms} ray-sphere tests/s with no memory traffic ({:.2e} tests in {:.3} s)",
            ceiling.tests_per_s() / 1e9,
            ceiling.tests as f64,
            ceiling.seconds
        );
    }
    outln!(
        "{:<22} {:>9} {:>9} {:>8} {:>10} {:>9} {:>9} {:>8}  per ray type: rays, tests/ray, nodes/ray",
        "scene", "GPU f32", "CPU f32", "GPU/CPU", "rays", "Mrays/s", "Mtests/s", "ceiling"
    );
    for r in rows {
        let work = r.counts.by_ray();
        let rays: u64 = work.values().map(|w| w.rays).sum();
        let tests: u64 = work.values().map(|w| w.tests_total()).sum();
        let tests_per_s = tests as f64 / r.gpu_s;
        let per_type: Vec<String> = work
            .iter()
            .filter(|(_, w)| w.rays > 0)
            .map(|(t, w)| {
                format!(
                    "{t} {} {:.1} {:.1}",
                    w.rays,
                    w.tests_total() as f64 / w.rays as f64,
                    w.nodes() as f64 / w.rays as f64
                )
            })
            .collect();
        // --gpu-only measures neither the CPU nor the ceiling.
        let (cpu, ratio) = if r.cpu_s.is_nan() {
            ("-".to_owned(), "-".to_owned())
        } else {
            (
                format!("{:.3}s", r.cpu_s),
                format!("{:.2}", r.gpu_s / r.cpu_s),
            )
        };
        let share = ceiling.map_or("-".to_owned(), |c| {
            format!("{:.1}%", 100.0 * tests_per_s / c.tests_per_s())
        });
        outln!(
            "{:<22} {:>8.3}s {:>9} {:>8} {:>10} {:>9.2} {:>9.1} {:>8}  {}",
            r.scene.file_name().unwrap_or_default().to_string_lossy(),
            r.gpu_s,
            cpu,
            ratio,
            rays,
            rays as f64 / r.gpu_s / 1e6,
            tests_per_s / 1e6,
            share,
            per_type.join("; ")
        );
    }
}
