//! Triangles and meshes: the watertight intersection, smooth normals, and
//! meshes read from OBJ files (docs/scene-format.md, Triangles and Meshes).

mod common;

use std::path::Path;

use glam::DVec3;
use glint::cpu;
use glint::cpu::ray::Ray;
use glint::cpu::real::{Real, Vec3};
use glint::prim::triangle::{Triangle, TriangleR};
use glint::prim::{Kind, Shape};
use glint::raster::diff::figures;
use glint::raster::Image;
use glint::scene::{parse, Overrides, Scene};

/// The unit octahedron, closed: every edge is shared by two faces.
fn octahedron() -> Vec<Triangle> {
    let v = [
        DVec3::X,
        DVec3::NEG_X,
        DVec3::Y,
        DVec3::NEG_Y,
        DVec3::Z,
        DVec3::NEG_Z,
    ];
    let faces = [
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    faces
        .iter()
        .map(|f| Triangle::new(f.map(|i| v[i]), None, 0).unwrap())
        .collect()
}

/// Rays from inside the octahedron aimed exactly at its edges (at points
/// along them) and at its vertices: each must leave through some face.
fn rays_at_edges_and_vertices<R: Real>(n: usize) -> Vec<Ray<R>> {
    let tris = octahedron();
    let mut rng = common::Rng(0x9e37_79b9_7f4a_7c15);
    let mut rays = Vec::new();
    for _ in 0..n {
        for t in &tris {
            for (a, b) in [(0, 1), (1, 2), (2, 0)] {
                let (a, b) = (t.vertices[a], t.vertices[b]);
                for target in [a, a + (b - a) * rng.unit()] {
                    let origin = DVec3::new(rng.unit(), rng.unit(), rng.unit()) * 0.6 - 0.3;
                    let origin = Vec3::of(origin);
                    let dir = (Vec3::of(target) - origin).normalize();
                    rays.push(Ray { origin, dir });
                }
            }
        }
    }
    rays
}

fn leaks<R: Real>(hit: impl Fn(&TriangleR<R>, &Ray<R>) -> bool) -> usize {
    let tris: Vec<TriangleR<R>> = octahedron().iter().map(|t| t.cpu()).collect();
    rays_at_edges_and_vertices::<R>(400)
        .iter()
        .filter(|r| !tris.iter().any(|t| hit(t, r)))
        .count()
}

#[test]
fn rays_through_shared_edges_and_vertices_never_leak() {
    assert_eq!(leaks::<f32>(|t, r| t.intersect(r, false).is_some()), 0);
    assert_eq!(leaks::<f64>(|t, r| t.intersect(r, false).is_some()), 0);
}

/// The check above can fail: the textbook Möller–Trumbore test, which
/// computes each edge test from barycentric coordinates of its own, lets
/// some of the same rays through in f32.
#[test]
fn a_test_that_is_not_watertight_leaks_on_the_same_rays() {
    let moller_trumbore = |t: &TriangleR<f32>, r: &Ray<f32>| {
        let [v0, v1, v2] = t.vertices;
        let (e1, e2) = (v1 - v0, v2 - v0);
        let p = r.dir.cross(e2);
        let det = e1.dot(p);
        if det == 0.0 {
            return false;
        }
        let tv = r.origin - v0;
        let u = tv.dot(p) / det;
        let q = tv.cross(e1);
        let v = r.dir.dot(q) / det;
        u >= 0.0 && v >= 0.0 && u + v <= 1.0 && e2.dot(q) / det > 0.0
    };
    assert!(leaks::<f32>(moller_trumbore) > 0);
}

fn scene_at(dir: &Path, text: &str) -> Scene {
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    Scene::load(&path, &Overrides::default()).unwrap_or_else(|e| panic!("{e}"))
}

const CAMERA: &str = r#"
[image]
width = 96
height = 72
[render]
max_depth = 3
background = [1.0, 0.0, 1.0]
[materials.m]
ambient = [0.2, 0.2, 0.2]
diffuse = [0.6, 0.6, 0.6]
specular = [0.5, 0.5, 0.5]
shininess = 20.0
reflectivity = 0.3
[[lights]]
type = "point"
position = [0.1, 0.2, 0.3]
ambient = [0.2, 0.2, 0.2]
diffuse = [0.8, 0.8, 0.8]
"#;

/// A camera inside the closed icosphere of scenes/meshes/, with a light
/// inside too: no eye ray and no reflection may escape to the background.
#[test]
fn a_closed_mesh_seen_from_inside_has_no_holes() {
    let mesh = common::repo().join("scenes/meshes/icosphere-flat.obj");
    let text = format!(
        "{CAMERA}[camera]\neye = [0.05, -0.1, 0.02]\nlook_at = [1.0, 0.3, 0.2]\nvfov = 120.0\n\
         [[meshes]]\nfile = \"{}\"\nmaterial = \"m\"\nscale = 2.0\n",
        mesh.display()
    );
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_at(dir.path(), &text);
    let magenta = |p: &[f32; 3]| p[0] > 0.99 && p[1] == 0.0 && p[2] > 0.99;
    for (what, image) in [
        ("GPU", common::render_gpu(&scene)),
        ("CPU f32", cpu::render::<f32>(&scene)),
        ("CPU f64", cpu::render::<f64>(&scene)),
    ] {
        assert!(!image.pixels.iter().any(magenta), "{what}: a ray escaped");
    }
    // The check can fail: with every tenth face left out, rays escape.
    let obj = std::fs::read_to_string(&mesh).unwrap();
    let mut face = 0;
    let holed: String = obj
        .lines()
        .filter(|l| {
            !l.starts_with("f ") || {
                face += 1;
                face % 10 != 0
            }
        })
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(dir.path().join("holed.obj"), holed).unwrap();
    let text = text.replace(&mesh.display().to_string(), "holed.obj");
    let scene = scene_at(dir.path(), &text);
    assert!(cpu::render::<f64>(&scene).pixels.iter().any(magenta));
}

fn pyramid(normals: &str) -> String {
    format!(
        "{CAMERA}[camera]\neye = [0.0, 1.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nvfov = 50.0\n\
         [[triangles]]\nvertices = [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 1.0, -0.5]]\n{normals}\
         material = \"m\"\n\
         [[triangles]]\nvertices = [[1.0, -1.0, 0.0], [1.0, 1.0, -2.0], [0.0, 1.0, -0.5]]\n\
         material = \"m\"\n"
    )
}

/// Vertex normals equal to the face's own normal shade as the flat
/// triangle does, on both renderers (to rounding: the interpolation
/// normalises a sum of three copies), and other normals do not.
#[test]
fn vertex_normals_equal_to_the_face_normal_change_nothing() {
    let n = (DVec3::new(2.0, 0.0, 0.0))
        .cross(DVec3::new(1.0, 2.0, -0.5))
        .normalize();
    let normals = format!(
        "normals = [[{0}, {1}, {2}], [{0}, {1}, {2}], [{0}, {1}, {2}]]\n",
        n.x, n.y, n.z
    );
    let flat = common::scene(&pyramid(""));
    let smooth = common::scene(&pyramid(&normals));
    let tilted = common::scene(&pyramid(
        "normals = [[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]]\n",
    ));
    let max_abs = |a: &Image, b: &Image| figures(a, b).unwrap().max_abs;
    let cpu = |s: &Scene| cpu::render::<f64>(s);
    assert!(max_abs(&cpu(&flat), &cpu(&smooth)) < 1e-12);
    assert!(max_abs(&cpu(&flat), &cpu(&tilted)) > 0.05);
    let mut gpu = common::gpu();
    let mut gpu = |s: &Scene| gpu.render(s, &|_| {}).unwrap().0;
    let (a, b, c) = (gpu(&flat), gpu(&smooth), gpu(&tilted));
    assert!(max_abs(&a, &b) < 1e-5, "{}", max_abs(&a, &b));
    assert!(max_abs(&a, &c) > 0.05);
}

#[test]
fn interpolated_normals_are_the_vertex_normals_at_the_vertices() {
    let normals = [
        DVec3::new(0.0, 0.0, 1.0),
        DVec3::new(1.0, 0.0, 1.0).normalize(),
        DVec3::new(0.0, 1.0, 1.0).normalize(),
    ];
    let vertices = [DVec3::ZERO, DVec3::X, DVec3::Y];
    let t: TriangleR<f64> = Triangle::new(vertices, Some(normals), 0).unwrap().cpu();
    for (v, n) in vertices.iter().zip(normals) {
        let s = t.shading(Vec3::of(*v), t.normal(Vec3::of(*v)));
        assert!(
            (DVec3::new(s.x, s.y, s.z) - n).length() < 1e-12,
            "{s:?} {n}"
        );
    }
    // Halfway along the first edge: the normalised mean of its ends.
    let s = t.shading(Vec3::new(0.5, 0.0, 0.0), t.normal(Vec3::zero()));
    let want = (normals[0] + normals[1]).normalize();
    assert!((DVec3::new(s.x, s.y, s.z) - want).length() < 1e-12);
}

/// A mesh placed with scale and translate is the same triangles written
/// out in the scene file: the same image, bit for bit.
#[test]
fn a_mesh_is_its_triangles_placed() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("tri.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 -1\nf 1 2 3\nf 2 4 3\n",
    )
    .unwrap();
    let camera = "[camera]\neye = [0.5, 0.5, 6.0]\nlook_at = [0.5, 0.5, 0.0]\nvfov = 40.0\n";
    let mesh = scene_at(
        dir.path(),
        &format!(
            "{CAMERA}{camera}[[meshes]]\nfile = \"tri.obj\"\nmaterial = \"m\"\n\
             scale = 2.0\ntranslate = [-0.5, -0.5, 0.25]\n"
        ),
    );
    let written = common::scene(&format!(
        "{CAMERA}{camera}\
         [[triangles]]\nvertices = [[-0.5, -0.5, 0.25], [1.5, -0.5, 0.25], [-0.5, 1.5, 0.25]]\nmaterial = \"m\"\n\
         [[triangles]]\nvertices = [[1.5, -0.5, 0.25], [1.5, 1.5, -1.75], [-0.5, 1.5, 0.25]]\nmaterial = \"m\"\n"
    ));
    assert_eq!(mesh.prims, written.prims);
    assert_eq!(
        cpu::render::<f32>(&mesh).pixels,
        cpu::render::<f32>(&written).pixels
    );
}

