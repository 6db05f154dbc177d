//! The BVH changes which primitives a ray tests, never the image: every
//! scene renders the same bits with `--accel bvh` and `--accel none`, on the
//! GPU and on the CPU in both precisions. Ties in t (coincident and touching
//! spheres) go to the sphere that comes first in the file either way.

mod common;

use glint::accel::Accel;
use glint::cpu::{self, world::World};
use glint::gpu::{GpuOptions, Intersect, Precision, RenderSettings, Renderer};
use glint::raster::Image;
use glint::scene::{Overrides, Scene};

fn gpu(accel: Accel, intersect: Intersect, precision: Precision) -> Renderer {
    let options = GpuOptions {
        validate: true,
        settings: RenderSettings {
            accel,
            intersect,
            precision,
            generic: false,
        },
        ..GpuOptions::default()
    };
    Renderer::new(&options).expect("device")
}

fn small(path: &std::path::Path) -> Scene {
    let o = Overrides {
        width: Some(96),
        height: Some(72),
        ..Overrides::default()
    };
    Scene::load(path, &o).unwrap_or_else(|e| panic!("{e}"))
}

/// Spheres on a jittered grid with exact duplicates and touching pairs,
/// reflective, with shadows: many ties in t and many BVH leaves.
fn crowd(n: usize) -> Scene {
    let mut text = String::from(
        "[image]\nwidth = 96\nheight = 72\n[render]\nmax_depth = 4\nshadows = true\n\
         [camera]\neye = [0, 2, 30]\nlook_at = [0, 0, 0]\nvfov = 50\n\
         [materials.a]\ndiffuse = [0.7, 0.2, 0.2]\nspecular = [0.5, 0.5, 0.5]\nshininess = 30\nreflectivity = 0.4\n\
         [materials.b]\ndiffuse = [0.2, 0.2, 0.7]\nreflectivity = 0.2\n\
         [[lights]]\ntype = \"point\"\nposition = [10, 20, 20]\ndiffuse = [1, 1, 1]\nspecular = [1, 1, 1]\n\
         [[planes]]\npoint = [0, -6, 0]\nnormal = [0, 1, 0]\nmaterial = \"b\"\n",
    );
    for i in 0..n {
        let (x, y, z) = ((i % 10) as f64, ((i / 10) % 10) as f64, (i / 100) as f64);
        let c = [x * 2.0 - 9.0, y * 1.2 - 5.0, -z * 2.0];
        let r = if i % 3 == 0 {
            1.0
        } else {
            0.45 + 0.05 * (i % 7) as f64
        };
        let m = if i % 2 == 0 { "a" } else { "b" };
        text += &format!(
            "[[spheres]]\ncenter = [{}, {}, {}]\nradius = {r}\nmaterial = \"{m}\"\n",
            c[0], c[1], c[2]
        );
        if i % 11 == 0 {
            // The same sphere again, in the other material: a tie on every hit.
            let other = if m == "a" { "b" } else { "a" };
            text += &format!(
                "[[spheres]]\ncenter = [{}, {}, {}]\nradius = {r}\nmaterial = \"{other}\"\n",
                c[0], c[1], c[2]
            );
        }
    }
    common::scene(&text)
}

fn all_scenes() -> Vec<(String, Scene)> {
    let mut files = common::scene_files("scenes");
    files.extend(common::scene_files("scenes/extreme"));
    let mut v: Vec<(String, Scene)> = files
        .iter()
        .map(|p| (p.display().to_string(), small(p)))
        .collect();
    v.push(("crowd".to_owned(), crowd(300)));
    v
}

#[test]
fn gpu_images_do_not_depend_on_the_bvh() {
    for (intersect, precision) in [
        (Intersect::Robust, Precision::F32),
        (Intersect::Naive, Precision::F32),
        (Intersect::Robust, Precision::F64),
    ] {
        let mut bvh = gpu(Accel::Bvh, intersect, precision);
        let mut none = gpu(Accel::None, intersect, precision);
        for (name, scene) in all_scenes() {
            let a = bvh
                .render(&scene, &|_| {})
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            let b = none
                .render(&scene, &|_| {})
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            if scene.prims.bounded_count() > 0 {
                assert!(bvh.variant_for(&scene).0.bvh_layouts > 0, "{name}");
            }
            assert!(
                a.0 == b.0,
                "{name} ({intersect:?}, {precision:?}): BVH and none differ"
            );
        }
    }
}

#[test]
fn cpu_images_do_not_depend_on_the_bvh() {
    for (name, scene) in all_scenes() {
        let bvh = cpu::render_rows::<f64>(&scene, Accel::Bvh, &|_| {});
        let none = cpu::render_rows::<f64>(&scene, Accel::None, &|_| {});
        assert!(bvh == none, "{name}: f64 BVH and none differ");
        let bvh = cpu::render_rows::<f32>(&scene, Accel::Bvh, &|_| {});
        let none = cpu::render_rows::<f32>(&scene, Accel::None, &|_| {});
        assert!(bvh == none, "{name}: f32 BVH and none differ");
    }
}

/// The check above can fail: a tree whose boxes miss part of what they
/// hold, or whose tie rule is wrong, renders another image.
#[test]
fn a_broken_tree_changes_the_image() {
    let scene = crowd(300);
    let reference: Image = cpu::render_rows::<f64>(&scene, Accel::None, &|_| {});
    let mut world = World::<f64>::new(&scene, Accel::Bvh);
    let tree = world.bvh.as_mut().unwrap();
    // Shrink every leaf's box to its lower half in y.
    for node in tree.nodes.iter_mut().filter(|n| n.leaf != 0) {
        node.hi[1] = (node.lo[1] + node.hi[1]) / 2.0;
    }
    assert!(cpu::render_world(&world, &|_| {}) != reference);
}

/// The tie rule, not the walk's order, decides between coincident spheres:
/// reversing the primitives of every leaf keeps the image.
#[test]
fn leaf_order_does_not_matter() {
    let scene = crowd(300);
    let reference: Image = cpu::render_rows::<f64>(&scene, Accel::None, &|_| {});
    let mut world = World::<f64>::new(&scene, Accel::Bvh);
    let tree = world.bvh.as_mut().unwrap();
    // Every layout holds the same leaves; take them once.
    let leaves: Vec<_> = tree.layout(0).iter().filter_map(|n| n.prims()).collect();
    assert!(
        leaves.iter().any(|(_, r)| r.len() >= 2),
        "leaves of several spheres"
    );
    for (kind, r) in leaves {
        tree.orders[kind][r].reverse();
    }
    assert!(cpu::render_world(&world, &|_| {}) == reference);
}

#[test]
fn auto_takes_the_bvh_from_its_threshold_up() {
    let r = gpu(Accel::Auto, Intersect::Robust, Precision::F32);
    assert!(r.variant_for(&crowd(300)).0.bvh_layouts == 8);
    let few = small(&common::repo().join("scenes/seed-fig3.toml"));
    assert_eq!(r.variant_for(&few).0.bvh_layouts, 0);
    assert!(Accel::Auto.uses_bvh(&crowd(300)) && !Accel::Auto.uses_bvh(&few));
}
