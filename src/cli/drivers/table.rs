//! The matrix as drivers.md, drivers.csv, drivers.json and index.html:
//! scenes as rows, drivers as columns, each column headed by the device's
//! name, driver, Vulkan version and type.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use serde::Serialize;

use glint::drivers::verdict::{Verdict, WORDS};
use glint::drivers::Identity;
use glint::output::{self, Outputs};
use glint::report::escape;

/// A driver's column.
#[derive(Serialize)]
pub struct Column {
    pub icd: PathBuf,
    pub name: String,
    /// The device, where the driver named one.
    pub identity: Option<Identity>,
    /// How loading the driver ended, where it named no device.
    pub load: Option<Verdict>,
}

/// One driver's run of one scene.
#[derive(Serialize)]
pub struct Cell {
    #[serde(flatten)]
    pub verdict: Verdict,
    /// The reproducer's folder, for a failure.
    pub repro: Option<PathBuf>,
    /// The pixel its `explain.txt` explains, for a wrong image: the worst.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub explained: Option<(u32, u32)>,
}

/// A scene's row: one cell per column.
#[derive(Serialize)]
pub struct Row {
    pub scene: String,
    pub cells: Vec<Cell>,
}

/// The whole run.
#[derive(Serialize)]
pub struct Matrix {
    pub columns: Vec<Column>,
    /// The ICD files that offered no device here, and why.
    pub absent: Vec<(PathBuf, String)>,
    pub rows: Vec<Row>,
    /// The image size every scene rendered at.
    pub size: (u32, u32),
    /// The whole run's wall time.
    pub seconds: f64,
    /// `GLINT_EXPERIMENT`, where set: the shaders are not the default ones.
    pub experiment: Option<String>,
    /// Whether the probes ran under the Khronos validation layer.
    pub validation: bool,
}

impl Matrix {
    /// Cells that are a driver's failure (`Verdict::is_failure`).
    pub fn failures(&self) -> usize {
        self.cells().filter(|(_, c)| c.verdict.is_failure()).count()
    }

    fn cells(&self) -> impl Iterator<Item = (usize, &Cell)> {
        self.rows.iter().flat_map(|r| r.cells.iter().enumerate())
    }

    /// Each column's count of cells with `word`.
    fn count(&self, column: usize, word: &str) -> usize {
        self.cells()
            .filter(|(i, c)| *i == column && c.verdict.word() == word)
            .count()
    }
}

/// The files `write_all` writes into `dir`, the page last.
pub fn files(dir: &Path) -> Vec<PathBuf> {
    ["drivers.md", "drivers.csv", "drivers.json", "index.html"]
        .iter()
        .map(|n| dir.join(n))
        .collect()
}

/// Writes the four files through `outputs`, staged and committed together.
pub fn write_all(m: &Matrix, dir: &Path, mut outputs: Outputs) -> anyhow::Result<()> {
    use anyhow::Context;
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let texts = [
        markdown(m),
        csv(m)?,
        serde_json::to_string_pretty(m)?,
        page(m),
    ];
    for (path, text) in files(dir).iter().zip(&texts) {
        outputs.stage(path, |out: &mut dyn std::io::Write| {
            out.write_all(text.as_bytes()).map_err(output::io_err(path))
        })?;
    }
    Ok(outputs.commit()?)
}

/// A column's heading: the device and its driver, or the ICD's name.
fn heading(c: &Column) -> String {
    match &c.identity {
        Some(d) => format!(
            "{} ({}; {}; Vulkan {})",
            shown(&d.name),
            shown(&d.kind),
            shown(&d.driver),
            shown(&d.api_version)
        ),
        None => format!(
            "{} (failed to load: {})",
            shown(&c.name),
            glint::printable::one_line(&c.load.as_ref().map(|v| v.detail()).unwrap_or_default())
        ),
    }
}

/// What the run did, in a few sentences: the size, the rule, the time,
/// and the experiment where one was set.
fn about(m: &Matrix) -> String {
    format!(
        "Each scene at {}x{} on each driver, in a process of its own, held to the CPU f64 reference with glint compare's tolerance{}. The run took {:.1} s.{}",
        m.size.0,
        m.size.1,
        validation_words(m),
        m.seconds,
        m.experiment
            .as_ref()
            .map(|e| format!(" GLINT_EXPERIMENT={e}: not the default shaders."))
            .unwrap_or_default()
    )
}

