//! A bounded fuzz harness (proptest) for what reads user bytes: the scene
//! parser, OBJ meshes' MTL files, the image readers (as files and as
//! textures) and shader sources. Every input must give a value or an error,
//! never a panic; a scene that parses must render on the CPU to finite
//! pixels, with the same image through the BVH as without it. The corpus
//! below holds the first hostile inputs as fixed seeds. A later round added
//! the command line's streams and outputs (stdout and stderr full, closed
//! or read; images and statistics into /dev/stdout and /dev/stderr),
//! polygon fans, deep and large shader sources, and swapped tiles. Each
//! property runs 256 cases from a fixed seed (see `config`; 24 or 8 where a
//! case is a process or a compile), a few seconds in all.

mod common;

use std::path::Path;

use proptest::prelude::*;
use proptest::test_runner::RngSeed;

use glint::accel::Accel;
use glint::cpu;
use glint::raster::io;
use glint::scene::{parse, Overrides, Scene};

/// A small valid scene whose values the mutations below replace.
const BASE: &str = r#"[image]
width = 6
height = 4
samples = 1
[render]
max_depth = 3
shadows = true
background = [0.1, 0.2, 0.3]
[camera]
eye = [0, 1, 8]
look_at = [0, 0, 0]
vfov = 45
[materials.m]
ambient = [0.1, 0.1, 0.1]
diffuse = [0.7, 0.3, 0.2]
specular = [0.5, 0.5, 0.5]
shininess = 20
reflectivity = 0.5
[[spheres]]
center = [0, 0, 0]
radius = 1
material = "m"
[[planes]]
point = [0, -1, 0]
normal = [0, 1, 0]
material = "m"
[[lights]]
type = "point"
position = [3, 4, 5]
diffuse = [1, 1, 1]
specular = [1, 1, 1]
"#;

/// The first hostile inputs, as scene texts.
const CORPUS: &[&str] = &[
    "[image]\nwidth = 8\nheight = 8\n[camera]\neye = [0,0,0,999,\"junk\",[1,2]]\n",
    "[image]\nwidth = 9223372036854775808\nheight = 8\n",
    "[image]\nwidth = 1979-05-27\n",
    "[image]\nwidth = 8\n[image]\nheight = 8\n",
    "[image\nwidth = 8\n",
    "",
    "\u{0}\u{1b}[31m",
];

fn try_render(text: &str) {
    let Ok(scene) = parse(text, Path::new("fuzz.toml"), &Overrides::default()) else {
        return;
    };
    render_small(&scene);
}

/// The base scene sampled by contrast, with these keys under `[image]`.
fn sampled_by_contrast(keys: &str) -> String {
    BASE.replacen(
        "samples = 1\n",
        &format!("samples = 1\nsampling = \"contrast\"\n{keys}\n"),
        1,
    )
}

/// A scene that parsed renders at a few pixels without a panic, through
/// both scene managements, to the same image.
fn render_small(scene: &Scene) {
    let mut s = scene.clone();
    s.width = s.width.min(6);
    s.height = s.height.min(4);
    s.samples = s.samples.min(2);
    let a = cpu::render_rows::<f64>(&s, Accel::None, &|_| {});
    let b = cpu::render_rows::<f64>(&s, Accel::Bvh, &|_| {});
    // Bit patterns, not ==: a light at 1e308 makes NaN pixels (0 * inf in
    // the falloff), the same NaNs either way.
    let bits = |i: &glint::raster::Image| -> Vec<u32> {
        i.pixels.iter().flatten().map(|c| c.to_bits()).collect()
    };
    assert!(
        bits(&a) == bits(&b),
        "the BVH changed a fuzzed scene's image"
    );
    // The bounds on coordinates and brightness keep every pixel finite.
    assert!(
        a.pixels.iter().flatten().all(|c| c.is_finite()),
        "a scene that parsed rendered a non-finite pixel"
    );
}

/// Found by this harness: a light at x = 1e308 gave NaN pixels (0 * inf in
/// the falloff); it is refused now, as every coordinate past 1e18 is.
#[test]
fn a_light_at_1e308_is_refused() {
    let text = BASE.replace("position = [3, 4, 5]", "position = [1e308, 4, 5]");
    assert!(parse(&text, Path::new("fuzz.toml"), &Overrides::default()).is_err());
}

