//! OBJ materials (docs/scene-format.md, Triangles and meshes): a mesh
//! without a `material` takes each object's from its MTL file, mapped after
//! the MTL format's illumination models; bad MTL files are named.

mod common;

use std::path::Path;

use glam::DVec3;
use glint::cpu;
use glint::raster::diff::{figures, Tolerance};
use glint::scene::{parse, Overrides, Scene};

const OBJ: &str = "mtllib cubes.mtl\n\
    v -2 -1 0\nv -0.2 -1 0\nv -0.2 1 0\nv -2 1 0\n\
    v 0.2 -1 -0.5\nv 2 -1 -0.5\nv 2 1 -0.5\nv 0.2 1 -0.5\n\
    v -3 -1.2 -2\nv 3 -1.2 -2\nv 3 -1.2 3\nv -3 -1.2 3\n\
    o red\nusemtl red\nf 1 2 3 4\n\
    o glass\nusemtl glass\nf 5 6 7 8\n\
    o floor\nusemtl floor\nf 9 10 11 12\n";

const MTL: &str = "newmtl red\nKa 0.1 0.02 0.02\nKd 0.8 0.1 0.1\nKs 0.3 0.3 0.3\nNs 40\nillum 2\n\
    newmtl glass\nKd 0.05 0.05 0.05\nKs 0.6 0.3 0.3\nNs 200\nNi 1.33\nd 0.25\nillum 4\n\
    newmtl floor\nKa 0.2 0.2 0.2\nKd 0.6 0.6 0.5\nKs 0.9 0.9 0.9\nTr 0.5\nillum 1\n";

fn scene_text(material: &str) -> String {
    format!(
        "[image]\nwidth = 64\nheight = 48\n[render]\nmax_depth = 4\n\
         [camera]\neye = [0.0, 0.5, 6.0]\nlook_at = [0.0, 0.0, 0.0]\nvfov = 45.0\n\
         [materials.grey]\ndiffuse = [0.5, 0.5, 0.5]\n\
         [[meshes]]\nfile = \"model.obj\"\n{material}\
         [[lights]]\ntype = \"point\"\nposition = [2.0, 4.0, 5.0]\nambient = [0.2, 0.2, 0.2]\n\
         diffuse = [0.9, 0.9, 0.9]\nspecular = [1.0, 1.0, 1.0]\n"
    )
}

fn write(dir: &Path, obj: &str, mtl: Option<&str>) {
    std::fs::write(dir.join("model.obj"), obj).unwrap();
    if let Some(mtl) = mtl {
        std::fs::write(dir.join("cubes.mtl"), mtl).unwrap();
    }
}

fn load(dir: &Path, text: &str) -> Result<Scene, String> {
    parse(text, &dir.join("scene.toml"), &Overrides::default()).map_err(|e| e.to_string())
}

#[test]
fn a_mesh_without_a_material_takes_its_mtl_materials() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), OBJ, Some(MTL));
    let scene = load(dir.path(), &scene_text("")).unwrap();
    // The scene's own material, then the MTL's in the file's order.
    let names: Vec<&str> = scene.materials.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names.len(), 4, "{names:?}");
    assert!(names[1].ends_with("cubes.mtl: red"), "{names:?}");
    let [red, glass, floor] = [
        &scene.materials[1],
        &scene.materials[2],
        &scene.materials[3],
    ];
    // illum 2: highlights, no reflection.
    assert_eq!(red.ambient, DVec3::new(0.1, 0.02, 0.02));
    assert_eq!(red.diffuse, DVec3::new(0.8, 0.1, 0.1));
    assert_eq!(
        (red.shininess, red.reflectivity, red.transmittance),
        (40.0, 0.0, 0.0)
    );
    // illum 4: reflection of weight mean(Ks), refraction of weight 1 - d.
    assert!((glass.reflectivity - 0.4).abs() < 1e-12, "{glass:?}");
    assert_eq!((glass.transmittance, glass.ior), (0.75, 1.33));
    // illum 1: ambient and diffuse, no highlight, and Tr ignored (opaque model).
    assert_eq!(floor.specular, DVec3::ZERO);
    assert_eq!(floor.transmittance, 0.0);
    // Each object's faces carry its material.
    let used: Vec<u32> = scene.prims.triangles.iter().map(|t| t.material).collect();
    assert_eq!(used, [1, 1, 2, 2, 3, 3]);
    // The MTL file is one of the scene's inputs (an output may not replace it).
    assert!(scene.input_files.iter().any(|f| f.ends_with("cubes.mtl")));

    let reference = cpu::render::<f64>(&scene);
    let tolerance = Tolerance::default();
    let f32_figures = figures(&cpu::render::<f32>(&scene), &reference).unwrap();
    assert!(
        tolerance.violations(&f32_figures).is_empty(),
        "{f32_figures:?}"
    );
    if let Some(gpu) = common::render_gpu_if_built(&scene) {
        let f = figures(&gpu, &reference).unwrap();
        assert!(tolerance.violations(&f).is_empty(), "{f:?}");
    }
    // Another Kd in the MTL file is another image.
    write(
        dir.path(),
        OBJ,
        Some(&MTL.replace("Kd 0.8 0.1 0.1", "Kd 0.1 0.8 0.1")),
    );
    let green = load(dir.path(), &scene_text("")).unwrap();
    let f = figures(&cpu::render::<f64>(&green), &reference).unwrap();
    assert!(!tolerance.violations(&f).is_empty(), "{f:?}");
}

