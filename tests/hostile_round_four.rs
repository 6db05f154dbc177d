//! Defects of issue 41 (hostile input, round four) that need no GPU, each
//! fixed: a polygon that is a fan of a million triangles, a comment that
//! defeated the block-by-block parse, and a change that kept its file's
//! size and time. Each is one clear error with exit status 2, or the right
//! answer, and no panic.

mod common;

use std::path::Path;
use std::process::Output;

use common::glint;

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn assert_refused(o: &Output, needle: &str) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains(needle), "wanted {needle:?} in: {err}");
}

/// A CPU render of `scene` at 8x8 into `dir`.
fn render(dir: &Path, scene: &Path) -> Output {
    let out = dir.join("out.png");
    glint(&[
        "render",
        scene.to_str().unwrap(),
        "--backend",
        "cpu",
        "--width",
        "8",
        "--height",
        "8",
        "-o",
        out.to_str().unwrap(),
    ])
}

/// `f 1 2 3 4 2 3 4 …`: a triangle for every 2 bytes of a 2 MB file, which
/// took 324 MB on the CPU; and an NFF polygon of a million corners.
#[test]
fn a_polygon_fan_past_the_files_allowance_is_refused_naming_the_face() {
    let dir = tempfile::tempdir().unwrap();
    let fan = format!(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 1 2 3 {}\n",
        ["4 2 3"; 330_000].join(" ")
    );
    std::fs::write(dir.path().join("fan.obj"), fan).unwrap();
    let scene = dir.path().join("fan.toml");
    std::fs::write(
        &scene,
        "[image]\nwidth = 8\nheight = 8\n[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nvfov = 40\n[materials.m]\n\
         [[meshes]]\nfile = \"fan.obj\"\nmaterial = \"m\"\n",
    )
    .unwrap();
    assert_refused(
        &render(dir.path(), &scene),
        "fan.obj:6: this face brings the file to",
    );

    let mut nff = String::from(
        "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution 8 8\nb 0 0 0\n\
         l 1 1 1\nf 1 0 0 1 0 0 0 1\np 1000000\n",
    );
    nff.push_str(&"0 0 0\n".repeat(1_000_000));
    let scene = dir.path().join("p.nff");
    std::fs::write(&scene, nff).unwrap();
    assert_refused(
        &render(dir.path(), &scene),
        "p.nff:11:1: this face brings the file to",
    );
}

/// The same faces written one triangle a line are within the allowance.
#[test]
fn triangles_written_as_triangles_are_within_the_allowance() {
    use std::fmt::Write;
    let dir = tempfile::tempdir().unwrap();
    let mut obj = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n");
    for _ in 0..100_000 {
        writeln!(obj, "f 1 2 3").unwrap();
    }
    std::fs::write(dir.path().join("many.obj"), obj).unwrap();
    let scene = dir.path().join("many.toml");
    std::fs::write(
        &scene,
        "[image]\nwidth = 8\nheight = 8\n[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nvfov = 40\n[materials.m]\n\
         [[meshes]]\nfile = \"many.obj\"\nmaterial = \"m\"\n",
    )
    .unwrap();
    let o = render(dir.path(), &scene);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// A main shader of `terms` additions in one expression.
#[cfg(feature = "gpu")]
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
#[cfg(feature = "gpu")]
#[test]
fn deep_and_large_shader_sources_compile_or_are_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let deep = deep_sum(dir.path(), 20_001);
    let o = glint(&["shader", "check", deep.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let large = deep_sum(dir.path(), 500_000);
    let o = glint(&["shader", "check", large.to_str().unwrap()]);
    let err = stderr(&o);
    assert!(!o.status.success() && o.status.code() != Some(134), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.contains("past the bound of 512 KiB on one compile"),
        "{err}"
    );
}
