//! `glint bench`: the ceiling shader and the figures it prints.

#![cfg(feature = "gpu")]

mod common;

use glint::bench::{self, CEILING_TESTS};
use glint::gpu::GpuOptions;

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
