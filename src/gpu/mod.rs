//! The GPU renderer: the model of docs/scene-format.md (Rays, Shading) as a
//! Vulkan compute shader, one invocation per pixel, large images in tiles.

mod access;
pub mod compile;
mod error;
pub(crate) mod generated;
pub(crate) mod layout;
mod macros;
pub mod schedule;
pub mod variant;
pub(crate) mod vk;

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use ash::vk as raw;
use glam::UVec4;

use crate::accel::Accel;
use crate::base::interface::Array;
pub use crate::base::{Precision, WORKGROUP};
use crate::raster::region::Region;
use crate::raster::Image;
use crate::scene::Scene;
use crate::stats::{Counter, Counts};
pub use error::GpuError;
use layout::{TileRect, Uploads};
pub use schedule::Schedule;
use variant::{Block, Variant};
use vk::buffer::Buffer;
use vk::command::{memory_barrier, Completed, OneShot};
use vk::device::Device;
pub use vk::device::DeviceInfo;
use vk::instance::Instance;
use vk::pipeline::{ComputePipeline, Resource};
use vk::pipeline_cache::PipelineCache;
use vk::query::Timestamps;
use vk::texel_view::TexelBuffer;

/// Rays per dispatch at most: small enough that no single dispatch runs long
/// enough to trip a desktop GPU's watchdog, large enough to fill one.
const RAYS_PER_DISPATCH: u64 = 1 << 22;
/// The word the output tile is filled with before each dispatch: a NaN.
const UNWRITTEN: u32 = 0xffff_ffff;
/// The most a tile's wavefront paths may take of device memory.
const PATH_BYTES: u64 = 256 << 20;

/// Which ray/primitive intersection forms the shader uses.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, serde::Serialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Intersect {
    /// Camera-relative coordinates, the stable sphere roots with an exact
    /// power term, and secondary rays that know which surface they left.
    #[default]
    Robust,
    /// The textbook forms with a fixed epsilon of 1e-4, in world coordinates.
    Naive,
}

/// How a [`Renderer`] is made: the device, validation, the shader files and
/// defines, the caches, and the settings of [`Renderer::render`].
#[derive(Debug, Clone, Default)]
pub struct GpuOptions {
    /// Pick the first device whose name contains this.
    pub device: Option<String>,
    /// Enable the Khronos validation layer and fail on any message.
    pub validate: bool,
    /// Directories searched for shader files ahead of the built-in ones.
    pub include_dirs: Vec<PathBuf>,
    /// A main shader to use instead of main.comp.
    pub main_shader: Option<PathBuf>,
    /// A built-in shader to use instead of main.comp (`glint bench` runs
    /// `ceiling.comp`).
    pub main_builtin: Option<String>,
    /// Defines added after the variant's own (-D NAME=VALUE).
    pub defines: Vec<(String, Option<String>)>,
    /// The settings of `Renderer::render`; `render_with` takes others.
    pub settings: RenderSettings,
    /// Where compiled SPIR-V and the Vulkan pipeline cache are kept between
    /// runs; None: compile every time.
    pub cache_dir: Option<PathBuf>,
    /// The longest wait for one tile; None: derived from the tile's work
    /// (`tile_timeout`).
    pub timeout: Option<Duration>,
    /// Upload the scene through a staging buffer into device-local memory
    /// the host does not map. None: where the device has such memory (a
    /// discrete GPU); GLINT_STAGE_UPLOADS=1 or 0 sets it.
    pub stage_uploads: Option<bool>,
}

impl GpuOptions {
    /// Validation is also switched on by GLINT_VALIDATION=1 (the tests set it).
    pub fn from_env(device: Option<String>) -> Self {
        let validate = std::env::var("GLINT_VALIDATION").is_ok_and(|v| v == "1");
        let stage_uploads = std::env::var("GLINT_STAGE_UPLOADS").ok().map(|v| v == "1");
        Self {
            device,
            stage_uploads,
            validate,
            ..Self::default()
        }
    }

    /// The platform's cache directory with `glint` in it: on Linux
    /// $XDG_CACHE_HOME/glint, or ~/.cache/glint.
    pub fn default_cache_dir() -> Option<PathBuf> {
        directories::BaseDirs::new().map(|d| d.cache_dir().join("glint"))
    }
}

/// How one render is done. A value per call: `Renderer::render_with`
/// takes one, `Renderer::render` the renderer's own (`GpuOptions::settings`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub struct RenderSettings {
    /// The intersection forms.
    pub intersect: Intersect,
    /// The shader's arithmetic.
    pub precision: Precision,
    /// Which primitives each ray tests: every one, or through a BVH.
    pub accel: Accel,
    /// Render with the one shader that handles every feature.
    pub generic: bool,
    /// How the rays are laid on the device.
    pub schedule: Schedule,
}

/// One-time costs, apart from any render: opening the device, and compiling
/// the scene's shader variant (or reading it from the SPIR-V cache) and
/// creating its pipeline; zero when the variant was already built.
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct SetupTimes {
    /// Opening the device (the renderer's, once).
    pub device_s: f64,
    /// Compiling the variant's shader, or reading its SPIR-V from the cache.
    pub compile_s: f64,
    /// Creating its pipeline.
    pub pipeline_s: f64,
    /// Whether the SPIR-V came from the cache.
    pub spirv_cached: bool,
    /// The pipeline's first dispatch, one workgroup that shades no pixel:
    /// where the driver compiles the shader to machine code (lavapipe runs
    /// LLVM there), bounded by `COMPILE_TIMEOUT` rather than the render's
    /// watchdog.
    pub driver_compile_s: f64,
}

/// The cost of one render.
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct RenderTimes {
    /// What this call spent compiling its variant and creating its
    /// pipeline (zero where an earlier call did); `device_s` is the
    /// renderer's, spent once when it was made.
    pub setup: SetupTimes,
    /// Building the BVH: a setup cost, apart from the render's total.
    pub bvh_s: f64,
    /// Laying the scene out (apart from the BVH) and uploading it.
    pub upload_s: f64,
    /// The dispatches, with their submissions and waits.
    pub dispatch_s: f64,
    /// Copying the tiles out of mapped memory into the image.
    pub readback_s: f64,
    /// The dispatches' own time on the device, from timestamp queries;
    /// None where its queue writes none. `dispatch_s` also holds the
    /// submission, the fill of the output and the wait.
    pub device_dispatch_s: Option<f64>,
}

