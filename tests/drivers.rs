//! `glint drivers`: the scenes on each driver, each in its own process,
//! held to the CPU f64 reference; a wrong driver is caught with a
//! reproducer, and a crashing one is a row, not the end of the run.

#![cfg(feature = "gpu")]

mod common;

use std::path::{Path, PathBuf};
use std::process::Output;

use serde_json::Value;
use std::process::Command;

/// The lavapipe `ci/setup` installs (as ci/test pins it).
fn current_lavapipe() -> Option<PathBuf> {
    glint::files::sorted(Path::new("/usr/share/vulkan/icd.d"), |p| {
        p.file_name()
            .is_some_and(|n| n.to_string_lossy().starts_with("lvp_icd"))
    })
    .ok()?
    .into_iter()
    .next()
}

fn both_lavapipes(what: &str) -> Option<(PathBuf, PathBuf)> {
    match (current_lavapipe(), common::old_lavapipe()) {
        (Some(a), Some(b)) => Some((a, b)),
        _ => {
            common::skip(
                what,
                "both lavapipes are needed (ci/setup, ci/old-lavapipe)",
            );
            None
        }
    }
}

fn drivers(args: &[&str], icds: &[&Path], out: &Path, env: &[(&str, &str)]) -> Output {
    let mut c = common::cmd();
    c.current_dir(common::repo()).arg("drivers").args(args);
    for icd in icds {
        c.arg("--icd").arg(icd);
    }
    c.arg("--only").arg("-o").arg(out);
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().expect("run glint drivers")
}

/// Asserts that the run exited with `code`, showing its stderr where not.
fn assert_exit(o: &Output, code: i32) {
    assert_eq!(
        o.status.code(),
        Some(code),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Builds the shared library `so` from the C file `source` with `flags`
/// (and libdl, which a forwarding driver opens its real one with); false
/// where there is no C compiler.
fn build_c_library(source: &Path, so: &Path, flags: &[String]) -> bool {
    std::process::Command::new("cc")
        .args(["-shared", "-fPIC"])
        .args(flags)
        .arg("-o")
        .arg(so)
        .arg(source)
        .arg("-ldl")
        .status()
        .is_ok_and(|s| s.success())
}

fn matrix(out: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(out.join("drivers.json")).unwrap()).unwrap()
}

/// The column of the driver whose ICD file is `icd`.
fn column(m: &Value, icd: &Path) -> usize {
    m["columns"]
        .as_array()
        .unwrap()
        .iter()
        .position(|c| c["icd"] == icd.to_str().unwrap())
        .unwrap_or_else(|| panic!("no column for {}: {m}", icd.display()))
}

fn cell<'a>(m: &'a Value, scene: &str, column: usize) -> &'a Value {
    let row = m["rows"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["scene"] == scene)
        .unwrap_or_else(|| panic!("no row {scene}"));
    &row["cells"][column]
}

#[test]
fn quick_on_both_lavapipes_passes_every_scene() {
    let Some((new, old)) = both_lavapipes("drivers --quick") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m");
    let o = drivers(&["--quick"], &[&new, &old], &out, &[]);
    common::assert_ok(&o);
    let m = matrix(&out);
    let columns = m["columns"].as_array().unwrap();
    assert_eq!(columns.len(), 2, "{m}");
    for c in columns {
        assert!(
            c["identity"]["driver"].as_str().unwrap().contains("Mesa"),
            "{c}"
        );
    }
    let rows = m["rows"].as_array().unwrap();
    assert_eq!(rows.len(), common::scene_files("scenes").len());
    for r in rows {
        for c in r["cells"].as_array().unwrap() {
            assert_eq!(c["result"], "pass", "{}: {c}", r["scene"]);
        }
    }
    for f in ["drivers.md", "drivers.csv", "index.html"] {
        assert!(out.join(f).is_file(), "{f}");
    }
    let page = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(
        page.contains("Mesa 22.3.6") && page.contains("Vulkan 1.3"),
        "{page}"
    );
}

