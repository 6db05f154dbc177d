//! Buffers: host-visible ones, mapped for their whole life, and
//! device-local ones filled through a staging buffer.

use ash::vk;

use super::command::OneShot;
use super::device::Device;
use crate::gpu::error::{GpuError, VkContext};

pub struct Buffer {
    pub raw: vk::Buffer,
    pub memory: vk::DeviceMemory,
    pub size: vk::DeviceSize,
    /// Null for a device-local buffer, which the host does not map.
    mapped: *mut u8,
    device: ash::Device,
}

impl Buffer {
    /// A buffer of `size` bytes (at least 16: Vulkan has no empty buffers),
    /// in memory the host can map; device-local where the device offers both.
    pub fn new(
        device: &Device,
        size: vk::DeviceSize,
        usage: vk::BufferUsageFlags,
        what: &'static str,
    ) -> Result<Self, GpuError> {
        Self::allocate(device, size, usage, what, true)
    }

    /// A buffer of `size` bytes in device-local memory, which the host does
    /// not map: a discrete GPU's own memory where it has memory the host
    /// cannot see, else any device-local memory. Filled by [`Buffer::staged`].
    pub fn device_local(
        device: &Device,
        size: vk::DeviceSize,
        usage: vk::BufferUsageFlags,
        what: &'static str,
    ) -> Result<Self, GpuError> {
        Self::allocate(device, size, usage, what, false)
    }

    fn allocate(
        device: &Device,
        size: vk::DeviceSize,
        usage: vk::BufferUsageFlags,
        what: &'static str,
        host: bool,
    ) -> Result<Self, GpuError> {
        let size = size.max(16);
        let raw_device = &device.raw;
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        let raw = unsafe { raw_device.create_buffer(&info, None) }.doing("vkCreateBuffer")?;
        let needs = unsafe { raw_device.get_buffer_memory_requirements(raw) };
        let mapped_flags =
            vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT;
        let local = vk::MemoryPropertyFlags::DEVICE_LOCAL;
        let bits = needs.memory_type_bits;
        let type_index = if host {
            device
                .memory_type(bits, mapped_flags | local)
                .or_else(|| device.memory_type(bits, mapped_flags))
        } else {
            device
                .memory_type_without(bits, local, vk::MemoryPropertyFlags::HOST_VISIBLE)
                .or_else(|| device.memory_type(bits, local))
        };
        let Some(type_index) = type_index else {
            unsafe { raw_device.destroy_buffer(raw, None) };
            return Err(GpuError::NoMemoryType(what));
        };
        let alloc = vk::MemoryAllocateInfo::default()
            .allocation_size(needs.size)
            .memory_type_index(type_index);
        let memory = match unsafe { raw_device.allocate_memory(&alloc, None) } {
            Ok(m) => m,
            Err(result) => {
                unsafe { raw_device.destroy_buffer(raw, None) };
                return Err(GpuError::Vk {
                    what: "vkAllocateMemory",
                    result,
                });
            }
        };
        let mapped = unsafe {
            raw_device.bind_buffer_memory(raw, memory, 0).and_then(|_| {
                if host {
                    raw_device.map_memory(memory, 0, vk::WHOLE_SIZE, vk::MemoryMapFlags::empty())
                } else {
                    Ok(std::ptr::null_mut())
                }
            })
        };
        match mapped {
            Ok(ptr) => Ok(Self {
                raw,
                memory,
                size,
                mapped: ptr.cast(),
                device: raw_device.clone(),
            }),
            Err(result) => {
                unsafe {
                    raw_device.destroy_buffer(raw, None);
                    raw_device.free_memory(memory, None);
                }
                Err(GpuError::Vk {
                    what: "vkMapMemory",
                    result,
                })
            }
        }
    }

    /// A buffer holding `data`.
    pub fn with_data<T: bytemuck::Pod>(
        device: &Device,
        data: &[T],
        usage: vk::BufferUsageFlags,
        what: &'static str,
    ) -> Result<Self, GpuError> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let buffer = Self::new(device, bytes.len() as vk::DeviceSize, usage, what)?;
        buffer.write(bytes);
        Ok(buffer)
    }

    /// A device-local buffer holding `data`, copied in through a staging
    /// buffer by one submission of `commands`, which this waits on.
    pub fn staged<T: bytemuck::Pod>(
        device: &Device,
        commands: &OneShot,
        data: &[T],
        usage: vk::BufferUsageFlags,
        what: &'static str,
    ) -> Result<Self, GpuError> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let size = bytes.len() as vk::DeviceSize;
        let buffer = Self::device_local(
            device,
            size,
            usage | vk::BufferUsageFlags::TRANSFER_DST,
            what,
        )?;
        let staging = Self::with_data(device, bytes, vk::BufferUsageFlags::TRANSFER_SRC, what)?;
        let copy = vk::BufferCopy::default().size(staging.size.min(buffer.size));
        commands.run(std::time::Duration::from_secs(60), |d, cb| unsafe {
            d.cmd_copy_buffer(cb, staging.raw, buffer.raw, &[copy]);
            // The copy is done before any shader reads the buffer.
            let barrier = vk::MemoryBarrier::default()
                .src_access_mask(vk::AccessFlags::TRANSFER_WRITE)
                .dst_access_mask(vk::AccessFlags::SHADER_READ | vk::AccessFlags::UNIFORM_READ);
            d.cmd_pipeline_barrier(
                cb,
                vk::PipelineStageFlags::TRANSFER,
                vk::PipelineStageFlags::COMPUTE_SHADER,
                vk::DependencyFlags::empty(),
                &[barrier],
                &[],
                &[],
            );
        })?;
        Ok(buffer)
    }

    /// Writes `data` at the start of the buffer, while the GPU does not use it.
    pub fn write<T: bytemuck::Pod>(&self, data: &[T]) {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        assert!(!self.mapped.is_null(), "write to a device-local buffer");
        assert!(
            bytes.len() as vk::DeviceSize <= self.size,
            "write past the end of a buffer"
        );
        // SAFETY: the mapping covers `size` bytes; the caller waited on the
        // fence of the last work that used the buffer.
        unsafe { std::ptr::copy_nonoverlapping(bytes.as_ptr(), self.mapped, bytes.len()) };
    }

    /// The mapped contents, read after the GPU's writes were made visible.
    pub fn read<T: bytemuck::Pod>(&self, count: usize) -> &[T] {
        let bytes = count * std::mem::size_of::<T>();
        assert!(!self.mapped.is_null(), "read of a device-local buffer");
        assert!(
            bytes as vk::DeviceSize <= self.size,
            "read past the end of a buffer"
        );
        // SAFETY: mapped for the buffer's life, coherent, aligned to at least
        // minMemoryMapAlignment (>= 64), and the caller waited on the fence.
        let slice = unsafe { std::slice::from_raw_parts(self.mapped, bytes) };
        bytemuck::cast_slice(slice)
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        unsafe {
            if !self.mapped.is_null() {
                self.device.unmap_memory(self.memory);
            }
            self.device.destroy_buffer(self.raw, None);
            self.device.free_memory(self.memory, None);
        }
    }
}
