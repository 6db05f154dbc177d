use crate::cli::console::outln;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use serde_json::json;

use glint::gpu::Renderer;
use glint::scene::{Overrides, Scene};
use glint::stability;

use super::{progress, DeviceArgs};

#[derive(Args)]
pub struct StabilityArgs {
    /// Scene files [default: every scene in scenes/extreme/]
    scenes: Vec<PathBuf>,
    /// Print one JSON object on stdout.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    device: DeviceArgs,
}

pub fn run(a: &StabilityArgs) -> anyhow::Result<ExitCode> {
    let scenes = if a.scenes.is_empty() {
        super::scene_files("scenes/extreme")?
    } else {
        a.scenes.clone()
    };
    let mut renderer = Renderer::new(&a.device.options()?)?;
    let bar = progress::bar(scenes.len() as u64, "scenes");
    let mut results = Vec::new();
    for path in &scenes {
        let scene = Scene::load(path, &Overrides::default())?;
        glint::cpu::bound::check(&scene)?;
        bar.set_message(
            path.file_stem()
                .unwrap_or_default()
                .to_string_lossy()
                .into_owned(),
        );
        results.push((path.clone(), stability::evaluate(&mut renderer, &scene)?));
        bar.inc(1);
    }
    bar.finish_and_clear();
    if a.json {
        let rows: Vec<_> = results
            .iter()
            .map(|(p, r)| json!({ "scene": p, "peak": r.peak, "variants": r.rows }))
            .collect();
        outln!(
            "{}",
            json!({ "device": renderer.device_info(), "scenes": rows })
        );
        return Ok(ExitCode::SUCCESS);
    }
    outln!(
        "errors against CPU f64, relative to the reference's peak value; device {}",
        renderer.device_info().name
    );
    outln!(
        "{:<24} {:<15} {:>10} {:>10} {:>11} {:>9}  tolerance",
        "scene",
        "variant",
        "max_abs",
        "rmse",
        "over 1/255",
        "nonfinite"
    );
    for (path, r) in &results {
        let name = path.file_stem().unwrap_or_default().to_string_lossy();
        for (i, row) in r.rows.iter().enumerate() {
            let e = &row.error;
            outln!(
                "{:<24} {:<15} {:>10.2e} {:>10.2e} {:>10.4}% {:>9}  {}",
                if i == 0 { name.as_ref() } else { "" },
                row.variant,
                e.max_abs,
                e.rmse,
                100.0 * e.frac_over_1_255,
                e.nonfinite,
                if row.pass { "pass" } else { "FAIL" }
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}
