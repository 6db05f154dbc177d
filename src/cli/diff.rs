use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

use glint::raster::{diff, io};

#[derive(Args)]
pub struct DiffArgs {
    /// The image to measure (.png, .pfm or .exr).
    a: PathBuf,
    /// The reference it is measured against.
    b: PathBuf,
    /// Print one JSON object on stdout.
    #[arg(long)]
    json: bool,
    /// Write a heat-map of the per-pixel error (a PNG, PFM or EXR).
    #[arg(long, value_name = "FILE")]
    diff_out: Option<PathBuf>,
}

pub fn run(a: &DiffArgs) -> anyhow::Result<ExitCode> {
    if let Some(path) = &a.diff_out {
        io::Format::of(path)?;
        io::refuse_input(path, &[&a.a, &a.b])?;
    }
    let img = io::read(&a.a)?;
    let reference = io::read(&a.b)?;
    let figures = diff::figures(&img, &reference)?;
    if let Some(path) = &a.diff_out {
        io::write(path, &diff::heat_map(&img, &reference)?, false)?;
    }
    if a.json {
        println!("{}", serde_json::to_string(&figures)?);
    } else {
        println!("{}", super::compare::format_figures(&figures));
    }
    Ok(ExitCode::SUCCESS)
}
