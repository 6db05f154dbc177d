//! `glint report`: every variant of every scene, its error against the CPU
//! f64 reference and its run time, written as tables, a plot and a page.

pub mod html;
pub mod svg;
pub mod tables;

use std::time::Instant;

use serde::Serialize;

use crate::accel::Accel;
use crate::cpu;
use crate::gpu::vk::device::DeviceInfo;
use crate::gpu::{GpuError, Intersect, Precision, RenderSettings, Renderer, SetupTimes};
use crate::raster::diff::{figures, ErrorFigures};
use crate::raster::{quantize_pixels, Image};
use crate::scene::Scene;

/// What `measure` measures.
#[derive(Debug, Clone, Copy)]
pub struct Settings {
    /// Warm runs per variant; the median is reported.
    pub runs: usize,
    /// Also sweep max_depth and samples from 1 to the scene's own.
    pub sweeps: bool,
    /// Also the sampling axis: uniform, adaptive and contrast sampling
    /// against a converged render (`SAMPLING_UNIFORM`, `SAMPLING_ADAPTIVE`,
    /// `SAMPLING_CONTRAST`, `SAMPLING_RANGE`).
    pub sampling: bool,
}

/// The sampling axis's uniform grids, samples a side.
pub const SAMPLING_UNIFORM: [u32; 4] = [1, 2, 4, 8];
/// Its adaptive settings: threshold in thousandths, and levels.
pub const SAMPLING_ADAPTIVE: [(u32, u32); 4] = [(200, 2), (100, 2), (50, 2), (20, 3)];
/// The sampling axis's contrast settings: a threshold in every channel
/// (in thousandths) and the most samples a pixel takes.
pub const SAMPLING_CONTRAST: [(u32, u32); 4] = [(200, 17), (100, 17), (50, 17), (50, 33)];
/// Contrast sampling with the range test, trees not compared: the bound
/// (in thousandths) and the most samples a pixel takes.
pub const SAMPLING_RANGE: [(u32, u32); 3] = [(50, 17), (50, 33), (30, 33)];
/// The converged render the sampling axis is measured against: CPU f64
/// with this many uniform samples a side.
pub const CONVERGED_SAMPLES: u32 = 16;

/// Medians over the warm runs, in seconds.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct Timing {
    /// The median run's total.
    pub median_s: f64,
    /// GPU only: the median run's upload.
    pub upload_s: Option<f64>,
    /// GPU only: the median run's dispatches, with their waits.
    pub dispatch_s: Option<f64>,
    /// GPU only: the median run's readback.
    pub readback_s: Option<f64>,
    /// Primary rays (pixels x samples²) per second at the median.
    pub rays_per_s: f64,
}

/// What one measurement renders with. Its name, its columns in the tables
/// and its colour in the plot all follow from it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Variant {
    /// The scene's own shader variant, in f32, with these intersection forms.
    Gpu(Intersect),
    /// The scene's own shader variant in f64 (where the device has doubles).
    Gpu64,
    /// The one shader that handles every feature, in f32: what the scene's
    /// own variant saves.
    GpuGeneric,
    /// The scene's own variant (f32, robust) at a lower max_depth.
    GpuDepth(u32),
    /// The scene's own variant (f32, robust) with fewer samples a side.
    GpuSamples(u32),
    /// The sampling axis: GPU f32 robust with this uniform grid a side.
    GpuUniform(u32),
    /// The sampling axis: GPU f32 robust, adaptive sampling with this
    /// threshold (in thousandths) and levels.
    GpuAdaptive(u32, u32),
    /// The sampling axis: GPU f32 robust, contrast sampling with this
    /// threshold in every channel (in thousandths) and most samples.
    GpuContrast(u32, u32),
    /// The sampling axis: GPU f32 robust, contrast sampling with the range
    /// test at this bound (in thousandths) and most samples, trees not
    /// compared.
    GpuRange(u32, u32),
    /// The CPU reference in f32.
    Cpu32,
    /// The CPU reference in f64: the reference itself.
    Cpu64,
}