impl RenderTimes {
    /// Upload, dispatch and readback: the render, without its setup.
    pub fn total_s(&self) -> f64 {
        self.upload_s + self.dispatch_s + self.readback_s
    }
}

/// The GPU renderer: a Vulkan device, and the pipelines of the shader
/// variants its scenes needed so far.
///
/// ```no_run
/// use glint::gpu::{GpuOptions, Renderer};
/// use glint::raster::{diff, io};
/// use glint::scene::{Overrides, Scene};
///
/// let scene = Scene::load("scenes/seed-fig5.toml".as_ref(), &Overrides::default())?;
/// let mut gpu = Renderer::new(&GpuOptions::from_env(None))?;
/// let (image, times) = gpu.render(&scene, &|_pixels| {})?;
/// let reference = glint::cpu::render::<f64>(&scene);
/// let error = diff::figures(&image, &reference)?;
/// println!("rmse {:.2e} in {:.3} s", error.rmse, times.total_s());
/// io::write("out.png".as_ref(), &image, scene.srgb)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// Field order is drop order: the pipelines and the buffers bound to them,
/// the pipeline cache and the commands go before the renderer's `Arc` of the
/// device. Each holds its own `Arc` as well, so the device (and after it the
/// instance) is destroyed after the last of them whatever the order.
pub struct Renderer {
    /// Keyed by the variant and the fingerprint of the shader sources, so
    /// that an edited shader file makes a new pipeline (`glint watch`),
    /// which replaces the variant's old one.
    pipelines: HashMap<PipelineKey, ComputePipeline>,
    /// The pipelines dispatched at least once, so compiled by the driver.
    driver_compiled: std::collections::HashSet<PipelineKey>,
    pipeline_cache: PipelineCache,
    /// The last render's buffers, which the next render of the same scene
    /// with the same pipeline uses again (`watch`, `report`, `compare`'s
    /// second render).
    resident: Option<Resident>,
    /// Where the device's queue writes timestamps.
    timestamps: Option<Timestamps>,
    commands: OneShot,
    device: Arc<Device>,
    sources: compile::Sources,
    defines: Vec<(String, Option<String>)>,
    cache_dir: Option<PathBuf>,
    /// The settings of `render`.
    settings: RenderSettings,
    /// Seconds spent opening the device.
    device_s: f64,
    timeout: Option<Duration>,
    /// Whether scene buffers are device-local, filled through staging.
    stage_uploads: bool,
    /// The last scene laid out, so that `variant_for`, `prepare_for` and
    /// `render` of one scene build its uploads (and its BVH) once.
    laid_out: std::cell::RefCell<Option<LaidOut>>,
}

/// Buffers bound to a pipeline's descriptor set, and what they hold.
/// A pipeline: its variant, and the hash of its shader's sources and defines.
type PipelineKey = (Variant, u64);

struct Resident {
    pipeline: PipelineKey,
    uploads: std::rc::Rc<Uploads>,
    tile: (u32, u32),
    /// In the variant's binding order; the output tile last.
    buffers: Vec<Bound>,
}

/// What one binding holds: a buffer, a texel buffer (a buffer seen
/// through its view), or a buffer read through its address (the binding's
/// uniform block holds the address).
enum Bound {
    Buffer(Buffer),
    Texels(TexelBuffer),
    Address { data: Buffer, address: Buffer },
}

impl Bound {
    fn buffer(&self) -> &Buffer {
        match self {
            Bound::Buffer(b) => b,
            Bound::Texels(t) => &t.buffer,
            Bound::Address { data, .. } => data,
        }
    }

    fn resource(&self) -> Resource {
        match self {
            Bound::Buffer(b) => Resource::Buffer(b.raw),
            Bound::Texels(t) => Resource::Texels(t.view),
            Bound::Address { address, .. } => Resource::Buffer(address.raw),
        }
    }
}

/// A scene's uploads and what they were built from.
struct LaidOut {
    scene: Scene,
    settings: (Intersect, Precision, Accel),
    uploads: std::rc::Rc<Uploads>,
}

/// The slowest rate glint expects of any device, in ray–primitive tests
/// (or BVH node visits) per second: a tenth of what lavapipe reached on 2
/// cores before the BVH. A tile's wait is its work at this rate, and at
/// least `MIN_TIMEOUT`.
const SLOWEST_TESTS_PER_S: f64 = 2e7;
const MIN_TIMEOUT: Duration = Duration::from_secs(10);

/// The longest wait for a driver's compile of one pipeline (its first
/// dispatch, which shades no pixel): lavapipe took up to 12 s for the f64
/// generic shader on 2 cores. Past it the device is taken to be hung.
pub const COMPILE_TIMEOUT: Duration = Duration::from_secs(300);

/// The longest wait for a tile of `pixels` of `scene`: its rays (samples,
/// bounces, a shadow ray a light) times the tests a ray makes (every object,
/// or about 64 node visits and 8 a doubling of the spheres through a BVH).
pub fn tile_timeout(scene: &Scene, pixels: u64, bvh: bool) -> Duration {
    let rays = pixels as f64
        * f64::from(scene.samples * scene.samples)
        * f64::from(scene.max_depth)
        * (1.0 + scene.lights.len() as f64);
    let objects = scene.prims.len().max(1) as f64;
    let unbounded = (scene.prims.len() - scene.prims.bounded_count()) as f64;
    let per_ray = if bvh {
        // A walk visits at most every node (2 a primitive) and tests every one.
        (64.0 + 8.0 * objects.log2()).min(3.0 * objects) + unbounded
    } else {
        objects
    };
    Duration::from_secs_f64(rays * per_ray / SLOWEST_TESTS_PER_S).max(MIN_TIMEOUT)
}

