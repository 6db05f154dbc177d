//! What a run of `glint drivers` is asked, checked before any driver
//! runs: its time limits, its image size, its scenes (each loaded) and the
//! drivers' ICD files.

use std::path::PathBuf;
use std::time::Duration;

use glint::cpu;
use glint::scene::{Overrides, Scene};

use super::generated::Generated;
use super::{icd, memory, DriversArgs, MIN_DEADLINE};

/// The run's time limits.
pub(super) struct Limits {
    /// One driver's run of one scene.
    pub deadline: Duration,
    /// Shrinking one failure's reproducer.
    pub shrink_budget: Duration,
    /// The whole run, where it has one.
    pub budget: Option<Duration>,
}

impl Limits {
    pub(super) fn of(a: &DriversArgs) -> anyhow::Result<Limits> {
        let seconds = |name: &str, v: f64| {
            anyhow::ensure!(
                v.is_finite() && v > 0.0 && v <= 1e6,
                "{name} {}: must be in (0, 1e6] seconds",
                glint::printable::number(v)
            );
            Ok(Duration::from_secs_f64(v))
        };
        let deadline = seconds("--deadline", a.deadline.unwrap_or(120.0))?;
        // Below a second a probe is killed while its process and the driver
        // load, and every driver, with a device or none, would read "hung":
        // that is no verdict on a driver.
        anyhow::ensure!(
            deadline >= MIN_DEADLINE,
            "--deadline {}: must be at least {} s, the time a probe takes to start and load its driver",
            glint::printable::number(a.deadline.unwrap_or_default()),
            MIN_DEADLINE.as_secs()
        );
        Ok(Limits {
            deadline,
            shrink_budget: seconds("--shrink-budget", a.shrink_budget.unwrap_or(60.0))?,
            budget: a.budget.map(|b| seconds("--budget", b)).transpose()?,
        })
    }
}

/// Every scene's size, checked against the machine's memory.
pub(super) fn size(a: &DriversArgs) -> anyhow::Result<Overrides> {
    let size = Overrides {
        width: Some(a.width.unwrap_or(if a.quick { 64 } else { 160 })),
        height: Some(a.height.unwrap_or(if a.quick { 48 } else { 120 })),
        ..Overrides::default()
    };
    memory::check(
        size.width.unwrap_or_default(),
        size.height.unwrap_or_default(),
    )?;
    Ok(size)
}

/// A row's scene: read before any driver runs, or generated as its row
/// starts (`--generated`).
pub(super) enum Source {
    Read(Box<Scene>),
    Generated(u64),
}

/// The run's rows: each scene's path and its source, with the generated
/// scenes' folder and the size every scene is read at.
pub(super) struct Scenes {
    pub paths: Vec<PathBuf>,
    pub sources: Vec<Source>,
    pub generated: Option<Generated>,
    pub size: Overrides,
}

/// The scenes' files and the scenes: those named (or the defaults), every
/// one read at `size` before minutes of rendering and before anything is
/// written, then the generated ones, whose folder is made anew here.
pub(super) fn scenes(a: &DriversArgs, size: &Overrides) -> anyhow::Result<Scenes> {
    let mut paths = if !a.scenes.is_empty() || a.generated.is_some() {
        a.scenes.clone()
    } else if a.quick {
        crate::cli::scene_files("scenes")?
    } else {
        let mut v = crate::cli::scene_files("scenes")?;
        v.extend(crate::cli::scene_files("scenes/spd")?);
        v.extend(crate::cli::scene_files("scenes/extreme")?);
        v
    };
    let mut scenes = paths
        .iter()
        .map(|p| {
            let s = Scene::load(p, size)?;
            cpu::bound::check(&s)?;
            Ok(Source::Read(Box::new(s)))
        })
        .collect::<anyhow::Result<Vec<_>>>()?;
    let Some(n) = a.generated else {
        return Ok(Scenes {
            paths,
            sources: scenes,
            generated: None,
            size: *size,
        });
    };
    let mut read = paths.clone();
    for s in &scenes {
        if let Source::Read(s) = s {
            read.extend(s.input_files.iter().cloned());
        }
    }
    let generated = Generated::new(&a.output, n, a.seed, &read)?;
    generated.make_folder()?;
    for i in 0..n as u64 {
        paths.push(generated.path(i));
        scenes.push(Source::Generated(i));
    }
    Ok(Scenes {
        paths,
        sources: scenes,
        generated: Some(generated),
        size: *size,
    })
}

/// The drivers' ICD files: the loader's, the unpacked ones and those
/// given, or those given alone (`--only`), each once.
pub(super) fn driver_files(a: &DriversArgs) -> anyhow::Result<Vec<PathBuf>> {
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
    Ok(files)
}

/// Every file the run reads: the scenes and theirs, the shader files, the
/// ICD files and the drivers' libraries (a drivers.csv linked to the
/// library the run loaded replaced it).
pub(super) fn inputs(a: &DriversArgs, scenes: &Scenes, files: &[PathBuf]) -> Vec<PathBuf> {
    let mut inputs = a.device.inputs();
    inputs.extend(a.icd.iter().cloned());
    for (p, s) in scenes.paths.iter().zip(&scenes.sources) {
        if let Source::Read(s) = s {
            inputs.push(p.clone());
            inputs.extend(s.input_files.iter().cloned());
        }
    }
    inputs.extend(files.iter().cloned());
    inputs.extend(files.iter().filter_map(|f| icd::library(f)));
    inputs
}
