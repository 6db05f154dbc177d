//! A scene prepared for the GPU: laid out, compiled and uploaded once by
//! [`Renderer::prepare`](super::Renderer::prepare), then rendered region by region as a list of
//! passes (megakernel or wavefront tiles; adaptive sampling's refinement
//! after the corners), each run by the executor under its watchdog.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use glam::UVec4;

use super::blocks::{Block, Form};
use super::layout::Uploads;
use super::options::RenderSettings;
use super::passes::{Executor, Pass, Target};
use super::refine;
use super::resident::{scene_blocks, Blocks, StageInput};
use super::shared::Shared;
use super::times::{RenderTimes, SetupTimes};
use super::variant::Variant;
use super::vk::buffer::Buffer;
use super::vk::command::Completed;
use super::work::{PixelWork, COMPILE_TIMEOUT};
use super::{GpuError, Precision};
use crate::accel::refit::Shape;
use crate::base::aov::{self, Aov};
use crate::base::record;
use crate::raster::region::Region;
use crate::raster::Image;
use crate::sampling::contrast::Entry;
use crate::sampling::Sampled;
use crate::scene::decisions::Decisions;
use crate::scene::{Adaptive, Contrast, Scene};
use crate::stats::{Counter, Counts};

mod contrast;
mod refinement;
mod stage;
mod update;

use stage::{pick, BoundStage};

pub use update::Update;

/// A scene on the device: its variant's pipeline, its buffers and its own
/// descriptor sets. It holds no copy of the scene.
///
/// Field order is drop order: the stages (their sets, then their
/// buffers) before the scene's buffers, before the commands, before the
/// renderer's device.
pub struct Prepared {
    main: BoundStage,
    /// Adaptive sampling's second pass, made at the first render that
    /// splits a pixel.
    refine: Option<BoundStage>,
    scene: Blocks,
    executor: Executor,
    shared: Arc<Shared>,
    /// What the traced image (the corner grid, where the scene samples
    /// corners) asks of a pixel.
    work: PixelWork,
    /// The image's size: the scene's, not its corner grid's.
    size: (u32, u32),
    gather: Gather,
    /// The shader's arithmetic, in which the refinement sums its squares.
    precision: Precision,
    /// What preparing cost, reported by the first render.
    pending: Option<RenderTimes>,
    /// Set from elsewhere to stop a render between tiles ([`Prepared::stop_when`]).
    stop: Option<Arc<AtomicBool>>,
    /// The last render's record, where the main stage records a tree.
    record: Option<Vec<u32>>,
    /// The last render's AOVs, where the main stage writes them.
    aovs: Option<Vec<Aov>>,
    /// What it was prepared under, which an update lays the scene out by.
    settings: RenderSettings,
    /// Its BVH's shape, which an update refits.
    shape: Option<Shape>,
    /// The texels uploaded (shared with the scene, not copied), which an
    /// update writes again only where the scene's differ.
    texels: Arc<Vec<[f32; 3]>>,
    /// The sampling decisions its renders replay (`Scene::replay`).
    replay: Option<Arc<Decisions>>,
}

/// How a pixel's colour comes from what the shader traces.
#[derive(Clone, Copy, PartialEq)]
enum Gather {
    /// The traced pixels are the image's.
    Pixels,
    /// The traced pixels are the image's corners, averaged.
    Corners,
    /// Corners, and pixels whose corners differ split (`Variant::refine`).
    Adaptive(Adaptive),
    /// Contrast sampling's levels, each a list (`Variant::contrast`).
    Contrast(Contrast),
}

impl Gather {
    /// How `scene`'s pixels come from what is traced (`corners`: it traces
    /// its corner grid).
    fn of(scene: &Scene, corners: bool) -> Self {
        if let Some(c) = scene.contrast_sampling() {
            return Gather::Contrast(c);
        }
        match (corners, scene.adaptive_sampling()) {
            (false, _) => Gather::Pixels,
            (true, None) => Gather::Corners,
            (true, Some(a)) => Gather::Adaptive(a),
        }
    }

    /// The main stage's variant, from the scene's: contrast sampling
    /// traces nothing but its levels' lists, so its one stage is theirs,
    /// made with the scene as every other mode's is.
    fn stage(&self, scene: Variant) -> Variant {
        match self {
            Gather::Contrast(c) => scene.listing(Some(c.compare_trees)),
            _ => scene,
        }
    }
}