fn secs(d: Duration) -> f64 {
    d.as_secs_f64()
}

/// The counters' buffer as the counts, read once `done` has completed.
fn read_counts(buffer: &Buffer, done: &Completed) -> Counts {
    let words: &[[u32; 2]] = buffer.read(done, Counter::SLOTS);
    Counts::from_slots(std::array::from_fn(|i| {
        u64::from(words[i][1]) << 32 | u64::from(words[i][0])
    }))
}

/// The error of a tile whose pixel was not finished: alpha 1 means every
/// loop of the invocation ran to its end (shaders/budget.glsl), 0 that
/// they were cut short, NaN (the fill before each dispatch) that the
/// shader wrote nothing there. `(x0, y0, w)`: the tile's corner and width.
fn unfinished(tile: &[[f32; 4]], (x0, y0, w): (u32, u32, u32), device: &str) -> Option<GpuError> {
    let i = tile.iter().position(|s| s[3] != 1.0)?;
    let (x, y) = (x0 + i as u32 % w, y0 + i as u32 / w);
    Some(if tile[i][3].is_nan() {
        GpuError::Unwritten { x, y }
    } else {
        GpuError::LoopBudget {
            x,
            y,
            device: device.to_owned(),
        }
    })
}

impl Renderer {
    /// Opens the device `opts` names (or the best one) and prepares to
    /// render; no shader is compiled until a scene needs one.
    pub fn new(opts: &GpuOptions) -> Result<Self, GpuError> {
        if let Some((name, _)) = opts
            .defines
            .iter()
            .find(|(n, _)| compile::reserved_define(n))
        {
            return Err(GpuError::Unsupported(format!(
                "-D {name}: glint defines {name} itself for each scene (docs/shaders.md, Variants); \
                 choose another name"
            )));
        }
        let t0 = Instant::now();
        let instance = Instance::new(opts.validate)?;
        let device = Device::open(instance, opts.device.as_deref())?;
        let commands = OneShot::new(&device)?;
        let timestamps = Timestamps::new(&device)?;
        let device_has_private_memory = device.has_private_memory();
        let cache_file = opts
            .cache_dir
            .as_ref()
            .map(|d| d.join(format!("pipelines-{}.bin", device.info.cache_id())));
        let pipeline_cache = PipelineCache::new(&device, cache_file.as_deref())?;
        let renderer = Self {
            pipelines: HashMap::new(),
            driver_compiled: Default::default(),
            pipeline_cache,
            resident: None,
            timestamps,
            commands,
            device,
            sources: compile::Sources {
                dirs: opts.include_dirs.clone(),
                main: opts.main_shader.clone(),
                main_builtin: opts.main_builtin.clone(),
                generated: Vec::new(),
            },
            defines: opts.defines.clone(),
            cache_dir: opts.cache_dir.as_ref().map(|d| d.join("spirv")),
            settings: opts.settings,
            device_s: secs(t0.elapsed()),
            timeout: opts.timeout,
            stage_uploads: opts.stage_uploads.unwrap_or(device_has_private_memory),
            laid_out: std::cell::RefCell::new(None),
        };
        renderer.check_validation()?;
        Ok(renderer)
    }

    /// What the renderer's device is and supports.
    pub fn device_info(&self) -> &DeviceInfo {
        &self.device.info
    }

    /// The settings `render` uses.
    pub fn settings(&self) -> RenderSettings {
        self.settings
    }

    /// Seconds spent opening the device, once.
    pub fn device_s(&self) -> f64 {
        self.device_s
    }

    fn check_validation(&self) -> Result<(), GpuError> {
        let messages = self.device.instance().take_messages();
        if messages.is_empty() {
            Ok(())
        } else {
            Err(GpuError::Validation(messages))
        }
    }

    /// Tile size in pixels: within the rays-per-dispatch budget and the
    /// device's storage buffer range, whole rows where the image is narrow.
    fn tile_size(&self, scene: &Scene, variant: &Variant) -> (u32, u32) {
        let rays_per_pixel = u64::from(scene.samples * scene.samples);
        let range = u64::from(self.device.info.max_storage_buffer_range);
        let mut by_range = range / 16;
        if variant.wavefront {
            // The paths' buffers: within the range, and within PATH_BYTES.
            let (reals, words) = variant.path_bytes();
            let path = reals + words;
            by_range = by_range.min(range / path).min(PATH_BYTES / path);
        }
        let pixels = (RAYS_PER_DISPATCH / rays_per_pixel)
            .min(by_range)
            .max(u64::from(WORKGROUP * WORKGROUP));
        let width = scene.width.min(2048);
        let height = (pixels / u64::from(width)).clamp(1, u64::from(scene.height)) as u32;
        (width, height)
    }

    /// The variant `scene` renders with, and its defines (the user's last).
    pub fn variant_for(&self, scene: &Scene) -> (Variant, Vec<(String, Option<String>)>) {
        self.variant_with(scene, &self.settings)
    }

    /// As `variant_for`, with the given settings.
    pub fn variant_with(
        &self,
        scene: &Scene,
        settings: &RenderSettings,
    ) -> (Variant, Vec<(String, Option<String>)>) {
        self.variant_of(
            scene,
            settings,
            &self.uploads(scene, settings).0,
            false,
            None,
        )
    }

    /// `scene`'s uploads under `settings`, built or reused from the last
    /// call, and the seconds this call spent laying them out, apart from
    /// the BVH's build (`Uploads::bvh_s`).
    fn uploads(&self, scene: &Scene, settings: &RenderSettings) -> (std::rc::Rc<Uploads>, f64) {
        let key = (settings.intersect, settings.precision, settings.accel);
        let mut cache = self.laid_out.borrow_mut();
        if let Some(l) = cache.as_ref() {
            if l.settings == key && l.scene == *scene {
                return (l.uploads.clone(), 0.0);
            }
        }
        let t0 = Instant::now();
        let uploads = std::rc::Rc::new(Uploads::new(scene, key.0, key.1, key.2));
        let layout_s = secs(t0.elapsed()) - uploads.bvh_s;
        *cache = Some(LaidOut {
            scene: scene.clone(),
            settings: key,
            uploads: uploads.clone(),
        });
        (uploads, layout_s)
    }

