//! The CPU-only build's binary (`--no-default-features`): what needs no
//! device works, and what needs one says so in one line, exit status 2.

#![cfg(not(feature = "gpu"))]

mod common;

use assert_cmd::assert::OutputAssertExt;

/// Renders on the CPU, whole and as a tile, then assembles, diffs and
/// converts: the commands that need no device.
#[test]
fn the_cpu_commands_work_without_the_gpu() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("a.png");
    common::assert_ok(&common::small_cpu_render(&png, &[]));
    assert!(png.is_file());
    let tile = dir.path().join("t0.pfm");
    common::assert_ok(&common::small_cpu_render(&tile, &["--tile", "0/1"]));
    let whole = dir.path().join("whole.pfm");
    common::assert_ok(&common::glint(&[
        "assemble",
        tile.to_str().unwrap(),
        "-o",
        whole.to_str().unwrap(),
    ]));
    let direct = dir.path().join("direct.pfm");
    common::assert_ok(&common::small_cpu_render(&direct, &[]));
    let same = common::glint(&["diff", whole.to_str().unwrap(), direct.to_str().unwrap()]);
    common::assert_ok(&same);
    assert!(String::from_utf8_lossy(&same.stdout).contains("identical"));
    // What the commands wrote is the library's CPU render (f64, the CPU's
    // default), not merely a file (exit codes alone were checked).
    let small = glint::scene::Overrides {
        width: Some(40),
        height: Some(30),
        ..Default::default()
    };
    let scene =
        glint::scene::Scene::load(&common::repo().join("scenes/seed-fig3.toml"), &small).unwrap();
    let reference = glint::cpu::render::<f64>(&scene);
    for pfm in [&direct, &whole] {
        let read = glint::raster::io::read(pfm).unwrap();
        assert!(common::same_bits(&read, &reference), "{}", pfm.display());
    }
    let read = glint::raster::io::read(&png).unwrap();
    assert_eq!((read.width, read.height), (40, 30));
    for (p, q) in read.pixels.iter().zip(&reference.pixels) {
        for c in 0..3 {
            let want = glint::raster::quantize(q[c], scene.srgb);
            assert_eq!(
                glint::raster::quantize(p[c], scene.srgb),
                want,
                "{p:?} against {q:?}"
            );
        }
    }
    let nff = common::repo().join("scenes/spd/balls.nff");
    let toml = dir.path().join("balls.toml");
    common::assert_ok(&common::glint(&[
        "convert",
        nff.to_str().unwrap(),
        "-o",
        toml.to_str().unwrap(),
    ]));
    // The converted file is the same scene.
    let none = glint::scene::Overrides::default();
    let from_nff = glint::scene::Scene::load(&nff, &none).unwrap();
    let from_toml = glint::scene::Scene::load(&toml, &none).unwrap();
    assert_eq!(from_nff.prims, from_toml.prims);
    assert_eq!(
        (from_nff.lights, from_nff.camera),
        (from_toml.lights, from_toml.camera)
    );
}

/// Each command that needs the GPU, and a render on it (the default
/// backend), is one error line naming the missing renderer, and writes
/// nothing.
#[test]
fn what_needs_the_gpu_says_so_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    let scene = common::repo().join("scenes/seed-fig3.toml");
    let scene = scene.to_str().unwrap();
    let runs: [&[&str]; 9] = [
        &["render", scene, "-o", out.to_str().unwrap()],
        &["compare", scene],
        &["info"],
        &["stability"],
        &["report", "--quick"],
        &["shader", "check", "x.glsl"],
        &["watch", scene, "-o", out.to_str().unwrap()],
        &["bench"],
        &["drivers", "--quick"],
    ];
    for args in runs {
        let o = common::glint(args);
        common::assert_user_error(&o, "built without it");
        o.clone().assert().stderr(common::one_line());
        assert!(!out.exists(), "{args:?} wrote its output");
    }
}

/// `--version` says that this binary has no GPU renderer.
#[test]
fn version_says_the_gpu_is_not_built_in() {
    let o = common::glint(&["--version"]);
    common::assert_ok(&o);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.lines().next().unwrap().contains("(commit "), "{text}");
    assert!(text.contains("Vulkan: not built in"), "{text}");
}
