use crate::cli::console::outln;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use serde_json::json;

use glint::condition;
use glint::output::Outputs;
use glint::raster::diff::{self, Tolerance};
use glint::raster::io;

use super::render::render_cpu_timed;
use super::render_gpu;
use super::whole::Want;
use super::{DeviceArgs, Precision, SceneArgs};

#[derive(Args)]
pub struct CompareArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Print one JSON object on stdout.
    #[arg(long)]
    json: bool,
    /// Write a heat-map of the GPU's per-pixel error against the reference.
    #[arg(long, value_name = "FILE")]
    diff_out: Option<PathBuf>,
    /// Where the check fails, explain its N worst pixels as `glint explain` does (1..=100).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=100))]
    explain: Option<u32>,
    #[command(flatten)]
    device: DeviceArgs,
}

pub fn run(a: &CompareArgs) -> anyhow::Result<ExitCode> {
    if let Some(path) = &a.diff_out {
        io::Format::of_output(path)?;
    }
    let t_load = std::time::Instant::now();
    let scene = a.scene.load()?;
    glint::cpu::bound::check(&scene)?;
    glint::raster::memory::check_render(scene.width, scene.height)?;
    let load_s = t_load.elapsed().as_secs_f64();
    let mut outputs = Outputs::new(super::inputs(&a.scene.scene, &scene, &a.device), false);
    if let Some(path) = &a.diff_out {
        outputs.check(path)?;
    }
    // The first render pays for the driver's own compile of the shader (on
    // lavapipe, LLVM at the first dispatch); the timed one is the second.
    let first = render_gpu::timed(&scene, &a.device, Precision::F32, false)?;
    let setup = first.times.setup;
    let (gpu_image, mut renderer, mut prepared) = (first.image, first.renderer, first.prepared);
    let first = first.times;
    let warm = prepared.render(None, &|_| {})?;
    let (warm_image, gpu_times, gpu_sampled) = (warm.image, warm.times, warm.sampled);
    anyhow::ensure!(
        warm_image == gpu_image,
        "two GPU renders of the same scene differ"
    );
    let accel = a.device.accel;
    let cpu64 = render_cpu_timed(&scene, Precision::F64, accel, Want::default())?;
    let cpu32 = render_cpu_timed(&scene, Precision::F32, accel, Want::default())?;
    let reference_sampled = cpu64.sampled;
    let (reference, cpu32_image, cpu64, cpu32) =
        (cpu64.image, cpu32.image, cpu64.times, cpu32.times);
    let (cpu64_s, cpu32_s) = (cpu64.render_s, cpu32.render_s);
    let unit = condition::unit(&reference);
    let cpu32_err = diff::figures(&cpu32_image.scaled(unit), &reference.scaled(unit))?;
    let tolerance = Tolerance::default();
    let bar = super::progress::bar(
        u64::from(scene.height) * u64::from(condition::MOVED_TRIALS + 1),
        "conditioning",
    );
    let settings = renderer.settings();
    let replay = |replaying: &glint::scene::Scene| {
        let r = renderer
            .prepare(replaying, &settings)?
            .render(None, &|_| {})?;
        Ok::<_, glint::gpu::GpuError>((r.image, r.sampled))
    };
    let judgement = condition::judge_rendered(
        &scene,
        (&gpu_image, gpu_sampled.as_ref()),
        (&reference, reference_sampled.as_ref()),
        replay,
        &tolerance,
        accel,
        &|n| bar.inc(n),
    )?;
    bar.finish_and_clear();
    let (gpu_err, conditioned, decisions, violations) = (
        judgement.error,
        judgement.conditioned,
        judgement.decisions,
        judgement.violations,
    );
    super::diff::write_heat_map(outputs, a.diff_out.as_deref(), &gpu_image, &reference)?;
    let explanations = match a.explain {
        Some(n) if !violations.is_empty() => {
            explain_worst(&mut renderer, &scene, &a.device, &gpu_image, &reference, n)?
        }
        _ => Vec::new(),
    };
    let threads = rayon::current_num_threads();
    let info = renderer.device_info();
    let variant = prepared.variant().name();
    if a.json {
        let out = json!({
            "scene": a.scene.scene,
            "width": scene.width,
            "height": scene.height,
            "samples": scene.samples,
            "max_depth": scene.max_depth,
            "device": info,
            "shader_variant": variant,
            "load_s": load_s,
            "cpu_threads": threads,
            "setup": setup,
            "gpu_f32": {
                "seconds": gpu_times.total_s(),
                "times": gpu_times,
                "first_render_s": first.total_s(),
                "error": gpu_err
            },
            "cpu_f32": { "seconds": cpu32_s, "setup_s": cpu32.setup_s, "error": cpu32_err },
            "cpu_f64": { "seconds": cpu64_s, "setup_s": cpu64.setup_s },
            "unit": unit,
            "spec_worst": renderer.spec_worst(),
            "tolerance": tolerance,
            "conditioned": conditioned,
            "decisions": decisions,
            "pass": violations.is_empty(),
            "violations": violations,
            "explanations": explanations,
        });
        outln!("{out}");
    } else {
        outln!("{}", super::scene_line(&a.scene.scene, &scene));
        outln!("device     {} ({}, {})", info.name, info.kind, info.driver);
        outln!(
            "shader     {variant}{}{}",
            if setup.spirv_cached {
                " (SPIR-V from the cache)"
            } else {
                ""
            },
            if renderer.spec_worst() {
                ", run as the least precise conformant driver (--spec-worst)"
            } else {
                ""
            }
        );
        outln!(
            "setup      load {load_s:.3} s, device {:.3} s, shader compile {:.3} s, pipeline {:.3} s, BVH {:.3} s, tables {:.3} s (not in the times below)",
            setup.device_s, setup.compile_s, setup.pipeline_s, gpu_times.bvh_s, gpu_times.tables_s
        );
        outln!(
            "gpu f32    {:.3} s  (upload {:.3}, dispatch {:.3}{}, readback {:.3}; the first render took {:.3} s)",
            gpu_times.total_s(),
            gpu_times.upload_s,
            gpu_times.dispatch_s,
            gpu_times
                .device_dispatch_s
                .map_or(String::new(), |s| format!(" of which {s:.3} on the device")),
            gpu_times.readback_s,
            first.total_s()
        );
        outln!(
            "cpu f32    {cpu32_s:.3} s  ({threads} threads)  {:.2}x the GPU's time",
            cpu32_s / gpu_times.total_s()
        );
        outln!("cpu f64    {cpu64_s:.3} s  ({threads} threads)  reference");
        if unit > 1.0 {
            outln!("unit       {unit:.3e}: the reference's peak, which the errors are relative to");
        }
        outln!("gpu error  {}", super::diff::format_figures(&gpu_err));
        outln!("cpu32 err  {}", super::diff::format_figures(&cpu32_err));
        if let Some(d) = &decisions {
            outln!("{}", super::diff::format_decisions(d));
            if let Some(plain) = &d.plain {
                outln!("plain err  {}", super::diff::format_figures(plain));
            }
        }
        if let Some(c) = &conditioned {
            for line in super::diff::condition_lines(c) {
                outln!("{line}");
            }
        }
        outln!(
            "{}",
            super::diff::tolerance_line(&tolerance, conditioned.is_some(), violations.is_empty())
        );
        for v in &violations {
            outln!("           {v}");
        }
        match a.explain {
            Some(_) if violations.is_empty() => {
                outln!("explain    the check passed: nothing to explain")
            }
            Some(n) => {
                outln!(
                    "\nexplain    the {} worst pixel(s) of {n} asked for, as `glint explain` gives them\n{}",
                    explanations.iter().map(|e| e.sample.pixel).collect::<std::collections::BTreeSet<_>>().len(),
                    super::explain::header()
                );
                for e in &explanations {
                    outln!("\n{}", super::explain::text(e, &scene));
                }
            }
            None => {}
        }
    }
    Ok(if violations.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

/// The explanations of the `n` worst pixels of `image` against `reference`,
/// every sample of each.
fn explain_worst(
    renderer: &mut glint::gpu::Renderer,
    scene: &glint::scene::Scene,
    device: &DeviceArgs,
    image: &glint::raster::Image,
    reference: &glint::raster::Image,
    n: u32,
) -> anyhow::Result<Vec<glint::explain::Explanation>> {
    let options = device.options()?;
    let mut chosen = Vec::new();
    for pixel in glint::explain::worst_pixels(image, reference, n as usize) {
        chosen.extend(glint::explain::samples(scene, pixel, None)?);
    }
    let others = super::explain::Others {
        icds: Vec::new(),
        forward: Vec::new(),
    };
    super::explain::explain(renderer, scene, &options.settings, &chosen, &others)
}
