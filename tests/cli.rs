//! The `glint` binary run as a user runs it: exit codes, files written,
//! JSON parsed, errors on stderr. GPU runs use the validation layer.

#![cfg(feature = "gpu")]

mod common;

use std::path::{Path, PathBuf};

use glint::raster::io;
use predicates::prelude::*;
use predicates::str::contains;

use common::{cmd, json_of};

fn scene_path(name: &str) -> String {
    common::repo()
        .join("scenes")
        .join(name)
        .display()
        .to_string()
}

fn tmp() -> tempfile::TempDir {
    tempfile::tempdir().expect("temp dir")
}

fn p(dir: &Path, name: &str) -> PathBuf {
    dir.join(name)
}

#[test]
fn render_writes_png_pfm_and_exr() {
    let dir = tmp();
    let scene = scene_path("seed-fig4.toml");
    for ext in ["png", "pfm", "exr"] {
        let out = p(dir.path(), &format!("a.{ext}"));
        cmd()
            .args(["render", &scene, "--width", "80", "--height", "60", "-o"])
            .arg(&out)
            .assert()
            .success();
        let img = io::read(&out).expect("reads back");
        assert_eq!((img.width, img.height), (80, 60), "{ext}");
    }
    // The PNG holds the float image quantized after the sRGB curve, and
    // reads back decoded: within half a level through the curve's
    // steepest decoding (2.4 / 1.055); the EXR holds it exactly.
    let pfm = io::read(&p(dir.path(), "a.pfm")).unwrap();
    let exr = io::read(&p(dir.path(), "a.exr")).unwrap();
    assert_eq!(pfm, exr);
    let png = io::read(&p(dir.path(), "a.png")).unwrap();
    for (a, b) in png.pixels.iter().zip(&pfm.pixels) {
        for c in 0..3 {
            assert!((a[c] - b[c].clamp(0.0, 1.0)).abs() <= 0.5 / 255.0 * 2.4 / 1.055 + 1e-6);
        }
    }
}

#[test]
fn pfm_is_standard_bottom_to_top_little_endian() {
    let dir = tmp();
    let out = p(dir.path(), "ref.pfm");
    let scene = scene_path("seed-fig3.toml");
    cmd()
        .args(["render", &scene, "--backend", "cpu"])
        .args(["--width", "40", "--height", "30", "-o"])
        .arg(&out)
        .assert()
        .success();
    let bytes = std::fs::read(&out).unwrap();
    assert!(bytes.starts_with(b"PF\n40 30\n-1.0\n"));
    assert_eq!(bytes.len(), "PF\n40 30\n-1.0\n".len() + 40 * 30 * 12);
    // The first stored row is the image's bottom row.
    let scene = glint::scene::Scene::load(
        Path::new(&scene),
        &glint::scene::Overrides {
            width: Some(40),
            height: Some(30),
            ..Default::default()
        },
    )
    .unwrap();
    let reference = glint::cpu::render::<f64>(&scene);
    let header = "PF\n40 30\n-1.0\n".len();
    let first = f32::from_le_bytes(bytes[header..header + 4].try_into().unwrap());
    assert_eq!(first, reference.get(0, 29)[0]);
    assert_eq!(io::read(&out).unwrap(), reference);
}

#[test]
fn compare_json_passes_on_a_seed_scene() {
    let run = cmd()
        .args(["compare", &scene_path("seed-fig4.toml")])
        .args(["--width", "160", "--height", "120", "--json"])
        .assert()
        .code(0);
    let v = json_of(&run);
    assert_eq!(v["pass"], true);
    for key in ["max_abs", "rmse", "psnr_db", "frac_over_1_255", "nonfinite"] {
        assert!(
            v["gpu_f32"]["error"].get(key).is_some(),
            "missing {key}: {v}"
        );
    }
    assert!(v["gpu_f32"]["seconds"].as_f64().unwrap() > 0.0);
    assert!(v["cpu_f64"]["seconds"].as_f64().unwrap() > 0.0);
    assert!(v["gpu_f32"]["first_render_s"].as_f64().unwrap() > 0.0);
    assert!(v["setup"]["compile_s"].as_f64().unwrap() >= 0.0);
}

#[test]
fn compare_exits_1_when_the_shader_is_wrong() {
    // A shade.glsl that adds a little light everywhere: the GPU no longer
    // agrees with the reference, and compare must say so.
    let dir = tmp();
    let shade = std::fs::read_to_string(common::repo().join("shaders/shade.glsl")).unwrap();
    let broken = shade.replace("    return local;", "    return local + vec3(0.05);");
    assert_ne!(shade, broken);
    std::fs::write(p(dir.path(), "shade.glsl"), broken).unwrap();
    let heat = p(dir.path(), "heat.png");
    cmd()
        .args(["compare", &scene_path("seed-fig3.toml")])
        .args(["--width", "80", "--height", "60", "-I"])
        .arg(dir.path())
        .arg("--diff-out")
        .arg(&heat)
        .assert()
        .code(1)
        .stdout(contains("FAIL"));
    assert!(heat.exists());
}