impl Variant {
    /// Its name in the tables, the plot and report.json.
    pub fn name(self) -> String {
        match self {
            Variant::Gpu(Intersect::Robust) => "gpu f32 robust".to_owned(),
            Variant::Gpu(Intersect::Naive) => "gpu f32 naive".to_owned(),
            Variant::Gpu64 => "gpu f64".to_owned(),
            Variant::GpuGeneric => "gpu f32 generic".to_owned(),
            Variant::GpuDepth(d) => format!("gpu f32 depth {d}"),
            Variant::GpuSamples(s) => format!("gpu f32 samples {s}"),
            Variant::GpuUniform(n) => format!("gpu f32 uniform {n}x{n}"),
            Variant::GpuAdaptive(t, l) => {
                format!("gpu f32 adaptive {}/{l}", f64::from(t) / 1000.0)
            }
            Variant::GpuContrast(t, m) => {
                format!("gpu f32 contrast {}/{m}", f64::from(t) / 1000.0)
            }
            Variant::GpuRange(r, m) => {
                format!("gpu f32 range {}/{m}", f64::from(r) / 1000.0)
            }
            Variant::Cpu32 => "cpu f32".to_owned(),
            Variant::Cpu64 => "cpu f64".to_owned(),
        }
    }

    /// `gpu` or `cpu`.
    pub fn backend(self) -> &'static str {
        match self {
            Variant::Cpu32 | Variant::Cpu64 => "cpu",
            _ => "gpu",
        }
    }

    /// Its arithmetic.
    pub fn precision(self) -> Precision {
        match self {
            Variant::Gpu64 | Variant::Cpu64 => Precision::F64,
            _ => Precision::F32,
        }
    }

    /// The intersection forms of a GPU variant.
    pub fn intersect(self) -> Option<Intersect> {
        match self {
            Variant::Gpu(form) => Some(form),
            Variant::Cpu32 | Variant::Cpu64 => None,
            _ => Some(Intersect::Robust),
        }
    }
}

/// report.json's `variant` (the name), `backend`, `precision` and
/// `intersect`, all from the one value.
impl Serialize for Variant {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(Some(4))?;
        m.serialize_entry("variant", &self.name())?;
        m.serialize_entry("backend", self.backend())?;
        m.serialize_entry("precision", &self.precision())?;
        m.serialize_entry("intersect", &self.intersect())?;
        m.end()
    }
}

/// One variant of one scene: its error against the CPU f64 reference and
/// its time.
#[derive(Debug, Clone, Serialize)]
pub struct Measurement {
    /// What rendered (in report.json, its name and what it follows from).
    #[serde(flatten)]
    pub variant: Variant,
    /// The ray tree's depth it rendered at.
    pub max_depth: u32,
    /// The samples a side it rendered with.
    pub samples: u32,
    /// Its error against the CPU f64 reference.
    pub error: ErrorFigures,
    /// Mean LDR-FLIP error (0: identical, 1: as different as can be) of the
    /// sRGB-encoded 8-bit images.
    pub flip_mean: f64,
    /// Its medians.
    pub time: Timing,
    /// GPU only: compile and pipeline creation for this variant (one-time).
    pub setup: Option<SetupTimes>,
    /// On the scene's Pareto front of error (rmse) against time.
    pub pareto: bool,
}

/// The columns of a measurement's row in report.md and index.html.
pub const ROW_HEADERS: [&str; 11] = [
    "variant",
    "time",
    "upload / dispatch / readback (s)",
    "Mrays/s",
    "compile + pipeline",
    "max_abs",
    "rmse",
    "PSNR",
    "over 1/255",
    "nonfinite",
    "FLIP",
];

