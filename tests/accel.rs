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
    // The SPD databases: most of their rays are shadow rays.
    for name in [
        "balls", "gears", "mount", "rings", "teapot", "tetra", "tree",
    ] {
        let path = common::repo().join(format!("scenes/spd/{name}.nff"));
        v.push((path.display().to_string(), small(&path)));
    }
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
        let mut tables = gpu(Accel::Tables, intersect, precision);
        for (name, scene) in all_scenes() {
            let a = bvh
                .render(&scene, &|_| {})
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            // The SPD's databases are here for the tables: scanned without
            // a tree, balls needs more loop iterations than Mesa 22.3
            // allows, so they are held to the BVH's image alone.
            let b = if name.ends_with(".nff") {
                None
            } else {
                Some(
                    none.render(&scene, &|_| {})
                        .unwrap_or_else(|e| panic!("{name}: {e}")),
                )
            };
            if scene.prims.bounded_count() > 0 {
                assert!(common::variant(&bvh, &scene).0.bvh_stack > 0, "{name}");
            }
            // The SPD's tree under the naive forms is the one scene whose
            // GPU image depends on where the shader tests a primitive: the
            // textbook forms are not `precise`, so the driver may fuse their
            // products into FMAs differently in the scan, the walk and the
            // list (the BVH and the scan differ there at 456e660 too).
            if intersect == Intersect::Naive && name.ends_with("tree.nff") {
                continue;
            }
            if let Some(b) = b {
                assert!(
                    a.0 == b.0,
                    "{name} ({intersect:?}, {precision:?}): BVH and none differ"
                );
            }
            let c = tables
                .render(&scene, &|_| {})
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            if scene.prims.bounded_count() > 0 {
                assert!(common::variant(&tables, &scene).0.tables, "{name}");
            }
            assert!(
                c.0 == a.0,
                "{name} ({intersect:?}, {precision:?}): tables and BVH differ"
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
        let tables = cpu::render_rows::<f64>(&scene, Accel::Tables, &|_| {});
        assert!(tables == none, "{name}: f64 tables and none differ");
        let bvh = cpu::render_rows::<f32>(&scene, Accel::Bvh, &|_| {});
        let none = cpu::render_rows::<f32>(&scene, Accel::None, &|_| {});
        assert!(bvh == none, "{name}: f32 BVH and none differ");
        let tables = cpu::render_rows::<f32>(&scene, Accel::Tables, &|_| {});
        assert!(tables == none, "{name}: f32 tables and none differ");
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
    // Never the tables (measured, they do not yet pay; docs/performance.md).
    assert!(!common::variant(&r, &crowd()).0.tables);
    assert!(!common::variant(&r, &few).0.tables);
    let cpu = cpu::Prepared::<f32>::new(&crowd(), Accel::Auto);
    assert_eq!(cpu.tables_s(), 0.0, "auto takes no tables on the CPU");
}

/// The tables on the other paths through the shader: the counting variant
/// (`--stats`) and the wavefront schedule render the BVH's bits and cast
/// the same rays; on the GPU and the CPU alike every eye and shadow ray
/// reads one cell, and the shadow and eye rays walk less of the tree.
#[test]
#[cfg(feature = "gpu")]
fn the_tables_count_as_the_cpu_and_serve_every_schedule() {
    use glint::gpu::Schedule;
    use glint::stats::{Counter, RayType};
    let mut bvh = gpu(Accel::Bvh, Intersect::Robust, Precision::F32);
    let mut tables = gpu(Accel::Tables, Intersect::Robust, Precision::F32);
    let mut wave = common::gpu_with(RenderSettings {
        accel: Accel::Tables,
        schedule: Schedule::Wavefront,
        generic: false,
        ..RenderSettings::default()
    });
    let runs_wave = wave.device_info().runs_the_wavefront;
    for file in [
        "scenes/seed-fig5.toml",
        "scenes/glass.toml",
        "scenes/spd/balls.nff",
        "scenes/spd/tree.nff",
        "scenes/spd/gears.nff",
    ] {
        let scene = small(&common::repo().join(file));
        let (a, walked) = common::render_counted(&mut bvh, &scene);
        let (b, read) = common::render_counted(&mut tables, &scene);
        assert!(common::same_bits(&a, &b), "{file}: counted renders differ");
        let (_, cpu) = cpu::render_counted::<f32>(&scene, Accel::Tables, &|_| {});
        assert_eq!(read.rays(), walked.rays(), "{file}: rays");
        // Every eye ray reads its tile and every shadow ray its light's
        // cell (each of these scenes' lights has a light buffer).
        for (who, c) in [("GPU", &read), ("CPU", &cpu)] {
            let r = c.rays();
            assert_eq!(
                c.get(Counter::Cell),
                r.eye + r.shadow,
                "{file}: {who}'s cells"
            );
        }
        let nodes = |c: &glint::stats::Counts, t: RayType| c.by_ray()[t.name()].nodes();
        for t in [RayType::Eye, RayType::Shadow] {
            assert!(
                nodes(&read, t) < nodes(&walked, t),
                "{file}: {t:?} rays walk as much"
            );
        }
        if runs_wave {
            let c = wave
                .render(&scene, &|_| {})
                .unwrap_or_else(|e| panic!("{file}: {e}"));
            assert!(
                common::same_bits(&a, &c.0),
                "{file}: the wavefront's tables differ"
            );
        }
    }
}