#[test]
fn the_corpus_is_refused_or_rendered_without_a_panic() {
    for text in CORPUS {
        try_render(text);
    }
    try_render(BASE);
    assert!(parse(BASE, Path::new("base.toml"), &Overrides::default()).is_ok());
}

/// Numbers that break naive code: huge, tiny, negative, zero, non-finite
/// spellings, integers past i64.
fn hostile_number() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("0".to_owned()),
        Just("-0.0".to_owned()),
        Just("1e308".to_owned()),
        Just("-1e308".to_owned()),
        Just("1e-320".to_owned()),
        Just("inf".to_owned()),
        Just("nan".to_owned()),
        Just("9223372036854775807".to_owned()),
        Just("18446744073709551616".to_owned()),
        Just("16385".to_owned()),
        any::<f64>().prop_map(|x| format!("{x:e}")),
        (-1000i64..1000).prop_map(|x| x.to_string()),
    ]
}

/// A mesh whose faces take the materials of `MTL_BASE`.
const OBJ_BASE: &str = "mtllib m.mtl\nv -1 -1 0\nv 1 -1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n\
    usemtl a\nf 1/1 2/2 3/3\n";

/// Two materials, one with a map: the lines the MTL property damages.
const MTL_BASE: &str = "newmtl a\nKa 0.1 0.1 0.1\nKd 0.8 0.2 0.2\nKs 0.5 0.5 0.5\nNs 30\n\
    Ni 1.5\nd 0.5\nillum 4\nmap_Kd t.pfm\nnewmtl b\nKd 0.1 0.9 0.1\nTr 0.25\n";

/// A scene of `OBJ_BASE` in `dir`, which also holds `m.mtl` and `t.pfm`.
fn mesh_scene(dir: &Path) -> Option<Scene> {
    let text = "[image]\nwidth = 6\nheight = 4\n[camera]\neye = [0, 0, 4]\n\
        look_at = [0, 0, 0]\nvfov = 45\n[[meshes]]\nfile = \"m.obj\"\n[[lights]]\n\
        type = \"point\"\nposition = [1, 2, 4]\ndiffuse = [1, 1, 1]\n";
    parse(text, &dir.join("s.toml"), &Overrides::default()).ok()
}

