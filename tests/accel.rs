//! The BVH changes which primitives a ray tests, never the image: every
//! scene renders the same bits with `--accel bvh` and `--accel none`, on the
//! GPU and on the CPU in both precisions. Ties in t (coincident and touching
//! spheres) go to the sphere that comes first in the file either way.

mod common;

use glint::accel::Accel;
use glint::cpu;
#[cfg(feature = "gpu")]
use glint::gpu::{Intersect, Precision, RenderSettings, Renderer};
use glint::scene::{Overrides, Scene};

#[cfg(feature = "gpu")]
fn gpu(accel: Accel, intersect: Intersect, precision: Precision) -> Renderer {
    common::gpu_with(RenderSettings {
        accel,
        intersect,
        precision,
        generic: false,
        ..RenderSettings::default()
    })
}

fn small(path: &std::path::Path) -> Scene {
    let o = Overrides {
        width: Some(96),
        height: Some(72),
        ..Overrides::default()
    };
    Scene::load(path, &o).unwrap_or_else(|e| panic!("{e}"))
}

/// tests/data/crowd.toml: 300 spheres, some coincident (ties on every hit).
fn crowd() -> Scene {
    Scene::load(
        &common::repo().join("tests/data/crowd.toml"),
        &Overrides::default(),
    )
    .unwrap()
}

fn all_scenes() -> Vec<(String, Scene)> {
    let mut files = common::scene_files("scenes");
    files.extend(common::scene_files("scenes/extreme"));
    let mut v: Vec<(String, Scene)> = files
        .iter()
        .map(|p| (p.display().to_string(), small(p)))
        .collect();
    v.push(("crowd".to_owned(), crowd()));
    v
}

#[test]
#[cfg(feature = "gpu")]
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
                assert!(common::variant(&bvh, &scene).0.bvh_stack > 0, "{name}");
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

#[test]
#[cfg(feature = "gpu")]
fn auto_takes_the_bvh_from_its_threshold_up() {
    let r = gpu(Accel::Auto, Intersect::Robust, Precision::F32);
    assert!(common::variant(&r, &crowd()).0.bvh_stack > 0);
    let few = small(&common::repo().join("scenes/seed-fig3.toml"));
    assert_eq!(common::variant(&r, &few).0.bvh_stack, 0);
    assert!(Accel::Auto.uses_bvh(&crowd().prims) && !Accel::Auto.uses_bvh(&few.prims));
}