/// A render of a prepared scene.
#[derive(Debug, Clone)]
pub struct Rendered {
    /// The region's pixels.
    pub image: Image,
    /// What the render cost.
    pub times: RenderTimes,
    /// The shader's counts of rays, tests and BVH nodes, where the scene
    /// was prepared to count (`RenderSettings::count`).
    pub counts: Option<Counts>,
    /// The recorded sample's ray tree, where the scene was prepared to
    /// record one (`RenderSettings::record`): the Record block's words,
    /// which `crate::base::record::decode` reads.
    pub record: Option<Vec<u32>>,
    /// The region's pixels' AOVs, row by row, where the scene was
    /// prepared to give them (`RenderSettings::aovs`).
    pub aovs: Option<Vec<Aov>>,
    /// What adaptive or contrast sampling decided (`Scene::replay`).
    pub sampled: Option<Sampled>,
}

impl Prepared {
    pub(crate) fn new(
        shared: &Arc<Shared>,
        scene: &Scene,
        settings: &RenderSettings,
    ) -> Result<Self, GpuError> {
        shared.check_can_render(settings)?;
        let grid = scene.corner_grid();
        let traced = grid.as_ref().unwrap_or(scene);
        let gather = Gather::of(scene, grid.is_some());
        if settings.aovs {
            if let Some(file) = shared.sources.without_aovs().first() {
                return Err(GpuError::Unsupported(format!(
                    "AOVs: {file} replaces a shader file that gives them and calls no AOV_ hook \
                     (shaders/aov.glsl): its AOVs would say that nothing was met"
                )));
            }
        }
        if let Some(why) = settings
            .aovs
            .then(|| crate::sampling::aovs_refused(scene))
            .flatten()
        {
            return Err(GpuError::Unsupported(why));
        }
        let t0 = Instant::now();
        let up = Uploads::new(
            traced,
            settings.intersect,
            settings.precision,
            settings.accel,
        );
        let layout_s = t0.elapsed().as_secs_f64() - up.bvh_s - up.tables_s;
        let wanted = super::features::Experiment::from_env().reads;
        if let Some(why) = super::features::refused_reads(wanted, &up, &shared.device.info) {
            return Err(GpuError::Unsupported(why));
        }
        let variant = gather.stage(shared.variant(traced, settings, &up, settings.count).0);
        let defines = shared.defines_of(&variant);
        let (pipeline, setup) = shared.pipeline(&variant, &defines)?;
        let t1 = Instant::now();
        let info = &shared.device.info;
        if variant.reads == Form::Storage {
            up.check_storage_range(
                info.max_storage_buffer_range,
                info.max_texel_buffer_elements,
            )
            .map_err(GpuError::Unsupported)?;
        }
        let mut executor = Executor::new(&shared.device)?;
        let blocks = scene_blocks(
            &shared.device,
            &mut executor.commands,
            shared.stage_uploads,
            &variant,
            &up,
        )?;
        let work = PixelWork::of(traced).through(up.ray_cost);
        // Contrast sampling's levels are lists on this stage: its output
        // holds the largest, the first's one entry a pixel.
        let tile = match gather {
            Gather::Contrast(_) => refinement::list_tiles(scene.width * scene.height, 1).1,
            _ => work.tile_size(&variant, info.max_storage_buffer_range),
        };
        // Contrast sampling's stage holds a list of one empty entry until
        // its first level binds one of its own: the driver's compile below
        // dispatches it over no pixels.
        let empty;
        let own = match gather {
            Gather::Contrast(_) => {
                empty = refine::entries(&[Entry::default()]);
                StageInput::Refine(&empty)
            }
            _ => StageInput::Main(settings.record),
        };
        let main = BoundStage::new(shared, pipeline, variant, &blocks, tile, own)?;
        let upload_s = layout_s + t1.elapsed().as_secs_f64();
        let mut prepared = Self {
            main,
            refine: None,
            scene: blocks,
            executor,
            shared: shared.clone(),
            work,
            size: (scene.width, scene.height),
            gather,
            precision: settings.precision,
            pending: None,
            stop: None,
            record: None,
            aovs: None,
            settings: *settings,
            shape: up.shape.clone(),
            texels: traced.texels.clone(),
            replay: scene.replay.clone(),
        };
        let driver_compile_s = prepared.compile_on_driver(false)?;
        prepared.pending = Some(RenderTimes {
            setup: SetupTimes {
                driver_compile_s,
                ..setup
            },
            bvh_s: up.bvh_s,
            tables_s: up.tables_s,
            upload_s,
            ..RenderTimes::default()
        });
        Ok(prepared)
    }

    /// Renders stop with [`GpuError::Interrupted`] before the next tile
    /// once `flag` is set (a host's Ctrl-C, as the Python module's): a
    /// tile on the device is not cut short, so the device and this scene
    /// stay usable. A later render runs again once `flag` is cleared.
    pub fn stop_when(&mut self, flag: Arc<AtomicBool>) {
        self.stop = Some(flag);
    }

    /// The image's width and height (the scene's, not its corner grid's).
    pub fn size(&self) -> (u32, u32) {
        self.size
    }