    /// As `variant_with`, with the scene's uploads already built; `refine`:
    /// adaptive sampling's second pass (`Variant::refine`).
    fn variant_of(
        &self,
        scene: &Scene,
        settings: &RenderSettings,
        uploads: &Uploads,
        count: bool,
        refine: Option<(u64, u32)>,
    ) -> (Variant, Vec<(String, Option<String>)>) {
        let mut variant = Variant::for_scene(
            scene,
            uploads,
            settings.intersect,
            settings.precision,
            &self.device.info,
            settings.generic,
            count,
        );
        variant.refine = refine;
        // The refinement's list is the megakernel's alone; so is a shader
        // of the user's, which knows nothing of the wavefront's stages.
        variant.wavefront = refine.is_none()
            && self.sources.main_is_glints()
            && settings.schedule.wavefront_for(scene);
        let mut defines = variant.defines();
        defines.extend(self.defines.iter().cloned());
        (variant, defines)
    }

    /// Compiles the variant's shader and creates its pipeline, once per
    /// variant and version of the sources. Returns the pipeline's key and
    /// what this call cost (nothing where the variant was built before).
    fn prepare(
        &mut self,
        variant: &Variant,
        defines: &[(String, Option<String>)],
    ) -> Result<(PipelineKey, SetupTimes), GpuError> {
        let sources = self.sources.for_variant(variant);
        let fingerprint = sources.fingerprint();
        let key = (variant.clone(), fingerprint);
        let mut setup = SetupTimes {
            device_s: self.device_s,
            ..SetupTimes::default()
        };
        if self.pipelines.contains_key(&key) {
            return Ok((key, setup));
        }
        let t0 = Instant::now();
        let (spirv, cached) =
            compile::compile_cached(&sources, fingerprint, defines, self.cache_dir.as_deref())?;
        let t1 = Instant::now();
        let push_bytes = std::mem::size_of::<TileRect>() as u32;
        let pipeline = ComputePipeline::new(
            &self.device,
            &spirv,
            &variant.descriptor_layout(),
            push_bytes,
            self.pipeline_cache.raw,
        )?;
        setup.compile_s = secs(t1 - t0);
        setup.pipeline_s = secs(t1.elapsed());
        setup.spirv_cached = cached;
        // An edit's pipeline replaces the variant's old one; the buffers
        // bound to the old one's descriptor set go with it (the device is
        // idle between renders).
        if self
            .resident
            .as_ref()
            .is_some_and(|r| r.pipeline.0 == key.0)
        {
            self.resident = None;
        }
        self.pipelines.retain(|(v, _), _| *v != key.0);
        self.driver_compiled.retain(|(v, _)| *v != key.0);
        self.pipelines.insert(key.clone(), pipeline);
        self.check_validation()?;
        Ok((key, setup))
    }

    /// Compiles what `scene` needs without rendering it, so that a timed
    /// render measures the render alone. Returns what this call cost: zero
    /// compile and pipeline times where the variant was built before.
    pub fn prepare_for(&mut self, scene: &Scene) -> Result<SetupTimes, GpuError> {
        self.prepare_with(scene, &self.settings.clone())
    }

    /// As `prepare_for`, with the given settings.
    pub fn prepare_with(
        &mut self,
        scene: &Scene,
        settings: &RenderSettings,
    ) -> Result<SetupTimes, GpuError> {
        let (variant, defines) = self.variant_with(scene, settings);
        Ok(self.prepare(&variant, &defines)?.1)
    }

    /// Renders `scene` with the renderer's settings, calling
    /// `progress(pixels)` as tiles finish.
    pub fn render(
        &mut self,
        scene: &Scene,
        progress: &dyn Fn(u64),
    ) -> Result<(Image, RenderTimes), GpuError> {
        self.render_with(scene, &self.settings.clone(), progress)
    }

    /// Renders `scene` with `settings`, calling `progress(pixels)` as tiles finish.
    pub fn render_with(
        &mut self,
        scene: &Scene,
        settings: &RenderSettings,
        progress: &dyn Fn(u64),
    ) -> Result<(Image, RenderTimes), GpuError> {
        let whole = Region::whole(scene.width, scene.height);
        let (image, times, _) =
            self.render_maybe_counted(scene, settings, whole, false, progress)?;
        Ok((image, times))
    }

    /// The pixels of `region` of `scene`'s image, with the renderer's
    /// settings: bit for bit those of the whole render (docs/scale-out.md).
    pub fn render_region(
        &mut self,
        scene: &Scene,
        region: Region,
        progress: &dyn Fn(u64),
    ) -> Result<(Image, RenderTimes), GpuError> {
        let region = region
            .within(scene.width, scene.height)
            .map_err(|e| GpuError::Unsupported(e.to_string()))?;
        let settings = self.settings;
        let (image, times, _) =
            self.render_maybe_counted(scene, &settings, region, false, progress)?;
        Ok((image, times))
    }

    /// As `render`, with the shader's counts of rays, tests and BVH nodes
    /// (src/stats.rs); the counting variant is compiled for it.
    pub fn render_counted(
        &mut self,
        scene: &Scene,
        progress: &dyn Fn(u64),
    ) -> Result<(Image, RenderTimes, Counts), GpuError> {
        let settings = self.settings;
        let whole = Region::whole(scene.width, scene.height);
        let (image, times, counts) =
            self.render_maybe_counted(scene, &settings, whole, true, progress)?;
        Ok((image, times, counts.expect("a counting render counts")))
    }

