//! Image textures (docs/scene-format.md, Textures): PNG (sRGB, decoded to
//! linear), EXR and PFM (linear) images on spheres (latitude and
//! longitude), planes, triangles with uvs and OBJ meshes with vt and
//! map_Kd render alike on both renderers; a shifted uv, a turned image or
//! a changed texel fails the comparison; bad images and missing uvs are
//! named in one line.

mod common;

use std::path::Path;
use std::sync::Arc;

use glint::cpu;
use glint::scene::{parse, Overrides, Scene};

fn textures_scene(text: &str) -> Scene {
    let o = Overrides {
        width: Some(160),
        height: Some(120),
        ..Overrides::default()
    };
    parse(text, &common::repo().join("scenes/textures.toml"), &o)
        .unwrap_or_else(|e| panic!("scenes/textures.toml: {e}"))
}

fn textures_text() -> String {
    std::fs::read_to_string(common::repo().join("scenes/textures.toml")).unwrap()
}

/// The scene of every way to map an image: the GPU and CPU f32 against
/// the f64 reference.
#[test]
fn the_textures_scene_agrees_on_both_renderers() {
    let scene = textures_scene(&textures_text());
    assert!(scene.has_image_textures());
    // One PNG, read once for the three textures that name it.
    assert_eq!(scene.texels.len(), 128 * 64);
    assert_eq!(
        scene.textures.len(),
        4,
        "map, tiles, the MTL's map_Kd and map_Ka"
    );
    assert!(scene.input_files.iter().any(|f| f.ends_with("globe.png")));
    let reference = cpu::render::<f64>(&scene);
    common::assert_renderers_agree("the MTL scene", &scene, &reference);
}

/// A perturbed mapping fails: the floor's uvs shifted by a fiftieth, the
/// tiles turned by a degree, the sphere's image repeated at 1.02, and the
/// map's white mark painted out.
#[test]
fn a_shifted_uv_or_a_changed_texel_fails() {
    let text = textures_text();
    let scene = textures_scene(&text);
    let reference = cpu::render::<f64>(&scene);
    let perturbed = [
        text.replace(
            "uvs = [[0.0, 2.0], [0.0, 0.0]",
            "uvs = [[0.02, 2.0], [0.02, 0.0]",
        ),
        text.replace("angle = 30.0", "angle = 31.0"),
        text.replace(
            "image = \"meshes/globe.png\"\n\n[textures.tiles]",
            "image = \"meshes/globe.png\"\nsize = 1.02\n\n[textures.tiles]",
        ),
    ];
    for t in perturbed {
        assert_ne!(t, text);
        let moved = textures_scene(&t);
        assert!(
            !common::passes(&cpu::render::<f64>(&moved), &reference),
            "a perturbed mapping passed"
        );
    }
    let mut painted = scene.clone();
    let texels = Arc::make_mut(&mut painted.texels);
    for y in 16..24 {
        for x in 40..56 {
            texels[y * 128 + x] = [0.0; 3];
        }
    }
    assert!(!common::passes(&cpu::render::<f64>(&painted), &reference));
}

fn write_png(path: &Path, w: u32, h: u32, texel: impl Fn(u32, u32) -> [u8; 3]) {
    image::RgbImage::from_fn(w, h, |x, y| image::Rgb(texel(x, y)))
        .save(path)
        .unwrap();
}

/// A PFM of `w × h` texels of `value`.
fn write_pfm(path: &Path, w: u32, h: u32, value: f32) {
    let mut bytes = format!("PF\n{w} {h}\n-1.0\n").into_bytes();
    for _ in 0..w * h * 3 {
        bytes.extend(value.to_le_bytes());
    }
    std::fs::write(path, bytes).unwrap();
}

/// A small scene in `dir` whose `[textures.t]` and primitives are given.
fn small(texture: &str, prims: &str) -> String {
    format!(
        "[image]\nwidth = 32\nheight = 24\n\
         [camera]\neye = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\nvfov = 45.0\n\
         [textures.t]\n{texture}\n\
         [materials.m]\ntexture = \"t\"\n\
         {prims}\
         [[lights]]\ntype = \"point\"\nposition = [2.0, 4.0, 5.0]\nambient = [0.2, 0.2, 0.2]\n\
         diffuse = [0.9, 0.9, 0.9]\n"
    )
}

const SPHERE: &str = "[[spheres]]\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\nmaterial = \"m\"\n";

fn load(dir: &Path, text: &str) -> Result<Scene, String> {
    parse(text, &dir.join("scene.toml"), &Overrides::default()).map_err(|e| e.to_string())
}