#[test]
fn diff_reports_figures_for_two_files() {
    let dir = tmp();
    let a = p(dir.path(), "a.pfm");
    let b = p(dir.path(), "b.pfm");
    let scene = scene_path("seed-fig3.toml");
    for (out, backend) in [(&a, "gpu"), (&b, "cpu")] {
        cmd()
            .args(["render", &scene, "--width", "64", "--height", "48"])
            .args(["--backend", backend, "-o"])
            .arg(out)
            .assert()
            .success();
    }
    let diff = |x: &Path, y: &Path| {
        let run = cmd()
            .arg("diff")
            .arg(x)
            .arg(y)
            .arg("--json")
            .assert()
            .success();
        json_of(&run)
    };
    let v = diff(&a, &b);
    assert!(v["max_abs"].as_f64().unwrap() > 0.0);
    assert!(v["max_abs"].as_f64().unwrap() < 0.01);
    assert_eq!(v["nonfinite"], 0);
    let v = diff(&a, &a);
    assert_eq!(v["max_abs"], 0.0);
    assert!(v["psnr_db"].is_null());
}

#[test]
fn a_bad_scene_is_one_clear_error_and_leaves_the_output_alone() {
    let dir = tmp();
    let scene = p(dir.path(), "bad.toml");
    let text = std::fs::read_to_string(scene_path("seed-fig3.toml"))
        .unwrap()
        .replacen("radius = 6.0", "radius = -6.0", 1);
    std::fs::write(&scene, &text).unwrap();
    let out = p(dir.path(), "out.png");
    std::fs::write(&out, b"the previous image").unwrap();
    let line = text
        .lines()
        .position(|l| l.contains("radius = -6.0"))
        .unwrap()
        + 1;
    cmd()
        .arg("render")
        .arg(&scene)
        .arg("-o")
        .arg(&out)
        .assert()
        .code(2)
        .stderr(
            contains(format!("bad.toml:{line}:"))
                .and(contains("spheres[0].radius"))
                .and(common::one_line())
                .and(contains("panicked").not())
                .and(contains("backtrace").not()),
        );
    assert_eq!(std::fs::read(&out).unwrap(), b"the previous image");
    // No temporary file is left behind either.
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");
}

#[test]
fn user_errors_exit_2_without_a_panic() {
    let dir = tmp();
    let missing = p(dir.path(), "missing.toml");
    let cases: Vec<Vec<String>> = vec![
        vec!["render".into(), missing.display().to_string()],
        vec![
            "render".into(),
            scene_path("seed-fig3.toml"),
            "-o".into(),
            p(dir.path(), "x.jpg").display().to_string(),
        ],
        vec![
            "render".into(),
            scene_path("seed-fig3.toml"),
            "--samples".into(),
            "0".into(),
        ],
        vec![
            "render".into(),
            scene_path("seed-fig3.toml"),
            "--device".into(),
            "no such device".into(),
        ],
        vec![
            "diff".into(),
            missing.display().to_string(),
            missing.display().to_string(),
        ],
    ];
    for args in cases {
        cmd()
            .args(&args)
            .assert()
            .code(2)
            .stderr(predicate::str::starts_with("error: ").and(contains("panicked").not()));
    }
    assert!(!p(dir.path(), "x.jpg").exists());
}

#[test]
fn no_vulkan_device_is_a_clear_error_and_the_cpu_still_renders() {
    let dir = tmp();
    let out = p(dir.path(), "cpu.png");
    let no_driver = || {
        let mut c = cmd();
        c.env("VK_DRIVER_FILES", "/nonexistent/icd.json")
            .env("VK_ICD_FILENAMES", "/nonexistent/icd.json")
            .env_remove("GLINT_VALIDATION");
        c
    };
    let scene = scene_path("seed-fig3.toml");
    let small = ["--width", "32", "--height", "24"];
    no_driver()
        .args(["render", &scene])
        .args(small)
        .assert()
        .code(2)
        .stderr(contains("mesa-vulkan-drivers").and(contains("--backend cpu")));
    no_driver()
        .args(["render", &scene])
        .args(small)
        .args(["--backend", "cpu", "-o"])
        .arg(&out)
        .assert()
        .success();
    assert!(out.exists());
}

#[test]
fn info_lists_devices() {
    let v = json_of(&cmd().args(["info", "--json"]).assert().success());
    let devices = v["devices"].as_array().expect("a list");
    assert!(!devices.is_empty());
    assert!(devices[0]["name"].as_str().is_some_and(|n| !n.is_empty()));
    assert!(devices[0].get("shader_float64").is_some());
}