    /// Renders `region` of `scene` (inside it), counting where `count`:
    /// lays the scene out, builds its variant, makes its buffers resident,
    /// lets the driver compile, then dispatches the tiles.
    fn render_maybe_counted(
        &mut self,
        scene: &Scene,
        settings: &RenderSettings,
        region: Region,
        count: bool,
        progress: &dyn Fn(u64),
    ) -> Result<(Image, RenderTimes, Option<Counts>), GpuError> {
        self.check_can_render(settings)?;
        if let Some(grid) = scene.corner_grid() {
            let first =
                self.render_maybe_counted(&grid, settings, region.corners(), count, progress)?;
            return match scene.adaptive_sampling() {
                None => Ok((first.0.corner_mean(), first.1, first.2)),
                Some(a) => self.refine(&grid, settings, a, region, first, count),
            };
        }
        // Laying the scene out counts as upload (where this call did it), but
        // not the compiles; the BVH build is reported apart.
        let (up, layout_s) = self.uploads(scene, settings);
        let (variant, defines) = self.variant_of(scene, settings, &up, count, None);
        let (key, setup) = self.prepare(&variant, &defines)?;
        let mut times = RenderTimes {
            setup,
            device_dispatch_s: self.timestamps.as_ref().map(|_| 0.0),
            ..RenderTimes::default()
        };
        let t0 = Instant::now();
        if variant.reads == access::Form::Storage {
            let info = &self.device.info;
            up.check_storage_range(
                info.max_storage_buffer_range,
                info.max_texel_buffer_elements,
            )
            .map_err(GpuError::Unsupported)?;
        }
        let tile = self.tile_size(scene, &variant);
        self.make_resident(&key, &variant, &up, tile, None)?;
        times.upload_s = layout_s + secs(t0.elapsed());
        times.bvh_s = up.bvh_s;
        times.setup.driver_compile_s = self.compile_on_driver(&key)?;
        let (pixels, counts) = self.dispatch_tiles(
            scene, &key, &variant, region, tile, 1.0, &mut times, progress,
        )?;
        self.check_validation()?;
        Ok((
            Image::new(region.width, region.height, pixels),
            times,
            counts,
        ))
    }

    /// Adaptive sampling's second pass: the pixels of `region` whose
    /// corners (`first`'s image of its corners, traced from `grid`) differ by
    /// more than the threshold, refined as one list in the image's order
    /// (shaders/adaptive.glsl); the others are their corners' mean. The
    /// first pass's times and counts join this one's.
    fn refine(
        &mut self,
        grid: &Scene,
        settings: &RenderSettings,
        adaptive: crate::scene::Adaptive,
        region: Region,
        first: (Image, RenderTimes, Option<Counts>),
        count: bool,
    ) -> Result<(Image, RenderTimes, Option<Counts>), GpuError> {
        let (corners, mut times, counts) = first;
        let mut image = corners.corner_mean();
        // The corner image's pixel (x, y) is the top-left corner of the
        // region's pixel (x, y); the list holds the image's coordinates.
        let (mut list, mut at) = (Vec::new(), Vec::new());
        for y in 0..image.height {
            for x in 0..image.width {
                let c = corners.corners_of(x, y);
                if adaptive.splits(&c) {
                    list.push(layout::refine::Values {
                        c00: c[0],
                        x: region.x + x,
                        c10: c[1],
                        y: region.y + y,
                        c01: c[2],
                        pad0: 0,
                        c11: c[3],
                        pad1: 0,
                    });
                    at.push((y * image.width + x) as usize);
                }
            }
        }
        if list.is_empty() {
            return Ok((image, times, counts));
        }
        let n = list.len() as u32;
        let entries = crate::base::interface::array(list.into_iter(), Precision::F32);
        let (up, _) = self.uploads(grid, settings);
        let refine = Some((adaptive.threshold_steps().to_bits(), adaptive.levels));
        let (variant, defines) = self.variant_of(grid, settings, &up, count, refine);
        let (key, setup) = self.prepare(&variant, &defines)?;
        times.setup.compile_s += setup.compile_s;
        times.setup.pipeline_s += setup.pipeline_s;
        let width = variant::REFINE_WIDTH.min(n);
        let entries_region = Region::whole(width, n.div_ceil(width));
        let per_entry = adaptive.most_rays_per_pixel();
        let rows = (RAYS_PER_DISPATCH as f64 / (per_entry * f64::from(width))) as u32;
        let tile = (width, rows.clamp(1, entries_region.height));
        let t0 = Instant::now();
        self.make_resident(&key, &variant, &up, tile, Some(&entries))?;
        times.upload_s += secs(t0.elapsed());
        times.setup.driver_compile_s += self.compile_on_driver(&key)?;
        let mut second = RenderTimes {
            device_dispatch_s: times.device_dispatch_s.map(|_| 0.0),
            ..RenderTimes::default()
        };
        let (pixels, second_counts) = self.dispatch_tiles(
            grid,
            &key,
            &variant,
            entries_region,
            tile,
            per_entry,
            &mut second,
            &|_| {},
        )?;
        self.check_validation()?;
        // These buffers hold this list alone: the next render binds anew.
        self.resident = None;
        times.dispatch_s += second.dispatch_s;
        times.readback_s += second.readback_s;
        if let (Some(t), Some(s)) = (&mut times.device_dispatch_s, second.device_dispatch_s) {
            *t += s;
        }
        for (p, colour) in at.into_iter().zip(pixels) {
            image.pixels[p] = colour;
        }
        let counts = match (counts, second_counts) {
            (Some(a), Some(b)) => Some(crate::stats::Tally::merge(a, b)),
            (a, _) => a,
        };
        Ok((image, times, counts))
    }

    /// Refuses a render this renderer cannot do: on a lost device, or in
    /// f64 on a device without doubles.
    fn check_can_render(&self, settings: &RenderSettings) -> Result<(), GpuError> {
        if self.device.hung() {
            return Err(GpuError::Lost);
        }
        if settings.schedule == Schedule::Wavefront {
            let info = &self.device.info;
            if !self.sources.main_is_glints() {
                return Err(GpuError::Unsupported(
                    "--schedule wavefront runs glint's own main.comp (shaders/wavefront.glsl); \
                     a --shader of your own renders with the megakernel (--schedule megakernel)"
                        .to_owned(),
                ));
            }
            if !info.runs_the_wavefront {
                return Err(GpuError::Unsupported(format!(
                    "--schedule wavefront: the driver {} is known to crash running it; render \
                     with --schedule megakernel, or with lavapipe from Mesa 25 (ci/setup \
                     installs it)",
                    info.driver
                )));
            }
            if !info.subgroup_ballot {
                return Err(GpuError::Unsupported(format!(
                    "--schedule wavefront: {} has no subgroup ballot in compute shaders, with \
                     which the wavefront compacts its queues; render with --schedule megakernel",
                    info.name
                )));
            }
        }
        if settings.precision == Precision::F64 && !self.device.info.shader_float64 {
            return Err(GpuError::Unsupported(format!(
                "{} has no shaderFloat64: render in f32, or on the CPU in f64",
                self.device.info.name
            )));
        }
        Ok(())
    }

