//! Buffers: host-visible ones, mapped for their whole life, and
//! device-local ones filled through a staging buffer.

use std::sync::Arc;

use ash::vk;

use super::command::{memory_barrier, Completed, OneShot};
use super::device::Device;
use crate::gpu::error::{GpuError, VkContext};

/// One buffer [`Buffer::overwrite`] writes: the buffer, the bytes to
/// write at its start, and what fills them.
pub type Overwrite<'a> = (&'a Buffer, usize, Box<dyn FnOnce(&mut [u8]) + 'a>);

/// A buffer and its own memory, which keeps its device alive.
pub struct Buffer {
    pub raw: vk::Buffer,
    pub memory: vk::DeviceMemory,
    pub size: vk::DeviceSize,
    /// Null for a device-local buffer, which the host does not map.
    mapped: *mut u8,
    device: Arc<Device>,
}

// SAFETY: `mapped` is this buffer's own mapping of its own memory: Vulkan
// maps memory for the process, not for a thread, so the pointer stays valid
// wherever the buffer moves, and every access through it is bounded by the
// borrows of `fill_with` and `read`, which hold on any thread. (A prepared
// scene moves to the thread a host renders on: the Python module's.)
unsafe impl Send for Buffer {}

impl Buffer {
    /// A buffer of `size` bytes (at least 16: Vulkan has no empty buffers),
    /// in memory the host can map; device-local where the device offers both.
    pub fn new(
        device: &Arc<Device>,
        size: vk::DeviceSize,
        usage: vk::BufferUsageFlags,
        what: &'static str,
    ) -> Result<Self, GpuError> {
        Self::allocate(device, size, usage, what, true)
    }

    /// A buffer of `size` bytes in device-local memory, which the host does
    /// not map: a discrete GPU's own memory where it has memory the host
    /// cannot see, else any device-local memory. Filled by [`Buffer::staged_written`].
    pub fn device_local(
        device: &Arc<Device>,
        size: vk::DeviceSize,
        usage: vk::BufferUsageFlags,
        what: &'static str,
    ) -> Result<Self, GpuError> {
        Self::allocate(device, size, usage, what, false)
    }

