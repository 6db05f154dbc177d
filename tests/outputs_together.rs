//! Through the command line: a device node or FIFO
//! is written into, never replaced (1); `report` and `shader dump` check
//! every file they write against every input (2); a run whose second
//! output cannot be written replaces none (3). Device nodes are private
//! ones made by mknod in a temporary folder: CI runs as root; where mknod
//! is refused, those tests say so and check nothing.

#![cfg(feature = "gpu")]

mod common;

use std::os::unix::fs::FileTypeExt;
use std::path::{Path, PathBuf};

use common::{assert_ok, assert_user_error, glint, small_cpu_render};

fn seed3() -> PathBuf {
    common::repo().join("scenes/seed-fig3.toml")
}

fn null_device(dir: &Path) -> Option<PathBuf> {
    let path = dir.join("null");
    let made = std::process::Command::new("mknod")
        .arg(&path)
        .args(["c", "1", "3"])
        .status()
        .is_ok_and(|s| s.success());
    if !made {
        common::skip(
            "a device node as an output",
            "mknod is refused here (not root?)",
        );
    }
    made.then_some(path)
}

fn still_char_device(p: &Path) -> bool {
    std::fs::symlink_metadata(p).is_ok_and(|m| m.file_type().is_char_device())
}

#[test]
fn stats_and_image_into_a_device_node_leave_it_a_device_node() {
    let dir = tempfile::tempdir().unwrap();
    let Some(null) = null_device(dir.path()) else {
        return;
    };
    let out = dir.path().join("a.png");
    let o = small_cpu_render(&out, &["--stats", null.to_str().unwrap()]);
    assert_ok(&o);
    assert!(still_char_device(&null), "--stats replaced the device node");
    assert!(out.is_file());

    // -o the device itself: no extension, so written as PNG; and through a link.
    let link = dir.path().join("to-null.png");
    std::os::unix::fs::symlink(&null, &link).unwrap();
    for target in [&null, &link] {
        assert_ok(&small_cpu_render(target, &[]));
        assert!(still_char_device(&null), "-o replaced the device node");
    }
    assert!(std::fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
}

#[test]
fn a_stats_file_that_cannot_be_written_fails_before_the_image_is_replaced() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("a.png");
    std::fs::write(&out, b"old image").unwrap();
    let folder = dir.path().join("folder");
    std::fs::create_dir(&folder).unwrap();
    let missing = dir.path().join("missing").join("stats.json");
    for (stats, words) in [
        (&folder, "is a directory"),
        (&missing, "No such file or directory"),
    ] {
        let o = small_cpu_render(&out, &["--stats", stats.to_str().unwrap()]);
        assert_user_error(&o, words);
        assert_eq!(std::fs::read(&out).unwrap(), b"old image");
    }
    assert!(folder.is_dir());
    let mut left: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    left.sort();
    assert_eq!(left, ["a.png", "folder"], "no temporary file is left");
}

#[test]
fn report_refuses_to_overwrite_its_shader_or_scene() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    // The user's main shader, saved where the report's page goes.
    let shader = out.join("index.html");
    std::fs::copy(common::repo().join("shaders/main.comp"), &shader).unwrap();
    assert_refused_over(
        &[
            "report",
            seed3().to_str().unwrap(),
            "--quick",
            "--shader",
            shader.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ],
        &shader,
    );
    // A scene saved as report.md.
    let scene = out.join("report.md");
    std::fs::copy(seed3(), &scene).unwrap();
    assert_refused_over(
        &[
            "report",
            scene.to_str().unwrap(),
            "--quick",
            "-o",
            out.to_str().unwrap(),
        ],
        &scene,
    );
}

/// A run refused for overwriting `input`, which it leaves as it was.
fn assert_refused_over(args: &[&str], input: &Path) {
    let before = std::fs::read(input).unwrap();
    assert_user_error(&glint(args), "refusing to overwrite an input");
    assert_eq!(std::fs::read(input).unwrap(), before);
}

#[test]
fn shader_dump_refuses_to_overwrite_the_shader_it_compiles() {
    let dir = tempfile::tempdir().unwrap();
    // Which file the dump writes: a first dump into another folder says.
    let probe = dir.path().join("probe");
    let o = glint(&[
        "shader",
        "dump",
        seed3().to_str().unwrap(),
        "-o",
        probe.to_str().unwrap(),
    ]);
    assert_ok(&o);
    let comp = String::from_utf8_lossy(&o.stdout)
        .lines()
        .next()
        .map(PathBuf::from)
        .unwrap();
    let name = comp.file_name().unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    let shader = out.join(name);
    std::fs::copy(common::repo().join("shaders/main.comp"), &shader).unwrap();
    assert_refused_over(
        &[
            "shader",
            "dump",
            seed3().to_str().unwrap(),
            "--shader",
            shader.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ],
        &shader,
    );
}
