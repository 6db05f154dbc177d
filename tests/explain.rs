//! `glint explain`: one pixel's ray tree on every renderer, down to the
//! first number that differs. Each test checks a real explanation: a
//! near-tie and a self-intersection named in words, a scene that agrees, a
//! lane broken on purpose named at its first wrong value; and the recording
//! variant costs nothing where it is not asked for.

#![cfg(feature = "gpu")]

mod common;

use std::path::{Path, PathBuf};

use serde_json::Value;

use glint::gpu::compile::{compile, Sources};
use glint::gpu::{RenderSettings, Schedule};
use glint::scene::{Overrides, Scene};
use glint::settings::{Intersect, Precision};

/// Two spheres whose fronts lie 1e-7 apart: in f32 their centres round to
/// the same point, so every ray meets both at one distance and the tie goes
/// to the earlier, sphere 0 (red), which f64 puts behind sphere 1 (green).
const NEAR_TIE: &str = r#"
[image]
width = 32
height = 24
samples = 1

[render]
max_depth = 1
background = [0.2, 0.2, 0.3]

[camera]
eye = [0.0, 0.0, 0.0]
look_at = [0.0, 0.0, -1.0]
up = [0.0, 1.0, 0.0]
vfov = 30.0

[materials.red]
ambient = [0.1, 0.0, 0.0]
diffuse = [0.9, 0.0, 0.0]

[materials.green]
ambient = [0.0, 0.1, 0.0]
diffuse = [0.0, 0.9, 0.0]

[[spheres]]
center = [0.0, 0.0, -5.0000001]
radius = 1.0
material = "red"

[[spheres]]
center = [0.0, 0.0, -5.0]
radius = 1.0
material = "green"

[[lights]]
type = "point"
position = [0.0, 5.0, 0.0]
diffuse = [1.0, 1.0, 1.0]
"#;

/// A planet of radius 8000 whose top the camera looks at from 1 unit
/// above: its hit points are about 8000 from the origin, where f32 rounds
/// them by about 5e-4, past the naive forms' fixed epsilon of 1e-4; a
/// shadow ray from a point rounded inside meets the planet again at once.
const SELF_SHADOW: &str = r#"
[image]
width = 64
height = 48
samples = 1

[render]
max_depth = 1
background = [0.2, 0.2, 0.3]

[camera]
eye = [0.0, 8001.0, 0.0]
look_at = [0.0, 8000.0, -3.0]
up = [0.0, 1.0, 0.0]
vfov = 40.0

[materials.ground]
ambient = [0.1, 0.1, 0.1]
diffuse = [0.8, 0.8, 0.8]

[[spheres]]
center = [0.0, 0.0, 0.0]
radius = 8000.0
material = "ground"

[[lights]]
type = "point"
position = [2.0, 8010.0, -2.0]
diffuse = [1.0, 1.0, 1.0]
specular = [1.0, 1.0, 1.0]
"#;

