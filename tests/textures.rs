//! Procedural textures (docs/scene-format.md, Textures): the checker on
//! planes and triangles and the solid checker on any primitive render
//! alike on both renderers, a moved or turned checker fails the comparison,
//! and bad tables are named.

mod common;

use glint::cpu;
use glint::raster::Image;
use glint::scene::Scene;

fn whitted(width: u32, height: u32) -> (String, Scene) {
    let text = std::fs::read_to_string(common::repo().join("scenes/whitted-1980.toml")).unwrap();
    let scene = common::scene_sized(&text, width, height);
    (text, scene)
}

/// The two colours of the checker, as the image shows them lit: both occur.
fn distinct_colours(image: &Image) -> usize {
    let mut seen: Vec<[u8; 3]> = image
        .pixels
        .iter()
        .map(|p| p.map(|c| (c.clamp(0.0, 1.0) * 15.0) as u8))
        .collect();
    seen.sort_unstable();
    seen.dedup();
    seen.len()
}

/// The Whitted scene: the GPU and CPU f32 against the f64 reference.
#[test]
fn the_whitted_scene_agrees_on_both_renderers() {
    let (_, scene) = whitted(160, 120);
    let reference = cpu::render::<f64>(&scene);
    common::assert_renderers_agree("whitted", &scene, &reference);
}

/// A perturbed checker fails the comparison: squares 2 % larger, or the
/// cubes moved by a tenth of their side.
#[test]
fn a_moved_or_turned_checker_fails() {
    let (text, scene) = whitted(160, 120);
    let reference = cpu::render::<f64>(&scene);
    let perturbed = [
        text.replace("size = 1.0", "size = 1.02"),
        text.replace("origin = [0.0, 0.5, 0.0]", "origin = [0.1, 0.5, 0.0]"),
    ];
    for t in perturbed {
        assert_ne!(t, text);
        let moved = common::scene_sized(&t, 160, 120);
        assert!(
            !common::passes(&cpu::render::<f64>(&moved), &reference),
            "a perturbed checker passed"
        );
    }
}

const SOLID: &str = r#"
[image]
width = 96
height = 72

[camera]
eye = [0.0, 0.5, 6.0]
look_at = [0.0, 0.0, 0.0]
vfov = 40.0

[textures.cubes]
pattern = "solid_checker"
size = 0.35
colors = [[0.9, 0.9, 0.9], [0.1, 0.2, 0.8]]
origin = [0.1, 0.05, 0.0]

[textures.tiles]
pattern = "checker"
size = 0.5
colors = [[0.2, 0.8, 0.2], [0.8, 0.2, 0.2]]
angle = 30.0

[materials.stone]
texture = "cubes"
ambient = [0.05, 0.05, 0.05]

[materials.tiled]
texture = "tiles"
ambient_texture = "cubes"

[[spheres]]
center = [-0.8, 0.0, 0.0]
radius = 1.0
material = "stone"

[[cylinders]]
base = [1.4, -1.0, 0.0]
base_radius = 0.5
apex = [1.4, 1.0, 0.0]
apex_radius = 0.3
material = "stone"

[[triangles]]
vertices = [[-3.0, -1.0, -2.0], [3.0, -1.0, -2.0], [0.0, 2.5, -2.5]]
material = "tiled"

[[lights]]
type = "point"
position = [2.0, 4.0, 5.0]
ambient = [0.3, 0.3, 0.3]
diffuse = [0.8, 0.8, 0.8]
"#;

/// The solid checker on a sphere and a cylinder, a turned checker on a
/// triangle with the solid checker as its ambient texture: the same image
/// on both renderers, with the textures' colours in it, and a change of
/// the solid checker's origin fails.
#[test]
fn solid_and_turned_checkers_agree_and_can_fail() {
    let scene = common::scene(SOLID);
    let reference = cpu::render::<f64>(&scene);
    assert!(distinct_colours(&reference) > 6, "the textures show");
    common::assert_renderers_agree("the checkers", &scene, &reference);
    let moved =
        common::scene(&SOLID.replace("origin = [0.1, 0.05, 0.0]", "origin = [0.135, 0.05, 0.0]"));
    assert!(!common::passes(&cpu::render::<f64>(&moved), &reference));
    // Without the textures the image is another.
    let plain = SOLID
        .replace(
            "texture = \"tiles\"\nambient_texture = \"cubes\"\n",
            "diffuse = [0.5, 0.5, 0.5]\n",
        )
        .replace("texture = \"cubes\"\n", "diffuse = [0.5, 0.5, 0.5]\n");
    assert!(!plain.contains("texture ="));
    assert!(!common::passes(
        &cpu::render::<f64>(&common::scene(&plain)),
        &reference
    ));
}

