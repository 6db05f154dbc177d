//! OBJ and NFF faces from hostile files: a polygon written as a fan of
//! a million triangles is refused naming its face, against the file's
//! allowance of triangles, and the same faces written one triangle a line
//! load; a million faces that no tree can separate bound the CPU's render
//! by what they cost through it. Each refusal is one clear error with exit status 2 and no panic.

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

/// A million identical faces (20 MB, within the triangles'
/// allowance) make a tree that cannot separate them, so every ray tests
/// them all. The CPU's bound counted rays alone, and 1024x768 (hours) was
/// accepted; it now counts each ray at what it costs through the tree that
/// was built, and refuses the render in one line, at once.
#[test]
fn a_tree_that_cannot_separate_its_faces_bounds_the_cpu_by_its_cost() {
    let dir = tempfile::tempdir().unwrap();
    let mut obj = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    obj.push_str(&"f 1 2 3            \n".repeat(1_000_000));
    std::fs::write(dir.path().join("same.obj"), obj).unwrap();
    let scene = dir.path().join("same.toml");
    std::fs::write(
        &scene,
        "[image]\nwidth = 1024\nheight = 768\n[render]\nmax_depth = 3\n\
         [camera]\neye = [0.3, 0.3, 3]\nlook_at = [0.3, 0.3, 0]\nvfov = 40\n[materials.m]\n\
         [[meshes]]\nfile = \"same.obj\"\nmaterial = \"m\"\n\
         [[lights]]\ntype = \"point\"\nposition = [0, 0, 5]\ndiffuse = [1, 1, 1]\n",
    )
    .unwrap();
    let out = dir.path().join("out.png");
    let o = glint(&[
        "render",
        scene.to_str().unwrap(),
        "--backend",
        "cpu",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_refused(
        &o,
        "node visits and tests through its tree of 1000000 primitives",
    );
    assert!(!out.exists());
}
