//! The NFF reader's unit tests.

use super::*;

fn read_str(text: &str) -> Result<Nff, SceneError> {
    read(text, Path::new("t.nff"))
}

const VIEW: &str = "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution 8 8\n";

#[test]
fn a_polygon_is_a_fan_and_a_patch_keeps_its_normals() {
    let text = format!(
        "{VIEW}f 1 0 0 1 0 1 0 1\np 4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n\
         pp 3\n0 0 1 0 0 1\n1 0 1 0 0 1\n0 1 1 0 1 1\n"
    );
    let nff = read_str(&text).unwrap();
    assert_eq!(nff.scene.triangles.len(), 3);
    assert!(nff.scene.triangles[0].normals.is_none());
    assert!(nff.scene.triangles[2].normals.is_some());
    let at = |i: usize| {
        let path = KeyPath::default().key("triangles").index(i);
        nff.lines.find(&path).map(|at| at.line)
    };
    assert_eq!(at(1), Some(9));
    assert_eq!(at(2), Some(14));
}

#[test]
fn identical_fills_are_one_material() {
    let text = format!(
        "{VIEW}f 1 0 0 1 0 1 0 1\ns 0 0 0 1\nf 0 1 0 1 0 1 0 1\ns 0 0 0 1\n\
         f 1 0 0 1 0 1 0 1\ns 0 0 0 -1\n"
    );
    let nff = read_str(&text).unwrap();
    assert_eq!(nff.scene.materials.len(), 2);
    let m: Vec<&str> = nff
        .scene
        .spheres
        .iter()
        .map(|s| s.material.as_str())
        .collect();
    assert_eq!(m, ["f1", "f2", "f1"]);
    assert_eq!(nff.scene.spheres[2].radius, 1.0);
}

#[test]
fn errors_name_the_line() {
    for (text, line, words) in [
        (format!("{VIEW}s 0 0 0 1\n"), 8, "before any \"f\""),
        (
            format!("{VIEW}f 1 0 0 1 0 1 0\n"),
            8,
            "expected 8 numbers, got 7",
        ),
        (
            format!("{VIEW}f 1 0 0 1 0 1 0 1\np 3\n0 0 0\n1 0\n"),
            11,
            "p vertex 2",
        ),
        (
            format!("{VIEW}f 1 0 0 1 0 1 0 1\np 3\n0 0 0\n"),
            10,
            "file ends",
        ),
        (format!("{VIEW}q 1\n"), 8, "unknown entity \"q\""),
        (
            format!("{VIEW}f 1 0 0 1 0 1 0 1\nc 0 0 0 1 0 1 0\n"),
            9,
            "c: expected 8 numbers",
        ),
        ("b 0 0 0\n".to_owned(), 1, "no view"),
        (
            VIEW.replace("angle 40", "angle x"),
            5,
            "not a finite number",
        ),
        (VIEW.replace("hither 1", "yon 1"), 6, "expected \"hither\""),
    ] {
        let msg = read_str(&text).err().expect(&text).to_string();
        assert!(msg.starts_with(&format!("t.nff:{line}:")), "{msg}");
        assert!(msg.contains(words), "{words}: {msg}");
    }
}

#[test]
fn the_angle_spans_the_edge_pixels_centres() {
    let text = format!("{VIEW}b 0 0 0\n");
    let scene = crate::scene::parse_nff(&text, Path::new("t.nff"), &Default::default()).unwrap();
    // The top row's centre at 1 − 1/8 of the half-height is 20° up.
    let top = scene.camera.screen_up.y * (1.0 - 1.0 / 8.0);
    assert!((top - 20f64.to_radians().tan()).abs() < 1e-15, "{top}");
}
