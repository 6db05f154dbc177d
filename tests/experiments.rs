//! The shader's experiment switches (docs/shaders.md, the defines;
//! docs/performance.md, The lavapipe-specific choices) change how the work
//! is laid on the device, never the image: each renders the same bits as
//! the shipped shader on the scenes that exercise it, under the validation
//! layer, so that a measurement made with one measures the same picture.

#![cfg(feature = "gpu")]

mod common;

use glint::gpu::compile::{compile, Sources};
use glint::gpu::{GpuOptions, Renderer};
use glint::raster::Image;
use glint::scene::{Overrides, Scene};

fn renderer(define: Option<&str>) -> Renderer {
    common::gpu_from(GpuOptions {
        defines: define.map(|d| (d.to_owned(), None)).into_iter().collect(),
        ..GpuOptions::default()
    })
}

fn scene(name: &str) -> Scene {
    let o = Overrides {
        width: Some(64),
        height: Some(48),
        ..Overrides::default()
    };
    let path = common::repo().join(name);
    Scene::load(&path, &o).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn render(r: &mut Renderer, scene: &Scene) -> Image {
    r.render(scene, &|_| {}).expect("render").0
}

/// The SPIR-V `r` compiles for `scene`.
fn spirv(r: &Renderer, scene: &Scene) -> Vec<u32> {
    let (variant, defines) = r.variant(scene, &r.settings());
    let sources = Sources::default().for_variant(&variant);
    compile(&sources, &defines).expect("compile").spirv
}

/// Renders each scene with and without `define` and requires the same
/// bits, once the define is seen to change the compiled shader (else the
/// two renders would be of one shader).
fn same_bits_with(define: &str, scenes: &[&str]) {
    let mut shipped = renderer(None);
    let mut with = renderer(Some(define));
    for name in scenes {
        let s = scene(name);
        assert_ne!(
            spirv(&shipped, &s),
            spirv(&with, &s),
            "{name}: -D {define} does not reach the shader"
        );
        let a = render(&mut shipped, &s);
        let b = render(&mut with, &s);
        assert!(
            common::same_bits(&a, &b),
            "{name}: -D {define} changed the image"
        );
    }
}

/// The BVH scenes: spheres (seed-fig5), triangles, cylinders and a mix (rings).
const TREES: &[&str] = &[
    "scenes/seed-fig5.toml",
    "scenes/triangles.toml",
    "scenes/glass.toml",
    "scenes/spd/rings.nff",
];

#[test]
fn the_while_while_walk_finds_what_the_walk_finds() {
    same_bits_with("WALK_WHILE_WHILE", TREES);
}

#[test]
fn shadow_rays_in_slot_order_find_what_sorted_ones_find() {
    same_bits_with("SHADOW_ANY_ORDER", TREES);
}

#[test]
fn a_stack_in_registers_finds_what_the_array_finds() {
    same_bits_with("REGISTER_STACK", TREES);
}

#[test]
fn two_nodes_a_visit_find_what_one_node_finds() {
    same_bits_with("PAIR_VISIT", TREES);
}

/// MATERIAL_SELECT picks among the materials' uniform slots: a driver that
/// gets no uniform buffers (llvmpipe before Mesa 25.0, which corrupted its
/// heap on them; issue 56) has none to pick among.
#[test]
fn material_selects_pick_the_loaded_material() {
    if !renderer(None).device_info().reads_uniform_arrays {
        common::skip(
            "MATERIAL_SELECT",
            "this driver reads no scene from uniform buffers (llvmpipe before Mesa 25.0)",
        );
        return;
    }
    same_bits_with(
        "MATERIAL_SELECT",
        &[
            "scenes/showcase.toml",
            "scenes/seed-fig3.toml",
            "scenes/textures.toml",
        ],
    );
}

#[test]
fn lanes_in_quads_shade_every_pixel_once() {
    // 64x48 is whole workgroups; the odd size leaves part of one unshaded
    // where the mapping were wrong at an edge.
    same_bits_with(
        "LANE_QUADS",
        &["scenes/seed-fig4.toml", "scenes/showcase.toml"],
    );
    let o = Overrides {
        width: Some(61),
        height: Some(43),
        ..Overrides::default()
    };
    let s = Scene::load(&common::repo().join("scenes/seed-fig3.toml"), &o).unwrap();
    let a = render(&mut renderer(None), &s);
    let b = render(&mut renderer(Some("LANE_QUADS")), &s);
    assert!(common::same_bits(&a, &b), "LANE_QUADS at 61x43");
}

#[test]
fn the_refraction_stack_in_arrays_keeps_the_branches() {
    same_bits_with(
        "BRANCH_ARRAYS",
        &["scenes/glass.toml", "scenes/whitted-1980.toml"],
    );
}

/// The bit comparison `same_bits_with` makes fails on two real renders
/// one bit apart (scenes whose backgrounds are one f32 step apart).
#[test]
fn the_bit_comparison_sees_one_changed_bit() {
    let (a, b) = common::one_bit_apart(&scene("scenes/seed-fig4.toml"));
    let mut r = renderer(None);
    let (image, nudged) = (render(&mut r, &a), render(&mut r, &b));
    assert!(common::same_bits(&image, &render(&mut r, &a)));
    assert!(common::differ_in_one_bit(&image, &nudged));
    assert!(!common::same_bits(&image, &nudged));
}

/// A define the shader never reads is caught before any render: its
/// SPIR-V is the shipped shader's (issue 43: renaming an `#ifdef` kept the
/// tests below green).
#[test]
fn a_define_the_shader_never_reads_changes_nothing_and_is_caught() {
    let s = scene("scenes/seed-fig4.toml");
    assert_eq!(
        spirv(&renderer(None), &s),
        spirv(&renderer(Some("NO_SHADER_READS_THIS")), &s)
    );
    assert_ne!(
        spirv(&renderer(None), &s),
        spirv(&renderer(Some("LANE_QUADS")), &s)
    );
}

/// An experiment glint does not have is one error naming those it has,
/// exit 2 and no image (issue 43): it was ignored, so a run measured the
/// default shaders under a misspelt experiment's name.
#[test]
fn an_unknown_experiment_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.png");
    let scene = common::repo().join("scenes/seed-fig3.toml");
    let o = common::cmd()
        .args([
            "render",
            scene.to_str().unwrap(),
            "--width",
            "32",
            "--height",
            "24",
        ])
        .arg("-o")
        .arg(&out)
        .env("GLINT_EXPERIMENT", "unroll-all,no-such-thing")
        .output()
        .unwrap();
    common::assert_user_error(&o, "no experiment \"no-such-thing\"");
    let stderr = String::from_utf8_lossy(&o.stderr);
    for known in glint::gpu::EXPERIMENTS {
        assert!(stderr.contains(known), "{known}: {stderr}");
    }
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    assert!(!out.exists());
}
