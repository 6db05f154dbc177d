//! `glint report`: every variant of every scene, its error against the CPU
//! f64 reference and its run time, written as tables, a plot and a page.

pub mod html;
pub mod svg;
pub mod tables;

use std::time::Instant;

use serde::Serialize;

use crate::cpu;
use crate::gpu::vk::device::DeviceInfo;
use crate::gpu::{GpuError, Intersect, Precision, RenderSettings, Renderer, SetupTimes};
use crate::raster::diff::{figures, ErrorFigures};
use crate::raster::{quantize, Image};
use crate::scene::Scene;

#[derive(Debug, Clone, Copy)]
pub struct Settings {
    /// Warm runs per variant; the median is reported.
    pub runs: usize,
    /// Also sweep max_depth and samples from 1 to the scene's own.
    pub sweeps: bool,
}

/// Medians over the warm runs, in seconds.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct Timing {
    pub median_s: f64,
    /// GPU only: the parts of the median run.
    pub upload_s: Option<f64>,
    pub dispatch_s: Option<f64>,
    pub readback_s: Option<f64>,
    /// Primary rays (pixels x samples²) per second at the median.
    pub rays_per_s: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct Measurement {
    pub variant: String,
    pub backend: &'static str,
    pub precision: &'static str,
    pub intersect: Option<Intersect>,
    pub max_depth: u32,
    pub samples: u32,
    pub error: ErrorFigures,
    /// Mean LDR-FLIP error (0: identical, 1: as different as can be) of the
    /// sRGB-encoded 8-bit images.
    pub flip_mean: f64,
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
            self.variant.clone(),
            format!("{:.4} s", self.time.median_s),
            parts,
            format!("{:.2}", self.time.rays_per_s / 1e6),
            self.setup.map_or(String::new(), |x| {
                format!("{:.3} s", x.compile_s + x.pipeline_s)
            }),
            format!("{:.2e}", e.max_abs),
            format!("{:.2e}", e.rmse),
            if e.psnr_db.is_finite() {
                format!("{:.1} dB", e.psnr_db)
            } else {
                "inf".to_owned()
            },
            format!("{:.4}%", 100.0 * e.frac_over_1_255),
            e.nonfinite.to_string(),
            format!("{:.2e}", self.flip_mean),
        ]
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct SceneReport {
    pub name: String,
    pub width: u32,
    pub height: u32,
    pub samples: u32,
    pub max_depth: u32,
    pub measurements: Vec<Measurement>,
    /// Not serialized: the images for the page.
    #[serde(skip)]
    pub images: SceneImages,
}

#[derive(Debug, Clone, Default)]
pub struct SceneImages {
    pub gpu: Option<Image>,
    pub reference: Option<Image>,
    pub srgb: bool,
}

