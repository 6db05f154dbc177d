//! The extreme scenes of scenes/extreme/ (docs/stability.md): each test checks
//! a property that a textbook f32 ray tracer fails, and where the issue asks
//! for it, that the naive forms (--intersect naive) do fail it.

mod common;

use std::path::Path;

use glint::cpu;
use glint::gpu::{GpuOptions, Intersect, RenderSettings, Renderer};
use glint::raster::diff::{figures, ErrorFigures, Tolerance};
use glint::raster::{io, Image};
use glint::scene::{Overrides, Scene};
use glint::stability::{peak, scaled};

fn load(name: &str) -> Scene {
    let path = common::repo()
        .join("scenes/extreme")
        .join(format!("{name}.toml"));
    Scene::load(&path, &Overrides::default()).unwrap_or_else(|e| panic!("{e}"))
}

fn gpu(scene: &Scene, intersect: Intersect) -> Image {
    let options = GpuOptions {
        validate: true,
        settings: RenderSettings {
            intersect,
            ..RenderSettings::default()
        },
        ..GpuOptions::default()
    };
    let mut r = Renderer::new(&options).expect("device");
    r.render(scene, &|_| {}).unwrap_or_else(|e| panic!("{e}")).0
}

/// Error relative to the reference's peak, as `glint stability` reports it.
fn error(image: &Image, reference: &Image) -> ErrorFigures {
    let p = peak(reference);
    figures(&scaled(image, p), &scaled(reference, p)).expect("same size")
}

fn passes(image: &Image, reference: &Image) -> bool {
    Tolerance::default()
        .violations(&error(image, reference))
        .is_empty()
}

fn assert_passes(name: &str, what: &str, image: &Image, reference: &Image) {
    let f = error(image, reference);
    assert!(passes(image, reference), "{name} {what}: {f:?}");
}

/// Robust GPU f32 and CPU f32 agree with CPU f64; returns the reference.
fn robust_agrees(name: &str) -> (Scene, Image) {
    let scene = load(name);
    let reference = cpu::render::<f64>(&scene);
    assert_passes(
        name,
        "GPU robust",
        &gpu(&scene, Intersect::Robust),
        &reference,
    );
    assert_passes(name, "CPU f32", &cpu::render::<f32>(&scene), &reference);
    (scene, reference)
}

fn naive_fails(name: &str, scene: &Scene, reference: &Image) {
    let naive = gpu(scene, Intersect::Naive);
    assert!(
        !passes(&naive, reference),
        "{name}: the naive forms passed: {:?}",
        error(&naive, reference)
    );
}

#[test]
fn giant_ground_spheres() {
    for r in ["1e4", "1e5", "1e6"] {
        let name = format!("giant-ground-{r}");
        let (scene, reference) = robust_agrees(&name);
        naive_fails(&name, &scene, &reference);
    }
}

#[test]
fn tiny_spheres_have_no_holes() {
    let background = [1.0f32, 0.0, 1.0];
    for r in ["1e-3", "1e-4", "1e-5"] {
        let name = format!("tiny-{r}");
        let (scene, reference) = robust_agrees(&name);
        let image = gpu(&scene, Intersect::Robust);
        // The hit masks agree but for pixels on the f64 mask's perimeter.
        let hit = |img: &Image, x: u32, y: u32| img.get(x, y) != background;
        let (w, h) = (scene.width, scene.height);
        let mut hits = 0;
        for y in 0..h {
            for x in 0..w {
                hits += u32::from(hit(&reference, x, y));
                if hit(&image, x, y) != hit(&reference, x, y) {
                    let on_perimeter =
                        [(-1i64, 0i64), (1, 0), (0, -1), (0, 1)]
                            .iter()
                            .any(|(dx, dy)| {
                                let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                                nx >= 0
                                    && ny >= 0
                                    && nx < w as i64
                                    && ny < h as i64
                                    && hit(&reference, nx as u32, ny as u32)
                                        != hit(&reference, x, y)
                            });
                    assert!(
                        on_perimeter,
                        "{name}: pixel ({x}, {y}) differs inside the mask"
                    );
                }
            }
        }
        assert!(hits > 100, "{name}: the spheres cover {hits} pixels");
    }
    let scene = load("tiny-1e-5");
    naive_fails("tiny-1e-5", &scene, &cpu::render::<f64>(&scene));
}

#[test]
fn far_translation_does_not_change_the_image() {
    let base = cpu::render::<f64>(&load("translated-0"));
    for offset in ["1e3", "1e4", "1e5", "1e6"] {
        let name = format!("translated-{offset}");
        let scene = load(&name);
        // Against the untranslated image, not the translated reference.
        assert_passes(&name, "GPU robust", &gpu(&scene, Intersect::Robust), &base);
        assert_passes(&name, "CPU f32", &cpu::render::<f32>(&scene), &base);
        naive_fails(&name, &scene, &base);
    }
}

#[test]
fn power_of_two_scaling_does_not_change_the_image() {
    let unscaled = gpu(&load("scaled-2e0"), Intersect::Robust);
    let unscaled_cpu = cpu::render::<f32>(&load("scaled-2e0"));
    for k in ["-20", "-10", "10", "20"] {
        let name = format!("scaled-2e{k}");
        let scene = load(&name);
        // Exactly: every operation commutes with a power-of-two scale, and
        // no absolute epsilon remains to break that.
        assert_eq!(gpu(&scene, Intersect::Robust), unscaled, "{name} GPU");
        assert_eq!(cpu::render::<f32>(&scene), unscaled_cpu, "{name} CPU f32");
    }
    for k in ["-20", "20"] {
        let name = format!("scaled-2e{k}");
        let scene = load(&name);
        naive_fails(&name, &scene, &cpu::render::<f64>(&scene));
    }
}