impl Measurement {
    /// The cells of this measurement's row, as the tables show them.
    pub fn row(&self) -> [String; 11] {
        let e = &self.error;
        let parts = match (
            self.time.upload_s,
            self.time.dispatch_s,
            self.time.readback_s,
        ) {
            (Some(u), Some(d), Some(r)) => format!("{u:.4} / {d:.4} / {r:.4}"),
            _ => String::new(),
        };
        [
            self.variant.name(),
            format!("{:.4} s", self.time.median_s),
            parts,
            format!("{:.2}", self.time.rays_per_s / 1e6),
            self.setup.map_or(String::new(), |x| {
                format!("{:.3} s", x.compile_s + x.pipeline_s)
            }),
            format!("{:.2e}", e.max_abs),
            format!("{:.2e}", e.rmse),
            psnr(e.psnr_db, 1, " dB"),
            format!("{:.4}%", 100.0 * e.frac_over_1_255),
            e.nonfinite.to_string(),
            format!("{:.2e}", self.flip_mean),
        ]
    }
}

/// Every variant of one scene.
#[derive(Debug, Clone, Serialize)]
pub struct SceneReport {
    /// The scene's name (its file's stem).
    pub name: String,
    /// The image's width.
    pub width: u32,
    /// The image's height.
    pub height: u32,
    /// The scene's samples a side.
    pub samples: u32,
    /// How the scene samples a pixel, in a few words (`Scene::sampling_summary`).
    pub sampling_summary: String,
    /// The scene's ray-tree depth.
    pub max_depth: u32,
    /// One a variant.
    pub measurements: Vec<Measurement>,
    /// The sampling axis, where measured: each against the converged
    /// render (CPU f64, `CONVERGED_SAMPLES`² uniform samples), not the
    /// scene's own reference.
    pub sampling: Vec<Measurement>,
    /// Not serialized: the images for the page.
    #[serde(skip)]
    pub images: SceneImages,
}

/// The images index.html shows of a scene.
#[derive(Debug, Clone, Default)]
pub struct SceneImages {
    /// The GPU's (f32, robust).
    pub gpu: Option<Image>,
    /// The CPU f64 reference's.
    pub reference: Option<Image>,
    /// Whether the scene writes sRGB.
    pub srgb: bool,
}

/// The machine the report was made on.
#[derive(Debug, Clone, Serialize)]
pub struct Machine {
    /// The CPU's model name.
    pub cpu: String,
    /// The CPU renderer's threads.
    pub threads: usize,
    /// The operating system's name.
    pub os: String,
}

/// A whole report: the machine, the device, and every scene's measurements.
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    /// Where it was made.
    pub machine: Machine,
    /// The Vulkan device the GPU variants ran on.
    pub device: DeviceInfo,
    /// Opening the Vulkan device, once.
    pub device_s: f64,
    /// Warm runs a variant.
    pub runs: usize,
    /// The scenes.
    pub scenes: Vec<SceneReport>,
}

/// This machine, as far as /proc and /etc/os-release say.
pub fn machine() -> Machine {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_owned())
        })
        .unwrap_or_else(|| std::env::consts::ARCH.to_owned());
    let os = std::fs::read_to_string("/etc/os-release")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("PRETTY_NAME="))
                .map(|l| l[12..].trim_matches('"').to_owned())
        })
        .unwrap_or_else(|| std::env::consts::OS.to_owned());
    Machine {
        cpu,
        threads: rayon::current_num_threads(),
        os,
    }
}

