//! How a tile's rays are laid on the device: the megakernel, one
//! invocation per pixel that traces its whole ray tree (shaders/main.comp),
//! or the wavefront, where the paths wait in buffers and each dispatch
//! advances every live one by a segment (shaders/wavefront.glsl). Both give
//! the same bits (tests/schedules.rs); docs/performance.md (Schedules) has
//! their figures.

use std::time::Duration;

use ash::vk as raw;
use glam::UVec4;

use super::layout::{TileRect, UNWRITTEN};
use super::vk::command::{memory_barrier, Completed, OneShot};
use super::vk::pipeline::ComputePipeline;
use super::vk::query::Timestamps;
use super::{GpuError, WORKGROUP};
use crate::scene::Scene;
pub use crate::settings::Schedule;

/// A buffer, and the offset and size of the bytes in it a render starts
/// from zero.
pub(crate) type Zeroed = (raw::Buffer, raw::DeviceSize, raw::DeviceSize);

impl Schedule {
    /// Whether `scene` renders with the wavefront under this schedule. A
    /// scene without objects has no ray tree to schedule and always takes
    /// the megakernel.
    pub fn wavefront_for(self, scene: &Scene) -> bool {
        if scene.prims.is_empty() {
            return false;
        }
        match self {
            Schedule::Megakernel => false,
            Schedule::Wavefront => true,
            Schedule::Auto => auto_picks_wavefront(scene),
        }
    }
}

/// Auto's rule. On lavapipe the wavefront measured slower than the
/// megakernel, or within the noise of it, on every bench scene
/// (docs/performance.md, Schedules), so auto takes the megakernel for every
/// scene; no real GPU has been measured yet (`ci/gpu-check` would).
fn auto_picks_wavefront(_scene: &Scene) -> bool {
    false
}

/// The wavefront's stages (shaders/wavefront.glsl).
const START: u32 = 0;
const BOUNCE: u32 = 1;
const ARGS: u32 = 2;

/// The words of the queues' header before a tile: both empty (a dispatch
/// size with 1, 1 after it, then the count, for each).
const START_HEADER: [u32; 8] = [0, 1, 1, 0, 0, 1, 1, 0];

/// The count of queue `queue` in the queues' header.
pub(crate) fn live_paths(header: &[u32], queue: u32) -> u32 {
    header[4 * queue as usize + 3]
}

/// One submission of a tile's wavefront.
pub(crate) struct Wave<'a> {
    pub pipeline: &'a ComputePipeline,
    pub set: raw::DescriptorSet,
    pub rect: UVec4,
    pub queues: raw::Buffer,
    /// The first submission of the tile: it also fills the output with
    /// NaNs, zeroes the counters where given (a buffer, the offset and
    /// size of its bytes to zero), sets the header and starts the paths.
    pub first: Option<(raw::Buffer, Option<Zeroed>)>,
    /// The queue the first bounce reads.
    pub queue: u32,
    pub rounds: u32,
}

/// Records and runs `wave`, waiting at most `timeout`: the token that it
/// finished, and its time on the device where the queue writes timestamps.
pub(crate) fn submit<'c>(
    commands: &'c mut OneShot,
    timestamps: Option<&Timestamps>,
    wave: &Wave<'_>,
    timeout: Duration,
) -> Result<(Completed<'c>, Option<f64>), GpuError> {
    let p = wave.pipeline;
    let compute = raw::PipelineStageFlags::COMPUTE_SHADER;
    let shader_rw = raw::AccessFlags::SHADER_READ | raw::AccessFlags::SHADER_WRITE;
    let push = |dev: &ash::Device, cb, stage: u32, queue: u32| {
        let constants = TileRect {
            rect: wave.rect,
            stage: UVec4::new(stage, queue, 0, 0),
        };
        // SAFETY: recording, with the pipeline's layout, in its range.
        unsafe {
            dev.cmd_push_constants(
                cb,
                p.layout,
                raw::ShaderStageFlags::COMPUTE,
                0,
                bytemuck::bytes_of(&constants),
            )
        };
    };
    // SAFETY: the pipeline, its set and the buffers bound to it are alive
    // until `run` returns (the renderer holds them) and are leaked if the
    // wait times out; the fills cover whole buffers, the header update the
    // queues' first 32 bytes; the command buffer is recording, outside a
    // render pass.
    let done = commands.run(timeout, |dev, cb| unsafe {
        if let Some((out, counters)) = wave.first {
            dev.cmd_fill_buffer(cb, out, 0, raw::WHOLE_SIZE, UNWRITTEN);
            if let Some((buffer, offset, size)) = counters {
                dev.cmd_fill_buffer(cb, buffer, offset, size, 0);
            }
            dev.cmd_update_buffer(cb, wave.queues, 0, bytemuck::cast_slice(&START_HEADER));
            memory_barrier(
                dev,
                cb,
                (
                    raw::PipelineStageFlags::TRANSFER,
                    raw::AccessFlags::TRANSFER_WRITE,
                ),
                (compute, shader_rw),
            );
        }
        p.record_bind(dev, cb, wave.set);
        if let Some(t) = timestamps {
            t.begin(cb, raw::PipelineStageFlags::TRANSFER);
        }
        if wave.first.is_some() {
            // The first segments, then queue 0's dispatch size from its count.
            push(dev, cb, START, 0);
            let groups = |n: u32| n.div_ceil(WORKGROUP);
            dev.cmd_dispatch(cb, groups(wave.rect.z), groups(wave.rect.w), 1);
            memory_barrier(
                dev,
                cb,
                (compute, raw::AccessFlags::SHADER_WRITE),
                (compute, shader_rw),
            );
            push(dev, cb, ARGS, 0);
            dev.cmd_dispatch(cb, 1, 1, 1);
        }
        let mut queue = wave.queue;
        for _ in 0..wave.rounds {
            // The last stage's writes (and those of an earlier submission)
            // before this bounce reads the paths and its dispatch size.
            memory_barrier(
                dev,
                cb,
                (compute, raw::AccessFlags::SHADER_WRITE),
                (
                    compute | raw::PipelineStageFlags::DRAW_INDIRECT,
                    shader_rw | raw::AccessFlags::INDIRECT_COMMAND_READ,
                ),
            );
            push(dev, cb, BOUNCE, queue);
            dev.cmd_dispatch_indirect(cb, wave.queues, 16 * u64::from(queue));
            memory_barrier(
                dev,
                cb,
                (compute, raw::AccessFlags::SHADER_WRITE),
                (compute, shader_rw),
            );
            queue = 1 - queue;
            push(dev, cb, ARGS, queue);
            dev.cmd_dispatch(cb, 1, 1, 1);
        }
        if let Some(t) = timestamps {
            t.end(cb, compute);
        }
        // The shader's writes visible to the host's reads of the mappings.
        memory_barrier(
            dev,
            cb,
            (compute, raw::AccessFlags::SHADER_WRITE),
            (raw::PipelineStageFlags::HOST, raw::AccessFlags::HOST_READ),
        );
    })?;
    let on_device = timestamps.map(|t| t.seconds(&done)).transpose()?;
    Ok((done, on_device))
}
