//! Shared by the integration tests. Every GPU renderer here runs with the
//! Khronos validation layer, and any message it sends fails the render.

#![allow(dead_code)]

pub mod page;

use std::path::{Path, PathBuf};
use std::process::Output;

use assert_cmd::assert::OutputAssertExt;
use predicates::prelude::*;
use predicates::str::{contains, starts_with};

#[cfg(feature = "gpu")]
use glint::gpu::variant::Variant;
#[cfg(feature = "gpu")]
use glint::gpu::{GpuOptions, RenderSettings, Renderer};
#[cfg(feature = "gpu")]
use glint::raster::region::Region;
use glint::raster::Image;
use glint::scene::{parse, Overrides, Scene};
#[cfg(feature = "gpu")]
use glint::stats::Counts;

#[cfg(feature = "gpu")]
pub fn gpu() -> Renderer {
    gpu_with(RenderSettings::default())
}

/// A renderer with these settings (the validation layer on).
#[cfg(feature = "gpu")]
pub fn gpu_with(settings: RenderSettings) -> Renderer {
    gpu_from(GpuOptions {
        settings,
        ..GpuOptions::default()
    })
}

/// A renderer of `options` with the validation layer on, whatever they say.
#[cfg(feature = "gpu")]
pub fn gpu_from(options: GpuOptions) -> Renderer {
    let options = GpuOptions {
        validate: true,
        ..options
    };
    Renderer::new(&options)
        .unwrap_or_else(|e| panic!("cannot open the Vulkan device with validation: {e}"))
}

/// `region` of `scene` rendered by `r` with its own settings.
#[cfg(feature = "gpu")]
pub fn render_region(r: &mut Renderer, scene: &Scene, region: Region) -> Image {
    let settings = r.settings();
    r.prepare(scene, &settings)
        .and_then(|mut p| p.render(Some(region), &|_| {}))
        .unwrap_or_else(|e| panic!("GPU render of {region:?} failed: {e}"))
        .image
}

/// The whole of `scene` rendered by `r` with its own settings and the
/// counting variant: the image and the counts.
#[cfg(feature = "gpu")]
pub fn render_counted(r: &mut Renderer, scene: &Scene) -> (Image, Counts) {
    let settings = RenderSettings {
        count: true,
        ..r.settings()
    };
    let rendered = r
        .prepare(scene, &settings)
        .and_then(|mut p| p.render(None, &|_| {}))
        .unwrap_or_else(|e| panic!("counted GPU render failed: {e}"));
    (
        rendered.image,
        rendered.counts.expect("a counting render counts"),
    )
}

/// The variant `r` compiles `scene` with under its own settings.
#[cfg(feature = "gpu")]
pub fn variant(r: &Renderer, scene: &Scene) -> (Variant, Vec<(String, Option<String>)>) {
    r.variant(scene, &r.settings())
}

/// The glint binary with validation on, as a user runs it.
pub fn cmd() -> assert_cmd::Command {
    let mut c = assert_cmd::Command::new(env!("CARGO_BIN_EXE_glint"));
    c.env("GLINT_VALIDATION", "1");
    c
}

/// Runs the glint binary with validation on, as a user would.
pub fn glint(args: &[&str]) -> Output {
    cmd().args(args).output().expect("run glint")
}

/// A 40x30 CPU render of seed-fig3 to `out`, with `extra` arguments: a
/// quick run for tests of what happens to the files around it.
pub fn small_cpu_render(out: &Path, extra: &[&str]) -> Output {
    let scene = repo().join("scenes/seed-fig3.toml");
    let mut args = vec![
        "render",
        scene.to_str().unwrap(),
        "--backend",
        "cpu",
        "--width",
        "40",
        "--height",
        "30",
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    glint(&args)
}

/// Says in the test log why a test (or a part of one) does not run on
/// this machine. Written to stderr directly, past the harness's capture,
/// so that a skip shows in a passing run's log and is never silent.
pub fn skip(what: &str, why: &str) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "skipped: {what}: {why}");
}

/// A run that succeeded (its stderr shown where not).
pub fn assert_ok(o: &Output) {
    o.clone().assert().success();
}

/// A user's error: exit status 2, one `error: ` message naming `words`,
/// no panic.
pub fn assert_user_error(o: &Output, words: &str) {
    o.clone().assert().code(2).stderr(
        starts_with("error: ")
            .and(contains(words))
            .and(contains("panicked").not()),
    );
}

/// Text of exactly one line (trailing whitespace aside): what every error
/// message is.
pub fn one_line() -> impl Predicate<str> {
    predicate::function(|text: &str| text.trim().lines().count() == 1)
}

