//! Host-visible buffers, mapped for their whole life.

use ash::vk;

use super::device::Device;
use crate::gpu::error::{GpuError, VkContext};

pub struct Buffer {
    pub raw: vk::Buffer,
    pub memory: vk::DeviceMemory,
    pub size: vk::DeviceSize,
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
        let size = size.max(16);
        let raw_device = &device.raw;
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        let raw = unsafe { raw_device.create_buffer(&info, None) }.doing("vkCreateBuffer")?;
        let needs = unsafe { raw_device.get_buffer_memory_requirements(raw) };
        let host = vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT;
        let Some(type_index) = device
            .memory_type(
                needs.memory_type_bits,
                host | vk::MemoryPropertyFlags::DEVICE_LOCAL,
            )
            .or_else(|| device.memory_type(needs.memory_type_bits, host))
        else {
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
                raw_device.map_memory(memory, 0, vk::WHOLE_SIZE, vk::MemoryMapFlags::empty())
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
        // SAFETY: the mapping covers `size` >= bytes.len() bytes and nothing
        // else aliases it while the GPU is idle.
        unsafe { std::ptr::copy_nonoverlapping(bytes.as_ptr(), buffer.mapped, bytes.len()) };
        Ok(buffer)
    }

    /// The mapped contents, read after the GPU's writes were made visible.
    pub fn read<T: bytemuck::Pod>(&self, count: usize) -> &[T] {
        let bytes = count * std::mem::size_of::<T>();
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
            self.device.unmap_memory(self.memory);
            self.device.destroy_buffer(self.raw, None);
            self.device.free_memory(self.memory, None);
        }
    }
}
