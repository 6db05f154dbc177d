//! What `glint fuzz` and `glint drivers --generated` write and leave
//! behind: whole scene files (never half of one, never a user's file
//! deleted), no temporary folder after a signal, and one clear error for a
//! count or a time that no run can take.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::assert_user_error;

/// Sends `signal` to `child` (from Rust, not kill(1): a minimal Debian
/// has no procps).
fn signal(child: &std::process::Child, signal: libc::c_int) {
    let pid = libc::pid_t::try_from(child.id()).unwrap();
    // SAFETY: kill(2) on our own child's pid, not yet waited for.
    assert_eq!(unsafe { libc::kill(pid, signal) }, 0);
}

/// Waits (up to a minute) until `ready` holds or `child` ends; whether it
/// held.
fn wait_for(child: &mut std::process::Child, ready: impl Fn() -> bool) -> bool {
    let start = Instant::now();
    while start.elapsed() < Duration::from_secs(60) {
        if ready() {
            return true;
        }
        if child.try_wait().unwrap().is_some() {
            return false;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    false
}

fn entries(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|r| r.flatten().map(|e| e.path()).collect())
        .unwrap_or_default();
    v.sort();
    v
}

fn tomls(dir: &Path) -> Vec<PathBuf> {
    entries(dir)
        .into_iter()
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect()
}

/// `--minutes` past what a clock holds panicked (exit 101, a backtrace);
/// `--objects` past what a scene may hold allocated 16 GB and aborted.
#[test]
fn fuzz_refuses_counts_and_times_no_run_can_take() {
    for (flag, value, words) in [
        ("--minutes", "1e300", "--minutes 1e300"),
        ("--minutes=-1", "", "--minutes -1"),
        ("--minutes=NaN", "", "--minutes NaN"),
        ("--objects", "4294967296", "--objects 4294967296"),
        ("--objects", "10000000", "at most 100000 objects"),
    ] {
        let mut args = vec!["fuzz", "--backend", "cpu", flag];
        if !value.is_empty() {
            args.push(value);
        }
        let o = common::glint(&args);
        assert_user_error(&o, words);
        assert_eq!(String::from_utf8_lossy(&o.stderr).trim().lines().count(), 1);
    }
}

/// `--dump --json` printed text; it prints one JSON object naming each
/// scene written, and the folder gets the outputs' checks (a file in its
/// place is one error).
#[test]
fn fuzz_dump_prints_json_and_checks_its_folder() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("d");
    let run = common::cmd()
        .args([
            "fuzz",
            "--backend",
            "cpu",
            "--cases",
            "3",
            "--json",
            "--dump",
        ])
        .arg(&out)
        .assert()
        .success();
    let json = common::json_of(&run);
    let scenes = json["scenes"].as_array().unwrap();
    assert_eq!(scenes.len(), 3);
    for s in scenes {
        assert!(Path::new(s.as_str().unwrap()).is_file(), "{s}");
    }
    assert_eq!(tomls(&out).len(), 3);
    let file = dir.path().join("a-file");
    std::fs::write(&file, "mine").unwrap();
    let o = common::glint(&[
        "fuzz",
        "--backend",
        "cpu",
        "--cases",
        "1",
        "--dump",
        file.join("sub").to_str().unwrap(),
    ]);
    assert_user_error(&o, "a-file");
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "mine");
}

/// A signal during `--dump` leaves each scene whole: the new one or the
/// last run's, never one cut at a write's boundary (each was a plain
/// `fs::write`, and a SIGINT left a truncated scene in place of the last
/// dump's), and no temporary file.
#[test]
fn an_interrupted_dump_leaves_every_scene_whole() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("d");
    // Large scenes (megabytes each), so that a signal meets a write.
    let dump = |objects: &str| {
        let mut c = Command::new(env!("CARGO_BIN_EXE_glint"));
        c.args(["fuzz", "--backend", "cpu", "--seed", "7", "--cases", "6"])
            .args(["--objects", objects, "--dump"])
            .arg(&out)
            .stdout(Stdio::null())
            .stderr(Stdio::piped());
        c
    };
    assert!(dump("30000").status().unwrap().success());
    let before: Vec<(PathBuf, String)> = tomls(&out)
        .into_iter()
        .map(|p| {
            let t = std::fs::read_to_string(&p).unwrap();
            (p, t)
        })
        .collect();
    assert_eq!(before.len(), 6);
    let mut interrupted = 0;
    for delay_ms in [0u64, 5, 20, 60] {
        let mut child = dump("60000").spawn().unwrap();
        std::thread::sleep(Duration::from_millis(delay_ms));
        let temp = || {
            entries(&out)
                .iter()
                .any(|p| p.to_string_lossy().ends_with(".tmp"))
        };
        if wait_for(&mut child, temp) {
            signal(&child, libc::SIGINT);
            interrupted += 1;
        }
        let o = child.wait_with_output().unwrap();
        assert!(
            o.status.success() || o.status.code() == Some(130),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        for (path, old) in &before {
            let now = std::fs::read_to_string(path).unwrap();
            assert!(
                now == *old || now.parse::<toml::Table>().is_ok(),
                "{}: neither the old scene nor a whole new one ({} bytes)",
                path.display(),
                now.len()
            );
        }
        let left: Vec<_> = entries(&out)
            .into_iter()
            .filter(|p| p.to_string_lossy().ends_with(".tmp"))
            .collect();
        assert!(left.is_empty(), "temporary files left: {left:?}");
    }
    if interrupted == 0 {
        common::skip(
            "an_interrupted_dump_leaves_every_scene_whole",
            "no signal met a write",
        );
    }
}

