use crate::cli::console::errln;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

use glint::report::{self, Report, Settings};
use glint::scene::{Overrides, Scene};

use glint::output::Outputs;

use super::{progress, DeviceArgs};

#[derive(Args)]
pub struct ReportArgs {
    /// Scene files [default: every scene in scenes/]
    scenes: Vec<PathBuf>,
    /// The directory to write report.md, report.csv, report.json, error_vs_time.svg, sampling_vs_time.svg (where the sampling axis is measured) and index.html into.
    #[arg(short, long, value_name = "DIR")]
    output: PathBuf,
    /// Warm runs per variant (the median is reported; 1..=1000).
    #[arg(long, default_value_t = 5)]
    runs: usize,
    /// Small images (160x120), 2 runs, no depth or sample sweeps and no sampling axis: for tests and CI.
    #[arg(long)]
    quick: bool,
    /// Measure the sampling axis (uniform 1x1 to 8x8 and adaptive sampling, against a converged render) also with --quick.
    #[arg(long)]
    sampling: bool,
    #[command(flatten)]
    device: DeviceArgs,
}

pub fn run(a: &ReportArgs) -> anyhow::Result<ExitCode> {
    anyhow::ensure!(
        (1..=super::MAX_RUNS).contains(&a.runs),
        "--runs {}: must be in 1..={}",
        a.runs,
        super::MAX_RUNS
    );
    glint::output::check_folder(&a.output)?;
    let paths = if a.scenes.is_empty() {
        super::scene_files("scenes")?
    } else {
        a.scenes.clone()
    };
    let overrides = if a.quick {
        Overrides {
            width: Some(160),
            height: Some(120),
            ..Overrides::default()
        }
    } else {
        Overrides::default()
    };
    // Load every scene first: a bad one fails before minutes of measuring.
    let scenes = paths
        .iter()
        .map(|p| Scene::load(p, &overrides))
        .collect::<Result<Vec<_>, _>>()?;
    for scene in &scenes {
        glint::cpu::bound::check(scene)?;
    }
    let settings = Settings {
        runs: if a.quick { 2 } else { a.runs },
        sweeps: !a.quick,
        sampling: !a.quick || a.sampling,
    };
    let names: Vec<String> = paths.iter().map(|p| super::scene_name(p)).collect();
    let mut inputs = a.device.inputs();
    for (path, scene) in paths.iter().zip(&scenes) {
        inputs.push(path.clone());
        inputs.extend(scene.input_files.iter().cloned());
    }
    // Every output can be written, and none is an input, before minutes of measuring.
    let mut outputs = Outputs::new(inputs, false);
    for file in report::html::files(&names, &a.output, settings.sampling) {
        // The folder may not exist yet: it is made before the writes.
        if file.parent().is_some_and(|d| d.is_dir()) {
            outputs.check(&file)?;
        }
    }
    let options = a.device.options()?;
    let mut renderer = super::render_gpu::open(&options)?;
    let device_s = renderer.device_s();
    let total: u64 = scenes
        .iter()
        .map(|s| {
            5 + if settings.sweeps {
                u64::from(s.max_depth - 1 + s.samples - 1)
            } else {
                0
            } + if settings.sampling {
                (1 + report::SAMPLING_UNIFORM.len()
                    + report::SAMPLING_ADAPTIVE.len()
                    + report::SAMPLING_CONTRAST.len()) as u64
            } else {
                0
            }
        })
        .sum();
    let bar = progress::bar(total, "report");
    let mut reports = Vec::new();
    for (name, scene) in names.iter().zip(&scenes) {
        bar.set_message(format!("{name}: the CPU f64 reference"));
        let r = report::measure(&mut renderer, scene, name, settings, &|variant| {
            bar.set_message(format!("{name}: {variant}"));
            bar.inc(1);
        })?;
        reports.push(r);
    }
    bar.finish_and_clear();
    let report = Report {
        machine: report::machine(),
        device: renderer.device_info().clone(),
        device_s,
        runs: settings.runs,
        scenes: reports,
    };
    report::html::write_all(&report, &a.output, outputs)?;
    let written = report::html::texts(report::html::measured_sampling(&report));
    errln!(
        "wrote {}/index.html, {}",
        a.output.display(),
        written.join(", ")
    );
    Ok(ExitCode::SUCCESS)
}
