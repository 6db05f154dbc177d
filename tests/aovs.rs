//! A render's AOVs (src/base/aov.rs): the GPU's and the CPU's the same ids
//! and ray counts, the rest within f32's rounding; the colour the plain
//! render's; a region's the whole image's; the rays the counts' total.

mod common;

use glint::accel::Accel;
#[cfg(feature = "gpu")]
use glint::aov::Aov;
use glint::cpu;
#[cfg(feature = "gpu")]
use glint::raster::region::Region;
use glint::scene::{Overrides, Scene};

fn scenes() -> Vec<Scene> {
    let o = Overrides {
        width: Some(40),
        height: Some(30),
        ..Overrides::default()
    };
    let mut out = vec![common::scene_sized(common::SMALL, 40, 30)];
    for name in ["glass.toml", "textures.toml", "cylinders.toml"] {
        out.push(Scene::load(&common::repo().join("scenes").join(name), &o).unwrap());
    }
    out
}

#[cfg(feature = "gpu")]
/// How far an image texture's albedo may be between the GPU and the CPU:
/// a sphere's uv comes through acos and atan2, which llvmpipe computes a
/// few f32 ulps of the angle off libm (`glint explain` shows v 1.9e-5
/// apart on textures.toml), and the texel lookup moves with it (measured
/// up to 1.4e-3). Colours without an image texture agree to f32 rounding.
const ALBEDO_TEXTURED: f64 = 2e-3;

#[cfg(feature = "gpu")]
/// How far a unit normal's components may be between the GPU and the CPU,
/// both in f32: a smooth triangle's normal is interpolated with weights
/// from the ray's hit, which the shader and the CPU round differently
/// (measured up to 1.3e-5 on cylinders.toml's triangles).
const NORMAL: f64 = 1e-4;

#[cfg(feature = "gpu")]
fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-5 * a.abs().max(b.abs()).max(1.0)
}

/// The CPU's AOVs agree with themselves across precisions where it counts:
/// the same primitives met, the same rays, and the colour of a plain render.
#[test]
fn the_cpus_aovs_are_its_renders() {
    for scene in scenes() {
        let f32s = cpu::Prepared::<f32>::new(&scene, Accel::Auto);
        let (image, aovs) = f32s.render_aovs(None, &|_| {});
        assert_eq!(image, f32s.render(&|_| {}));
        let (_, counted) = f32s.render_counted(&|_| {});
        let r = counted.rays();
        let total: u64 = aovs.iter().map(|a| u64::from(a.rays)).sum();
        assert_eq!(total, r.eye + r.reflect + r.refract + r.shadow);
        assert!(aovs.iter().any(|a| a.hit.is_some()));
    }
}

#[cfg(feature = "gpu")]
#[test]
fn the_gpus_aovs_are_the_cpus() {
    use glint::gpu::RenderSettings;
    let mut r = common::gpu();
    let settings = RenderSettings {
        aovs: true,
        ..r.settings()
    };
    for scene in scenes() {
        let image_textured = scene.has_image_textures();
        let mut prepared = r.prepare(&scene, &settings).unwrap();
        assert!(prepared.variant().aovs);
        let rendered = prepared.render(None, &|_| {}).unwrap();
        let gpu: Vec<Aov> = rendered.aovs.expect("an AOV render gives them");
        assert_eq!(
            rendered.image,
            common::render_gpu(&scene),
            "the colour is the plain render's"
        );
        let (_, cpu) = cpu::Prepared::<f32>::new(&scene, Accel::Auto).render_aovs(None, &|_| {});
        assert_eq!(gpu.len(), cpu.len());
        for (i, (g, c)) in gpu.iter().zip(&cpu).enumerate() {
            assert_eq!(g.rays, c.rays, "pixel {i}: rays");
            match (g.hit, c.hit) {
                (None, None) => {}
                (Some(g), Some(c)) => {
                    assert_eq!(g.prim, c.prim, "pixel {i}: primitive");
                    assert!(
                        close(g.depth, c.depth),
                        "pixel {i}: depth {} {}",
                        g.depth,
                        c.depth
                    );
                    for k in 0..3 {
                        let dn = (g.normal[k] - c.normal[k]).abs();
                        assert!(
                            dn <= NORMAL,
                            "pixel {i}: normal {:?} {:?}",
                            g.normal,
                            c.normal
                        );
                        let d = (g.albedo[k] - c.albedo[k]).abs();
                        assert!(
                            close(g.albedo[k], c.albedo[k])
                                || image_textured && d <= ALBEDO_TEXTURED,
                            "pixel {i}: albedo {:?} {:?}",
                            g.albedo,
                            c.albedo
                        );
                    }
                }
                (g, c) => panic!("pixel {i}: {g:?} on the GPU, {c:?} on the CPU"),
            }
        }
        // A region's AOVs are the whole image's there.
        let region = Region {
            x: 7,
            y: 5,
            width: 20,
            height: 11,
        };
        let part = prepared
            .render(Some(region), &|_| {})
            .unwrap()
            .aovs
            .unwrap();
        for y in 0..region.height {
            for x in 0..region.width {
                let whole = gpu[((region.y + y) * scene.width + region.x + x) as usize];
                assert_eq!(part[(y * region.width + x) as usize], whole);
            }
        }
        // A plain render gives none.
        let plain = r.prepare(&scene, &r.settings()).unwrap();
        assert!(!plain.variant().aovs);
    }
}