    /// Makes `up`'s buffers, with an output tile of `tile` pixels, the ones
    /// pipeline `key` is bound to, unless they already are.
    fn make_resident(
        &mut self,
        key: &PipelineKey,
        variant: &Variant,
        up: &std::rc::Rc<Uploads>,
        tile: (u32, u32),
        refine: Option<&Array>,
    ) -> Result<(), GpuError> {
        let reuse = refine.is_none()
            && self.resident.as_ref().is_some_and(|r| {
                r.pipeline == *key && r.tile == tile && std::rc::Rc::ptr_eq(&r.uploads, up)
            });
        if reuse {
            return Ok(());
        }
        // The old buffers go first: the device is idle between renders.
        self.resident = None;
        let buffers = self.scene_buffers(variant, up, tile, refine)?;
        // SAFETY: the device is idle between renders; the buffers are
        // kept in `resident` until the set is bound again or the
        // pipeline is dropped, or leaked where a dispatch timed out.
        unsafe {
            self.pipelines[key].bind(&buffers.iter().map(Bound::resource).collect::<Vec<_>>())
        };
        self.resident = Some(Resident {
            pipeline: key.clone(),
            uploads: up.clone(),
            tile,
            buffers,
        });
        Ok(())
    }

    /// The first dispatch of pipeline `key`, where the driver compiles its
    /// shader: one workgroup over an empty tile, under `COMPILE_TIMEOUT`,
    /// so that the render's own watchdog times shading alone. Its seconds;
    /// 0 for a pipeline the driver has compiled already.
    fn compile_on_driver(&mut self, key: &PipelineKey) -> Result<f64, GpuError> {
        if self.driver_compiled.contains(key) {
            return Ok(0.0);
        }
        let t = Instant::now();
        let resident = self.resident.as_ref().expect("made resident first");
        let empty = Dispatch {
            pipeline: &self.pipelines[key],
            out: resident
                .buffers
                .last()
                .expect("the output binding is last")
                .buffer()
                .raw,
            zero: None,
            rect: bytemuck::Zeroable::zeroed(),
        };
        match dispatch(&mut self.commands, None, &empty, COMPILE_TIMEOUT) {
            Err(GpuError::Vk {
                result: raw::Result::TIMEOUT,
                ..
            }) => {
                // The device may still read and write these: never free them.
                std::mem::forget(self.resident.take());
                return Err(GpuError::CompileTimeout {
                    seconds: COMPILE_TIMEOUT.as_secs_f64(),
                });
            }
            other => {
                other?;
            }
        }
        self.driver_compiled.insert(key.clone());
        Ok(secs(t.elapsed()))
    }

    /// Dispatches `region` in tiles of `tile` pixels, in the image's own
    /// pixel coordinates, each under its watchdog (for `work` times a
    /// pixel's rays); the region's pixels, and the counts where `variant`
    /// counts.
    #[allow(clippy::too_many_arguments)]
    fn dispatch_tiles(
        &mut self,
        scene: &Scene,
        key: &PipelineKey,
        variant: &Variant,
        region: Region,
        (tile_w, tile_h): (u32, u32),
        work: f64,
        times: &mut RenderTimes,
        progress: &dyn Fn(u64),
    ) -> Result<(Vec<[f32; 3]>, Option<Counts>), GpuError> {
        let pipeline = &self.pipelines[key];
        let buffers = &self.resident.as_ref().expect("made resident first").buffers;
        let out = buffers.last().expect("the output binding is last").buffer();
        // The counters start at zero on the device, in the first dispatch.
        let mut counters = variant
            .binding_of(Block::Counts)
            .map(|at| buffers[at].buffer().raw);
        let mut last = None;
        let (x_end, y_end) = (region.x + region.width, region.y + region.height);
        let mut pixels = vec![[0.0f32; 3]; region.pixel_count() as usize];
        for y0 in (region.y..y_end).step_by(tile_h as usize) {
            for x0 in (region.x..x_end).step_by(tile_w as usize) {
                let (w, h) = (tile_w.min(x_end - x0), tile_h.min(y_end - y0));
                let t1 = Instant::now();
                // `work`: a pixel's rays, in pixels of `scene`'s (the
                // refinement's list entries trace up to many a pixel's).
                let timeout = self.timeout.unwrap_or_else(|| {
                    let pixels = (work * f64::from(w) * f64::from(h)).ceil() as u64;
                    tile_timeout(scene, pixels, variant.bvh_stack > 0)
                });
                let job = Dispatch {
                    pipeline,
                    out: out.raw,
                    zero: counters.take(),
                    rect: TileRect {
                        rect: UVec4::new(x0, y0, w, h),
                        stage: UVec4::ZERO,
                    },
                };
                let done = if variant.wavefront {
                    let queues = buffers[variant
                        .binding_of(Block::Queues)
                        .expect("a wavefront has queues")]
                    .buffer();
                    wavefront_tile(
                        &mut self.commands,
                        self.timestamps.as_ref(),
                        &job,
                        queues,
                        schedule::rounds_per_submit(scene),
                        timeout,
                    )
                } else {
                    dispatch(&mut self.commands, self.timestamps.as_ref(), &job, timeout)
                };
                let (done, on_device) = match done {
                    Err(GpuError::Vk {
                        result: raw::Result::TIMEOUT,
                        ..
                    }) => {
                        // The GPU may still read and write these: never free them.
                        std::mem::forget(self.resident.take());
                        return Err(GpuError::Timeout {
                            x: x0,
                            y: y0,
                            w,
                            h,
                            seconds: timeout.as_secs_f64(),
                        });
                    }
                    other => other?,
                };
                if let (Some(total), Some(s)) = (&mut times.device_dispatch_s, on_device) {
                    *total += s;
                }
                let t2 = Instant::now();
                let tile: &[[f32; 4]] = out.read(&done, w as usize * h as usize);
                if let Some(e) = unfinished(tile, (x0, y0, w), &self.device.info.name) {
                    return Err(e);
                }
                for (row, src) in tile.chunks_exact(w as usize).enumerate() {
                    let start = ((y0 - region.y) as usize + row) * region.width as usize
                        + (x0 - region.x) as usize;
                    for (dst, s) in pixels[start..start + w as usize].iter_mut().zip(src) {
                        *dst = [s[0], s[1], s[2]];
                    }
                }
                times.dispatch_s += secs(t2 - t1);
                times.readback_s += secs(t2.elapsed());
                progress(u64::from(w) * u64::from(h));
                last = Some(done);
            }
        }
        let buffers = &self.resident.as_ref().expect("made resident first").buffers;
        let counts = variant.binding_of(Block::Counts).map(|at| {
            let done = last.as_ref().expect("a region has at least one tile");
            read_counts(buffers[at].buffer(), done)
        });
        Ok((pixels, counts))
    }

