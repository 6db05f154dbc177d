//! `render --aov NAME[=FILE]`: a render's AOVs as files (docs/commands.md,
//! AOVs), each row of the AOV table (`glint::aov::AOVS`) written as its
//! channels say: one channel as a PFM of one channel (`Pf`) or an EXR of
//! channel `Y`, two or three as a PFM or EXR of three (a third channel of
//! 0 after two). Whole numbers (primitive ids, ray counts) are written as
//! the floats that hold them exactly.

use std::path::{Path, PathBuf};

use glint::aov::{Aov, AovType, Values};
use glint::output::Outputs;
use glint::raster::io::{self, Format};
use glint::raster::plane::{stage_plane, Plane};
use glint::raster::Image;
use glint::scene::Scene;

/// The largest whole number an f32 holds exactly, with every one below it.
const EXACT: f64 = 16_777_216.0;

/// The AOVs a render writes, and where.
pub struct AovFiles {
    /// Each AOV asked for, with its file.
    pub files: Vec<(&'static AovType, PathBuf)>,
    /// Whether one of them takes `-o`'s file, so that the colour is not
    /// written.
    pub takes_output: bool,
}

impl AovFiles {
    /// The `--aov` words: `NAME` writes to `output` in place of the colour
    /// (at most one), `NAME=FILE` to FILE beside it. Each file a .exr or
    /// .pfm, each AOV once, and no two to one file.
    pub fn parse(words: &[String], output: &Path) -> anyhow::Result<Self> {
        let mut files: Vec<(&'static AovType, PathBuf)> = Vec::new();
        let mut takes_output = false;
        for word in words {
            let (name, path) = match word.split_once('=') {
                Some((name, file)) => (name, PathBuf::from(file)),
                None => {
                    anyhow::ensure!(
                        !takes_output,
                        "--aov {word}: one AOV takes -o's file; give the others as NAME=FILE"
                    );
                    takes_output = true;
                    (word.as_str(), output.to_owned())
                }
            };
            let Some(t) = glint::aov::named(name) else {
                anyhow::bail!(
                    "--aov {}: no such AOV (the AOVs: {})",
                    glint::printable::text(name),
                    glint::aov::names().collect::<Vec<_>>().join(", ")
                );
            };
            anyhow::ensure!(
                !files.iter().any(|(f, _)| f.name == t.name),
                "--aov {name} is asked for twice"
            );
            anyhow::ensure!(
                matches!(io::Format::of_output(&path)?, Format::Exr | Format::Pfm),
                "--aov {name}: {} is a PNG, and an AOV's values are not colours: write it as .exr or .pfm",
                glint::printable::path(&path)
            );
            files.push((t, path));
        }
        // Two outputs to one file, the colour's included where it is written.
        for (i, (t, path)) in files.iter().enumerate() {
            let twice = files[..i].iter().any(|(_, p)| p == path);
            let colour = !takes_output && path == output;
            anyhow::ensure!(
                !twice && !colour,
                "--aov {}: {} is another output's file too",
                t.name,
                glint::printable::path(path)
            );
        }
        Ok(Self {
            files,
            takes_output,
        })
    }

    /// Whether any AOV is asked for.
    pub fn any(&self) -> bool {
        !self.files.is_empty()
    }

    /// Refuses a scene whose sampling takes no AOVs.
    pub fn check(&self, scene: &Scene) -> anyhow::Result<()> {
        if let Some(why) = self
            .any()
            .then(|| glint::sampling::aovs_refused(scene))
            .flatten()
        {
            anyhow::bail!("--aov: {why}");
        }
        Ok(())
    }

    /// Stages each AOV's file from the pixels' records `aovs` of a
    /// `width` x `height` render.
    pub fn stage(
        &self,
        outputs: &mut Outputs,
        aovs: &[Aov],
        (width, height): (u32, u32),
    ) -> anyhow::Result<()> {
        for (t, path) in &self.files {
            let channels: Vec<[f64; 3]> = aovs.iter().map(|a| (t.read)(a)).collect();
            if t.values != Values::Float {
                if let Some(v) = channels.iter().flatten().find(|v| v.abs() > EXACT) {
                    anyhow::bail!(
                        "--aov {}: {v} is past the whole numbers a float file holds exactly (2^24)",
                        t.name
                    );
                }
            }
            if t.channels == 1 {
                let plane = Plane {
                    width,
                    height,
                    values: channels.iter().map(|c| c[0] as f32).collect(),
                };
                stage_plane(outputs, path, &plane)?;
            } else {
                let pixels = channels.iter().map(|c| c.map(|v| v as f32)).collect();
                let image = Image::new(width, height, pixels);
                io::stage(outputs, path, &image, false)?;
            }
        }
        Ok(())
    }
}
