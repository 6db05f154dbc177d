//! `glint drivers`: the same scenes on every Vulkan driver the machine
//! has, each in a child process of its own, each image held to one CPU
//! f64 reference with `compare`'s tolerance, and a reproducer for each
//! failure (docs/drivers.md).

use crate::cli::console::{out, outln};

mod generated;
pub mod icd;
mod memory;
pub mod probe;
mod repro;
mod scene_run;
mod shrink;
mod staging;
mod table;
mod verdict;

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

use anyhow::Context;
use clap::Args;

use glint::cpu;
use glint::output::Outputs;
use glint::raster::Image;
use glint::scene::{Overrides, Scene};

use probe::{Ended, Identity, Job};
use repro::Size;
use staging::{check_reproducers, Staging};
use table::{Cell, Column, Matrix, Row};
use verdict::Verdict;

use super::{progress, DeviceArgs};

#[derive(Args)]
pub struct DriversArgs {
    /// Scene files [default: every scene in scenes/, scenes/spd and scenes/extreme; with --quick, scenes/ alone].
    scenes: Vec<PathBuf>,
    /// The folder to write drivers.md, drivers.csv, drivers.json, index.html and the reproducers (repro/) into.
    #[arg(short, long, value_name = "DIR", default_value = "drivers")]
    output: PathBuf,
    /// Small images (64x48) of the scenes in scenes/ alone: seconds, for tests and CI.
    #[arg(long)]
    quick: bool,
    /// Also the driver of this ICD manifest file; repeatable.
    #[arg(long, value_name = "FILE")]
    icd: Vec<PathBuf>,
    /// Only the drivers given with --icd: none of those the machine has.
    #[arg(long, requires = "icd")]
    only: bool,
    /// Image width for every scene [default: 160; 64 with --quick].
    #[arg(long)]
    width: Option<u32>,
    /// Image height for every scene [default: 120; 48 with --quick].
    #[arg(long)]
    height: Option<u32>,
    /// Give up on one driver's run of one scene after SECONDS and call it hung [default: 120].
    #[arg(long, value_name = "SECONDS")]
    deadline: Option<f64>,
    /// Keep each reproducer at the size it failed at, without trying smaller images.
    #[arg(long)]
    no_shrink: bool,
    /// Spend at most SECONDS shrinking one failure's reproducer [default: 60].
    #[arg(long, value_name = "SECONDS")]
    shrink_budget: Option<f64>,
    /// Start no driver's run past SECONDS from the start: the cells not
    /// reached are "not run", and the run is not a pass [default: no limit].
    #[arg(long, value_name = "SECONDS")]
    budget: Option<f64>,
    /// Also N generated scenes (`glint fuzz`'s random set), written into DIR/generated/; alone where no scene is named.
    #[arg(long, value_name = "N")]
    generated: Option<usize>,
    /// The seed of the --generated scenes.
    #[arg(long, default_value_t = 56, requires = "generated")]
    seed: u64,
    #[command(flatten)]
    device: DeviceArgs,
}

/// A driver of the matrix: its ICD file, a short name, and the device it
/// gave (or how naming it ended).
struct Driver {
    /// Its place among the ICD files found (its probe folder's number).
    index: usize,
    icd: PathBuf,
    name: String,
    identity: Result<Identity, Verdict>,
}

/// What every run of one scene shares.
/// The shortest --deadline: a probe's start and its driver's load.
const MIN_DEADLINE: Duration = Duration::from_secs(1);

struct Run<'a> {
    args: &'a DriversArgs,
    device_args: Vec<OsString>,
    work: &'a Path,
    deadline: Duration,
    shrink_budget: Duration,
    /// When the run's --budget ends, where it has one.
    ends: Option<Instant>,
}