/// CI runs the same cases every time, so that a landing never hangs on
/// chance; `GLINT_FUZZ_SEED=N` (or `random`) explores others.
fn config() -> ProptestConfig {
    let seed = match std::env::var("GLINT_FUZZ_SEED").ok().as_deref() {
        Some("random") => RngSeed::Random,
        Some(n) => RngSeed::Fixed(n.parse().expect("GLINT_FUZZ_SEED: a u64 or `random`")),
        None => RngSeed::Fixed(0x6c69_6e74),
    };
    ProptestConfig {
        cases: 256,
        rng_seed: seed,
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

/// The outputs' classes: every reader refuses a device that never ends, by
/// its name or through a link with the reader's extension.
#[test]
fn every_reader_refuses_an_endless_device() {
    let dir = tempfile::tempdir().unwrap();
    let zero = Path::new("/dev/zero");
    assert!(Scene::load(zero, &Overrides::default()).is_err());
    for name in ["z.toml", "z.nff", "z.pfm", "z.png", "z.exr"] {
        let link = dir.path().join(name);
        std::os::unix::fs::symlink(zero, &link).unwrap();
        let refused = |e: String| assert!(e.contains("not a regular file"), "{name}: {e}");
        if name.ends_with(".toml") || name.ends_with(".nff") {
            refused(
                Scene::load(&link, &Overrides::default())
                    .unwrap_err()
                    .to_string(),
            );
        } else {
            refused(io::read(&link).unwrap_err().to_string());
            refused(io::dimensions(&link).unwrap_err().to_string());
        }
    }
}

proptest! {
    #![proptest_config(config())]

    /// Non-finite values at any channels of either image, or both: always
    /// counted, never identical, never within tolerance.
    #[test]
    fn a_nonfinite_value_in_either_image_fails_the_comparison(
        at in proptest::collection::vec((0usize..24, 0usize..3, any::<bool>(), 0u8..3), 1..6),
    ) {
        use glint::raster::diff::{figures, Tolerance};
        use glint::raster::Image;
        let clean = Image::new(6, 4, (0..24).map(|i| [i as f32 / 24.0; 3]).collect());
        let (mut a, mut b) = (clean.clone(), clean);
        for (pixel, channel, in_a, value) in at {
            let v = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY][usize::from(value)];
            let img = if in_a { &mut a } else { &mut b };
            img.pixels[pixel][channel] = v;
        }
        let f = figures(&a, &b).unwrap();
        prop_assert!(f.nonfinite > 0);
        prop_assert!(f.psnr_db == f64::NEG_INFINITY);
        prop_assert!(!Tolerance::default().violations(&f).is_empty());
    }

    /// Any text at all: a scene or an error.
    #[test]
    fn any_text_parses_or_errs(text in "\\PC{0,400}") {
        try_render(&text);
    }

    /// Contrast sampling's keys with a hostile number: the range test's
    /// bound, a threshold, or the most samples, beside either test. The
    /// same keys with tame numbers render, so the hostile ones are tried
    /// on a scene that gets as far as the sampler.
    #[test]
    fn a_hostile_contrast_key_is_refused_or_rendered(key in 0usize..4, n in hostile_number()) {
        let tame = ["range = 0.03\nmax_samples = 9", "thresholds = [0.1, 0.1, 0.1]\nmax_samples = 9"];
        for keys in tame {
            let scene = parse(&sampled_by_contrast(keys), Path::new("fuzz.toml"), &Overrides::default());
            prop_assert!(scene.is_ok(), "{keys}: {:?}", scene.err());
        }
        let keys = match key {
            0 => format!("range = {n}\nmax_samples = 9"),
            1 => format!("range = 0.03\nmax_samples = {n}"),
            2 => format!("thresholds = [0.1, {n}, 0.1]\nmax_samples = 9"),
            _ => format!("thresholds = [0.1, 0.1, 0.1]\nmax_samples = {n}"),
        };
        try_render(&sampled_by_contrast(&keys));
    }

    /// The base scene with one number replaced by a hostile one.
    #[test]
    fn a_hostile_number_anywhere_is_refused_or_rendered(which in 0usize..40, n in hostile_number()) {
        let mut seen = 0;
        let mut out = String::new();
        for line in BASE.lines() {
            let mut l = line.to_owned();
            if let Some((key, value)) = line.split_once(" = ") {
                // Replace the first number of the value.
                if let Some(start) = value.find(|c: char| c.is_ascii_digit() || c == '-') {
                    if seen == which {
                        let end = value[start..]
                            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '.' || c == '-' || c == '+'))
                            .map_or(value.len(), |e| start + e);
                        l = format!("{key} = {}{n}{}", &value[..start], &value[end..]);
                    }
                    seen += 1;
                }
            }
            out.push_str(&l);
            out.push('\n');
        }
        try_render(&out);
    }

    /// The base scene cut short or with bytes spliced in.
    #[test]
    fn a_damaged_scene_is_refused_or_rendered(cut in 0usize..BASE.len(), junk in "\\PC{0,20}") {
        let mut text = BASE[..cut].to_owned();
        text.push_str(&junk);
        text.push_str(&BASE[cut..]);
        try_render(&text);
        try_render(&BASE[..cut]);
    }

    /// PFM bytes: a header of any sizes and scale, then any data.
    #[test]
    fn any_pfm_reads_or_errs(
        w in prop_oneof![0u64..8, Just(65536), Just(1 << 31), Just(u64::from(u32::MAX)), Just(1 << 40)],
        h in prop_oneof![0u64..8, Just(65537), Just(1 << 31)],
        scale in prop_oneof![Just("-1.0".to_owned()), Just("1.0".to_owned()), Just("nan".to_owned()), "\\PC{0,5}"],
        data in proptest::collection::vec(any::<u8>(), 0..400),
    ) {
        let mut bytes = format!("PF\n{w} {h}\n{scale}\n").into_bytes();
        bytes.extend(data);
        if let Ok(img) = io::read_pfm(&bytes) {
            prop_assert_eq!(u64::from(img.width) * u64::from(img.height), w * h);
        }
    }

    /// PNG and EXR files of any bytes after a real signature.
    #[test]
    fn any_png_or_exr_reads_or_errs(data in proptest::collection::vec(any::<u8>(), 0..300), exr in any::<bool>()) {
        let dir = tempfile::tempdir().unwrap();
        let (name, magic): (&str, &[u8]) = if exr {
            ("x.exr", &[0x76, 0x2f, 0x31, 0x01])
        } else {
            ("x.png", &[0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a])
        };
        let path = dir.path().join(name);
        let mut bytes = magic.to_vec();
        bytes.extend(data);
        std::fs::write(&path, bytes).unwrap();
        let _ = io::read(&path);
    }

    /// The MTL file with one line replaced by any text, or a colour's
    /// values cut short: materials or an error, never a panic (the
    /// short colour lines panicked in the parser).
    #[test]
    fn a_damaged_mtl_file_is_refused_or_rendered(
        line in 0usize..12,
        junk in prop_oneof!["\\PC{0,30}", "(Ka|Kd|Ks|Ke|Ns|Ni|d|Tr|illum|map_Kd|newmtl)( [-0-9.e]{0,6}){0,4}"],
    ) {
        let dir = tempfile::tempdir().unwrap();
        let mut lines: Vec<&str> = MTL_BASE.lines().collect();
        lines[line] = &junk;
        std::fs::write(dir.path().join("m.obj"), OBJ_BASE).unwrap();
        std::fs::write(dir.path().join("m.mtl"), lines.join("\n")).unwrap();
        let mut pfm = b"PF\n1 1\n-1.0\n".to_vec();
        pfm.extend([0.5f32; 3].iter().flat_map(|c| c.to_le_bytes()));
        std::fs::write(dir.path().join("t.pfm"), pfm).unwrap();
        if let Some(scene) = mesh_scene(dir.path()) {
            render_small(&scene);
        }
    }

    /// An image texture of any bytes after a PNG's or an EXR's signature,
    /// named .png or .exr whichever its content: the scene loads with
    /// finite texels or is refused (a PNG named .exr was read with the
    /// wrong colour curve).
    #[test]
    fn any_image_texture_loads_or_is_refused(
        data in proptest::collection::vec(any::<u8>(), 0..300),
        exr_content in any::<bool>(),
        exr_name in any::<bool>(),
    ) {
        let dir = tempfile::tempdir().unwrap();
        let magic: &[u8] = if exr_content {
            &[0x76, 0x2f, 0x31, 0x01]
        } else {
            &[0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a]
        };
        let name = if exr_name { "t.exr" } else { "t.png" };
        let mut bytes = magic.to_vec();
        bytes.extend(data);
        std::fs::write(dir.path().join(name), bytes).unwrap();
        std::fs::write(dir.path().join("m.obj"), OBJ_BASE).unwrap();
        std::fs::write(dir.path().join("m.mtl"), MTL_BASE.replace("t.pfm", name)).unwrap();
        if let Some(scene) = mesh_scene(dir.path()) {
            prop_assert!(scene.texels.iter().flatten().all(|c| c.is_finite() && *c >= 0.0));
            render_small(&scene);
        }
    }
}