/// The one JSON value a successful run printed.
pub fn json_of(run: &assert_cmd::assert::Assert) -> serde_json::Value {
    serde_json::from_slice(&run.get_output().stdout).expect("one JSON value on stdout")
}

/// Every pixel of `image` equals `want` to a relative error of `rel`.
pub fn assert_uniform(image: &Image, want: [f64; 3], rel: f64, what: &str) {
    for (i, p) in image.pixels.iter().enumerate() {
        for c in 0..3 {
            let err = (f64::from(p[c]) - want[c]).abs() / want[c];
            assert!(
                err <= rel,
                "{what}: pixel {i} channel {c}: {} against {} (relative error {err:.2e})",
                p[c],
                want[c]
            );
        }
    }
}

/// The GPU's render where glint is built with it; none in the CPU-only
/// build, whose tests check the CPU renderers alone.
pub fn render_gpu_if_built(scene: &Scene) -> Option<Image> {
    #[cfg(feature = "gpu")]
    return Some(render_gpu(scene));
    #[cfg(not(feature = "gpu"))]
    {
        let _ = scene;
        None
    }
}

#[cfg(feature = "gpu")]
pub fn render_gpu(scene: &Scene) -> Image {
    let mut r = gpu();
    r.render(scene, &|_| {})
        .unwrap_or_else(|e| panic!("GPU render failed: {e}"))
        .0
}

pub fn scene(text: &str) -> Scene {
    parse(text, Path::new("test.toml"), &Overrides::default())
        .unwrap_or_else(|e| panic!("test scene: {e}"))
}

pub fn scene_sized(text: &str, width: u32, height: u32) -> Scene {
    let o = Overrides {
        width: Some(width),
        height: Some(height),
        ..Overrides::default()
    };
    parse(text, Path::new("test.toml"), &o).unwrap_or_else(|e| panic!("test scene: {e}"))
}

pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The scene files directly in `dir` (relative to the repository), sorted.
pub fn scene_files(dir: &str) -> Vec<PathBuf> {
    glint::files::sorted(&repo().join(dir), |p| {
        p.extension().is_some_and(|e| e == "toml")
    })
    .expect("scene directory")
}

/// A small scene with spheres, a plane, every light type and reflection.
pub const SMALL: &str = r#"
[image]
width = 64
height = 48
[render]
max_depth = 3
background = [0.1, 0.1, 0.2]
[camera]
eye = [0.0, 1.0, 8.0]
look_at = [0.0, 0.0, 0.0]
vfov = 50.0
[materials.a]
ambient = [0.1, 0.1, 0.1]
diffuse = [0.7, 0.3, 0.2]
specular = [0.5, 0.5, 0.5]
shininess = 30.0
reflectivity = 0.4
[materials.b]
diffuse = [0.4, 0.5, 0.6]
[[spheres]]
center = [0.0, 0.0, 0.0]
radius = 1.0
material = "a"
[[spheres]]
center = [1.8, 0.0, -1.0]
radius = 0.7
material = "b"
[[planes]]
point = [0.0, -1.0, 0.0]
normal = [0.0, 1.0, 0.0]
material = "b"
[[lights]]
type = "point"
position = [3.0, 4.0, 5.0]
ambient = [0.2, 0.2, 0.2]
diffuse = [1.0, 1.0, 1.0]
specular = [1.0, 1.0, 1.0]
[[lights]]
type = "directional"
direction = [-1.0, -1.0, 0.0]
diffuse = [0.3, 0.3, 0.3]
[[lights]]
type = "spot"
position = [0.0, 4.0, 0.0]
direction = [0.0, -1.0, 0.0]
diffuse = [0.5, 0.5, 0.5]
cutoff = 30.0
exponent = 4.0
"#;

/// A copy of shaders/specular.glsl whose loop never ends (the condition
/// holds for every finite normal): a hung shader, on a driver without a
/// loop limit; on one with a limit (Mesa 22.3) the budget ends it.
pub fn runaway_include(dir: &Path) -> PathBuf {
    let inc = dir.join("runaway");
    std::fs::create_dir(&inc).unwrap();
    std::fs::write(
        inc.join("specular.glsl"),
        "real specular(vec3r n, vec3r l, vec3r v, real shininess) {\n\
         \x20   real s = 0.0;\n\
         \x20   while (dot(n, n) >= 0.0) { s += 1.0; }\n\
         \x20   return s;\n\
         }\n",
    )
    .unwrap();
    inc
}

