use crate::cli::console::outln;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Args;

use glint::output::Outputs;
use glint::raster::diff::ErrorFigures;
use glint::raster::{diff, io, Image};

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
    let mut outputs = Outputs::new([&a.a, &a.b], false);
    if let Some(path) = &a.diff_out {
        io::Format::of_output(path)?;
        outputs.check(path)?;
    }
    // Sizes from the headers first: two images that cannot be compared
    // are never decoded.
    let (wa, ha) = io::dimensions(&a.a)?;
    let (wb, hb) = io::dimensions(&a.b)?;
    if (wa, ha) != (wb, hb) {
        anyhow::bail!(
            "{} is {wa}x{ha} and {} is {wb}x{hb}: the images differ in size",
            glint::printable::path(&a.a),
            glint::printable::path(&a.b)
        );
    }
    let img = super::progress::waiting("reading the first image", || io::read(&a.a))?;
    let reference = super::progress::waiting("reading the reference", || io::read(&a.b))?;
    let figures = diff::figures(&img, &reference)?;
    write_heat_map(outputs, a.diff_out.as_deref(), &img, &reference)?;
    if a.json {
        outln!("{}", serde_json::to_string(&figures)?);
    } else {
        outln!("{}", format_figures(&figures));
    }
    Ok(ExitCode::SUCCESS)
}

/// `compare`'s conditioning lines: the share of ill-conditioned pixels
/// and the error over the well-conditioned ones (`compare` and `serve`).
#[cfg(feature = "gpu")]
pub fn condition_lines(c: &glint::condition::Conditioned) -> [String; 2] {
    [
        format!(
            "condition  {:.4}% of pixels ill-conditioned at f32 ({} perturbed f64 renders{} and the f32 one), {:.4}% over 1/255 among them",
            100.0 * c.ill,
            glint::condition::TRIALS,
            if c.driver_trials {
                format!(", {} more at a conformant driver's error,", glint::condition::DRIVER_TRIALS)
            } else {
                String::new()
            },
            100.0 * c.over_and_ill
        ),
        format!("well-cond  {}", format_figures(&c.error)),
    ]
}

/// `compare`'s verdict line: the tolerance and pass or FAIL.
#[cfg(feature = "gpu")]
pub fn tolerance_line(
    tolerance: &glint::raster::diff::Tolerance,
    conditioned: bool,
    pass: bool,
) -> String {
    format!(
        "tolerance  over 1/255 <= {:.2}%, rmse <= {:.1e}, no non-finite value{}: {}",
        100.0 * tolerance.frac_over_1_255,
        tolerance.rmse,
        if conditioned {
            ", over the well-conditioned pixels"
        } else {
            ""
        },
        if pass { "pass" } else { "FAIL" }
    )
}

/// The error figures in one line, as `diff` and `compare` print them.
pub fn format_figures(f: &ErrorFigures) -> String {
    format!(
        "max_abs {:.3e}  rmse {:.3e}  psnr {}  over 1/255 {:.4}%  nonfinite {}",
        f.max_abs,
        f.rmse,
        if f.psnr_db.is_finite() {
            format!("{:.1} dB", f.psnr_db)
        } else if f.psnr_db > 0.0 {
            "inf (identical)".to_owned()
        } else {
            "none (non-finite values)".to_owned()
        },
        100.0 * f.frac_over_1_255,
        f.nonfinite
    )
}

/// The sampling line of `compare`: how many decisions the renderer took
/// otherwise than the reference on its samples, how many of those the
/// trials explain, and how much of its own image it sampled otherwise.
#[cfg(feature = "gpu")]
pub fn format_decisions(d: &glint::condition::DecisionCheck) -> String {
    let mut line = format!(
        "sampling   {} decisions on the reference's samples, {} taken otherwise",
        d.decisions, d.otherwise
    );
    if d.otherwise > 0 {
        line.push_str(&format!(" ({} not by any trial)", d.unexplained));
    }
    if d.sampled_otherwise > 0.0 {
        line.push_str(&format!(
            "; its own decisions sampled {:.4}% of pixels otherwise, so the error below is of its replay of the reference's",
            100.0 * d.sampled_otherwise
        ));
    }
    line
}

/// Writes the heat map of `img` against `reference` to `path` where one
/// was asked for (`--diff-out`), through `outputs`, which holds it alone.
pub(super) fn write_heat_map(
    mut outputs: Outputs,
    path: Option<&Path>,
    img: &Image,
    reference: &Image,
) -> anyhow::Result<()> {
    if let Some(path) = path {
        io::stage(&mut outputs, path, &diff::heat_map(img, reference)?, false)?;
        outputs.commit()?;
    }
    Ok(())
}
