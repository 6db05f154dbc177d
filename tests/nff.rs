//! NFF scenes (docs/scene-format.md, NFF): every entity read, `glint
//! convert` writing a TOML scene that renders the same image, errors that
//! name the NFF file and line, and corner sampling on both renderers.

#![cfg(feature = "gpu")]

mod common;

use std::path::Path;

use glint::cpu;
use glint::raster::diff::{figures, Tolerance};
use glint::scene::{parse_nff, Overrides, Scene};

/// Every NFF entity, both forms of `c`, lights with and without colour,
/// comments, a polygon with a collinear corner and a patch.
const EVERY_ENTITY: &str = "# every entity
b 0.1 0.2 0.3
v
from 0 -6 2
at 0 0 0.5
up 0 0 1
angle 40
hither 0.01
resolution 48 40
l 4 -3 6
l -4 -3 5 0.3 0.3 0.6   # a coloured light
f 0.9 0.8 0.2 0.7 0.3 20 0 1
p 5
-3 -3 0
0 -3 0
3 -3 0
3 3 0
-3 3 0
f 0.2 0.4 0.9 0.6 0.4 50 0.5 1.3
s -1 0 1 0.8
s 1.2 0.5 0.6 -0.6
f 0.8 0.3 0.3 0.8 0.2 10 0 0
c
-2 1.5 0 0.4
-2 1.5 1.5 0.1
c 2 -1 0 0.3 2 -1 1.2 0.3
pp 3
0 -1 0.01 0 0 1
1 -2 0.01 0.3 0 1
-1 -2 0.01 -0.3 0 1
";

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn every_entity_is_read_and_convert_renders_the_same_image() {
    let dir = tempfile::tempdir().unwrap();
    let nff = write(dir.path(), "every.nff", EVERY_ENTITY);
    let scene = Scene::load(&nff, &Overrides::default()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.prims.spheres.len(), 2);
    assert_eq!(scene.prims.cylinders.len(), 2);
    // The pentagon's fan has three triangles, one without area (its first
    // three corners lie on one line): two, and the patch's one.
    assert_eq!(scene.prims.triangles.len(), 3);
    assert!(scene.prims.triangles[2].normals.is_some());
    assert_eq!(scene.lights.len(), 2);
    assert_eq!(scene.materials.len(), 3);

    let toml = dir.path().join("every.toml");
    let o = common::glint(&[
        "convert",
        nff.to_str().unwrap(),
        "-o",
        toml.to_str().unwrap(),
    ]);
    common::assert_ok(&o);
    let converted = Scene::load(&toml, &Overrides::default()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(converted, scene);
    assert_eq!(
        cpu::render::<f32>(&converted).pixels,
        cpu::render::<f32>(&scene).pixels
    );
    // Converting over its own input is refused, and the input stays.
    let o = common::glint(&[
        "convert",
        nff.to_str().unwrap(),
        "-o",
        nff.to_str().unwrap(),
    ]);
    common::assert_user_error(&o, "refusing to overwrite an input");
    assert_eq!(std::fs::read_to_string(&nff).unwrap(), EVERY_ENTITY);
}

/// The GPU agrees with the reference on a corner-sampled NFF scene, and the
/// check can fail: the same scene sampled at the centres differs from it.
#[test]
fn corner_sampling_agrees_on_both_renderers() {
    let scene = parse_nff(EVERY_ENTITY, Path::new("every.nff"), &Overrides::default()).unwrap();
    let reference = cpu::render::<f64>(&scene);
    assert_eq!((reference.width, reference.height), (48, 40));
    let gpu = common::render_gpu(&scene);
    let f = figures(&gpu, &reference).unwrap();
    assert!(Tolerance::default().violations(&f).is_empty(), "{f:?}");
    let mut centres = scene.clone();
    centres.sampling = glint::scene::Sampling::Centers;
    let f = figures(&cpu::render::<f64>(&centres), &reference).unwrap();
    assert!(!Tolerance::default().violations(&f).is_empty(), "{f:?}");
}

#[test]
fn errors_name_the_nff_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    for (edit, line, words) in [
        // Read errors.
        (("s -1 0 1 0.8", "s -1 0 1"), 20, "expected 4 numbers"),
        (("hither 0.01", "hither"), 8, "v hither"),
        // Checks of the scene the NFF makes: named at the entity's line.
        (("s -1 0 1 0.8", "s -1 0 1 0"), 20, "radius"),
        (
            ("c 2 -1 0 0.3 2 -1 1.2 0.3", "c 2 -1 0 0.3 2 -1 0 0.3"),
            26,
            "no length",
        ),
        (
            (
                "0.2 0.4 0.9 0.6 0.4 50 0.5 1.3",
                "0.2 0.4 0.9 0.6 0.4 50 0.5 0",
            ),
            19,
            "ior",
        ),
        (("0 -1 0.01 0 0 1", "0 -1 0.01 0 0 0"), 27, "normals"),
    ] {
        let text = EVERY_ENTITY.replacen(edit.0, edit.1, 1);
        assert_ne!(text, EVERY_ENTITY, "{edit:?}");
        let path = write(dir.path(), "bad.nff", &text);
        let out = dir.path().join("out.png");
        let o = common::glint(&[
            "render",
            path.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--backend",
            "cpu",
        ]);
        common::assert_user_error(&o, &format!("bad.nff:{line}:"));
        common::assert_user_error(&o, words);
        assert!(!out.exists());
    }
}

