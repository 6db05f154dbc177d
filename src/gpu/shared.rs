//! What a renderer and every scene it prepared share (`Shared`): the
//! device, the shader sources and the pipelines compiled so far. Kept
//! below both renderer.rs, which makes it, and prepared.rs, which renders
//! with it, so that neither imports the other's file for it.

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use super::compile;
use super::layout::{TileRect, Uploads};
use super::options::RenderSettings;
use super::schedule::Schedule;
use super::times::SetupTimes;
use super::variant::{Request, Variant};
use super::vk::device::Device;
use super::vk::pipeline::ComputePipeline;
use super::vk::pipeline_cache::PipelineCache;
use super::{GpuError, Precision};
use crate::scene::Scene;

/// The pipelines a renderer keeps, each with when it was last asked for.
#[derive(Default)]
pub(super) struct Pipelines {
    pub(super) map: HashMap<PipelineKey, (Arc<Pipeline>, u64)>,
    clock: u64,
}

/// How many pipelines a renderer keeps beyond those its prepared scenes
/// hold: a process that renders many variants (`glint fuzz`, a notebook)
/// took 2.6 GB by its 300th on lavapipe, each kept for ever.
pub(super) const KEPT_PIPELINES: usize = 32;

impl Pipelines {
    /// The pipeline of `key`, where kept, marked as just used.
    fn get(&mut self, key: &PipelineKey) -> Option<Arc<Pipeline>> {
        self.clock += 1;
        let now = self.clock;
        self.map.get_mut(key).map(|(p, used)| {
            *used = now;
            p.clone()
        })
    }

    /// Keeps `pipeline` under `key`, in place of the variant's older one
    /// (an edit's); then lets go of the least recently used ones that no
    /// prepared scene holds, down to `KEPT_PIPELINES`.
    fn insert(&mut self, key: PipelineKey, pipeline: Arc<Pipeline>) {
        self.map.retain(|(v, _), _| *v != key.0);
        self.clock += 1;
        self.map.insert(key, (pipeline, self.clock));
        while self.map.len() > KEPT_PIPELINES {
            let idle = self
                .map
                .iter()
                .filter(|(_, (p, _))| Arc::strong_count(p) == 1)
                .min_by_key(|(_, (_, used))| *used)
                .map(|(k, _)| k.clone());
            match idle {
                Some(k) => {
                    self.map.remove(&k);
                }
                None => break,
            }
        }
    }

    /// How many are kept.
    #[cfg(test)]
    pub(super) fn len(&self) -> usize {
        self.map.len()
    }
}

/// What the renderer and every scene it prepared share. Field order is
/// drop order: the pipelines and the pipeline cache go before the device
/// (each holds its own `Arc` of it as well).
pub(crate) struct Shared {
    /// Keyed by the variant and the fingerprint of the shader sources, so
    /// that an edited shader file makes a new pipeline (`glint watch`),
    /// which replaces the variant's old one here; a scene prepared with
    /// the old one keeps it.
    pub(super) pipelines: Mutex<Pipelines>,
    pub(super) pipeline_cache: PipelineCache,
    pub device: Arc<Device>,
    pub(super) sources: compile::Sources,
    pub(super) defines: Vec<(String, Option<String>)>,
    pub(super) cache_dir: Option<PathBuf>,
    /// Every pipeline's SPIR-V rewritten by `crate::spec_worst`.
    pub(super) spec_worst: bool,
    /// The settings of `Renderer::render`.
    pub(super) settings: RenderSettings,
    /// Seconds spent opening the device.
    pub(super) device_s: f64,
    /// The longest wait for one tile; None: from the tile's work.
    pub timeout: Option<std::time::Duration>,
    /// Whether scene buffers are device-local, filled through staging.
    pub stage_uploads: bool,
}

/// A pipeline: its variant, and the hash of its shader's sources and defines.
type PipelineKey = (Variant, u64);

/// A compiled variant's pipeline, and whether the driver has compiled its
/// shader to machine code yet (its first dispatch).
pub(crate) struct Pipeline {
    pub raw: ComputePipeline,
    pub driver_compiled: AtomicBool,
}