    /// The buffers of `variant`'s bindings, in order, holding `up` (the
    /// output tile last, of `tile` pixels); only those its shader declares.
    fn scene_buffers(
        &mut self,
        variant: &Variant,
        up: &Uploads,
        tile: (u32, u32),
        refine: Option<&Array>,
    ) -> Result<Vec<Bound>, GpuError> {
        let d = &self.device;
        let commands = &mut self.commands;
        let stage_uploads = self.stage_uploads;
        let pixels = u64::from(tile.0) * u64::from(tile.1);
        let out_bytes = pixels * 16;
        // What the shader only reads: device-local through staging, or mapped.
        let mut scene = |bytes: &[u8], usage, what| {
            if stage_uploads {
                Buffer::staged(d, commands, bytes, usage, what)
            } else {
                Buffer::with_data(d, bytes, usage, what)
            }
        };
        let mut buffers = Vec::new();
        for (block, _, ty) in variant.bindings() {
            let form = access::ArrayDecl::of(block).map(|_| variant.form(block));
            let usage = match (form, ty) {
                (Some(access::Form::Address), _) => {
                    raw::BufferUsageFlags::STORAGE_BUFFER
                        | raw::BufferUsageFlags::SHADER_DEVICE_ADDRESS
                }
                (_, raw::DescriptorType::UNIFORM_BUFFER) => raw::BufferUsageFlags::UNIFORM_BUFFER,
                (_, raw::DescriptorType::UNIFORM_TEXEL_BUFFER) => {
                    raw::BufferUsageFlags::UNIFORM_TEXEL_BUFFER
                }
                _ => raw::BufferUsageFlags::STORAGE_BUFFER,
            };
            let buffer = match block {
                Block::Globals => scene(
                    bytemuck::cast_slice(&up.globals),
                    raw::BufferUsageFlags::UNIFORM_BUFFER,
                    "the uniform block",
                )?,
                Block::Kind(k) => scene(&up.kinds[k].bytes, usage, block.name())?,
                Block::Materials => scene(&up.materials.bytes, usage, "materials")?,
                Block::Lights => scene(&up.lights.bytes, usage, "lights")?,
                Block::Textures => scene(&up.textures.bytes, usage, "textures")?,
                Block::Texels => scene(&up.texels.bytes, usage, "texels")?,
                Block::Uvs => scene(&up.uvs.bytes, usage, "uvs")?,
                Block::Nodes => scene(
                    &up.nodes.as_ref().expect("a BVH variant has nodes").bytes,
                    usage,
                    "BVH nodes",
                )?,
                Block::Counts => Buffer::new(
                    d,
                    (2 * Counter::SLOTS * std::mem::size_of::<u32>()) as u64,
                    raw::BufferUsageFlags::STORAGE_BUFFER | raw::BufferUsageFlags::TRANSFER_DST,
                    "the counters",
                )?,
                Block::Refine => scene(
                    &refine.expect("a refining variant has its list").bytes,
                    raw::BufferUsageFlags::STORAGE_BUFFER,
                    "the pixels to refine",
                )?,
                Block::PathReals | Block::PathWords => {
                    let (reals, words) = variant.path_bytes();
                    let size = if block == Block::PathReals {
                        reals
                    } else {
                        words
                    };
                    Buffer::device_local(
                        d,
                        pixels * size,
                        raw::BufferUsageFlags::STORAGE_BUFFER,
                        block.name(),
                    )?
                }
                Block::Queues => Buffer::new(
                    d,
                    32 + 2 * 4 * pixels,
                    raw::BufferUsageFlags::STORAGE_BUFFER
                        | raw::BufferUsageFlags::TRANSFER_DST
                        | raw::BufferUsageFlags::INDIRECT_BUFFER,
                    "the path queues",
                )?,
                Block::Pixels => Buffer::new(
                    d,
                    out_bytes,
                    raw::BufferUsageFlags::STORAGE_BUFFER | raw::BufferUsageFlags::TRANSFER_DST,
                    "the output tile",
                )?,
            };
            buffers.push(match form {
                Some(access::Form::Texels) => Bound::Texels(TexelBuffer::new(d, buffer)?),
                Some(access::Form::Address) => {
                    let at = [buffer.address(), 0u64];
                    let address = Buffer::with_data(
                        d,
                        &at,
                        raw::BufferUsageFlags::UNIFORM_BUFFER,
                        "an array's address",
                    )?;
                    Bound::Address {
                        data: buffer,
                        address,
                    }
                }
                _ => Bound::Buffer(buffer),
            });
        }
        Ok(buffers)
    }
}

