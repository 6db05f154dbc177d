//! The GPU's side of the module: `Renderer`, a device opened once, and
//! `PreparedScene`, a scene on it, which follows its scene's changes
//! (`Scene.params`) by updating in place or preparing again.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use serde_json::json;

use glint::gpu::{self, GpuOptions, RenderSettings};
use glint::settings::Choice;

use crate::errors::{self, guard};
use crate::image::to_numpy;
use crate::render::{
    counts_json, interruptible, interruptible_with, merge, precision as precision_of,
    region as region_of, Progress, RegionArg, Rendered,
};
use crate::scene::Scene;

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
    /// Shared with the scenes prepared on it, which prepare again on it
    /// when their scene needs another shader.
    inner: Arc<Mutex<gpu::Renderer>>,
    /// The scene `render` prepared last, by its id and the settings it
    /// was prepared under: rendered again, or updated, where `render` is
    /// given that scene again (a notebook's sweep).
    last: Mutex<Option<(LastKey, Py<PreparedScene>)>>,
    /// A dict's shader files, written out for the compiler; removed
    /// with the renderer.
    _texts: Option<tempfile::TempDir>,
    device: String,
    /// Whether a render's stats have counted the device's opening: the
    /// first render through this renderer counts it, later ones spent
    /// nothing on it (every render of a prepared scene counted it
    /// again).
    device_counted: Arc<AtomicBool>,
}

