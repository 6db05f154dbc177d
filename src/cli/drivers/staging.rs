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

/// The pid in a name `<prefix><pid><suffix>`.
fn pid_in(name: &str, prefix: &str, suffix: &str) -> Option<u32> {
    name.strip_prefix(prefix)?
        .strip_suffix(suffix)?
        .parse()
        .ok()
}

/// Removes what runs killed by SIGKILL left in `dir`: their staging
/// folders (`.glint-drivers-<pid>.new` and `.old`, each holding the mark)
/// whose process no longer runs (`render` removes its own temporary files
/// the same way).
pub(super) fn remove_stale(dir: &Path) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let pid = pid_in(&name, ".glint-drivers-", ".new")
            .or_else(|| pid_in(&name, ".glint-drivers-", ".old"));
        if let Some(pid) = pid {
            let path = e.path();
            if pid != std::process::id() && !glint::output::alive(pid) && path.join(MARK).is_file()
            {
                let _ = std::fs::remove_dir_all(path);
            }
        }
    }
}

/// The bytes a folder of the probes must take before any starts: a probe
/// writes its image (230 KB at the default 160x120) and its report.
const ROOM: usize = 1 << 20;

/// Refuses a temporary folder without room for the probes' files, naming
/// it: on a full file system every probe's report and stderr were lost,
/// and every driver read "crashed".
pub(super) fn room(dir: &Path) -> anyhow::Result<()> {
    let file = dir.join(".room");
    let wrote = std::fs::write(&file, vec![0u8; ROOM]);
    let _ = std::fs::remove_file(&file);
    wrote.with_context(|| {
        format!(
            "the temporary folder {} has no room for the probes' files (set TMPDIR to a folder with a few MB free)",
            glint::printable::path(dir)
        )
    })
}

impl Staging {
    pub(super) fn new(output: &Path) -> anyhow::Result<Self> {
        remove_stale(output);
        let dir = output.join(format!(".glint-drivers-{}.new", std::process::id()));
        glint::output::interrupt::make_folder(|| std::fs::create_dir_all(&dir).map(|()| &dir))
            .with_context(|| format!("cannot create {}", glint::printable::path(&dir)))?;
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

    /// Puts this run's reproducers at `root` in place of the last run's:
    /// swapped in one step where the system can (renameat2's exchange), so
    /// that no moment is without a repro/ the tables link to;
    /// else by two renames, the last run's aside, then these in.
    pub(super) fn replace(mut self, root: &Path) -> anyhow::Result<()> {
        let old = self.dir.with_extension("old");
        if root.exists() && exchange(&self.dir, root) {
            // The last run's reproducers are where this run's were.
            self.replaced = true;
            glint::output::interrupt::folder_kept(&self.dir);
            std::fs::remove_dir_all(&self.dir)
                .with_context(|| format!("cannot remove {}", glint::printable::path(&self.dir)))?;
            return Ok(());
        }
        if root.exists() {
            std::fs::rename(root, &old)
                .with_context(|| format!("cannot move {} aside", glint::printable::path(root)))?;
        }
        std::fs::rename(&self.dir, root)
            .with_context(|| format!("cannot make {}", glint::printable::path(root)))?;
        self.replaced = true;
        glint::output::interrupt::folder_kept(&self.dir);
        if old.exists() {
            std::fs::remove_dir_all(&old)
                .with_context(|| format!("cannot remove {}", glint::printable::path(&old)))?;
        }
        Ok(())
    }
}

/// Swaps the folders `a` and `b` in one step; false where the system
/// cannot (then nothing moved).
#[cfg(target_os = "linux")]
fn exchange(a: &Path, b: &Path) -> bool {
    use std::os::unix::ffi::OsStrExt;
    let (Ok(a), Ok(b)) = (
        std::ffi::CString::new(a.as_os_str().as_bytes()),
        std::ffi::CString::new(b.as_os_str().as_bytes()),
    ) else {
        return false;
    };
    // SAFETY: two NUL-terminated paths, relative to the working folder.
    unsafe {
        libc::renameat2(
            libc::AT_FDCWD,
            a.as_ptr(),
            libc::AT_FDCWD,
            b.as_ptr(),
            libc::RENAME_EXCHANGE,
        ) == 0
    }
}

#[cfg(not(target_os = "linux"))]
fn exchange(_: &Path, _: &Path) -> bool {
    false
}

impl Drop for Staging {
    fn drop(&mut self) {
        if !self.replaced {
            let _ = std::fs::remove_dir_all(&self.dir);
            glint::output::interrupt::folder_kept(&self.dir);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The last run's reproducers are swapped out in one step, and the
    /// staging folder is gone after; a first run's are renamed in.
    #[test]
    fn replace_swaps_the_last_runs_reproducers_out() {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path().join("repro");
        for round in 0..2 {
            let s = Staging::new(dir.path()).unwrap();
            std::fs::write(s.dir.join("round"), format!("{round}")).unwrap();
            let staged = s.dir.clone();
            s.replace(&root).unwrap();
            assert_eq!(
                std::fs::read_to_string(root.join("round")).unwrap(),
                format!("{round}")
            );
            assert!(!staged.exists() && !staged.with_extension("old").exists());
        }
    }

    #[test]
    fn only_glints_staging_names_carry_a_pid() {
        assert_eq!(
            pid_in(".glint-drivers-12.new", ".glint-drivers-", ".new"),
            Some(12)
        );
        assert_eq!(
            pid_in(".glint-drivers-12.new-x", ".glint-drivers-", ".new"),
            None
        );
        assert_eq!(
            pid_in("glint-drivers-12.new", ".glint-drivers-", ".new"),
            None
        );
    }
}