    fn allocate(
        device: &Arc<Device>,
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
        // SAFETY: a live device; size is non-zero.
        let raw = unsafe { raw_device.create_buffer(&info, None) }.doing("vkCreateBuffer")?;
        // SAFETY: `raw` was made from this device just above.
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
            // SAFETY: unused, unbound, and not handed out.
            unsafe { raw_device.destroy_buffer(raw, None) };
            return Err(GpuError::NoMemoryType(what));
        };
        // A buffer the shader reads through its address needs memory that
        // has one.
        let mut flags =
            vk::MemoryAllocateFlagsInfo::default().flags(vk::MemoryAllocateFlags::DEVICE_ADDRESS);
        let mut alloc = vk::MemoryAllocateInfo::default()
            .allocation_size(needs.size)
            .memory_type_index(type_index);
        if usage.contains(vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS) {
            alloc = alloc.push_next(&mut flags);
        }
        // SAFETY: a memory type index the device listed for this buffer.
        let memory = match unsafe { raw_device.allocate_memory(&alloc, None) } {
            Ok(m) => m,
            Err(result) => {
                // SAFETY: unused, unbound, and not handed out.
                unsafe { raw_device.destroy_buffer(raw, None) };
                return Err(GpuError::vk("vkAllocateMemory", result));
            }
        };
        // SAFETY: fresh memory of the size and type the buffer needs, bound
        // at offset 0; only host-visible memory is mapped.
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
                device: device.clone(),
            }),
            Err(result) => {
                // SAFETY: unused and not handed out; freeing memory unmaps it.
                unsafe {
                    raw_device.destroy_buffer(raw, None);
                    raw_device.free_memory(memory, None);
                }
                Err(GpuError::vk("vkMapMemory", result))
            }
        }
    }

    /// A buffer holding `data`.
    pub fn with_data<T: bytemuck::Pod>(
        device: &Arc<Device>,
        data: &[T],
        usage: vk::BufferUsageFlags,
        what: &'static str,
    ) -> Result<Self, GpuError> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        Self::written(
            device,
            bytes.len(),
            |dst| dst.copy_from_slice(bytes),
            usage,
            what,
        )
    }

    /// A buffer of `size` bytes that `write` fills in place, through the
    /// mapping: the data is never held anywhere else.
    pub fn written(
        device: &Arc<Device>,
        size: usize,
        write: impl FnOnce(&mut [u8]),
        usage: vk::BufferUsageFlags,
        what: &'static str,
    ) -> Result<Self, GpuError> {
        let buffer = Self::new(device, size as vk::DeviceSize, usage, what)?;
        buffer.fill_with(size, write);
        Ok(buffer)
    }

    /// A device-local buffer of `size` bytes, copied in through a staging
    /// buffer that `write` fills in place, by one submission of `commands`,
    /// which this waits on.
    pub fn staged_written(
        device: &Arc<Device>,
        commands: &mut OneShot,
        size: usize,
        write: impl FnOnce(&mut [u8]),
        usage: vk::BufferUsageFlags,
        what: &'static str,
    ) -> Result<Self, GpuError> {
        let buffer = Self::device_local(
            device,
            size as vk::DeviceSize,
            usage | vk::BufferUsageFlags::TRANSFER_DST,
            what,
        )?;
        match Self::overwrite(device, commands, vec![(&buffer, size, Box::new(write))]) {
            Ok(()) => Ok(buffer),
            Err(e) => {
                if device.hung() {
                    // The copy may still be writing it.
                    std::mem::forget(buffer);
                }
                Err(e)
            }
        }
    }

    /// Writes each of `writes` (a buffer made with `TRANSFER_DST`, the
    /// bytes to write at its start, and what fills them) through a staging
    /// buffer of its own, all copied in by one submission of `commands`,
    /// which this waits on. Buffers the GPU has read are written on the
    /// device, never through their mapping (`fill_with`): a prepared
    /// scene's arrays, updated.
    pub fn overwrite(
        device: &Arc<Device>,
        commands: &mut OneShot,
        writes: Vec<Overwrite<'_>>,
    ) -> Result<(), GpuError> {
        let mut copies = Vec::with_capacity(writes.len());
        for (dst, size, write) in writes {
            assert!(
                size as vk::DeviceSize <= dst.size,
                "write past the end of a buffer"
            );
            let staging = Self::written(
                device,
                size,
                write,
                vk::BufferUsageFlags::TRANSFER_SRC,
                "a staging buffer",
            )?;
            copies.push((staging, dst.raw, size as vk::DeviceSize));
        }
        // SAFETY: every buffer is alive until `run` returns, which waits for
        // the copies (on a timeout the staging buffers are leaked, below);
        // each copy is within both of its buffers.
        let copied = commands.run(std::time::Duration::from_secs(60), |d, cb| unsafe {
            for (staging, dst, size) in copies.iter().filter(|c| c.2 > 0) {
                d.cmd_copy_buffer(
                    cb,
                    staging.raw,
                    *dst,
                    &[vk::BufferCopy::default().size(*size)],
                );
            }
            memory_barrier(
                d,
                cb,
                (
                    vk::PipelineStageFlags::TRANSFER,
                    vk::AccessFlags::TRANSFER_WRITE,
                ),
                (
                    vk::PipelineStageFlags::COMPUTE_SHADER,
                    vk::AccessFlags::SHADER_READ | vk::AccessFlags::UNIFORM_READ,
                ),
            );
        });
        match copied {
            Ok(_) => Ok(()),
            Err(e) => {
                if device.hung() {
                    std::mem::forget(copies);
                }
                Err(e)
            }
        }
    }

    /// The buffer's device address (made with `SHADER_DEVICE_ADDRESS`
    /// usage, on a device with bufferDeviceAddress enabled).
    pub fn address(&self) -> u64 {
        let info = vk::BufferDeviceAddressInfo::default().buffer(self.raw);
        // SAFETY: a live buffer of this device, made with that usage.
        unsafe { self.device.raw.get_buffer_device_address(&info) }
    }

    /// The device the buffer belongs to.
    pub fn device(&self) -> &Arc<Device> {
        &self.device
    }

    /// Writes `bytes` at the start of a buffer just made, which no
    /// command has used yet. (A buffer the GPU has used is filled on the
    /// device, by `vkCmdFillBuffer` or a copy, never from the host.)
    fn fill_with(&self, len: usize, write: impl FnOnce(&mut [u8])) {
        assert!(!self.mapped.is_null(), "write to a device-local buffer");
        assert!(
            len as vk::DeviceSize <= self.size,
            "write past the end of a buffer"
        );
        // SAFETY: the mapping covers `size` bytes, host-visible and
        // coherent, and the buffer is new (private to `written`), so no GPU
        // work can be using it and nothing else aliases the slice.
        let dst = unsafe { std::slice::from_raw_parts_mut(self.mapped, len) };
        write(dst);
    }

    /// The first `count` values of the mapped contents, once the work that
    /// wrote them has finished: `done` is the token of that work's
    /// submission, and the slice lives no longer than it, so no later
    /// submission can write under it. The work must also have made its
    /// writes visible to the host (a barrier to `HOST_READ`).
    pub fn read<'a, T: bytemuck::Pod>(&'a self, done: &Completed<'a>, count: usize) -> &'a [T] {
        let _ = done;
        let bytes = count * std::mem::size_of::<T>();
        assert!(!self.mapped.is_null(), "read of a device-local buffer");
        assert!(
            bytes as vk::DeviceSize <= self.size,
            "read past the end of a buffer"
        );
        // SAFETY: mapped for the buffer's life, coherent, aligned to at least
        // minMemoryMapAlignment (>= 64, which any Pod's alignment divides),
        // `bytes` within the mapping, and no GPU work is running that could
        // write it (`done`, which this borrow outlives).
        let slice = unsafe { std::slice::from_raw_parts(self.mapped, bytes) };
        bytemuck::cast_slice(slice)
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        // A hung device's work may still read and write it: leaked, as the
        // device is.
        if self.device.hung() {
            return;
        }
        let d = &self.device.raw;
        // SAFETY: the device is alive (this holds it); no submission uses
        // the buffer: each `OneShot::run` waits, and a wait that timed out
        // marked the device hung.
        unsafe {
            if !self.mapped.is_null() {
                d.unmap_memory(self.memory);
            }
            d.destroy_buffer(self.raw, None);
            d.free_memory(self.memory, None);
        }
    }
}
