//! `glint bench`: the ceiling shader and the figures it prints.

#![cfg(feature = "gpu")]

mod common;

use glint::bench::{self, CEILING_TESTS};
use glint::gpu::GpuOptions;
use std::process::Command;

/// The ceiling shader compiles into the renderer's variant, runs clean under
/// the validation layer and its loop budget, and times its tests.
#[test]
fn the_ceiling_shader_runs_and_counts_its_tests() {
    let options = GpuOptions {
        validate: true,
        ..GpuOptions::default()
    };
    let c = bench::ceiling(&options, 32, 1).unwrap();
    assert_eq!(c.tests, 32 * 32 * CEILING_TESTS);
    assert!(c.seconds > 0.0 && c.seconds.is_finite(), "{c:?}");
}

/// The JSON of one scene: its times, and the counts of a counting render
/// (seed-fig3: 800×600 eye rays, each tested against its 4 objects with no
/// BVH).
#[test]
fn bench_reports_times_and_counts() {
    let scene = common::repo().join("scenes/seed-fig3.toml");
    let run = common::cmd()
        .arg("bench")
        .arg(&scene)
        .args(["--runs", "1", "--json"])
        .assert()
        .success();
    let json = common::json_of(&run);
    assert!(json["ceiling"]["tests_per_s"].as_f64().unwrap() > 0.0);
    let s = &json["scenes"][0];
    for t in ["gpu_f32_s", "cpu_f32_s"] {
        assert!(s[t].as_f64().unwrap() > 0.0, "{json}");
    }
    let eye = s["rays"]["eye"].as_u64().unwrap();
    assert_eq!(eye, 800 * 600, "{json}");
    let by_ray = &s["by_ray"]["eye"];
    assert_eq!(by_ray["rays"], eye);
    let tests: u64 = ["spheres", "planes"]
        .iter()
        .map(|k| by_ray["tests"][k].as_u64().unwrap())
        .sum();
    assert_eq!(tests, 4 * eye, "{json}");
}

/// Timestamp queries time the dispatches on the device, where its queue
/// writes them (lavapipe's does): less than the host's dispatch time, which
/// also holds the submission, the output's fill and the wait.
#[test]
fn timestamps_time_the_dispatches_on_the_device() {
    let mut gpu = common::gpu();
    let scene = common::scene(common::SMALL);
    let has = gpu.device_info().timestamps.is_some();
    let (_, times) = gpu.render(&scene, &|_| {}).unwrap();
    match times.device_dispatch_s {
        Some(s) => assert!(s > 0.0 && s <= times.dispatch_s, "{times:?}"),
        None => assert!(!has, "{times:?}"),
    }
}

/// A scene of one sphere and no light renders garbage on the
/// GPU. Its variant is the bench's ceiling's own (one sphere, no light,
/// depth 1), and the SPIR-V cache's key did not say which file was the
/// main shader, so after a `glint bench` the cache handed such a scene the
/// ceiling's shader (values up to 4.3e4 in 22 % of the pixels, exit 0).
/// The tests' renderers keep no cache, which is why none of them saw it:
/// this one shares a cache folder between the ceiling and `glint compare`,
/// as a user's ~/.cache/glint is shared.
#[test]
fn a_scene_of_the_ceilings_variant_renders_its_own_shader_after_the_bench() {
    let home = tempfile::tempdir().unwrap();
    let options = glint::gpu::GpuOptions {
        cache_dir: Some(home.path().join("glint")),
        validate: true,
        ..glint::gpu::GpuOptions::default()
    };
    glint::bench::ceiling(&options, 16, 0).unwrap();
    let spirv = home.path().join("glint/spirv");
    assert_eq!(
        std::fs::read_dir(&spirv).unwrap().count(),
        1,
        "the ceiling is cached"
    );

    let scene = home.path().join("one-sphere.toml");
    std::fs::write(
        &scene,
        "[image]\nwidth = 32\nheight = 24\n[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\n\
         vfov = 45\n[materials.m]\nambient = [1, 1, 1]\n\
         [[spheres]]\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"m\"\n",
    )
    .unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_glint"))
        .env("XDG_CACHE_HOME", home.path())
        .args(["compare", scene.to_str().unwrap()])
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{out}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(out.contains("(identical)"), "a black image is exact: {out}");
    assert_eq!(
        std::fs::read_dir(&spirv).unwrap().count(),
        2,
        "the scene's shader has an entry of its own"
    );
}
