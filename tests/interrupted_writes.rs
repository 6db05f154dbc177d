//! An output is whole or absent: SIGINT or SIGTERM during a write removes
//! the temporary file, and a temporary file that a killed run left behind
//! is removed by the next write into its directory.

#![cfg(feature = "gpu")]

mod common;

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const SCENE: &str = "[image]\nwidth = 4096\nheight = 4096\n[render]\nmax_depth = 1\n\
    [camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nvfov = 40\n\
    [materials.m]\ndiffuse = [0.5, 0.5, 0.5]\n\
    [[spheres]]\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"m\"\n";

fn temp_files(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect()
}

/// Starts a CPU render of a 4096² PFM (192 MiB) and sends `signal` while
/// its temporary file exists. Returns false where the write ended before
/// the signal could be sent.
fn interrupt_a_write(signal: libc::c_int) -> bool {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("big.toml");
    std::fs::write(&scene, SCENE).unwrap();
    let out = dir.path().join("big.pfm");
    let mut child = Command::new(env!("CARGO_BIN_EXE_glint"))
        .args(["render", scene.to_str().unwrap(), "--backend", "cpu", "-o"])
        .arg(&out)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let mut sent = false;
    while start.elapsed() < Duration::from_secs(120) {
        if child.try_wait().unwrap().is_some() {
            break;
        }
        if !temp_files(dir.path()).is_empty() {
            // From Rust, not kill(1): a minimal Debian has no procps.
            let pid = libc::pid_t::try_from(child.id()).unwrap();
            // SAFETY: kill(2) on our own child's pid, which it still is
            // (not yet waited for); no memory is involved.
            assert_eq!(unsafe { libc::kill(pid, signal) }, 0);
            sent = true;
            break;
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    let o = child.wait_with_output().unwrap();
    if !sent {
        return false;
    }
    let err = String::from_utf8_lossy(&o.stderr);
    if o.status.success() {
        // The rename won the race: the output is whole.
        assert!(out.exists());
    } else {
        assert_eq!(o.status.code(), Some(130), "{err}");
        assert!(err.contains("interrupted"), "{err}");
        assert!(!out.exists(), "a partial output was left");
    }
    assert_eq!(
        temp_files(dir.path()),
        Vec::<String>::new(),
        "temp file left"
    );
    true
}

#[test]
fn sigint_and_sigterm_during_a_write_leave_no_temporary_file() {
    for signal in [libc::SIGINT, libc::SIGTERM] {
        // A machine fast enough to write 192 MiB between two polls gets
        // more tries; every try that sent the signal was checked.
        let tried = (0..5).any(|_| interrupt_a_write(signal));
        assert!(tried, "signal {signal}: the write never outlasted a poll");
    }
}

#[test]
fn a_killed_runs_temporary_file_is_removed_by_the_next_write() {
    let dir = tempfile::tempdir().unwrap();
    // As SIGKILL would leave it: a pid that runs nowhere (pid_max <= 2^22).
    let stale = dir.path().join(".glint-4194305-a1b2c3.tmp");
    std::fs::write(&stale, b"half an image").unwrap();
    let unrelated = dir.path().join("notes.tmp");
    std::fs::write(&unrelated, b"mine").unwrap();
    let out = dir.path().join("x.png");
    let o = common::small_cpu_render(&out, &[]);
    assert!(o.status.success());
    assert!(!stale.exists(), "the stale temporary file is still there");
    assert!(unrelated.exists());
    assert!(out.exists());
}
