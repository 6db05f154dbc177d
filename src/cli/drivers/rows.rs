//! The matrix's rows: each scene's CPU f64 reference, then its run on
//! every driver, with a reproducer for each failure.

use std::path::{Path, PathBuf};

use glint::cpu;
use glint::drivers::repro::Size;
use glint::drivers::Verdict;
use glint::raster::Image;
use glint::scene::Scene;

use super::folder::folder;
use super::identify::Driver;
use super::plan::{Scenes, Source};
use super::table::{Cell, Row};
use super::Run;
use crate::cli::{progress, scene_name};

impl Run<'_> {
    /// Each scene (of `paths`) on each driver: its row of cells.
    /// `load_repro` is each driver's load reproducer, where it has one;
    /// the run's reproducers go into `staging_dir`, where `repro_root`
    /// will hold them.
    pub(super) fn rows(
        &self,
        scenes: &Scenes,
        drivers: &[Driver],
        load_repro: &[Option<PathBuf>],
        staging_dir: &Path,
        repro_root: &Path,
    ) -> anyhow::Result<Vec<Row>> {
        let bar = progress::bar((scenes.paths.len() * drivers.len()) as u64, "drivers");
        let mut rows = Vec::new();
        let named = scenes.paths.iter().zip(&scenes.sources);
        for ((path, source), name) in named.zip(row_names(&scenes.paths)) {
            let shown = glint::printable::text(&name);
            // Past the budget no scene is read or written: its row is "not run".
            let made;
            let scene = match (source, &scenes.generated) {
                _ if self.past_budget() => None,
                (Source::Read(s), _) => Some(&**s),
                (Source::Generated(i), Some(g)) => {
                    bar.set_message(format!("{shown}: writing it"));
                    made = g.scene(*i, &scenes.size)?;
                    Some(&made)
                }
                (Source::Generated(_), None) => anyhow::bail!("{shown}: no folder for it"),
            };
            bar.set_message(format!("{shown}: the CPU f64 reference"));
            let reference = match scene {
                Some(scene) => Some((scene, reference(scene, self.args.device.accel)?)),
                None => None,
            };
            let mut cells = Vec::new();
            for (d, load_repro) in drivers.iter().zip(load_repro) {
                let driver = glint::printable::text(&d.name);
                bar.set_message(format!("{shown} on {driver}"));
                let cell = match (&d.identity, &reference) {
                    (Err(v), Some(_)) => Cell {
                        verdict: v.clone(),
                        repro: load_repro.clone(),
                        explained: None,
                    },
                    (Ok(identity), Some((scene, reference))) if !self.past_budget() => {
                        let (verdict, image, stderr) = self.scene(
                            d,
                            path,
                            scene,
                            reference,
                            "run",
                            Size::of(scene),
                            self.deadline,
                        )?;
                        let mut explained = None;
                        let repro = if verdict.is_failure() {
                            let rel = Path::new(&folder(&d.name, &d.icd))
                                .join(folder(&scene_name(path), path));
                            bar.set_message(format!("{shown} on {driver}: reproducer"));
                            explained = self.reproducer(
                                d,
                                identity,
                                path,
                                scene,
                                &verdict,
                                image,
                                reference,
                                stderr,
                                &staging_dir.join(&rel),
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
                                self.args.budget.unwrap_or_default()
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
        Ok(rows)
    }
}

/// The CPU f64 reference of `scene`.
pub(super) fn reference(scene: &Scene, accel: glint::accel::Accel) -> anyhow::Result<Image> {
    Ok(cpu::reference(scene, accel)?)
}

/// Each scene's row: its stem, or the path as given where two scenes share
/// a stem (a/s.toml and b/s.toml were two rows "s").
fn row_names(paths: &[PathBuf]) -> Vec<String> {
    let stems: Vec<String> = paths.iter().map(|p| scene_name(p)).collect();
    // Counted once: a run of --generated 100000 compared every pair.
    let mut count = std::collections::HashMap::<&str, usize>::new();
    for s in &stems {
        *count.entry(s).or_default() += 1;
    }
    paths
        .iter()
        .zip(&stems)
        .map(|(p, stem)| {
            if count[stem.as_str()] > 1 {
                p.display().to_string()
            } else {
                stem.clone()
            }
        })
        .collect()
}