impl Shared {
    /// The validation layer's messages since the last call, as an error.
    pub fn check_validation(&self) -> Result<(), GpuError> {
        let messages = self.device.instance().take_messages();
        if messages.is_empty() {
            Ok(())
        } else {
            Err(GpuError::Validation(messages))
        }
    }

    /// The variant of `scene` laid out as `up`, counting where `count`.
    pub fn variant(
        &self,
        scene: &Scene,
        settings: &RenderSettings,
        up: &Uploads,
        count: bool,
    ) -> (Variant, Vec<(String, Option<String>)>) {
        let request = Request {
            intersect: settings.intersect,
            precision: settings.precision,
            generic: settings.generic,
            schedule: settings.schedule,
            record: settings.record.is_some(),
            aovs: settings.aovs,
            count,
            main_is_glints: self.sources.main_is_glints(),
        };
        let variant = Variant::for_scene(scene, up, &self.device.info, &request);
        let defines = self.defines_of(&variant);
        (variant, defines)
    }

    /// `variant`'s defines, then the user's.
    pub fn defines_of(&self, variant: &Variant) -> Vec<(String, Option<String>)> {
        let mut defines = variant.defines();
        defines.extend(self.defines.iter().cloned());
        defines
    }

    /// Seconds the renderer spent opening the device.
    pub fn device_s(&self) -> f64 {
        self.device_s
    }

    /// The pipeline of `variant`, compiled and created once per variant and
    /// version of the sources, and what this call cost (nothing where it
    /// was built before).
    pub fn pipeline(
        &self,
        variant: &Variant,
        defines: &[(String, Option<String>)],
    ) -> Result<(Arc<Pipeline>, SetupTimes), GpuError> {
        let sources = self.sources.for_variant(variant);
        let fingerprint = sources.fingerprint();
        let key = (variant.clone(), fingerprint);
        let mut setup = SetupTimes {
            device_s: self.device_s,
            ..SetupTimes::default()
        };
        let mut pipelines = self.pipelines.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(p) = pipelines.get(&key) {
            return Ok((p, setup));
        }
        let t0 = Instant::now();
        let (spirv, cached) =
            compile::compile_cached(&sources, fingerprint, defines, self.cache_dir.as_deref())?;
        // The rewrite follows the cache: the cached SPIR-V is glslang's,
        // shared by native and --spec-worst renders.
        let spirv = if self.spec_worst {
            crate::spec_worst::apply(&spirv, &crate::spec_worst::BOUNDS)
                .map_err(GpuError::Shader)?
                .0
        } else {
            spirv
        };
        let t1 = Instant::now();
        let push_bytes = std::mem::size_of::<TileRect>() as u32;
        let raw = ComputePipeline::new(
            &self.device,
            &spirv,
            &variant.descriptor_layout(),
            push_bytes,
            self.pipeline_cache.raw,
        )?;
        setup.compile_s = (t1 - t0).as_secs_f64();
        setup.pipeline_s = t1.elapsed().as_secs_f64();
        setup.spirv_cached = cached;
        let pipeline = Arc::new(Pipeline {
            raw,
            driver_compiled: AtomicBool::new(false),
        });
        pipelines.insert(key, pipeline.clone());
        drop(pipelines);
        self.check_validation()?;
        Ok((pipeline, setup))
    }

    /// Refuses a render this renderer cannot do: on a lost device, a
    /// wavefront it cannot run, or f64 on a device without doubles.
    pub fn check_can_render(&self, settings: &RenderSettings) -> Result<(), GpuError> {
        if self.device.hung() {
            return Err(GpuError::Lost);
        }
        let info = &self.device.info;
        if settings.schedule == Schedule::Wavefront {
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
        if settings.precision == Precision::F64 && !info.shader_float64 {
            return Err(GpuError::Unsupported(format!(
                "{} has no shaderFloat64: render in f32, or on the CPU in f64",
                info.name
            )));
        }
        Ok(())
    }
}

impl Pipeline {
    /// Whether this is the pipeline's first dispatch; marks it made.
    pub fn first_dispatch(&self) -> bool {
        !self.driver_compiled.swap(true, Ordering::Relaxed)
    }

    /// Undoes `first_dispatch` where that dispatch failed.
    pub fn undo_first_dispatch(&self) {
        self.driver_compiled.store(false, Ordering::Relaxed);
    }
}
