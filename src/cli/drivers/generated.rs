//! `glint drivers --generated N`: generated scenes (`glint fuzz`'s random
//! set) among the scenes every driver is held to, written under -o so that
//! their reproducers can name them: a GraphicsFuzz for ray-tracing compute
//! shaders (issue 56).

use std::path::{Path, PathBuf};

use anyhow::Context;

/// Writes `n` generated scenes of `seed` into `output`/generated/ (the
/// last run's there removed first); their paths.
pub fn write(output: &Path, n: usize, seed: u64) -> anyhow::Result<Vec<PathBuf>> {
    let dir = output.join("generated");
    if dir.join(MARK).is_file() {
        std::fs::remove_dir_all(&dir)
            .with_context(|| format!("cannot remove {}", glint::printable::path(&dir)))?;
    }
    anyhow::ensure!(
        !dir.exists(),
        "{}: the folder exists and is not one `glint drivers --generated` wrote; remove it or choose another -o",
        glint::printable::path(&dir)
    );
    std::fs::create_dir_all(&dir)
        .with_context(|| format!("cannot create {}", glint::printable::path(&dir)))?;
    std::fs::write(
        dir.join(MARK),
        "scenes written by glint drivers --generated\n",
    )
    .with_context(|| format!("cannot write in {}", glint::printable::path(&dir)))?;
    (0..n as u64)
        .map(|i| {
            let spec =
                glint::generate::space::random(glint::generate::case_seed(seed, i), 40, 16, 12);
            spec.scene()
                .write(&dir, &format!("case-{seed}-{i}.toml"))
                .with_context(|| format!("cannot write into {}", glint::printable::path(&dir)))
        })
        .collect()
}

/// The file that marks the folder as this option's.
const MARK: &str = ".glint-generated";