/// Mesa 22.3 miscompiles the scene loops unrolled past about 100 objects
/// (docs/performance.md, The lavapipe-specific choices): with glint's cap
/// switched off, and the uniform buffers glint no longer gives Mesa 22.3
/// (they corrupted its heap), its lane is wrong, and the matrix says so
/// with a reproducer that holds what a bug report needs. (Mesa 25.0's
/// lane crashes on this experiment, at 676c44f too: not judged.)
#[test]
fn a_wrong_driver_fails_with_a_reproducer() {
    let Some((new, old)) = both_lavapipes("the broken lane") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m");
    let o = drivers(
        &["scenes/seed-fig5.toml", "--accel", "none", "--quick"],
        &[&new, &old],
        &out,
        &[("GLINT_EXPERIMENT", "unroll-all,uniforms-always")],
    );
    assert_exit(&o, 1);
    let m = matrix(&out);
    let bad = cell(&m, "seed-fig5", column(&m, &old));
    assert_eq!(bad["result"], "fail", "{bad}");
    let repro = PathBuf::from(bad["repro"].as_str().unwrap());
    for f in [
        "README.md",
        "command.sh",
        "driver.json",
        "seed-fig5.toml",
        "gpu.pfm",
        "reference.pfm",
        "heat.png",
    ] {
        assert!(
            repro.join(f).is_file(),
            "{f} missing from {}",
            repro.display()
        );
    }
    // Its worst pixel explained on the broken driver: the explanation
    // stops at a first wrong value, which no f32 rounding explains, and
    // the page links to it.
    let explained = std::fs::read_to_string(repro.join("explain.txt")).unwrap();
    let verdict = explained.lines().last().unwrap_or_default();
    assert!(
        verdict.starts_with("gpu f32: first divergence at ") && !verdict.contains("near-tie"),
        "{explained}"
    );
    let [x, y] = [0, 1].map(|k| bad["explained"][k].as_u64().expect("the explained pixel"));
    assert!(explained.contains(&format!("pixel {x},{y}")), "{explained}");
    let page = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(
        page.contains(&format!("pixel {x},{y} explained</a>")),
        "{page}"
    );
    let shader: Vec<PathBuf> = glint::files::sorted(&repro.join("shader"), |_| true).unwrap();
    assert!(shader
        .iter()
        .any(|p| p.extension().is_some_and(|e| e == "comp")));
    assert!(shader
        .iter()
        .any(|p| p.extension().is_some_and(|e| e == "spv")));
    let command = std::fs::read_to_string(repro.join("command.sh")).unwrap();
    assert!(
        command.contains(&format!("VK_DRIVER_FILES={}", old.display()))
            || command.contains(&format!("VK_DRIVER_FILES='{}'", old.display())),
        "{command}"
    );
    assert!(command.contains("GLINT_EXPERIMENT=unroll-all") && command.contains("--accel none"));
    // Shrunk: the failure is still there at a smaller image, and with
    // fewer objects.
    let (w, h) = glint::raster::io::dimensions(&repro.join("gpu.pfm")).unwrap();
    assert!(w < 64 && h < 48, "{w}x{h}");
    let readme = std::fs::read_to_string(repro.join("README.md")).unwrap();
    assert!(readme.contains("- Objects: "), "{readme}");
    let shrunk = std::fs::read_to_string(repro.join("seed-fig5.toml")).unwrap();
    let original = std::fs::read_to_string(common::repo().join("scenes/seed-fig5.toml")).unwrap();
    assert!(
        shrunk.matches("[[spheres]]").count() < original.matches("[[spheres]]").count(),
        "no sphere was left out"
    );
    // The reproducer's own command shows the failure again: compare fails.
    let again = common::cmd()
        .current_dir(&repro)
        .args(["compare", "seed-fig5.toml", "--accel", "none"])
        .args(["--width", &w.to_string(), "--height", &h.to_string()])
        .env("VK_DRIVER_FILES", &old)
        .env("GLINT_EXPERIMENT", "unroll-all,uniforms-always")
        .output()
        .unwrap();
    assert_eq!(again.status.code(), Some(1));
    // Without the experiment the same run passes: the failure is the lane's.
    let fine = dir.path().join("fine");
    let o = drivers(
        &["scenes/seed-fig5.toml", "--accel", "none", "--quick"],
        &[&old],
        &fine,
        &[],
    );
    common::assert_ok(&o);
}

/// An ICD whose library aborts as the loader opens it is a row that says
/// so, and the other driver's scenes still run.
#[test]
fn a_crashing_driver_is_a_row() {
    let Some(new) = current_lavapipe() else {
        common::skip("a crashing driver", "no lavapipe");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let c = dir.path().join("abort.c");
    std::fs::write(
        &c,
        "#include <stdlib.h>\n__attribute__((constructor)) static void die(void) { abort(); }\n",
    )
    .unwrap();
    let lib = dir.path().join("libabort.so");
    if !build_c_library(&c, &lib, &[]) {
        common::skip(
            "a crashing driver",
            "no C compiler to build the aborting library",
        );
        return;
    }
    let icd = dir.path().join("abort_icd.json");
    common::write_icd_manifest(&icd, &lib);
    let out = dir.path().join("m");
    let o = drivers(
        &["scenes/seed-fig3.toml", "scenes/seed-fig4.toml", "--quick"],
        &[&icd, &new],
        &out,
        &[],
    );
    assert_exit(&o, 1);
    let m = matrix(&out);
    for scene in ["seed-fig3", "seed-fig4"] {
        let crashed = cell(&m, scene, column(&m, &icd));
        assert_eq!(crashed["result"], "crashed", "{crashed}");
        assert!(
            crashed["how"].as_str().unwrap().contains("SIGABRT"),
            "{crashed}"
        );
        assert_eq!(cell(&m, scene, column(&m, &new))["result"], "pass");
    }
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("crashed") && stdout.contains("pass"),
        "{stdout}"
    );
}

/// A folder of the user's named `repro` under -o is never removed.
#[test]
fn a_users_repro_folder_is_left_alone() {
    let Some(new) = current_lavapipe() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m");
    std::fs::create_dir_all(out.join("repro")).unwrap();
    std::fs::write(out.join("repro/mine.txt"), "keep").unwrap();
    let o = drivers(&["scenes/seed-fig3.toml", "--quick"], &[&new], &out, &[]);
    common::assert_user_error(&o, "is not one `glint drivers` wrote");
    assert!(out.join("repro/mine.txt").is_file());
}