/// `--stats` on both renderers: a camera inside a mirror sphere with a
/// light at its centre. Every eye ray hits, each hit reflects until the
/// depth ends, and every hit casts one shadow ray (the light is always in
/// front): the counts are known exactly, and every one of those rays tests
/// the one sphere once (one sphere takes no BVH), which `by_ray` puts down
/// to the ray's type. With corner sampling
/// there are (w+1)×(h+1) eye rays.
#[test]
fn stats_count_the_ray_tree() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write(
        dir.path(),
        "inside.toml",
        "[image]\nwidth = 20\nheight = 10\nsampling = \"corners\"\n[render]\nmax_depth = 4\n\
         [camera]\neye = [0.1, 0.2, 0.0]\nlook_at = [1.0, 0.0, 0.0]\nvfov = 60.0\n\
         [materials.mirror]\ndiffuse = [0.5, 0.5, 0.5]\nreflectivity = 1.0\n\
         [[spheres]]\ncenter = [0.0, 0.0, 0.0]\nradius = 3.0\nmaterial = \"mirror\"\n\
         [[lights]]\ntype = \"point\"\nposition = [0.0, 0.0, 0.0]\ndiffuse = [0.1, 0.1, 0.1]\n",
    );
    for backend in ["cpu", "gpu"] {
        let stats = dir.path().join(format!("{backend}.json"));
        let o = common::glint(&[
            "render",
            scene.to_str().unwrap(),
            "-o",
            dir.path().join(format!("{backend}.png")).to_str().unwrap(),
            "--backend",
            backend,
            "--stats",
            stats.to_str().unwrap(),
        ]);
        common::assert_ok(&o);
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
        let rays = &json["rays"];
        let eye = 21 * 11;
        assert_eq!(rays["eye"], eye, "{backend}");
        assert_eq!(rays["eye_hit"], eye, "{backend}");
        assert_eq!(rays["reflect"], eye * 3, "{backend}");
        assert_eq!(rays["refract"], 0, "{backend}");
        assert_eq!(rays["shadow"], eye * 4, "{backend}");
        let tests = &json["tests"];
        assert_eq!(tests["spheres"], eye * (1 + 3 + 4), "{backend}: {json}");
        // Each ray type tests the sphere once a ray.
        for (ray, n) in [("eye", 1), ("reflect", 3), ("refract", 0), ("shadow", 4)] {
            let work = &json["by_ray"][ray];
            assert_eq!(work["rays"], eye * n, "{backend} {ray}: {json}");
            assert_eq!(work["tests"]["spheres"], eye * n, "{backend} {ray}: {json}");
        }
        for none in ["triangles", "cylinders", "planes", "bvh_nodes"] {
            assert_eq!(tests[none], 0, "{backend}: {json}");
        }
        for part in ["input", "setup", "trace"] {
            assert!(
                json["seconds"][part].as_f64().is_some_and(|s| s >= 0.0),
                "{json}"
            );
        }
    }
}
