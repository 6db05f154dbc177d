//! The comparison is not vacuous: a perturbed image and an image with one
//! NaN pixel both fail it, while the image itself passes.

mod common;

use glint::cpu;
use glint::raster::diff::{figures, Tolerance};
use glint::raster::Image;

fn reference() -> Image {
    let scene = common::scene_sized(common::SMALL, 200, 150);
    cpu::render::<f64>(&scene)
}

#[test]
fn the_reference_passes_against_itself() {
    let r = reference();
    let f = figures(&r, &r).unwrap();
    assert_eq!(f.max_abs, 0.0);
    assert!(f.psnr_db.is_infinite());
    assert!(Tolerance::default().violations(&f).is_empty());
}

#[test]
fn one_percent_of_pixels_off_by_four_levels_fails() {
    let r = reference();
    let mut perturbed = r.clone();
    // Every 100th pixel, spread over the whole image.
    for p in perturbed.pixels.iter_mut().step_by(100) {
        p[1] += 4.0 / 255.0;
    }
    let f = figures(&perturbed, &r).unwrap();
    assert!((f.frac_over_1_255 - 0.01).abs() < 1e-3, "{f:?}");
    let v = Tolerance::default().violations(&f);
    assert!(!v.is_empty(), "a 1% perturbation passed: {f:?}");
}

#[test]
fn one_nan_pixel_fails() {
    let r = reference();
    let mut broken = r.clone();
    broken.pixels[1234][0] = f32::NAN;
    let f = figures(&broken, &r).unwrap();
    assert_eq!(f.nonfinite, 1);
    assert!(!Tolerance::default().violations(&f).is_empty());
}

#[test]
fn one_infinite_pixel_fails() {
    let r = reference();
    let mut broken = r.clone();
    broken.pixels[7][2] = f32::INFINITY;
    let f = figures(&broken, &r).unwrap();
    assert_eq!(f.nonfinite, 1);
    assert!(!Tolerance::default().violations(&f).is_empty());
}

#[test]
#[cfg(feature = "gpu")]
fn a_gpu_image_perturbed_fails() {
    let scene = common::scene_sized(common::SMALL, 200, 150);
    let r = cpu::render::<f64>(&scene);
    let mut g = common::render_gpu(&scene);
    assert!(Tolerance::default()
        .violations(&figures(&g, &r).unwrap())
        .is_empty());
    for p in g.pixels.iter_mut().step_by(100) {
        p[0] -= 4.0 / 255.0;
    }
    assert!(!Tolerance::default()
        .violations(&figures(&g, &r).unwrap())
        .is_empty());
}

/// A scene lit at 1e15 is judged in units of its peak: the GPU's image
/// passes, where an absolute 1/255 would fail nearly every pixel, and 1 % of
/// its pixels off by 4/255 of the peak fails.
#[test]
#[cfg(feature = "gpu")]
fn a_bright_scene_is_judged_relative_to_its_peak() {
    use glint::accel::Accel;
    use glint::condition;
    use glint::scene::{Overrides, Scene};
    let path = common::repo().join("scenes/extreme/intensity-1e15.toml");
    let scene = Scene::load(&path, &Overrides::default()).unwrap();
    let reference = cpu::render::<f64>(&scene);
    let image = common::render_gpu(&scene);
    let judge = |img: &Image| {
        condition::judge(
            &scene,
            img,
            &reference,
            &Tolerance::default(),
            Accel::Auto,
            &|_| {},
        )
    };
    let j = judge(&image);
    assert!(j.pass() && j.unit > 1e15, "{j:?}");
    assert!(figures(&image, &reference).unwrap().frac_over_1_255 > 0.5);
    let mut perturbed = image.clone();
    for p in perturbed.pixels.iter_mut().step_by(100) {
        p[1] += (4.0 / 255.0 * j.unit) as f32;
    }
    assert!(!judge(&perturbed).pass());
}
