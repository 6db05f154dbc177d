//! The schedule changes how the rays are laid on the device, never the
//! image: every scene renders the same bits, and counts the same rays and
//! tests, with `--schedule megakernel` and `--schedule wavefront`
//! (src/gpu/schedule.rs). The CPU reference has no schedule.

#![cfg(feature = "gpu")]

mod common;

use std::path::Path;

use glint::gpu::{Intersect, Precision, RenderSettings, Renderer, Schedule};
use glint::raster::region::Region;
use glint::scene::{Overrides, Scene};

fn gpu(schedule: Schedule, intersect: Intersect, precision: Precision) -> Renderer {
    common::gpu_with(RenderSettings {
        intersect,
        precision,
        schedule,
        ..RenderSettings::default()
    })
}

/// Whether the device runs the wavefront; where it does not (Mesa 22.3's
/// llvmpipe), `--schedule wavefront` must be one clear error instead.
fn runs_the_wavefront(wave: &mut Renderer) -> bool {
    if wave.device_info().runs_the_wavefront {
        return true;
    }
    let scene = small(&common::repo().join("scenes/seed-fig4.toml"));
    let e = wave.render(&scene, &|_| {}).unwrap_err().to_string();
    assert!(e.contains("--schedule wavefront"), "{e}");
    common::skip(
        "the wavefront's half of this test",
        &format!("{} refuses it: {e}", wave.device_info().driver),
    );
    false
}

/// Renderers of both schedules, or None where the device does not run the
/// wavefront (its refusal checked).
fn both(intersect: Intersect, precision: Precision) -> Option<(Renderer, Renderer)> {
    let mega = gpu(Schedule::Megakernel, intersect, precision);
    let mut wave = gpu(Schedule::Wavefront, intersect, precision);
    runs_the_wavefront(&mut wave).then_some((mega, wave))
}

