//! Tiles and `glint assemble` (docs/scale-out.md): the tiles of a render put
//! together are the whole render, bit for bit, on the GPU and the CPU; a
//! missing, duplicated, mismatched or partial tile is named, and nothing is
//! written.

mod common;

#[cfg(feature = "gpu")]
use std::path::Path;

#[cfg(feature = "gpu")]
use common::{assert_ok as ok, assert_user_error as fails_with};
use glint::accel::Accel;
use glint::cpu;
#[cfg(feature = "gpu")]
use glint::raster::io;
use glint::raster::region::Region;
use glint::raster::Image;
use glint::scene::{Overrides, Scene};

fn load(path: &str) -> Scene {
    let o = Overrides {
        width: Some(67),
        height: Some(130),
        ..Overrides::default()
    };
    Scene::load(&common::repo().join(path), &o).unwrap()
}

/// The regions' images put together in their places.
fn put_together(scene: &Scene, parts: &[(Region, Image)]) -> Image {
    let mut pixels = vec![[f32::NAN; 3]; (scene.width * scene.height) as usize];
    for (r, img) in parts {
        for y in 0..r.height {
            for x in 0..r.width {
                pixels[((r.y + y) * scene.width + r.x + x) as usize] = img.get(x, y);
            }
        }
    }
    Image::new(scene.width, scene.height, pixels)
}

const SCENES: [&str; 2] = ["scenes/seed-fig5.toml", "scenes/spd/mount.nff"];

#[test]
#[cfg(feature = "gpu")]
fn gpu_tiles_are_the_whole_render_bit_for_bit() {
    let mut gpu = common::gpu();
    for path in SCENES {
        let scene = load(path);
        let whole = gpu.render(&scene, &|_| {}).unwrap().0;
        for n in [1, 3, 7, 16] {
            let parts: Vec<(Region, Image)> = (0..n)
                .map(|i| {
                    let r = Region::tile(i, n, scene.width, scene.height).unwrap();
                    (r, common::render_region(&mut gpu, &scene, r))
                })
                .collect();
            assert!(
                common::same_bits(&put_together(&scene, &parts), &whole),
                "{path} {n}"
            );
        }
        // An explicit region that is not a band, with corners on odd pixels.
        let r = Region {
            x: 13,
            y: 29,
            width: 31,
            height: 17,
        };
        let part = common::render_region(&mut gpu, &scene, r);
        for y in 0..r.height {
            for x in 0..r.width {
                assert_eq!(part.get(x, y), whole.get(r.x + x, r.y + y), "{path}");
            }
        }
    }
}

#[test]
fn cpu_tiles_are_the_whole_render_bit_for_bit() {
    for path in SCENES {
        let scene = load(path);
        let whole64 = cpu::render::<f64>(&scene);
        let whole32 = cpu::render::<f32>(&scene);
        for n in [1, 3, 7, 16] {
            let tiles = |f: &dyn Fn(Region) -> Image| -> Image {
                let parts: Vec<(Region, Image)> = (0..n)
                    .map(|i| {
                        let r = Region::tile(i, n, scene.width, scene.height).unwrap();
                        (r, f(r))
                    })
                    .collect();
                put_together(&scene, &parts)
            };
            let t64 = tiles(&|r| cpu::render_region::<f64>(&scene, Accel::Auto, r, &|_| {}));
            let t32 = tiles(&|r| cpu::render_region::<f32>(&scene, Accel::Auto, r, &|_| {}));
            assert!(common::same_bits(&t64, &whole64), "{path} {n} f64");
            assert!(common::same_bits(&t32, &whole32), "{path} {n} f32");
        }
    }
    // The check can fail: tiles of another scene are not these bits.
    let a = load(SCENES[0]);
    let b = cpu::render::<f64>(&load(SCENES[1]));
    assert!(!common::same_bits(&cpu::render::<f64>(&a), &b));
}

#[cfg(feature = "gpu")]
fn glint_in(dir: &Path, args: &[&str], env: &[(&str, &str)]) -> std::process::Output {
    let mut c = common::cmd();
    c.current_dir(dir).args(args);
    for var in ["SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"] {
        c.env_remove(var);
    }
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().unwrap()
}

