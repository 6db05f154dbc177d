//! Renders: the GPU's `Renderer` and its prepared scenes, the CPU
//! reference, and the wait that keeps Python's threads and Ctrl-C alive
//! while either runs.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::RecvTimeoutError;
use std::sync::Arc;
use std::time::{Duration, Instant};

use numpy::PyArray3;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use serde_json::json;

use glint::accel::Accel;
use glint::cpu;
use glint::raster::region::Region;
use glint::raster::Image;
use glint::settings::{Choice, Precision};
use glint::stats::Counts;

use crate::errors::{self, guard, panic_words};
use crate::image::to_numpy;
use crate::scene::Scene;

/// A render's image and, where asked for, its stats as JSON.
pub type Rendered<'py> = (Bound<'py, PyArray3<f32>>, Option<String>);

/// A region as Python gives it: `(x, y, width, height)`.
type RegionArg = Option<(u32, u32, u32, u32)>;

/// How often a waiting call looks for Ctrl-C: a render stops before its
/// next tile (GPU) or row (CPU) once the flag is set.
const POLL: Duration = Duration::from_millis(20);

/// Runs `job` on a thread of its own while this one waits without the GIL
/// (other Python threads run), looking for a signal every [`POLL`]. On
/// Ctrl-C it sets `stop`, waits for the job to stop and raises
/// `KeyboardInterrupt`; a panic in the job is `glint.Error`.
pub fn interruptible<T: Send>(
    py: Python<'_>,
    stop: &AtomicBool,
    job: impl FnOnce() -> PyResult<T> + Send,
) -> PyResult<T> {
    interruptible_with(py, stop, None, job)
}

/// A render's `progress=`: the Python callable, called as
/// `progress(pixels_done, pixels)` on the waiting thread (with the GIL)
/// every [`POLL`] while the count moves, and once at the end; the count
/// the job adds to as tiles (GPU) or rows (CPU) finish.
pub struct Progress<'a, 'py> {
    pub call: &'a Bound<'py, PyAny>,
    pub done: &'a AtomicU64,
    pub total: u64,
}

/// As [`interruptible`], calling `progress` as the job's count moves. An
/// exception the callable raises stops the render and is raised.
pub fn interruptible_with<T: Send>(
    py: Python<'_>,
    stop: &AtomicBool,
    progress: Option<Progress<'_, '_>>,
    job: impl FnOnce() -> PyResult<T> + Send,
) -> PyResult<T> {
    let mut shown = u64::MAX;
    let mut show = |interrupted: &mut Option<PyErr>| {
        if let Some(p) = &progress {
            let done = p.done.load(Ordering::Relaxed);
            if done != shown && interrupted.is_none() {
                shown = done;
                if let Err(e) = p.call.call1((done, p.total)) {
                    stop.store(true, Ordering::Relaxed);
                    *interrupted = Some(e);
                }
            }
        }
    };
    stop.store(false, Ordering::Relaxed);
    let (finished, mut done_rx) = std::sync::mpsc::channel::<()>();
    std::thread::scope(|s| {
        // A panic is caught on the job's thread, where it happens; the
        // job's errors are lazy PyErrs, which need no GIL to be made.
        let handle = s.spawn(move || {
            let result = catch_unwind(AssertUnwindSafe(job));
            let _ = finished.send(());
            result
        });
        let mut interrupted = None;
        loop {
            // The wait ends the moment the job does, not at the next poll.
            let (waited, rx) = py.detach(move || (done_rx.recv_timeout(POLL), done_rx));
            done_rx = rx;
            if !matches!(waited, Err(RecvTimeoutError::Timeout)) {
                break;
            }
            if interrupted.is_none() {
                if let Err(e) = py.check_signals() {
                    stop.store(true, Ordering::Relaxed);
                    interrupted = Some(e);
                }
            }
            show(&mut interrupted);
        }
        let done = handle.join().expect("the job catches its own panics");
        if done.as_ref().is_ok_and(|r| r.is_ok()) {
            show(&mut interrupted);
        }
        if let Some(e) = interrupted {
            return Err(e);
        }
        match done {
            Ok(result) => result,
            Err(payload) => Err(errors::Error::new_err(format!(
                "internal error (a bug in glint; please report it): {}",
                panic_words(&*payload)
            ))),
        }
    })
}

