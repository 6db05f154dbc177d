//! Every scene's own shader variant renders the same image as the generic
//! shader that handles every feature: leaving code out changes nothing.

#![cfg(feature = "gpu")]

mod common;

use glint::cpu;
use glint::gpu::variant::Block;
use glint::gpu::{Intersect, Precision, RenderSettings, Renderer};
use glint::raster::diff::{figures, Tolerance};
use glint::scene::{Overrides, Scene};

fn renderer(generic: bool, intersect: Intersect, precision: Precision) -> Renderer {
    common::gpu_with(RenderSettings {
        generic,
        intersect,
        precision,
        ..RenderSettings::default()
    })
}

/// The scenes in scenes/ at 160x120 render the same bits with their own
/// variant and with the generic shader, in these forms and precision.
fn seed_scenes_match(intersect: Intersect, precision: Precision) {
    let mut own = renderer(false, intersect, precision);
    let mut generic = renderer(true, intersect, precision);
    for path in common::scene_files("scenes") {
        let small = Overrides {
            width: Some(160),
            height: Some(120),
            ..Overrides::default()
        };
        let scene = Scene::load(&path, &small).unwrap();
        let a = own.render(&scene, &|_| {}).unwrap().0;
        let b = generic.render(&scene, &|_| {}).unwrap().0;
        assert!(a == b, "{} ({intersect:?}, {precision:?})", path.display());
    }
}

#[test]
fn each_variant_equals_the_generic_shader() {
    let mut own = renderer(false, Intersect::Robust, Precision::F32);
    let mut generic = renderer(true, Intersect::Robust, Precision::F32);
    let mut files = common::scene_files("scenes");
    files.extend(common::scene_files("scenes/extreme"));
    let mut names = std::collections::BTreeSet::new();
    for path in files {
        // A quarter of the pixels keeps this test quick; the variants do not
        // depend on the size.
        let full = Scene::load(&path, &Overrides::default()).unwrap();
        let o = Overrides {
            width: Some(full.width.div_ceil(2)),
            height: Some(full.height.div_ceil(2)),
            ..Overrides::default()
        };
        let scene = Scene::load(&path, &o).unwrap();
        let (variant, _) = common::variant(&own, &scene);
        assert!(variant.features.is_some());
        names.insert(variant.name());
        let a = own.render(&scene, &|_| {}).unwrap().0;
        let b = generic.render(&scene, &|_| {}).unwrap().0;
        // Bitwise: the variants differ only in code left out and constants
        // put in, never in the arithmetic of what remains.
        assert!(
            a == b,
            "{}: variant {} differs from the generic shader",
            path.display(),
            variant.name()
        );
    }
    // The suite exercises many distinct variants, not one.
    assert!(names.len() >= 10, "{names:?}");
}

#[test]
fn naive_variants_equal_the_naive_generic_shader() {
    seed_scenes_match(Intersect::Naive, Precision::F32);
}

#[test]
fn f64_variants_equal_the_f64_generic_shader() {
    seed_scenes_match(Intersect::Robust, Precision::F64);
}

#[test]
fn a_variant_declares_only_the_bindings_it_reads() {
    let r = renderer(false, Intersect::Robust, Precision::F32);
    let scene = common::scene(
        r#"
[image]
width = 8
height = 8
[camera]
eye = [0, 0, 5]
look_at = [0, 0, 0]
vfov = 40.0
[materials.m]
diffuse = [1, 1, 1]
[[spheres]]
center = [0, 0, 0]
radius = 1.0
material = "m"
"#,
    );
    let (variant, defines) = common::variant(&r, &scene);
    let blocks: Vec<Block> = variant.blocks().iter().map(|(b, _)| *b).collect();
    // No planes, no lights, and the rest numbered without gaps.
    assert_eq!(
        blocks,
        [
            Block::Globals,
            Block::Kind(0),
            Block::Materials,
            Block::Pixels
        ]
    );
    let numbers: Vec<u32> = variant.blocks().iter().map(|(_, n)| *n).collect();
    assert_eq!(numbers, [0, 1, 2, 3]);
    let has = |name: &str, value: &str| {
        defines
            .iter()
            .any(|(n, v)| n == name && v.as_deref() == Some(value))
    };
    assert!(
        has("HAS_PLANES", "0") && has("HAS_SHADOWS", "0") && has("MAX_DEPTH", "1u"),
        "{defines:?}"
    );
}