#[cfg(feature = "gpu")]
proptest! {
    // glslang takes tens of milliseconds a compile: fewer cases.
    #![proptest_config(ProptestConfig { cases: 24, ..config() })]

    /// A shader include of glint's own text with a line replaced by any
    /// text, defines and NUL bytes among it: compiled or one error, never
    /// a panic or a hang (a NUL byte panicked in the binding, doubling
    /// defines never finished).
    #[test]
    fn a_damaged_shader_source_compiles_or_errs(
        line in 0usize..200,
        junk in prop_oneof![
            "\\PC{0,40}",
            "#define [A-C] [A-C] [A-C] [A-C]",
            "[a-z ]{0,5}\u{0}[a-z ]{0,5}",
            "#include \"[a-z.]{0,12}\"",
        ],
    ) {
        use glint::gpu::compile::{compile, Sources};
        let dir = tempfile::tempdir().unwrap();
        let shade = include_str!("../shaders/shade.glsl");
        let mut lines: Vec<&str> = shade.lines().collect();
        let at = line % lines.len();
        lines[at] = &junk;
        std::fs::write(dir.path().join("shade.glsl"), lines.join("\n")).unwrap();
        let sources = Sources {
            dirs: vec![dir.path().to_owned()],
            ..Sources::default()
        };
        if let Err(e) = compile(&sources, &[]) {
            prop_assert!(!e.to_string().is_empty());
        }
    }
}