/// Whether the validation layer watched, in words.
fn validation_words(m: &Matrix) -> &'static str {
    if m.validation {
        ", under the Khronos validation layer"
    } else {
        " (not under the Khronos validation layer: the Vulkan loader finds none where it looks, so its messages are not looked for)"
    }
}

/// One line per driver: its counts.
pub fn summary(m: &Matrix) -> String {
    let mut s = String::new();
    for (i, c) in m.columns.iter().enumerate() {
        let counts: Vec<String> = WORDS
            .iter()
            .map(|w| (w, m.count(i, w)))
            .filter(|(_, n)| *n > 0)
            .map(|(w, n)| format!("{n} {w}"))
            .collect();
        let _ = writeln!(
            s,
            "{}: {} [{}]",
            shown(&c.name),
            counts.join(", "),
            heading(c)
        );
    }
    if !m.validation {
        let _ = writeln!(
            s,
            "not under the validation layer: the Vulkan loader finds no VK_LAYER_KHRONOS_validation (Debian: apt-get install vulkan-validationlayers)"
        );
    }
    if !m.absent.is_empty() {
        let names: Vec<String> = m
            .absent
            .iter()
            .map(|(icd, _)| shown(&super::icd::short_name(icd)))
            .collect();
        let _ = writeln!(
            s,
            "no device from {} more ICD file(s): {} (drivers.md says why)",
            names.len(),
            names.join(", ")
        );
    }
    s
}

fn markdown(m: &Matrix) -> String {
    let mut s = String::from("# glint drivers\n\n");
    let _ = writeln!(s, "{}\n", about(m));
    for c in &m.columns {
        let _ = writeln!(
            s,
            "- **{}**: {} — `{}`",
            md(&c.name),
            md(&heading(c)),
            md(&c.icd.to_string_lossy())
        );
    }
    for (icd, why) in &m.absent {
        let _ = writeln!(
            s,
            "- no device from `{}`: {}",
            md(&icd.to_string_lossy()),
            md(&glint::printable::one_line(why))
        );
    }
    s.push_str("\n| scene |");
    for c in &m.columns {
        let _ = write!(s, " {} |", md(&c.name));
    }
    s.push_str("\n|---|");
    s.push_str(&"---|".repeat(m.columns.len()));
    s.push('\n');
    for r in &m.rows {
        let _ = write!(s, "| {} |", md(&r.scene));
        for c in &r.cells {
            let link = c
                .repro
                .as_ref()
                .map(|p| {
                    let explained = c.explained.map_or(String::new(), |(x, y)| {
                        format!(", [pixel {x},{y} explained]({}/explain.txt)", relative(p))
                    });
                    format!(" ([reproducer]({}){explained})", relative(p))
                })
                .unwrap_or_default();
            let _ = write!(
                s,
                " {} {}{link} |",
                c.verdict.word(),
                md(&cell_text(&c.verdict))
            );
        }
        s.push('\n');
    }
    s
}

/// A name, a path or a driver's words as the terminal, drivers.md and
/// index.html show them: control characters escaped and cut short, as
/// errors show them (a manifest named with a terminal escape cleared the
/// screen when its name was printed).
fn shown(s: &str) -> String {
    glint::printable::text(s)
}

/// `shown`, and a `|` escaped, so that a name cannot add a column to a
/// Markdown table (nor a newline end its row: `shown` escapes it).
fn md(s: &str) -> String {
    shown(s).replace('|', "\\|")
}

/// A cell's short text: the figures and time, or the first words of why.
fn cell_text(v: &Verdict) -> String {
    let d = v.detail();
    let d = d.lines().next().unwrap_or("");
    let mut short: String = d.chars().take(90).collect();
    if d.chars().count() > 90 {
        short.push('…');
    }
    short
}

/// A reproducer's folder relative to the output folder (repro/…).
fn relative(p: &Path) -> String {
    let parts: Vec<String> = p
        .components()
        .rev()
        .take(3)
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    parts.into_iter().rev().collect::<Vec<_>>().join("/")
}

