//! The counts of `--stats` (src/stats.rs): the GPU's against the CPU's on
//! every scene in scenes/ and the SPD. Both count the same events at the
//! same places, so they can differ only where the two arithmetics decide a
//! hit differently: by at most 0.1 % of a counter (the bound).

#![cfg(feature = "gpu")]

mod common;

use std::path::Path;

use glint::accel::Accel;
use glint::cpu::{self, Real};
use glint::scene::{Overrides, Scene};
use glint::stats::Counts;

fn load(path: &Path, size: Option<u32>) -> Scene {
    let o = Overrides {
        width: size,
        height: size,
        ..Overrides::default()
    };
    Scene::load(path, &o).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The CPU's counts with the scene management the GPU's variant took: the
/// tables where `auto` took them on this device (they count cells, and
/// other tests than the walk).
fn cpu_counts<R: Real>(gpu: &glint::gpu::Renderer, scene: &Scene) -> Counts {
    let accel = if common::variant(gpu, scene).0.tables {
        Accel::Tables
    } else {
        Accel::Auto
    };
    cpu::render_counted::<R>(scene, accel, &|_| {}).1
}

/// The counters of `a` that differ from `b`'s by more than 0.1 %, or where
/// one is 0 and the other not: the rays and the tests of every ray, and
/// (to 0.5 %) each ray type's tests, which are smaller counts: balls'
/// reflection rays' triangle tests differ by 0.14 % between the GPU and
/// CPU f64, 68 of 49,534.
fn disagreements(a: &Counts, b: &Counts) -> Vec<String> {
    let off = |x: Vec<(String, u64)>, y: Vec<(String, u64)>, bound: f64| {
        x.into_iter()
            .zip(y)
            .filter(move |((_, x), (_, y))| {
                let (x, y) = (*x as f64, *y as f64);
                (x - y).abs() > bound * x.max(y) || (x == 0.0) != (y == 0.0)
            })
            .map(|((name, x), (_, y))| format!("{name} {x} against {y}"))
    };
    off(a.named(), b.named(), 1e-3)
        .chain(off(a.named_by_ray(), b.named_by_ray(), 5e-3))
        .collect()
}

/// The scenes, each with the size it is rendered at: scenes/ at 96×96
/// (where counting must also leave the image as it was), and the SPD at
/// its procedure's own 512×512. The bound is relative, and the pixels where
/// the arithmetics decide differently lie along curves, so their share
/// shrinks as 1/size: at 96×96 gears' triangle tests differ by 0.16 %.
fn scenes() -> Vec<(std::path::PathBuf, Option<u32>)> {
    let mut v: Vec<_> = common::scene_files("scenes")
        .into_iter()
        .map(|p| (p, Some(96)))
        .collect();
    for name in [
        "balls", "gears", "mount", "rings", "teapot", "tetra", "tree",
    ] {
        v.push((common::repo().join(format!("scenes/spd/{name}.nff")), None));
    }
    v
}

#[test]
fn gpu_counts_agree_with_the_cpu_within_a_thousandth() {
    let mut gpu = common::gpu();
    for (path, size) in scenes() {
        let scene = load(&path, size);
        let (image, counts) = common::render_counted(&mut gpu, &scene);
        if size.is_some() {
            let (plain, _) = gpu.render(&scene, &|_| {}).unwrap();
            assert!(
                image == plain,
                "{}: counting changed the image",
                path.display()
            );
        }
        assert!(counts.rays().eye > 0, "{}", path.display());
        for (what, cpu) in [
            ("f32", cpu_counts::<f32>(&gpu, &scene)),
            ("f64", cpu_counts::<f64>(&gpu, &scene)),
        ] {
            let off = disagreements(&counts, &cpu);
            assert!(off.is_empty(), "{} (CPU {what}): {off:?}", path.display());
        }
    }
}

/// The check can fail: the same scene with one sphere moved a little
/// changes the counts by more than a thousandth.
#[test]
fn a_moved_sphere_fails_the_count_check() {
    let path = common::repo().join("scenes/seed-fig5.toml");
    let scene = load(&path, Some(96));
    let mut moved = scene.clone();
    let first = &mut moved.prims.spheres[0];
    first.center.x += 0.05 * first.radius;
    let mut gpu = common::gpu();
    let (_, counts) = common::render_counted(&mut gpu, &scene);
    assert!(disagreements(&counts, &cpu_counts::<f32>(&gpu, &scene)).is_empty());
    assert!(!disagreements(&counts, &cpu_counts::<f32>(&gpu, &moved)).is_empty());
}