/// What `Renderer.render` keeps its last prepared scene by: the scene's
/// id, the precision's name, whether it counts, and whether it gives AOVs.
type LastKey = (u64, &'static str, bool, bool);

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
            // As the binary refuses -D and -I.
            for (name, value) in &opts.defines {
                gpu::check_define(name, value.as_deref()).map_err(|e| {
                    PyValueError::new_err(format!(
                        "defines: {:?}: {e}",
                        glint::printable::text(name)
                    ))
                })?;
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
                        let ok =
                            !name.is_empty() && !name.contains('/') && name != "." && name != "..";
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
            let inner =
                crate::gil::detach(py, || gpu::Renderer::new(&opts)).map_err(errors::gpu)?;
            let device = inner.device_info().name.clone();
            Ok(Self {
                inner: Arc::new(Mutex::new(inner)),
                last: Mutex::new(None),
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
        scene: Py<Scene>,
        precision: &str,
        stats: bool,
    ) -> PyResult<PreparedScene> {
        self.prepare_with(py, scene, precision, stats, false)
    }

    /// Renders `scene`: prepared on the first call, then rendered again
    /// from the device (updated in place where its values changed) while
    /// the calls are of the same scene, precision and stats.
    #[pyo3(signature = (scene, precision="f32", region=None, stats=false, progress=None, aovs=None))]
    #[allow(clippy::too_many_arguments)]
    fn render<'py>(
        &self,
        py: Python<'py>,
        scene: Py<Scene>,
        precision: &str,
        region: RegionArg,
        stats: bool,
        progress: Option<Bound<'py, PyAny>>,
        aovs: Option<Vec<String>>,
    ) -> PyResult<Rendered<'py>> {
        let asked = crate::aovs::asked(aovs)?;
        if asked.is_some() {
            crate::aovs::check_sampling(&scene.get().scene())?;
        }
        let key = (
            scene.get().id,
            precision_of(precision)?.name(),
            stats,
            asked.is_some(),
        );
        let (kept, last_key) = {
            let last = lock(&self.last);
            let kept = last
                .as_ref()
                .filter(|(k, _)| *k == key)
                .map(|(_, p)| p.clone_ref(py));
            (kept, last.as_ref().map(|(k, _)| *k))
        };
        let prepared = match kept {
            Some(p) => p,
            None => {
                // The last scene's buffers go before the next one's are made.
                *lock(&self.last) = None;
                let fresh = self.prepare_with(py, scene, precision, stats, asked.is_some())?;
                // Its first render says why it was prepared (a render of
                // this scene with other settings kept none to update).
                *lock(&fresh.note) = Some(why_prepared(last_key, key));
                let p = Py::new(py, fresh)?;
                *lock(&self.last) = Some((key, p.clone_ref(py)));
                p
            }
        };
        prepared
            .get()
            .render_with(py, region, stats, progress, asked.as_deref())
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
        sample: Option<Bound<'_, PyAny>>,
    ) -> PyResult<String> {
        let sample = crate::keywords::optional(sample.as_ref(), "sample", 0, u32::MAX)?;
        use glint::explain::{check_renders, explain_on_gpu, samples, ExplainError};
        let refused = |e: ExplainError| match e {
            ExplainError::Outside { .. } | ExplainError::Sample { .. } => errors::value(e),
            ExplainError::Gpu(e) => errors::gpu(e),
            _ => errors::other(e),
        };
        let scene = scene.scene();
        guard(|| {
            let chosen = samples(&scene, pixel, sample).map_err(refused)?;
            let stop = Arc::new(AtomicBool::new(false));
            interruptible(py, &stop, || {
                let mut renderer = lock(&self.inner);
                let settings = renderer.settings();
                let mut explained = Vec::new();
                for s in &chosen {
                    explained.push(
                        explain_on_gpu(&mut renderer, &scene, &settings, *s, Vec::new())
                            .map_err(refused)?,
                    );
                }
                check_renders(&mut renderer, &scene, &settings, &mut explained).map_err(refused)?;
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
    /// `prepare`, compiling the AOV variant where `aovs`.
    fn prepare_with(
        &self,
        py: Python<'_>,
        scene: Py<Scene>,
        precision: &str,
        stats: bool,
        aovs: bool,
    ) -> PyResult<PreparedScene> {
        let mut settings = self.settings(precision, stats)?;
        settings.aovs = aovs;
        guard(|| {
            let stop = Arc::new(AtomicBool::new(false));
            let (now, generation) = scene.get().current();
            let prepared = interruptible(py, &stop, || {
                lock(&self.inner)
                    .prepare(&now, &settings)
                    .map_err(errors::gpu)
            });
            log_cache_notices(py)?;
            let mut prepared = prepared?;
            prepared.stop_when(stop.clone());
            Ok(PreparedScene {
                inner: Mutex::new(Held {
                    prepared,
                    generation,
                }),
                scene,
                renderer: self.inner.clone(),
                settings,
                stop,
                device: self.device.clone(),
                device_counted: self.device_counted.clone(),
                note: Mutex::new(None),
            })
        })
    }

    fn settings(&self, precision: &str, count: bool) -> PyResult<RenderSettings> {
        let mut settings = lock(&self.inner).settings();
        settings.precision = precision_of(precision)?;
        settings.count = count;
        Ok(settings)
    }
}

/// A scene on the device: renders again without compiling or uploading,
/// and follows its scene's changes (`Scene.params`): in place where the
/// shader it has can render them, else prepared again.
#[pyclass(module = "glint", name = "PreparedScene", frozen)]
pub struct PreparedScene {
    inner: Mutex<Held>,
    scene: Py<Scene>,
    renderer: Arc<Mutex<gpu::Renderer>>,
    settings: RenderSettings,
    stop: Arc<AtomicBool>,
    device: String,
    device_counted: Arc<AtomicBool>,
    /// How its first render's scene was taken, where `Renderer.render`
    /// prepared it: its `stats["update"]`.
    note: Mutex<Option<String>>,
}

/// What the caches repaired (a damaged SPIR-V entry compiled again and
/// replaced), each to the `glint` logger at INFO, as the binary prints it.
fn log_cache_notices(py: Python<'_>) -> PyResult<()> {
    let notices = gpu::sealed::notices();
    if notices.is_empty() {
        return Ok(());
    }
    let logger = py
        .import("logging")?
        .call_method1("getLogger", ("glint",))?;
    for n in notices {
        logger.call_method1("info", (n,))?;
    }
    Ok(())
}

/// Why `Renderer.render` prepared a scene rather than render the one it
/// kept (`last`): the first render of it here, or one with other settings.
fn why_prepared(last: Option<LastKey>, now: LastKey) -> String {
    let Some(last) = last.filter(|l| l.0 == now.0) else {
        return "prepared: the first render of this scene on this renderer".to_owned();
    };
    let mut other = Vec::new();
    if last.1 != now.1 {
        other.push(format!("precision {:?}", last.1));
    }
    if last.2 != now.2 {
        other.push(format!("stats={}", if last.2 { "True" } else { "False" }));
    }
    if last.3 != now.3 {
        other.push(if last.3 { "AOVs" } else { "no AOVs" }.to_owned());
    }
    format!(
        "prepared: the last render of this scene here had {}",
        other.join(", ")
    )
}

/// The scene on the device, and the generation of its scene it shows.
struct Held {
    prepared: gpu::Prepared,
    generation: u64,
}

impl Held {
    /// Takes `now`, its scene's generation `generation`, where it shows
    /// another: in place, or prepared again on `renderer`. Says which.
    fn follow(
        &mut self,
        now: &glint::scene::Scene,
        generation: u64,
        renderer: &Mutex<gpu::Renderer>,
        settings: &RenderSettings,
        stop: &Arc<AtomicBool>,
    ) -> PyResult<Option<String>> {
        if generation == self.generation {
            return Ok(None);
        }
        let said = match self.prepared.update(now).map_err(errors::gpu)? {
            gpu::Update::InPlace => "updated in place".to_owned(),
            gpu::Update::Prepare(why) => {
                let mut fresh = lock(renderer).prepare(now, settings).map_err(errors::gpu)?;
                fresh.stop_when(stop.clone());
                self.prepared = fresh;
                format!("prepared again: {why}")
            }
        };
        self.generation = generation;
        Ok(Some(said))
    }
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
        self.render_with(py, region, stats, progress, None)
    }

    /// Width and height of the image it renders (its scene's, as last
    /// rendered).
    #[getter]
    fn size(&self) -> (u32, u32) {
        lock(&self.inner).prepared.size()
    }

    /// Whether its renders count rays (it was prepared with stats=True).
    #[getter]
    fn counted(&self) -> bool {
        self.settings.count
    }

    fn __repr__(&self) -> String {
        let (w, h) = self.size();
        format!(
            "<glint.PreparedScene {w}x{h} {} on {:?}>",
            self.settings.precision.name(),
            self.device
        )
    }
}

impl PreparedScene {
    /// `render`, with the AOVs `names` where it was prepared to give them.
    fn render_with<'py>(
        &self,
        py: Python<'py>,
        region: RegionArg,
        stats: bool,
        progress: Option<Bound<'py, PyAny>>,
        names: Option<&[&str]>,
    ) -> PyResult<Rendered<'py>> {
        let region = region_of(region);
        let (now, generation) = self.scene.get().current();
        if let Some(r) = region {
            // As the CPU's: ValueError, not glint.Error.
            r.within(now.width, now.height).map_err(errors::value)?;
        }
        let (w, h) = region.map_or((now.width, now.height), |r| (r.width, r.height));
        glint::raster::memory::check_render(w, h).map_err(errors::memory)?;
        guard(|| {
            let done = AtomicU64::new(0);
            let shown = progress.as_ref().map(|call| Progress {
                call,
                done: &done,
                total: u64::from(w) * u64::from(h),
            });
            let (rendered, call_s, followed) = interruptible_with(py, &self.stop, shown, || {
                let mut held = lock(&self.inner);
                let t0 = Instant::now();
                let followed = held
                    .follow(&now, generation, &self.renderer, &self.settings, &self.stop)?
                    .or_else(|| lock(&self.note).take());
                let tiles = |pixels: u64| {
                    done.fetch_add(pixels, Ordering::Relaxed);
                };
                let rendered = held.prepared.render(region, &tiles).map_err(errors::gpu)?;
                Ok((rendered, t0.elapsed().as_secs_f64(), followed))
            })?;
            let gpu::Rendered {
                image,
                times,
                counts,
                aovs,
                ..
            } = rendered;
            log_cache_notices(py)?;
            let compiled = times.setup.compile_s > 0.0 || times.setup.pipeline_s > 0.0;
            if let Some(said) = followed
                .as_deref()
                .filter(|s| s.starts_with("prepared again"))
            {
                // A change that needed more than new values says so.
                let compiling = if compiled { ", compiled a shader" } else { "" };
                py.import("logging")?
                    .call_method1("getLogger", ("glint",))?
                    .call_method1(
                        "info",
                        (format!("{}: {said}{compiling}", self.scene.get().source),),
                    )?;
            }
            let device_s = if self.device_counted.swap(true, Ordering::Relaxed) {
                0.0
            } else {
                times.setup.device_s
            };
            let stats = stats.then(|| {
                let variant = lock(&self.inner).prepared.variant().name();
                merge(
                    json!({
                        "backend": "gpu",
                        "device": self.device,
                        "precision": self.settings.precision.name(),
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
                        "compiled": compiled,
                        "update": followed,
                    }),
                    counts_json(counts.as_ref()),
                )
            });
            let values = match (names, aovs) {
                (Some(names), Some(values)) => Some(crate::aovs::arrays(
                    py,
                    names,
                    &values,
                    (image.width, image.height),
                )?),
                _ => None,
            };
            Ok((to_numpy(py, image)?, stats, values))
        })
    }
}

#[pyfunction]
pub fn devices_json(py: Python<'_>) -> PyResult<String> {
    guard(|| {
        // No driver, or no loader: no devices, as a listing says it; a
        // driver that fails otherwise still raises.
        let devices = match crate::gil::detach(py, gpu::list_devices) {
            Err(gpu::GpuError::NoDevice | gpu::GpuError::NoLoader(_)) => Vec::new(),
            listed => listed.map_err(errors::gpu)?,
        };
        serde_json::to_string(&devices).map_err(errors::other)
    })
}