pub fn run(a: &DriversArgs) -> anyhow::Result<ExitCode> {
    anyhow::ensure!(
        !a.device.names_a_device(),
        "--device does not apply to `glint drivers`: it runs each driver's own device (name a driver with --icd FILE --only)"
    );
    let seconds = |name: &str, v: f64| {
        anyhow::ensure!(
            v.is_finite() && v > 0.0 && v <= 1e6,
            "{name} {v:?}: must be in (0, 1e6] seconds"
        );
        Ok(Duration::from_secs_f64(v))
    };
    let deadline = seconds("--deadline", a.deadline.unwrap_or(120.0))?;
    // Below a second a probe is killed while its process and the driver
    // load, and every driver, with a device or none, would read "hung"
    // (issue 57, item 13): that is no verdict on a driver.
    anyhow::ensure!(
        deadline >= MIN_DEADLINE,
        "--deadline {:?}: must be at least {} s, the time a probe takes to start and load its driver",
        a.deadline.unwrap_or_default(),
        MIN_DEADLINE.as_secs()
    );
    let shrink_budget = seconds("--shrink-budget", a.shrink_budget.unwrap_or(60.0))?;
    let budget = a.budget.map(|b| seconds("--budget", b)).transpose()?;
    // The options every child would refuse, refused once here (issue 42,
    // defect 5: each driver became "no device" or "refused", exit 0).
    a.device.options()?.check()?;
    icd::check_given(&a.icd)?;
    let size = Overrides {
        width: Some(a.width.unwrap_or(if a.quick { 64 } else { 160 })),
        height: Some(a.height.unwrap_or(if a.quick { 48 } else { 120 })),
        ..Overrides::default()
    };
    memory::check(
        size.width.unwrap_or_default(),
        size.height.unwrap_or_default(),
    )?;
    let mut paths = if !a.scenes.is_empty() || a.generated.is_some() {
        a.scenes.clone()
    } else if a.quick {
        super::scene_files("scenes")?
    } else {
        let mut v = super::scene_files("scenes")?;
        v.extend(super::scene_files("scenes/spd")?);
        v.extend(super::scene_files("scenes/extreme")?);
        v
    };
    if let Some(n) = a.generated {
        paths.extend(generated::write(&a.output, n, a.seed)?);
    }
    // Every scene loads before minutes of rendering.
    let scenes = paths
        .iter()
        .map(|p| {
            let s = Scene::load(p, &size)?;
            cpu::bound::check(&s)?;
            Ok(s)
        })
        .collect::<anyhow::Result<Vec<_>>>()?;
    let started = Instant::now();
    let files = if a.only {
        a.icd.clone()
    } else {
        let mut v = icd::loader_files();
        v.extend(icd::unpacked_files());
        v.extend(a.icd.iter().cloned());
        v
    };
    let files = icd::once(files);
    anyhow::ensure!(
        !files.is_empty(),
        "no Vulkan driver found: no ICD file in the loader's folders (install mesa-vulkan-drivers, or name one with --icd FILE)"
    );
    // The drivers' libraries are inputs too (issue 42, defect 2: a
    // drivers.csv linked to the library the run loaded replaced it).
    let mut inputs = inputs_of(&paths, &scenes, a);
    inputs.extend(files.iter().cloned());
    inputs.extend(files.iter().filter_map(|f| icd::library(f)));
    let mut outputs = Outputs::new(inputs.iter(), false);
    for f in table::files(&a.output) {
        if f.parent().is_some_and(|d| d.is_dir()) {
            outputs.check(&f)?;
        }
    }
    staging::remove_stale_work();
    let work = tempfile::Builder::new()
        .prefix(&staging::work_prefix())
        .tempdir()
        .context("cannot make a temporary folder")?;
    crate::cli::interrupt::folder_made(work.path());
    staging::room(work.path())?;
    let run = Run {
        args: a,
        device_args: a.device.forward(),
        work: work.path(),
        deadline,
        shrink_budget,
        ends: budget.map(|b| started + b),
    };
    // The reproducers are written into a folder of their own beside
    // repro/, which replaces repro/ as the tables are written: an
    // interrupted run leaves the last run's tables and reproducers as they
    // were (issue 42, defect 4: they were deleted first).
    let repro_root = a.output.join("repro");
    check_reproducers(&repro_root, &inputs)?;
    let all: Vec<Driver> =
        progress::waiting("naming each driver's device", || identify(&run, &files))?;
    let (drivers, absent): (Vec<Driver>, Vec<Driver>) = all
        .into_iter()
        .partition(|d| !matches!(&d.identity, Err(Verdict::Error { .. })));
    // A run that can test nothing is not a pass (issue 42, defect 6:
    // `--icd X --only` where X gives no device exited 0 with an empty table).
    if drivers.is_empty() {
        let why: Vec<String> = absent
            .iter()
            .map(|d| {
                let detail = d
                    .identity
                    .as_ref()
                    .err()
                    .map(|v| v.detail())
                    .unwrap_or_default();
                format!(
                    "{}: {}",
                    glint::printable::path(&d.icd),
                    glint::printable::text(&detail)
                )
            })
            .collect();
        anyhow::bail!(
            "no driver could be tested, so nothing was: {}",
            why.join("; ")
        );
    }
    let staging = Staging::new(&a.output)?;
    // A driver that crashed or hung while loading has one reproducer,
    // which each of its cells names.
    let mut load_repro = Vec::new();
    for d in &drivers {
        load_repro.push(match &d.identity {
            Err(v) if v.is_failure() => {
                let rel = Path::new(&folder(&d.name, &d.icd)).join("load");
                let dir = staging.dir.join(&rel);
                let stderr = run
                    .work
                    .join(format!("identify-{}", d.index))
                    .join("stderr.txt");
                repro::write_load(&d.icd, v, &stderr, &dir)?;
                Some(repro_root.join(rel))
            }
            _ => None,
        });
    }
    let bar = progress::bar((scenes.len() * drivers.len()) as u64, "drivers");
    let mut rows = Vec::new();
    let names = row_names(&paths);
    for ((path, scene), name) in paths.iter().zip(&scenes).zip(names) {
        let shown = glint::printable::text(&name);
        bar.set_message(format!("{shown}: the CPU f64 reference"));
        let reference = if run.past_budget() {
            None
        } else {
            Some(reference(scene, a.device.accel)?)
        };
        let mut cells = Vec::new();
        for (d, load_repro) in drivers.iter().zip(&load_repro) {
            let driver = glint::printable::text(&d.name);
            bar.set_message(format!("{shown} on {driver}"));
            let cell = match (&d.identity, &reference) {
                (Err(v), Some(_)) => Cell {
                    verdict: v.clone(),
                    repro: load_repro.clone(),
                    explained: None,
                },
                (Ok(identity), Some(reference)) if !run.past_budget() => {
                    let (verdict, image, stderr) = run.scene(
                        d,
                        path,
                        scene,
                        reference,
                        "run",
                        Size::of(scene),
                        run.deadline,
                    )?;
                    let mut explained = None;
                    let repro = if verdict.is_failure() {
                        let rel = Path::new(&folder(&d.name, &d.icd))
                            .join(folder(&scene_name(path), path));
                        bar.set_message(format!("{shown} on {driver}: reproducer"));
                        explained = run.reproducer(
                            d,
                            identity,
                            path,
                            scene,
                            &verdict,
                            image,
                            reference,
                            stderr,
                            &staging.dir.join(&rel),
                        )?;
                        Some(repro_root.join(rel))
                    } else {
                        None
                    };
                    Cell {
                        verdict,
                        repro,
                        explained,
                    }
                }
                // Past the budget (the reference too, where it was first).
                _ => Cell {
                    verdict: Verdict::NotRun {
                        reason: format!(
                            "past the run's --budget of {} s",
                            a.budget.unwrap_or_default()
                        ),
                    },
                    repro: None,
                    explained: None,
                },
            };
            cells.push(cell);
            bar.inc(1);
        }
        rows.push(Row { scene: name, cells });
    }
    bar.finish_and_clear();
    let matrix = Matrix {
        columns: drivers
            .iter()
            .map(|d| Column {
                icd: d.icd.clone(),
                name: d.name.clone(),
                identity: d.identity.as_ref().ok().cloned(),
                load: d.identity.as_ref().err().cloned(),
            })
            .collect(),
        absent: absent
            .iter()
            .map(|d| {
                (
                    d.icd.clone(),
                    d.identity
                        .as_ref()
                        .err()
                        .map(|v| v.detail())
                        .unwrap_or_default(),
                )
            })
            .collect(),
        rows,
        size: (size.width.unwrap_or(0), size.height.unwrap_or(0)),
        seconds: started.elapsed().as_secs_f64(),
        experiment: std::env::var("GLINT_EXPERIMENT").ok(),
        validation: probe::validation_layer(),
    };
    staging.replace(&repro_root)?;
    table::write_all(&matrix, &a.output, outputs)?;
    out!("{}", table::summary(&matrix));
    outln!(
        "wrote {}/index.html, drivers.md, drivers.csv, drivers.json{} in {:.1} s",
        glint::printable::path(&a.output),
        if matrix
            .rows
            .iter()
            .flat_map(|r| &r.cells)
            .any(|c| c.repro.is_some())
        {
            " and repro/"
        } else {
            ""
        },
        matrix.seconds
    );
    // Exit 0 says every cell ran and some image was held to its
    // reference: a run of refusals, errors or cells past the budget tested
    // nothing, or not everything (issue 42, defects 5, 6 and 10).
    if matrix.failures() > 0 {
        return Ok(ExitCode::from(1));
    }
    let verdicts: Vec<&Verdict> = matrix
        .rows
        .iter()
        .flat_map(|r| &r.cells)
        .map(|c| &c.verdict)
        .collect();
    let not_run = verdicts
        .iter()
        .filter(|v| matches!(v, Verdict::NotRun { .. }))
        .count();
    anyhow::ensure!(
        not_run == 0,
        "{not_run} of {} cells were not run: the run reached its --budget of {} s (the tables say which)",
        verdicts.len(),
        a.budget.unwrap_or_default()
    );
    anyhow::ensure!(
        verdicts
            .iter()
            .any(|v| matches!(v, Verdict::Pass { .. } | Verdict::IllConditioned { .. })),
        "nothing was tested: every cell is refused or an error (the tables say why)"
    );
    Ok(ExitCode::SUCCESS)
}