/// Through the binary, as a farm runs it: tiles by index and from the
/// engine's variables, assembled, equal the whole render; each way a set of
/// tiles can be wrong is one error naming the tile, with no image written.
#[test]
#[cfg(feature = "gpu")]
fn render_tile_and_assemble_through_the_binary() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = common::repo().join("scenes/spd/tetra.nff");
    let scene = scene.to_str().unwrap();
    let size = ["--width", "67", "--height", "130"];
    let render = |out: &str, extra: &[&str], env: &[(&str, &str)]| {
        let mut args = vec!["render", scene, "-o", out];
        args.extend(size);
        args.extend(extra);
        glint_in(d, &args, env)
    };
    ok(&render("whole.pfm", &[], &[]));
    std::fs::create_dir(d.join("tiles")).unwrap();
    ok(&render("tiles/0.exr", &["--tile", "0/3"], &[]));
    ok(&render(
        "tiles/1.exr",
        &["--tile", "auto/3"],
        &[("SLURM_ARRAY_TASK_ID", "1")],
    ));
    ok(&render(
        "tiles/2.exr",
        &["--tile", "auto/3"],
        &[("JOB_COMPLETION_INDEX", "2")],
    ));
    ok(&glint_in(d, &["assemble", "tiles", "-o", "out.pfm"], &[]));
    let read = |p: &str| io::read(&d.join(p)).unwrap();
    assert!(common::same_bits(&read("out.pfm"), &read("whole.pfm")));

    let assemble = |tiles: &[&str], out: &str| {
        let mut args = vec!["assemble"];
        args.extend(tiles);
        args.extend(["-o", out]);
        glint_in(d, &args, &[])
    };
    let no_output = |out: &str| assert!(!d.join(out).exists(), "{out} was written");
    // Two bands of one size with their images swapped (a script's `mv`, a
    // farm writing the wrong name): each sidecar is bound to its pixels
    // (they assembled, 34 % of the pixels off).
    std::fs::create_dir(d.join("swapped")).unwrap();
    for (name, region) in [("top", "0,0,67,65"), ("bottom", "0,65,67,65")] {
        let out = format!("swapped/{name}.exr");
        ok(&render(&out, &["--region", region], &[]));
    }
    let swapped = |name: &str| d.join(format!("swapped/{name}.exr"));
    std::fs::rename(swapped("top"), swapped("x")).unwrap();
    std::fs::rename(swapped("bottom"), swapped("top")).unwrap();
    std::fs::rename(swapped("x"), swapped("bottom")).unwrap();
    fails_with(
        &assemble(&["swapped"], "swapped.pfm"),
        "its pixels are not the ones",
    );
    no_output("swapped.pfm");
    // A missing tile.
    fails_with(
        &assemble(&["tiles/0.exr", "tiles/2.exr"], "a.pfm"),
        "tile 1/3 of the 67x130 image is missing",
    );
    no_output("a.pfm");
    // A duplicate.
    std::fs::copy(d.join("tiles/0.exr"), d.join("copy.exr")).unwrap();
    std::fs::copy(d.join("tiles/0.exr.json"), d.join("copy.exr.json")).unwrap();
    fails_with(
        &assemble(
            &["tiles/0.exr", "copy.exr", "tiles/1.exr", "tiles/2.exr"],
            "b.pfm",
        ),
        "are the same tile",
    );
    no_output("b.pfm");
    // A tile of another render: other overrides change the scene's hash.
    let mut args = vec![
        "render",
        scene,
        "-o",
        "other.exr",
        "--tile",
        "1/3",
        "--max-depth",
        "2",
    ];
    args.extend(size);
    ok(&glint_in(d, &args, &[]));
    fails_with(
        &assemble(&["tiles/0.exr", "other.exr", "tiles/2.exr"], "c.pfm"),
        "other.exr is not of the render of tiles/0.exr: its scene_hash",
    );
    no_output("c.pfm");
    // A partial tile: its image is not its sidecar's region.
    std::fs::copy(d.join("tiles/1.exr"), d.join("tiles/1.exr.bak")).unwrap();
    let half = read("tiles/1.exr");
    let cut = Image::new(
        half.width,
        half.height / 2,
        half.pixels[..(half.width * (half.height / 2)) as usize].to_vec(),
    );
    io::write(&d.join("tiles/1.exr"), &cut, false).unwrap();
    fails_with(&assemble(&["tiles"], "d.pfm"), "a partial tile");
    no_output("d.pfm");
    // Pieces that are not an I/N split: the first pixel no tile holds.
    let mut args = vec!["render", scene, "-o", "r.exr", "--region", "0,0,67,100"];
    args.extend(size);
    ok(&glint_in(d, &args, &[]));
    fails_with(
        &assemble(&["r.exr"], "f.pfm"),
        "no tile holds pixel (0, 100)",
    );
    // A tile without its sidecar.
    std::fs::remove_file(d.join("tiles/2.exr.json")).unwrap();
    fails_with(
        &assemble(&["tiles/0.exr", "tiles/2.exr"], "e.pfm"),
        "no sidecar",
    );
    // Tiles are floats; auto needs an index.
    fails_with(
        &render("t.png", &["--tile", "0/3"], &[]),
        "a tile is written as .exr or .pfm",
    );
    fails_with(
        &render("t.exr", &["--tile", "auto/3"], &[]),
        "SLURM_ARRAY_TASK_ID (Slurm job arrays) or JOB_COMPLETION_INDEX",
    );
    fails_with(
        &render("t.exr", &["--tile", "3/3"], &[]),
        "index must be below",
    );
    fails_with(
        &render("t.exr", &["--region", "60,0,10,10"], &[]),
        "not inside",
    );
    assert!(!d.join("t.exr").exists() && !d.join("t.png").exists());

    // Sidecars edited: a huge scene name is cut in the message; a size past
    // any render is refused, not reported as a missing tile with an empty
    // list. copy.exr is tile 0 again, with a sidecar of its own to edit.
    let sidecar = d.join("copy.exr.json");
    let edit = |from: &str, to: &str| {
        let text = std::fs::read_to_string(&sidecar).unwrap();
        assert!(text.contains(from), "{from} not in {text}");
        std::fs::write(&sidecar, text.replacen(from, to, 1)).unwrap();
    };
    let original = std::fs::read_to_string(&sidecar).unwrap();
    edit("tetra.nff", &"x".repeat(100_000));
    let o = assemble(&["tiles/0.exr", "copy.exr"], "g.pfm");
    fails_with(&o, "is not of the render of");
    assert!(o.stderr.len() < 2000, "{} bytes of error", o.stderr.len());
    std::fs::write(&sidecar, &original).unwrap();
    edit("\"width\": 67", "\"width\": 65536");
    fails_with(
        &assemble(&["copy.exr"], "h.pfm"),
        "larger than any render (16384 a side)",
    );
    no_output("g.pfm");
    no_output("h.pfm");

    // A sidecar claiming 100,000,000 tiles names a few missing ones and
    // counts the rest (it listed them all, 3.8 GB).
    std::fs::write(&sidecar, &original).unwrap();
    edit("\"tile\": \"0/3\"", "\"tile\": \"0/100000000\"");
    let o = assemble(&["copy.exr"], "i.pfm");
    fails_with(&o, "tile 1/100000000, 2/100000000, 3/100000000, 4/100000000, 5/100000000, 99999994 more of the 67x130 image is missing");
    assert!(o.stderr.len() < 2000, "{} bytes of error", o.stderr.len());
    no_output("i.pfm");

    // A tile holding NaN or infinity is refused as render refuses such an
    // image (the NaN became black in the PNG).
    std::fs::write(&sidecar, &original).unwrap();
    let mut bad = read("tiles/0.exr");
    let w = bad.width as usize;
    bad.pixels[3 * w + 2][1] = f32::NAN;
    bad.pixels[5 * w][0] = f32::INFINITY;
    io::write(&d.join("copy.exr"), &bad, false).unwrap();
    std::fs::copy(d.join("tiles/1.exr.bak"), d.join("tiles/1.exr")).unwrap();
    fails_with(
        &assemble(&["copy.exr", "tiles/1.exr", "tiles/2.exr"], "j.png"),
        "copy.exr: holds 2 non-finite values, the first at pixel (2, 3) of the tile",
    );
    no_output("j.png");
}
