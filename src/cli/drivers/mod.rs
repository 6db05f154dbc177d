//! `glint drivers`: the same scenes on every Vulkan driver the machine
//! has, each in a child process of its own, each image held to one CPU
//! f64 reference with `compare`'s tolerance, and a reproducer for each
//! failure (docs/drivers.md).

mod folder;
mod generated;
pub mod icd;
mod identify;
mod memory;
mod outcome;
mod plan;
pub mod probe;
mod rows;
mod scene_run;
mod staging;
mod table;

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

use anyhow::Context;
use clap::Args;

use glint::output::Outputs;

use staging::{check_reproducers, Staging};

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

/// The shortest --deadline: a probe's start and its driver's load.
const MIN_DEADLINE: Duration = Duration::from_secs(1);

/// What every run of one scene shares.
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
    let limits = plan::Limits::of(a)?;
    // The options every child would refuse, refused once here (each
    // driver became "no device" or "refused", exit 0).
    a.device.options()?.check()?;
    icd::check_given(&a.icd)?;
    let size = plan::size(a)?;
    let scenes = plan::scenes(a, &size)?;
    let started = Instant::now();
    let files = plan::driver_files(a)?;
    let inputs = plan::inputs(a, &scenes, &files);
    let mut outputs = Outputs::new(inputs.iter(), false);
    for f in table::files(&a.output) {
        if f.parent().is_some_and(|d| d.is_dir()) {
            outputs.check(&f)?;
        }
    }
    let work = glint::output::interrupt::TempFolder::new("drivers")
        .context("cannot make a temporary folder")?;
    staging::room(work.path())?;
    let run = Run {
        args: a,
        device_args: a.device.forward(),
        work: work.path(),
        deadline: limits.deadline,
        shrink_budget: limits.shrink_budget,
        ends: limits.budget.map(|b| started + b),
    };
    // The reproducers are written into a folder of their own beside
    // repro/, which replaces repro/ as the tables are written: an
    // interrupted run leaves the last run's tables and reproducers as they
    // were (they were deleted first).
    let repro_root = a.output.join("repro");
    check_reproducers(&repro_root, &inputs)?;
    let all = progress::waiting("naming each driver's device", || {
        identify::identify(&run, &files)
    })?;
    let (drivers, absent) = identify::tested(all)?;
    let staging = Staging::new(&a.output)?;
    let load_repro = identify::load_reproducers(&run, &drivers, &staging, &repro_root)?;
    let rows = run.rows(&scenes, &drivers, &load_repro, &staging.dir, &repro_root)?;
    let seconds = started.elapsed().as_secs_f64();
    let matrix = outcome::matrix(&drivers, &absent, rows, &size, seconds);
    outcome::finish(&matrix, a, outputs, staging, &repro_root)
}
