//! Each driver's device, named in a child process of its own before any
//! scene runs, and the drivers that can be tested.

use std::path::{Path, PathBuf};

use glint::drivers::verdict::{self, Verdict};
use glint::drivers::{repro, Ended, Identity};

use super::folder::folder;
use super::probe::Job;
use super::staging::Staging;
use super::{icd, Run};

/// A driver of the matrix: its ICD file, a short name, and the device it
/// gave (or how naming it ended).
pub(super) struct Driver {
    /// Its place among the ICD files found (its probe folder's number).
    pub index: usize,
    pub icd: PathBuf,
    pub name: String,
    pub identity: Result<Identity, Verdict>,
}

/// Names each ICD's device, each in its own process.
pub(super) fn identify(run: &Run, files: &[PathBuf]) -> anyhow::Result<Vec<Driver>> {
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

/// The drivers that can be tested, and those absent (no device, an
/// error); an error where none can be: a run that can test nothing is not
/// a pass (`--icd X --only` where X gives no device exited 0 with an
/// empty table).
pub(super) fn tested(all: Vec<Driver>) -> anyhow::Result<(Vec<Driver>, Vec<Driver>)> {
    let (drivers, absent): (Vec<Driver>, Vec<Driver>) = all
        .into_iter()
        .partition(|d| !matches!(&d.identity, Err(Verdict::Error { .. })));
    if drivers.is_empty() {
        let why: Vec<String> = absent
            .iter()
            .map(|d| {
                format!(
                    "{}: {}",
                    glint::printable::path(&d.icd),
                    glint::printable::text(&d.absence())
                )
            })
            .collect();
        anyhow::bail!(
            "no driver could be tested, so nothing was: {}",
            why.join("; ")
        );
    }
    Ok((drivers, absent))
}

impl Driver {
    /// Why it has no device: its load's verdict ("" where it has one).
    pub(super) fn absence(&self) -> String {
        self.identity
            .as_ref()
            .err()
            .map(|v| v.detail())
            .unwrap_or_default()
    }
}

/// The reproducer of each driver that crashed or hung while loading,
/// written into `staging` (each of its cells names it): where it will be
/// under `repro_root`.
pub(super) fn load_reproducers(
    run: &Run,
    drivers: &[Driver],
    staging: &Staging,
    repro_root: &Path,
) -> anyhow::Result<Vec<Option<PathBuf>>> {
    let mut load_repro = Vec::new();
    for d in drivers {
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
    Ok(load_repro)
}
