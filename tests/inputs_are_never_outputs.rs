//! No command writes over a file it reads: the output is compared with every
//! input by device and inode, so a scene named like an image, a `./`
//! spelling, a hard link or a symbolic link are all caught, and the input is
//! left byte for byte as it was.

#![cfg(feature = "gpu")]

mod common;

use std::path::Path;

use common::{cmd, glint};
use predicates::prelude::*;
use predicates::str::contains;

const SCENE: &str = r#"
[image]
width = 16
height = 12
[camera]
eye = [0, 0, 40]
screen_center = [0, 0, 0]
screen_right = [20, 0, 0]
screen_up = [0, 15, 0]
[materials.m]
diffuse = [1, 0, 0]
[[spheres]]
center = [0, 0, -10]
radius = 8
material = "m"
"#;

fn assert_refused(args: &[&str], input: &Path, before: &[u8]) {
    cmd()
        .args(args)
        .assert()
        .code(2)
        .stderr(contains("refusing to overwrite an input").and(common::one_line()));
    assert_eq!(
        std::fs::read(input).unwrap(),
        before,
        "{} was modified",
        input.display()
    );
}

#[test]
fn render_refuses_to_write_over_its_scene() {
    let dir = tempfile::tempdir().unwrap();
    // A scene file that happens to be named like an image.
    let scene = dir.path().join("x.png");
    std::fs::write(&scene, SCENE).unwrap();
    let s = scene.to_str().unwrap();
    let dotted = format!("{}/./x.png", dir.path().display());
    let hard = dir.path().join("hard.png");
    std::fs::hard_link(&scene, &hard).unwrap();
    let soft = dir.path().join("soft.png");
    std::os::unix::fs::symlink(&scene, &soft).unwrap();
    for out in [s, &dotted, hard.to_str().unwrap(), soft.to_str().unwrap()] {
        for backend in ["cpu", "gpu"] {
            assert_refused(
                &["render", s, "--backend", backend, "-o", out],
                &scene,
                SCENE.as_bytes(),
            );
        }
    }
}

#[test]
fn render_refuses_a_default_output_that_is_the_scene() {
    let dir = tempfile::tempdir().unwrap();
    // The default output is <stem>.png in the current directory.
    let scene = dir.path().join("y.png");
    std::fs::write(&scene, SCENE).unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_glint"))
        .current_dir(dir.path())
        .args(["render", "y.png", "--backend", "cpu"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(std::fs::read(&scene).unwrap(), SCENE.as_bytes());
}

#[test]
fn diff_and_compare_refuse_a_heat_map_over_an_input() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("s.toml");
    std::fs::write(&scene, SCENE).unwrap();
    let a = dir.path().join("a.pfm");
    let b = dir.path().join("b.pfm");
    for out in [&a, &b] {
        let o = glint(&[
            "render",
            scene.to_str().unwrap(),
            "--backend",
            "cpu",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success());
    }
    let a_bytes = std::fs::read(&a).unwrap();
    let (sa, sb) = (a.to_str().unwrap(), b.to_str().unwrap());
    assert_refused(&["diff", sa, sb, "--diff-out", sa], &a, &a_bytes);
    assert_refused(&["diff", sa, sb, "--diff-out", sb], &b, &a_bytes);
    // The scene file renamed to .pfm, then named as compare's heat-map.
    let scene_pfm = dir.path().join("scene.pfm");
    std::fs::write(&scene_pfm, SCENE).unwrap();
    let sp = scene_pfm.to_str().unwrap();
    assert_refused(
        &["compare", sp, "--diff-out", sp],
        &scene_pfm,
        SCENE.as_bytes(),
    );
    // A fresh name is still written.
    let fresh = dir.path().join("heat.png");
    let o = glint(&["diff", sa, sb, "--diff-out", fresh.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(fresh.is_file());
}
