//! A render's AOVs (src/base/aov.rs): the GPU's and the CPU's the same ids
//! and ray counts, the rest within f32's rounding; the colour the plain
//! render's; a region's the whole image's; the rays the counts' total.

mod common;

use glint::accel::Accel;
#[cfg(feature = "gpu")]
use glint::aov::Aov;
use glint::cpu;
#[cfg(feature = "gpu")]
use glint::raster::region::Region;
use glint::scene::{Overrides, Scene};

fn scenes() -> Vec<Scene> {
    let o = Overrides {
        width: Some(40),
        height: Some(30),
        ..Overrides::default()
    };
    let mut out = vec![common::scene_sized(common::SMALL, 40, 30)];
    for name in ["glass.toml", "textures.toml", "cylinders.toml"] {
        out.push(Scene::load(&common::repo().join("scenes").join(name), &o).unwrap());
    }
    out
}

#[cfg(feature = "gpu")]
/// How far an image texture's albedo may be between the GPU and the CPU:
/// a sphere's uv comes through acos and atan2, which llvmpipe computes a
/// few f32 ulps of the angle off libm (`glint explain` shows v 1.9e-5
/// apart on textures.toml), and the texel lookup moves with it (measured
/// up to 1.4e-3). Colours without an image texture agree to f32 rounding.
const ALBEDO_TEXTURED: f64 = 2e-3;

#[cfg(feature = "gpu")]
/// How far a unit normal's components may be between the GPU and the CPU,
/// both in f32: a smooth triangle's normal is interpolated with weights
/// from the ray's hit, which the shader and the CPU round differently
/// (measured up to 1.3e-5 on cylinders.toml's triangles).
const NORMAL: f64 = 1e-4;

#[cfg(feature = "gpu")]
fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-5 * a.abs().max(b.abs()).max(1.0)
}

/// The CPU's AOVs agree with themselves across precisions where it counts:
/// the same primitives met, the same rays, and the colour of a plain render.
#[test]
fn the_cpus_aovs_are_its_renders() {
    for scene in scenes() {
        let f32s = cpu::Prepared::<f32>::new(&scene, Accel::Auto);
        let (image, aovs) = f32s.render_aovs(None, &|_| {});
        assert_eq!(image, f32s.render(&|_| {}));
        let (_, counted) = f32s.render_counted(&|_| {});
        let r = counted.rays();
        let total: u64 = aovs.iter().map(|a| u64::from(a.rays)).sum();
        assert_eq!(total, r.eye + r.reflect + r.refract + r.shadow);
        assert!(aovs.iter().any(|a| a.hit.is_some()));
    }
}

#[cfg(feature = "gpu")]
#[test]
fn the_gpus_aovs_are_the_cpus() {
    use glint::gpu::RenderSettings;
    let mut r = common::gpu();
    let settings = RenderSettings {
        aovs: true,
        ..r.settings()
    };
    for scene in scenes() {
        let image_textured = scene.has_image_textures();
        let mut prepared = r.prepare(&scene, &settings).unwrap();
        assert!(prepared.variant().aovs);
        let rendered = prepared.render(None, &|_| {}).unwrap();
        let gpu: Vec<Aov> = rendered.aovs.expect("an AOV render gives them");
        assert_eq!(
            rendered.image,
            common::render_gpu(&scene),
            "the colour is the plain render's"
        );
        let (_, cpu) = cpu::Prepared::<f32>::new(&scene, Accel::Auto).render_aovs(None, &|_| {});
        assert_eq!(gpu.len(), cpu.len());
        for (i, (g, c)) in gpu.iter().zip(&cpu).enumerate() {
            assert_eq!(g.rays, c.rays, "pixel {i}: rays");
            match (g.hit, c.hit) {
                (None, None) => {}
                (Some(g), Some(c)) => {
                    assert_eq!(g.prim, c.prim, "pixel {i}: primitive");
                    assert!(
                        close(g.depth, c.depth),
                        "pixel {i}: depth {} {}",
                        g.depth,
                        c.depth
                    );
                    for k in 0..3 {
                        let dn = (g.normal[k] - c.normal[k]).abs();
                        assert!(
                            dn <= NORMAL,
                            "pixel {i}: normal {:?} {:?}",
                            g.normal,
                            c.normal
                        );
                        let d = (g.albedo[k] - c.albedo[k]).abs();
                        assert!(
                            close(g.albedo[k], c.albedo[k])
                                || image_textured && d <= ALBEDO_TEXTURED,
                            "pixel {i}: albedo {:?} {:?}",
                            g.albedo,
                            c.albedo
                        );
                    }
                }
                (g, c) => panic!("pixel {i}: {g:?} on the GPU, {c:?} on the CPU"),
            }
        }
        // A region's AOVs are the whole image's there.
        let region = Region {
            x: 7,
            y: 5,
            width: 20,
            height: 11,
        };
        let part = prepared
            .render(Some(region), &|_| {})
            .unwrap()
            .aovs
            .unwrap();
        for y in 0..region.height {
            for x in 0..region.width {
                let whole = gpu[((region.y + y) * scene.width + region.x + x) as usize];
                assert_eq!(part[(y * region.width + x) as usize], whole);
            }
        }
        // A plain render gives none.
        let plain = r.prepare(&scene, &r.settings()).unwrap();
        assert!(!plain.variant().aovs);
    }
}