/// `--icd` naming a directory, a FIFO, a loop of links or
/// nothing says which, in one line, before any driver runs.
#[test]
fn an_icd_that_is_not_a_manifest_is_named_for_what_it_is() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    common::make_fifo(&d.join("fifo.json"));
    std::os::unix::fs::symlink(d.join("b.json"), d.join("a.json")).unwrap();
    std::os::unix::fs::symlink(d.join("a.json"), d.join("b.json")).unwrap();
    std::fs::create_dir(d.join("folder.json")).unwrap();
    for (name, says) in [
        ("folder.json", "is a directory, not a regular file"),
        ("fifo.json", "is a FIFO, not a regular file"),
        ("a.json", "symbolic links"),
        ("missing.json", "No such file"),
    ] {
        let o = drivers(
            &["scenes/seed-fig3.toml", "--quick"],
            &[&d.join(name)],
            &d.join("out"),
            &[],
        );
        common::assert_user_error(&o, says);
        assert!(!d.join("out").exists(), "{name}");
    }
}

/// Two scenes of one stem (a/s.toml, b/s.toml) are two rows,
/// each named by its path.
#[test]
fn two_scenes_of_one_name_are_two_rows() {
    let Some(new) = current_lavapipe() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for sub in ["a", "b"] {
        std::fs::create_dir(d.join(sub)).unwrap();
        std::fs::copy(
            common::repo().join("scenes/seed-fig3.toml"),
            d.join(sub).join("s.toml"),
        )
        .unwrap();
    }
    let (a, b) = (d.join("a/s.toml"), d.join("b/s.toml"));
    let out = d.join("m");
    let o = drivers(
        &[a.to_str().unwrap(), b.to_str().unwrap(), "--quick"],
        &[&new],
        &out,
        &[],
    );
    assert_exit(&o, 0);
    let m = matrix(&out);
    let rows: Vec<&str> = m["rows"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["scene"].as_str().unwrap())
        .collect();
    assert_eq!(rows, [a.to_str().unwrap(), b.to_str().unwrap()]);
}

/// `--icd X --only`, where X gives no device, tested nothing
/// and exited 0; it is one error, exit 2, and no table.
#[test]
fn a_run_that_can_test_no_driver_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let icd = d.join("nothing.json");
    common::write_icd_manifest(&icd, Path::new("/nonexistent/libvulkan_none.so"));
    let out = d.join("out");
    let o = drivers(&["scenes/seed-fig3.toml", "--quick"], &[&icd], &out, &[]);
    common::assert_user_error(&o, "no driver could be tested");
    assert!(!out.join("drivers.json").exists());
}

/// The ways `tests/data/misbehaving_icd.c` misbehaves (its MODE), each
/// with the cell it must give and what its reproducer's command says.
const MISBEHAVIOURS: [(&str, u32, &str); 4] = [
    ("skip", 1, "fault"),
    ("lose", 2, "fault"),
    ("hang", 3, "hung"),
    ("garbage", 4, "fail"),
];

/// Builds the misbehaving forwarding ICD over `real` (a lavapipe manifest)
/// in `dir`, once for each mode: the manifests, by mode's name; None
/// where there is no C compiler.
fn misbehaving_icds(real: &Path, dir: &Path) -> Option<Vec<PathBuf>> {
    let manifest: Value = serde_json::from_str(&std::fs::read_to_string(real).unwrap()).unwrap();
    let lib = manifest["ICD"]["library_path"].as_str().unwrap();
    let lib = if lib.contains('/') {
        real.parent().unwrap().join(lib).display().to_string()
    } else {
        lib.to_owned()
    };
    let mut icds = Vec::new();
    for (name, mode, _) in MISBEHAVIOURS {
        let so = dir.join(format!("lib{name}.so"));
        let flags = [
            "-O1".to_owned(),
            "-Wall".into(),
            "-Werror".into(),
            format!("-DMODE={mode}"),
            format!("-DREAL_LIBRARY=\"{lib}\""),
        ];
        let source = common::repo().join("tests/data/misbehaving_icd.c");
        if !build_c_library(&source, &so, &flags) {
            common::skip("a misbehaving driver", "no C compiler to build its ICD");
            return None;
        }
        let icd = dir.join(format!("{name}.json"));
        common::write_icd_manifest(&icd, &so);
        icds.push(icd);
    }
    Some(icds)
}

/// Runs a reproducer's command.sh from its own folder, with this build's
/// glint first on PATH, for at most `seconds`: its output (exit status
/// 124 where it was still running, as timeout(1) says).
fn run_reproducer(repro: &Path, seconds: u32) -> Output {
    let bin = Path::new(env!("CARGO_BIN_EXE_glint")).parent().unwrap();
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    std::process::Command::new("timeout")
        .args(["-k", "5", &seconds.to_string(), "sh", "command.sh"])
        .current_dir(repro)
        .env("PATH", path)
        .env("GLINT_VALIDATION", "1")
        .output()
        .unwrap()
}

