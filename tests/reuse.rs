//! A prepared scene keeps its buffers on the device and renders from them
//! again (docs/performance.md, On a real GPU): renders in any order, of
//! scenes prepared side by side, give the images of fresh renderers.

#![cfg(feature = "gpu")]

mod common;

use glint::gpu::RenderSettings;
use glint::scene::Scene;

#[test]
fn reused_buffers_give_the_images_of_fresh_renders() {
    let a = common::scene_sized(common::SMALL, 64, 48);
    let mut b = a.clone();
    b.prims.spheres[0].radius *= 0.5;
    let fresh = |s: &Scene| common::render_gpu(s);
    let (fa, fb) = (fresh(&a), fresh(&b));
    assert_ne!(fa, fb, "the two scenes differ");
    // Two scenes prepared on one renderer at once, with one pipeline: each
    // binds its own buffers, so rendering one never disturbs the other.
    let mut r = common::gpu();
    let settings = r.settings();
    let mut pa = r.prepare(&a, &settings).unwrap();
    let mut pb = r.prepare(&b, &settings).unwrap();
    assert_eq!(pa.variant(), pb.variant(), "one variant, so one pipeline");
    for _ in 0..2 {
        assert_eq!(pa.render(None, &|_| {}).unwrap().image, fa);
        assert_eq!(pb.render(None, &|_| {}).unwrap().image, fb);
    }
    // A counting scene rendered twice: its counters start at zero each time.
    let counting = RenderSettings {
        count: true,
        ..settings
    };
    let mut counted = r.prepare(&a, &counting).unwrap();
    let first = counted.render(None, &|_| {}).unwrap();
    let again = counted.render(None, &|_| {}).unwrap();
    assert_eq!(first.image, fa);
    assert_eq!(first.counts, again.counts);
    assert_eq!(first.counts.unwrap().rays().eye, 64 * 48);
}

/// Staged uploads (device-local scene buffers filled by a copy from a
/// staging buffer, as on a discrete GPU; lavapipe has no memory the host
/// cannot map, so the test forces them) give the same bits, under the
/// validation layer, for a scan and for a BVH with every kind of buffer.
#[test]
fn staged_uploads_give_the_same_images() {
    use glint::gpu::{GpuOptions, Renderer};
    use glint::scene::Overrides;
    let staged = GpuOptions {
        validate: true,
        stage_uploads: Some(true),
        ..GpuOptions::default()
    };
    let mut r = Renderer::new(&staged).unwrap();
    let o = Overrides {
        width: Some(96),
        height: Some(96),
        ..Overrides::default()
    };
    let mount = Scene::load(&common::repo().join("scenes/spd/mount.nff"), &o).unwrap();
    for scene in [common::scene_sized(common::SMALL, 64, 48), mount] {
        let image = r.render(&scene, &|_| {}).unwrap().0;
        assert_eq!(image, common::render_gpu(&scene));
    }
}