fn csv(m: &Matrix) -> anyhow::Result<String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "scene",
        "icd",
        "device",
        "driver",
        "vulkan",
        "type",
        "result",
        "rmse",
        "over_1_255",
        "max_abs",
        "seconds",
        "variant",
        "detail",
        "reproducer",
    ])?;
    for r in &m.rows {
        for (c, col) in r.cells.iter().zip(&m.columns) {
            let d = col.identity.clone().unwrap_or_default();
            let (rmse, over, max_abs, secs, variant) = match &c.verdict {
                Verdict::Pass {
                    error,
                    seconds,
                    variant,
                }
                | Verdict::Fail {
                    error,
                    seconds,
                    variant,
                    ..
                }
                | Verdict::IllConditioned {
                    error,
                    seconds,
                    variant,
                    ..
                } => (
                    error.rmse.to_string(),
                    error.frac_over_1_255.to_string(),
                    error.max_abs.to_string(),
                    seconds.to_string(),
                    variant.clone(),
                ),
                _ => Default::default(),
            };
            w.write_record([
                r.scene.clone(),
                col.icd.display().to_string(),
                d.name,
                d.driver,
                d.api_version,
                d.kind,
                c.verdict.word().to_owned(),
                rmse,
                over,
                max_abs,
                secs,
                variant,
                c.verdict.detail(),
                c.repro.as_ref().map(|p| relative(p)).unwrap_or_default(),
            ])?;
        }
    }
    Ok(String::from_utf8(w.into_inner()?)?)
}

fn page(m: &Matrix) -> String {
    let mut h = String::from(
        "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>glint drivers</title>\n<style>\
body{font-family:sans-serif;margin:2em;max-width:1400px}table{border-collapse:collapse;font-size:13px}\
td,th{border:1px solid #ccc;padding:3px 6px;vertical-align:top}th{background:#f3f3f3;max-width:260px}\
.pass{background:#e8f5e9}.FAIL,.crashed,.hung,.validation{background:#ffcdd2}.refused,.error,.ill-conditioned{background:#fff8e1}\
small{color:#555}</style></head><body>\n<h1>glint: the scenes on each Vulkan driver</h1>\n",
    );
    let _ = writeln!(
        h,
        "<p>{} Where the whole image is over the tolerance, it is held to its well-conditioned pixels. Red: a wrong image, a crash, a hang or a validation message, each with a reproducer; yellow: ill-conditioned (more than 10 % of the pixels are beyond any f32 renderer, so the image is not held to the reference), refused by a limit glint knows, or an error.</p>",
        escape(&about(m))
    );
    h.push_str("<table>\n<tr><th>scene</th>");
    for c in &m.columns {
        let _ = write!(
            h,
            "<th>{}<br><small>{}<br><code>{}</code></small></th>",
            escape(&shown(&c.name)),
            escape(&heading(c)),
            escape(&glint::printable::path(&c.icd))
        );
    }
    h.push_str("</tr>\n");
    for r in &m.rows {
        let _ = write!(h, "<tr><td>{}</td>", escape(&shown(&r.scene)));
        for c in &r.cells {
            let word = c.verdict.word();
            let link = c
                .repro
                .as_ref()
                .map(|p| {
                    let rel = relative(p);
                    let explained = c.explained.map_or(String::new(), |(x, y)| {
                        format!(
                            ", <a href=\"{}/explain.txt\">pixel {x},{y} explained</a>",
                            escape(&rel)
                        )
                    });
                    format!(
                        " <a href=\"{}/README.md\">reproducer</a>{explained}",
                        escape(&rel)
                    )
                })
                .unwrap_or_default();
            let _ = write!(
                h,
                "<td class=\"{word}\">{word}{link}<br><small>{}</small></td>",
                escape(&shown(&cell_text(&c.verdict)))
            );
        }
        h.push_str("</tr>\n");
    }
    h.push_str("</table>\n");
    if !m.absent.is_empty() {
        h.push_str("<p>ICD files with no device here:</p><ul>\n");
        for (icd, why) in &m.absent {
            let _ = writeln!(
                h,
                "<li><code>{}</code>: {}</li>",
                escape(&glint::printable::path(icd)),
                escape(&glint::printable::one_line(why))
            );
        }
        h.push_str("</ul>\n");
    }
    h.push_str("</body></html>\n");
    h
}