/// Why `r` refuses AOVs of `scene` (it must).
#[cfg(feature = "gpu")]
fn refused(r: &mut glint::gpu::Renderer, scene: &Scene) -> String {
    let settings = glint::gpu::RenderSettings {
        aovs: true,
        ..r.settings()
    };
    let e = r.prepare(scene, &settings).err().expect("refused");
    e.to_string()
}

/// A scene that samples its pixels' corners has no pixel samples of its
/// own, and a user's trace.glsl that calls no AOV hook (an experiment's)
/// would give AOVs that say nothing was met: both refused in one line,
/// the second naming the file.
#[cfg(feature = "gpu")]
#[test]
fn aovs_that_would_be_wrong_are_refused() {
    let mut scene = common::scene_sized(common::SMALL, 16, 12);
    let plain = scene.clone();
    scene.sampling = glint::scene::Sampling::Corners;
    let e = refused(&mut common::gpu(), &scene);
    assert!(e.contains("pixel's own samples"), "{e}");
    let mut r = common::gpu_from(glint::gpu::GpuOptions {
        include_dirs: vec![common::repo().join("shaders/experiments/normals")],
        ..glint::gpu::GpuOptions::default()
    });
    let e = refused(&mut r, &plain);
    assert!(e.contains("trace.glsl") && e.contains("AOV_"), "{e}");
    // Without AOVs it renders.
    assert!(r.prepare(&plain, &r.settings()).is_ok());
}

/// The AOVs without a tolerance (the primitive met first, the rays
/// traced) are held to the f64 reference's where the trials leave them
/// alone (`condition::judge_aovs`): on the scenes above and the extreme
/// ones where a near-tie decides them (triangle-slivers' faces that meet,
/// light-on-surface's light in the floor's plane) the GPU's differ only
/// where a trial's do, and somewhere they do differ. A primitive changed
/// on a pixel no trial moves fails the check.
#[cfg(feature = "gpu")]
#[test]
fn the_gpus_aovs_differ_from_the_references_only_at_near_ties() {
    use glint::condition::judge_aovs;
    use glint::gpu::RenderSettings;
    let mut r = common::gpu();
    let settings = RenderSettings {
        aovs: true,
        ..r.settings()
    };
    let o = Overrides {
        width: Some(80),
        height: Some(60),
        ..Overrides::default()
    };
    let extreme = ["triangle-slivers.toml", "light-on-surface.toml"]
        .map(|n| Scene::load(&common::repo().join("scenes/extreme").join(n), &o).unwrap());
    let mut differing = 0;
    for scene in scenes().into_iter().chain(extreme) {
        let mut prepared = r.prepare(&scene, &settings).unwrap();
        let gpu = prepared.render(None, &|_| {}).unwrap().aovs.unwrap();
        let check = judge_aovs(&scene, &gpu, Accel::Auto);
        assert!(check.pass(), "unexplained at {:?}", check.unexplained);
        differing += check.differing.len();
    }
    assert!(
        differing > 0,
        "no near-tie met: the check was not exercised"
    );
    let scene = &scenes()[0];
    let mut prepared = r.prepare(scene, &settings).unwrap();
    let mut gpu = prepared.render(None, &|_| {}).unwrap().aovs.unwrap();
    let centre = (scene.height / 2 * scene.width + scene.width / 2) as usize;
    let hit = gpu[centre]
        .hit
        .as_mut()
        .expect("the middle pixel meets something");
    hit.prim.1 += 1;
    let check = judge_aovs(scene, &gpu, Accel::Auto);
    assert_eq!(check.unexplained, vec![centre]);
}