fn write_scene(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn explain(args: &[&str]) -> std::process::Output {
    common::cmd()
        .current_dir(common::repo())
        .arg("explain")
        .args(args)
        .output()
        .unwrap()
}

fn stdout(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The issue's first check: seed-fig5's pixel 400,300 has the same tree on
/// the GPU and on both CPU renderers, and the command says so.
#[test]
fn a_scene_that_compares_well_has_every_tree_agree() {
    let o = explain(&["scenes/seed-fig5.toml", "--pixel", "400,300"]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let text = stdout(&o);
    assert!(text.contains("every tree agrees"), "{text}");
    for column in ["gpu f32", "cpu f32", "cpu f64"] {
        assert!(text.contains(column), "{column}: {text}");
    }
    assert!(
        !text.contains(" *"),
        "a value is marked as past its bound: {text}"
    );
    // The JSON has the three trees, each ray with its origin and direction.
    let o = explain(&["scenes/seed-fig5.toml", "--pixel", "400,300", "--json"]);
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["agree"], true);
    let trees = v["samples"][0]["trees"].as_array().unwrap();
    assert_eq!(trees.len(), 3);
    for t in trees {
        let eye = &t["rays"][0];
        assert_eq!(eye["type"], "eye");
        assert_eq!(eye["origin"].as_array().unwrap().len(), 3);
        assert_eq!(eye["direction"].as_array().unwrap().len(), 3);
        assert_eq!(eye["hit"]["primitive"]["kind"], "sphere");
    }
}

#[test]
fn a_near_tie_names_both_spheres_and_calls_it_one() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "tie.toml", NEAR_TIE);
    let o = explain(&[scene.to_str().unwrap(), "--pixel", "16,12"]);
    assert_eq!(
        o.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let text = stdout(&o);
    let verdict = text.lines().last().unwrap();
    assert!(
        verdict.contains("first divergence at ray 1: hit")
            && verdict.contains("the eye ray hits sphere 1 on the CPU and sphere 0 on the GPU")
            && verdict.contains("within f32 rounding of each other (a near-tie)"),
        "{verdict}"
    );
    // The distances it quotes are the trees' own.
    let o = explain(&[scene.to_str().unwrap(), "--pixel", "16,12", "--json"]);
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    let s = &v["samples"][0];
    let (gpu, cpu) = (
        &s["trees"][0]["rays"][0]["hit"],
        &s["trees"][2]["rays"][0]["hit"],
    );
    assert_eq!(gpu["primitive"]["index"], 0);
    assert_eq!(cpu["primitive"]["index"], 1);
    let (tg, tc) = (
        gpu["distance"].as_f64().unwrap(),
        cpu["distance"].as_f64().unwrap(),
    );
    assert!(
        (tg - tc).abs() < 1e-5 && (tg - tc).abs() <= 4.0 * f64::from(f32::EPSILON) * tc,
        "{tg} {tc}"
    );
    assert_eq!(s["divergences"][0]["quantity"], "ray 1: hit");
    assert_eq!(s["divergences"][0]["ill_conditioned"], true);
}

/// The issue's compare check and self-intersection together: under the
/// naive forms the planet shadows itself in speckles, compare fails, and
/// each of its three worst pixels is explained as the shadow ray to light 0
/// blocked by sphere 0 at a tiny t.
#[test]
fn compare_explains_its_worst_pixels_and_names_a_self_intersection() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "self.toml", SELF_SHADOW);
    let o = common::cmd()
        .args([
            "compare",
            scene.to_str().unwrap(),
            "--intersect",
            "naive",
            "--explain",
            "3",
            "--json",
        ])
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["pass"], false);
    let explained = v["explanations"].as_array().unwrap();
    assert_eq!(explained.len(), 3, "three pixels of one sample each");
    for e in explained {
        let d = &e["divergences"][0];
        let cause = d["cause"].as_str().unwrap();
        assert_eq!(d["quantity"], "ray 1, light 0: shadow ray", "{cause}");
        assert!(
            cause
                .starts_with("the shadow ray to light 0 is blocked on the GPU by sphere 0 at t = ")
                && cause.contains("(self-intersection)"),
            "{cause}"
        );
        let gpu = &e["trees"][0]["rays"][0];
        let shadow = &gpu["lights"][0]["shadow_ray"];
        let t = shadow["blocker"]["distance"].as_f64().unwrap();
        assert!(t > 0.0 && t < 1e-2, "t = {t}: not a tiny t");
        assert_eq!(
            e["trees"][2]["rays"][0]["lights"][0]["shadow_ray"]["blocked"],
            false
        );
    }
    // And as text: the table, then the verdict, for each.
    let o = common::cmd()
        .args([
            "compare",
            scene.to_str().unwrap(),
            "--intersect",
            "naive",
            "--explain",
            "1",
        ])
        .output()
        .unwrap();
    let text = stdout(&o);
    assert!(
        text.contains("explain    the 1 worst pixel(s)") && text.contains("(self-intersection)"),
        "{text}"
    );
}