/// The precision a keyword names, by the names the command line takes.
fn precision(p: &str) -> PyResult<Precision> {
    Precision::named(p).ok_or_else(|| {
        let names: Vec<String> = Precision::ALL
            .iter()
            .map(|(_, n, _)| format!("{n:?}"))
            .collect();
        PyValueError::new_err(format!(
            "precision {p:?}: glint renders in {}",
            names.join(" or ")
        ))
    })
}

fn region(r: RegionArg) -> Option<Region> {
    r.map(|(x, y, width, height)| Region {
        x,
        y,
        width,
        height,
    })
}

/// Ray counts as `glint render --stats` writes them.
fn counts_json(counts: Option<&Counts>) -> serde_json::Value {
    match counts {
        Some(c) => json!({ "rays": c.rays(), "tests": c.tests(), "by_ray": c.by_ray() }),
        None => json!({ "rays": null, "tests": null, "by_ray": null }),
    }
}

fn merge(mut a: serde_json::Value, b: serde_json::Value) -> String {
    if let (Some(a), serde_json::Value::Object(b)) = (a.as_object_mut(), b) {
        a.extend(b);
    }
    a.to_string()
}

/// The CPU reference: `glint.render(scene, backend="cpu")`.
#[pyfunction]
#[pyo3(signature = (scene, precision="f32", region=None, stats=false, progress=None))]
pub fn render_cpu<'py>(
    py: Python<'py>,
    scene: &Scene,
    precision: &str,
    region: RegionArg,
    stats: bool,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<Rendered<'py>> {
    let precision = self::precision(precision)?;
    let name = precision.name();
    let region = self::region(region);
    guard(|| {
        let scene = &scene.inner;
        cpu::bound::check(scene).map_err(errors::other)?;
        let (w, h) = region.map_or((scene.width, scene.height), |r| (r.width, r.height));
        glint::raster::memory::check_render(w, h).map_err(errors::memory)?;
        if let Some(r) = region {
            r.within(scene.width, scene.height).map_err(errors::value)?;
        }
        let stop = Arc::new(AtomicBool::new(false));
        // Rows as they finish, counted in pixels as the GPU's tiles are.
        let done = AtomicU64::new(0);
        let shown = progress.as_ref().map(|call| Progress {
            call,
            done: &done,
            total: u64::from(w) * u64::from(h),
        });
        let (image, stats) = interruptible_with(py, &stop, shown, || {
            fn go<R: cpu::Real>(
                scene: &glint::scene::Scene,
                region: Option<Region>,
                counted: bool,
                stop: &Arc<AtomicBool>,
                rows: &(dyn Fn(u64) + Sync),
            ) -> (Image, Option<Counts>, f64, f64, f64) {
                let t0 = Instant::now();
                let mut prepared = cpu::Prepared::<R>::new(scene, Accel::Auto);
                prepared.stop_when(stop.clone());
                let setup_s = t0.elapsed().as_secs_f64();
                let t1 = Instant::now();
                let (image, counts) = match region {
                    Some(r) if counted => {
                        let (image, counts) = prepared.render_region_counted(r, rows);
                        (image, Some(counts))
                    }
                    Some(r) => (prepared.render_region(r, rows), None),
                    None if counted => {
                        let (image, counts) = prepared.render_counted(rows);
                        (image, Some(counts))
                    }
                    None => (prepared.render(rows), None),
                };
                (
                    image,
                    counts,
                    setup_s,
                    prepared.tables_s(),
                    t1.elapsed().as_secs_f64(),
                )
            }
            let rows = |n: u64| {
                done.fetch_add(n * u64::from(w), Ordering::Relaxed);
            };
            let (image, counts, setup, tables, trace) = match precision {
                Precision::F64 => go::<f64>(scene, region, stats, &stop, &rows),
                Precision::F32 => go::<f32>(scene, region, stats, &stop, &rows),
            };
            let stats = stats.then(|| {
                merge(
                    json!({
                        "backend": "cpu",
                        "precision": name,
                        "seconds": { "setup": setup, "tables": tables, "trace": trace },
                    }),
                    counts_json(counts.as_ref()),
                )
            });
            Ok((image, stats))
        })?;
        scene.within(&image, name).map_err(errors::other)?;
        Ok((to_numpy(py, image)?, stats))
    })
}