/// `glint fuzz` makes a folder for each case's files; a signal left it in
/// $TMPDIR, and a SIGKILL's stayed for ever. Now the signal removes it,
/// and the next run removes a dead run's.
#[test]
fn fuzz_leaves_no_temporary_folder() {
    let tmp = tempfile::tempdir().unwrap();
    let dead = tmp.path().join("glint-fuzz-4194305-abc");
    std::fs::create_dir(&dead).unwrap();
    std::fs::write(dead.join("generated.toml"), "x").unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_glint"))
        .args(["fuzz", "--backend", "cpu", "--minutes", "1"])
        .env("TMPDIR", tmp.path())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let prefix = format!("glint-fuzz-{}-", child.id());
    let live = || {
        entries(tmp.path()).iter().any(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            name.starts_with(&prefix)
        })
    };
    let seen = wait_for(&mut child, live);
    assert!(seen, "no case folder was made");
    signal(&child, libc::SIGINT);
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(130));
    assert_eq!(entries(tmp.path()), Vec::<PathBuf>::new(), "left behind");
}

/// `glint drivers NAMED --generated N -o out` replaced out/generated/
/// before it read NAMED, and a generated scene the user had edited there
/// was deleted; a count past any run wrote every scene up front (50,000
/// files before the first probe, whatever --budget said).
#[cfg(feature = "gpu")]
mod drivers {
    use super::*;

    fn lavapipe() -> PathBuf {
        std::fs::read_dir("/usr/share/vulkan/icd.d")
            .unwrap()
            .filter_map(|e| e.ok().map(|e| e.path()))
            .find(|p| {
                p.file_name()
                    .is_some_and(|n| n.to_string_lossy().starts_with("lvp_icd"))
            })
            .expect("lavapipe's ICD file")
    }

    fn drivers(out: &Path, extra: &[&str]) -> std::process::Output {
        let icd = lavapipe();
        let mut args = vec![
            "drivers",
            "--quick",
            "--icd",
            icd.to_str().unwrap(),
            "--only",
        ];
        args.extend_from_slice(extra);
        args.extend(["-o", out.to_str().unwrap()]);
        common::glint(&args)
    }

    #[test]
    fn a_named_scene_inside_the_generated_folder_is_refused_and_kept() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let generated = out.join("generated");
        std::fs::create_dir_all(&generated).unwrap();
        std::fs::write(generated.join(".glint-generated"), "").unwrap();
        let mine = generated.join("case-56-1.toml");
        let text = std::fs::read_to_string(common::repo().join("scenes/seed-fig3.toml")).unwrap();
        std::fs::write(&mine, &text).unwrap();
        let o = drivers(&out, &[mine.to_str().unwrap(), "--generated", "1"]);
        assert_user_error(&o, "which --generated replaces");
        assert_eq!(std::fs::read_to_string(&mine).unwrap(), text);
        // Named by another spelling (through `..`): the same file.
        let other = out.join("generated/../generated/case-56-1.toml");
        let o = drivers(&out, &[other.to_str().unwrap(), "--generated", "1"]);
        assert_user_error(&o, "which --generated replaces");
        assert!(mine.is_file());
    }

    #[test]
    fn generated_scenes_are_written_as_they_run() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let o = drivers(&out, &["--generated", "100001"]);
        assert_user_error(&o, "at most 100000");
        assert!(!out.join("generated").exists());
        // Past the budget at once: no row runs, and no scene is written.
        let o = drivers(&out, &["--generated", "500", "--budget", "1e-6"]);
        assert_user_error(&o, "500 of 500 cells were not run");
        assert_eq!(tomls(&out.join("generated")), Vec::<PathBuf>::new());
        let json: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.join("drivers.json")).unwrap()).unwrap();
        assert_eq!(json["rows"].as_array().unwrap().len(), 500);
    }
}
