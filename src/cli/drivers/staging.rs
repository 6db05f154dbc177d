//! Where a run's reproducers are written: a folder of this run's beside
//! repro/, which replaces repro/ at the end, and the checks that repro/ is
//! this command's to replace.

use std::path::{Path, PathBuf};

use anyhow::Context;

/// The file that marks a folder of reproducers as this command's, so that
/// a later run replaces it and never a folder of the user's.
const MARK: &str = ".glint-drivers";

/// Refuses to replace `root` (repro/ under -o) where it is not a folder
/// this command made, or where it holds an input of this run.
pub(super) fn check_reproducers(root: &Path, inputs: &[PathBuf]) -> anyhow::Result<()> {
    let resolved = |p: &Path| std::fs::canonicalize(p).unwrap_or_else(|_| p.to_owned());
    if root.exists() {
        anyhow::ensure!(
            root.join(MARK).is_file(),
            "{}: the folder exists and is not one `glint drivers` wrote; remove it or choose another -o",
            glint::printable::path(root)
        );
        let root_r = resolved(root);
        if let Some(input) = inputs.iter().find(|i| resolved(i).starts_with(&root_r)) {
            anyhow::bail!(
                "{} is inside {}, which this run replaces; copy it elsewhere or choose another -o",
                glint::printable::path(input),
                glint::printable::path(root)
            );
        }
    }
    Ok(())
}

/// The folder this run's reproducers are written into, beside repro/
/// under -o, until `replace` makes it repro/; removed if the run ends
/// before that, by an error (drop) or a signal (`interrupt`).
pub(super) struct Staging {
    pub(super) dir: PathBuf,
    replaced: bool,
}

impl Staging {
    pub(super) fn new(output: &Path) -> anyhow::Result<Self> {
        let dir = output.join(format!(".glint-drivers-{}.new", std::process::id()));
        std::fs::create_dir_all(&dir)
            .with_context(|| format!("cannot create {}", glint::printable::path(&dir)))?;
        crate::cli::interrupt::folder_made(&dir);
        std::fs::write(
            dir.join(MARK),
            "reproducers written by glint drivers; replaced by its next run\n",
        )
        .with_context(|| format!("cannot write in {}", glint::printable::path(&dir)))?;
        Ok(Self {
            dir,
            replaced: false,
        })
    }

    /// Puts this run's reproducers at `root` in place of the last run's,
    /// by two renames: the last run's aside, then these in.
    pub(super) fn replace(mut self, root: &Path) -> anyhow::Result<()> {
        let old = self.dir.with_extension("old");
        if root.exists() {
            std::fs::rename(root, &old)
                .with_context(|| format!("cannot move {} aside", glint::printable::path(root)))?;
        }
        std::fs::rename(&self.dir, root)
            .with_context(|| format!("cannot make {}", glint::printable::path(root)))?;
        self.replaced = true;
        crate::cli::interrupt::folder_kept(&self.dir);
        if old.exists() {
            std::fs::remove_dir_all(&old)
                .with_context(|| format!("cannot remove {}", glint::printable::path(&old)))?;
        }
        Ok(())
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        if !self.replaced {
            let _ = std::fs::remove_dir_all(&self.dir);
            crate::cli::interrupt::folder_kept(&self.dir);
        }
    }
}