// The stream surfaces: printing into streams that refuse it, outputs that
// are descriptors, polygon fans, deep and large shader sources, and tiles
// whose images were swapped.

/// A stdout or stderr of one of three kinds: a pipe read to its end,
/// /dev/full, or a pipe whose reader is gone.
fn stream(kind: usize) -> std::process::Stdio {
    use std::os::fd::{FromRawFd, OwnedFd};
    match kind {
        0 => std::process::Stdio::piped(),
        1 => std::fs::File::options()
            .write(true)
            .open("/dev/full")
            .unwrap()
            .into(),
        _ => {
            let mut fds = [0i32; 2];
            // SAFETY: pipe() fills both descriptors, each owned once below.
            assert_eq!(unsafe { libc::pipe(fds.as_mut_ptr()) }, 0);
            // SAFETY: both are open and owned by nothing else.
            let (r, w) = unsafe { (OwnedFd::from_raw_fd(fds[0]), OwnedFd::from_raw_fd(fds[1])) };
            drop(r);
            w.into()
        }
    }
}

/// An OBJ of four corners whose one face fans over `corners` of them
/// (`f 1 2 3 4 2 3 4 …`, a triangle for every 2 bytes), `pad` bytes of
/// comment after it.
fn fan(corners: usize, pad: usize) -> String {
    let mut face = String::from("f 1");
    for i in 1..corners {
        face.push_str([" 2", " 3", " 4"][i % 3]);
    }
    format!(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n{face}\n#{}\n",
        "x".repeat(pad)
    )
}

proptest! {
    // A process or a load of megabytes a case: few cases.
    #![proptest_config(ProptestConfig { cases: 24, ..config() })]

    /// Any command of these, its stdout and stderr full, closed or read,
    /// its outputs files or the open stdout and stderr: status 0, 2 or
    /// 141 (a closed pipe), never a panic or an abort.
    #[test]
    fn any_stream_and_any_output_ends_in_a_known_status(
        command in 0usize..4,
        out in 0usize..3,
        err in 0usize..2,
        image_to in 0usize..3,
        stats_to in 0usize..4,
    ) {
        let dir = tempfile::tempdir().unwrap();
        let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
        let scene = repo.join("scenes/seed-fig3.toml").display().to_string();
        let png = repo.join("docs/img/seed-fig5.png").display().to_string();
        let file = |name: &str| dir.path().join(name).display().to_string();
        let to = |k: usize, name: &str| match k {
            0 => "/dev/stdout".to_owned(),
            1 => "/dev/stderr".to_owned(),
            _ => file(name),
        };
        let mut args: Vec<String> = match command {
            0 | 1 => ["render", &scene, "--backend", "cpu", "--width", "8", "--height", "6", "-o"]
                .iter().map(|s| s.to_string()).chain([to(image_to, "x.png")]).collect(),
            2 => vec!["diff".into(), png.clone(), png.clone()],
            _ => vec!["--version".into()],
        };
        if command == 1 && stats_to < 3 {
            args.extend(["--stats".to_owned(), to(stats_to, "s.json")]);
        }
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_glint"))
            .args(&args)
            .stdin(std::process::Stdio::null())
            .stdout(stream(out))
            .stderr(stream(err))
            .output()
            .unwrap();
        let code = o.status.code();
        prop_assert!(matches!(code, Some(0 | 2 | 141)), "{args:?} out {out} err {err}: {:?}", o.status);
        let text = String::from_utf8_lossy(&o.stderr);
        prop_assert!(!text.contains("panicked") && !text.contains("RUST_BACKTRACE"), "{text}");
    }

    /// A polygon fan of any length, padded or not: within the file's
    /// allowance of triangles (65,536 and one per 20 bytes past them) or
    /// refused naming the face.
    #[test]
    fn a_polygon_fan_is_within_the_allowance_or_refused(
        corners in 3usize..400_000,
        pad in 0usize..4_000_000,
    ) {
        let dir = tempfile::tempdir().unwrap();
        let obj = fan(corners, pad);
        std::fs::write(dir.path().join("m.obj"), &obj).unwrap();
        let text = "[image]\nwidth = 4\nheight = 4\n[camera]\neye = [0, 0, 4]\n\
            look_at = [0, 0, 0]\nvfov = 45\n[materials.m]\n[[meshes]]\nfile = \"m.obj\"\n\
            material = \"m\"\n";
        match parse(text, &dir.path().join("s.toml"), &Overrides::default()) {
            Ok(scene) => {
                let made = scene.prims.bounded_count();
                prop_assert!(made <= 65_536 + obj.len() / 20, "{made} triangles from {} bytes", obj.len());
            }
            Err(e) => prop_assert!(e.to_string().contains("m.obj:5: this face brings the file to"), "{e}"),
        }
    }

    /// Band tiles of one size, their images in any order under their
    /// names: assembled only where each is its own, else refused naming
    /// the tile.
    #[test]
    fn swapped_tiles_assemble_only_in_their_own_places(order in Just([0usize, 1, 2]).prop_shuffle()) {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
        let scene = repo.join("scenes/seed-fig3.toml").display().to_string();
        let glint = |args: &[&str]| {
            std::process::Command::new(env!("CARGO_BIN_EXE_glint"))
                .args(args)
                .current_dir(d)
                .output()
                .unwrap()
        };
        for k in 0..3 {
            let (tile, out) = (format!("{k}/3"), format!("t{k}.pfm"));
            let o = glint(&["render", &scene, "--backend", "cpu", "--width", "16", "--height", "24", "--tile", &tile, "-o", &out]);
            prop_assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        }
        for k in 0..3 {
            std::fs::rename(d.join(format!("t{k}.pfm")), d.join(format!("s{k}.pfm"))).unwrap();
        }
        for (k, from) in order.iter().enumerate() {
            std::fs::rename(d.join(format!("s{from}.pfm")), d.join(format!("t{k}.pfm"))).unwrap();
        }
        let o = glint(&["assemble", "t0.pfm", "t1.pfm", "t2.pfm", "-o", "all.pfm"]);
        if order == [0, 1, 2] {
            prop_assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        } else {
            let err = String::from_utf8_lossy(&o.stderr);
            prop_assert_eq!(o.status.code(), Some(2));
            prop_assert!(err.contains("its pixels are not the ones"), "{}", err);
            prop_assert!(!d.join("all.pfm").exists());
        }
    }
}

