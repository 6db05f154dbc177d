//! Users' own shader code: errors that name their file and line, defines,
//! a replaced main shader, the experiments, `shader dump` and `watch`.

#![cfg(feature = "gpu")]

mod common;

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::glint;

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

fn repo(rel: &str) -> String {
    common::repo().join(rel).display().to_string()
}

#[test]
fn shader_check_accepts_the_builtin_shader() {
    let o = glint(&["shader", "check", &repo("shaders/main.comp")]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains("compiles"));
}

#[test]
fn a_broken_include_is_reported_at_the_users_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let shade = std::fs::read_to_string(repo("shaders/shade.glsl")).unwrap();
    let broken = shade.replace(
        "    vec3r local = vec3r(0.0);",
        "    vec3r local = vec3r(0.0);\n    float oops = undefined_thing;",
    );
    assert_ne!(shade, broken);
    std::fs::write(dir.path().join("shade.glsl"), &broken).unwrap();
    let line = broken
        .lines()
        .position(|l| l.contains("undefined_thing"))
        .unwrap()
        + 1;
    let user_file = dir.path().join("shade.glsl").display().to_string();
    let o = glint(&[
        "shader",
        "check",
        &repo("shaders/main.comp"),
        "-I",
        dir.path().to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    let err = text(&o.stderr);
    assert!(
        err.contains(&format!("{user_file}:{line}: error:")),
        "{err}"
    );
    assert!(err.contains("undefined_thing"), "{err}");
    // And a render with it fails with the same message, exit 2.
    let o = glint(&[
        "render",
        &repo("scenes/seed-fig3.toml"),
        "-I",
        dir.path().to_str().unwrap(),
        "--no-cache",
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = text(&o.stderr);
    assert!(
        err.contains(&format!("{user_file}:{line}: error:")),
        "{err}"
    );
    // One line, as every user error is: not glslang's "compilation
    // terminated" trailer after it.
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(!err.contains("compilation terminated"), "{err}");
}

/// The exit-status rule (README, "Exit status"): a check that ran and
/// found a fault exits 1; input glint cannot use exits 2.
#[test]
fn shader_check_exits_1_for_a_verdict_and_2_for_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.comp");
    std::fs::write(
        &bad,
        "#version 450\nlayout(local_size_x = 1) in;\nvoid main() { foo(); }\n",
    )
    .unwrap();
    let o = glint(&["shader", "check", bad.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        text(&o.stderr).trim_end(),
        format!(
            "{}:3: error: 'foo' : no matching overloaded function found",
            bad.display()
        )
    );
    let missing = dir.path().join("missing.comp");
    let o = glint(&["shader", "check", missing.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let o = glint(&["shader", "check", &repo("shaders/main.comp"), "-D", "1BAD"]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn a_broken_main_shader_is_reported_at_its_own_line() {
    let dir = tempfile::tempdir().unwrap();
    let main = std::fs::read_to_string(repo("shaders/main.comp")).unwrap();
    let broken = main.replace(
        "    uint samples = SAMPLES;",
        "    uint samples = SAMPLES\n",
    );
    assert_ne!(main, broken);
    let file = dir.path().join("mine.comp");
    std::fs::write(&file, &broken).unwrap();
    let o = glint(&["shader", "check", file.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    let err = text(&o.stderr);
    assert!(err.starts_with(&format!("{}:", file.display())), "{err}");
}

#[test]
fn defines_reach_the_shader() {
    // A shade.glsl that scales the light by GAIN, which only -D defines.
    let dir = tempfile::tempdir().unwrap();
    let shade = std::fs::read_to_string(repo("shaders/shade.glsl")).unwrap();
    let gain = shade.replace("    return local;", "    return local * GAIN;");
    std::fs::write(dir.path().join("shade.glsl"), gain).unwrap();
    let inc = dir.path().to_str().unwrap();
    let scene = repo("scenes/seed-fig4.toml");
    let size = ["--width", "80", "--height", "60"];
    let with = |extra: &[&str]| {
        let mut args = vec!["compare", scene.as_str(), "-I", inc, "--no-cache"];
        args.extend_from_slice(&size);
        args.extend_from_slice(extra);
        glint(&args)
    };
    assert_eq!(with(&["-D", "GAIN=1.0"]).status.code(), Some(0));
    assert_eq!(with(&["-D", "GAIN=1.5"]).status.code(), Some(1));
    let undefined = with(&[]);
    assert_eq!(undefined.status.code(), Some(2));
    assert!(
        text(&undefined.stderr).contains("GAIN"),
        "{}",
        text(&undefined.stderr)
    );
    assert_eq!(with(&["-D", "1BAD"]).status.code(), Some(2));
}

#[test]
fn a_users_main_shader_renders_and_compares() {
    let dir = tempfile::tempdir().unwrap();
    let mine = dir.path().join("mine.comp");
    std::fs::copy(repo("shaders/main.comp"), &mine).unwrap();
    let o = glint(&[
        "compare",
        &repo("scenes/showcase.toml"),
        "--width",
        "120",
        "--height",
        "90",
        "--shader",
        mine.to_str().unwrap(),
    ]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}{}",
        text(&o.stdout),
        text(&o.stderr)
    );
}

#[test]
fn shader_dump_writes_glsl_and_spirv() {
    let dir = tempfile::tempdir().unwrap();
    let o = glint(&[
        "shader",
        "dump",
        &repo("scenes/seed-fig4.toml"),
        "-o",
        dir.path().to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let files: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    let glsl = files
        .iter()
        .find(|p| p.extension().is_some_and(|e| e == "comp"))
        .expect("a .comp file");
    let spv = files
        .iter()
        .find(|p| p.extension().is_some_and(|e| e == "spv"))
        .expect("a .spv file");
    let text = std::fs::read_to_string(glsl).unwrap();
    assert!(
        text.contains("// -D HAS_PLANES=1") && text.contains("void main()"),
        "{}",
        &text[..200.min(text.len())]
    );
    assert!(!text.contains("#include"), "preprocessed");
    let words = std::fs::read(spv).unwrap();
    assert_eq!(&words[..4], &0x0723_0203u32.to_le_bytes());
}

#[test]
fn each_experiment_renders() {
    let scene = glint::scene::Scene::load(
        Path::new(&repo("scenes/showcase.toml")),
        &glint::scene::Overrides {
            width: Some(96),
            height: Some(72),
            samples: Some(1),
            ..Default::default()
        },
    )
    .unwrap();
    let reference = common::render_gpu(&scene);
    for name in ["normals", "cost", "phong"] {
        let dir = common::repo().join("shaders/experiments").join(name);
        let options = glint::gpu::GpuOptions {
            validate: true,
            include_dirs: vec![dir],
            ..Default::default()
        };
        let mut r = glint::gpu::Renderer::new(&options).unwrap();
        let image = r
            .render(&scene, &|_| {})
            .unwrap_or_else(|e| panic!("{name}: {e}"))
            .0;
        assert!(
            image.pixels.iter().flatten().all(|v| v.is_finite()),
            "{name}"
        );
        assert_ne!(image, reference, "{name} renders something of its own");
        let first = image.pixels[0];
        assert!(
            image.pixels.iter().any(|p| *p != first),
            "{name} is not one flat colour"
        );
    }
}

/// shaders/experiments/stack counts each pixel's deepest walk stack: whole
/// numbers, some above 3 (a visit pushes up to three), none past the stack
/// the variant declares. (A scene sampled at its pixels' centres: the
/// SPD's corners average four counts.)
#[test]
fn the_stack_experiment_counts_within_the_declared_stack() {
    let scene = glint::scene::Scene::load(
        Path::new(&repo("scenes/glass.toml")),
        &glint::scene::Overrides {
            width: Some(48),
            height: Some(48),
            ..Default::default()
        },
    )
    .unwrap();
    let options = glint::gpu::GpuOptions {
        validate: true,
        include_dirs: vec![common::repo().join("shaders/experiments/stack")],
        ..Default::default()
    };
    let mut r = glint::gpu::Renderer::new(&options).unwrap();
    let declared = common::variant(&r, &scene).0.bvh_stack as f32;
    let image = r.render(&scene, &|_| {}).unwrap().0;
    let depths: Vec<f32> = image.pixels.iter().map(|p| p[0]).collect();
    assert!(depths
        .iter()
        .all(|d| d.fract() == 0.0 && *d >= 0.0 && *d <= declared));
    let deepest = depths.iter().copied().fold(0.0, f32::max);
    assert!(deepest > 3.0, "deepest {deepest} of {declared}");
}

/// The stack experiment's green channel counts each pixel's visits: over
/// the image they are the nodes `--stats` counts, one a visit; with two
/// nodes a visit (shaders/experiments/walk's `-D PAIR_VISIT`) fewer visits than nodes, and the image
/// the same.
#[test]
fn the_stack_experiment_counts_the_visits_that_stats_count() {
    let dir = tempfile::tempdir().unwrap();
    let scene = repo("scenes/glass.toml");
    let render = |extra: &[&str], out: &str| {
        let o = common::cmd()
            .args(["render", &scene, "--width", "48", "--height", "48"])
            .args(extra)
            .arg("-o")
            .arg(dir.path().join(out))
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", text(&o.stderr));
    };
    let stack = common::repo().join("shaders/experiments/stack");
    let stack = stack.to_str().unwrap();
    let visits = |file: &str| -> f64 {
        let image = glint::raster::io::read(&dir.path().join(file)).unwrap();
        image.pixels.iter().map(|p| f64::from(p[1])).sum()
    };
    let nodes = |file: &str| -> f64 {
        let stats = std::fs::read_to_string(dir.path().join(file)).unwrap();
        let stats: serde_json::Value = serde_json::from_str(&stats).unwrap();
        stats["tests"]["bvh_nodes"].as_f64().unwrap()
    };
    render(&["-I", stack], "one.pfm");
    render(
        &["--stats", dir.path().join("one.json").to_str().unwrap()],
        "one.png",
    );
    let walk = common::repo().join("shaders/experiments/walk");
    let walk = walk.to_str().unwrap();
    render(&["-I", stack, "-I", walk, "-D", "PAIR_VISIT"], "pair.pfm");
    let pair_json = dir.path().join("pair.json");
    render(
        &[
            "-I",
            walk,
            "-D",
            "PAIR_VISIT",
            "--stats",
            pair_json.to_str().unwrap(),
        ],
        "pair.png",
    );
    assert!(nodes("one.json") > 1000.0);
    assert_eq!(visits("one.pfm"), nodes("one.json"));
    assert!(visits("pair.pfm") < 0.9 * nodes("pair.json"));
    assert_eq!(
        std::fs::read(dir.path().join("one.png")).unwrap(),
        std::fs::read(dir.path().join("pair.png")).unwrap()
    );
}

/// Waits until `f` holds, for at most `limit`.
fn wait_for(limit: Duration, mut f: impl FnMut() -> bool) -> bool {
    let start = Instant::now();
    while start.elapsed() < limit {
        if f() {
            return true;
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    false
}

/// seed-fig4 at 64x48, as scene text.
fn small_seed_fig4() -> String {
    std::fs::read_to_string(repo("scenes/seed-fig4.toml"))
        .unwrap()
        .replace("width = 800", "width = 64")
        .replace("height = 600", "height = 48")
}

/// `glint watch SCENE -o OUT`, running; its stderr piped.
fn watch(scene: &Path, out: &Path) -> std::process::Child {
    Command::new(env!("CARGO_BIN_EXE_glint"))
        .args([
            "watch",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

#[test]
fn watch_rerenders_on_change_and_keeps_the_last_good_image() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.toml");
    let out = dir.path().join("out.pfm");
    let original = small_seed_fig4();
    std::fs::write(&scene, &original).unwrap();
    let mut child = watch(&scene, &out);
    let result = std::panic::catch_unwind(|| {
        let limit = Duration::from_secs(30);
        assert!(wait_for(limit, || out.exists()), "first render");
        let first = std::fs::read(&out).unwrap();
        // A changed background re-renders.
        std::thread::sleep(Duration::from_millis(1100));
        std::fs::write(
            &scene,
            original.replace(
                "background = [0.05, 0.05, 0.1]",
                "background = [0.5, 0.0, 0.0]",
            ),
        )
        .unwrap();
        assert!(
            wait_for(limit, || std::fs::read(&out).is_ok_and(|b| b != first)),
            "re-render"
        );
        let second = std::fs::read(&out).unwrap();
        // A broken scene leaves the last good image.
        std::thread::sleep(Duration::from_millis(1100));
        std::fs::write(&scene, original.replace("radius = 6.0", "radius = -6.0")).unwrap();
        std::thread::sleep(Duration::from_millis(1500));
        assert_eq!(std::fs::read(&out).unwrap(), second);
        // Saved as many editors save, a new file renamed over the old: the
        // original scene again, the first image again.
        let new = dir.path().join(".scene.toml.swp");
        std::fs::write(&new, &original).unwrap();
        std::fs::rename(&new, &scene).unwrap();
        assert!(
            wait_for(limit, || std::fs::read(&out).is_ok_and(|b| b == first)),
            "re-render after a rename"
        );
    });
    child.kill().unwrap();
    let output = child.wait_with_output().unwrap();
    result.unwrap();
    let err = text(&output.stderr);
    assert!(
        err.contains("radius") && err.contains("keeping the last good image"),
        "{err}"
    );
}

/// The scene's folder deleted and made again, with the scene in it: watch
/// renders the new scene (it used to stop reacting, its watch left on the
/// deleted folder).
#[test]
fn watch_follows_a_folder_deleted_and_made_again() {
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().join("work");
    std::fs::create_dir(&folder).unwrap();
    let scene = folder.join("scene.toml");
    let out = dir.path().join("out.pfm");
    let original = small_seed_fig4();
    std::fs::write(&scene, &original).unwrap();
    let mut child = watch(&scene, &out);
    let result = std::panic::catch_unwind(|| {
        let limit = Duration::from_secs(30);
        assert!(wait_for(limit, || out.exists()), "first render");
        let first = std::fs::read(&out).unwrap();
        std::fs::remove_dir_all(&folder).unwrap();
        std::thread::sleep(Duration::from_millis(1500));
        std::fs::create_dir(&folder).unwrap();
        let changed = original.replace(
            "background = [0.05, 0.05, 0.1]",
            "background = [0.5, 0.0, 0.0]",
        );
        assert_ne!(changed, original);
        std::fs::write(&scene, changed).unwrap();
        assert!(
            wait_for(limit, || std::fs::read(&out).is_ok_and(|b| b != first)),
            "no render after the folder came back"
        );
    });
    child.kill().unwrap();
    let _ = child.wait_with_output();
    result.unwrap();
}

/// A main shader finds the files it includes beside it, without `-I`:
/// `shader check` and `render --shader` alike.
#[test]
fn a_main_shader_finds_its_includes_beside_it() {
    let dir = tempfile::tempdir().unwrap();
    let main = dir.path().join("mine.comp");
    let text = std::fs::read_to_string(common::repo().join("shaders/main.comp")).unwrap();
    // One include that only this folder has.
    let text = text.replacen(
        "#include \"trace.glsl\"",
        "#include \"trace.glsl\"\n#include \"beside.glsl\"",
        1,
    );
    assert!(
        text.contains("beside.glsl"),
        "main.comp includes trace.glsl"
    );
    std::fs::write(&main, text).unwrap();
    std::fs::write(
        dir.path().join("beside.glsl"),
        "// found beside the main shader\n",
    )
    .unwrap();
    let o = common::glint(&["shader", "check", main.to_str().unwrap()]);
    common::assert_ok(&o);
    let out = dir.path().join("x.png");
    let scene = common::repo().join("scenes/seed-fig3.toml");
    let render = || {
        common::glint(&[
            "render",
            scene.to_str().unwrap(),
            "--width",
            "16",
            "--height",
            "12",
            "--shader",
            main.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ])
    };
    common::assert_ok(&render());
    // And the render's output may be written beside the shader again.
    common::assert_ok(&render());
}

/// `watch` after a render that timed out (a runaway loop in an include, on
/// a driver without a loop limit): the device is opened again, so fixing
/// the include renders (the watchdog, for watch). On a driver with
/// a loop limit the budget ends the loop, and the fix renders too.
#[test]
fn watch_renders_again_after_a_timeout() {
    let dir = tempfile::tempdir().unwrap();
    let inc = common::runaway_include(dir.path());
    let specular = inc.join("specular.glsl");
    let scene = dir.path().join("scene.toml");
    let small = std::fs::read_to_string(repo("scenes/seed-fig3.toml"))
        .unwrap()
        .replace("width = 800", "width = 32")
        .replace("height = 600", "height = 24");
    std::fs::write(&scene, small).unwrap();
    let out = dir.path().join("out.pfm");
    let mut child = Command::new(env!("CARGO_BIN_EXE_glint"))
        .args([
            "watch",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ])
        .args(["-I", inc.to_str().unwrap(), "--timeout", "1"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let result = std::panic::catch_unwind(|| {
        // The first render fails (a timeout, or the loop budget).
        std::thread::sleep(Duration::from_secs(4));
        assert!(!out.exists(), "a runaway shader wrote an image");
        // The include fixed: the built-in specular term again.
        std::fs::write(
            &specular,
            std::fs::read_to_string(repo("shaders/specular.glsl")).unwrap(),
        )
        .unwrap();
        assert!(
            wait_for(Duration::from_secs(60), || out.exists()),
            "no render after the fix"
        );
    });
    child.kill().unwrap();
    let output = child.wait_with_output().unwrap();
    result.unwrap();
    let err = text(&output.stderr);
    assert!(
        err.contains("did not finish the tile") || err.contains("loops were cut short"),
        "{err}"
    );
}

/// A same-size edit that keeps the file's time (`cp -p` of a version saved
/// in the same second, `rsync -t`) re-renders (the time and size alone
/// were compared, and the old image stayed).
#[test]
fn watch_sees_an_edit_that_keeps_the_size_and_the_time() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.toml");
    let out = dir.path().join("out.pfm");
    let original = small_seed_fig4();
    std::fs::write(&scene, &original).unwrap();
    let modified = std::fs::metadata(&scene).unwrap().modified().unwrap();
    let mut child = watch(&scene, &out);
    let result = std::panic::catch_unwind(|| {
        let limit = Duration::from_secs(30);
        assert!(wait_for(limit, || out.exists()), "first render");
        let first = std::fs::read(&out).unwrap();
        let changed = original.replace(
            "background = [0.05, 0.05, 0.1]",
            "background = [0.50, 0.05, 0.1]",
        );
        assert_eq!(changed.len(), original.len());
        assert_ne!(changed, original);
        // Written in place, then its time put back.
        let mut f = std::fs::OpenOptions::new()
            .write(true)
            .open(&scene)
            .unwrap();
        std::io::Write::write_all(&mut f, changed.as_bytes()).unwrap();
        f.set_modified(modified).unwrap();
        drop(f);
        assert_eq!(
            std::fs::metadata(&scene).unwrap().modified().unwrap(),
            modified
        );
        assert!(
            wait_for(limit, || std::fs::read(&out).is_ok_and(|b| b != first)),
            "re-render after a same-size, same-time edit"
        );
    });
    child.kill().unwrap();
    child.wait().unwrap();
    result.unwrap();
}

/// A main shader of `terms` additions in one expression.
fn deep_sum(dir: &Path, terms: usize) -> std::path::PathBuf {
    let path = dir.join(format!("sum{terms}.comp"));
    let sum = vec!["a"; terms].join("+");
    std::fs::write(
        &path,
        format!(
            "#version 460\nlayout(local_size_x = 1) in;\n\
             layout(std430, binding = 0) buffer B {{ float v[]; }};\n\
             void main() {{ float a = v[0]; v[1] = {sum}; }}\n"
        ),
    )
    .unwrap();
    path
}

/// A sum of 20,001 terms overflowed the main thread's stack in glslang
/// (exit 134); a 1 MB one took a gigabyte. The compile runs on a thread
/// of its own stack, and the sources are bounded.
#[test]
fn deep_and_large_shader_sources_compile_or_are_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let deep = deep_sum(dir.path(), 20_001);
    let o = glint(&["shader", "check", deep.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let large = deep_sum(dir.path(), 500_000);
    let o = glint(&["shader", "check", large.to_str().unwrap()]);
    let err = text(&o.stderr);
    assert!(!o.status.success() && o.status.code() != Some(134), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.contains("past the bound of 512 KiB on one compile"),
        "{err}"
    );
}
