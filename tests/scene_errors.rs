//! Every scene error names the file, the line and the key.

use std::path::Path;

use glint::scene::{parse, Overrides, SceneError};

const GOOD: &str = r#"[image]
width = 8
height = 6

[camera]
eye = [0.0, 0.0, 5.0]
look_at = [0.0, 0.0, 0.0]
vfov = 40.0

[materials.m]
diffuse = [0.5, 0.5, 0.5]

[[spheres]]
center = [0.0, 0.0, 0.0]
radius = 1.0
material = "m"

[[planes]]
point = [0.0, -1.0, 0.0]
normal = [0.0, 1.0, 0.0]
material = "m"

[[lights]]
type = "spot"
position = [0.0, 5.0, 0.0]
direction = [0.0, -1.0, 0.0]
cutoff = 30.0
"#;

fn error_of(text: &str) -> String {
    match parse(text, Path::new("bad.toml"), &Overrides::default()) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

/// Replaces the first `from` in GOOD (which must be there) with `to`.
fn with(from: &str, to: &str) -> String {
    assert!(GOOD.contains(from), "GOOD has no {from:?}");
    GOOD.replacen(from, to, 1)
}

fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .expect("needle in text")
        + 1
}

/// The error names bad.toml, the line where `needle` stands, and `key`.
fn check(text: &str, needle: &str, key: &str, words: &str) {
    let msg = error_of(text);
    let line = line_of(text, needle);
    assert!(
        msg.starts_with(&format!("bad.toml:{line}:")),
        "expected line {line}: {msg}"
    );
    assert!(msg.contains(key), "expected key {key}: {msg}");
    assert!(msg.contains(words), "expected {words:?}: {msg}");
}

#[test]
fn the_good_scene_parses() {
    parse(GOOD, Path::new("good.toml"), &Overrides::default()).unwrap();
}

#[test]
fn unknown_key() {
    let t = with("radius = 1.0", "radius = 1.0\nradius_typo = 2.0");
    check(&t, "radius_typo", "radius_typo", "unknown field");
}

#[test]
fn wrong_type() {
    let t = with("width = 8", "width = \"eight\"");
    check(&t, "width = \"eight\"", "image.width", "invalid type");
}

#[test]
fn missing_key() {
    let t = with("radius = 1.0\n", "");
    let msg = error_of(&t);
    assert!(msg.starts_with("bad.toml:"), "{msg}");
    assert!(msg.contains("radius"), "{msg}");
    assert!(msg.contains("missing"), "{msg}");
}

#[test]
fn nan_and_inf() {
    check(
        &with("center = [0.0, 0.0, 0.0]", "center = [0.0, nan, 0.0]"),
        "nan",
        "spheres[0].center[1]",
        "finite",
    );
    check(
        &with("vfov = 40.0", "vfov = inf"),
        "vfov = inf",
        "camera.vfov",
        "finite",
    );
    check(
        &with("radius = 1.0", "radius = -inf"),
        "radius = -inf",
        "spheres[0].radius",
        "finite",
    );
}

#[test]
fn radius_not_positive() {
    check(
        &with("radius = 1.0", "radius = 0.0"),
        "radius = 0.0",
        "spheres[0].radius",
        "> 0",
    );
    check(
        &with("radius = 1.0", "radius = -2.0"),
        "radius = -2.0",
        "spheres[0].radius",
        "> 0",
    );
}

#[test]
fn zero_normal() {
    check(
        &with("normal = [0.0, 1.0, 0.0]", "normal = [0.0, 0.0, 0.0]"),
        "normal =",
        "planes[0].normal",
        "non-zero",
    );
}

#[test]
fn unknown_material() {
    check(
        &with("material = \"m\"", "material = \"gold\""),
        "\"gold\"",
        "spheres[0].material",
        "unknown material \"gold\"",
    );
}

#[test]
fn reflectivity_out_of_range() {
    let t = with(
        "diffuse = [0.5, 0.5, 0.5]",
        "diffuse = [0.5, 0.5, 0.5]\nreflectivity = 1.5",
    );
    check(&t, "reflectivity", "materials.m.reflectivity", "[0, 1]");
}

#[test]
fn unknown_light_type() {
    check(
        &with("type = \"spot\"", "type = \"area\""),
        "type = \"area\"",
        "lights[0].type",
        "unknown light type \"area\"",
    );
}

#[test]
fn cutoff_out_of_range() {
    check(
        &with("cutoff = 30.0", "cutoff = 95.0"),
        "cutoff = 95.0",
        "lights[0].cutoff",
        "(0, 90]",
    );
    check(
        &with("cutoff = 30.0", "cutoff = 0.0"),
        "cutoff = 0.0",
        "lights[0].cutoff",
        "(0, 90]",
    );
}

#[test]
fn sizes_out_of_range() {
    check(
        &with("width = 8", "width = 0"),
        "width = 0",
        "image.width",
        "1..=16384",
    );
    check(
        &with("height = 6", "height = 16385"),
        "height = 16385",
        "image.height",
        "1..=16384",
    );
    check(
        &with("height = 6", "height = 6\nsamples = 17"),
        "samples = 17",
        "image.samples",
        "1..=16",
    );
    check(
        &with("[camera]", "[render]\nmax_depth = 65\n\n[camera]"),
        "max_depth = 65",
        "render.max_depth",
        "1..=64",
    );
}