fn error_of(dir: &Path, text: &str) -> String {
    let path = dir.join("bad.toml");
    std::fs::write(&path, text).unwrap();
    match Scene::load(&path, &Overrides::default()) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn bad_triangles_and_meshes_are_named() {
    let camera = "[camera]\neye = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\nvfov = 40.0\n";
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("broken.obj"), "v 0 0 0\nv 1 0 0\nf 1 2 9\n").unwrap();
    for (table, key, words) in [
        (
            "[[triangles]]\nvertices = [[0, 0, 0], [1, 1, 1], [2, 2, 2]]\nmaterial = \"m\"\n",
            "triangles[0].vertices",
            "no area",
        ),
        (
            "[[triangles]]\nvertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\n\
             normals = [[0, 0, 1], [0, 0, 0], [0, 0, 1]]\nmaterial = \"m\"\n",
            "triangles[0].normals[1]",
            "non-zero",
        ),
        (
            "[[triangles]]\nvertices = [[0, 0, 0], [1, 0, 0]]\nmaterial = \"m\"\n",
            "triangles[0].vertices",
            "length",
        ),
        (
            "[[meshes]]\nfile = \"missing.obj\"\nmaterial = \"m\"\n",
            "meshes[0].file",
            "cannot read",
        ),
        (
            "[[meshes]]\nfile = \"broken.obj\"\nmaterial = \"m\"\n",
            "meshes[0].file",
            "not a valid OBJ",
        ),
        (
            "[[meshes]]\nfile = \"broken.obj\"\nmaterial = \"m\"\nscale = 0.0\n",
            "meshes[0].scale",
            "> 0",
        ),
        (
            "[[meshes]]\nfile = \"broken.obj\"\nmaterial = \"m\"\nrotate = 1.0\n",
            "rotate",
            "unknown field",
        ),
    ] {
        let msg = error_of(dir.path(), &format!("{CAMERA}{camera}{table}"));
        assert!(msg.contains("bad.toml:"), "{msg}");
        assert!(msg.contains(key), "expected {key}: {msg}");
        assert!(msg.contains(words), "expected {words:?}: {msg}");
    }
    // And the scene without the bad table parses: the errors are the tables'.
    parse(
        &format!("{CAMERA}{camera}"),
        Path::new("ok.toml"),
        &Overrides::default(),
    )
    .unwrap();
}