fn small(path: &Path) -> Scene {
    let o = Overrides {
        width: Some(48),
        height: Some(36),
        ..Overrides::default()
    };
    Scene::load(path, &o).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// scenes/, scenes/extreme/ and the SPD's databases.
fn every_scene() -> Vec<(String, Scene)> {
    let mut files = common::scene_files("scenes");
    files.extend(common::scene_files("scenes/extreme"));
    files.extend(
        glint::files::sorted(&common::repo().join("scenes/spd"), |p| {
            p.extension().is_some_and(|e| e == "nff")
        })
        .expect("scenes/spd"),
    );
    files
        .iter()
        .map(|p| (p.display().to_string(), small(p)))
        .collect()
}

#[test]
fn every_scene_renders_the_same_bits_on_both_schedules() {
    let Some((mut mega, mut wave)) = both(Intersect::Robust, Precision::F32) else {
        return;
    };
    let scenes = every_scene();
    assert!(scenes.len() > 20, "found {} scenes", scenes.len());
    for (name, scene) in scenes {
        assert!(!common::variant(&mega, &scene).0.wavefront, "{name}");
        assert_eq!(
            common::variant(&wave, &scene).0.wavefront,
            !scene.prims.is_empty(),
            "{name}: the wavefront is the variant rendered"
        );
        let a = mega
            .render(&scene, &|_| {})
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let b = wave
            .render(&scene, &|_| {})
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(
            common::same_bits(&a.0, &b.0),
            "{name}: the schedules differ"
        );
    }
}

/// The counting variants (`--stats`) count the same rays and tests on
/// both, on the scenes of every kind of ray tree: refraction (glass,
/// whitted-1980, gears), 3x3 samples (showcase), a BVH (seed-fig5, balls),
/// images (textures), and adaptive sampling's first pass (whitted-1980).
#[test]
fn both_schedules_count_the_same_rays_and_tests() {
    let Some((mut mega, mut wave)) = both(Intersect::Robust, Precision::F32) else {
        return;
    };
    for file in [
        "scenes/glass.toml",
        "scenes/whitted-1980.toml",
        "scenes/showcase.toml",
        "scenes/seed-fig5.toml",
        "scenes/textures.toml",
        "scenes/spd/balls.nff",
        "scenes/spd/gears.nff",
    ] {
        let scene = small(&common::repo().join(file));
        let (a, ca) = common::render_counted(&mut mega, &scene);
        let (b, cb) = common::render_counted(&mut wave, &scene);
        assert!(common::same_bits(&a, &b), "{file}: counted renders differ");
        assert_eq!(ca, cb, "{file}: the schedules count differently");
    }
}

/// The naive forms and f64, on the scenes with the deepest trees (glass
/// refracts, seed-fig5 reflects through a BVH, showcase takes 3x3
/// samples). whitted-1980 is left to f32: its f64 shaders take half a
/// minute each to compile on lavapipe.
#[test]
fn the_other_forms_and_precisions_render_the_same_bits() {
    for (intersect, precision) in [
        (Intersect::Naive, Precision::F32),
        (Intersect::Robust, Precision::F64),
    ] {
        let Some((mut mega, mut wave)) = both(intersect, precision) else {
            return;
        };
        for name in ["glass", "seed-fig5", "showcase"] {
            let scene = small(&common::repo().join(format!("scenes/{name}.toml")));
            let a = mega.render(&scene, &|_| {}).unwrap().0;
            let b = wave.render(&scene, &|_| {}).unwrap().0;
            assert!(
                common::same_bits(&a, &b),
                "{name} ({intersect:?}, {precision:?}): the schedules differ"
            );
        }
    }
}

/// A region off the image's corner: the wavefront's paths know their
/// pixel by the tile's origin.
#[test]
fn a_wavefront_region_is_the_whole_renders_crop() {
    let scene = small(&common::repo().join("scenes/glass.toml"));
    let whole = gpu(Schedule::Megakernel, Intersect::Robust, Precision::F32)
        .render(&scene, &|_| {})
        .unwrap()
        .0;
    let r = Region {
        x: 7,
        y: 11,
        width: 29,
        height: 13,
    };
    let mut wave = gpu(Schedule::Wavefront, Intersect::Robust, Precision::F32);
    if !runs_the_wavefront(&mut wave) {
        return;
    }
    let part = common::render_region(&mut wave, &scene, r);
    for y in 0..r.height {
        for x in 0..r.width {
            let (p, q) = (part.get(x, y), whole.get(r.x + x, r.y + y));
            assert_eq!(p.map(f32::to_bits), q.map(f32::to_bits), "({x}, {y})");
        }
    }
}

/// The bit-for-bit comparison above can fail: two real renders, of scenes
/// whose backgrounds are one f32 step apart, differ in one bit, and the
/// comparison sees it.
#[test]
fn the_comparison_sees_one_bit() {
    let scene = small(&common::repo().join("scenes/seed-fig5.toml"));
    let Some((mut mega, mut wave)) = both(Intersect::Robust, Precision::F32) else {
        return;
    };
    let (a, b) = common::one_bit_apart(&scene);
    let image = wave.render(&a, &|_| {}).unwrap().0;
    let other = mega.render(&a, &|_| {}).unwrap().0;
    let nudged = mega.render(&b, &|_| {}).unwrap().0;
    assert!(common::same_bits(&image, &other), "the schedules agree");
    assert!(
        common::differ_in_one_bit(&image, &nudged),
        "the renders are one bit apart"
    );
    assert!(!common::same_bits(&image, &nudged), "one bit is seen");
}

/// A user's main shader knows nothing of the wavefront's stages: asking for
/// both is one clear error, and auto takes the megakernel.
#[test]
fn a_shader_of_ones_own_refuses_the_wavefront() {
    let dir = tempfile::tempdir().unwrap();
    let shader = dir.path().join("mine.comp");
    std::fs::copy(common::repo().join("shaders/main.comp"), &shader).unwrap();
    let out = dir.path().join("out.png");
    let scene = common::repo().join("scenes/seed-fig4.toml");
    let args = |schedule: &str| {
        vec![
            "render".to_owned(),
            scene.display().to_string(),
            "--width".to_owned(),
            "16".to_owned(),
            "--height".to_owned(),
            "12".to_owned(),
            "--shader".to_owned(),
            shader.display().to_string(),
            "--schedule".to_owned(),
            schedule.to_owned(),
            "-o".to_owned(),
            out.display().to_string(),
        ]
    };
    let refused = common::cmd().args(args("wavefront")).output().unwrap();
    common::assert_user_error(&refused, "--schedule wavefront");
    assert!(!out.exists(), "no image from a refused render");
    let auto = common::cmd().args(args("auto")).output().unwrap();
    common::assert_ok(&auto);
    assert!(out.exists());
}