/// A driver that skips the dispatch, loses the device, hangs in
/// the fence wait or writes garbage is a failure (FAIL, hung), with a
/// reproducer whose command, run from its own folder, fails the same way;
/// with the scene's mesh copied, and the run's relative -I and --icd
/// paths meaning the same there.
#[test]
fn a_misbehaving_driver_fails_in_each_way_with_a_reproducer_that_reproduces() {
    let Some(real) = current_lavapipe() else {
        common::skip("a misbehaving driver", "no lavapipe");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let Some(icds) = misbehaving_icds(&real, d) else {
        return;
    };
    // The run is from the scene's folder, with relative paths.
    let home = d.join("scene");
    std::fs::create_dir_all(home.join("meshes")).unwrap();
    std::fs::create_dir_all(d.join("include")).unwrap();
    std::fs::copy(
        common::repo().join("scenes/glass.toml"),
        home.join("glass.toml"),
    )
    .unwrap();
    std::fs::copy(
        common::repo().join("scenes/meshes/icosphere-smooth.obj"),
        home.join("meshes/icosphere-smooth.obj"),
    )
    .unwrap();
    let mut c = common::cmd();
    c.current_dir(&home)
        .args(["drivers", "glass.toml", "--quick", "--deadline", "3"])
        .args(["-I", "../include", "--only", "-o", "../out"]);
    for icd in &icds {
        c.arg("--icd")
            .arg(Path::new("..").join(icd.file_name().unwrap()));
    }
    let o = c.output().unwrap();
    assert_exit(&o, 1);
    let m = matrix(&d.join("out"));
    for (i, (name, _, result)) in MISBEHAVIOURS.iter().enumerate() {
        let cell = &m["rows"][0]["cells"][i];
        assert_eq!(cell["result"], *result, "{name}: {cell}");
        // As written: relative to where the run was, or absolute.
        let repro = home.join(cell["repro"].as_str().unwrap());
        assert!(
            repro.join("meshes/icosphere-smooth.obj").is_file(),
            "{name}: the mesh was not copied into {}",
            repro.display()
        );
        let again = run_reproducer(&repro, 20);
        let stderr = String::from_utf8_lossy(&again.stderr);
        let same = match *name {
            "skip" => stderr.contains("the shader wrote nothing"),
            "lose" => stderr.contains("device has been lost"),
            "hang" => again.status.code() == Some(124),
            _ => again.status.code() == Some(1) && stderr.is_empty(),
        };
        assert!(same, "{name}: {:?} {stderr}", again.status);
    }
}

/// The misbehaving ICD of `mode` ("skip", "lose", "hang", "garbage"),
/// built in `dir`; None (the test skipped) without lavapipe or a compiler.
fn misbehaving(mode: &str, dir: &Path) -> Option<PathBuf> {
    let real = current_lavapipe()?;
    let i = MISBEHAVIOURS.iter().position(|(n, _, _)| *n == mode)?;
    misbehaving_icds(&real, dir).map(|v| v[i].clone())
}

/// Options that every child would refuse are one error from
/// the parent, exit 2, before any driver runs; they turned every driver
/// into "no device" or "refused", exit 0.
#[test]
fn options_every_driver_would_refuse_are_refused_once() {
    let Some(new) = current_lavapipe() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    for (option, value, says) in [
        ("-I", "missing-dir", "-I missing-dir: not a directory"),
        ("--timeout", "0", "--timeout 0.0: must be in"),
        ("--timeout", "nan", "--timeout NaN: must be in"),
        (
            "--shader",
            "missing.comp",
            "--shader missing.comp: no such file",
        ),
        ("-D", "=x", "-D =x: a define is NAME"),
        ("-D", "MAX_DEPTH=1", "glint defines MAX_DEPTH itself"),
    ] {
        let o = drivers(
            &["scenes/seed-fig3.toml", "--quick", option, value],
            &[&new],
            &out,
            &[],
        );
        common::assert_user_error(&o, says);
        assert!(!out.exists(), "{option} {value}");
    }
}

/// Where the loader finds no validation layer (here
/// $XDG_DATA_DIRS names an empty folder), the drivers run without it and
/// the run says so; every child failed asking for the layer before.
#[test]
fn without_a_layer_where_the_loader_looks_the_run_says_so() {
    let Some(new) = current_lavapipe() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let empty = dir.path().join("share");
    std::fs::create_dir(&empty).unwrap();
    let out = dir.path().join("out");
    let o = drivers(
        &["scenes/seed-fig3.toml", "--quick"],
        &[&new],
        &out,
        &[("XDG_DATA_DIRS", empty.to_str().unwrap())],
    );
    common::assert_ok(&o);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("1 pass") && stdout.contains("not under the validation layer"),
        "{stdout}"
    );
    let md = std::fs::read_to_string(out.join("drivers.md")).unwrap();
    assert!(
        md.contains("not under the Khronos validation layer"),
        "{md}"
    );
    assert_eq!(matrix(&out)["validation"], false);
}

/// An output linked to the library a working --icd manifest
/// names is refused like one linked to the manifest; the run replaced
/// the library it had loaded with the CSV, and exited 0.
#[test]
fn an_output_onto_a_driver_library_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let Some(icd) = misbehaving("garbage", d) else {
        return;
    };
    let lib = d.join("libgarbage.so");
    let bytes = std::fs::read(&lib).unwrap();
    let out = d.join("out");
    std::fs::create_dir(&out).unwrap();
    std::os::unix::fs::symlink(&lib, out.join("drivers.csv")).unwrap();
    let o = drivers(&["scenes/seed-fig3.toml", "--quick"], &[&icd], &out, &[]);
    common::assert_user_error(&o, "refusing to overwrite an input");
    assert_eq!(std::fs::read(&lib).unwrap(), bytes);
}