#[test]
fn keys_of_another_light_type() {
    let t = GOOD.replace("type = \"spot\"", "type = \"point\"");
    check(
        &t,
        "direction = [0.0, -1.0, 0.0]",
        "lights[0].direction",
        "does not apply to a point light",
    );
}

#[test]
fn mixed_camera_forms() {
    let t = with("vfov = 40.0", "vfov = 40.0\nscreen_up = [0.0, 1.0, 0.0]");
    check(
        &t,
        "look_at",
        "camera.look_at",
        "mixes the two camera forms",
    );
}

#[test]
fn syntax_error_names_the_line() {
    let t = with("radius = 1.0", "radius = = 1.0");
    let msg = error_of(&t);
    let line = line_of(&t, "radius = = 1.0");
    assert!(msg.starts_with(&format!("bad.toml:{line}:")), "{msg}");
}

#[test]
fn overrides_are_checked() {
    let o = Overrides {
        samples: Some(0),
        ..Overrides::default()
    };
    let e = parse(GOOD, Path::new("good.toml"), &o).unwrap_err();
    assert!(
        matches!(
            e,
            SceneError::Override {
                flag: "--samples",
                ..
            }
        ),
        "{e}"
    );
}

#[test]
fn defaults_follow_the_spec() {
    let s = parse(GOOD, Path::new("good.toml"), &Overrides::default()).unwrap();
    assert_eq!(
        (s.samples, s.max_depth, s.shadows, s.srgb),
        (1, 3, true, true)
    );
    assert_eq!(s.background, glam::DVec3::ZERO);
    let m = &s.materials[0];
    assert_eq!((m.shininess, m.reflectivity), (1.0, 0.0));
    // A spot light's own numbers (src/scene/light/spot.rs): its attenuation,
    // [1, 0, 0] by default, then the cosine of its cutoff and its exponent, 0.
    let cos_cutoff = 30f64.to_radians().cos();
    assert_eq!(
        s.lights[0].own,
        [1.0, 0.0, 0.0, 0.0, cos_cutoff, 0.0, 0.0, 0.0]
    );
    assert!(!s.lights[0].attenuated());
}

#[test]
fn look_at_camera_converts_to_a_screen_at_distance_one() {
    let s = parse(GOOD, Path::new("good.toml"), &Overrides::default()).unwrap();
    let c = s.camera;
    assert!(((c.screen_center - c.eye).length() - 1.0).abs() < 1e-12);
    let half = (20.0f64).to_radians().tan();
    assert!((c.screen_up.length() - half).abs() < 1e-12);
    assert!((c.screen_right.length() - half * 8.0 / 6.0).abs() < 1e-12);
}

/// A light type's own keys are read by its type (src/scene/light): a wrong
/// value is named by its key path at its own line, a number that is not
/// finite is refused, a missing key is named, and a key no type takes is
/// an unknown field at its line.
#[test]
fn a_light_types_own_keys_are_named_where_they_stand() {
    let cases = [
        (
            "cutoff = 30.0",
            "cutoff = \"x\"",
            "lights[0].cutoff",
            "invalid type",
        ),
        (
            "position = [0.0, 5.0, 0.0]",
            "position = [0.0, 5.0, \"a\"]",
            "lights[0].position[2]",
            "invalid type",
        ),
        (
            "cutoff = 30.0",
            "cutoff = nan",
            "lights[0].cutoff",
            "finite",
        ),
        (
            "cutoff = 30.0",
            "cutoff = 30.0\nbeam = 2.0",
            "lights[0].beam",
            "unknown field `beam`",
        ),
    ];
    for (from, to, key, words) in cases {
        let needle = to.lines().last().unwrap();
        check(&with(from, to), needle, key, words);
    }
    let t = with("cutoff = 30.0", "");
    let msg = error_of(&t);
    assert!(
        msg.contains("lights[0]: missing key `cutoff` (required for a spot light)"),
        "{msg}"
    );
}

/// A number past a few digits is in exponent form in its error: -1e300
/// printed in full was a 301-digit "got -1000…000", and -1e-300 a
/// 354-byte line.
#[test]
fn numbers_in_errors_are_short() {
    let cases = [
        ("radius = 1.0", "radius = -1e300", "got -1e300"),
        ("radius = 1.0", "radius = -1e-300", "got -1e-300"),
        ("vfov = 40.0", "vfov = 1e200", "got 1e200"),
        ("cutoff = 30.0", "cutoff = -2.5e-9", "got -2.5e-9"),
        (
            "cutoff = 30.0",
            "cutoff = 30.0\nexponent = -1e300",
            "got -1e300",
        ),
    ];
    for (from, to, words) in cases {
        let e = error_of(&with(from, to));
        assert!(e.contains(words), "{to}: {e}");
        assert!(e.len() < 200, "{to}: {} bytes: {e}", e.len());
    }
}
