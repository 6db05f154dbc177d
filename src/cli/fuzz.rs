//! `glint fuzz`: generated scenes held to the oracle (docs/guarantees.md,
//! Generated scenes): random ones for a number of minutes or cases, the CI
//! set, or every small scene; each failure shrunk and written out as a
//! scene file with its seed.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use anyhow::Context;
use clap::{Args, ValueEnum};

use glint::fuzz::{self, Case, Device, Property};
use glint::generate::{space, Spec};

use super::console::outln;
use super::{progress, Backend};

/// Which scenes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Set {
    /// Random scenes over wide ranges, until --minutes or --cases.
    Random,
    /// The CI set: the core exhaustively, the rest by a covering array.
    Ci,
    /// Every scene of the small space (tens of thousands).
    Full,
}

#[derive(Args)]
pub struct FuzzArgs {
    /// Which scenes: random (until --minutes or --cases), the CI set, or the full small space.
    #[arg(long, value_enum, default_value = "random")]
    set: Set,
    /// Stop starting cases after this many minutes [default: 1, or the whole set].
    #[arg(long, value_name = "N")]
    minutes: Option<f64>,
    /// Stop after this many cases.
    #[arg(long, value_name = "N")]
    cases: Option<usize>,
    /// The seed of the scenes' placements and of the random set.
    #[arg(long, default_value_t = 56)]
    seed: u64,
    /// Random scenes hold up to N objects (past 16 bounded ones, the BVH).
    #[arg(long, value_name = "N", default_value_t = 40)]
    objects: usize,
    /// Hold the GPU (gpu) or only the CPU's f32 and the metamorphic checks (cpu) to the reference.
    #[arg(long, value_enum, default_value = "gpu")]
    backend: Backend,
    /// Use the first Vulkan device whose name contains NAME.
    #[arg(long, value_name = "NAME")]
    device: Option<String>,
    /// Where each failure's shrunk scene is written.
    #[arg(short = 'o', long, value_name = "DIR", default_value = "fuzz-found")]
    out: PathBuf,
    /// The most checks one failure's shrinking may take.
    #[arg(long, value_name = "N", default_value_t = 60)]
    shrink: usize,
    /// Write the set's scenes into DIR (case-SEED-I.toml and their files) instead of checking them.
    #[arg(long, value_name = "DIR")]
    dump: Option<PathBuf>,
    /// Print one JSON object on stdout.
    #[arg(long)]
    json: bool,
    /// Run the GPU's shader as the least precise conformant Vulkan driver may (docs/guarantees.md).
    #[arg(long)]
    spec_worst: bool,
}

/// The GPU's oracle, where this build and the backend have one.
#[cfg(feature = "gpu")]
fn device(a: &FuzzArgs) -> anyhow::Result<Option<Box<dyn Device>>> {
    if a.backend == Backend::Cpu {
        return Ok(None);
    }
    let opts = glint::gpu::GpuOptions {
        spec_worst: a.spec_worst,
        ..glint::gpu::GpuOptions::from_env(a.device.clone())
    };
    Ok(Some(Box::new(fuzz::GpuOracle::new(&opts)?)))
}

#[cfg(not(feature = "gpu"))]
fn device(a: &FuzzArgs) -> anyhow::Result<Option<Box<dyn Device>>> {
    if a.backend == Backend::Cpu {
        return Ok(None);
    }
    Err(super::without_gpu::refuse("glint fuzz --backend gpu"))
}

/// The device for one more check.
fn borrowed(d: &mut Option<Box<dyn Device>>) -> Option<&mut dyn Device> {
    match d {
        Some(b) => Some(b.as_mut()),
        None => None,
    }
}

/// The scenes of the set, lazily: the random set has no end.
fn scenes(a: &FuzzArgs) -> Box<dyn Iterator<Item = Spec>> {
    let seed = a.seed;
    match a.set {
        Set::Random => {
            let n = a.objects;
            Box::new(
                (0u64..)
                    .map(move |i| space::random(glint::generate::case_seed(seed, i), n, 16, 12)),
            )
        }
        Set::Ci => Box::new(space::ci().into_iter().map(move |p| p.spec(seed, 16, 12))),
        Set::Full => Box::new(space::full().map(move |p| p.spec(seed, 16, 12))),
    }
}