/// The GPU's f64 variant and the generic shader render the textures too.
#[cfg(feature = "gpu")]
#[test]
fn the_f64_and_generic_shaders_texture_alike() {
    use glint::gpu::{Precision, RenderSettings};
    let scene = common::scene(SOLID);
    let reference = cpu::render::<f64>(&scene);
    for (generic, precision) in [(true, Precision::F32), (false, Precision::F64)] {
        let mut r = common::gpu_with(RenderSettings {
            generic,
            precision,
            ..RenderSettings::default()
        });
        if precision == Precision::F64 && !r.device_info().shader_float64 {
            common::skip("textures in f64", "no shaderFloat64");
            continue;
        }
        let (image, _) = r.render(&scene, &|_| {}).unwrap();
        let f = glint::raster::diff::figures(&image, &reference).unwrap();
        assert!(
            common::passes(&image, &reference),
            "generic {generic}, {precision:?}: {f:?}"
        );
    }
}

fn error_of(text: &str) -> String {
    match glint::scene::parse(text, std::path::Path::new("bad.toml"), &Default::default()) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn bad_textures_are_named() {
    for (from, to, line_of, key, words) in [
        (
            "texture = \"cubes\"",
            "texture = \"marble\"",
            "texture = \"marble\"",
            "materials.stone.texture",
            "unknown texture \"marble\" (defined: cubes, tiles)",
        ),
        (
            "pattern = \"solid_checker\"",
            "pattern = \"wood\"",
            "pattern = \"wood\"",
            "textures.cubes.pattern",
            "unknown pattern",
        ),
        (
            "size = 0.35",
            "size = 0.0",
            "size = 0.0",
            "textures.cubes.size",
            "must be at least 1e-18",
        ),
        // 1e-40 made the f32 shading NaN, and render said only
        // that the image had non-finite values.
        (
            "size = 0.35",
            "size = 1e-40",
            "size = 1e-40",
            "textures.cubes.size",
            "must be at least 1e-18 and at most 1e18, so that a coordinate over it stays finite in f32; got 1e-40",
        ),
        (
            "origin = [0.1, 0.05, 0.0]",
            "origin = [0.1, 0.05, 0.0]\nangle = 3.0",
            "angle = 3.0",
            "textures.cubes.angle",
            "only a \"checker\"",
        ),
        (
            "angle = 30.0",
            "angle = 30.0\norigin = [0.0, 0.0, 0.0]",
            "origin = [0.0, 0.0, 0.0]",
            "textures.tiles.origin",
            "only a \"solid_checker\"",
        ),
        (
            "size = 0.5",
            "size = 0.5\nscale = 2.0",
            "scale = 2.0",
            "textures.tiles",
            "unknown field `scale`",
        ),
        // A pattern reads its own keys: a wrong value is named by its path.
        (
            "origin = [0.1, 0.05, 0.0]",
            "origin = [0.1, \"x\", 0.0]",
            "origin = [0.1, \"x\", 0.0]",
            "textures.cubes.origin[1]",
            "invalid type",
        ),
        (
            "colors = [[0.9, 0.9, 0.9], [0.1, 0.2, 0.8]]",
            "colors = [[0.9, 0.9, 0.9], [0.1, -0.2, 0.8]]",
            "colors = [[0.9, 0.9, 0.9], [0.1, -0.2, 0.8]]",
            "textures.cubes.colors[1][1]",
            "must be >= 0",
        ),
        // A checker needs a surface's own coordinates: on a sphere, the
        // sphere is named.
        (
            "[materials.stone]\ntexture = \"cubes\"",
            "[materials.stone]\ntexture = \"tiles\"",
            "material = \"stone\"",
            "spheres[0].material",
            "checker texture \"tiles\"",
        ),
    ] {
        assert!(SOLID.contains(from), "{from}");
        let text = SOLID.replacen(from, to, 1);
        let msg = error_of(&text);
        let line = text.lines().position(|l| l.contains(line_of)).unwrap() + 1;
        assert!(
            msg.starts_with(&format!("bad.toml:{line}:")),
            "line {line}: {msg}"
        );
        assert!(msg.contains(key), "expected {key}: {msg}");
        assert!(msg.contains(words), "expected {words:?}: {msg}");
        assert_eq!(msg.lines().count(), 1, "{msg}");
    }
}