#[cfg(feature = "gpu")]
proptest! {
    // A compile of up to half a megabyte: few cases.
    #![proptest_config(ProptestConfig { cases: 8, ..config() })]

    /// An include of one expression, a flat sum of any length or
    /// parentheses nested any depth, and a macro that repeats it: compiled,
    /// or refused in one error past the 512 KiB bound; never a crash of
    /// glslang's stack.
    #[test]
    fn deep_and_large_shader_sources_compile_or_are_refused(
        terms in 1usize..60_000,
        nested in any::<bool>(),
        repeats in prop_oneof![Just(1usize), 1usize..64],
    ) {
        use glint::gpu::compile::{compile, Sources};
        let dir = tempfile::tempdir().unwrap();
        let expression = if nested {
            let depth = terms.min(3_000);
            format!("{}1.0{}", "(1.0 + ".repeat(depth), ")".repeat(depth))
        } else {
            vec!["1.0"; terms].join(" + ")
        };
        let body = format!(
            "#define BIG ({expression})\nfloat big() {{ return {}; }}\n",
            vec!["BIG"; repeats].join(" + ")
        );
        std::fs::write(dir.path().join("big.glsl"), body).unwrap();
        let main = dir.path().join("main.comp");
        std::fs::write(
            &main,
            "#version 450\n#extension GL_GOOGLE_include_directive : require\n\
             layout(local_size_x = 1) in;\nlayout(std430, binding = 0) buffer B { float v[]; };\n\
             #include \"big.glsl\"\nvoid main() { v[0] = big(); }\n",
        )
        .unwrap();
        let sources = Sources {
            dirs: vec![dir.path().to_owned()],
            main: Some(main),
            ..Sources::default()
        };
        if let Err(e) = compile(&sources, &[]) {
            let text = e.to_string();
            prop_assert!(text.contains("past the bound of 512 KiB"), "{text}");
        }
    }
}