    /// The variant the scene was compiled with (docs/shaders.md, Variants).
    pub fn variant(&self) -> &Variant {
        &self.main.variant
    }

    /// Renders `region` of the image (None: the whole image), calling
    /// `progress(pixels)` as tiles finish. A region's pixels are bit for
    /// bit those of the whole render (docs/scale-out.md).
    pub fn render(
        &mut self,
        region: Option<Region>,
        progress: &dyn Fn(u64),
    ) -> Result<Rendered, GpuError> {
        if self.shared.device.hung() {
            return Err(GpuError::Lost);
        }
        let (width, height) = self.size;
        let region = match region {
            None => Region::whole(width, height),
            Some(r) => r
                .within(width, height)
                .map_err(|e| GpuError::Unsupported(e.to_string()))?,
        };
        let mut times = self.pending.take().unwrap_or_else(|| RenderTimes {
            setup: SetupTimes {
                device_s: self.shared.device_s(),
                ..SetupTimes::default()
            },
            ..RenderTimes::default()
        });
        if self.executor.timed() {
            times.device_dispatch_s.get_or_insert(0.0);
        }
        let rendered = match self.gather {
            Gather::Contrast(c) => match self.precision {
                Precision::F32 => self.contrast::<f32>(&c, region, times)?,
                Precision::F64 => self.contrast::<f64>(&c, region, times)?,
            },
            Gather::Pixels => {
                let (pixels, counts) = self.tiles(false, region, 1.0, &mut times, progress)?;
                Rendered {
                    image: Image::new(region.width, region.height, pixels),
                    times,
                    counts,
                    record: self.record.take(),
                    aovs: self.aovs.take(),
                    sampled: None,
                }
            }
            Gather::Corners | Gather::Adaptive(_) => {
                let traced = region.corners();
                let (pixels, counts) = self.tiles(false, traced, 1.0, &mut times, progress)?;
                let corners = Image::new(traced.width, traced.height, pixels);
                let mut rendered = Rendered {
                    image: corners.corner_mean(),
                    times,
                    counts,
                    record: self.record.take(),
                    aovs: None,
                    sampled: None,
                };
                if let Gather::Adaptive(a) = self.gather {
                    match self.precision {
                        Precision::F32 => {
                            self.refine::<f32>(&a, &corners, region, &mut rendered)?
                        }
                        Precision::F64 => {
                            self.refine::<f64>(&a, &corners, region, &mut rendered)?
                        }
                    }
                }
                rendered
            }
        };
        self.shared.check_validation()?;
        Ok(rendered)
    }

    /// The first dispatch of the main stage's pipeline (or the refinement's,
    /// where `refine`), where the driver compiles its shader: one workgroup
    /// over an empty tile, under `COMPILE_TIMEOUT`, so that the render's own
    /// watchdog times shading alone. Its seconds; 0 for a pipeline the
    /// driver has compiled already.
    fn compile_on_driver(&mut self, refine: bool) -> Result<f64, GpuError> {
        let stage = pick(&self.main, &self.refine, refine);
        if !stage.pipeline.first_dispatch() {
            return Ok(0.0);
        }
        let t = Instant::now();
        let mut empty = stage.target();
        empty.rect = UVec4::ZERO;
        if let Err(e) = self.executor.run(&Pass::Compile(empty), COMPILE_TIMEOUT) {
            stage.pipeline.undo_first_dispatch();
            return Err(e);
        }
        Ok(t.elapsed().as_secs_f64())
    }