#[derive(Debug, Clone, Serialize)]
pub struct Machine {
    pub cpu: String,
    pub threads: usize,
    pub os: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct Report {
    pub machine: Machine,
    pub device: DeviceInfo,
    /// Opening the Vulkan device, once.
    pub device_s: f64,
    pub runs: usize,
    pub scenes: Vec<SceneReport>,
}

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
fn escape(s: &str) -> String {
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
        let bytes: Vec<u8> = img
            .pixels
            .iter()
            .flat_map(|p| p.map(|c| quantize(c, true)))
            .collect();
        nv_flip::FlipImageRgb8::with_data(img.width, img.height, &bytes)
    };
    let map = nv_flip::flip(
        to8(reference),
        to8(image),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    f64::from(nv_flip::FlipPool::from_image(&map).mean())
}

/// What one variant renders with.
#[derive(Clone, Copy)]
enum Backend {
    Gpu(Intersect),
    Gpu64,
    /// The generic shader, to show what the scene's own variant saves.
    GpuGeneric,
    Cpu32,
    Cpu64,
}

/// Measures every variant of `scene`; `progress` is called once per variant.
pub fn measure(
    renderer: &mut Renderer,
    scene: &Scene,
    name: &str,
    settings: Settings,
    progress: &dyn Fn(&str),
) -> Result<SceneReport, GpuError> {
    let reference = cpu::render::<f64>(scene);
    let mut variants: Vec<(String, Backend, u32, u32)> = vec![
        (
            "gpu f32 robust".into(),
            Backend::Gpu(Intersect::Robust),
            scene.max_depth,
            scene.samples,
        ),
        (
            "gpu f32 naive".into(),
            Backend::Gpu(Intersect::Naive),
            scene.max_depth,
            scene.samples,
        ),
        (
            "cpu f32".into(),
            Backend::Cpu32,
            scene.max_depth,
            scene.samples,
        ),
        (
            "cpu f64".into(),
            Backend::Cpu64,
            scene.max_depth,
            scene.samples,
        ),
    ];
    if renderer.device_info().shader_float64 {
        variants.insert(
            2,
            (
                "gpu f64".into(),
                Backend::Gpu64,
                scene.max_depth,
                scene.samples,
            ),
        );
    }
    variants.push((
        "gpu f32 generic".into(),
        Backend::GpuGeneric,
        scene.max_depth,
        scene.samples,
    ));
    if settings.sweeps {
        for d in 1..scene.max_depth {
            variants.push((
                format!("gpu f32 depth {d}"),
                Backend::Gpu(Intersect::Robust),
                d,
                scene.samples,
            ));
        }
        for s in 1..scene.samples {
            variants.push((
                format!("gpu f32 samples {s}"),
                Backend::Gpu(Intersect::Robust),
                scene.max_depth,
                s,
            ));
        }
    }
    let mut measurements = Vec::new();
    let mut images = SceneImages {
        reference: Some(reference.clone()),
        srgb: scene.srgb,
        ..SceneImages::default()
    };
    for (variant, backend, max_depth, samples) in variants {
        progress(&variant);
        let mut s = scene.clone();
        s.max_depth = max_depth;
        s.samples = samples;
        let rays = s.ray_count() as f64;
        let (image, time, setup) = match backend {
            Backend::Gpu(_) | Backend::Gpu64 | Backend::GpuGeneric => {
                let (form, precision) = match backend {
                    Backend::Gpu(form) => (form, Precision::F32),
                    Backend::Gpu64 => (Intersect::Robust, Precision::F64),
                    _ => (Intersect::Robust, Precision::F32),
                };
                let how = RenderSettings {
                    intersect: form,
                    precision,
                    generic: matches!(backend, Backend::GpuGeneric),
                    ..renderer.settings()
                };
                let setup = renderer.prepare_with(&s, &how)?;
                let (image, _) = renderer.render_with(&s, &how, &|_| {})?; // warm-up, untimed
                let mut runs: Vec<(f64, crate::gpu::RenderTimes)> = Vec::new();
                for _ in 0..settings.runs {
                    let t = renderer.render_with(&s, &how, &|_| {})?.1;
                    runs.push((t.total_s(), t));
                }
                runs.sort_by(|a, b| a.0.total_cmp(&b.0));
                let (m, parts) = runs[runs.len() / 2];
                let time = Timing {
                    median_s: m,
                    upload_s: Some(parts.upload_s),
                    dispatch_s: Some(parts.dispatch_s),
                    readback_s: Some(parts.readback_s),
                    rays_per_s: rays / m,
                };
                (image, time, Some(setup))
            }
            Backend::Cpu32 | Backend::Cpu64 => {
                let render = |s: &Scene| match backend {
                    Backend::Cpu32 => cpu::render::<f32>(s),
                    _ => cpu::render::<f64>(s),
                };
                let image = render(&s);
                let mut times: Vec<f64> = (0..settings.runs)
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
        let error = figures(&image, &reference).expect("same size");
        let flip = flip_mean(&image, &reference);
        if variant == "gpu f32 robust" {
            images.gpu = Some(image);
        }
        let (backend_name, precision, intersect) = match backend {
            Backend::Gpu(form) => ("gpu", "f32", Some(form)),
            Backend::Gpu64 => ("gpu", "f64", Some(Intersect::Robust)),
            Backend::GpuGeneric => ("gpu", "f32", Some(Intersect::Robust)),
            Backend::Cpu32 => ("cpu", "f32", None),
            Backend::Cpu64 => ("cpu", "f64", None),
        };
        measurements.push(Measurement {
            variant,
            backend: backend_name,
            precision,
            intersect,
            max_depth,
            samples,
            error,
            flip_mean: flip,
            time,
            setup,
            pareto: false,
        });
    }
    mark_pareto(&mut measurements);
    Ok(SceneReport {
        name: name.to_owned(),
        width: scene.width,
        height: scene.height,
        samples: scene.samples,
        max_depth: scene.max_depth,
        measurements,
        images,
    })
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
