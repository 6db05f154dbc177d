//! The extreme scenes of scenes/extreme/ (docs/stability.md): each test checks
//! a property that a textbook f32 ray tracer fails, and where the issue asks
//! for it, that the naive forms (--intersect naive) do fail it.

#![cfg(feature = "gpu")]

mod common;

use std::path::Path;

use glint::cpu;
use glint::gpu::{Intersect, RenderSettings};
use glint::raster::diff::{figures, ErrorFigures, Tolerance};
use glint::raster::{io, Image};
use glint::scene::{Overrides, Scene};

fn load(name: &str) -> Scene {
    let path = common::repo()
        .join("scenes/extreme")
        .join(format!("{name}.toml"));
    Scene::load(&path, &Overrides::default()).unwrap_or_else(|e| panic!("{e}"))
}

fn gpu(scene: &Scene, intersect: Intersect) -> Image {
    let mut r = common::gpu_with(RenderSettings {
        intersect,
        ..RenderSettings::default()
    });
    r.render(scene, &|_| {}).unwrap_or_else(|e| panic!("{e}")).0
}

/// Error relative to the reference's peak, as `glint stability` reports it.
fn error(image: &Image, reference: &Image) -> ErrorFigures {
    let p = reference.peak();
    figures(&image.scaled(p), &reference.scaled(p)).expect("same size")
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
    for k in ["-40", "-20", "-10", "10", "20"] {
        let name = format!("scaled-2e{k}");
        let scene = load(&name);
        // Exactly: every operation commutes with a power-of-two scale, and
        // no absolute epsilon remains to break that.
        assert!(gpu(&scene, Intersect::Robust) == unscaled, "{name} GPU");
        assert!(cpu::render::<f32>(&scene) == unscaled_cpu, "{name} CPU f32");
    }
    // At 2^-56 (lengths of 1e-17 and less: tiny scales), near the
    // bound under which a scene is refused, the GPU is still exact; the
    // CPU's f32 meets a subnormal product in a few pixels and moves them by
    // an ulp or two (2.98e-8 here), far inside the tolerance.
    let scene = load("scaled-2e-56");
    assert!(
        gpu(&scene, Intersect::Robust) == unscaled,
        "scaled-2e-56 GPU"
    );
    let cpu_tiny = error(&cpu::render::<f32>(&scene), &unscaled_cpu);
    assert!(
        cpu_tiny.max_abs < 1e-7,
        "scaled-2e-56 CPU f32: {cpu_tiny:?}"
    );
    for k in ["-56", "-20", "20"] {
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
        let p = image.peak();
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

/// Refraction where it is stiff: rays entering water at up to 89.9° from
/// its normal and a glass sphere at its silhouette agree with f64; inside a
/// glass sphere of radius 1e3, 0.999 r from the centre, every pixel is one
/// of the two analytic values, Ka (the ray leaves at its first hit) or 6 Ka
/// (totally reflected at all six hits of depth 6; a chord meets the wall at
/// the same angle at both ends), on the side of the critical angle that the
/// ray's distance from the centre says, but within rounding of it.
#[test]
fn refraction_at_grazing_entry_and_at_the_critical_angle() {
    robust_agrees("refract-grazing");
    let (scene, reference) = robust_agrees("refract-critical");
    naive_fails("refract-critical", &scene, &reference);
    let r = scene.prims.spheres[0].radius;
    let ka = [0.5, 0.25, 0.125].map(|k| 0.2 * k);
    let cam = &scene.camera;
    let (w, h) = (scene.width, scene.height);
    for (what, image) in [
        ("GPU", gpu(&scene, Intersect::Robust)),
        ("CPU f32", cpu::render::<f32>(&scene)),
        ("CPU f64", cpu::render::<f64>(&scene)),
    ] {
        let mut counts = [0; 2];
        for y in 0..h {
            for x in 0..w {
                let u = 2.0 * (f64::from(x) + 0.5) / f64::from(w) - 1.0;
                let v = 1.0 - 2.0 * (f64::from(y) + 0.5) / f64::from(h);
                let d = (cam.screen_center - cam.eye + cam.screen_right * u + cam.screen_up * v)
                    .normalize();
                // sin θ at the wall: the line's distance from the centre over r.
                let sin = cam.eye.cross(d).length() / r;
                let got = image.get(x, y);
                let is = |times: f64| {
                    (0..3)
                        .all(|c| (f64::from(got[c]) - times * ka[c]).abs() <= 1e-5 * times * ka[c])
                };
                let total = is(6.0);
                assert!(total || is(1.0), "{what} ({x}, {y}): {got:?}");
                if (sin - 1.0 / 1.5).abs() > 1e-4 {
                    assert_eq!(total, sin > 1.0 / 1.5, "{what} ({x}, {y}): sin {sin}");
                }
                counts[usize::from(total)] += 1;
            }
        }
        // The check can fail: both values occur.
        assert!(counts[0] > 1000 && counts[1] > 1000, "{what}: {counts:?}");
    }
}

/// Transmitters of index 1 with no colour of their own, one of them seen
/// almost edge-on, leave the image as it is without them, to within the
/// lift of rays leaving a triangle (shadows are off in that scene, since
/// they would cast them).
#[test]
fn an_index_of_one_passes_even_grazing_rays_straight_through() {
    let (scene, reference) = robust_agrees("refract-ior1");
    let air = scene
        .materials
        .iter()
        .position(|m| m.name == "air")
        .unwrap() as u32;
    let mut without = scene.clone();
    without.prims.spheres.retain(|s| s.material != air);
    without.prims.triangles.retain(|t| t.material != air);
    without.prims.cylinders.retain(|c| c.material != air);
    assert_eq!(
        scene.prims.len() - without.prims.len(),
        4,
        "a sphere, two triangles and a cylinder"
    );
    let bare = cpu::render::<f64>(&without);
    // Not to the last bit: a ray leaving a triangle starts lifted off it
    // (by 1/16384 of its coordinates, docs/scene-format.md, Shading), which
    // moves the pane's rays by 1.5e-4 and the image by 3e-4 at most.
    let f = error(&reference, &bare);
    assert!(
        f.frac_over_1_255 == 0.0 && f.max_abs < 1e-3,
        "f64 with and without: {f:?}"
    );
    assert_passes(
        "refract-ior1",
        "GPU against the bare world",
        &gpu(&scene, Intersect::Robust),
        &bare,
    );
    // The check can fail: index 1.01 bends the rays.
    let mut bent = scene.clone();
    bent.materials[air as usize].ior = 1.01;
    assert!(!passes(&cpu::render::<f64>(&bent), &bare));
}

/// The smooth icosphere mesh scaled by 1e5 and 1e-5 and moved 1e6 from the
/// origin (camera and light with it) gives the image it gives at scale 1,
/// on the GPU, within tolerance; each agrees with its own f64 image.
#[test]
fn meshes_look_the_same_at_any_scale_and_offset() {
    let (_, near) = robust_agrees("mesh-near");
    for name in ["mesh-huge-1e5", "mesh-tiny-1e-5", "mesh-far-1e6"] {
        let (scene, reference) = robust_agrees(name);
        if name != "mesh-huge-1e5" {
            naive_fails(name, &scene, &reference);
        }
        assert_passes(
            name,
            "GPU against scale 1",
            &gpu(&scene, Intersect::Robust),
            &near,
        );
    }
}

/// Slivers of aspect 530 and a vertex shared by 1,000 triangles leave no
/// background pixel inside the shapes they tile, on either renderer.
#[test]
fn slivers_and_a_crowded_vertex_leave_no_holes() {
    let scene = load("triangle-slivers");
    naive_fails("triangle-slivers", &scene, &cpu::render::<f64>(&scene));
    let magenta = [1.0f32, 0.0, 1.0];
    // Where pixel (x, y)'s ray meets z = 0 (generate.py), and whether that
    // is inside a shape by more than a pixel.
    let at = |x: u32, y: u32| {
        (
            0.015 * (f64::from(x) + 0.5) - 2.4,
            1.8 - 0.015 * (f64::from(y) + 0.5),
        )
    };
    let (left, _) = at(60, 0);
    let (rect_x, rect_y) = (left - 4.0 * 0.015 / 8.0, -0.5);
    let (rect_w, rect_h) = (640.0 * 0.015 / 8.0, 1.0);
    let centre = at(220, 119);
    let inside = |(px, py): (f64, f64)| {
        let m = 0.015;
        let in_rect = px > rect_x + m
            && px < rect_x + rect_w - m
            && py > rect_y + m
            && py < rect_y + rect_h - m;
        let in_disc = (px - centre.0).hypot(py - centre.1) < 0.5 - m;
        in_rect || in_disc
    };
    for (what, image) in [
        ("GPU", gpu(&scene, Intersect::Robust)),
        ("CPU f32", cpu::render::<f32>(&scene)),
        ("CPU f64", cpu::render::<f64>(&scene)),
    ] {
        let mut covered = 0;
        for y in 0..scene.height {
            for x in 0..scene.width {
                if inside(at(x, y)) {
                    covered += 1;
                    assert_ne!(image.get(x, y), magenta, "{what}: a hole at ({x}, {y})");
                }
            }
        }
        assert!(covered > 8_000, "{covered}");
        // The check can fail: outside the shapes the background shows.
        assert_eq!(image.get(5, 5), magenta);
    }
    // The centre pixel of the fan is the crowded vertex.
    assert!(inside(centre));
}

/// Rays along a pipe's axis (A = 0) pass through to the far end; a cone's
/// axis, a ray in a cone's surface, a rod of radius 1e-3 seen end-on and
/// a silhouette all agree with f64.
#[test]
fn rays_along_a_cylinder_axis_and_a_cone_surface() {
    let (scene, reference) = robust_agrees("cylinder-axis");
    let bg = scene.background.as_vec3().to_array();
    let image = gpu(&scene, Intersect::Robust);
    // The centre pixel's ray is the pipe's axis: it meets nothing of the
    // pipe and sees the background through its far end.
    for img in [&image, &reference] {
        assert_eq!(img.get(80, 60), bg, "the axis ray");
        // The check can fail: its neighbours a few pixels off meet the wall.
        assert_ne!(img.get(80, 60 + 40), bg);
    }
    robust_agrees("cylinder-along");
}

/// A field of view too narrow for f32 to tell neighbouring pixels' rays
/// apart (1e-6 rad over 160 pixels), and one of 1e-300: the camera's
/// screen is built in f64, so the GPU's image is the f64 one's, not a
/// flat fill of something else.
#[test]
fn a_narrow_field_of_view_renders_what_f64_sees() {
    let dir = tempfile::tempdir().unwrap();
    let showcase = std::fs::read_to_string(common::repo().join("scenes/showcase.toml")).unwrap();
    for vfov in ["1e-6", "1e-300"] {
        let text = showcase.replace("vfov = 45.0", &format!("vfov = {vfov}"));
        assert_ne!(text, showcase);
        let path = dir.path().join(format!("vfov-{vfov}.toml"));
        std::fs::write(&path, text).unwrap();
        let small = Overrides {
            width: Some(160),
            height: Some(120),
            ..Overrides::default()
        };
        let scene = Scene::load(&path, &small).unwrap();
        let reference = cpu::render::<f64>(&scene);
        assert_passes(
            &format!("vfov {vfov}"),
            "GPU robust",
            &gpu(&scene, Intersect::Robust),
            &reference,
        );
    }
}

/// A mirror ball inside a sphere of radius 1e16 whose centre is
/// off the origin. A ray reflected back from the far wall places its hit on
/// the ball only to the rounding of its origin (about 1), so the hit was up
/// to 7 radii off the ball, its normal 7 long, and the specular power of
/// that: pixels of 1e22 in f64 (1e36 at radius 1e17), NaNs in f32 with
/// 500 small balls. Every render now stays within the model's bound.
fn mirror_in_a_dome(balls: usize) -> glint::scene::Scene {
    use std::fmt::Write;
    let mut text = String::from(
        "[image]\nwidth = 32\nheight = 24\n[render]\nmax_depth = 8\nbackground = [0.3, 0.45, 0.7]\n\
         [camera]\neye = [-2.9391716911269397, -0.05477895489670814, -0.606107222535142]\n\
         look_at = [0, 0, 0]\nvfov = 50\n\
         [materials.mirror]\nambient = [0.1, 0.1, 0.1]\ndiffuse = [0.5, 0.5, 0.5]\n\
         specular = [0.6, 0.6, 0.6]\nshininess = 60\nreflectivity = 1.0\n\
         [materials.dome]\nambient = [0.1, 0.1, 0.1]\ndiffuse = [0.5, 0.5, 0.5]\n\
         specular = [0.1, 0.1, 0.1]\nshininess = 10\nreflectivity = 0.5\n\
         [[spheres]]\ncenter = [0, 0, 0]\nradius = 1.0\nmaterial = \"mirror\"\n\
         [[spheres]]\ncenter = [1.732340106813079, -2.4368424793545906, -2.8299151408679624]\n\
         radius = 1e16\nmaterial = \"dome\"\n\
         [[lights]]\ntype = \"point\"\nposition = [6.715302078397393, -1.344658641898933, 5.245601649158839]\n\
         diffuse = [1, 1, 1]\nspecular = [1, 1, 1]\n",
    );
    // Small balls on a fixed lattice of pseudo-random places.
    let mut seed = 12345u64;
    let mut next = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    for _ in 0..balls {
        let (x, y, z, r) = (next(), next(), next(), next());
        write!(
            text,
            "[[spheres]]\ncenter = [{}, {}, {}]\nradius = {}\nmaterial = \"mirror\"\n",
            x * 6.0 - 3.0,
            y * 6.0 - 3.0,
            z * 6.0 - 3.0,
            0.01 + r * 0.09
        )
        .unwrap();
    }
    common::scene(&text)
}

fn assert_within(scene: &glint::scene::Scene, image: &glint::raster::Image, what: &str) {
    let bound = scene.brightest_pixel();
    assert!(image.nonfinite().is_none(), "{what}: non-finite pixels");
    let peak = image.peak();
    assert!(
        peak <= bound,
        "{what}: a pixel of {peak:e}, past the bound {bound:e}"
    );
}

#[test]
fn renders_inside_a_giant_sphere_stay_within_the_models_bound() {
    use glint::cpu;
    for balls in [0, 500] {
        let scene = mirror_in_a_dome(balls);
        let reference = cpu::reference(&scene, glint::accel::Accel::Auto)
            .unwrap_or_else(|e| panic!("{balls} balls: {e}"));
        assert_within(&scene, &reference, &format!("CPU f64, {balls} balls"));
        let f32_image = cpu::render::<f32>(&scene);
        assert_within(&scene, &f32_image, &format!("CPU f32, {balls} balls"));
        for precision in [glint::gpu::Precision::F32, glint::gpu::Precision::F64] {
            let mut r = common::gpu_with(glint::gpu::RenderSettings {
                precision,
                ..glint::gpu::RenderSettings::default()
            });
            let image = r.render(&scene, &|_| {}).unwrap().0;
            assert_within(&scene, &image, &format!("GPU {precision:?}, {balls} balls"));
        }
    }
}

/// A CPU render past the bound is an error naming the pixel, never an
/// image: shown on the check itself, since a render that leaves the bound
/// is the defect fixed above (`src/scene/brightness.rs` has the unit test).
#[test]
fn a_pixel_past_the_bound_is_an_error_naming_it() {
    let scene = mirror_in_a_dome(0);
    let mut image = glint::cpu::render::<f64>(&scene);
    image.pixels[5 * 32 + 7] = [1e22, 0.0, 0.0];
    let e = scene.within(&image, "f64").unwrap_err();
    assert_eq!((e.x, e.y), (7, 5));
    assert!(
        e.to_string()
            .contains("pixel (7, 5) of the CPU f64 render is 1e22"),
        "{e}"
    );
}

/// The shadows of 200 balls on a sky of radius 1e6. f32 rounds a
/// shadow ray's direction by about 1e-7, which over 1e6 moves it across a
/// ball's edge: the GPU and the CPU's f32 both miss such edges, each at
/// pixels of its own, and the check called the GPU wrong (rmse 8.4e-3 over
/// the well-conditioned pixels). The trials now turn every ray that leaves
/// a surface by as much as f32 rounds it, and so find those pixels.
#[test]
fn shadow_edges_that_f32_cannot_place_are_ill_conditioned_not_wrong() {
    use glint::accel::Accel;
    use glint::condition::judge;
    use glint::raster::diff::Tolerance;
    let scene = glint::scene::Scene::load(
        &common::repo().join("tests/data/dome-shadows.toml"),
        &glint::scene::Overrides::default(),
    )
    .unwrap();
    let reference = glint::cpu::reference(&scene, Accel::Auto).unwrap();
    let gpu = common::render_gpu(&scene);
    let tolerance = Tolerance::default();
    let verdict = judge(&scene, &gpu, &reference, &tolerance, Accel::Auto, &|_| {});
    assert!(verdict.pass(), "{:?}", verdict.violations);
    let ill = verdict
        .conditioned
        .as_ref()
        .expect("judged by its conditioning")
        .ill;
    assert!(ill < 0.10, "{ill}");
    // The check still fails a wrong image: a band of rows brightened by
    // 0.05 where the balls are not.
    let mut wrong = gpu.clone();
    for p in &mut wrong.pixels[..scene.width as usize * 20] {
        p[0] += 0.05;
    }
    let verdict = judge(&scene, &wrong, &reference, &tolerance, Accel::Auto, &|_| {});
    assert!(!verdict.pass(), "a brightened band passed");
}
