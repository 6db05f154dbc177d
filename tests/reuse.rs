//! A renderer keeps the last render's buffers and uses them again for the
//! next render of the same scene with the same pipeline (docs/performance.md,
//! On a real GPU): renders in any order give the images of fresh renderers.

#![cfg(feature = "gpu")]

mod common;

use glint::scene::Scene;

#[test]
fn reused_buffers_give_the_images_of_fresh_renders() {
    let a = common::scene_sized(common::SMALL, 64, 48);
    let mut b = a.clone();
    b.prims.spheres[0].radius *= 0.5;
    let fresh = |s: &Scene| common::render_gpu(s);
    let (fa, fb) = (fresh(&a), fresh(&b));
    assert_ne!(fa, fb, "the two scenes differ");
    let mut r = common::gpu();
    let mut render = |s: &Scene| r.render(s, &|_| {}).unwrap().0;
    for (scene, want) in [(&a, &fa), (&a, &fa), (&b, &fb), (&a, &fa), (&a, &fa)] {
        assert_eq!(&render(scene), want);
    }
    // A counting render between two plain ones: its counters start at zero
    // each time it is reused.
    let counted = r.render_counted(&a, &|_| {}).unwrap().2;
    assert_eq!(r.render(&a, &|_| {}).unwrap().0, fa);
    let again = r.render_counted(&a, &|_| {}).unwrap().2;
    assert_eq!(counted, again);
    assert_eq!(counted.rays().eye, 64 * 48);
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