#[cfg(feature = "gpu")]
mod gpu_side {
    use super::*;
    use std::path::PathBuf;
    use std::sync::Mutex;

    use glint::gpu::{self, GpuOptions, RenderSettings};

    /// What `include=` may be: folders, or file names and their text.
    #[derive(FromPyObject)]
    pub enum Include {
        Texts(std::collections::BTreeMap<String, String>),
        Dir(PathBuf),
        Dirs(Vec<PathBuf>),
    }

    /// A Vulkan device, opened once, and the pipelines compiled on it.
    #[pyclass(module = "glint", name = "Renderer", frozen)]
    pub struct Renderer {
        inner: Mutex<gpu::Renderer>,
        /// A dict's shader files, written out for the compiler; removed
        /// with the renderer.
        _texts: Option<tempfile::TempDir>,
        device: String,
        /// Whether a render's stats have counted the device's opening:
        /// the first render through this renderer counts it, later ones
        /// spent nothing on it (issue 60: every render of a prepared scene
        /// counted it again).
        device_counted: Arc<AtomicBool>,
    }

    fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
        // A render that panicked left nothing half-done that a later
        // one reads: the device's work is waited on within each call.
        m.lock().unwrap_or_else(|p| p.into_inner())
    }

    #[pymethods]
    impl Renderer {
        #[new]
        #[pyo3(signature = (device=None, include=None, defines=None, validate=None, timeout=None, cache=true))]
        fn new(
            py: Python<'_>,
            device: Option<String>,
            include: Option<Include>,
            defines: Option<std::collections::BTreeMap<String, Option<String>>>,
            validate: Option<bool>,
            timeout: Option<f64>,
            cache: bool,
        ) -> PyResult<Self> {
            guard(|| {
                let mut opts = GpuOptions::from_env(device);
                if let Some(v) = validate {
                    opts.validate = v;
                }
                // The binary's own caches of SPIR-V and pipelines, unless
                // cache=False (its --no-cache).
                if cache {
                    opts.cache_dir = GpuOptions::default_cache_dir();
                }
                if let Some(t) = timeout {
                    if !(t.is_finite() && t > 0.0 && t <= 1e6) {
                        return Err(PyValueError::new_err(format!(
                            "timeout {t}: must be in (0, 1e6] seconds"
                        )));
                    }
                    opts.timeout = Some(Duration::from_secs_f64(t));
                }
                opts.defines = defines.unwrap_or_default().into_iter().collect();
                // As the binary refuses -D and -I (issue 57, defect 4).
                for (name, value) in &opts.defines {
                    gpu::check_define(name, value.as_deref())
                        .map_err(|e| PyValueError::new_err(format!("defines: {name:?}: {e}")))?;
                }
                let mut texts = None;
                match include {
                    None => {}
                    Some(Include::Dir(d)) => opts.include_dirs = vec![d],
                    Some(Include::Dirs(ds)) => opts.include_dirs = ds,
                    Some(Include::Texts(files)) => {
                        let dir = tempfile::Builder::new()
                            .prefix("glint-shaders-")
                            .tempdir()
                            .map_err(errors::other)?;
                        for (name, text) in &files {
                            let ok = !name.is_empty()
                                && !name.contains('/')
                                && name != "."
                                && name != "..";
                            if !ok {
                                return Err(PyValueError::new_err(format!(
                                    "include: {name:?} is not a shader file's name (no folders)"
                                )));
                            }
                            std::fs::write(dir.path().join(name), text).map_err(errors::other)?;
                        }
                        opts.include_dirs = vec![dir.path().to_owned()];
                        texts = Some(dir);
                    }
                }
                for dir in &opts.include_dirs {
                    gpu::check_include_dir(dir)
                        .map_err(|e| PyValueError::new_err(format!("include: {e}")))?;
                }
                let inner = py
                    .detach(|| gpu::Renderer::new(&opts))
                    .map_err(errors::gpu)?;
                let device = inner.device_info().name.clone();
                Ok(Self {
                    inner: Mutex::new(inner),
                    _texts: texts,
                    device,
                    device_counted: Arc::new(AtomicBool::new(false)),
                })
            })
        }

        /// The device's name.
        #[getter]
        fn device(&self) -> &str {
            &self.device
        }

        #[pyo3(signature = (scene, precision="f32", stats=false))]
        fn prepare(
            &self,
            py: Python<'_>,
            scene: &Scene,
            precision: &str,
            stats: bool,
        ) -> PyResult<PreparedScene> {
            let settings = self.settings(precision, stats)?;
            guard(|| {
                let stop = Arc::new(AtomicBool::new(false));
                let mut prepared = interruptible(py, &stop, || {
                    lock(&self.inner)
                        .prepare(&scene.inner, &settings)
                        .map_err(errors::gpu)
                })?;
                prepared.stop_when(stop.clone());
                Ok(PreparedScene {
                    inner: Mutex::new(prepared),
                    stop,
                    device: self.device.clone(),
                    device_counted: self.device_counted.clone(),
                    scene: (scene.inner.width, scene.inner.height),
                    counted: stats,
                    precision: settings.precision.name(),
                })
            })
        }

        #[pyo3(signature = (scene, precision="f32", region=None, stats=false, progress=None))]
        fn render<'py>(
            &self,
            py: Python<'py>,
            scene: &Scene,
            precision: &str,
            region: RegionArg,
            stats: bool,
            progress: Option<Bound<'py, PyAny>>,
        ) -> PyResult<Rendered<'py>> {
            let prepared = self.prepare(py, scene, precision, stats)?;
            prepared.render(py, region, stats, progress)
        }

        /// `glint explain`'s record of pixel (x, y) of `scene` (`sample`:
        /// that one alone, else each in turn): a JSON list, one entry a
        /// sample, with its table and verdict as the binary prints them.
        #[pyo3(signature = (scene, pixel, sample=None))]
        fn explain(
            &self,
            py: Python<'_>,
            scene: &Scene,
            pixel: (u32, u32),
            sample: Option<u32>,
        ) -> PyResult<String> {
            use glint::explain::{check_renders, explain_on_gpu, samples, ExplainError};
            let refused = |e: ExplainError| match e {
                ExplainError::Outside { .. } | ExplainError::Sample { .. } => errors::value(e),
                ExplainError::Gpu(e) => errors::gpu(e),
                _ => errors::other(e),
            };
            guard(|| {
                let chosen = samples(&scene.inner, pixel, sample).map_err(refused)?;
                let stop = Arc::new(AtomicBool::new(false));
                interruptible(py, &stop, || {
                    let mut renderer = lock(&self.inner);
                    let settings = renderer.settings();
                    let mut explained = Vec::new();
                    for s in &chosen {
                        explained.push(
                            explain_on_gpu(&mut renderer, &scene.inner, &settings, *s, Vec::new())
                                .map_err(refused)?,
                        );
                    }
                    check_renders(&mut renderer, &scene.inner, &settings, &mut explained)
                        .map_err(refused)?;
                    let mut out = Vec::new();
                    for e in explained {
                        out.push(json!({
                            "explanation": e,
                            "table": e.table,
                            "verdict": e.verdict(),
                        }));
                    }
                    serde_json::to_string(&out).map_err(errors::other)
                })
            })
        }

        fn __repr__(&self) -> String {
            format!("<glint.Renderer on {:?}>", self.device)
        }
    }

    impl Renderer {
        fn settings(&self, precision: &str, count: bool) -> PyResult<RenderSettings> {
            let mut settings = lock(&self.inner).settings();
            settings.precision = super::precision(precision)?;
            settings.count = count;
            Ok(settings)
        }
    }

    /// A scene on the device: renders again without compiling or uploading.
    #[pyclass(module = "glint", name = "PreparedScene", frozen)]
    pub struct PreparedScene {
        inner: Mutex<gpu::Prepared>,
        stop: Arc<AtomicBool>,
        device: String,
        device_counted: Arc<AtomicBool>,
        scene: (u32, u32),
        counted: bool,
        precision: &'static str,
    }

    #[pymethods]
    impl PreparedScene {
        #[pyo3(signature = (region=None, stats=false, progress=None))]
        pub fn render<'py>(
            &self,
            py: Python<'py>,
            region: RegionArg,
            stats: bool,
            progress: Option<Bound<'py, PyAny>>,
        ) -> PyResult<Rendered<'py>> {
            let region = super::region(region);
            if let Some(r) = region {
                // As the CPU's: ValueError, not glint.Error (issue 57).
                r.within(self.scene.0, self.scene.1)
                    .map_err(errors::value)?;
            }
            let (w, h) = region.map_or(self.scene, |r| (r.width, r.height));
            glint::raster::memory::check_render(w, h).map_err(super::errors::memory)?;
            guard(|| {
                let done = AtomicU64::new(0);
                let shown = progress.as_ref().map(|call| Progress {
                    call,
                    done: &done,
                    total: u64::from(w) * u64::from(h),
                });
                let (rendered, call_s) = interruptible_with(py, &self.stop, shown, || {
                    let mut prepared = lock(&self.inner);
                    let t0 = Instant::now();
                    let tiles = |pixels: u64| {
                        done.fetch_add(pixels, Ordering::Relaxed);
                    };
                    let rendered = prepared.render(region, &tiles).map_err(errors::gpu)?;
                    Ok((rendered, t0.elapsed().as_secs_f64()))
                })?;
                let gpu::Rendered {
                    image,
                    times,
                    counts,
                    ..
                } = rendered;
                let device_s = if self.device_counted.swap(true, Ordering::Relaxed) {
                    0.0
                } else {
                    times.setup.device_s
                };
                let stats = stats.then(|| {
                    let variant = lock(&self.inner).variant().name();
                    merge(
                        json!({
                            "backend": "gpu",
                            "device": self.device,
                            "precision": self.precision,
                            "variant": variant,
                            "times": times,
                            "seconds": {
                                "setup": device_s + times.setup.compile_s
                                    + times.setup.pipeline_s + times.setup.driver_compile_s
                                    + times.bvh_s,
                                "tables": times.tables_s,
                                "trace": times.total_s(),
                                "call": call_s,
                            },
                            "compiled": times.setup.compile_s > 0.0 || times.setup.pipeline_s > 0.0,
                        }),
                        counts_json(counts.as_ref()),
                    )
                });
                Ok((to_numpy(py, image)?, stats))
            })
        }

        /// Width and height of the image it renders.
        #[getter]
        fn size(&self) -> (u32, u32) {
            self.scene
        }

        /// Whether its renders count rays (it was prepared with stats=True).
        #[getter]
        fn counted(&self) -> bool {
            self.counted
        }

        fn __repr__(&self) -> String {
            format!(
                "<glint.PreparedScene {}x{} {} on {:?}>",
                self.scene.0, self.scene.1, self.precision, self.device
            )
        }
    }

    #[pyfunction]
    pub fn devices_json(py: Python<'_>) -> PyResult<String> {
        guard(|| {
            // No driver, or no loader: no devices, as a listing says it
            // (issue 60); a driver that fails otherwise still raises.
            let devices = match py.detach(gpu::list_devices) {
                Err(gpu::GpuError::NoDevice | gpu::GpuError::NoLoader(_)) => Vec::new(),
                listed => listed.map_err(errors::gpu)?,
            };
            serde_json::to_string(&devices).map_err(errors::other)
        })
    }
}

#[cfg(feature = "gpu")]
pub use gpu_side::{devices_json, PreparedScene, Renderer};

#[cfg(not(feature = "gpu"))]
mod cpu_only {
    use super::*;

    /// In a build without the GPU renderer: a class whose construction
    /// raises `DeviceError` with the binary's words.
    #[pyclass(module = "glint", name = "Renderer", frozen)]
    pub struct Renderer;

    #[pymethods]
    impl Renderer {
        #[new]
        #[pyo3(signature = (*_args, **_kwargs))]
        fn new(
            _args: &Bound<'_, pyo3::types::PyTuple>,
            _kwargs: Option<&Bound<'_, pyo3::types::PyDict>>,
        ) -> PyResult<Self> {
            Err(errors::unbuilt("glint.Renderer"))
        }
    }

    /// Never made in this build; listed so that the module's names are
    /// the same in both.
    #[pyclass(module = "glint", name = "PreparedScene", frozen)]
    pub struct PreparedScene;

    #[pyfunction]
    pub fn devices_json() -> PyResult<String> {
        Err(errors::unbuilt("glint.devices"))
    }
}

#[cfg(not(feature = "gpu"))]
pub use cpu_only::{devices_json, PreparedScene, Renderer};