/// What an interrupted run may leave under `out`: whole files alone. No
/// `.tmp` file of a write the signal met, every scene whole TOML, and
/// nothing in its $TMPDIR (`tmp`) or among the processes.
fn left_whole(out: &Path, tmp: &Path) -> Result<(), TestCaseError> {
    fn walk(dir: &Path, found: &mut Vec<std::path::PathBuf>) {
        for e in std::fs::read_dir(dir).into_iter().flatten().flatten() {
            let p = e.path();
            if p.is_dir() {
                walk(&p, found);
            } else {
                found.push(p);
            }
        }
    }
    let mut files = Vec::new();
    walk(out, &mut files);
    for f in &files {
        let name = f.to_string_lossy();
        prop_assert!(
            !name.ends_with(".tmp"),
            "a temporary file was left: {}",
            name
        );
        if name.ends_with(".toml") {
            let text = std::fs::read_to_string(f).unwrap_or_default();
            prop_assert!(
                text.parse::<toml::Table>().is_ok(),
                "{} is not whole ({} bytes)",
                name,
                text.len()
            );
        }
    }
    let mut temporary = Vec::new();
    walk(tmp, &mut temporary);
    prop_assert!(temporary.is_empty(), "left in $TMPDIR: {:?}", temporary);
    let name = tmp.to_string_lossy().into_owned();
    let children: Vec<String> = common::command_lines()
        .into_iter()
        .filter(|c| c.contains("driver-probe") && c.contains(&name))
        .collect();
    prop_assert!(children.is_empty(), "children left: {:?}", children);
    Ok(())
}

/// Interrupted runs fuzzed: `glint fuzz --dump` (scenes of a few to tens
/// of thousands of objects, so that a signal can meet a write) and, where
/// the GPU is built, `glint drivers --generated`, each stopped by SIGINT,
/// SIGTERM or SIGHUP after a random delay. Each run ends at once with
/// exit 0 (done) or 130 (or by the signal, where it came before the
/// handler), and leaves only whole files ([`left_whole`]).
#[test]
fn interrupted_runs_leave_only_whole_files() {
    let commands = if cfg!(feature = "gpu") { 2 } else { 1 };
    let cases = (0..commands, 0..3usize, 0..700u64, 0..3usize, 0..1000u64);
    let config = ProptestConfig {
        cases: 12,
        ..config()
    };
    proptest!(config, |((command, sig, delay_ms, size, seed) in cases)| {
        let dir = tempfile::tempdir().unwrap();
        let (out, tmp) = (dir.path().join("out"), dir.path().join("tmp"));
        std::fs::create_dir(&tmp).unwrap();
        let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_glint"));
        if command == 0 {
            let objects = ["50", "5000", "40000"][size];
            c.args(["fuzz", "--backend", "cpu", "--cases", "3", "--objects", objects])
                .args(["--seed", &seed.to_string(), "--dump"])
                .arg(&out);
        } else {
            c.current_dir(common::repo())
                .args(["drivers", "--quick", "--generated", &(1 + size).to_string()])
                .args(["--seed", &seed.to_string(), "-o"])
                .arg(&out);
        }
        let mut child = c
            .env("TMPDIR", &tmp)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(delay_ms));
        let signal = [libc::SIGINT, libc::SIGTERM, libc::SIGHUP][sig];
        // SAFETY: signals the child this test started.
        unsafe { libc::kill(child.id() as libc::pid_t, signal) };
        let asked = std::time::Instant::now();
        let status = child.wait().unwrap();
        prop_assert!(
            asked.elapsed() < std::time::Duration::from_secs(20),
            "it took {:?} to stop",
            asked.elapsed()
        );
        // A signal before main installs the handler (the first thing it
        // does) ends the process as the signal's default does: nothing is
        // written by then, which `left_whole` checks.
        use std::os::unix::process::ExitStatusExt;
        prop_assert!(
            status.success() || status.code() == Some(130) || status.signal() == Some(signal),
            "{:?}",
            status
        );
        // A probe that outlived glint would write its folder back by now.
        std::thread::sleep(std::time::Duration::from_millis(200));
        left_whole(&out, &tmp)?;
    });
}
