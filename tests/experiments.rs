//! The experiments that change how the work is laid on the device, never
//! the image (shaders/experiments/walk: other controls of the BVH walk,
//! each behind a define): each renders the same bits as the shipped
//! shader on the scenes that exercise it, under the validation layer, so
//! that a measurement made with one measures the same picture.

#![cfg(feature = "gpu")]

mod common;

use glint::gpu::compile::{compile, Sources};
use glint::gpu::{GpuOptions, Renderer};
use glint::raster::Image;
use glint::scene::{Overrides, Scene};

/// The BVH walk's experiments: shaders/experiments/walk/bvh.glsl, which
/// replaces the shipped walk, and the define that picks each.
const WALK: &str = "shaders/experiments/walk";

/// A renderer of the shipped shaders, with `define` where one is given.
fn renderer(define: Option<&str>) -> Renderer {
    common::gpu_from(GpuOptions {
        defines: define.map(|d| (d.to_owned(), None)).into_iter().collect(),
        ..GpuOptions::default()
    })
}

/// A renderer of the walk experiment, with `define` where one is given.
fn walk(define: Option<&str>) -> Renderer {
    common::gpu_from(GpuOptions {
        defines: define.map(|d| (d.to_owned(), None)).into_iter().collect(),
        include_dirs: vec![common::repo().join(WALK)],
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

/// The SPIR-V `r` compiles for `scene`, with the walk experiment's folder
/// first where `walk`.
fn spirv(r: &Renderer, scene: &Scene, walk: bool) -> Vec<u32> {
    let (variant, defines) = r.variant(scene, &r.settings());
    let sources = Sources {
        dirs: walk
            .then(|| common::repo().join(WALK))
            .into_iter()
            .collect(),
        ..Sources::default()
    }
    .for_variant(&variant);
    compile(&sources, &defines).expect("compile").spirv
}

/// Renders each scene with the shipped shaders and with the walk
/// experiment's `define`, and requires the same bits, once the define is
/// seen to change the experiment's compiled shader (else the two renders
/// could be of one walk).
fn same_bits_with(define: &str, scenes: &[&str]) {
    let mut shipped = renderer(None);
    let plain = walk(None);
    let mut with = walk(Some(define));
    for name in scenes {
        let s = scene(name);
        assert_ne!(
            spirv(&plain, &s, true),
            spirv(&with, &s, true),
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

/// Each define the walk experiment's header lists is one of the four
/// tested above: a fifth would go untested.
#[test]
fn the_walk_experiment_lists_the_defines_tested() {
    let text = std::fs::read_to_string(common::repo().join(WALK).join("bvh.glsl")).unwrap();
    let mut listed: Vec<&str> = text
        .lines()
        .filter_map(|l| l.strip_prefix("#ifdef "))
        .filter(|d| !d.starts_with("USE_") && !d.starts_with("ON_"))
        .collect();
    listed.sort_unstable();
    listed.dedup();
    assert_eq!(
        listed,
        [
            "PAIR_VISIT",
            "REGISTER_STACK",
            "SHADOW_ANY_ORDER",
            "WALK_WHILE_WHILE"
        ]
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

/// A define the shader never reads is caught before any render: its SPIR-V
/// is the shipped shader's (renaming an `#ifdef` kept the tests below
/// green).
#[test]
fn a_define_the_shader_never_reads_changes_nothing_and_is_caught() {
    let s = scene("scenes/seed-fig5.toml");
    assert_eq!(
        spirv(&renderer(None), &s, false),
        spirv(&renderer(Some("NO_SHADER_READS_THIS")), &s, false)
    );
    assert_eq!(
        spirv(&walk(None), &s, true),
        spirv(&walk(Some("NO_SHADER_READS_THIS")), &s, true)
    );
    assert_ne!(
        spirv(&walk(None), &s, true),
        spirv(&walk(Some("PAIR_VISIT")), &s, true)
    );
}

/// An experiment glint does not have is one error naming those it has,
/// exit 2 and no image: it was ignored, so a run measured the default
/// shaders under a misspelt experiment's name.
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
