//! llvmpipe before Mesa 25.0 stops every loop of an invocation once it has
//! run about 65,535 iterations in all; 25.0 removed that limit ("gallivm:
//! Remove loop limiting"). glint never writes the image a cut loop leaves:
//! the canary loop of shaders/budget.glsl finds the spent budget and the
//! render fails with one clear error, naming the pixel. These tests ask the
//! driver rather than its version: a render past the budget is either that
//! error or an image equal to the CPU reference.

#![cfg(feature = "gpu")]

mod common;

use assert_cmd::assert::OutputAssertExt;

use glint::accel::Accel;
use glint::cpu;
use glint::gpu::{GpuError, GpuOptions, RenderSettings, Renderer};
use glint::raster::diff::{figures, Tolerance};
use glint::scene::Scene;

/// One visible sphere and `n` tiny ones off screen, 2x2 samples: a linear
/// scan makes 4 * (n + 1) sphere tests per pixel for the eye rays alone.
fn scene_text(n: usize) -> String {
    let mut text = String::from(
        "[image]\nwidth = 32\nheight = 24\nsamples = 2\n[render]\nmax_depth = 1\n\
         [camera]\neye = [0, 0, 40]\nscreen_center = [0, 0, 0]\n\
         screen_right = [20, 0, 0]\nscreen_up = [0, 15, 0]\n\
         [materials.m]\ndiffuse = [0.8, 0.3, 0.2]\nambient = [0.1, 0.1, 0.1]\n\
         [[lights]]\ntype = \"point\"\nposition = [30, 30, 50]\ndiffuse = [1, 1, 1]\n\
         [[spheres]]\ncenter = [0, 0, 0]\nradius = 10\nmaterial = \"m\"\n",
    );
    for i in 0..n {
        text += &format!(
            "[[spheres]]\ncenter = [{}, {}, 0]\nradius = 0.5\nmaterial = \"m\"\n",
            1000 + (i % 100) * 3,
            (i / 100) * 3
        );
    }
    text
}

fn scene() -> Scene {
    common::scene(&scene_text(20_000))
}

fn renderer(accel: Accel) -> Renderer {
    Renderer::new(&GpuOptions {
        validate: true,
        settings: RenderSettings {
            accel,
            ..RenderSettings::default()
        },
        ..GpuOptions::default()
    })
    .expect("device")
}

/// Renders the scene with a linear scan: Err(pixel) where the driver cut
/// its loops, else the image, which must then equal the CPU reference.
fn linear_scan(scene: &Scene) -> Result<(), (u32, u32)> {
    match renderer(Accel::None).render(scene, &|_| {}) {
        Err(GpuError::LoopBudget { x, y, .. }) => Err((x, y)),
        Err(e) => panic!("wrong error: {e}"),
        Ok((image, _)) => {
            let reference = cpu::render::<f64>(scene);
            let f = figures(&image, &reference).unwrap();
            assert!(Tolerance::default().violations(&f).is_empty(), "{f:?}");
            Ok(())
        }
    }
}

#[test]
fn a_linear_scan_past_the_budget_is_an_error_or_the_right_image() {
    match linear_scan(&scene()) {
        Err((x, y)) => {
            eprintln!("this driver cuts loops: the render stopped at ({x}, {y})");
            assert!(x < 32 && y < 24);
        }
        Ok(()) => eprintln!("this driver has no loop budget: the image is the reference's"),
    }
}

#[test]
fn the_bvh_renders_the_same_scene_right() {
    let scene = scene();
    let (image, _) = renderer(Accel::Bvh)
        .render(&scene, &|_| {})
        .expect("renders");
    let reference = cpu::render::<f64>(&scene);
    let f = figures(&image, &reference).unwrap();
    assert!(Tolerance::default().violations(&f).is_empty(), "{f:?}");
}

#[test]
fn render_past_the_budget_exits_2_with_one_line_and_writes_nothing_or_renders() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("many.toml");
    std::fs::write(&path, scene_text(20_000)).unwrap();
    let out = dir.path().join("many.png");
    let o = common::glint(&[
        "render",
        path.to_str().unwrap(),
        "--accel",
        "none",
        "-o",
        out.to_str().unwrap(),
    ]);
    if linear_scan(&scene()).is_err() {
        common::assert_user_error(&o, "loops were cut short");
        o.assert().stderr(common::one_line());
        assert!(!out.exists());
    } else {
        common::assert_ok(&o);
        assert!(out.is_file());
    }
    let left = std::fs::read_dir(dir.path()).unwrap().count();
    assert_eq!(left, 1 + usize::from(out.exists()), "no temp file left");
}
