//! What a run that SIGINT or SIGTERM stops must not leave behind: its
//! child processes and its temporary folders (a child `glint
//! driver-probe` kept running, re-parented to init, and a 4.7 MB
//! temporary folder stayed). A command lists them here while they exist;
//! the binary's signal handler calls `clean_up` before it exits.

use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

/// What an interrupted run removes, and whether the run is stopping: one
/// lock, so that a child or a folder is either made and listed before the
/// clean-up looks, or not made at all (a probe spawned while the signal
/// thread cleaned up outlived glint and wrote its folder back; a temporary
/// folder made while the signal thread exited stayed).
struct Listed {
    children: Vec<u32>,
    folders: Vec<PathBuf>,
    stopping: bool,
}

static LISTED: Mutex<Listed> = Mutex::new(Listed {
    children: Vec::new(),
    folders: Vec::new(),
    stopping: false,
});

/// The list, even where a thread panicked holding it: the clean-up must
/// still run.
fn listed() -> MutexGuard<'static, Listed> {
    LISTED.lock().unwrap_or_else(|e| e.into_inner())
}

/// The list, to add to. Once the run is stopping, the signal thread is
/// ending the process: the caller waits for that rather than make what no
/// clean-up would remove, or print a second error line.
fn listed_to_add_to() -> MutexGuard<'static, Listed> {
    let listed = listed();
    if listed.stopping {
        drop(listed);
        loop {
            std::thread::park();
        }
    }
    listed
}

/// Starts `c` and lists it for an interrupted run to kill; once the run is
/// stopping, never returns.
pub fn spawn(c: &mut std::process::Command) -> std::io::Result<std::process::Child> {
    let mut listed = listed_to_add_to();
    let child = c.spawn()?;
    listed.children.push(child.id());
    Ok(child)
}

/// The child `pid` was waited for: it is no longer this run's to kill.
pub fn child_ended(pid: u32) {
    listed().children.retain(|p| *p != pid);
}

/// Makes a folder (`make` returns it) and lists it for an interrupted run
/// to remove, with what is in it; once the run is stopping, never returns.
pub fn make_folder<T: AsRef<Path>>(
    make: impl FnOnce() -> std::io::Result<T>,
) -> std::io::Result<T> {
    let mut listed = listed_to_add_to();
    let folder = make()?;
    listed.folders.push(folder.as_ref().to_owned());
    Ok(folder)
}

/// Creates `dir` and the folders above it that are missing, inside a
/// listed folder: before the clean-up removes that folder, or not at all
/// (a probe's folder made after it made the temporary folder again, and
/// it stayed); once the run is stopping, never returns.
pub fn create_dir_all(dir: &Path) -> std::io::Result<()> {
    let _listed = listed_to_add_to();
    std::fs::create_dir_all(dir)
}

/// The folder was removed, or is now an output: it stays.
pub fn folder_kept(path: &Path) {
    listed().folders.retain(|p| p != path);
}

/// Stops new children and folders, kills and reaps the listed children,
/// then removes the listed folders (the children first, so that none
/// writes into a folder being removed). Runs on the signal handler's
/// thread (cli/signals.rs, outside the signal context); once it has run,
/// `spawn` and `make_folder` make nothing.
pub fn clean_up() {
    let mut listed = listed();
    listed.stopping = true;
    for &pid in listed.children.iter() {
        let Ok(pid) = libc::pid_t::try_from(pid) else {
            continue;
        };
        // SAFETY: signals a process this run started and has not yet
        // reaped (its pid cannot have been reused), then reaps it.
        unsafe {
            libc::kill(pid, libc::SIGKILL);
            libc::waitpid(pid, std::ptr::null_mut(), 0);
        }
    }
    listed.children.clear();
    for f in listed.folders.drain(..) {
        let _ = std::fs::remove_dir_all(f);
    }
}

/// A run's temporary folder, `$TMPDIR/glint-<what>-<pid>-XXXXXX`: listed
/// for an interrupted run to remove, and removed when dropped. Those of
/// the same `what` that a run left behind and no longer runs (a SIGKILL's)
/// are removed as the first is made: a signal that no handler sees leaves
/// one folder until the next run, not for ever.
pub struct TempFolder(Option<tempfile::TempDir>);

impl TempFolder {
    /// Makes one for `what` (letters and '-': `fuzz`, `drivers`); once
    /// the run is stopping, never returns.
    pub fn new(what: &str) -> std::io::Result<Self> {
        remove_stale_folders(what);
        let prefix = format!("{}{}-", folder_stem(what), std::process::id());
        let dir = make_folder(|| tempfile::Builder::new().prefix(&prefix).tempdir())?;
        Ok(Self(Some(dir)))
    }

    /// Where it is.
    pub fn path(&self) -> &Path {
        self.0.as_ref().expect("held until dropped").path()
    }
}

impl Drop for TempFolder {
    fn drop(&mut self) {
        if let Some(dir) = self.0.take() {
            let path = dir.path().to_owned();
            // Removed, then unlisted: a signal between finds it listed.
            drop(dir);
            folder_kept(&path);
        }
    }
}

/// The start of a `what` folder's name, before its pid.
fn folder_stem(what: &str) -> String {
    format!("glint-{what}-")
}

/// Removes the `what` folders in the system's temporary folder whose run
/// no longer runs: once a process for each `what` (`glint fuzz` makes a
/// folder for every scene it checks, and a killed run's folders are gone
/// after the first).
fn remove_stale_folders(what: &str) {
    static SWEPT: Mutex<Vec<String>> = Mutex::new(Vec::new());
    {
        let mut swept = SWEPT.lock().unwrap_or_else(|e| e.into_inner());
        if swept.iter().any(|w| w == what) {
            return;
        }
        swept.push(what.to_owned());
    }
    let stem = folder_stem(what);
    let Ok(entries) = std::fs::read_dir(std::env::temp_dir()) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let pid = name
            .strip_prefix(&stem)
            .and_then(|rest| rest.split_once('-'))
            .and_then(|(pid, _)| pid.parse::<u32>().ok());
        if let Some(pid) = pid {
            if pid != std::process::id() && !super::alive(pid) && e.path().is_dir() {
                let _ = std::fs::remove_dir_all(e.path());
            }
        }
    }
}