/// A driver's name with a terminal escape and a `|` is escaped
/// on stdout and in drivers.md, where it would have cleared the screen
/// and added a column.
#[test]
fn names_are_escaped_in_every_output() {
    let Some(new) = current_lavapipe() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let icd = dir.path().join("x|y\u{1b}[2Jred.json");
    std::fs::copy(&new, &icd).unwrap();
    let out = dir.path().join("out");
    let o = drivers(&["scenes/seed-fig3.toml", "--quick"], &[&icd], &out, &[]);
    common::assert_ok(&o);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        !stdout.contains('\u{1b}') && stdout.contains("x|y\\u{1b}[2Jred"),
        "{stdout}"
    );
    let md = std::fs::read_to_string(out.join("drivers.md")).unwrap();
    assert!(!md.contains('\u{1b}'), "{md}");
    let header = md.lines().find(|l| l.starts_with("| scene |")).unwrap();
    assert!(header.ends_with("/x\\|y\\u{1b}[2Jred |"), "{header}");
    let page = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(!page.contains('\u{1b}'));
}

/// A driver and a scene named `...json` and `...toml`, and a
/// scene of a 245-character name, on a failing driver, get reproducers
/// inside repro/, and nothing is written beside the scenes; `...` was
/// "..", and the reproducer replaced the README.md of the folder the
/// run was in, and the long name failed the run ("File name too long").
#[test]
fn reproducers_stay_inside_repro_whatever_the_names() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let Some(garbage) = misbehaving("garbage", d) else {
        return;
    };
    // The driver "..": a manifest named `...json` in a folder icd.d.
    std::fs::create_dir(d.join("icd.d")).unwrap();
    let icd = d.join("icd.d/...json");
    std::fs::copy(&garbage, &icd).unwrap();
    let here = d.join("here");
    std::fs::create_dir(&here).unwrap();
    std::fs::write(here.join("README.md"), "mine").unwrap();
    let scene = std::fs::read_to_string(common::repo().join("scenes/seed-fig3.toml")).unwrap();
    let long = format!("{}.toml", "n".repeat(245));
    for name in ["...toml", &long] {
        std::fs::write(here.join(name), &scene).unwrap();
    }
    let o = common::cmd()
        .current_dir(&here)
        .args(["drivers", "./...toml", &long, "--quick", "--no-shrink"])
        .arg("--icd")
        .arg(&icd)
        .args(["--only", "-o", "out"])
        .output()
        .unwrap();
    assert_exit(&o, 1);
    assert_eq!(
        std::fs::read_to_string(here.join("README.md")).unwrap(),
        "mine"
    );
    for name in ["...toml", &long] {
        assert_eq!(std::fs::read_to_string(here.join(name)).unwrap(), scene);
    }
    let mut names: Vec<String> = std::fs::read_dir(&here)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    let mut want = vec![
        "...toml".to_owned(),
        long.clone(),
        "README.md".into(),
        "out".into(),
    ];
    want.sort();
    assert_eq!(names, want);
    let m = matrix(&here.join("out"));
    for row in m["rows"].as_array().unwrap() {
        let repro = here.join(row["cells"][0]["repro"].as_str().unwrap());
        // repro/<driver>/<scene>, and nowhere else.
        let inside = std::fs::canonicalize(&repro).unwrap();
        assert_eq!(
            inside.parent().and_then(Path::parent),
            Some(
                std::fs::canonicalize(here.join("out/repro"))
                    .unwrap()
                    .as_path()
            ),
            "{}",
            repro.display()
        );
        assert!(repro.join("README.md").is_file() && repro.join("command.sh").is_file());
    }
}

/// A FIFO among the manifests of the folder the loader is
/// given hangs its child, which is killed; its reproducer then read the
/// FIFO and blocked the run for ever. It says what the file is.
#[test]
fn a_fifo_among_the_manifests_does_not_block_the_run() {
    let Some(new) = current_lavapipe() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let icds = dir.path().join("icd.d");
    std::fs::create_dir(&icds).unwrap();
    std::fs::copy(&new, icds.join("a_lvp.json")).unwrap();
    common::make_fifo(&icds.join("b_fifo.json"));
    let out = dir.path().join("out");
    let o = common::cmd()
        .current_dir(common::repo())
        .args([
            "drivers",
            "scenes/seed-fig3.toml",
            "--quick",
            "--deadline",
            "3",
        ])
        .arg("-o")
        .arg(&out)
        .env("VK_DRIVER_FILES", &icds)
        .env("HOME", dir.path())
        .env_remove("XDG_CACHE_HOME")
        .timeout(std::time::Duration::from_secs(120))
        .output()
        .unwrap();
    assert_exit(&o, 1);
    let m = matrix(&out);
    let fifo = cell(&m, "seed-fig3", column(&m, &icds.join("b_fifo.json")));
    assert_eq!(fifo["result"], "hung", "{fifo}");
    let repro = PathBuf::from(fifo["repro"].as_str().unwrap());
    let driver = std::fs::read_to_string(repro.join("driver.json")).unwrap();
    assert!(
        driver.contains("(not read: ") && driver.contains("FIFO"),
        "{driver}"
    );
    assert_eq!(
        cell(&m, "seed-fig3", column(&m, &icds.join("a_lvp.json")))["result"],
        "pass"
    );
}

