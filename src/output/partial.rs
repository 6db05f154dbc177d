//! Temporary files of writes in progress. Each is named `.glint-<pid>-*.tmp`
//! beside its target and listed here until it is renamed over the target
//! or dropped. On SIGINT or SIGTERM the binary removes the listed files
//! (`remove_in_progress`) before it exits. SIGKILL leaves one behind; a
//! later write into the same directory removes it, since its pid names a
//! process that no longer runs (`remove_stale`).

use std::path::{Path, PathBuf};
use std::sync::Mutex;

static IN_PROGRESS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// The prefix of this process's temporary files.
pub fn prefix() -> String {
    format!(".glint-{}-", std::process::id())
}

pub fn register(path: &Path) {
    if let Ok(mut v) = IN_PROGRESS.lock() {
        v.push(path.to_owned());
    }
}

pub fn unregister(path: &Path) {
    if let Ok(mut v) = IN_PROGRESS.lock() {
        v.retain(|p| p != path);
    }
}

/// Removes every temporary file of a write in progress (from a signal
/// handler's thread: cli/signals.rs runs it outside the signal context).
pub fn remove_in_progress() {
    if let Ok(v) = IN_PROGRESS.lock() {
        for p in v.iter() {
            let _ = std::fs::remove_file(p);
        }
    }
}

/// Removes `.glint-<pid>-*.tmp` files in `dir` whose process is gone.
/// Only files named by glint's own pattern, with a pid that no process
/// has, are touched.
pub fn remove_stale(dir: &Path) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name();
        let Some(pid) = stale_pid(&name.to_string_lossy()) else {
            continue;
        };
        if pid != std::process::id() && !alive(pid) {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

/// The pid in a `.glint-<pid>-<random>.tmp` name.
fn stale_pid(name: &str) -> Option<u32> {
    let rest = name.strip_prefix(".glint-")?.strip_suffix(".tmp")?;
    let (pid, random) = rest.split_once('-')?;
    if random.is_empty() {
        return None;
    }
    pid.parse().ok()
}

/// Whether process `pid` runs (a run's leftovers are removed only where
/// it does not).
#[cfg(target_os = "linux")]
pub fn alive(pid: u32) -> bool {
    Path::new(&format!("/proc/{pid}")).exists()
}

/// Without /proc, every pid counts as alive: nothing is removed.
#[cfg(not(target_os = "linux"))]
pub fn alive(_pid: u32) -> bool {
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_glints_own_names_with_a_pid_are_stale_candidates() {
        assert_eq!(stale_pid(".glint-123-abc.tmp"), Some(123));
        assert_eq!(stale_pid(".glint-abc.tmp"), None);
        assert_eq!(stale_pid(".glint-123-.tmp"), None);
        assert_eq!(stale_pid("glint-123-abc.tmp"), None);
        assert_eq!(stale_pid(".glint-123-abc.png"), None);
    }

    #[test]
    fn stale_files_of_dead_processes_go_and_others_stay() {
        let dir = tempfile::tempdir().unwrap();
        // pid_max on Linux is at most 2^22: this pid runs nowhere.
        let dead = dir.path().join(".glint-4194305-abc.tmp");
        let mine = dir.path().join(format!("{}x.tmp", prefix()));
        let other = dir.path().join(".glint-notes.tmp");
        for p in [&dead, &mine, &other] {
            std::fs::write(p, b"x").unwrap();
        }
        remove_stale(dir.path());
        assert!(!dead.exists());
        assert!(mine.exists() && other.exists());
    }
}
