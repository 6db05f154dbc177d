//! Contrast sampling (docs/scene-format.md, Rays): both renderers sample
//! alike and near the f64 reference, a contrast nothing passes is the
//! centres' image bit for bit, more samples bring the image nearer a
//! converged one, regions are the whole render bit for bit, the GPU counts
//! as the CPU does, and bad keys are named.

mod common;

use glint::cpu;
use glint::raster::diff::figures;
use glint::raster::Image;
use glint::scene::{Sampling, Scene};

/// `path` at `width`×`height`, sampled by contrast with `threshold` in
/// every channel and at most `max_samples` a pixel.
fn contrast(path: &str, width: u32, height: u32, threshold: f64, max_samples: u32) -> Scene {
    contrast_with(path, width, height, threshold, max_samples, true)
}

fn contrast_with(
    path: &str,
    width: u32,
    height: u32,
    threshold: f64,
    max_samples: u32,
    compare_trees: bool,
) -> Scene {
    let t = threshold;
    let keys = format!(
        "sampling = \"contrast\"\nthresholds = [{t}, {t}, {t}]\n\
         max_samples = {max_samples}\ncompare_trees = {compare_trees}\n"
    );
    let scene = common::resampled(path, width, height, &keys);
    assert_eq!(scene.sampling, Sampling::Contrast);
    scene
}

/// `path` at `width`×`height`, sampled by contrast with the range test's
/// bound `range`, at most `max_samples` a pixel, trees not compared.
fn by_range(path: &str, width: u32, height: u32, range: f64, max_samples: u32) -> Scene {
    let keys = format!(
        "sampling = \"contrast\"\nrange = {range}\n\
         max_samples = {max_samples}\ncompare_trees = false\n"
    );
    let scene = common::resampled(path, width, height, &keys);
    assert_eq!(scene.contrast.map(|c| c.range), Some(Some(range)));
    scene
}

/// The GPU and CPU f32 agree with the f64 reference, on the Whitted scene
/// and the showcase; a scene perturbed by 1 % of a sphere's radius does
/// not, so the comparison can fail.
#[test]
fn both_renderers_sample_alike() {
    for (path, w, h) in [
        ("scenes/whitted-1980.toml", 160, 120),
        ("scenes/showcase.toml", 160, 120),
    ] {
        let scene = contrast(path, w, h, 0.05, 17);
        let reference = cpu::render::<f64>(&scene);
        common::assert_renderers_agree(path, &scene, &reference);
        let mut perturbed = scene.clone();
        perturbed.prims.spheres[0].radius *= 1.01;
        let moved = common::render_gpu_if_built(&perturbed)
            .unwrap_or_else(|| cpu::render::<f32>(&perturbed));
        assert!(!common::passes(&moved, &reference), "{path}: perturbed");
    }
}

/// With the range test too: the renderers agree with the reference on
/// seed-fig5 (whose beads are what the test is for), and a perturbed
/// scene fails the comparison.
#[test]
fn both_renderers_sample_alike_with_the_range_test() {
    let path = "scenes/seed-fig5.toml";
    let scene = by_range(path, 160, 120, 0.05, 33);
    let reference = cpu::render::<f64>(&scene);
    common::assert_renderers_agree(path, &scene, &reference);
    let mut perturbed = scene.clone();
    perturbed.prims.spheres[0].radius *= 1.01;
    let moved =
        common::render_gpu_if_built(&perturbed).unwrap_or_else(|| cpu::render::<f32>(&perturbed));
    assert!(!common::passes(&moved, &reference), "perturbed");
}

/// The range test on what a scene may lack: no lights (a sphere lit by
/// its ambient term alone, whose edge is all there is to refine) and no
/// objects (the background only, where nothing passes). Both renderers
/// agree with the f64 reference, and the empty scene is its centres.
#[test]
fn the_range_test_on_a_scene_with_no_lights_or_no_objects() {
    let head = "[image]\nwidth = 40\nheight = 30\nsampling = \"contrast\"\nrange = 0.05\n\
                [render]\nbackground = [0.2, 0.3, 0.4]\n\
                [camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nvfov = 45\n";
    let unlit = format!(
        "{head}[materials.m]\nambient = [1, 1, 1]\n\
         [[spheres]]\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"m\"\n"
    );
    let scene = common::scene_sized(&unlit, 40, 30);
    let reference = cpu::render::<f64>(&scene);
    common::assert_renderers_agree("no lights", &scene, &reference);
    assert_below(0.0, difference_from_the_centres(&scene));

    let empty = common::scene_sized(head, 40, 30);
    common::assert_renderers_agree("no objects", &empty, &cpu::render::<f64>(&empty));
    assert_the_centres_image(&empty);
}

