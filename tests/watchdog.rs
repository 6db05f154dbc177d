//! Every wait on the GPU is bounded: a tile that runs past its limit stops
//! the render with the tile named, the renderer refuses further work, and
//! the binary exits at once without an output. On lavapipe a runaway loop
//! ends at the loop budget, so these tests use a limit shorter than an
//! ordinary render instead.

#![cfg(feature = "gpu")]

mod common;

use std::time::{Duration, Instant};

use glint::gpu::{tile_timeout, GpuError, GpuOptions, Renderer};
use glint::scene::{Overrides, Scene};

fn seed_fig5() -> Scene {
    Scene::load(
        &common::repo().join("scenes/seed-fig5.toml"),
        &Overrides::default(),
    )
    .unwrap()
}

#[test]
fn a_tile_past_its_limit_is_an_error_and_the_renderer_is_retired() {
    let mut r = Renderer::new(&GpuOptions {
        validate: true,
        timeout: Some(Duration::from_micros(100)),
        ..GpuOptions::default()
    })
    .expect("device");
    let scene = seed_fig5();
    let settings = r.settings();
    let mut prepared = r.prepare(&scene, &settings).unwrap();
    match prepared.render(None, &|_| {}) {
        Err(GpuError::Timeout { x, y, w, h, .. }) => {
            assert_eq!((x, y), (0, 0));
            assert!(w > 0 && h > 0);
        }
        other => panic!("expected a timeout, got {:?}", other.map(|_| ())),
    }
    assert!(matches!(
        prepared.render(None, &|_| {}),
        Err(GpuError::Lost)
    ));
    assert!(matches!(r.render(&scene, &|_| {}), Err(GpuError::Lost)));
    // Dropping it waits for the dispatch that timed out, then frees.
    drop(r);
}

#[test]
fn the_derived_limit_grows_with_the_work_and_is_never_short() {
    let scene = seed_fig5();
    let px = u64::from(scene.width) * u64::from(scene.height);
    assert!(tile_timeout(&scene, 64, true) >= Duration::from_secs(10));
    assert!(tile_timeout(&scene, 4 * px, false) > tile_timeout(&scene, px, false));
    // Through a BVH, 7,381 spheres cost a ray far less than a linear scan.
    let flake = Scene::load(
        &common::repo().join("scenes/scale/flake-4.toml"),
        &Overrides::default(),
    )
    .unwrap();
    let fpx = 1 << 20;
    assert!(tile_timeout(&flake, fpx, false) > 10 * tile_timeout(&flake, fpx, true));
}

#[test]
fn the_binary_stops_at_once_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    let scene = common::repo().join("scenes/seed-fig5.toml");
    let start = Instant::now();
    let o = common::glint(&[
        "render",
        scene.to_str().unwrap(),
        "--timeout",
        "0.0001",
        "-o",
        out.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("did not finish the tile at (0, 0)"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(!out.exists());
    assert!(start.elapsed() < Duration::from_secs(60));
    let o = common::glint(&["render", scene.to_str().unwrap(), "--timeout", "-1"]);
    assert_eq!(o.status.code(), Some(2));
    // A huge limit is named as given, not in 301 digits.
    let o = common::glint(&["render", scene.to_str().unwrap(), "--timeout", "1e300"]);
    common::assert_user_error(&o, "--timeout 1e300: must be in (0, 1e6] seconds");
}

#[test]
fn every_command_stops_a_runaway_shader_within_its_limit() {
    let dir = tempfile::tempdir().unwrap();
    let inc = common::runaway_include(dir.path());
    let scene = common::repo().join("scenes/seed-fig3.toml");
    let (scene, inc) = (scene.to_str().unwrap(), inc.to_str().unwrap());
    let report = dir.path().join("report");
    let image = dir.path().join("x.png");
    let small = ["--width", "32", "--height", "24"];
    let runs: Vec<Vec<&str>> = vec![
        [
            &["render", scene, "-o", image.to_str().unwrap()][..],
            &small,
        ]
        .concat(),
        [&["compare", scene][..], &small].concat(),
        vec!["bench", scene, "--runs", "1"],
        vec!["report", scene, "--quick", "-o", report.to_str().unwrap()],
        vec!["stability", scene],
    ];
    for args in runs {
        let args = [&args[..], &["-I", inc, "--timeout", "2"]].concat();
        let start = Instant::now();
        let o = common::glint(&args);
        let seconds = start.elapsed().as_secs_f64();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.contains("did not finish the tile") || err.contains("loops were cut short"),
            "{args:?}: {err}"
        );
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        // 2 s for the tile, the device's start and the driver's compile.
        assert!(seconds < 60.0, "{args:?} took {seconds:.1} s");
        eprintln!("{} stopped in {seconds:.1} s", args[0]);
    }
    assert!(!image.exists());
    assert!(!report.join("index.html").exists());
}
