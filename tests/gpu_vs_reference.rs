//! Every scene in scenes/ rendered on the GPU in f32 (and on the CPU in
//! f32) agrees with the CPU f64 reference within the documented tolerance.

#![cfg(feature = "gpu")]

mod common;

use glint::cpu;
use glint::raster::diff::{figures, Tolerance};
use glint::scene::{Overrides, Scene};

#[test]
fn every_scene_agrees_with_the_f64_reference() {
    let mut gpu = common::gpu();
    let tolerance = Tolerance::default();
    let files = common::scene_files("scenes");
    assert!(
        files.len() >= 4,
        "scenes/ holds the seed scenes and the showcase"
    );
    for path in files {
        let scene = Scene::load(&path, &Overrides::default()).expect("scene loads");
        let reference = cpu::render::<f64>(&scene);
        let (gpu_image, _) = gpu.render(&scene, &|_| {}).expect("GPU render");
        let cpu32 = cpu::render::<f32>(&scene);
        for (what, image) in [("GPU f32", &gpu_image), ("CPU f32", &cpu32)] {
            let f = figures(image, &reference).expect("same size");
            let v = tolerance.violations(&f);
            assert!(v.is_empty(), "{} {what}: {f:?}: {v:?}", path.display());
            // Not vacuous: f32 does differ from f64 somewhere.
            assert!(
                f.max_abs > 0.0,
                "{} {what} is bit-identical to f64",
                path.display()
            );
        }
    }
}

#[test]
fn small_scene_agrees_pixel_by_pixel() {
    let scene = common::scene(common::SMALL);
    let reference = cpu::render::<f64>(&scene);
    let gpu_image = common::render_gpu(&scene);
    let f = figures(&gpu_image, &reference).unwrap();
    assert!(Tolerance::default().violations(&f).is_empty(), "{f:?}");
    assert_eq!(f.nonfinite, 0);
}

#[test]
fn large_images_render_in_tiles_that_join_seamlessly() {
    // 4 x 4 supersampling makes the rays-per-dispatch budget split this
    // image into several tiles; the result must still match the reference.
    let mut scene = common::scene_sized(common::SMALL, 1500, 1100);
    scene.samples = 4;
    let reference = cpu::render::<f64>(&scene);
    let gpu_image = common::render_gpu(&scene);
    let f = figures(&gpu_image, &reference).unwrap();
    assert!(Tolerance::default().violations(&f).is_empty(), "{f:?}");
}

#[test]
fn an_empty_scene_is_the_background() {
    let scene = common::scene(
        r#"
[image]
width = 17
height = 9
[render]
background = [0.25, 0.5, 0.75]
[camera]
eye = [0, 0, 1]
look_at = [0, 0, 0]
vfov = 60.0
"#,
    );
    for image in [common::render_gpu(&scene), cpu::render::<f64>(&scene)] {
        assert!(image.pixels.iter().all(|p| *p == [0.25, 0.5, 0.75]));
    }
}