/// Two copies of `scene` whose backgrounds are one f32 step apart in green
/// (from at least 1/4, a normal float every device keeps): real renders of
/// the two differ in one bit wherever a pixel is the background, so a
/// bit-for-bit comparison of renders is shown to fail on a real image, not
/// a copy with a flipped bit.
pub fn one_bit_apart(scene: &Scene) -> (Scene, Scene) {
    let mut a = scene.clone();
    let green = (a.background.y as f32).max(0.25);
    a.background.y = f64::from(green);
    let mut b = a.clone();
    b.background.y = f64::from(f32::from_bits(green.to_bits() + 1));
    (a, b)
}

/// Whether some channel of some pixel of `a` and `b` differs in exactly
/// its last bit.
pub fn differ_in_one_bit(a: &Image, b: &Image) -> bool {
    a.pixels
        .iter()
        .zip(&b.pixels)
        .any(|(p, q)| (0..3).any(|c| p[c].to_bits().abs_diff(q[c].to_bits()) == 1))
}

/// Bit for bit: the same bits in every channel (NaN would differ from itself).
pub fn same_bits(a: &Image, b: &Image) -> bool {
    a.pixels.len() == b.pixels.len()
        && a.pixels
            .iter()
            .zip(&b.pixels)
            .all(|(p, q)| (0..3).all(|c| p[c].to_bits() == q[c].to_bits()))
}

/// Asserts that the CPU f32 render of `scene` (`what`, in the message),
/// and the GPU's where glint is built with it, are within the default
/// tolerance of `reference` (its CPU f64 render).
pub fn assert_renderers_agree(what: &str, scene: &Scene, reference: &Image) {
    assert!(
        passes(&glint::cpu::render::<f32>(scene), reference),
        "{what}: CPU f32"
    );
    if let Some(gpu) = render_gpu_if_built(scene) {
        let f = glint::raster::diff::figures(&gpu, reference).unwrap();
        assert!(passes(&gpu, reference), "{what}: GPU f32: {f:?}");
    }
}

/// The CPU f64 render of the scene file `path` at `width`×`height` with
/// 16×16 samples a pixel: a converged image, for the samplings' tests.
pub fn converged(path: &str, width: u32, height: u32) -> Image {
    let text = std::fs::read_to_string(repo().join(path)).unwrap();
    let mut s = scene_sized(&text, width, height);
    s.samples = 16;
    s.sampling = glint::scene::Sampling::Centers;
    s.adaptive = None;
    glint::cpu::render::<f64>(&s)
}

/// The CPU f32 render's ray counts of `scene`, once the GPU's count of its
/// eye rays is asserted to be within 0.1 % of them.
#[cfg(feature = "gpu")]
pub fn eye_rays_counted_alike(scene: &Scene) -> glint::stats::RayCounts {
    let (_, cpu_counts) =
        glint::cpu::render_counted::<f32>(scene, glint::accel::Accel::Auto, &|_| {});
    let (_, gpu_counts) = render_counted(&mut gpu(), scene);
    let (c, g) = (cpu_counts.rays(), gpu_counts.rays());
    let off = (c.eye as f64 - g.eye as f64).abs() / c.eye as f64;
    assert!(off <= 0.001, "{c:?} against {g:?}");
    c
}

/// Asserts that an 8×6 scene with `image` in its `[image]` table is
/// refused in one error that names bad.toml, `key` and `words`.
pub fn assert_image_keys_refused(image: &str, key: &str, words: &str) {
    let text = format!(
        "[image]\nwidth = 8\nheight = 6\n{image}\
         [camera]\neye = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\nvfov = 40.0\n"
    );
    let msg = match parse(&text, Path::new("bad.toml"), &Overrides::default()) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e.to_string(),
    };
    assert!(msg.starts_with("bad.toml:"), "{msg}");
    assert!(msg.contains(key), "expected {key}: {msg}");
    assert!(msg.contains(words), "expected {words:?}: {msg}");
}

/// Whether `image` is within the default tolerance of `reference`.
pub fn passes(image: &Image, reference: &Image) -> bool {
    let f = glint::raster::diff::figures(image, reference).unwrap();
    glint::raster::diff::Tolerance::default()
        .violations(&f)
        .is_empty()
}

/// Makes a FIFO at `path`.
pub fn make_fifo(path: &Path) {
    let c = std::ffi::CString::new(path.to_str().unwrap()).unwrap();
    // SAFETY: a NUL-terminated path for the call.
    assert_eq!(
        unsafe { libc::mkfifo(c.as_ptr(), 0o600) },
        0,
        "mkfifo {}",
        path.display()
    );
}