/// Setup times belong to the call that asked for them: a variant built
/// before costs nothing now, rather than showing the last compile's time
/// (docs/report.md once printed the f64 variant's compile as the generic
/// shader's).
#[test]
fn setup_times_are_those_of_the_call() {
    let mut generic = renderer(true, Intersect::Robust, Precision::F32);
    let a = Scene::load(
        &common::repo().join("scenes/seed-fig3.toml"),
        &Overrides::default(),
    )
    .unwrap();
    let b = Scene::load(
        &common::repo().join("scenes/seed-fig4.toml"),
        &Overrides::default(),
    )
    .unwrap();
    let settings = generic.settings();
    // What preparing cost, as the first render of the prepared scene reports it.
    let mut setup_of = |scene: &Scene, settings: &RenderSettings| {
        let mut prepared = generic.prepare(scene, settings).unwrap();
        prepared.render(None, &|_| {}).unwrap().times.setup
    };
    let first = setup_of(&a, &settings);
    assert!(first.compile_s > 0.0 && first.pipeline_s > 0.0, "{first:?}");
    let in_f64 = RenderSettings {
        precision: Precision::F64,
        ..settings
    };
    let f64_setup = setup_of(&a, &in_f64);
    assert!(f64_setup.compile_s > 0.0, "{f64_setup:?}");
    // The generic f32 shader again, for another scene: already built.
    let again = setup_of(&b, &settings);
    assert_eq!((again.compile_s, again.pipeline_s), (0.0, 0.0), "{again:?}");
    let again = setup_of(&a, &in_f64);
    assert_eq!(again.compile_s, 0.0, "built before: {again:?}");
}

/// Every mix of primitive kinds and light types renders, in its own variant,
/// and agrees with the reference on the GPU and in the CPU's f32: from the
/// tables, so a new kind or light type is in it with no edit here, and with
/// the mixes that have nothing: no objects (and so no material used: the
/// scene's two materials stay unused), no lights (the image is its
/// background and black where objects are, since ambient comes from the
/// lights). Then each pattern of the textures' table on every kind, lit by
/// each light type. Lavapipe 22.3 crashed (a segmentation fault in a worker
/// thread) on two of these mixes' uniform buffer variants; glint gives it
/// none (src/gpu/variant.rs).
#[test]
fn every_mix_of_kinds_and_lights_renders() {
    use glint::generate::space::{Point, MAX_KINDS};
    use glint::scene::texture::PATTERNS;
    use glint::scene::LIGHT_TYPES;
    let mut gpu = renderer(false, Intersect::Robust, Precision::F32);
    let kinds = glint::generate::kind_keys().len();
    let every_kind = (1u32 << kinds) - 1;
    let mixes = (0..(1u32 << kinds))
        .flat_map(|mask| (0..=LIGHT_TYPES.len()).map(move |lights| (mask, lights, 0)))
        .chain(
            (1..=PATTERNS.len())
                .flat_map(|t| (1..=LIGHT_TYPES.len()).map(move |lights| (every_kind, lights, t))),
        );
    for (mask, lights, texture) in mixes {
        let mut counts = [0u8; MAX_KINDS];
        for (k, c) in counts.iter_mut().enumerate().take(kinds) {
            *c = u8::from(mask & (1 << k) != 0);
        }
        let point = Point {
            counts,
            // None, then one light of each type.
            lights,
            reflect: true,
            transmit: false,
            texture,
            shadows: true,
            sampling: 0,
            deep: true,
        };
        let generated = point.spec(57, 32, 24).scene();
        let text = &generated.text;
        // Written with its files: an image pattern names one.
        let dir = tempfile::tempdir().unwrap();
        let path = generated.write(dir.path(), "mix.toml").unwrap();
        let scene = Scene::load(&path, &Overrides::default()).unwrap_or_else(|e| panic!("{e}"));
        if texture > 0 {
            let pattern = PATTERNS[texture - 1].pattern;
            let used = scene.materials.iter().filter_map(|m| m.texture);
            let found = used
                .into_iter()
                .any(|t| scene.textures[t as usize].pattern == pattern);
            assert!(found, "no material takes a {pattern:?} in\n{text}");
        }
        let reference = cpu::render::<f64>(&scene);
        let image = gpu
            .render(&scene, &|_| {})
            .unwrap_or_else(|e| panic!("{text}\n{e}"))
            .0;
        for (who, image) in [("gpu", image), ("cpu f32", cpu::render::<f32>(&scene))] {
            let f = figures(&image, &reference).unwrap();
            assert!(
                Tolerance::default().violations(&f).is_empty(),
                "{who}\n{text}\n{f:?}"
            );
        }
        if lights == 0 {
            // Only the background's light is in such a scene: mirrors
            // pass on a share of it, and nothing may add to it.
            let bg = scene.background;
            let lit = reference
                .pixels
                .iter()
                .any(|p| (0..3).any(|c| f64::from(p[c]) > bg[c] + 1e-6));
            assert!(!lit, "no pixel is brighter than the background\n{text}");
        }
    }
}

