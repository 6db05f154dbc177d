//! `glint drivers --generated N`: generated scenes (`glint fuzz`'s random
//! set) among the scenes every driver is held to, written under -o so that
//! their reproducers can name them: a GraphicsFuzz for ray-tracing compute
//! shaders (docs/drivers.md). Each scene is made as its row starts, so a
//! run past its --budget writes no scene it does not run.

use std::path::{Path, PathBuf};

use anyhow::Context;

use glint::scene::{Overrides, Scene};

/// The most generated scenes one run takes: past a day of probes at a
/// second each, where the paths alone stay a few megabytes.
pub const MAX_GENERATED: usize = 100_000;

/// The folder of a run's generated scenes, and their seed.
pub struct Generated {
    dir: PathBuf,
    seed: u64,
}

impl Generated {
    /// The folder `output`/generated/ for `n` scenes of `seed`, checked:
    /// `named` (the scenes named on the command line, each read already,
    /// with the files they read) must not be inside it, since the last
    /// run's folder is replaced. Nothing is touched yet.
    pub fn new(output: &Path, n: usize, seed: u64, named: &[PathBuf]) -> anyhow::Result<Self> {
        anyhow::ensure!(
            n <= MAX_GENERATED,
            "--generated {n}: a run takes at most {MAX_GENERATED} generated scenes"
        );
        let dir = output.join("generated");
        if let Ok(inside) = dir.canonicalize() {
            for f in named {
                if f.canonicalize().is_ok_and(|f| f.starts_with(&inside)) {
                    anyhow::bail!(
                        "{}: is inside {}, which --generated replaces with new scenes; copy it elsewhere or choose another -o",
                        glint::printable::path(f),
                        glint::printable::path(&dir)
                    );
                }
            }
        }
        Ok(Self { dir, seed })
    }

    /// Replaces the last run's folder (the one this option marked) with an
    /// empty one.
    pub fn make_folder(&self) -> anyhow::Result<()> {
        let dir = &self.dir;
        if dir.join(MARK).is_file() {
            std::fs::remove_dir_all(dir)
                .with_context(|| format!("cannot remove {}", glint::printable::path(dir)))?;
        }
        anyhow::ensure!(
            !dir.exists(),
            "{}: the folder exists and is not one `glint drivers --generated` wrote; remove it or choose another -o",
            glint::printable::path(dir)
        );
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create {}", glint::printable::path(dir)))?;
        std::fs::write(
            dir.join(MARK),
            "scenes written by glint drivers --generated\n",
        )
        .with_context(|| format!("cannot write in {}", glint::printable::path(dir)))
    }

    /// Where scene `i` is written.
    pub fn path(&self, i: u64) -> PathBuf {
        self.dir.join(self.name(i))
    }

    /// Scene `i`'s file name.
    fn name(&self, i: u64) -> String {
        format!("case-{}-{i}.toml", self.seed)
    }

    /// Writes scene `i` and reads it back at `size`.
    pub fn scene(&self, i: u64, size: &Overrides) -> anyhow::Result<Scene> {
        let spec =
            glint::generate::space::random(glint::generate::case_seed(self.seed, i), 40, 16, 12);
        let path = spec.scene().write(&self.dir, &self.name(i))?;
        let scene = Scene::load(&path, size)?;
        glint::cpu::bound::check(&scene)?;
        Ok(scene)
    }
}

/// The file that marks the folder as this option's.
const MARK: &str = ".glint-generated";
