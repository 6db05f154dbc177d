//! One command buffer, recorded and submitted once at a time, waited on with
//! a fence.

use std::marker::PhantomData;
use std::sync::Arc;

use ash::vk;

use super::device::Device;
use crate::gpu::error::{GpuError, VkContext};

/// A command pool with one command buffer and the fence its submissions
/// signal.
pub struct OneShot {
    pub fence: vk::Fence,
    pub buffer: vk::CommandBuffer,
    pub pool: vk::CommandPool,
    device: Arc<Device>,
}

/// Proof that the last submission of a [`OneShot`] has finished: its fence
/// was waited on. Host reads of what that work wrote take one
/// ([`Buffer::read`](super::buffer::Buffer::read)); it borrows the
/// `OneShot` mutably, so no other submission of it can start while a token
/// (or anything read with it) is alive.
pub struct Completed<'a>(PhantomData<&'a mut OneShot>);

impl OneShot {
    /// A pool, its one command buffer and a fence, on `device`'s queue family.
    pub fn new(device: &Arc<Device>) -> Result<Self, GpuError> {
        let raw = &device.raw;
        let mut s = Self {
            fence: vk::Fence::null(),
            buffer: vk::CommandBuffer::null(),
            pool: vk::CommandPool::null(),
            device: device.clone(),
        };
        // Built up field by field so that Drop frees whatever was made if a
        // later step fails.
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(device.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: a live device; the family is the device's compute queue's.
        s.pool =
            unsafe { raw.create_command_pool(&pool_info, None) }.doing("vkCreateCommandPool")?;
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(s.pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: the pool was made from this device just above.
        s.buffer =
            unsafe { raw.allocate_command_buffers(&alloc) }.doing("vkAllocateCommandBuffers")?[0];
        // SAFETY: a live device.
        s.fence = unsafe { raw.create_fence(&vk::FenceCreateInfo::default(), None) }
            .doing("vkCreateFence")?;
        Ok(s)
    }

    /// Records with `record`, submits, and waits for the GPU to finish, at
    /// most `timeout`; the token says it finished.
    ///
    /// Whatever `record` records must stay valid until this returns `Ok`.
    /// On a timeout (`GpuError::Vk` with `vk::Result::TIMEOUT`) the work
    /// may still be running: the device is marked hung, nothing more is
    /// submitted to it (`GpuError::Lost`), and the caller must never free
    /// what the work uses.
    pub fn run(
        &mut self,
        timeout: std::time::Duration,
        record: impl FnOnce(&ash::Device, vk::CommandBuffer),
    ) -> Result<Completed<'_>, GpuError> {
        if self.device.hung() {
            return Err(GpuError::Lost);
        }
        let d = &self.device.raw;
        // SAFETY: the command buffer is not pending: the last submission's
        // fence was waited on (or this is the first), and `&mut self` rules
        // out a submission from another thread. The pool allows resetting
        // one buffer.
        unsafe {
            d.reset_command_buffer(self.buffer, vk::CommandBufferResetFlags::empty())
                .doing("vkResetCommandBuffer")?;
            let begin = vk::CommandBufferBeginInfo::default()
                .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            d.begin_command_buffer(self.buffer, &begin)
                .doing("vkBeginCommandBuffer")?;
        }
        record(d, self.buffer);
        let buffers = [self.buffer];
        let submit = vk::SubmitInfo::default().command_buffers(&buffers);
        let nanos = u64::try_from(timeout.as_nanos()).unwrap_or(u64::MAX);
        // SAFETY: the buffer is recording (begun above); the queue is only
        // used through `&mut OneShot`s, one submission at a time; the fence
        // is unsignalled (created so, reset after each wait).
        unsafe {
            d.end_command_buffer(self.buffer)
                .doing("vkEndCommandBuffer")?;
            d.queue_submit(self.device.queue, &[submit], self.fence)
                .doing("vkQueueSubmit")?;
            if let Err(result) = d.wait_for_fences(&[self.fence], true, nanos) {
                // Timed out, lost or out of memory: the work may still run.
                self.device.mark_hung();
                return Err(GpuError::vk("vkWaitForFences", result));
            }
            d.reset_fences(&[self.fence]).doing("vkResetFences")?;
        }
        Ok(Completed(PhantomData))
    }
}

impl OneShot {
    /// The token for work already waited on: every submission that did not
    /// hang the device was waited for by its `run`, so none is pending
    /// unless the device is marked hung.
    pub fn idle(&mut self) -> Result<Completed<'_>, GpuError> {
        if self.device.hung() {
            return Err(GpuError::Lost);
        }
        Ok(Completed(PhantomData))
    }
}

/// Records a global memory barrier: what the `src` stage wrote through
/// `src.1` is visible to `dst.1` accesses at the `dst` stage.
///
/// # Safety
/// `cb` is a command buffer of `d` in the recording state, outside a render
/// pass.
pub unsafe fn memory_barrier(
    d: &ash::Device,
    cb: vk::CommandBuffer,
    src: (vk::PipelineStageFlags, vk::AccessFlags),
    dst: (vk::PipelineStageFlags, vk::AccessFlags),
) {
    let barrier = vk::MemoryBarrier::default()
        .src_access_mask(src.1)
        .dst_access_mask(dst.1);
    // SAFETY: the caller's contract; the barrier lives for the call.
    unsafe {
        d.cmd_pipeline_barrier(
            cb,
            src.0,
            dst.0,
            vk::DependencyFlags::empty(),
            &[barrier],
            &[],
            &[],
        )
    };
}

impl Drop for OneShot {
    fn drop(&mut self) {
        // A hung device's submission may never end: its fence and pool are
        // leaked rather than waited for (the device is leaked too).
        if self.device.hung() {
            return;
        }
        // SAFETY: no submission is pending (each `run` waits, and a wait
        // that timed out marked the device hung). Null handles (a
        // half-built OneShot) are ignored by vkDestroy*.
        unsafe {
            self.device.raw.destroy_fence(self.fence, None);
            self.device.raw.destroy_command_pool(self.pool, None);
        }
    }
}
