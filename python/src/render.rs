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
use pyo3::types::PyDict;
use serde_json::json;

use glint::accel::Accel;
use glint::aov::Aov;
use glint::cpu;
use glint::raster::region::Region;
use glint::raster::Image;
use glint::settings::{Choice, Precision};
use glint::stats::Counts;

use crate::errors::{self, guard, panic_words};
use crate::image::to_numpy;
use crate::scene::Scene;

/// A render's image and, where asked for, its stats as JSON and its AOVs
/// by name.
pub type Rendered<'py> = (
    Bound<'py, PyArray3<f32>>,
    Option<String>,
    Option<Bound<'py, PyDict>>,
);

/// A region as Python gives it: `(x, y, width, height)`.
pub(crate) type RegionArg = Option<(u32, u32, u32, u32)>;

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
            let (waited, rx) =
                crate::gil::detach(py, move || (done_rx.recv_timeout(POLL), done_rx));
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
pub(crate) fn precision(p: &str) -> PyResult<Precision> {
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

pub(crate) fn region(r: RegionArg) -> Option<Region> {
    r.map(|(x, y, width, height)| Region {
        x,
        y,
        width,
        height,
    })
}

/// Ray counts as `glint render --stats` writes them.
pub(crate) fn counts_json(counts: Option<&Counts>) -> serde_json::Value {
    match counts {
        Some(c) => json!({ "rays": c.rays(), "tests": c.tests(), "by_ray": c.by_ray() }),
        None => json!({ "rays": null, "tests": null, "by_ray": null }),
    }
}

pub(crate) fn merge(mut a: serde_json::Value, b: serde_json::Value) -> String {
    if let (Some(a), serde_json::Value::Object(b)) = (a.as_object_mut(), b) {
        a.extend(b);
    }
    a.to_string()
}

/// The CPU reference: `glint.render(scene, backend="cpu")`.
#[pyfunction]
#[pyo3(signature = (scene, precision="f32", region=None, stats=false, progress=None, aovs=None))]
pub fn render_cpu<'py>(
    py: Python<'py>,
    scene: &Scene,
    precision: &str,
    region: RegionArg,
    stats: bool,
    progress: Option<Bound<'py, PyAny>>,
    aovs: Option<Vec<String>>,
) -> PyResult<Rendered<'py>> {
    let precision = self::precision(precision)?;
    let name = precision.name();
    let region = self::region(region);
    let asked = crate::aovs::asked(aovs)?;
    guard(|| {
        let scene = scene.scene();
        let scene = &*scene;
        if asked.is_some() {
            crate::aovs::check_sampling(scene)?;
        }
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
        let with_aovs = asked.is_some();
        let (image, stats, values) = interruptible_with(py, &stop, shown, || {
            type Done = (Image, Option<Counts>, Option<Vec<Aov>>, f64, f64, f64);
            fn go<R: cpu::Real>(
                scene: &glint::scene::Scene,
                region: Option<Region>,
                (counted, aovs): (bool, bool),
                stop: &Arc<AtomicBool>,
                rows: &(dyn Fn(u64) + Sync),
            ) -> Done {
                let t0 = Instant::now();
                let mut prepared = cpu::Prepared::<R>::new(scene, Accel::Auto);
                prepared.stop_when(stop.clone());
                let setup_s = t0.elapsed().as_secs_f64();
                let t1 = Instant::now();
                let (image, counts, values) = match region {
                    _ if aovs && counted => {
                        let (image, values, counts) = prepared.render_aovs_counted(region, rows);
                        (image, Some(counts), Some(values))
                    }
                    _ if aovs => {
                        let (image, values) = prepared.render_aovs(region, rows);
                        (image, None, Some(values))
                    }
                    Some(r) if counted => {
                        let (image, counts) = prepared.render_region_counted(r, rows);
                        (image, Some(counts), None)
                    }
                    Some(r) => (prepared.render_region(r, rows), None, None),
                    None if counted => {
                        let (image, counts) = prepared.render_counted(rows);
                        (image, Some(counts), None)
                    }
                    None => (prepared.render(rows), None, None),
                };
                (
                    image,
                    counts,
                    values,
                    setup_s,
                    prepared.tables_s(),
                    t1.elapsed().as_secs_f64(),
                )
            }
            let rows = |n: u64| {
                done.fetch_add(n * u64::from(w), Ordering::Relaxed);
            };
            let how = (stats, with_aovs);
            let (image, counts, values, setup, tables, trace) = match precision {
                Precision::F64 => go::<f64>(scene, region, how, &stop, &rows),
                Precision::F32 => go::<f32>(scene, region, how, &stop, &rows),
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
            Ok((image, stats, values))
        })?;
        scene.within(&image, name).map_err(errors::other)?;
        let size = (image.width, image.height);
        let values = match (&asked, values) {
            (Some(names), Some(values)) => Some(crate::aovs::arrays(py, names, &values, size)?),
            _ => None,
        };
        Ok((to_numpy(py, image)?, stats, values))
    })
}

#[cfg(feature = "gpu")]
pub use crate::renderer::{devices_json, PreparedScene, Renderer};

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