/// A PNG's 8-bit values are sRGB, decoded to linear; a PFM's are linear
/// as stored; rows run from the top.
#[test]
fn png_texels_are_decoded_from_srgb_and_pfm_texels_are_linear() {
    let dir = tempfile::tempdir().unwrap();
    write_png(&dir.path().join("a.png"), 2, 1, |x, _| {
        [[0, 128, 255][x as usize], 0, 255]
    });
    let scene = load(dir.path(), &small("image = \"a.png\"", SPHERE)).unwrap();
    let t = &scene.texels;
    assert_eq!(t.len(), 2);
    assert_eq!(t[0], [0.0, 0.0, 1.0]);
    assert!((t[1][0] - 0.215_861).abs() < 1e-5, "{:?}", t[1]);
    write_pfm(&dir.path().join("b.pfm"), 1, 1, 0.5);
    let scene = load(dir.path(), &small("image = \"b.pfm\"", SPHERE)).unwrap();
    assert_eq!(scene.texels[0], [0.5; 3]);
}

/// A file's content must be the format its extension names: a PNG named
/// .exr read 128 as 0.502 (linear) and an EXR named .png read 0.5 as 0.214
/// (sRGB-decoded) without a word.
#[test]
fn an_image_whose_content_is_not_its_extensions_format_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    write_png(&dir.path().join("a.png"), 1, 1, |_, _| [128; 3]);
    std::fs::copy(dir.path().join("a.png"), dir.path().join("png.exr")).unwrap();
    let exr = glint::raster::Image::new(1, 1, vec![[0.5; 3]]);
    glint::raster::io::write(&dir.path().join("real.exr"), &exr, false).unwrap();
    std::fs::rename(dir.path().join("real.exr"), dir.path().join("exr.png")).unwrap();
    for (file, words) in [
        (
            "png.exr",
            "png.exr: its content is Png, not the OpenEXR its extension names",
        ),
        (
            "exr.png",
            "exr.png: its content is OpenExr, not the PNG its extension names",
        ),
    ] {
        let msg = load(dir.path(), &small(&format!("image = \"{file}\""), SPHERE)).unwrap_err();
        assert!(msg.contains(words), "expected {words:?}: {msg}");
        assert_eq!(msg.lines().count(), 1, "{msg}");
    }
    // diff reads images the same way (the binary needs the GPU feature).
    #[cfg(feature = "gpu")]
    {
        let o = common::glint(&[
            "diff",
            dir.path().join("a.png").to_str().unwrap(),
            dir.path().join("png.exr").to_str().unwrap(),
        ]);
        common::assert_user_error(&o, "its content is Png, not the OpenEXR");
    }
}

/// A sphere's latitude and longitude: the image's middle column faces +z
/// (the camera), its left half is on −x, its top at +y.
#[test]
fn a_sphere_maps_the_image_by_latitude_and_longitude() {
    let dir = tempfile::tempdir().unwrap();
    // Left half red, right half green; the top 3/8 of rows blue.
    write_png(&dir.path().join("q.png"), 64, 32, |x, y| {
        if y < 12 {
            [0, 0, 255]
        } else if x < 32 {
            [255, 0, 0]
        } else {
            [0, 255, 0]
        }
    });
    let text = small("image = \"q.png\"", SPHERE)
        .replace("width = 32\nheight = 24", "width = 64\nheight = 64");
    let scene = load(dir.path(), &text).unwrap();
    let image = cpu::render::<f64>(&scene);
    let at = |x: u32, y: u32| image.get(x, y);
    // Left of the middle (−x, u < ½): red; right: green; near the top: blue.
    let left = at(24, 34);
    let right = at(40, 34);
    let top = at(32, 19);
    assert!(left[0] > 4.0 * left[1], "{left:?}");
    assert!(right[1] > 4.0 * right[0], "{right:?}");
    assert!(top[2] > 4.0 * top[0].max(top[1]), "{top:?}");
    if let Some(gpu) = common::render_gpu_if_built(&scene) {
        assert!(common::passes(&gpu, &image));
    }
}

