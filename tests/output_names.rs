//! Outputs named the ways a shell names them (docs/guarantees.md,
//! Outputs): an open descriptor (`/dev/stdout`, `/dev/fd/N`) is written
//! into where the shell pointed it, two spellings of one file are one
//! output, and a name that cannot be a file, or a folder that cannot be
//! one, is refused before any work.

mod common;

use std::fs::File;
use std::path::Path;
use std::process::{Command, Output, Stdio};

use common::repo;

fn glint() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_glint"));
    c.env("GLINT_VALIDATION", "1");
    c
}

/// A small CPU render of seed-fig3 with `extra` arguments, in `dir`.
fn render(dir: &Path, extra: &[&str], stdout: Stdio) -> Output {
    glint()
        .current_dir(dir)
        .arg("render")
        .arg(repo().join("scenes/seed-fig3.toml"))
        .args(["--backend", "cpu", "--width", "16", "--height", "12"])
        .args(extra)
        .stdout(stdout)
        .stderr(Stdio::piped())
        .output()
        .expect("run glint")
}

fn stats_json(bytes: &[u8]) -> serde_json::Value {
    serde_json::from_slice(bytes).unwrap_or_else(|e| {
        panic!(
            "not the statistics ({e}): {}",
            String::from_utf8_lossy(bytes)
        )
    })
}

#[test]
fn stats_into_stdout_appended_to_a_log_keep_its_lines() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("run.log");
    std::fs::write(&log, "an earlier line\n").unwrap();
    let appending = File::options().append(true).open(&log).unwrap();
    let out = render(
        dir.path(),
        &["-o", "x.png", "--stats", "/dev/stdout"],
        appending.into(),
    );
    assert!(out.status.success(), "{out:?}");
    let text = std::fs::read_to_string(&log).unwrap();
    let rest = text
        .strip_prefix("an earlier line\n")
        .unwrap_or_else(|| panic!("the log lost its line: {text}"));
    assert!(stats_json(rest.as_bytes())["rays"]["eye"].as_u64() == Some(192));
}

#[test]
fn an_image_and_stats_into_pipes() {
    let dir = tempfile::tempdir().unwrap();
    let out = render(dir.path(), &["-o", "/dev/stdout"], Stdio::piped());
    assert!(out.status.success(), "{out:?}");
    let image = image::load_from_memory_with_format(&out.stdout, image::ImageFormat::Png)
        .expect("a PNG on stdout");
    assert_eq!((image.width(), image.height()), (16, 12));

    let out = render(
        dir.path(),
        &["-o", "x.png", "--stats", "/dev/stdout"],
        Stdio::piped(),
    );
    assert!(out.status.success(), "{out:?}");
    stats_json(&out.stdout);
}

/// `/dev/fd/3` as bash's `3>&1 | cat` makes it, and as `>(cat)` names it.
#[test]
fn a_descriptor_by_number_is_written_into() {
    let dir = tempfile::tempdir().unwrap();
    let g = env!("CARGO_BIN_EXE_glint");
    let scene = repo().join("scenes/seed-fig3.toml");
    let common = format!(
        "'{g}' render '{}' --backend cpu --width 16 --height 12 -o x.png",
        scene.display()
    );
    let script = format!(
        "{common} --stats /dev/fd/3 3>&1 >/dev/null 2>&1 | cat > piped.json && \
         {common} --stats >(cat > substituted.json) >/dev/null 2>&1 && wait"
    );
    let status = Command::new("bash")
        .current_dir(dir.path())
        .args(["-c", &script])
        .status()
        .unwrap();
    assert!(status.success());
    stats_json(&std::fs::read(dir.path().join("piped.json")).unwrap());
    // The substituted process may finish after bash: wait for its file.
    let substituted = dir.path().join("substituted.json");
    for _ in 0..100 {
        if std::fs::read(&substituted)
            .is_ok_and(|b| serde_json::from_slice::<serde_json::Value>(&b).is_ok())
        {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    stats_json(&std::fs::read(&substituted).unwrap());
}

#[test]
fn one_file_spelled_two_ways_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    std::os::unix::fs::symlink(".", dir.path().join("here")).unwrap();
    let absolute = dir.path().join("x.png").display().to_string();
    for spelling in ["./x.png", absolute.as_str(), "here/x.png"] {
        let out = render(
            dir.path(),
            &["-o", spelling, "--stats", "x.png"],
            Stdio::null(),
        );
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{spelling}: {err}");
        assert!(
            err.contains("another output of this run"),
            "{spelling}: {err}"
        );
        assert!(!dir.path().join("x.png").exists(), "{spelling}");
    }
}

#[test]
fn a_name_ending_in_a_slash_is_refused_before_the_render() {
    let dir = tempfile::tempdir().unwrap();
    let out = render(dir.path(), &["-o", "out.png/"], Stdio::null());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("out.png/: is a folder's name"), "{err}");
    assert!(!err.contains("rendered"), "{err}");
}

#[cfg(feature = "gpu")]
#[test]
fn output_folders_and_run_counts_are_checked_before_any_work() {
    use std::io::Write;
    use std::path::PathBuf;
    let dir = tempfile::tempdir().unwrap();
    let file: PathBuf = dir.path().join("FILE");
    File::create(&file).unwrap().write_all(b"mine").unwrap();
    let scene = repo().join("scenes/seed-fig3.toml");
    let runs: [Vec<std::ffi::OsString>; 4] = [
        vec![
            "report".into(),
            "--quick".into(),
            "-o".into(),
            file.clone().into(),
        ],
        vec![
            "report".into(),
            "--quick".into(),
            "-o".into(),
            file.join("below").into(),
        ],
        vec![
            "shader".into(),
            "dump".into(),
            scene.clone().into(),
            "-o".into(),
            file.clone().into(),
        ],
        vec![
            "bench".into(),
            scene.into(),
            "--runs".into(),
            "4294967296".into(),
        ],
    ];
    for args in runs {
        let out = glint().current_dir(repo()).args(&args).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(
            err.contains("cannot be an output folder") || err.contains("--runs 4294967296"),
            "{args:?}: {err}"
        );
    }
    assert_eq!(std::fs::read(&file).unwrap(), b"mine");
}