/// Every file the run reads: the scenes and theirs, the shader files and
/// the ICD files named.
fn inputs_of(paths: &[PathBuf], scenes: &[Scene], a: &DriversArgs) -> Vec<PathBuf> {
    let mut inputs = a.device.inputs();
    inputs.extend(a.icd.iter().cloned());
    for (p, s) in paths.iter().zip(scenes) {
        inputs.push(p.clone());
        inputs.extend(s.input_files.iter().cloned());
    }
    inputs
}

/// Names each ICD's device, each in its own process.
fn identify(run: &Run, files: &[PathBuf]) -> anyhow::Result<Vec<Driver>> {
    let mut names = std::collections::HashSet::new();
    let mut drivers = Vec::new();
    for (i, icd) in files.iter().enumerate() {
        let mut name = icd::short_name(icd);
        if !names.insert(name.clone()) {
            name = format!("{name}-{i}");
        }
        let out = run.work.join(format!("identify-{i}"));
        let job = Job {
            icd,
            args: run.device_args.clone(),
            out,
            deadline: run.deadline,
        };
        let identity = match job.run()? {
            Ended::Wrote(p) => match (p.device, verdict::rendered(p.seen)) {
                (Some(d), Ok(_)) => Ok(d),
                (None, Ok(_)) => Err(Verdict::Error {
                    message: "no device named".into(),
                }),
                (_, Err(v)) => Err(v),
            },
            other => Err(verdict::judge_ended(other)),
        };
        drivers.push(Driver {
            index: i,
            icd: icd.clone(),
            name,
            identity,
        });
    }
    Ok(drivers)
}