/// Each bad image or missing uv is one line naming the file, line and key.
#[test]
fn bad_images_and_missing_uvs_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_png(&d.join("ok.png"), 4, 4, |x, y| {
        [(x * 60) as u8, (y * 60) as u8, 0]
    });
    write_png(&d.join("wide.png"), 8193, 1, |_, _| [0, 0, 0]);
    write_pfm(&d.join("negative.pfm"), 2, 2, -1.0);
    // A texel of 1e38 once blamed lights[0].
    write_pfm(&d.join("huge.pfm"), 1, 1, 1e38);
    std::fs::write(d.join("flat.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    std::fs::write(
        d.join("bad-vt.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n",
    )
    .unwrap();
    let triangle =
        "[[triangles]]\nvertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\nmaterial = \"m\"\n";
    let cylinder = "[[cylinders]]\nbase = [0, -1, 0]\napex = [0, 1, 0]\nbase_radius = 1\napex_radius = 1\nmaterial = \"m\"\n";
    let mesh = |f: &str| format!("[[meshes]]\nfile = \"{f}\"\nmaterial = \"m\"\n");
    let ok = "image = \"ok.png\"";
    for (texture, prims, words) in [
        ("image = \"missing.png\"", SPHERE.to_owned(), "textures.t.image: cannot read the image"),
        ("image = \"ok.txt\"", SPHERE.to_owned(), "unsupported image type"),
        ("image = \"wide.png\"", SPHERE.to_owned(), "is 8193x1: an image texture may be at most 8192 a side"),
        ("image = \"negative.pfm\"", SPHERE.to_owned(), "texel (0, 0) has the value -1: texels must be finite and >= 0"),
        ("image = \"huge.pfm\"", SPHERE.to_owned(), "materials.m: its texture's brightest value, 1.000e38, makes the brightest pixel"),
        ("image = \"ok.png\"\npattern = \"checker\"", SPHERE.to_owned(), "a pattern or an image, not both"),
        ("image = \"ok.png\"\ncolors = [[1, 1, 1], [0, 0, 0]]", SPHERE.to_owned(), "an image takes no `colors`"),
        ("size = 1.0", SPHERE.to_owned(), "needs a pattern (checker, solid_checker) or an image"),
        (ok, triangle.to_owned(), "triangles[0].material: material \"m\" has the image texture \"t\", which needs uv coordinates: give this triangle uvs"),
        (ok, cylinder.to_owned(), "cylinders[0].material: material \"m\" has the image texture \"t\", which needs uv coordinates"),
        (ok, mesh("flat.obj"), "meshes[0].file: material \"m\" has the image texture \"t\", which needs uv coordinates, and face 0 of this OBJ has none"),
        (ok, mesh("bad-vt.obj"), "not a valid OBJ file"),
        (ok, triangle.replace("material", "uvs = [[0, 0], [1, 0], [0, nan]]\nmaterial"), "triangles[0].uvs[2]: [0, NaN] is not finite"),
    ] {
        let text = small(texture, &prims);
        let msg = match load(d, &text) {
            Ok(_) => panic!("{words:?}: the scene loaded"),
            Err(e) => e,
        };
        assert!(msg.contains("scene.toml:"), "{msg}");
        assert!(msg.contains(words), "expected {words:?}: {msg}");
        assert_eq!(msg.lines().count(), 1, "{msg}");
    }
    // The same scenes with uvs, or a solid checker for the cylinder, load.
    let with_uvs = triangle.replace("material", "uvs = [[0, 0], [1, 0], [0, 1]]\nmaterial");
    assert!(load(d, &small(ok, &with_uvs)).is_ok());
    let solid = "pattern = \"solid_checker\"\nsize = 0.5\ncolors = [[1, 1, 1], [0, 0, 0]]";
    assert!(load(d, &small(solid, cylinder)).is_ok());
}

/// The command line's error for a missing texture: one line, exit 2, no
/// image written.
#[cfg(feature = "gpu")]
#[test]
fn the_cli_names_a_missing_image_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.toml");
    std::fs::write(&scene, small("image = \"gone.png\"", SPHERE)).unwrap();
    let out = dir.path().join("out.png");
    let o = common::glint(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--backend",
        "cpu",
    ]);
    common::assert_user_error(&o, "cannot read the image");
    assert!(!out.exists());
}

/// An EXR with more channels than glint decodes is refused from its header,
/// before any block is inflated (4,000 channels took 48 s and 520 MB as a
/// texture).
#[test]
fn an_exr_of_too_many_channels_is_refused_before_decoding() {
    use exr::prelude::*;
    let dir = tempfile::tempdir().unwrap();
    let write = |n: usize| {
        // R, G and B, and the rest extra.
        let name = |i: usize| {
            ["R", "G", "B"]
                .get(i)
                .map_or(format!("x{i:04}"), |c| (*c).to_owned())
        };
        let channels: SmallVec<[AnyChannel<FlatSamples>; 4]> = (0..n)
            .map(|i| AnyChannel::new(name(i).as_str(), FlatSamples::F32(vec![0.5; 16])))
            .collect();
        let image = exr::image::Image::from_channels((4, 4), AnyChannels::sort(channels));
        image.write().to_file(dir.path().join("t.exr")).unwrap();
    };
    write(65);
    let msg = load(dir.path(), &small("image = \"t.exr\"", SPHERE)).unwrap_err();
    assert!(
        msg.contains("t.exr: has 65 channels, more than the 64 glint decodes"),
        "{msg}"
    );
    // At the bound it reads.
    write(64);
    let scene = load(dir.path(), &small("image = \"t.exr\"", SPHERE)).unwrap();
    assert_eq!(scene.texels[0], [0.5; 3]);
}
