//! What `glint bench` measures beyond a render's time: the device's ceiling
//! for the ray–sphere test (shaders/ceiling.comp), against which a scene's
//! achieved tests per second are read (docs/performance.md, The bench).

use std::path::Path;
use std::time::Duration;

use crate::gpu::{GpuError, GpuOptions, Renderer};
use crate::scene::{parse, Overrides};

/// Sphere tests per invocation of the ceiling shader (its CEILING_TESTS).
pub const CEILING_TESTS: u64 = 8192;

/// The ceiling: tests in one dispatch and the seconds it took.
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct Ceiling {
    /// Sphere tests the dispatch made.
    pub tests: u64,
    /// Its time on the device (or the host's, where the queue has no timestamps).
    pub seconds: f64,
}

impl Ceiling {
    /// The rate: the most tests a second this device makes.
    pub fn tests_per_s(&self) -> f64 {
        self.tests as f64 / self.seconds
    }
}

/// Runs the ceiling shader over `size`×`size` invocations, with the
/// intersection forms and precision of `options`, `runs` times after one
/// warm-up (lavapipe compiles at the first dispatch); the fastest run.
pub fn ceiling(options: &GpuOptions, size: u32, runs: usize) -> Result<Ceiling, GpuError> {
    let text = format!(
        "[image]\nwidth = {size}\nheight = {size}\n[render]\nmax_depth = 1\n\
         [camera]\neye = [0.0, 0.0, 0.0]\nlook_at = [0.0, 0.0, -1.0]\nvfov = 40.0\n\
         [materials.m]\ndiffuse = [1.0, 1.0, 1.0]\n\
         [[spheres]]\ncenter = [0.0, 0.0, -6.0]\nradius = 1.0\nmaterial = \"m\"\n"
    );
    let scene = parse(&text, Path::new("(ceiling)"), &Overrides::default())
        .expect("the ceiling's scene is valid");
    let options = GpuOptions {
        main_shader: None,
        main_builtin: Some("ceiling.comp".to_owned()),
        // The tile timeout counts a scene's rays, not these tests.
        timeout: Some(Duration::from_secs(600)),
        // The ceiling shader is a megakernel of its own.
        settings: crate::gpu::RenderSettings {
            schedule: crate::gpu::Schedule::Megakernel,
            ..options.settings
        },
        ..options.clone()
    };
    let mut renderer = Renderer::new(&options)?;
    let mut prepared = renderer.prepare(&scene, &options.settings)?;
    let tests = u64::from(size) * u64::from(size) * CEILING_TESTS;
    let mut best = f64::INFINITY;
    for run in 0..=runs {
        let crate::gpu::Rendered { image, times, .. } = prepared.render(None, &|_| {})?;
        // The sums are finite: a test that went wrong would show.
        if image.pixels.iter().flatten().any(|v| !v.is_finite()) {
            return Err(GpuError::Shader(
                "the ceiling shader wrote a non-finite value".into(),
            ));
        }
        if run > 0 {
            best = best.min(times.dispatch_s);
        }
    }
    Ok(Ceiling {
        tests,
        seconds: best,
    })
}

/// The CPU seconds this process's threads have run, where the system says
/// (Linux's /proc/self/task/*/schedstat, in nanoseconds). On a device that
/// is the CPU (lavapipe), the difference across a render is the render's
/// work, which varies less than its wall time on a shared machine:
/// `glint bench --json` reports it beside the wall time.
pub fn process_cpu_s() -> Option<f64> {
    let mut total = 0u64;
    for task in std::fs::read_dir("/proc/self/task").ok()? {
        let Ok(task) = task else { continue };
        // A thread that ended since the listing is no longer counted.
        let Ok(stat) = std::fs::read_to_string(task.path().join("schedstat")) else {
            continue;
        };
        total += stat.split_whitespace().next()?.parse::<u64>().ok()?;
    }
    Some(total as f64 * 1e-9)
}