#[test]
fn a_mesh_with_a_material_reads_no_mtl_file() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), OBJ, None);
    let scene = load(dir.path(), &scene_text("material = \"grey\"\n")).unwrap();
    assert_eq!(scene.materials.len(), 1);
    assert!(scene.prims.triangles.iter().all(|t| t.material == 0));
}

#[test]
fn bad_mtl_files_are_named() {
    let dir = tempfile::tempdir().unwrap();
    for (obj, mtl, words) in [
        (OBJ.to_owned(), None, "cannot read"),
        (
            OBJ.replace("usemtl red\n", ""),
            Some(MTL.to_owned()),
            "object \"red\" has no material",
        ),
        (
            OBJ.to_owned(),
            Some(MTL.replace("Kd 0.8 0.1 0.1", "Kd 0.8 -0.1 0.1")),
            "material \"red\": Kd must be finite and >= 0",
        ),
        (
            OBJ.to_owned(),
            Some(MTL.replace("illum 4", "illum 11")),
            "material \"glass\": illum must be in 0..=10",
        ),
        (
            OBJ.to_owned(),
            Some(MTL.replace("d 0.25", "d 1.5")),
            "material \"glass\": d (or 1 - Tr) is out of range",
        ),
        (
            OBJ.to_owned(),
            Some(MTL.replace("Ns 40\n", "Ns 40\nmap_Kd red.png\n")),
            "map_Kd: cannot read the image",
        ),
        (
            OBJ.to_owned(),
            Some(MTL.replace("Ns 40\n", "Ns 40\nmap_Kd -s 2 2 1 red.png\n")),
            "a map's file name alone, without options",
        ),
    ] {
        let _ = std::fs::remove_file(dir.path().join("cubes.mtl"));
        write(dir.path(), &obj, mtl.as_deref());
        let msg = load(dir.path(), &scene_text("")).unwrap_err();
        assert!(msg.contains("scene.toml:"), "{msg}");
        assert!(msg.contains("meshes[0]"), "{msg}");
        assert!(msg.contains(words), "expected {words:?}: {msg}");
        assert_eq!(msg.lines().count(), 1, "{msg}");
    }
}

/// Each MTL file's maps are found beside it and its materials named after
/// it, whichever `mtllib` line named it (the second file's maps were
/// looked up beside the first, and the texture it named was not an
/// input).
#[test]
fn each_mtl_file_resolves_its_maps_in_its_own_folder() {
    let dir = tempfile::tempdir().unwrap();
    let sub = dir.path().join("sub");
    std::fs::create_dir(&sub).unwrap();
    let obj = OBJ
        .replace(
            "mtllib cubes.mtl\n",
            "mtllib cubes.mtl\nmtllib sub/more.mtl\n",
        )
        .replace(
            "f 9 10 11 12",
            "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 9/1 10/2 11/3 12/4",
        );
    let mtl = MTL.replace("newmtl floor", "newmtl old_floor");
    write(dir.path(), &obj, Some(&mtl));
    std::fs::write(
        sub.join("more.mtl"),
        "newmtl floor\nKd 1 1 1\nmap_Kd tex.pfm\n",
    )
    .unwrap();
    // Only the folder of more.mtl holds tex.pfm: red there, green beside
    // cubes.mtl, where the map was wrongly looked up.
    let pfm = |rgb: [f32; 3]| {
        let mut bytes = b"PF\n1 1\n-1.0\n".to_vec();
        bytes.extend(rgb.iter().flat_map(|c| c.to_le_bytes()));
        bytes
    };
    std::fs::write(sub.join("tex.pfm"), pfm([1.0, 0.0, 0.0])).unwrap();
    std::fs::write(dir.path().join("tex.pfm"), pfm([0.0, 1.0, 0.0])).unwrap();
    let scene = load(dir.path(), &scene_text("")).unwrap();
    let floor = scene.materials.last().unwrap();
    assert!(floor.name.ends_with("more.mtl: floor"), "{}", floor.name);
    assert_eq!(scene.texels.as_slice(), [[1.0, 0.0, 0.0]]);
    let inputs = &scene.input_files;
    assert!(
        inputs.iter().any(|f| f.ends_with("sub/more.mtl")),
        "{inputs:?}"
    );
    assert!(
        inputs.iter().any(|f| f.ends_with("sub/tex.pfm")),
        "{inputs:?}"
    );
    // An error in the second file names that file.
    std::fs::write(sub.join("more.mtl"), "newmtl floor\nKd 1 -1 1\n").unwrap();
    let msg = load(dir.path(), &scene_text("")).unwrap_err();
    assert!(msg.contains("more.mtl: material \"floor\""), "{msg}");
}