/// The CPU f64 reference of `scene`.
fn reference(scene: &Scene, accel: glint::accel::Accel) -> anyhow::Result<Image> {
    Ok(cpu::reference(scene, accel)?)
}

/// The scene's name: its file's stem.
fn scene_name(path: &Path) -> String {
    super::scene_name(path)
}

/// Each scene's row: its stem, or the path as given where two scenes share
/// a stem (issue 42, defect 3: a/s.toml and b/s.toml were two rows "s").
fn row_names(paths: &[PathBuf]) -> Vec<String> {
    let stems: Vec<String> = paths.iter().map(|p| scene_name(p)).collect();
    paths
        .iter()
        .zip(&stems)
        .map(|(p, stem)| {
            if stems.iter().filter(|s| *s == stem).count() > 1 {
                p.display().to_string()
            } else {
                stem.clone()
            }
        })
        .collect()
}

/// The longest readable part of a folder name.
const FOLDER_NAME: usize = 40;

/// A folder's name for `name`, unique to `key` (the path it came from, as
/// given): the name's letters, digits, '-', '_' and inner '.', at most
/// [`FOLDER_NAME`] of them, and 8 hex digits of `key`'s hash. Never "." or
/// "..", so never outside `repro/` (issue 42, defect 1); two inputs of one
/// name, or of two names that the letters alone make one, get two folders
/// (defect 3); and a name of any length makes a short one (defect 13).
fn folder(name: &str, key: &Path) -> String {
    use std::hash::Hasher;
    use std::os::unix::ffi::OsStrExt;
    let safe: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "._-".contains(c) {
                c
            } else {
                '-'
            }
        })
        .collect();
    let mut readable: String = safe.trim_matches('.').chars().take(FOLDER_NAME).collect();
    if readable.is_empty() {
        readable.push('x');
    }
    let mut hash = glint::fnv::Fnv::default();
    hash.write(key.as_os_str().as_bytes());
    format!("{readable}-{:08x}", hash.finish() as u32)
}

#[cfg(test)]
mod tests {
    use super::folder;
    use std::path::Path;

    #[test]
    fn folders_stay_inside_are_short_and_unique_to_their_input() {
        for name in ["..", ".", "...", "", "a/../..", "/"] {
            let f = folder(name, Path::new(name));
            assert!(!f.starts_with('.') && !f.contains('/'), "{name:?}: {f}");
        }
        assert_ne!(
            folder("s", Path::new("a/s.toml")),
            folder("s", Path::new("b/s.toml"))
        );
        assert_ne!(
            folder("x y", Path::new("x y.json")),
            folder("x-y", Path::new("x-y.json"))
        );
        let long = "n".repeat(245);
        assert!(folder(&long, Path::new(&long)).len() <= 49);
    }
}