/// A lane broken on purpose, as a user's include might break it: a
/// specular term twice what it should be. The explanation stops at that
/// term of the first lit hit, not at the colours it spoils later.
#[test]
fn a_broken_lane_is_named_at_its_first_wrong_value() {
    let dir = tempfile::tempdir().unwrap();
    let shipped = std::fs::read_to_string(common::repo().join("shaders/specular.glsl")).unwrap();
    let broken = shipped.replacen("return ", "return 2.0 * ", 1);
    assert_ne!(broken, shipped);
    std::fs::write(dir.path().join("specular.glsl"), broken).unwrap();
    let o = explain(&[
        "scenes/seed-fig5.toml",
        "--pixel",
        "400,300",
        "-I",
        dir.path().to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(
        o.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    let d = &v["samples"][0]["divergences"][0];
    assert_eq!(d["quantity"], "ray 1, light 0: specular", "{d}");
    assert!(d["stage"].as_str().unwrap().starts_with("shade"), "{d}");
    let cause = d["cause"].as_str().unwrap();
    assert!(
        cause.contains("past its f32 bound") && !cause.contains("near-tie"),
        "{cause}"
    );
}

/// `--icd` runs another driver in a child, as `glint drivers` does: its
/// tree is a column of its own, beside this process's device.
#[test]
fn another_driver_in_a_child_is_its_own_column() {
    let Some(old) = common::old_lavapipe() else {
        common::skip(
            "another driver's column",
            "Debian 12's lavapipe is needed (ci/old-lavapipe)",
        );
        return;
    };
    let o = explain(&[
        "scenes/seed-fig5.toml",
        "--width",
        "64",
        "--height",
        "48",
        "--pixel",
        "32,24",
        "--icd",
        old.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    let s = &v["samples"][0];
    let trees = s["trees"].as_array().unwrap();
    let names: Vec<&str> = trees
        .iter()
        .map(|t| t["renderer"].as_str().unwrap())
        .collect();
    assert_eq!(names[0], "gpu f32");
    assert!(names[1].starts_with("gpu f32 on llvmpipe"), "{names:?}");
    assert_eq!(&names[2..], ["cpu f32", "cpu f64"]);
    assert_eq!(s["divergences"].as_array().unwrap().len(), 2);
    assert_eq!(v["agree"], true, "{s}");
}

#[test]
fn bad_input_gets_one_line_and_status_2() {
    let dir = tempfile::tempdir().unwrap();
    let adaptive = write_scene(
        dir.path(),
        "adaptive.toml",
        &NEAR_TIE.replace("samples = 1", "samples = 1\nsampling = \"adaptive\""),
    );
    let empty = write_scene(
        dir.path(),
        "empty.toml",
        "[image]\nwidth = 8\nheight = 8\n\n[camera]\neye = [0.0, 0.0, 0.0]\nlook_at = [0.0, 0.0, -1.0]\nvfov = 40.0\n",
    );
    let fig5 = "scenes/seed-fig5.toml";
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec![fig5, "--pixel", "800,10"],
            "pixel 800,10 is outside the 800x600 image",
        ),
        (
            vec![fig5, "--pixel", "1,1", "--sample", "1"],
            "sample 1 is past the pixel's 1 samples",
        ),
        (
            vec![fig5, "--pixel", "1,1", "--samples", "2", "--sample", "4"],
            "sample 4 is past the pixel's 4 samples (a 2x2 grid)",
        ),
        (
            vec![adaptive.to_str().unwrap(), "--pixel", "1,1"],
            "samples adaptively",
        ),
        (
            vec![empty.to_str().unwrap(), "--pixel", "1,1"],
            "the scene has no primitives",
        ),
        (
            vec![fig5, "--pixel", "1,1", "-D", "COUNT_RAYS"],
            "-D COUNT_RAYS: glint defines COUNT_RAYS itself",
        ),
    ];
    let o = explain(&[fig5, "--pixel", "10"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("a pixel is X,Y"));
    for (args, words) in cases {
        let o = explain(&args);
        common::assert_user_error(&o, words);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(o.stdout.is_empty(), "{args:?}: printed {}", stdout(&o));
    }
}

/// A scene the GPU cannot render is refused in one line, before any tree.
#[test]
fn a_scene_the_gpu_cannot_render_is_one_line() {
    let o = explain(&[
        "scenes/seed-fig5.toml",
        "--pixel",
        "1,1",
        "--shader",
        "/nonexistent/main.comp",
    ]);
    common::assert_user_error(&o, "--shader /nonexistent/main.comp: no such file");
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("shade.glsl"), "this is not GLSL\n").unwrap();
    let o = explain(&[
        "scenes/seed-fig5.toml",
        "--pixel",
        "1,1",
        "-I",
        dir.path().to_str().unwrap(),
    ]);
    common::assert_user_error(&o, "the shader does not compile");
}

fn small(name: &str) -> Scene {
    let o = Overrides {
        width: Some(48),
        height: Some(36),
        ..Overrides::default()
    };
    Scene::load(&common::repo().join(name), &o).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Scenes that reach every hook: reflection (seed-fig5), refraction and its
/// stack (glass), textures and image uvs (textures), several kinds through
/// the BVH (rings), corners (the SPD's sampling).
const HOOKED: &[&str] = &[
    "scenes/seed-fig5.toml",
    "scenes/glass.toml",
    "scenes/textures.toml",
    "scenes/spd/rings.nff",
];

/// The recording variant renders the plain variant's bits: recording only
/// writes beside the image. Run on both drivers by CI's two lanes.
#[test]
fn the_recording_variant_renders_the_same_bits() {
    let mut r = common::gpu();
    for name in HOOKED {
        let scene = small(name);
        let plain = r.settings();
        let traced = scene
            .corner_grid()
            .map_or((scene.width, scene.height), |g| (g.width, g.height));
        let recording = RenderSettings {
            record: Some([traced.0 / 2, traced.1 / 2, 0, 0]),
            schedule: Schedule::Megakernel,
            ..plain
        };
        let a = r
            .prepare(&scene, &plain)
            .unwrap()
            .render(None, &|_| {})
            .unwrap();
        let mut p = r.prepare(&scene, &recording).unwrap();
        assert!(p.variant().record, "{name}: not the recording variant");
        let b = p.render(None, &|_| {}).unwrap();
        assert!(
            common::same_bits(&a.image, &b.image),
            "{name}: recording changed the image"
        );
        let words = b.record.expect("a record");
        assert!(words[4] > 0, "{name}: the sample recorded nothing");
        assert!(a.record.is_none());
    }
}

/// `text` with the includes of record.glsl and aov.glsl and every hook's
/// statement (to its `;`, over as many lines as it takes) cut out.
fn without_hooks(text: &str) -> String {
    let mut out = String::new();
    let mut in_hook = false;
    for line in text.lines() {
        if line.contains("\"record.glsl\"") || line.contains("\"aov.glsl\"") {
            continue;
        }
        let hook = line.trim_start();
        in_hook |= hook.starts_with("RECORD_") || hook.starts_with("AOV_");
        if !in_hook {
            out.push_str(line);
            out.push('\n');
        }
        in_hook &= !line.trim_end().ends_with(';');
    }
    out
}

/// The plain variants compile to the same SPIR-V with the record's and
/// the AOVs' hooks cut out of the sources: recording and AOVs cost nothing
/// where they are not asked for. The recording variant's differs (the hooks reach the shader).
#[test]
fn the_plain_variants_spirv_is_unchanged_by_the_hooks() {
    let dir = tempfile::tempdir().unwrap();
    for file in ["main.comp", "shade.glsl", "trace.glsl"] {
        let text = std::fs::read_to_string(common::repo().join("shaders").join(file)).unwrap();
        let cut = without_hooks(&text);
        assert_ne!(cut, text, "{file} has no hook");
        std::fs::write(dir.path().join(file), cut).unwrap();
    }
    let stripped = Sources {
        dirs: vec![dir.path().to_owned()],
        ..Sources::default()
    };
    let r = common::gpu();
    let mut compared = 0;
    for name in HOOKED {
        let scene = small(name);
        for settings in [
            r.settings(),
            RenderSettings {
                generic: true,
                ..r.settings()
            },
            RenderSettings {
                count: true,
                ..r.settings()
            },
            RenderSettings {
                intersect: Intersect::Naive,
                ..r.settings()
            },
            RenderSettings {
                precision: Precision::F64,
                ..r.settings()
            },
            RenderSettings {
                schedule: Schedule::Wavefront,
                ..r.settings()
            },
        ] {
            let (variant, defines) = r.variant(&scene, &settings);
            let shipped = compile(&Sources::default().for_variant(&variant), &defines)
                .unwrap()
                .spirv;
            let cut = compile(&stripped.for_variant(&variant), &defines)
                .unwrap()
                .spirv;
            assert!(
                shipped == cut,
                "{name}, {}: the hooks change the plain SPIR-V",
                variant.name()
            );
            compared += 1;
        }
        let recording = RenderSettings {
            record: Some([0, 0, 0, 0]),
            ..r.settings()
        };
        let (variant, defines) = r.variant(&scene, &recording);
        let with = compile(&Sources::default().for_variant(&variant), &defines)
            .unwrap()
            .spirv;
        let plain = {
            let (v, d) = r.variant(&scene, &r.settings());
            compile(&Sources::default().for_variant(&v), &d)
                .unwrap()
                .spirv
        };
        assert!(
            with != plain,
            "{name}: the recording variant is the plain one"
        );
    }
    assert_eq!(compared, HOOKED.len() * 6);
}

/// `explain --icd` took a folder (with an `apt-get install`
/// hint) or a FIFO (waiting 20 s on it). It refuses both up front now, as
/// `drivers --icd` does, before the device is opened.
#[test]
fn explain_refuses_an_icd_that_is_not_a_file() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("icd.json");
    common::make_fifo(&fifo);
    let scene = common::repo().join("scenes/seed-fig3.toml");
    for icd in [dir.path().to_path_buf(), fifo] {
        let started = std::time::Instant::now();
        let o = common::glint(&[
            "explain",
            scene.to_str().unwrap(),
            "--pixel",
            "1,1",
            "--icd",
            icd.to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.contains("--icd") && !err.contains("apt-get"), "{err}");
        assert!(started.elapsed().as_secs() < 10, "{err}");
    }
}

/// `glint explain` of pixel (x, y) of `scene`, with `extra` arguments.
fn explain_pixel(scene: &Path, (x, y): (u32, u32), extra: &[&str]) -> std::process::Output {
    let pixel = format!("{x},{y}");
    let mut args = vec!["explain", scene.to_str().unwrap(), "--pixel", &pixel];
    args.extend(extra);
    common::glint(&args)
}

/// Explain judged the tree the recording variant records, never
/// the pixel the plain variant writes. A main shader that records every
/// ray but stores half the colour failed `compare` while `explain` said
/// "every tree agrees". The recorded samples' mean is held to the plain
/// pixel now: a difference is a divergence of its own, exit status 1; the
/// same shader storing the whole colour still agrees.
#[test]
fn explain_holds_the_recorded_tree_to_the_pixel_the_render_wrote() {
    let dir = tempfile::tempdir().unwrap();
    let main = std::fs::read_to_string(common::repo().join("shaders/main.comp")).unwrap();
    let store = "vec3(sum * (1.0 / real(samples * samples)))";
    assert!(main.contains(store), "main.comp stores the pixel's mean");
    let scene = common::repo().join("scenes/seed-fig5.toml");
    let small = ["--width", "32", "--height", "24", "--samples", "2"];
    for (halved, status) in [(false, 0), (true, 1)] {
        let file = dir
            .path()
            .join(if halved { "half.comp" } else { "whole.comp" });
        let text = if halved {
            main.replace(store, &format!("0.5 * {store}"))
        } else {
            main.clone()
        };
        std::fs::write(&file, text).unwrap();
        let mut args = vec!["--shader", file.to_str().unwrap()];
        args.extend(small);
        let o = explain_pixel(&scene, (16, 12), &args);
        let out = String::from_utf8_lossy(&o.stdout);
        assert_eq!(
            o.status.code(),
            Some(status),
            "{out}\n{}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert_eq!(
            out.contains("the render differs from its recorded tree"),
            halved,
            "{out}"
        );
    }
}

/// `explain --generic` said the trees part where the GPU records
/// a hit's uv and the CPU does not, on 4 of 5 stock scenes whose generic
/// image is the variant's: the generic shader holds the images' code for
/// every scene, and recorded uvs for every hit. It records them where the
/// scene has image textures now, as the CPU does, and each agrees.
#[test]
fn explain_generic_agrees_where_the_generic_image_does() {
    for name in ["seed-fig3", "seed-fig5", "glass", "textures", "triangles"] {
        let scene = common::repo().join(format!("scenes/{name}.toml"));
        let o = explain_pixel(
            &scene,
            (30, 20),
            &["--generic", "--width", "60", "--height", "45"],
        );
        let out = String::from_utf8_lossy(&o.stdout);
        assert_eq!(o.status.code(), Some(0), "{name}: {out}");
        assert!(out.contains("every tree agrees"), "{name}: {out}");
    }
}

/// `explain -I DIR` with glint's own normals experiment, which
/// replaces trace.glsl, blamed "a main shader of your own" though main.comp
/// was glint's. The message names the include that records nothing.
#[test]
fn explain_names_the_include_that_records_nothing() {
    let dir = common::repo().join("shaders/experiments/normals");
    let o = explain_pixel(
        &common::repo().join("scenes/seed-fig5.toml"),
        (40, 30),
        &[
            "--width",
            "80",
            "--height",
            "60",
            "-I",
            dir.to_str().unwrap(),
        ],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("normals/trace.glsl replaces glint's file"),
        "{err}"
    );
    assert!(!err.contains("main shader of your own"), "{err}");
}

/// `explain` of one pixel whose tree has hundreds of rays held
/// every trial's tree at once (0.7-1 GB in the issue's scene) and printed
/// every ray (14.6 MB for this one's 549 rays). It folds the trials into the bounds one at a time and prints
/// the first ray, the path to each first divergence and a line for the
/// rest: a few hundred lines, where `--json` still holds every ray.
#[test]
fn explain_of_a_deep_tree_prints_a_summary() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("nested.toml");
    std::fs::write(&scene, common::nested_glass(11)).unwrap();
    let o = explain_pixel(&scene, (0, 0), &[]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(
        out.contains("more rays, 2 to 11 deep, are not shown"),
        "{out}"
    );
    assert!(out.lines().count() < 400, "{} lines", out.lines().count());
    let json = explain_pixel(&scene, (0, 0), &["--json"]);
    let v: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    let rays = v["samples"][0]["trees"][0]["rays"]
        .as_array()
        .map_or(0, Vec::len);
    assert!(rays > 100, "{rays} rays in the JSON");
}