/// The AOV table's contract, row by row (`glint::aov::AOVS`): on every
/// scene, each row's channels from the GPU's record are the CPU's within
/// the row's agreement (whole numbers the same), its unused channels are
/// 0, and a pixel that met nothing reads as the row's miss on both.
#[cfg(feature = "gpu")]
#[test]
fn every_aov_of_the_table_agrees_on_both_renderers() {
    use glint::aov::{Values, AOVS};
    use glint::gpu::RenderSettings;
    let mut r = common::gpu();
    let settings = RenderSettings {
        aovs: true,
        ..r.settings()
    };
    let mut missed = 0;
    for scene in scenes() {
        let gpu = r
            .prepare(&scene, &settings)
            .unwrap()
            .render(None, &|_| {})
            .unwrap()
            .aovs
            .unwrap();
        let (_, cpu) = cpu::Prepared::<f32>::new(&scene, Accel::Auto).render_aovs(None, &|_| {});
        for t in AOVS {
            for (i, (g, c)) in gpu.iter().zip(&cpu).enumerate() {
                let (a, b) = ((t.read)(g), (t.read)(c));
                for k in 0..3 {
                    let (x, y) = (a[k], b[k]);
                    if k >= t.channels {
                        assert_eq!((x, y), (0.0, 0.0), "{}: pixel {i} channel {k}", t.name);
                    } else if t.values != Values::Float || x.is_infinite() || y.is_infinite() {
                        assert_eq!(x, y, "{}: pixel {i} channel {k}", t.name);
                        if t.values != Values::Float {
                            assert_eq!(x.fract(), 0.0, "{}: pixel {i}", t.name);
                        }
                    } else {
                        assert!(
                            (x - y).abs() <= t.agreement * x.abs().max(y.abs()).max(1.0),
                            "{}: pixel {i} channel {k}: GPU {x}, CPU {y}",
                            t.name
                        );
                    }
                }
            }
        }
        missed += cpu.iter().filter(|a| a.hit.is_none()).count();
    }
    assert!(missed > 0, "some pixel of the scenes meets nothing");
}

