//! Triangles and meshes: no holes in a closed mesh, smooth normals, and
//! meshes read from OBJ files (docs/scene-format.md, Triangles and Meshes).
//! The intersect's watertightness is a unit test (src/prim/triangle_tests.rs).

mod common;

use std::path::Path;

use glam::DVec3;
use glint::cpu;
use glint::raster::diff::figures;
use glint::raster::Image;
use glint::scene::{parse, Overrides, Scene};

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
    let mut renders = vec![
        ("CPU f32", cpu::render::<f32>(&scene)),
        ("CPU f64", cpu::render::<f64>(&scene)),
    ];
    renders.extend(common::render_gpu_if_built(&scene).map(|image| ("GPU", image)));
    for (what, image) in renders {
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
    #[cfg(feature = "gpu")]
    {
        let mut gpu = common::gpu();
        let mut gpu = |s: &Scene| gpu.render(s, &|_| {}).unwrap().0;
        let (a, b, c) = (gpu(&flat), gpu(&smooth), gpu(&tilted));
        assert!(max_abs(&a, &b) < 1e-5, "{}", max_abs(&a, &b));
        assert!(max_abs(&a, &c) > 0.05);
    }
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

/// A mesh's `rotate`: degrees about x, then y, then z, after the scale and
/// before the translation, its normals turned with it.
#[test]
fn a_rotated_mesh_is_its_points_turned_x_then_y_then_z() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("tri.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n",
    )
    .unwrap();
    let camera = "[camera]\neye = [0.5, 0.5, 6.0]\nlook_at = [0.5, 0.5, 0.0]\nvfov = 40.0\n";
    let placed = |rotate: &str| {
        scene_at(
            dir.path(),
            &format!(
                "{CAMERA}{camera}[[meshes]]\nfile = \"tri.obj\"\nmaterial = \"m\"\n\
                 scale = 2.0\nrotate = {rotate}\ntranslate = [1.0, 0.0, 0.0]\n"
            ),
        )
        .prims
        .triangles[0]
            .clone()
    };
    let near = |a: glam::DVec3, b: [f64; 3]| (a - glam::DVec3::from(b)).length() < 1e-12;
    // About x by 90, then y by 90: (0, 2, 0) goes to (0, 0, 2), then to
    // (2, 0, 0); the other order would leave it at (0, 0, 2).
    let t = placed("[90.0, 90.0, 0.0]");
    assert!(near(t.vertices[2], [3.0, 0.0, 0.0]), "{:?}", t.vertices);
    assert!(near(t.vertices[1], [1.0, 0.0, -2.0]), "{:?}", t.vertices);
    let n = t.normals.expect("smooth normals")[0];
    assert!(near(n, [0.0, -1.0, 0.0]), "{n:?}");
    let t = placed("[0.0, 0.0, 90.0]");
    assert!(near(t.vertices[1], [1.0, 2.0, 0.0]), "{:?}", t.vertices);
    // A whole turn is where it started, to rounding.
    let (turned, still) = (placed("[360.0, 0.0, 0.0]"), placed("[0.0, 0.0, 0.0]"));
    for (a, b) in turned.vertices.iter().zip(&still.vertices) {
        assert!((*a - *b).length() < 1e-12);
    }
    let e = error_of(
        dir.path(),
        &format!(
            "{CAMERA}{camera}[[meshes]]\nfile = \"tri.obj\"\nmaterial = \"m\"\nrotate = [0.0, 1e7, 0.0]\n"
        ),
    );
    assert!(e.contains("meshes[0].rotate") && e.contains("1e7"), "{e}");
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
            "[[meshes]]\nfile = \"broken.obj\"\nmaterial = \"m\"\nspin = 1.0\n",
            "spin",
            "unknown field",
        ),
        (
            "[[meshes]]\nfile = \"broken.obj\"\nmaterial = \"m\"\nrotate = 1.0\n",
            "meshes[0].rotate",
            "expected a sequence",
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

/// A scene read again with a mesh cache (the Python module's
/// `Scene.params`) takes an unchanged OBJ file from the cache and reads a
/// changed one again: the same triangles as a plain parse each time.
#[test]
fn a_mesh_cache_rereads_only_a_changed_file() {
    use glint::scene::{parse_cached, MeshCache};
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("m.obj");
    let quad = |z: &str| format!("v 0 0 {z}\nv 1 0 {z}\nv 1 1 {z}\nv 0 1 {z}\nf 1 2 3 4\n");
    std::fs::write(&obj, quad("0")).unwrap();
    let text = "[image]\nwidth = 4\nheight = 4\n[camera]\neye = [0.5, 0.5, 5]\n\
                look_at = [0.5, 0.5, 0]\nvfov = 40\n[materials.m]\ndiffuse = [1, 1, 1]\n\
                [[meshes]]\nfile = \"m.obj\"\nmaterial = \"m\"\n";
    let file = dir.path().join("scene.toml");
    let o = Overrides::default();
    let cache = MeshCache::default();
    let read = |cache| {
        parse_cached(text, &file, &o, cache)
            .unwrap()
            .prims
            .triangles
    };
    let plain = read(None);
    assert_eq!(plain.len(), 2);
    assert_eq!(read(Some(&cache)), plain);
    assert_eq!(cache.reads(), 1);
    assert_eq!(read(Some(&cache)), plain, "from the cache");
    assert_eq!(cache.reads(), 1, "an unchanged file is not read again");
    // Changed (another length): read again.
    std::fs::write(&obj, quad("-1")).unwrap();
    let moved = read(None);
    assert_ne!(moved, plain);
    assert_eq!(read(Some(&cache)), moved);
    assert_eq!(cache.reads(), 2);
    // Changed with its length and time of modification kept, as `cp -p`,
    // `rsync -a` and `tar x` leave it: its change time tells (the cache
    // kept the old mesh when it looked at length and mtime alone).
    let when = std::fs::metadata(&obj).unwrap().modified().unwrap();
    std::fs::write(&obj, quad("-2")).unwrap();
    std::fs::File::options()
        .write(true)
        .open(&obj)
        .unwrap()
        .set_modified(when)
        .unwrap();
    let again = read(None);
    assert_ne!(again, moved);
    assert_eq!(read(Some(&cache)), again);
    // Another file of the same length and times renamed over it (an
    // editor's save, `rsync`'s rename): its inode tells.
    let other = dir.path().join("m2.obj");
    std::fs::write(&other, quad("-3")).unwrap();
    let f = std::fs::File::options().write(true).open(&other).unwrap();
    f.set_modified(when).unwrap();
    drop(f);
    std::fs::rename(&other, &obj).unwrap();
    let renamed = read(None);
    assert_ne!(renamed, again);
    assert_eq!(read(Some(&cache)), renamed);
}