#[test]
fn grazing_light_and_tangent_rays() {
    robust_agrees("grazing");
}

#[test]
fn camera_inside_a_sphere_gives_the_analytic_value() {
    // att (Ia Ka + Id Kd), att = 1 / (1 + 0.1 * 3 + 0.01 * 9).
    let att = 1.0 / 1.39;
    let ka = [0.2, 0.1, 0.05];
    let kd = [0.6, 0.5, 0.4];
    let want: [f64; 3] = [0, 1, 2].map(|c| att * (0.2 * ka[c] + kd[c]));
    for name in ["inside-center", "inside-0999"] {
        let scene = load(name);
        for (what, image, rel) in [
            ("GPU", gpu(&scene, Intersect::Robust), 1e-5),
            ("CPU f32", cpu::render::<f32>(&scene), 1e-5),
            ("CPU f64", cpu::render::<f64>(&scene), 1e-7),
        ] {
            common::assert_uniform(&image, want, rel, &format!("{name} {what}"));
        }
    }
}

#[test]
fn touching_and_intersecting_spheres() {
    robust_agrees("touching");
}

#[test]
fn lights_on_a_surface_and_inside_a_sphere() {
    // A light exactly on the floor sees the floor edge-on: N.L is zero, and
    // rounding decides its sign in f64 as much as in f32. Only finiteness is
    // asked of that scene (docs/stability.md).
    let scene = load("light-on-surface");
    for image in [
        gpu(&scene, Intersect::Robust),
        cpu::render::<f32>(&scene),
        cpu::render::<f64>(&scene),
    ] {
        assert!(image.pixels.iter().flatten().all(|v| v.is_finite()));
    }
    // A light inside an opaque sphere lights nothing outside: all black.
    let scene = load("light-inside-sphere");
    for image in [
        gpu(&scene, Intersect::Robust),
        cpu::render::<f32>(&scene),
        cpu::render::<f64>(&scene),
    ] {
        assert!(image.pixels.iter().all(|p| *p == [0.0; 3]));
    }
}

#[test]
fn shininess_from_0_to_1e5() {
    robust_agrees("shininess");
}

#[test]
fn parallel_mirrors_sum_the_geometric_series() {
    // Ia Ka = (0.01, 0.02, 0.03) * (1, 0.5, 0.25); 64 bounces.
    let local = [0.01, 0.02 * 0.5, 0.03 * 0.25];
    for (name, kr) in [("mirrors-1", 1.0f64), ("mirrors-09", 0.9)] {
        let series: f64 = (0..64).map(|k| kr.powi(k)).sum();
        let scene = load(name);
        assert_eq!(scene.max_depth, 64);
        for (what, image, rel) in [
            ("GPU", gpu(&scene, Intersect::Robust), 1e-5),
            ("CPU f32", cpu::render::<f32>(&scene), 1e-5),
            ("CPU f64", cpu::render::<f64>(&scene), 1e-7),
        ] {
            let want = local.map(|l| l * series);
            common::assert_uniform(&image, want, rel, &format!("{name} {what}"));
        }
    }
}

#[test]
fn many_dim_lights_equal_one_bright_light() {
    let one = load("lights-1");
    let many = load("lights-1024");
    assert_eq!(many.lights.len(), 1024);
    let reference = cpu::render::<f64>(&one);
    assert_passes(
        "lights-1024",
        "GPU",
        &gpu(&many, Intersect::Robust),
        &reference,
    );
    assert_passes(
        "lights-1024",
        "CPU f64",
        &cpu::render::<f64>(&many),
        &reference,
    );
}

#[test]
fn extreme_intensities_stay_finite_and_survive_hdr_files() {
    let dir = tempfile::tempdir().unwrap();
    for e in ["-30", "-15", "15", "30"] {
        let name = format!("intensity-1e{e}");
        let (scene, _) = robust_agrees(&name);
        let image = gpu(&scene, Intersect::Robust);
        assert!(
            image.pixels.iter().flatten().all(|v| v.is_finite()),
            "{name}"
        );
        let p = peak(&image);
        let expected_scale: f64 = format!("1e{e}").parse().unwrap();
        assert!(
            p > 0.1 * expected_scale && p < 10.0 * expected_scale,
            "{name}: peak {p}"
        );
        for ext in ["pfm", "exr"] {
            let path = dir.path().join(format!("{name}.{ext}"));
            io::write(&path, &image, false).unwrap();
            assert_eq!(
                io::read(&path).unwrap(),
                image,
                "{name}.{ext} keeps the values"
            );
        }
    }
}

#[test]
fn no_scene_in_the_suite_gives_a_non_finite_value() {
    let files = common::scene_files("scenes/extreme");
    assert!(files.len() >= 30);
    for path in files {
        let scene = Scene::load(Path::new(&path), &Overrides::default()).unwrap();
        for (what, image) in [
            ("GPU robust", gpu(&scene, Intersect::Robust)),
            ("GPU naive", gpu(&scene, Intersect::Naive)),
            ("CPU f32", cpu::render::<f32>(&scene)),
            ("CPU f64", cpu::render::<f64>(&scene)),
        ] {
            let bad = image
                .pixels
                .iter()
                .flatten()
                .filter(|v| !v.is_finite())
                .count();
            assert_eq!(bad, 0, "{} {what}: {bad} non-finite values", path.display());
        }
    }
}