/// `s` as text or an attribute value of HTML or SVG.
pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The median of `v` (the upper one of an even count), sorting it.
pub fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// LDR-FLIP between two linear images, each sRGB-encoded and quantized.
pub fn flip_mean(image: &Image, reference: &Image) -> f64 {
    let to8 = |img: &Image| -> nv_flip::FlipImageRgb8 {
        let bytes = quantize_pixels(&img.pixels, true);
        nv_flip::FlipImageRgb8::with_data(img.width, img.height, &bytes)
    };
    let map = nv_flip::flip(
        to8(reference),
        to8(image),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    f64::from(nv_flip::FlipPool::from_image(&map).mean())
}

/// Measures every variant of `scene`; `progress` is called once per variant.
pub fn measure(
    renderer: &mut Renderer,
    scene: &Scene,
    name: &str,
    settings: Settings,
    progress: &dyn Fn(&str),
) -> Result<SceneReport, GpuError> {
    let reference = cpu::reference(scene, Accel::Auto)?;
    let mut variants = vec![
        Variant::Gpu(Intersect::Robust),
        Variant::Gpu(Intersect::Naive),
    ];
    if renderer.device_info().shader_float64 {
        variants.push(Variant::Gpu64);
    }
    variants.extend([Variant::Cpu32, Variant::Cpu64, Variant::GpuGeneric]);
    if settings.sweeps {
        variants.extend((1..scene.max_depth).map(Variant::GpuDepth));
        variants.extend((1..scene.samples).map(Variant::GpuSamples));
    }
    let mut measurements = Vec::new();
    let mut gpu_image = None;
    for variant in variants {
        let (m, image) = measure_one(
            renderer,
            scene,
            variant,
            &reference,
            settings.runs,
            progress,
        )?;
        if variant == Variant::Gpu(Intersect::Robust) {
            gpu_image = Some(image);
        }
        measurements.push(m);
    }
    mark_pareto(&mut measurements);
    let mut sampling = Vec::new();
    if settings.sampling {
        progress("converged reference");
        let converged = cpu::reference(
            &sampled(scene, Variant::GpuUniform(CONVERGED_SAMPLES)),
            Accel::Auto,
        )?;
        let axis = SAMPLING_UNIFORM
            .map(Variant::GpuUniform)
            .into_iter()
            .chain(SAMPLING_ADAPTIVE.map(|(t, l)| Variant::GpuAdaptive(t, l)))
            .chain(SAMPLING_CONTRAST.map(|(t, m)| Variant::GpuContrast(t, m)))
            .chain(SAMPLING_RANGE.map(|(r, m)| Variant::GpuRange(r, m)));
        for variant in axis {
            let (m, _) = measure_one(
                renderer,
                scene,
                variant,
                &converged,
                settings.runs,
                progress,
            )?;
            sampling.push(m);
        }
        mark_pareto(&mut sampling);
    }
    Ok(SceneReport {
        name: name.to_owned(),
        width: scene.width,
        height: scene.height,
        samples: scene.samples,
        sampling_summary: scene.sampling_summary(),
        max_depth: scene.max_depth,
        measurements,
        sampling,
        images: SceneImages {
            reference: Some(reference),
            gpu: gpu_image,
            srgb: scene.srgb,
        },
    })
}

/// `scene` as `variant` renders it: its depth, samples or sampling.
fn sampled(scene: &Scene, variant: Variant) -> Scene {
    let mut s = scene.clone();
    match variant {
        Variant::GpuDepth(d) => s.max_depth = d,
        Variant::GpuSamples(n) => s.samples = n,
        Variant::GpuUniform(n) => {
            s.samples = n;
            s.sampling = crate::scene::Sampling::Centers;
            s.adaptive = None;
        }
        Variant::GpuContrast(t, m) => by_contrast(
            &mut s,
            crate::scene::Contrast {
                thresholds: [f64::from(t) / 1000.0; 3],
                max_samples: m,
                compare_trees: true,
                range: None,
            },
        ),
        Variant::GpuRange(r, m) => by_contrast(
            &mut s,
            crate::scene::Contrast {
                max_samples: m,
                compare_trees: false,
                range: Some(f64::from(r) / 1000.0),
                ..crate::scene::Contrast::default()
            },
        ),
        Variant::GpuAdaptive(t, l) => {
            s.samples = 1;
            s.sampling = crate::scene::Sampling::Adaptive;
            s.adaptive = Some(crate::scene::Adaptive {
                threshold: f64::from(t) / 1000.0,
                levels: l,
            });
        }
        _ => {}
    }
    s
}

/// `s` sampled by contrast as `contrast` says: the sampling axis's two
/// tests differ in their settings alone.
fn by_contrast(s: &mut Scene, contrast: crate::scene::Contrast) {
    s.samples = 1;
    s.sampling = crate::scene::Sampling::Contrast;
    s.adaptive = None;
    s.contrast = Some(contrast);
}

/// One variant of `scene`: its error against `reference`, and the median
/// of `runs` warm runs; with its image.
fn measure_one(
    renderer: &mut Renderer,
    scene: &Scene,
    variant: Variant,
    reference: &Image,
    runs: usize,
    progress: &dyn Fn(&str),
) -> Result<(Measurement, Image), GpuError> {
    progress(&variant.name());
    let s = sampled(scene, variant);
    let rays = s.ray_count() as f64;
    let (image, time, setup) = match variant.intersect() {
        Some(intersect) => {
            let how = RenderSettings {
                intersect,
                precision: variant.precision(),
                generic: variant == Variant::GpuGeneric,
                ..renderer.settings()
            };
            let mut prepared = renderer.prepare(&s, &how)?;
            // The warm-up, untimed: its times carry the setup.
            let warm = prepared.render(None, &|_| {})?;
            let (image, setup) = (warm.image, warm.times.setup);
            let mut timed: Vec<(f64, crate::gpu::RenderTimes)> = Vec::new();
            for _ in 0..runs {
                let t = prepared.render(None, &|_| {})?.times;
                timed.push((t.total_s(), t));
            }
            timed.sort_by(|a, b| a.0.total_cmp(&b.0));
            let (m, parts) = timed[timed.len() / 2];
            let time = Timing {
                median_s: m,
                upload_s: Some(parts.upload_s),
                dispatch_s: Some(parts.dispatch_s),
                readback_s: Some(parts.readback_s),
                rays_per_s: rays / m,
            };
            (image, time, Some(setup))
        }
        None => {
            let render = |s: &Scene| match variant.precision() {
                Precision::F32 => cpu::render::<f32>(s),
                Precision::F64 => cpu::render::<f64>(s),
            };
            let image = render(&s);
            let mut times: Vec<f64> = (0..runs)
                .map(|_| {
                    let t = Instant::now();
                    let _ = render(&s);
                    t.elapsed().as_secs_f64()
                })
                .collect();
            let m = median(&mut times);
            (
                image,
                Timing {
                    median_s: m,
                    rays_per_s: rays / m,
                    ..Timing::default()
                },
                None,
            )
        }
    };
    let error = figures(&image, reference).expect("same size");
    let flip = flip_mean(&image, reference);
    let m = Measurement {
        variant,
        max_depth: s.max_depth,
        samples: s.samples,
        error,
        flip_mean: flip,
        time,
        setup,
        pareto: false,
    };
    Ok((m, image))
}

/// Marks the measurements that no other beats on both time and rmse.
pub fn mark_pareto(ms: &mut [Measurement]) {
    let points: Vec<(f64, f64)> = ms.iter().map(|m| (m.time.median_s, m.error.rmse)).collect();
    for (i, m) in ms.iter_mut().enumerate() {
        let (t, e) = points[i];
        m.pareto = !points
            .iter()
            .enumerate()
            .any(|(j, &(tj, ej))| j != i && tj <= t && ej <= e && (tj < t || ej < e));
    }
}

/// A PSNR with `digits` decimals and its unit, or "inf" (the images agree).
fn psnr(db: f64, digits: usize, unit: &str) -> String {
    if db.is_finite() {
        format!("{db:.digits$}{unit}")
    } else {
        "inf".to_owned()
    }
}