/// Writes a Vulkan driver manifest at `path` whose library is `library`.
pub fn write_icd_manifest(path: &Path, library: &Path) {
    let manifest = serde_json::json!({
        "file_format_version": "1.0.0",
        "ICD": { "library_path": library, "api_version": "1.3.0" },
    });
    std::fs::write(path, manifest.to_string()).unwrap();
}

/// Debian 12's stock lavapipe (Mesa 22.3), as `ci/old-lavapipe` unpacks it.
pub fn old_lavapipe() -> Option<PathBuf> {
    let o = std::process::Command::new(repo().join("ci/old-lavapipe"))
        .output()
        .ok()?;
    let path = PathBuf::from(String::from_utf8_lossy(&o.stdout).trim());
    (o.status.success() && path.is_file()).then_some(path)
}

/// The command lines of the processes running now.
pub fn command_lines() -> Vec<String> {
    std::fs::read_dir("/proc")
        .unwrap()
        .filter_map(|e| std::fs::read(e.ok()?.path().join("cmdline")).ok())
        .map(|b| String::from_utf8_lossy(&b).replace('\0', " "))
        .collect()
}

/// Tiles and regions of `scene`'s render (3 and 7 tiles) are the whole
/// render's pixels, bit for bit, on the CPU in f32 and, where built, on
/// the GPU: for a sampling whose pixels depend on their neighbours'.
pub fn regions_are_the_whole(scene: &Scene) {
    use glint::accel::Accel;
    let whole = glint::cpu::render::<f32>(scene);
    #[cfg(feature = "gpu")]
    let mut gpu = gpu();
    #[cfg(feature = "gpu")]
    let gpu_whole = gpu.render(scene, &|_| {}).unwrap().0;
    for n in [3, 7] {
        for i in 0..n {
            let r = glint::raster::region::Region::tile(i, n, scene.width, scene.height).unwrap();
            let part = glint::cpu::render_region::<f32>(scene, Accel::Auto, r, &|_| {});
            #[cfg(feature = "gpu")]
            let gpu_part = render_region(&mut gpu, scene, r);
            for y in 0..r.height {
                for x in 0..r.width {
                    let want = whole.get(r.x + x, r.y + y);
                    assert_eq!(
                        part.get(x, y).map(f32::to_bits),
                        want.map(f32::to_bits),
                        "CPU tile {i} of {n} at ({x}, {y})"
                    );
                    #[cfg(feature = "gpu")]
                    assert_eq!(
                        gpu_part.get(x, y).map(f32::to_bits),
                        gpu_whole.get(r.x + x, r.y + y).map(f32::to_bits),
                        "GPU tile {i} of {n} at ({x}, {y})"
                    );
                }
            }
        }
    }
}

/// The scene file at `path` (under the repository) at `width`×`height`,
/// its own sampling keys taken out of `[image]` and `keys` (TOML lines)
/// put in.
pub fn resampled(path: &str, width: u32, height: u32, keys: &str) -> Scene {
    let text = std::fs::read_to_string(repo().join(path)).unwrap();
    let text: String = text
        .lines()
        .filter(|l| {
            !["samples =", "sampling =", "threshold =", "max_level ="]
                .iter()
                .any(|k| l.starts_with(k))
        })
        .map(|l| format!("{l}\n"))
        .collect();
    let text = text.replace("[image]\n", &format!("[image]\n{keys}"));
    scene_sized(&text, width, height)
}

/// Six nested glass spheres at depth `max_depth` under 16 lights, seen in
/// one pixel: a tree of hundreds of rays at depth 11, 1,977 at depth 13.
pub fn nested_glass(max_depth: u32) -> String {
    let mut s = format!(
        "[image]\nwidth = 1\nheight = 1\n[render]\nmax_depth = {max_depth}\n[camera]\neye = [0, 0, 10]\n\
         look_at = [0, 0, 0]\nvfov = 10\n[materials.g]\ndiffuse = [0.2, 0.2, 0.2]\n\
         specular = [0.5, 0.5, 0.5]\nshininess = 50\nreflectivity = 0.3\ntransmittance = 0.6\nior = 1.5\n",
    );
    for i in 0..6 {
        s += &format!(
            "[[spheres]]\ncenter = [0, 0, 0]\nradius = {}\nmaterial = \"g\"\n",
            3.0 - 0.4 * f64::from(i)
        );
    }
    for k in 0..16 {
        let a = f64::from(k) * std::f64::consts::TAU / 16.0;
        s += &format!(
            "[[lights]]\ntype = \"point\"\nposition = [{}, {}, 6]\ndiffuse = [0.1, 0.1, 0.1]\n",
            8.0 * a.cos(),
            8.0 * a.sin()
        );
    }
    s
}