/// Writes the first --cases scenes of the set into `dir`, each file as
/// every output is written (whole or not at all, never half a scene).
fn dump(a: &FuzzArgs, dir: &std::path::Path) -> anyhow::Result<ExitCode> {
    glint::output::check_folder(dir)?;
    std::fs::create_dir_all(dir)
        .with_context(|| format!("cannot make {}", glint::printable::path(dir)))?;
    let mut written = Vec::new();
    for (i, spec) in scenes(a).take(a.cases.unwrap_or(1000)).enumerate() {
        written.push(
            spec.scene()
                .write(dir, &format!("case-{}-{i}.toml", a.seed))?,
        );
    }
    if a.json {
        outln!(
            "{}",
            serde_json::json!({ "set": format!("{:?}", a.set).to_lowercase(), "seed": a.seed,
                "folder": dir, "scenes": written })
        );
    } else {
        outln!(
            "{} generated scenes written into {}",
            written.len(),
            glint::printable::path(dir)
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// The longest --minutes: about two years, and a deadline a clock can hold.
const MAX_MINUTES: f64 = 1e6;

/// Refuses what no run can do before any scene is made: a --minutes no
/// clock holds (1e300 overflowed a `Duration` and panicked), and more
/// objects than a generated scene may hold (4294967296 asked 16 GB at once
/// and aborted).
fn check(a: &FuzzArgs) -> anyhow::Result<()> {
    if let Some(m) = a.minutes {
        anyhow::ensure!(
            m > 0.0 && m <= MAX_MINUTES,
            "--minutes {}: must be a number of minutes in (0, {}]",
            glint::printable::number(m),
            glint::printable::number(MAX_MINUTES)
        );
    }
    anyhow::ensure!(
        a.objects <= space::MAX_OBJECTS,
        "--objects {}: a generated scene holds at most {} objects",
        a.objects,
        space::MAX_OBJECTS
    );
    anyhow::ensure!(
        !(a.spec_worst && a.backend == Backend::Cpu),
        "--spec-worst applies to the GPU's shader, and --backend cpu reads none (drop --spec-worst, or fuzz the GPU)"
    );
    Ok(())
}

pub fn run(a: &FuzzArgs) -> anyhow::Result<ExitCode> {
    check(a)?;
    if let Some(dir) = &a.dump {
        return dump(a, dir);
    }
    let mut device = device(a)?;
    let total = match a.set {
        Set::Random => None,
        Set::Ci => Some(space::ci().len()),
        Set::Full => Some(space::full_len()),
    };
    let minutes = a.minutes.or(total.is_none().then_some(1.0));
    let deadline = minutes.map(|m| Instant::now() + Duration::from_secs_f64(m * 60.0));
    let limit = a.cases.or(total).unwrap_or(usize::MAX);
    let bar = progress::bar(limit.min(1 << 40) as u64, "scenes");
    let everything = |_: Property| true;
    let started = Instant::now();
    let (mut run, mut found): (usize, Vec<(Case, usize, usize)>) = (0, Vec::new());
    for spec in scenes(a).take(limit) {
        if deadline.is_some_and(|d| Instant::now() >= d) {
            break;
        }
        let failures = fuzz::check(&spec, borrowed(&mut device), &everything);
        run += 1;
        bar.inc(1);
        if let Some(first) = failures.first() {
            let (small, shrunk, checks) =
                fuzz::shrink(&spec, first.property, borrowed(&mut device), a.shrink);
            let case = Case {
                spec: small,
                failures: shrunk,
            };
            found.push((case, run - 1, checks));
            bar.set_message(format!("{} failing", found.len()));
        }
    }
    bar.finish_and_clear();
    let seconds = started.elapsed().as_secs_f64();
    let mut written = Vec::new();
    if !found.is_empty() {
        glint::output::check_folder(&a.out)?;
        std::fs::create_dir_all(&a.out)
            .with_context(|| format!("cannot make {}", a.out.display()))?;
    }
    for (case, index, _) in &found {
        let name = format!("case-{}-{index}.toml", a.seed);
        let path = fuzz::write_case(case, &a.out, &name)?;
        written.push(path);
    }
    if a.json {
        let failures: Vec<_> = found
            .iter()
            .zip(&written)
            .map(|((case, index, checks), path)| {
                serde_json::json!({ "case": index, "scene": path, "shrink_checks": checks,
                    "spec": case.spec, "failures": case.failures })
            })
            .collect();
        outln!(
            "{}",
            serde_json::json!({ "set": format!("{:?}", a.set).to_lowercase(), "seed": a.seed,
                "spec_worst": a.spec_worst, "cases": run, "seconds": seconds, "failures": failures })
        );
    } else {
        outln!(
            "{run} generated scenes ({:?} set, seed {}{}) in {seconds:.1} s: {} failing",
            a.set,
            a.seed,
            if a.spec_worst { ", --spec-worst" } else { "" },
            found.len()
        );
        for ((case, index, checks), path) in found.iter().zip(&written) {
            for f in &case.failures {
                outln!(
                    "case {index}: {} fails {}: {}",
                    glint::printable::text(&path.display().to_string()),
                    f.property.name(),
                    glint::printable::text(&f.detail)
                );
            }
            outln!(
                "  shrunk in {checks} checks to {} objects, {} lights",
                case.spec.objects.len(),
                case.spec.lights.len()
            );
        }
    }
    Ok(if found.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}
