//! How the shader reads the scene (src/gpu/access.rs) changes how fast,
//! never what: texel buffers (the default outside uniform blocks), storage
//! buffers (where an array is longer than a texel buffer can be), device
//! addresses (an experiment), and the small tables in uniform blocks or
//! not, each render the same bits, under the validation layer. The forms
//! are chosen through `GLINT_EXPERIMENT` (src/gpu/variant.rs), so each
//! render is its own run of the binary.

#![cfg(feature = "gpu")]

mod common;

use std::path::Path;

/// The BVH scenes of every bounded kind, a scene whose arrays fit uniform
/// blocks (seed-fig4), and image textures (texels and uvs).
const SCENES: &[&str] = &[
    "scenes/seed-fig4.toml",
    "scenes/triangles.toml",
    "scenes/glass.toml",
    "scenes/textures.toml",
    "scenes/spd/rings.nff",
];

/// A 48x36 render of `scene` with `experiment`, as a PFM's bytes; with
/// `f64`, in f64.
fn render(scene: &str, experiment: &str, f64: bool, dir: &Path) -> Vec<u8> {
    let out = dir.join(format!(
        "{}-{experiment}-{f64}.pfm",
        scene.replace('/', "_")
    ));
    let path = common::repo().join(scene);
    let mut args = vec![
        "render",
        path.to_str().unwrap(),
        "--width",
        "48",
        "--height",
        "36",
        "-o",
        out.to_str().unwrap(),
        "--force",
    ];
    if f64 {
        args.extend(["--precision", "f64"]);
    }
    let o = common::cmd()
        .env("GLINT_EXPERIMENT", experiment)
        .args(&args)
        .output()
        .expect("run glint");
    common::assert_ok(&o);
    std::fs::read(&out).unwrap()
}

/// The variant's name for `scene` under `experiment`, from `shader dump`.
fn variant(scene: &str, experiment: &str, dir: &Path) -> String {
    let out = dir.join(format!("dump-{}-{experiment}", scene.replace('/', "_")));
    let path = common::repo().join(scene);
    let o = common::cmd()
        .env("GLINT_EXPERIMENT", experiment)
        .args(["shader", "dump", path.to_str().unwrap(), "-o"])
        .arg(&out)
        .output()
        .expect("run glint");
    common::assert_ok(&o);
    let names: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".comp"))
        .collect();
    assert_eq!(names.len(), 1, "{names:?}");
    names[0].clone()
}

/// The word of the variant's name that `experiment` puts there: the read
/// form it asks for, so that a test of it fails where the form is not the
/// one read.
fn form_word(experiment: &str) -> Option<&'static str> {
    match experiment {
        "address-reads" => Some("-address-"),
        "texel-reads" => Some("-texels-"),
        _ => None,
    }
}

fn same_bits_with(experiment: &str, f64: bool) {
    let dir = tempfile::tempdir().unwrap();
    // The form asked for is the form read, where a scene reads any array
    // outside uniform blocks (teapot).
    if let Some(word) = form_word(experiment) {
        let name = variant("scenes/spd/teapot.nff", experiment, dir.path());
        assert!(name.contains(word), "{experiment}: {name}");
    }
    if experiment == "storage-reads" {
        let name = variant("scenes/spd/teapot.nff", experiment, dir.path());
        assert!(
            !name.contains("-texels-") && !name.contains("-address-"),
            "{name}"
        );
    }
    for scene in SCENES {
        let shipped = render(scene, "", f64, dir.path());
        let other = render(scene, experiment, f64, dir.path());
        assert!(shipped == other, "{scene}: {experiment} changed the image");
    }
}

#[test]
fn the_large_arrays_are_texel_buffers_by_default() {
    let dir = tempfile::tempdir().unwrap();
    let name = variant("scenes/spd/teapot.nff", "", dir.path());
    assert!(name.contains("-texels-"), "{name}");
    let name = variant("scenes/spd/teapot.nff", "storage-reads", dir.path());
    assert!(!name.contains("-texels-"), "{name}");
    // The small tables stay uniform blocks (where the scene has spheres:
    // Mesa 22.3 crashed on sphere-less uniform variants), on a driver that
    // reads uniform buffers safely: llvmpipe before Mesa 25.0 takes none
    // (it corrupted its heap on them).
    let uniforms = common::gpu().device_info().reads_uniform_arrays;
    let name = variant("scenes/spd/balls.nff", "", dir.path());
    assert!(
        name.contains("-texels-") && name.contains("-tables-") == uniforms,
        "{name}"
    );
    // A scene whose arrays fit uniform blocks keeps them there.
    let name = variant("scenes/seed-fig4.toml", "", dir.path());
    assert_eq!(name.contains("-ubo-"), uniforms, "{name}");
}

#[test]
fn storage_buffers_read_what_texel_buffers_read() {
    same_bits_with("storage-reads", false);
}

#[test]
fn device_addresses_read_what_texel_buffers_read() {
    same_bits_with("address-reads", false);
}

#[test]
fn the_tables_read_the_same_outside_uniform_blocks() {
    same_bits_with("no-uniform-tables", false);
}

#[test]
fn doubles_are_rebuilt_from_their_texels_bit_for_bit() {
    same_bits_with("storage-reads", true);
}
