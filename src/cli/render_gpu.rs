//! Renders on the GPU for `render`, `compare` and tiles: the renderer made
//! from the command line's options, the scene prepared and rendered.

use std::path::Path;

use glint::gpu;
use glint::raster::region::Region;
use glint::raster::Image;
use glint::scene::Scene;
use glint::settings::Choice;
use glint::stats::Counts;
use glint::tiles::{GpuKey, Sidecar};

use super::tile;
use super::{progress, DeviceArgs, Precision};

/// The GPU options of `device` for a render in `precision`.
fn options(device: &DeviceArgs, precision: Precision) -> anyhow::Result<gpu::GpuOptions> {
    let mut options = device.options()?;
    options.settings.precision = precision;
    Ok(options)
}

/// A GPU render, with the renderer (for its device), the prepared scene
/// (to render again warm) and the setup times of the scene's variant.
pub struct GpuRender {
    pub image: Image,
    pub renderer: gpu::Renderer,
    pub prepared: gpu::Prepared,
    pub times: gpu::RenderTimes,
    /// Where the render counted (the counting variant: its times include
    /// the counting).
    pub counts: Option<Counts>,
    /// The pixels' AOVs, where the options asked for them.
    pub aovs: Option<Vec<glint::aov::Aov>>,
}

impl GpuRender {
    /// `GPU f32 on <device>`.
    pub fn label(&self, precision: Precision) -> String {
        let l = label(precision, &self.renderer.device_info().name);
        if self.renderer.spec_worst() {
            l + " run as the least precise conformant driver (--spec-worst)"
        } else {
            l
        }
    }
}

/// `GPU <precision> on <device>`, as `render` reports what rendered.
fn label(precision: Precision, device: &str) -> String {
    format!("GPU {} on {device}", precision.name())
}

/// Opens the device `options` name, under a line that says so: lavapipe
/// takes a moment, and a command that opens it has nothing else to show
/// yet. The line has no clock (`progress::waiting_without_a_clock`).
pub fn open(options: &gpu::GpuOptions) -> Result<gpu::Renderer, gpu::GpuError> {
    progress::waiting_without_a_clock("opening the Vulkan device", || gpu::Renderer::new(options))
}

/// Opens the device and prepares `scene` on it, under a spinner: opening
/// lavapipe, building a large BVH, compiling a new shader variant and the
/// driver's compile of its pipeline each take seconds.
fn open_and_prepare(
    scene: &Scene,
    options: &gpu::GpuOptions,
) -> anyhow::Result<(gpu::Renderer, gpu::Prepared)> {
    let mut renderer = open(options)?;
    let prepared = progress::waiting(
        "preparing the scene: buffers, BVH, and the shader (compiled on first use of a variant)",
        || renderer.prepare(scene, &options.settings),
    )?;
    Ok((renderer, prepared))
}

/// Renders the whole of `scene` in `precision`, counting where `count`.
pub fn timed(
    scene: &Scene,
    device: &DeviceArgs,
    precision: Precision,
    count: bool,
) -> anyhow::Result<GpuRender> {
    let mut options = options(device, precision)?;
    options.settings.count = count;
    render_with(scene, &options, precision)
}

/// Renders the whole of `scene` with `options`.
fn render_with(
    scene: &Scene,
    options: &gpu::GpuOptions,
    precision: Precision,
) -> anyhow::Result<GpuRender> {
    let (renderer, mut prepared) = open_and_prepare(scene, options)?;
    let bar = progress::bar(
        scene.pixel_count(),
        &format!("gpu {precision:?}").to_lowercase(),
    );
    let rendered = prepared.render(None, &|n| bar.inc(n))?;
    bar.finish_and_clear();
    Ok(GpuRender {
        image: rendered.image,
        renderer,
        prepared,
        times: rendered.times,
        counts: rendered.counts,
        aovs: rendered.aovs,
    })
}

/// `render`'s GPU render of the whole of `scene`, with what `want` asks.
pub fn whole(
    scene: &Scene,
    device: &DeviceArgs,
    precision: Precision,
    want: super::whole::Want,
) -> anyhow::Result<super::whole::Whole> {
    let mut options = options(device, precision)?;
    options.settings.count = want.count;
    options.settings.aovs = want.aovs;
    let r = render_with(scene, &options, precision)?;
    let setup = r.times.setup;
    Ok(super::whole::Whole {
        label: r.label(precision),
        seconds: r.times.total_s(),
        setup_s: setup.device_s
            + setup.compile_s
            + setup.pipeline_s
            + r.times.bvh_s
            + r.times.tables_s,
        tables_s: r.times.tables_s,
        image: r.image,
        counts: r.counts,
        aovs: r.aovs,
    })
}

/// `region` of `scene` rendered in `precision`: its pixels, bit for bit
/// those of the whole render; a label; the tile's sidecar.
pub fn tile(
    scene_arg: &Path,
    scene: &Scene,
    device: &DeviceArgs,
    precision: Precision,
    region: Region,
    tile: Option<String>,
) -> anyhow::Result<(Image, String, Sidecar)> {
    let options = options(device, precision)?;
    let (renderer, mut prepared) = open_and_prepare(scene, &options)?;
    let bar = progress::bar(region.pixel_count(), "gpu tile");
    let image = prepared.render(Some(region), &|n| bar.inc(n))?.image;
    bar.finish_and_clear();
    let device = renderer.device_info().name.clone();
    let key = gpu_key(&options, &device);
    let sidecar = tile::sidecar(
        scene_arg,
        scene,
        precision.name(),
        Some(key),
        region,
        tile,
        &image,
    );
    Ok((image, label(precision, &device), sidecar))
}

/// What of a GPU render can change a tile's bits: the intersection forms,
/// the generic shader, the user's shader files (the built-in ones come
/// with the version) and defines, and the device.
fn gpu_key(o: &gpu::GpuOptions, device: &str) -> GpuKey {
    use glint::gpu::compile::{cache_key, Sources};
    let sources = Sources {
        dirs: o.include_dirs.clone(),
        main: o.main_shader.clone(),
        ..Sources::default()
    };
    GpuKey {
        intersect: format!("{:?}", o.settings.intersect).to_lowercase(),
        generic: o.settings.generic,
        shader: cache_key(sources.fingerprint(), &o.defines),
        device: device.to_owned(),
    }
}
