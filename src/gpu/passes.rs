//! The passes a render is made of (megakernel tiles, wavefront tiles, a
//! new pipeline's first dispatch), and the one executor that records each,
//! submits it, waits on its fence under the watchdog and times it.

use std::time::Duration;

use ash::vk as raw;
use glam::UVec4;

use super::layout::{TileRect, UNWRITTEN};
use super::schedule::{self, Zeroed};
use super::vk::buffer::Buffer;
use super::vk::command::{memory_barrier, Completed, OneShot};
use super::vk::device::Device;
use super::vk::pipeline::ComputePipeline;
use super::vk::query::Timestamps;
use super::{GpuError, WORKGROUP};

/// What a pass dispatches: the pipeline with its set, the output tile (each
/// word made `UNWRITTEN` first), the bytes to zero first (the first tile
/// of a render: the counters, or a record's count of entries), and the tile.
pub(crate) struct Target<'a> {
    pub pipeline: &'a ComputePipeline,
    pub set: raw::DescriptorSet,
    pub out: raw::Buffer,
    /// The bytes of `out` the tile writes, from its start: what the
    /// megakernel's dispatch fills first (a stage's output may hold more:
    /// contrast sampling's levels share the first level's).
    pub out_bytes: raw::DeviceSize,
    pub zero: Option<Zeroed>,
    pub rect: UVec4,
}

/// One pass of a render.
pub(crate) enum Pass<'a> {
    /// A new pipeline's first dispatch, one workgroup over an empty tile:
    /// where the driver compiles the shader (lavapipe runs LLVM there),
    /// under `COMPILE_TIMEOUT` rather than a tile's wait.
    Compile(Target<'a>),
    /// A megakernel tile: one invocation a pixel, each tracing its tree.
    Tile(Target<'a>),
    /// A wavefront tile (schedule.rs): submissions of `rounds` segments
    /// each until no path of the tile is alive.
    Wave {
        target: Target<'a>,
        queues: &'a Buffer,
        rounds: u32,
    },
}

/// A command buffer with its fence, and the timestamps its submissions
/// write where the queue writes them.
pub(crate) struct Executor {
    timestamps: Option<Timestamps>,
    pub commands: OneShot,
}

impl Executor {
    pub fn new(device: &std::sync::Arc<Device>) -> Result<Self, GpuError> {
        Ok(Self {
            commands: OneShot::new(device)?,
            timestamps: Timestamps::new(device)?,
        })
    }

    /// Whether the passes report their time on the device.
    pub fn timed(&self) -> bool {
        self.timestamps.is_some()
    }

    /// Runs `pass`, waiting at most `timeout` for each submission: the
    /// token that it finished, and its time on the device where the queue
    /// writes timestamps. A wait that runs out is the pass's own error (the
    /// tile, or the compile), and the device is then lost.
    pub fn run(
        &mut self,
        pass: &Pass<'_>,
        timeout: Duration,
    ) -> Result<(Completed<'_>, Option<f64>), GpuError> {
        let (commands, timestamps) = (&mut self.commands, self.timestamps.as_ref());
        let result = match pass {
            Pass::Compile(t) => dispatch(commands, None, t, timeout),
            Pass::Tile(t) => dispatch(commands, timestamps, t, timeout),
            Pass::Wave {
                target,
                queues,
                rounds,
            } => wavefront(commands, timestamps, target, queues, *rounds, timeout),
        };
        result.map_err(|e| {
            if !e.timed_out() {
                return e;
            }
            let seconds = timeout.as_secs_f64();
            match pass {
                Pass::Compile(_) => GpuError::CompileTimeout { seconds },
                Pass::Tile(t) | Pass::Wave { target: t, .. } => GpuError::Timeout {
                    x: t.rect.x,
                    y: t.rect.y,
                    w: t.rect.z,
                    h: t.rect.w,
                    seconds,
                },
            }
        })
    }
}

/// Runs one megakernel dispatch of `target`.
fn dispatch<'c>(
    commands: &'c mut OneShot,
    timestamps: Option<&Timestamps>,
    target: &Target<'_>,
    timeout: Duration,
) -> Result<(Completed<'c>, Option<f64>), GpuError> {
    let groups = |n: u32| n.div_ceil(WORKGROUP);
    let Target {
        pipeline: p,
        set,
        out,
        out_bytes,
        zero,
        rect,
    } = *target;
    let constants = TileRect {
        rect,
        stage: UVec4::ZERO,
    };
    // SAFETY: the pipeline, its set and the buffers bound to it are alive
    // until `run` returns (the prepared scene holds them) and are leaked if
    // the wait times out; the output's fill is within it (`out_bytes` are a
    // tile's words, at most the stage's) and the counters' is whole; the
    // command buffer is recording, outside a render pass (the contract of
    // the timestamps).
    let done = commands.run(timeout, |dev, cb| unsafe {
        // Every output word starts as a NaN, so a pixel the shader never
        // writes is seen, not read as whatever the memory held.
        dev.cmd_fill_buffer(cb, out, 0, out_bytes, UNWRITTEN);
        if let Some((buffer, offset, size)) = zero {
            dev.cmd_fill_buffer(cb, buffer, offset, size, 0);
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
        p.record_bind(dev, cb, set);
        dev.cmd_push_constants(
            cb,
            p.layout,
            raw::ShaderStageFlags::COMPUTE,
            0,
            bytemuck::bytes_of(&constants),
        );
        // From when the fill is done to when the dispatch is.
        if let Some(t) = timestamps {
            t.begin(cb, raw::PipelineStageFlags::TRANSFER);
        }
        dev.cmd_dispatch(cb, groups(rect.z), groups(rect.w), 1);
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

/// Runs `target`'s tile as a wavefront: submissions of `rounds` segments
/// each, every one under `timeout`, until no path of the tile is alive;
/// then the token, and the device's time summed.
fn wavefront<'c>(
    commands: &'c mut OneShot,
    timestamps: Option<&Timestamps>,
    target: &Target<'_>,
    queues: &Buffer,
    rounds: u32,
    timeout: Duration,
) -> Result<(Completed<'c>, Option<f64>), GpuError> {
    let mut on_device = timestamps.map(|_| 0.0);
    let mut wave = schedule::Wave {
        pipeline: target.pipeline,
        set: target.set,
        rect: target.rect,
        queues: queues.raw,
        first: Some((target.out, target.zero)),
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