/// One tile's dispatch: the pipeline (its set bound), its output buffer,
/// the counters to zero first (the first tile of a counted render), and the
/// tile.
struct Dispatch<'a> {
    pipeline: &'a ComputePipeline,
    out: raw::Buffer,
    zero: Option<raw::Buffer>,
    rect: TileRect,
}

/// Runs `job` on `commands`, waiting at most `timeout`: the token that it
/// finished, and the dispatch's own time on the device where it writes
/// timestamps.
fn dispatch<'c>(
    commands: &'c mut OneShot,
    timestamps: Option<&Timestamps>,
    job: &Dispatch<'_>,
    timeout: Duration,
) -> Result<(Completed<'c>, Option<f64>), GpuError> {
    let groups = |n: u32| n.div_ceil(WORKGROUP);
    let Dispatch {
        pipeline: p,
        out,
        zero,
        rect,
    } = *job;
    // SAFETY: the pipeline, its set and the buffers bound to it are alive
    // until `run` returns (the renderer holds them) and are leaked if the
    // wait times out; the fills cover whole buffers; the command buffer is
    // recording, outside a render pass (the contract of the timestamps).
    let done = commands.run(timeout, |dev, cb| unsafe {
        // Every output word starts as a NaN, so a pixel the shader never
        // writes is seen, not read as whatever the memory held.
        dev.cmd_fill_buffer(cb, out, 0, raw::WHOLE_SIZE, UNWRITTEN);
        if let Some(counters) = zero {
            dev.cmd_fill_buffer(cb, counters, 0, raw::WHOLE_SIZE, 0);
        }
        memory_barrier(
            dev,
            cb,
            (
                raw::PipelineStageFlags::TRANSFER,
                raw::AccessFlags::TRANSFER_WRITE,
            ),
            (
                raw::PipelineStageFlags::COMPUTE_SHADER,
                raw::AccessFlags::SHADER_READ | raw::AccessFlags::SHADER_WRITE,
            ),
        );
        p.record_bind(dev, cb);
        dev.cmd_push_constants(
            cb,
            p.layout,
            raw::ShaderStageFlags::COMPUTE,
            0,
            bytemuck::bytes_of(&rect),
        );
        // From when the fill is done to when the dispatch is.
        if let Some(t) = timestamps {
            t.begin(cb, raw::PipelineStageFlags::TRANSFER);
        }
        dev.cmd_dispatch(cb, groups(rect.rect.z), groups(rect.rect.w), 1);
        if let Some(t) = timestamps {
            t.end(cb, raw::PipelineStageFlags::COMPUTE_SHADER);
        }
        // Make the shader's writes visible to the host's read of the mapping.
        memory_barrier(
            dev,
            cb,
            (
                raw::PipelineStageFlags::COMPUTE_SHADER,
                raw::AccessFlags::SHADER_WRITE,
            ),
            (raw::PipelineStageFlags::HOST, raw::AccessFlags::HOST_READ),
        );
    })?;
    let on_device = timestamps.map(|t| t.seconds(&done)).transpose()?;
    Ok((done, on_device))
}

/// Runs `job`'s tile as a wavefront (src/gpu/schedule.rs): submissions of
/// `rounds` segments each, every one under `timeout`, until no path of the
/// tile is alive; then the token, and the device's time summed.
fn wavefront_tile<'c>(
    commands: &'c mut OneShot,
    timestamps: Option<&Timestamps>,
    job: &Dispatch<'_>,
    queues: &Buffer,
    rounds: u32,
    timeout: Duration,
) -> Result<(Completed<'c>, Option<f64>), GpuError> {
    let mut on_device = timestamps.map(|_| 0.0);
    let mut wave = schedule::Wave {
        pipeline: job.pipeline,
        rect: job.rect.rect,
        queues: queues.raw,
        first: Some((job.out, job.zero)),
        queue: 0,
        rounds,
    };
    loop {
        let (done, t) = schedule::submit(commands, timestamps, &wave, timeout)?;
        if let (Some(total), Some(t)) = (&mut on_device, t) {
            *total += t;
        }
        wave.queue = (wave.queue + rounds) % 2;
        if schedule::live_paths(queues.read(&done, 8), wave.queue) == 0 {
            break;
        }
        wave.first = None;
    }
    Ok((commands.idle()?, on_device))
}

/// Every Vulkan device, best first, for `glint info`.
pub fn list_devices() -> Result<Vec<DeviceInfo>, GpuError> {
    let instance = Instance::new(false)?;
    Ok(vk::device::candidates(&instance)?
        .into_iter()
        .map(|c| c.info)
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Overrides;

    /// An edited shader file makes a new pipeline for the variant, which
    /// replaces the old one (as `glint watch` edits it), rather than
    /// piling up one pipeline an edit.
    #[test]
    fn an_edit_replaces_the_variants_pipeline() {
        let dir = tempfile::tempdir().unwrap();
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let specular = std::fs::read_to_string(root.join("shaders/specular.glsl")).unwrap();
        let file = dir.path().join("specular.glsl");
        std::fs::write(&file, &specular).unwrap();
        let small = Overrides {
            width: Some(16),
            height: Some(12),
            ..Overrides::default()
        };
        let scene = Scene::load(&root.join("scenes/seed-fig4.toml"), &small).unwrap();
        let mut renderer = Renderer::new(&GpuOptions {
            include_dirs: vec![dir.path().to_owned()],
            ..GpuOptions::from_env(None)
        })
        .unwrap();
        let (before, _) = renderer.render(&scene, &|_| {}).unwrap();
        std::fs::write(&file, specular.replace("spec_pow(", "0.0 * spec_pow(")).unwrap();
        let (after, _) = renderer.render(&scene, &|_| {}).unwrap();
        assert!(before != after, "the edit changes the image");
        assert_eq!(renderer.pipelines.len(), 1);
        // The edit undone: the first image again, still one pipeline.
        std::fs::write(&file, &specular).unwrap();
        let (again, _) = renderer.render(&scene, &|_| {}).unwrap();
        assert!(again == before);
        assert_eq!(renderer.pipelines.len(), 1);
    }
}