/// Why `r` refuses AOVs of `scene` (it must).
#[cfg(feature = "gpu")]
fn refused(r: &mut glint::gpu::Renderer, scene: &Scene) -> String {
    let settings = glint::gpu::RenderSettings {
        aovs: true,
        ..r.settings()
    };
    let e = r.prepare(scene, &settings).err().expect("refused");
    e.to_string()
}

/// A scene that samples its pixels' corners has no pixel samples of its
/// own, and a user's trace.glsl that calls no AOV hook (an experiment's)
/// would give AOVs that say nothing was met: both refused in one line,
/// the second naming the file.
#[cfg(feature = "gpu")]
#[test]
fn aovs_that_would_be_wrong_are_refused() {
    let mut scene = common::scene_sized(common::SMALL, 16, 12);
    let plain = scene.clone();
    scene.sampling = glint::scene::Sampling::Corners;
    let e = refused(&mut common::gpu(), &scene);
    assert!(e.contains("pixel's own samples"), "{e}");
    let mut r = common::gpu_from(glint::gpu::GpuOptions {
        include_dirs: vec![common::repo().join("shaders/experiments/normals")],
        ..glint::gpu::GpuOptions::default()
    });
    let e = refused(&mut r, &plain);
    assert!(e.contains("trace.glsl") && e.contains("AOV_"), "{e}");
    // Without AOVs it renders.
    assert!(r.prepare(&plain, &r.settings()).is_ok());
}

/// The AOVs without a tolerance (the primitive met first, the rays
/// traced) are held to the f64 reference's where the trials leave them
/// alone (`condition::judge_aovs`): on the scenes above and the extreme
/// ones where a near-tie decides them (triangle-slivers' faces that meet,
/// light-on-surface's light in the floor's plane) the GPU's differ only
/// where a trial's do, and somewhere they do differ. A primitive changed
/// on a pixel no trial moves fails the check.
#[cfg(feature = "gpu")]
#[test]
fn the_gpus_aovs_differ_from_the_references_only_at_near_ties() {
    use glint::condition::judge_aovs;
    use glint::gpu::RenderSettings;
    let mut r = common::gpu();
    let settings = RenderSettings {
        aovs: true,
        ..r.settings()
    };
    let o = Overrides {
        width: Some(80),
        height: Some(60),
        ..Overrides::default()
    };
    let extreme = ["triangle-slivers.toml", "light-on-surface.toml"]
        .map(|n| Scene::load(&common::repo().join("scenes/extreme").join(n), &o).unwrap());
    let mut differing = 0;
    for scene in scenes().into_iter().chain(extreme) {
        let mut prepared = r.prepare(&scene, &settings).unwrap();
        let gpu = prepared.render(None, &|_| {}).unwrap().aovs.unwrap();
        let check = judge_aovs(&scene, &gpu, Accel::Auto);
        assert!(check.pass(), "unexplained at {:?}", check.unexplained);
        differing += check.differing.len();
    }
    assert!(
        differing > 0,
        "no near-tie met: the check was not exercised"
    );
    let scene = &scenes()[0];
    let mut prepared = r.prepare(scene, &settings).unwrap();
    let mut gpu = prepared.render(None, &|_| {}).unwrap().aovs.unwrap();
    let centre = (scene.height / 2 * scene.width + scene.width / 2) as usize;
    let hit = gpu[centre]
        .hit
        .as_mut()
        .expect("the middle pixel meets something");
    hit.prim.1 += 1;
    let check = judge_aovs(scene, &gpu, Accel::Auto);
    assert_eq!(check.unexplained, vec![centre]);
}