#[test]
fn stability_json_holds_every_variant() {
    let scenes = common::repo().join("scenes/extreme");
    let a = scenes.join("tiny-1e-5.toml");
    let b = scenes.join("mirrors-09.toml");
    let run = cmd()
        .arg("stability")
        .args([a, b])
        .arg("--json")
        .assert()
        .success();
    let v = json_of(&run);
    let scenes = v["scenes"].as_array().unwrap();
    assert_eq!(scenes.len(), 2);
    for s in scenes {
        let variants: Vec<&str> = s["variants"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| r["variant"].as_str().unwrap())
            .collect();
        assert_eq!(variants, ["gpu f32 robust", "gpu f32 naive", "cpu f32"]);
    }
    // tiny-1e-5: the robust forms pass and the naive ones fail.
    assert_eq!(scenes[0]["variants"][0]["pass"], true);
    assert_eq!(scenes[0]["variants"][1]["pass"], false);
}

#[test]
fn compiled_shaders_are_cached_between_runs_unless_told_not_to() {
    let cache = tmp();
    let run = |extra: &[&str]| {
        let mut args = vec!["compare", "--json", "--width", "32", "--height", "24"];
        let scene = scene_path("seed-fig3.toml");
        args.insert(1, &scene);
        args.extend_from_slice(extra);
        let run = cmd()
            .args(&args)
            .env("XDG_CACHE_HOME", cache.path())
            .assert()
            .success();
        json_of(&run)["setup"]["spirv_cached"].as_bool().unwrap()
    };
    assert!(!run(&[]), "a cold cache compiles");
    assert!(run(&[]), "the second run reads SPIR-V from the cache");
    assert!(!run(&["--no-cache"]));
    let files: Vec<_> = std::fs::read_dir(cache.path().join("glint/spirv"))
        .unwrap()
        .collect();
    assert_eq!(files.len(), 1);
    assert!(cache.path().join("glint").read_dir().unwrap().any(|e| e
        .unwrap()
        .file_name()
        .to_string_lossy()
        .starts_with("pipelines-")));
}

/// Every command's help speaks to users: no Rust or shader names from the
/// code (a review found `AUTO_MIN_BOUNDED` and `auto_picks_wavefront`
/// there), and `--accel` names every bounded kind.
#[test]
fn help_text_shows_no_internal_names() {
    let commands = [
        "render",
        "compare",
        "diff",
        "info",
        "stability",
        "report",
        "shader",
        "watch",
        "convert",
        "assemble",
        "bench",
        "completions",
        "man",
        "drivers",
    ];
    for command in commands {
        let o = common::glint(&[command, "--help"]);
        assert!(o.status.success(), "{command} --help");
        let help = String::from_utf8_lossy(&o.stdout);
        // Value names (<MAX_DEPTH>) are clap's, and the environment
        // variables a user sets are the user's.
        let mut prose = String::new();
        for (i, part) in help.split(['<', '>']).enumerate() {
            if i % 2 == 0 {
                prose.push_str(part);
            }
        }
        let environment = ["SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"];
        for word in prose.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == ':')) {
            let constant = word.contains('_')
                && word
                    .chars()
                    .all(|c| c.is_ascii_uppercase() || c == '_' || c.is_ascii_digit())
                && !word.starts_with("GLINT_")
                && !environment.contains(&word);
            let item = word.contains("::") || (word.contains('_') && word.ends_with("()"));
            assert!(!constant && !item, "{command} --help shows {word}");
        }
        assert!(!help.contains("auto_picks_wavefront"), "{command}");
        if help.contains("--accel") {
            assert!(
                help.contains("spheres, triangles and cylinders"),
                "{command}"
            );
        }
    }
}

/// `--version` names the commit and each Vulkan device with its driver;
/// `-V` only the first line.
#[test]
fn version_names_the_commit_and_the_driver() {
    let o = common::glint(&["--version"]);
    common::assert_ok(&o);
    let text = String::from_utf8_lossy(&o.stdout);
    let mut lines = text.lines();
    let first = lines.next().unwrap();
    assert!(
        first.starts_with(&format!("glint {} (commit ", env!("CARGO_PKG_VERSION"))),
        "{text}"
    );
    let devices: Vec<&str> = lines.collect();
    assert!(!devices.is_empty(), "{text}");
    assert!(
        devices[0].starts_with("Vulkan 0: ") && devices[0].contains(", driver "),
        "{text}"
    );
    let short = common::glint(&["-V"]);
    common::assert_ok(&short);
    assert_eq!(String::from_utf8_lossy(&short.stdout).trim_end(), first);
}

/// Completions and the man page come from the command line's own
/// definition: every command is in them.
#[test]
fn completions_and_man_page_list_every_command() {
    for shell in ["bash", "zsh", "fish"] {
        let o = common::glint(&["completions", shell]);
        common::assert_ok(&o);
        let script = String::from_utf8_lossy(&o.stdout);
        for command in ["render", "compare", "assemble", "bench"] {
            assert!(script.contains(command), "{shell}: {command}");
        }
    }
    let o = common::glint(&["man"]);
    common::assert_ok(&o);
    let page = String::from_utf8_lossy(&o.stdout);
    assert!(
        page.starts_with(".ie") && page.contains(".TH glint 1"),
        "{page}"
    );
    assert!(page.contains("render") && page.contains("compare"));
    let o = common::glint(&["completions", "tcsh"]);
    assert_eq!(o.status.code(), Some(2));
}