    /// Dispatches `region` on the main stage (or the refinement's) in tiles,
    /// in the image's own pixel coordinates, each under its watchdog (for
    /// `work` times a pixel's rays); the region's pixels, and the counts
    /// where the stage counts.
    fn tiles(
        &mut self,
        refine: bool,
        region: Region,
        work: f64,
        times: &mut RenderTimes,
        progress: &dyn Fn(u64),
    ) -> Result<(Vec<[f32; 3]>, Option<Counts>), GpuError> {
        let stage = pick(&self.main, &self.refine, refine);
        let (tile_w, tile_h) = stage.tile;
        let bvh = stage.variant.bvh_stack > 0;
        // Colours an invocation writes, one after another.
        let per = stage.variant.outputs_per_invocation() as usize;
        let out = stage.buffer(Block::Pixels).expect("a stage has its output");
        // The counters, or a record's count of entries, start at zero on
        // the device, in the first dispatch.
        let counters = stage
            .buffer(Block::Counts)
            .map(|b| (b.raw, 0, ash::vk::WHOLE_SIZE));
        let record_count = stage
            .buffer(Block::Record)
            .map(|b| (b.raw, 4 * record::COUNT_WORD as u64, 4));
        let mut zero = counters.or(record_count);
        let queues = stage.buffer(Block::Queues);
        let mut last = None;
        let (x_end, y_end) = (region.x + region.width, region.y + region.height);
        let mut pixels = vec![[0.0f32; 3]; region.pixel_count() as usize * per];
        let aov_out = stage.buffer(Block::Aovs);
        let mut aov_words = aov_out.map(|_| vec![0u32; region.pixel_count() as usize * aov::WORDS]);
        for y0 in (region.y..y_end).step_by(tile_h as usize) {
            for x0 in (region.x..x_end).step_by(tile_w as usize) {
                if self
                    .stop
                    .as_ref()
                    .is_some_and(|s| s.load(Ordering::Relaxed))
                {
                    return Err(GpuError::Interrupted);
                }
                let (w, h) = (tile_w.min(x_end - x0), tile_h.min(y_end - y0));
                let t1 = Instant::now();
                // `work`: a pixel's rays, in pixels of the scene's (the
                // refinement's list entries trace up to many a pixel's).
                let timeout = self.shared.timeout.unwrap_or_else(|| {
                    let pixels = (work * f64::from(w) * f64::from(h)).ceil() as u64;
                    self.work.timeout(pixels, bvh)
                });
                let target = Target {
                    out_bytes: u64::from(w) * u64::from(h) * per as u64 * 16,
                    zero: zero.take(),
                    rect: UVec4::new(x0, y0, w, h),
                    ..stage.target()
                };
                let pass = match queues {
                    Some(queues) => Pass::Wave {
                        target,
                        queues,
                        rounds: self.work.rounds_per_submit(),
                    },
                    None => Pass::Tile(target),
                };
                let (done, on_device) = self.executor.run(&pass, timeout)?;
                if let (Some(total), Some(s)) = (&mut times.device_dispatch_s, on_device) {
                    *total += s;
                }
                let t2 = Instant::now();
                let tile: &[[f32; 4]] = out.read(&done, w as usize * h as usize * per);
                let device = &self.shared.device.info.name;
                if let Some(e) = unfinished(tile, per, (x0, y0, w), device) {
                    return Err(e);
                }
                let row_len = w as usize * per;
                for (row, src) in tile.chunks_exact(row_len).enumerate() {
                    let start = (((y0 - region.y) as usize + row) * region.width as usize
                        + (x0 - region.x) as usize)
                        * per;
                    for (dst, s) in pixels[start..start + row_len].iter_mut().zip(src) {
                        *dst = [s[0], s[1], s[2]];
                    }
                }
                if let (Some(out), Some(words)) = (aov_out, aov_words.as_mut()) {
                    let tile: &[u32] = out.read(&done, w as usize * h as usize * aov::WORDS);
                    let row_len = w as usize * aov::WORDS;
                    for (row, src) in tile.chunks_exact(row_len).enumerate() {
                        let start = (((y0 - region.y) as usize + row) * region.width as usize
                            + (x0 - region.x) as usize)
                            * aov::WORDS;
                        words[start..start + row_len].copy_from_slice(src);
                    }
                }
                times.dispatch_s += (t2 - t1).as_secs_f64();
                times.readback_s += t2.elapsed().as_secs_f64();
                progress(u64::from(w) * u64::from(h));
                last = Some(done);
            }
        }
        let done = last.as_ref().expect("a region has at least one tile");
        let counts = stage
            .buffer(Block::Counts)
            .map(|counters| read_counts(counters, done));
        // The header, and the entries written (all of the buffer's where
        // the tree was cut short: `decode` says so).
        self.record = stage.buffer(Block::Record).map(|record| {
            let header: &[u32] = record.read(done, record::HEADER_WORDS);
            let used = (header[record::COUNT_WORD] as usize).min(record::CAPACITY);
            let words = record::HEADER_WORDS + used * record::ENTRY_WORDS;
            record.read::<u32>(done, words).to_vec()
        });
        self.aovs =
            aov_words.map(|words| words.chunks_exact(aov::WORDS).map(Aov::decode).collect());
        Ok((pixels, counts))
    }
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
/// shader wrote nothing there. `per`: the colours an invocation writes;
/// `(x0, y0, w)`: the tile's corner and width, in invocations.
fn unfinished(
    tile: &[[f32; 4]],
    per: usize,
    (x0, y0, w): (u32, u32, u32),
    device: &str,
) -> Option<GpuError> {
    let at = tile.iter().position(|s| s[3] != 1.0)?;
    let i = (at / per) as u32;
    let (x, y) = (x0 + i % w, y0 + i / w);
    let alpha = tile[at][3];
    Some(if alpha.is_nan() {
        GpuError::Unwritten { x, y }
    } else if alpha == 0.0 {
        GpuError::LoopBudget {
            x,
            y,
            device: device.to_owned(),
        }
    } else {
        // Neither value the shader writes: a loop budget cannot explain
        // it, so it is not reported as one.
        GpuError::Garbled { x, y, alpha }
    })
}