/// SIGTERM in the middle of a run kills its children, removes
/// its temporary folder and leaves the last run's tables and reproducers
/// as they were.
#[test]
fn an_interrupted_run_leaves_nothing_running_and_the_last_run_whole() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (Some(garbage), Some(hang)) = (misbehaving("garbage", d), misbehaving("hang", d)) else {
        return;
    };
    let out = d.join("out");
    let o = drivers(
        &["scenes/seed-fig3.toml", "--quick", "--no-shrink"],
        &[&garbage],
        &out,
        &[],
    );
    assert_exit(&o, 1);
    let listing = |p: &Path| -> Vec<PathBuf> {
        let mut v: Vec<PathBuf> = walk(p);
        v.sort();
        v
    };
    let before = listing(&out);
    let tables = std::fs::read(out.join("drivers.json")).unwrap();
    let tmp = d.join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_glint"))
        .current_dir(common::repo())
        .args([
            "drivers",
            "scenes/seed-fig3.toml",
            "--quick",
            "--deadline",
            "60",
        ])
        .arg("--icd")
        .arg(&hang)
        .arg("--only")
        .arg("-o")
        .arg(&out)
        .env("TMPDIR", &tmp)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // Until its child hangs on the scene.
    let tmp_name = tmp.to_str().unwrap().to_owned();
    let probing = || {
        common::command_lines()
            .iter()
            .any(|c| c.contains("driver-probe") && c.contains(&tmp_name) && c.contains("--scene"))
    };
    let start = std::time::Instant::now();
    while !probing() {
        assert!(start.elapsed().as_secs() < 60, "no child ran the scene");
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    // SAFETY: signals the child this test started.
    unsafe { libc::kill(child.id() as libc::pid_t, libc::SIGTERM) };
    assert_eq!(child.wait().unwrap().code(), Some(130));
    assert!(!probing(), "a child still runs");
    assert_eq!(
        std::fs::read_dir(&tmp).unwrap().count(),
        0,
        "the temporary folder stayed"
    );
    assert_eq!(listing(&out), before);
    assert_eq!(std::fs::read(out.join("drivers.json")).unwrap(), tables);
}

/// Every file and folder below `p`.
fn walk(p: &Path) -> Vec<PathBuf> {
    let mut v = Vec::new();
    for e in std::fs::read_dir(p).unwrap() {
        let path = e.unwrap().path();
        if path.is_dir() {
            v.extend(walk(&path));
        }
        v.push(path);
    }
    v
}

/// A hang is shrunk within --shrink-budget (a try cut short by
/// it is no evidence, so a budget under one deadline keeps the first
/// size), and no driver's run starts past --budget: those cells are "not
/// run". Each try hung for the whole deadline before, and nothing bounded
/// the run.
#[test]
fn a_hang_is_shrunk_within_its_budget_and_the_run_within_its_own() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let Some(hang) = misbehaving("hang", d) else {
        return;
    };
    let out = d.join("out");
    let o = drivers(
        &[
            "scenes/seed-fig3.toml",
            "scenes/seed-fig4.toml",
            "--quick",
            "--deadline",
            "2",
            "--shrink-budget",
            "1",
            "--budget",
            "1",
        ],
        &[&hang],
        &out,
        &[],
    );
    assert_exit(&o, 1);
    let m = matrix(&out);
    let first = cell(&m, "seed-fig3", 0);
    assert_eq!(first["result"], "hung", "{first}");
    let readme =
        std::fs::read_to_string(out.join(first["repro"].as_str().unwrap()).join("README.md"))
            .unwrap();
    assert!(
        readme.contains("- Size: 64x48, the scene's own sampling."),
        "{readme}"
    );
    let second = cell(&m, "seed-fig4", 0);
    assert_eq!(second["result"], "not_run", "{second}");
}

/// A size whose images do not fit in what the process may use
/// (here an address-space limit of 4 GiB, at 16384x16384) is one error
/// before anything is rendered; it aborted on an allocation after
/// minutes of rendering.
#[test]
fn a_size_that_does_not_fit_is_refused_before_rendering() {
    use std::os::unix::process::CommandExt;
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_glint"));
    c.current_dir(common::repo())
        .args([
            "drivers",
            "scenes/seed-fig3.toml",
            "--width",
            "16384",
            "--height",
            "16384",
        ])
        .arg("-o")
        .arg(&out);
    // SAFETY: setrlimit only, between fork and exec.
    unsafe {
        c.pre_exec(|| {
            let limit = libc::rlimit {
                rlim_cur: 4 << 30,
                rlim_max: 4 << 30,
            };
            if libc::setrlimit(libc::RLIMIT_AS, &limit) == 0 {
                Ok(())
            } else {
                Err(std::io::Error::last_os_error())
            }
        });
    }
    let o = c.output().unwrap();
    common::assert_user_error(&o, "ulimit -v");
    assert!(!out.exists());
}

