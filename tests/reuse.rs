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

/// A scene of 40 spheres (a BVH), a plane and a triangle.
fn bvh_scene() -> Scene {
    let mut text = String::from(
        "[image]\nwidth = 48\nheight = 36\n[camera]\neye = [0, 2, 30]\nlook_at = [0, 0, 0]\n\
         vfov = 50\n[materials.m]\ndiffuse = [0.6, 0.5, 0.4]\nspecular = [0.3, 0.3, 0.3]\n\
         shininess = 20\nreflectivity = 0.3\n[materials.floor]\ndiffuse = [0.3, 0.6, 0.3]\n\
         [[planes]]\npoint = [0, -8, 0]\nnormal = [0, 1, 0]\nmaterial = \"floor\"\n\
         [[triangles]]\nvertices = [[-9, -8, -9], [9, -8, -9], [0, 9, -10]]\nmaterial = \"m\"\n\
         [[lights]]\ntype = \"point\"\nposition = [5, 20, 20]\ndiffuse = [1, 1, 1]\n\
         specular = [1, 1, 1]\n",
    );
    let at = |i: usize, k: f64| ((i as f64 * k).fract() - 0.5) * 16.0;
    for i in 0..40 {
        let (x, y, z) = (at(i, 0.618_034), at(i, 0.414_214), at(i, 0.732_051));
        text += &format!("[[spheres]]\ncenter = [{x}, {y}, {z}]\nradius = 0.9\nmaterial = \"m\"\n");
    }
    common::scene(&text)
}

/// A prepared scene updated in place (a notebook's sweep) renders what a
/// fresh renderer renders of the scene as it is now, bit for bit, after
/// each kind of change: a sphere moved far (its BVH refitted), the camera
/// moved (every array camera-relative again), a colour and a light changed.
/// Mapped and staged uploads alike, under the validation layer.
#[test]
fn an_updated_scene_renders_as_a_fresh_one() {
    use glint::gpu::{GpuOptions, Update};
    type Edit = fn(&mut Scene);
    let edits: [(&str, Edit); 4] = [
        ("a sphere moved", |s| {
            s.prims.spheres[3].center = glam::DVec3::new(-7.0, 6.0, 4.0)
        }),
        ("the camera moved", |s| {
            let mut c = s.camera;
            c.eye = glam::DVec3::new(4.0, 5.0, 28.0);
            c.screen_center += glam::DVec3::new(4.0, 3.0, -2.0);
            s.camera = c;
        }),
        ("a colour changed", |s| {
            s.materials[0].diffuse = glam::DVec3::new(0.1, 0.2, 0.9)
        }),
        ("a light moved", |s| {
            s.lights[0].position = glam::DVec3::new(-10.0, 15.0, 5.0)
        }),
    ];
    for staged in [false, true] {
        let mut r = common::gpu_from(GpuOptions {
            stage_uploads: Some(staged),
            ..GpuOptions::default()
        });
        let mut scene = bvh_scene();
        let settings = r.settings();
        let mut prepared = r.prepare(&scene, &settings).unwrap();
        let mut before = prepared.render(None, &|_| {}).unwrap().image;
        assert_eq!(before, common::render_gpu(&scene));
        for (what, edit) in edits {
            edit(&mut scene);
            assert_eq!(prepared.update(&scene).unwrap(), Update::InPlace, "{what}");
            let after = prepared.render(None, &|_| {}).unwrap();
            let fresh = common::render_gpu(&scene);
            assert_ne!(before, fresh, "{what}: the change shows in the image");
            assert!(after.times.bvh_s > 0.0, "{what}: the tree was refitted");
            assert_eq!(after.image, fresh, "{what} (staged uploads: {staged})");
            before = after.image;
        }
    }
}

/// An update the prepared scene has no room or shader for changes nothing
/// and names what it needs: another variant (a deeper ray tree), or more
/// primitives than its buffers hold.
#[test]
fn an_update_that_needs_a_new_shader_says_so_and_changes_nothing() {
    use glint::gpu::Update;
    let mut r = common::gpu();
    let scene = bvh_scene();
    let settings = r.settings();
    let mut prepared = r.prepare(&scene, &settings).unwrap();
    let image = prepared.render(None, &|_| {}).unwrap().image;
    let mut deeper = scene.clone();
    deeper.max_depth += 3;
    let mut more = scene.clone();
    more.prims.spheres.push(more.prims.spheres[0]);
    more.prims.spheres[40].center.x += 3.0;
    let mut larger = scene.clone();
    larger.width += 1;
    for (s, words) in [(&deeper, "variant"), (&more, "spheres"), (&larger, "49x36")] {
        match prepared.update(s).unwrap() {
            Update::Prepare(why) => assert!(why.contains(words), "{why}"),
            Update::InPlace => panic!("updated in place: {words}"),
        }
        assert_eq!(prepared.render(None, &|_| {}).unwrap().image, image);
    }
}
