//! The renderer: a Vulkan device, and the shader sources, SPIR-V and
//! pipelines its scenes were compiled with. It keeps nothing of a scene:
//! `prepare` turns one into a [`Prepared`] that owns its buffers.

use std::sync::{Arc, Mutex};
use std::time::Instant;

use super::compile;
use super::layout::Uploads;
use super::options::{GpuOptions, RenderSettings};
use super::prepared::Prepared;
use super::shared::Shared;
use super::times::RenderTimes;
use super::variant::Variant;
use super::vk::bounded::{bounded, OPEN_LIMIT};
use super::vk::device::{Device, DeviceInfo};
use super::vk::instance::Instance;
use super::vk::pipeline_cache::PipelineCache;
use super::GpuError;
use crate::raster::Image;
use crate::scene::Scene;

/// The GPU renderer: a Vulkan device, and the pipelines of the shader
/// variants its scenes needed so far.
///
/// ```no_run
/// use glint::gpu::{GpuOptions, Rendered, Renderer};
/// use glint::raster::{diff, io};
/// use glint::scene::{Overrides, Scene};
///
/// let scene = Scene::load("scenes/seed-fig5.toml".as_ref(), &Overrides::default())?;
/// let mut gpu = Renderer::new(&GpuOptions::from_env(None))?;
/// // Compile and upload once; render as often as needed.
/// let mut prepared = gpu.prepare(&scene, &gpu.settings())?;
/// let Rendered { image, times, .. } = prepared.render(None, &|_pixels| {})?;
/// let reference = glint::cpu::render::<f64>(&scene);
/// let error = diff::figures(&image, &reference)?;
/// println!("rmse {:.2e} in {:.3} s", error.rmse, times.total_s());
/// io::write("out.png".as_ref(), &image, scene.srgb)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct Renderer {
    shared: Arc<Shared>,
}

impl Renderer {
    /// Opens the device `opts` names (or the best one) and prepares to
    /// render; no shader is compiled until a scene needs one.
    pub fn new(opts: &GpuOptions) -> Result<Self, GpuError> {
        opts.check()?;
        let t0 = Instant::now();
        let (validate, wanted) = (opts.validate, opts.device.clone());
        let device = bounded(OPEN_LIMIT, move || {
            Device::open(Instance::new(validate)?, wanted.as_deref())
        })?;
        let cache_file = opts
            .cache_dir
            .as_ref()
            .map(|d| d.join(format!("pipelines-{}.sealed", device.info.cache_id())));
        let pipeline_cache = PipelineCache::new(&device, cache_file.as_deref())?;
        let stage_uploads = opts
            .stage_uploads
            .unwrap_or_else(|| device.has_private_memory());
        let shared = Shared {
            pipelines: Mutex::default(),
            pipeline_cache,
            sources: compile::Sources {
                dirs: opts.include_dirs.clone(),
                main: opts.main_shader.clone(),
                main_builtin: opts.main_builtin.clone(),
                generated: Vec::new(),
            },
            defines: opts.defines.clone(),
            cache_dir: opts.cache_dir.as_ref().map(|d| d.join("spirv")),
            spec_worst: opts.spec_worst,
            settings: opts.settings,
            device_s: t0.elapsed().as_secs_f64(),
            timeout: opts.timeout,
            stage_uploads,
            device,
        };
        shared.check_validation()?;
        Ok(Self {
            shared: Arc::new(shared),
        })
    }

    /// Whether the shader runs as the least precise conformant driver may
    /// (`GpuOptions::spec_worst`).
    pub fn spec_worst(&self) -> bool {
        self.shared.spec_worst
    }

    /// What the renderer's device is and supports.
    pub fn device_info(&self) -> &DeviceInfo {
        &self.shared.device.info
    }

    /// The settings `render` uses (`GpuOptions::settings`).
    pub fn settings(&self) -> RenderSettings {
        self.shared.settings
    }

    /// Seconds spent opening the device, once.
    pub fn device_s(&self) -> f64 {
        self.shared.device_s
    }

    /// Lays `scene` out for the device under `settings`, compiles the
    /// shader variant it needs (once per variant) and uploads it: a
    /// prepared scene, which renders any region of the image as often as
    /// asked.
    pub fn prepare(
        &mut self,
        scene: &Scene,
        settings: &RenderSettings,
    ) -> Result<Prepared, GpuError> {
        Prepared::new(&self.shared, scene, settings)
    }

    /// Renders the whole of `scene` with the renderer's settings, calling
    /// `progress(pixels)` as tiles finish: `prepare`, then one render.
    pub fn render(
        &mut self,
        scene: &Scene,
        progress: &dyn Fn(u64),
    ) -> Result<(Image, RenderTimes), GpuError> {
        let settings = self.settings();
        let rendered = self.prepare(scene, &settings)?.render(None, progress)?;
        Ok((rendered.image, rendered.times))
    }

    /// The user's shader files that replace one of glint's recording ones
    /// and record nothing (`compile::Sources::unrecording`).
    pub fn unrecording(&self) -> Vec<String> {
        self.shared.sources.unrecording()
    }

    /// The variant `prepare` would compile `scene` with under `settings`,
    /// and its defines (the user's last), without compiling it: `glint
    /// shader dump`'s source.
    pub fn variant(
        &self,
        scene: &Scene,
        settings: &RenderSettings,
    ) -> (Variant, Vec<(String, Option<String>)>) {
        let traced = scene.corner_grid();
        let scene = traced.as_ref().unwrap_or(scene);
        let up = Uploads::new(
            scene,
            settings.intersect,
            settings.precision,
            settings.accel,
        );
        self.shared.variant(scene, settings, &up, settings.count)
    }
}

#[cfg(test)]
impl Renderer {
    /// How many pipelines the renderer keeps.
    pub(crate) fn pipelines(&self) -> usize {
        self.shared.pipelines.lock().unwrap().len()
    }
}