/// Debian unstable's lavapipe, in the tree `ci/sid-lavapipe` makes, is a
/// column of its own: its children run through the tree's loader
/// (`glint::drivers::tree`), and it passes. Skipped where the tree was
/// not made (ci/test makes it before the lanes where the archive can be
/// reached).
#[test]
fn the_unstable_lavapipe_is_a_column_where_its_tree_is_made() {
    let root = std::env::var_os("XDG_CACHE_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))
        .map(|c| c.join("glint-sid"));
    let icd = root
        .map(|r| glint::drivers::tree::icd_files(&r))
        .and_then(|files| files.into_iter().find(|f| f.ends_with("lvp_icd.json")));
    let Some(icd) = icd else {
        common::skip(
            "drivers on Debian unstable's lavapipe",
            "ci/sid-lavapipe made no tree",
        );
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m");
    let o = drivers(&["--quick", "scenes/seed-fig3.toml"], &[&icd], &out, &[]);
    common::assert_ok(&o);
    let m = matrix(&out);
    let c = column(&m, &icd);
    let identity = &m["columns"][c]["identity"];
    assert!(
        identity["driver"].as_str().unwrap().contains("Mesa"),
        "{identity}"
    );
    assert_eq!(cell(&m, "seed-fig3", c)["result"], "pass", "{m}");
    assert_eq!(m["columns"][c]["name"], "glint-sid/lvp_icd", "{m}");
}

/// A driver manifest that is a FIFO, and a manifest whose
/// library is one, blocked `info`, `render --timeout 2` and `--version` for
/// ever. Opening the device is now bounded (`OPEN_LIMIT`): one line, exit
/// 2, and the process ends though the loader's thread is still blocked.
#[test]
fn a_driver_manifest_or_library_that_is_a_fifo_ends_in_one_line() {
    use std::time::Duration;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let fifo = |name: &str| {
        let path = d.join(name);
        common::make_fifo(&path);
        path
    };
    let manifest_fifo = fifo("fifo.json");
    let library_fifo = fifo("libfifo.so");
    let manifest = d.join("lib-is-fifo.json");
    common::write_icd_manifest(&manifest, &library_fifo);
    let scene = common::repo().join("scenes/seed-fig3.toml");
    let out = d.join("out.png");
    let limit = glint::gpu::OPEN_LIMIT.as_secs();
    std::thread::scope(|s| {
        for icd in [&manifest_fifo, &manifest] {
            for args in [
                vec!["info"],
                vec![
                    "render",
                    scene.to_str().unwrap(),
                    "--timeout",
                    "2",
                    "-o",
                    out.to_str().unwrap(),
                ],
            ] {
                s.spawn(move || {
                    let o = common::cmd()
                        .args(&args)
                        .env("VK_DRIVER_FILES", icd)
                        .timeout(Duration::from_secs(limit + 40))
                        .output()
                        .unwrap();
                    let err = String::from_utf8_lossy(&o.stderr);
                    assert_eq!(o.status.code(), Some(2), "{args:?} {icd:?}: {err}");
                    assert_eq!(err.trim().lines().count(), 1, "{err}");
                    assert!(
                        err.contains(&format!("did not finish within {limit} s")),
                        "{err}"
                    );
                });
            }
        }
    });
    assert!(!out.exists());
}

/// `render` stopped by SIGTERM while
/// its open was stuck in the `dlopen` of a FIFO never ended, since the
/// signal handler's exit waited on the loader's lock. It now ends at once:
/// status 130, one line, no image. The test holds the FIFO open for
/// writing once the loader is in it, so the open stays stuck in its read.
#[test]
fn a_signal_during_a_stuck_open_ends_the_run_at_once() {
    use std::io::Read;
    use std::os::unix::fs::OpenOptionsExt;
    use std::time::{Duration, Instant};
    let dir = tempfile::tempdir().unwrap();
    let library = dir.path().join("libfifo.so");
    common::make_fifo(&library);
    let manifest = dir.path().join("icd.json");
    common::write_icd_manifest(&manifest, &library);
    let out = dir.path().join("out.png");
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_glint"))
        .arg("render")
        .arg(common::repo().join("scenes/seed-fig3.toml"))
        .arg("-o")
        .arg(&out)
        .env("VK_DRIVER_FILES", &manifest)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // A FIFO opens for writing without blocking only while a reader is in
    // its open: the loader is then inside `dlopen`, holding its lock.
    let start = Instant::now();
    let writer = loop {
        match std::fs::OpenOptions::new()
            .write(true)
            .custom_flags(libc::O_NONBLOCK)
            .open(&library)
        {
            Ok(w) => break w,
            Err(e) if e.raw_os_error() == Some(libc::ENXIO) && start.elapsed().as_secs() < 15 => {
                std::thread::sleep(Duration::from_millis(5))
            }
            Err(e) => {
                let _ = child.kill();
                panic!("the loader never opened the FIFO: {e}");
            }
        }
    };
    // SAFETY: signals the child this test started.
    unsafe { libc::kill(child.id() as libc::pid_t, libc::SIGTERM) };
    let signalled = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if signalled.elapsed().as_secs() >= 5 {
            let _ = child.kill();
            let _ = child.wait();
            panic!("SIGTERM did not end a run whose open is stuck");
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    drop(writer);
    let mut err = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    assert_eq!(status.code(), Some(130), "{err}");
    assert_eq!(err.trim(), "error: interrupted");
    assert!(!out.exists());
}

/// `drivers` interrupted while its probes start. The clean-up
/// ran on the signal thread while the main thread went on starting
/// probes, and in about 1 of 5–50 interrupts a probe outlived glint and
/// wrote its work folder back. A child is now started under the lock the
/// clean-up takes, and none starts after it. So is a folder made: the
/// temporary folder, or a probe's folder in it, made while the signal
/// thread exited, stayed (1 of about 20 runs of this test failed so). Over
/// 16 interrupts at delays across the probes' starts, no probe outlives
/// its parent and the temporary folder stays empty.
#[test]
fn an_interrupt_while_probes_start_leaves_no_probe() {
    let dir = tempfile::tempdir().unwrap();
    for k in 0..16u64 {
        let tmp = dir.path().join(format!("tmp{k}"));
        std::fs::create_dir(&tmp).unwrap();
        let out = dir.path().join(format!("out{k}"));
        let mut child = Command::new(env!("CARGO_BIN_EXE_glint"))
            .current_dir(common::repo())
            .args([
                "drivers",
                "scenes/seed-fig3.toml",
                "scenes/seed-fig4.toml",
                "--quick",
                "-o",
            ])
            .arg(&out)
            .env("TMPDIR", &tmp)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(40 + 45 * k));
        // SAFETY: signals the child this test started.
        unsafe { libc::kill(child.id() as libc::pid_t, libc::SIGTERM) };
        let status = child.wait().unwrap();
        // A probe that outlived glint would write its folder back by now.
        std::thread::sleep(std::time::Duration::from_millis(300));
        let name = tmp.to_str().unwrap().to_owned();
        let left: Vec<String> = common::command_lines()
            .into_iter()
            .filter(|c| c.contains("driver-probe") && c.contains(&name))
            .collect();
        assert!(left.is_empty(), "interrupt {k} ({status:?}): {left:?}");
        let files: Vec<_> = std::fs::read_dir(&tmp).unwrap().collect();
        assert!(files.is_empty(), "interrupt {k} ({status:?}): {files:?}");
    }
}

/// After a SIGKILLed `drivers`, its staging folder under -o and
/// its temporary folder stayed, and later runs never removed them. A run
/// now removes those of runs that no longer run (as `render` removes its
/// temporary files), and nothing of a live run or of the user's.
#[test]
fn a_killed_runs_leftovers_are_removed_by_the_next_run() {
    let dir = tempfile::tempdir().unwrap();
    let (out, tmp) = (dir.path().join("out"), dir.path().join("tmp"));
    // No process has a pid past the kernel's largest, 4194304.
    let dead = 4_194_305;
    let live = std::process::id();
    let mark = |d: &Path| {
        std::fs::create_dir_all(d).unwrap();
        std::fs::write(d.join(".glint-drivers"), "x").unwrap();
    };
    let stale = out.join(format!(".glint-drivers-{dead}.new"));
    let stale_old = out.join(format!(".glint-drivers-{dead}.old"));
    let running = out.join(format!(".glint-drivers-{live}.new"));
    let users = out.join(format!(".glint-drivers-{dead}.new-mine"));
    let unmarked = out.join(format!(".glint-drivers-{}.new", dead + 1));
    for d in [&stale, &stale_old, &running] {
        mark(d);
    }
    std::fs::create_dir_all(&users).unwrap();
    std::fs::create_dir_all(&unmarked).unwrap();
    let work = tmp.join(format!("glint-drivers-{dead}-abc"));
    let live_work = tmp.join(format!("glint-drivers-{live}-abc"));
    std::fs::create_dir_all(&work).unwrap();
    std::fs::create_dir_all(&live_work).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_glint"))
        .current_dir(common::repo())
        .args(["drivers", "scenes/seed-fig3.toml", "--quick", "-o"])
        .arg(&out)
        .env("TMPDIR", &tmp)
        .output()
        .unwrap();
    assert!(
        matches!(o.status.code(), Some(0 | 1)),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(!stale.exists() && !stale_old.exists() && !work.exists());
    for kept in [&running, &users, &unmarked, &live_work] {
        assert!(kept.exists(), "{}", kept.display());
    }
}

/// Item 13: on a full file system every probe's report and stderr were
/// lost, and `drivers` called every driver "crashed". A temporary folder
/// without room is refused first, naming it. (Needs a small tmpfs: root.)
#[test]
fn drivers_refuses_a_temporary_folder_without_room() {
    let dir = tempfile::tempdir().unwrap();
    let full = dir.path().join("full");
    std::fs::create_dir(&full).unwrap();
    let mounted = Command::new("mount")
        .args(["-t", "tmpfs", "-o", "size=64k", "tmpfs"])
        .arg(&full)
        .output()
        .is_ok_and(|o| o.status.success());
    if !mounted {
        common::skip(
            "a full temporary folder",
            "cannot mount a tmpfs here (not root)",
        );
        return;
    }
    let o = Command::new(env!("CARGO_BIN_EXE_glint"))
        .current_dir(common::repo())
        .args(["drivers", "scenes/seed-fig3.toml", "--quick", "-o"])
        .arg(dir.path().join("out"))
        .env("TMPDIR", &full)
        .output()
        .unwrap();
    let _ = Command::new("umount").arg(&full).status();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("has no room for the probes' files"), "{err}");
    assert!(err.contains(full.to_str().unwrap()), "{err}");
}
