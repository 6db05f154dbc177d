//! index.html: the plot, then per scene the GPU image, the reference and the
//! heat-map of their difference side by side, with the figures. The images
//! are PNG files beside the page, so it opens without a server.

use std::fmt::Write;
use std::path::{Path, PathBuf};

use super::{escape, tables, Report, ROW_HEADERS};
use crate::output::{self, Outputs};
use crate::raster::{diff, io};

/// A file-name-safe form of a scene's name.
fn slug(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// The files `write_all` writes into `dir` for the scenes `names`, the
/// page last, so that a command can check them before it measures. The
/// sampling axis's plot is among them only where `sampling` is measured.
pub fn files(names: &[String], dir: &Path, sampling: bool) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = texts(sampling).iter().map(|n| dir.join(n)).collect();
    v.extend(names.iter().flat_map(|n| image_paths(dir, n)));
    v.push(dir.join(PAGE));
    v
}

/// The text files of a report, by name; the sampling axis's plot only
/// where the sampling axis was measured, since without its points the plot
/// would draw an empty front under a label that claims a measurement.
pub fn texts(sampling: bool) -> Vec<&'static str> {
    let mut v = vec![
        "report.md",
        "report.csv",
        "report.json",
        "error_vs_time.svg",
    ];
    if sampling {
        v.push(SAMPLING_PLOT);
    }
    v
}

const SAMPLING_PLOT: &str = "sampling_vs_time.svg";
const PAGE: &str = "index.html";

/// A scene's images under img/: the GPU's, the reference and their heat-map.
fn image_paths(dir: &Path, name: &str) -> [PathBuf; 3] {
    let slug = slug(name);
    ["gpu", "reference", "diff"].map(|which| dir.join("img").join(format!("{slug}-{which}.png")))
}

/// Writes report.md, report.csv, report.json, error_vs_time.svg, index.html
/// and the images under img/ into `dir`, all through `outputs` (which
/// knows the run's inputs): staged, then committed together, the page last.
pub fn write_all(r: &Report, dir: &Path, mut outputs: Outputs) -> anyhow::Result<()> {
    use anyhow::Context;
    let img_dir = dir.join("img");
    std::fs::create_dir_all(&img_dir)
        .with_context(|| format!("cannot create {}", img_dir.display()))?;
    let sampling = measured_sampling(r);
    let mut texts = vec![
        tables::markdown(r),
        tables::csv(r),
        tables::json(r),
        super::svg::plot(r),
    ];
    if sampling {
        texts.push(super::svg::plot_sampling(r));
    }
    for (name, text) in self::texts(sampling).iter().zip(&texts) {
        stage_text(&mut outputs, &dir.join(name), text)?;
    }
    for s in &r.scenes {
        if let (Some(gpu), Some(reference)) = (&s.images.gpu, &s.images.reference) {
            let [g, rf, d] = image_paths(dir, &s.name);
            io::stage(&mut outputs, &g, gpu, s.images.srgb)?;
            io::stage(&mut outputs, &rf, reference, s.images.srgb)?;
            io::stage(&mut outputs, &d, &diff::heat_map(gpu, reference)?, false)?;
        }
    }
    stage_text(&mut outputs, &dir.join(PAGE), &page(r))?;
    Ok(outputs.commit()?)
}

/// Whether any scene of `r` has the sampling axis measured.
pub fn measured_sampling(r: &Report) -> bool {
    r.scenes.iter().any(|s| !s.sampling.is_empty())
}

fn stage_text(outputs: &mut Outputs, path: &Path, text: &str) -> Result<(), output::OutputError> {
    outputs.stage(path, |out: &mut dyn std::io::Write| {
        out.write_all(text.as_bytes()).map_err(output::io_err(path))
    })
}

fn page(r: &Report) -> String {
    let mut h = String::from(
        "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>glint report</title>\n<style>\
body{font-family:sans-serif;margin:2em;max-width:1400px}table{border-collapse:collapse;font-size:13px}\
td,th{border:1px solid #ccc;padding:3px 6px;text-align:right}th{background:#f3f3f3}td:first-child{text-align:left}\
.images{display:flex;gap:12px;flex-wrap:wrap}.images figure{margin:0}.images img{max-width:440px;border:1px solid #ccc}\
figcaption{font-size:13px;color:#444}.pareto{font-weight:bold}</style></head><body>\n<h1>glint: error against run time</h1>\n",
    );
    let _ = writeln!(
        h,
        "<p>Machine: {} ({} threads), {}. Vulkan device: {} ({}), driver {}. Times are medians of {} warm runs; GPU times are upload + dispatch + readback, apart from opening the device ({:.3} s) and compiling each shader variant.</p>",
        escape(&r.machine.cpu),
        r.machine.threads,
        escape(&r.machine.os),
        escape(&r.device.name),
        escape(&r.device.kind),
        escape(&r.device.driver),
        r.runs,
        r.device_s
    );
    h.push_str("<p><img src=\"error_vs_time.svg\" alt=\"error against run time, log-log\"></p>\n");
    if measured_sampling(r) {
        h.push_str("<p><img src=\"sampling_vs_time.svg\" alt=\"the sampling axis: error against run time, log-log\"></p>\n");
    }
    h.push_str("<p>Errors are against the CPU f64 reference at the scene's own settings. Bold rows are on the scene's Pareto front: no other variant is both faster and more accurate. The heat-map is black where the images agree, blue to red to white from 1e-7 through 1/255 to 1, magenta where a value is not finite.</p>\n");
    for s in &r.scenes {
        let slug = slug(&s.name);
        let _ = writeln!(
            h,
            "<h2>{} <small>({}x{}, {}, depth {})</small></h2>",
            escape(&s.name),
            s.width,
            s.height,
            escape(&s.sampling_summary),
            s.max_depth
        );
        if s.images.gpu.is_some() {
            let _ = writeln!(
                h,
                "<div class=\"images\"><figure><img src=\"img/{slug}-gpu.png\" alt=\"GPU\"><figcaption>GPU f32 (robust)</figcaption></figure>\
<figure><img src=\"img/{slug}-reference.png\" alt=\"reference\"><figcaption>CPU f64 reference</figcaption></figure>\
<figure><img src=\"img/{slug}-diff.png\" alt=\"difference\"><figcaption>|GPU - reference|, per pixel</figcaption></figure></div>"
            );
        }
        let headers: String = ROW_HEADERS
            .iter()
            .map(|c| format!("<th>{}</th>", escape(c)))
            .collect();
        let _ = writeln!(h, "<table><tr>{headers}</tr>");
        for m in &s.measurements {
            let cells: String = m
                .row()
                .iter()
                .map(|c| format!("<td>{}</td>", escape(c)))
                .collect();
            let class = if m.pareto { " class=\"pareto\"" } else { "" };
            let _ = writeln!(h, "<tr{class}>{cells}</tr>");
        }
        h.push_str("</table>\n");
    }
    h.push_str("</body></html>\n");
    h
}