/// `glint render --aov`: each AOV of the table written as its channels
/// say (one channel a plane, two or three an image) holds the values the
/// library's render gives, on each backend: floats to the f32 they are,
/// whole numbers exactly; `NAME` alone takes -o's file and no colour is
/// written, `NAME=FILE` writes beside the colour.
#[test]
fn render_writes_each_aov_as_the_library_gives_it() {
    use glint::raster::{io, plane};
    let dir = tempfile::tempdir().unwrap();
    let scene_path = common::repo().join("scenes/textures.toml");
    let o = Overrides {
        width: Some(40),
        height: Some(30),
        ..Overrides::default()
    };
    let scene = Scene::load(&scene_path, &o).unwrap();
    let (_, cpu) = cpu::Prepared::<f64>::new(&scene, Accel::Auto).render_aovs(None, &|_| {});
    let backends: &[&str] = if cfg!(feature = "gpu") {
        &["cpu", "gpu"]
    } else {
        &["cpu"]
    };
    for backend in backends {
        let at = |name: &str, ext: &str| dir.path().join(format!("{backend}-{name}.{ext}"));
        let colour = dir.path().join(format!("{backend}.png"));
        let mut args: Vec<String> = [
            "render",
            scene_path.to_str().unwrap(),
            "--width",
            "40",
            "--height",
            "30",
            "--backend",
            backend,
            "-o",
            colour.to_str().unwrap(),
        ]
        .map(String::from)
        .to_vec();
        for (k, t) in glint::aov::AOVS.iter().enumerate() {
            let ext = if k % 2 == 0 { "exr" } else { "pfm" };
            args.push("--aov".into());
            args.push(format!("{}={}", t.name, at(t.name, ext).display()));
        }
        let words: Vec<&str> = args.iter().map(String::as_str).collect();
        let out = common::glint(&words);
        assert!(
            out.status.success(),
            "{backend}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(colour.exists());
        for (k, t) in glint::aov::AOVS.iter().enumerate() {
            let path = at(t.name, if k % 2 == 0 { "exr" } else { "pfm" });
            let written: Vec<[f64; 3]> = if t.channels == 1 {
                let p = plane::read_plane(&path).unwrap();
                p.values.iter().map(|&v| [f64::from(v), 0.0, 0.0]).collect()
            } else {
                let image = io::read(&path).unwrap();
                image.pixels.iter().map(|p| p.map(f64::from)).collect()
            };
            assert_eq!(written.len(), cpu.len(), "{backend} {}", t.name);
            for (i, (w, a)) in written.iter().zip(&cpu).enumerate() {
                let want = (t.read)(a);
                for c in 0..3 {
                    let (x, y) = (w[c], want[c]);
                    let same = x == y || (x - y).abs() <= 2e-3 * y.abs().max(1.0);
                    let exact = t.values != glint::aov::Values::Float;
                    assert!(
                        if exact { x == y } else { same },
                        "{backend} {}: pixel {i} channel {c}: file {x}, library {y}",
                        t.name
                    );
                }
            }
        }
    }
    // NAME alone: -o's file is the AOV, and no colour is written.
    let depth = dir.path().join("depth.pfm");
    let out = common::glint(&[
        "render",
        scene_path.to_str().unwrap(),
        "--width",
        "40",
        "--height",
        "30",
        "--backend",
        "cpu",
        "--aov",
        "depth",
        "-o",
        depth.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let p = plane::read_plane(&depth).unwrap();
    assert_eq!((p.width, p.height), (40, 30));
    let read = glint::aov::named("depth").unwrap().read;
    for (v, a) in p.values.iter().zip(&cpu) {
        assert_eq!(*v, read(a)[0] as f32);
    }
    let pngs = std::fs::read_dir(dir.path())
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .path()
                .extension()
                .is_some_and(|x| x == "png")
        })
        .count();
    assert_eq!(
        pngs,
        backends.len(),
        "no colour beside the AOV that took -o"
    );
}

/// What `--aov` refuses, each in one line with exit status 2 and no file:
/// a PNG, an AOV glint does not have, one asked twice, two that want -o's
/// file, a file named twice, a tile, and a scene sampled at its corners.
#[test]
fn render_refuses_aovs_it_cannot_write_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let showcase = common::repo().join("scenes/showcase.toml");
    let balls = common::repo().join("scenes/spd/balls.nff");
    let file = |name: &str| dir.path().join(name).display().to_string();
    let cases: Vec<(&std::path::Path, Vec<String>, &str)> = vec![
        (
            &showcase,
            vec!["--aov".into(), "depth".into(), "-o".into(), file("x.png")],
            "an AOV's values are not colours",
        ),
        (
            &showcase,
            vec!["--aov".into(), format!("colour={}", file("y.exr"))],
            "no such AOV",
        ),
        (
            &showcase,
            vec![
                "--aov".into(),
                "depth".into(),
                "--aov".into(),
                "normal".into(),
                "-o".into(),
                file("z.exr"),
            ],
            "one AOV takes -o's file",
        ),
        (
            &showcase,
            vec![
                "--aov".into(),
                format!("depth={}", file("a.exr")),
                "--aov".into(),
                format!("depth={}", file("b.exr")),
            ],
            "asked for twice",
        ),
        (
            &showcase,
            vec![
                "--aov".into(),
                format!("depth={}", file("s.exr")),
                "-o".into(),
                file("s.exr"),
            ],
            "another output's file",
        ),
        (
            &showcase,
            vec![
                "--aov".into(),
                format!("depth={}", file("t.exr")),
                "--tile".into(),
                "0/4".into(),
                "-o".into(),
                file("tile.exr"),
            ],
            "not tiles",
        ),
        (
            &balls,
            vec!["--aov".into(), "depth".into(), "-o".into(), file("b.exr")],
            "samples its pixels' corners",
        ),
    ];
    for (scene, extra, words) in cases {
        let mut args = vec![
            "render".to_owned(),
            scene.display().to_string(),
            "--width".into(),
            "16".into(),
            "--height".into(),
            "12".into(),
            "--backend".into(),
            "cpu".into(),
        ];
        args.extend(extra);
        let a: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = common::glint(&a);
        let err = String::from_utf8_lossy(&o.stderr);
        common::assert_user_error(&o, words);
        assert_eq!(err.trim().lines().count(), 1, "{err}");
    }
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        0,
        "no file is written"
    );
}

/// The docs list every AOV of the table as the table has it: a row of
/// docs/commands.md each, and each name in docs/python.md's table.
#[test]
fn the_docs_list_the_aovs_of_the_table() {
    use glint::aov::{Values, AOVS};
    let commands = std::fs::read_to_string(common::repo().join("docs/commands.md")).unwrap();
    let python = std::fs::read_to_string(common::repo().join("docs/python.md")).unwrap();
    for t in AOVS {
        let values = match t.values {
            Values::Float => "floats",
            Values::Int => "whole numbers",
            Values::Count => "counts",
        };
        let row = format!("| `{}` | {} | {values} | {} |", t.name, t.channels, t.doc);
        assert!(
            commands.contains(&row),
            "docs/commands.md lacks the row\n{row}"
        );
        assert!(
            python.contains(&format!("| `\"{}\"` |", t.name)),
            "docs/python.md: {}",
            t.name
        );
    }
    let listed = commands
        .lines()
        .filter(|l| {
            l.starts_with("| `")
                && [" | floats | ", " | whole numbers | ", " | counts | "]
                    .iter()
                    .any(|v| l.contains(v))
        })
        .count();
    assert_eq!(listed, AOVS.len(), "docs/commands.md lists other AOVs");
}
