//! One command buffer, recorded and submitted once at a time, waited on with
//! a fence.

use ash::vk;

use super::device::Device;
use crate::gpu::error::{GpuError, VkContext};

pub struct OneShot {
    pub fence: vk::Fence,
    pub buffer: vk::CommandBuffer,
    pub pool: vk::CommandPool,
    queue: vk::Queue,
    device: ash::Device,
}

impl OneShot {
    pub fn new(device: &Device) -> Result<Self, GpuError> {
        let raw = &device.raw;
        let mut s = Self {
            fence: vk::Fence::null(),
            buffer: vk::CommandBuffer::null(),
            pool: vk::CommandPool::null(),
            queue: device.queue,
            device: raw.clone(),
        };
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(device.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        s.pool =
            unsafe { raw.create_command_pool(&pool_info, None) }.doing("vkCreateCommandPool")?;
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(s.pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        s.buffer =
            unsafe { raw.allocate_command_buffers(&alloc) }.doing("vkAllocateCommandBuffers")?[0];
        s.fence = unsafe { raw.create_fence(&vk::FenceCreateInfo::default(), None) }
            .doing("vkCreateFence")?;
        Ok(s)
    }

    /// Records with `record`, submits, and waits for the GPU to finish, at
    /// most `timeout`. On `Err(vk::Result::TIMEOUT)` (as `GpuError::Vk`)
    /// the work may still be running: the caller must neither free what it
    /// uses nor submit again before the device is idle.
    pub fn run(
        &self,
        timeout: std::time::Duration,
        record: impl FnOnce(&ash::Device, vk::CommandBuffer),
    ) -> Result<(), GpuError> {
        let d = &self.device;
        unsafe {
            d.reset_command_buffer(self.buffer, vk::CommandBufferResetFlags::empty())
                .doing("vkResetCommandBuffer")?;
            let begin = vk::CommandBufferBeginInfo::default()
                .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            d.begin_command_buffer(self.buffer, &begin)
                .doing("vkBeginCommandBuffer")?;
            record(d, self.buffer);
            d.end_command_buffer(self.buffer)
                .doing("vkEndCommandBuffer")?;
            let buffers = [self.buffer];
            let submit = vk::SubmitInfo::default().command_buffers(&buffers);
            d.queue_submit(self.queue, &[submit], self.fence)
                .doing("vkQueueSubmit")?;
            let nanos = u64::try_from(timeout.as_nanos()).unwrap_or(u64::MAX);
            d.wait_for_fences(&[self.fence], true, nanos)
                .doing("vkWaitForFences")?;
            d.reset_fences(&[self.fence]).doing("vkResetFences")?;
        }
        Ok(())
    }
}

impl Drop for OneShot {
    fn drop(&mut self) {
        unsafe {
            self.device.destroy_fence(self.fence, None);
            self.device.destroy_command_pool(self.pool, None);
        }
    }
}