/// The largest difference between `scene`'s render and its centres' (CPU
/// f32): more than 0 where the sampler refined a pixel.
fn difference_from_the_centres(scene: &Scene) -> f64 {
    let mut centres = scene.clone();
    centres.sampling = Sampling::Centers;
    centres.contrast = None;
    let c = cpu::render::<f32>(&centres);
    figures(&cpu::render::<f32>(scene), &c).unwrap().max_abs
}

/// Where no range passes the range test, every pixel keeps its centre
/// sample, on both renderers; where a range does, the image nears a
/// converged one, more with more samples.
#[test]
fn the_range_test_refines_toward_a_converged_image() {
    let path = "scenes/seed-fig5.toml";
    let (w, h) = (96, 72);
    let centre_image = assert_the_centres_image(&by_range(path, w, h, 9.0, 33));
    let converged = common::converged(path, w, h);
    let rmse = |i: &Image| figures(i, &converged).unwrap().rmse;
    let some = cpu::render::<f32>(&by_range(path, w, h, 0.05, 17));
    let more = cpu::render::<f32>(&by_range(path, w, h, 0.02, 65));
    assert_below(rmse(&some), 0.5 * rmse(&centre_image));
    assert_below(rmse(&more), rmse(&some));
}

/// `a < b`, both shown where not.
#[track_caller]
fn assert_below(a: f64, b: f64) {
    assert!(a < b, "{a} against {b}");
}

/// Where no contrast passes and trees are not compared, every pixel keeps
/// its centre sample: the image of one sample a pixel, bit for bit, on
/// both renderers.
#[test]
fn a_contrast_nothing_passes_is_the_centres_image() {
    assert_the_centres_image(&contrast_with(
        "scenes/whitted-1980.toml",
        64,
        48,
        9.0,
        33,
        false,
    ));
}

/// Asserts that `scene` renders as its centres alone (one sample a pixel),
/// bit for bit, on both renderers; the centres' CPU f32 image.
fn assert_the_centres_image(scene: &Scene) -> Image {
    let mut centres = scene.clone();
    centres.sampling = Sampling::Centers;
    centres.contrast = None;
    let image = cpu::render::<f32>(&centres);
    assert!(common::same_bits(&cpu::render::<f32>(scene), &image));
    if let (Some(a), Some(b)) = (
        common::render_gpu_if_built(scene),
        common::render_gpu_if_built(&centres),
    ) {
        assert!(common::same_bits(&a, &b));
    }
    image
}

/// More samples where pixels differ bring the image nearer a converged
/// one (16×16 uniform samples) than the centres alone; more levels
/// nearer still.
#[test]
fn more_samples_bring_the_image_nearer_a_converged_one() {
    let path = "scenes/whitted-1980.toml";
    let converged = common::converged(path, 96, 72);
    let rmse = |i: &Image| figures(i, &converged).unwrap().rmse;
    let centres = cpu::render::<f64>(&contrast_with(path, 96, 72, 9.0, 33, false));
    let five = cpu::render::<f64>(&contrast(path, 96, 72, 0.05, 5));
    let more = cpu::render::<f64>(&contrast(path, 96, 72, 0.05, 65));
    assert_below(rmse(&five), rmse(&centres));
    assert_below(rmse(&more), rmse(&five));
}

/// Tiles and regions of a contrast render are the whole render, bit for
/// bit, on both renderers.
#[test]
fn regions_are_the_whole_render_bit_for_bit() {
    let scene = contrast("scenes/whitted-1980.toml", 67, 61, 0.05, 17);
    common::regions_are_the_whole(&scene);
}

