//! Timestamp queries: the device's own time for a span of commands.

use std::sync::Arc;

use ash::vk;

use super::command::Completed;
use super::device::Device;
use crate::gpu::error::{GpuError, VkContext};

/// Two timestamps, around the commands to be timed.
pub struct Timestamps {
    pub pool: vk::QueryPool,
    /// Nanoseconds a tick.
    period_ns: f64,
    /// The ticks' valid bits.
    mask: u64,
    device: Arc<Device>,
}

impl Timestamps {
    /// None where the device's compute queue writes no timestamps.
    pub fn new(device: &Arc<Device>) -> Result<Option<Self>, GpuError> {
        let Some((period, bits)) = device.info.timestamps else {
            return Ok(None);
        };
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::TIMESTAMP)
            .query_count(2);
        // SAFETY: a live device whose compute queue writes timestamps.
        let pool =
            unsafe { device.raw.create_query_pool(&info, None) }.doing("vkCreateQueryPool")?;
        Ok(Some(Self {
            pool,
            period_ns: f64::from(period),
            mask: if bits >= 64 {
                u64::MAX
            } else {
                (1u64 << bits) - 1
            },
            device: device.clone(),
        }))
    }

    /// Records the reset and the first timestamp: once the commands before
    /// have passed `after`.
    ///
    /// # Safety
    /// `cb` is in the recording state, outside a render pass.
    pub unsafe fn begin(&self, cb: vk::CommandBuffer, after: vk::PipelineStageFlags) {
        // SAFETY: the caller's contract; the pool holds both queries.
        unsafe {
            self.device.raw.cmd_reset_query_pool(cb, self.pool, 0, 2);
            self.device.raw.cmd_write_timestamp(cb, after, self.pool, 0);
        }
    }

    /// Records the second timestamp: once the commands before have passed
    /// `after`.
    ///
    /// # Safety
    /// As [`Timestamps::begin`], which this command buffer recorded first.
    pub unsafe fn end(&self, cb: vk::CommandBuffer, after: vk::PipelineStageFlags) {
        // SAFETY: the caller's contract; query 1 was reset by `begin`.
        unsafe { self.device.raw.cmd_write_timestamp(cb, after, self.pool, 1) };
    }

    /// The seconds between the two, once the submission that wrote them
    /// has finished (`done`).
    pub fn seconds(&self, done: &Completed<'_>) -> Result<f64, GpuError> {
        let _ = done;
        let mut ticks = [0u64; 2];
        // SAFETY: both queries were written by the submission `done` waited
        // on; WAIT makes the read block until they are available.
        unsafe {
            self.device.raw.get_query_pool_results(
                self.pool,
                0,
                &mut ticks,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .doing("vkGetQueryPoolResults")?;
        let span = ticks[1].wrapping_sub(ticks[0]) & self.mask;
        Ok(span as f64 * self.period_ns * 1e-9)
    }
}

impl Drop for Timestamps {
    fn drop(&mut self) {
        // A hung device's dispatch may still write it: leaked, as the device is.
        if self.device.hung() {
            return;
        }
        // SAFETY: no submission that writes the pool is pending (each
        // `OneShot::run` waits, and a wait that timed out marked the device hung).
        unsafe { self.device.raw.destroy_query_pool(self.pool, None) };
    }
}