/// A colour line with fewer than three values is one error naming the
/// file and line (tobj panicked, exit 101).
#[test]
fn short_colour_lines_are_named_not_panics() {
    let dir = tempfile::tempdir().unwrap();
    for (from, to, words) in [
        (
            "Kd 0.8 0.1 0.1",
            "Kd 1 1",
            "cubes.mtl:3: Kd needs three numbers (r g b), got 2",
        ),
        (
            "Ka 0.1 0.02 0.02",
            "Ka 1",
            "cubes.mtl:2: Ka needs three numbers (r g b), got 1",
        ),
        (
            "Ns 40",
            "Ns 40\nKe 1",
            "cubes.mtl:6: Ke needs three numbers (r g b), got 1",
        ),
        (
            "Ns 40",
            "Ns 40\n  Ks\r",
            "cubes.mtl:6: Ks needs three numbers (r g b), got 0",
        ),
    ] {
        write(dir.path(), OBJ, Some(&MTL.replacen(from, to, 1)));
        let msg = load(dir.path(), &scene_text("")).unwrap_err();
        assert!(msg.contains(words), "expected {words:?}: {msg}");
        assert_eq!(msg.lines().count(), 1, "{msg}");
    }
}

/// A file named by many `mtllib` lines is read once (1,000 lines naming
/// one file loaded its materials 1,000 times).
#[test]
fn an_mtl_file_named_again_is_read_once() {
    let dir = tempfile::tempdir().unwrap();
    let again = "mtllib cubes.mtl\nmtllib ./cubes.mtl\n".repeat(500);
    write(dir.path(), &format!("{again}{OBJ}"), Some(MTL));
    let scene = load(dir.path(), &scene_text("")).unwrap();
    assert_eq!(scene.materials.len(), 4);
    let used: Vec<u32> = scene.prims.triangles.iter().map(|t| t.material).collect();
    assert_eq!(used, [1, 1, 2, 2, 3, 3]);
}

/// A long name or number does not push out what the error says is wrong:
/// names are cut, numbers shown in exponent form, and the message whole
/// (the line was cut at 200 characters as a whole).
#[test]
fn long_names_and_numbers_leave_the_reason_in_the_message() {
    let dir = tempfile::tempdir().unwrap();
    let name = "m".repeat(300);
    let obj = OBJ.replace("usemtl red", &format!("usemtl {name}"));
    let mtl = MTL.replace(
        "newmtl red\nKa 0.1 0.02 0.02\nKd 0.8 0.1 0.1",
        &format!("newmtl {name}\nKa 0.1 0.02 0.02\nKd 0.8 -0.1 0.1"),
    );
    write(dir.path(), &obj, Some(&mtl));
    let msg = load(dir.path(), &scene_text("")).unwrap_err();
    assert!(msg.contains("…\": Kd must be finite and >= 0"), "{msg}");
    let obj = OBJ.replace(
        "f 9 10 11 12",
        "vt 1e300 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 9/1 10/2 11/3 12/4",
    );
    write(dir.path(), &obj, Some(MTL));
    let msg = load(dir.path(), &scene_text("")).unwrap_err();
    assert!(
        msg.contains("texture coordinate 1e300 is not finite or beyond"),
        "{msg}"
    );
}
