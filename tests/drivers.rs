//! `glint drivers` (issue 34): the scenes on each driver, each in its own
//! process, held to the CPU f64 reference; a wrong driver is caught with a
//! reproducer, and a crashing one is a row, not the end of the run.

#![cfg(feature = "gpu")]

mod common;

use std::path::{Path, PathBuf};
use std::process::Output;

use serde_json::Value;

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

/// Debian 12's stock lavapipe (Mesa 22.3), as `ci/old-lavapipe` unpacks it.
fn old_lavapipe() -> Option<PathBuf> {
    let o = std::process::Command::new(common::repo().join("ci/old-lavapipe"))
        .output()
        .ok()?;
    let path = PathBuf::from(String::from_utf8_lossy(&o.stdout).trim());
    (o.status.success() && path.is_file()).then_some(path)
}

fn both_lavapipes(what: &str) -> Option<(PathBuf, PathBuf)> {
    match (current_lavapipe(), old_lavapipe()) {
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
/// switched off, its lane is wrong, and the matrix says so with a
/// reproducer that holds what a bug report needs.
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
        &[("GLINT_EXPERIMENT", "unroll-all")],
    );
    assert_eq!(
        o.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
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
        .env("GLINT_EXPERIMENT", "unroll-all")
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
    let built = std::process::Command::new("cc")
        .args(["-shared", "-fPIC", "-o"])
        .arg(&lib)
        .arg(&c)
        .status();
    if !built.is_ok_and(|s| s.success()) {
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
    assert_eq!(o.status.code(), Some(1));
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

/// Issue 42, defect 15: `--icd` naming a directory, a FIFO, a loop of
/// links or nothing says which, in one line, before any driver runs.
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

/// Issue 42, defect 3: two scenes of one stem (a/s.toml, b/s.toml) are two
/// rows, each named by its path.
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
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let m = matrix(&out);
    let rows: Vec<&str> = m["rows"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["scene"].as_str().unwrap())
        .collect();
    assert_eq!(rows, [a.to_str().unwrap(), b.to_str().unwrap()]);
}

/// Issue 42, defect 6: `--icd X --only`, where X gives no device, tested
/// nothing and exited 0; it is one error, exit 2, and no table.
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