/// The GPU counts the levels' eye rays as the CPU does: more than one a
/// pixel, fewer than the most.
#[cfg(feature = "gpu")]
#[test]
fn the_levels_are_counted_alike() {
    let scene = contrast("scenes/whitted-1980.toml", 80, 60, 0.05, 17);
    let c = common::eye_rays_counted_alike(&scene);
    assert!(c.eye > 80 * 60 && c.eye < 80 * 60 * 17, "{c:?}");
}

/// A prepared contrast scene is made with its levels' stage alone: its
/// variant is theirs, so no stage it never dispatches is compiled, and each
/// level binds its list on it. Rendered again, and updated in place (the
/// camera moved), it renders what a fresh renderer renders.
#[cfg(feature = "gpu")]
#[test]
fn a_prepared_contrast_scene_holds_its_levels_stage_alone() {
    use glint::gpu::Update;
    let mut scene = by_range("scenes/whitted-1980.toml", 64, 48, 0.05, 17);
    let mut r = common::gpu();
    let settings = r.settings();
    let mut prepared = r.prepare(&scene, &settings).unwrap();
    let v = prepared.variant();
    assert!(v.refine && v.contrast == Some(false), "{}", v.name());
    let before = prepared.render(None, &|_| {}).unwrap().image;
    assert_eq!(before, common::render_gpu(&scene));
    assert_eq!(prepared.render(None, &|_| {}).unwrap().image, before);
    scene.camera.eye += glam::DVec3::new(0.3, 0.2, 0.0);
    assert_eq!(prepared.update(&scene).unwrap(), Update::InPlace);
    let after = prepared.render(None, &|_| {}).unwrap().image;
    let fresh = common::render_gpu(&scene);
    assert_ne!(before, fresh, "the camera's move shows in the image");
    assert_eq!(after, fresh);
}

#[test]
fn bad_contrast_keys_are_named() {
    let on = "sampling = \"contrast\"\n";
    for (image, key, words) in [
        (
            "thresholds = [0.1, 0.1, 0.1]\n".to_owned(),
            "image.thresholds",
            "only sampling = \"contrast\"",
        ),
        (
            "sampling = \"adaptive\"\nmax_samples = 9\n".to_owned(),
            "image.max_samples",
            "only sampling = \"contrast\"",
        ),
        (
            "compare_trees = false\n".to_owned(),
            "image.compare_trees",
            "only sampling = \"contrast\"",
        ),
        (
            format!("{on}max_samples = 3\n"),
            "image.max_samples",
            "must be in 4..=256",
        ),
        (
            format!("{on}max_samples = 257\n"),
            "image.max_samples",
            "must be in 4..=256",
        ),
        (
            format!("{on}thresholds = [0.1, -0.2, 0.1]\n"),
            "image.thresholds[1]",
            "must be >= 0",
        ),
        (
            format!("{on}thresholds = [nan, 0.1, 0.1]\n"),
            "image.thresholds[0]",
            "must be a finite number",
        ),
        (
            format!("{on}thresholds = [0.1, 0.1, inf]\n"),
            "image.thresholds[2]",
            "must be a finite number",
        ),
        (
            format!("{on}thresholds = []\n"),
            "thresholds",
            "exactly three numbers",
        ),
        (
            format!("{on}max_samples = 99999999999\n"),
            "image.max_samples",
            "must be in 4..=256",
        ),
        (
            format!("{on}thresholds = [0.1, 0.2]\n"),
            "thresholds",
            "exactly three numbers",
        ),
        (
            format!("{on}samples = 2\n"),
            "image.sampling",
            "takes samples = 1",
        ),
        (
            "range = 0.05\n".to_owned(),
            "image.range",
            "only sampling = \"contrast\"",
        ),
        (format!("{on}range = -0.1\n"), "image.range", "must be >= 0"),
        (
            format!("{on}range = nan\n"),
            "image.range",
            "must be a finite number",
        ),
        (
            format!("{on}range = 0.05\nthresholds = [0.1, 0.1, 0.1]\n"),
            "image.range",
            "two tests: give one",
        ),
    ] {
        common::assert_image_keys_refused(&image, key, words);
    }
}
