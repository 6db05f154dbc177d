//! What a run that SIGINT or SIGTERM stops must not leave behind: its
//! child processes and its temporary folders (issue 42, defect 4: a child
//! `glint driver-probe` kept running, re-parented to init, and a 4.7 MB
//! temporary folder stayed). A command lists them here while they exist;
//! the binary's signal handler calls `clean_up` before it exits.

// Only `glint drivers` (a GPU command) lists anything yet; the handler
// calls `clean_up` in every build.
#![cfg_attr(not(feature = "gpu"), allow(dead_code))]

use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The children to kill, and whether the run is stopping: one lock, so
/// that a child is either started and listed before the clean-up looks,
/// or not started at all (issue 57, defect 11: a probe spawned while the
/// signal thread cleaned up outlived glint and wrote its folder back).
static CHILDREN: Mutex<(Vec<u32>, bool)> = Mutex::new((Vec::new(), false));
static FOLDERS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Starts `c` and lists it for an interrupted run to kill; refused once the
/// run is stopping.
pub fn spawn(c: &mut std::process::Command) -> std::io::Result<std::process::Child> {
    let mut guard = CHILDREN.lock().unwrap_or_else(|e| e.into_inner());
    if guard.1 {
        return Err(std::io::Error::new(
            std::io::ErrorKind::Interrupted,
            "the run is stopping",
        ));
    }
    let child = c.spawn()?;
    guard.0.push(child.id());
    Ok(child)
}

/// The child `pid` was waited for: it is no longer this run's to kill.
pub fn child_ended(pid: u32) {
    if let Ok(mut v) = CHILDREN.lock() {
        v.0.retain(|p| *p != pid);
    }
}

/// A folder that an interrupted run removes, with what is in it.
pub fn folder_made(path: &Path) {
    if let Ok(mut v) = FOLDERS.lock() {
        v.push(path.to_owned());
    }
}

/// The folder was removed, or is now an output: it stays.
pub fn folder_kept(path: &Path) {
    if let Ok(mut v) = FOLDERS.lock() {
        v.retain(|p| p != path);
    }
}

/// Stops new children, kills and reaps the listed ones, then removes the
/// listed folders (the children first, so that none writes into a folder
/// being removed). Runs on the signal handler's thread (cli/signals.rs, outside
/// the signal context); once it has run, `spawn` starts no child.
pub fn clean_up() {
    let mut guard = CHILDREN.lock().unwrap_or_else(|e| e.into_inner());
    guard.1 = true;
    {
        for &pid in guard.0.iter() {
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
        guard.0.clear();
    }
    if let Ok(v) = FOLDERS.lock() {
        for f in v.iter() {
            let _ = std::fs::remove_dir_all(f);
        }
    }
}