/// Moving one sphere through a scene keeps the scene's variant, and so its
/// compiled shader, whether its arrays are uniform blocks (a small scene:
/// the nodes' array is sized by the primitives' count) or not (the stack
/// is sized by it): every position in a mesh scene
/// compiled anew.
#[test]
fn moving_a_sphere_keeps_the_variant() {
    let r = renderer(false, Intersect::Robust, Precision::F32);
    for n in [40usize, 3000] {
        let mut forms = std::collections::BTreeSet::new();
        let mut variants = Vec::new();
        for step in 0..8 {
            let mut text = String::from(
                "[image]\nwidth = 8\nheight = 6\n[camera]\neye = [0, 0, 60]\nlook_at = [0, 0, 0]\n\
                 vfov = 60\n[materials.m]\ndiffuse = [0.5, 0.5, 0.5]\n\
                 [[lights]]\ntype = \"point\"\nposition = [0, 30, 30]\ndiffuse = [1, 1, 1]\n",
            );
            let at = |i: usize, k: f64| ((i as f64 * k).fract() - 0.5) * 40.0;
            for i in 0..n {
                let (x, y, z) = if i == 0 {
                    (-30.0 + 8.0 * step as f64, 25.0 - 7.0 * step as f64, 0.0)
                } else {
                    (at(i, 0.618_034), at(i, 0.414_214), at(i, 0.732_051))
                };
                text += &format!(
                    "[[spheres]]\ncenter = [{x}, {y}, {z}]\nradius = 0.3\nmaterial = \"m\"\n"
                );
            }
            let (variant, defines) = common::variant(&r, &common::scene(&text));
            forms.insert(format!("{:?}", variant.form(Block::Nodes)));
            variants.push((variant, defines));
        }
        assert!(
            variants.windows(2).all(|w| w[0] == w[1]),
            "{n} spheres: {:?}",
            variants
                .windows(2)
                .find(|w| w[0] != w[1])
                .map(|w| (&w[0].0, &w[1].0))
        );
        // llvmpipe before Mesa 25.0 reads no scene from uniform buffers
        // (`DeviceInfo::reads_uniform_arrays`).
        let uniform = forms.iter().all(|f| f.starts_with("Uniform"));
        assert_eq!(
            uniform,
            n == 40 && r.device_info().reads_uniform_arrays,
            "{n} spheres: the nodes are read as {forms:?}"
        );
    }
}
