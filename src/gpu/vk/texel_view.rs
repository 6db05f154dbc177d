//! Texel buffer views: a buffer seen by the shader as an array of texels
//! (`utextureBuffer`, read with `texelFetch`). llvmpipe fetches a texel for
//! all lanes of a SIMD group at once, where it reads a storage buffer at a
//! per-lane index lane by lane (docs/performance.md, Texel buffers).

use std::sync::Arc;

use ash::vk;

use super::buffer::Buffer;
use super::device::Device;
use crate::gpu::error::{GpuError, VkContext};

/// The texel format of every texel buffer glint binds: four 32-bit words,
/// which the shader turns back into floats, doubles or integers bit for
/// bit. An integer format, so that no device flushes a denormal or
/// quietens a NaN on the way (a leaf word read as a float is a denormal).
pub const TEXEL_FORMAT: vk::Format = vk::Format::R32G32B32A32_UINT;

/// Bytes a texel of `TEXEL_FORMAT`.
pub const TEXEL_BYTES: u64 = 16;

/// A buffer and the view that makes it a texel buffer. The view is
/// destroyed before the buffer it sees.
pub struct TexelBuffer {
    pub view: vk::BufferView,
    pub buffer: Buffer,
}

impl TexelBuffer {
    /// A view of the whole of `buffer` (a multiple of `TEXEL_BYTES`, made
    /// with `UNIFORM_TEXEL_BUFFER` usage) as texels of `TEXEL_FORMAT`.
    pub fn new(device: &Arc<Device>, buffer: Buffer) -> Result<Self, GpuError> {
        debug_assert_eq!(buffer.size % TEXEL_BYTES, 0);
        let info = vk::BufferViewCreateInfo::default()
            .buffer(buffer.raw)
            .format(TEXEL_FORMAT)
            .offset(0)
            .range(buffer.size);
        // SAFETY: a live device and buffer; the range is the buffer's size.
        let view =
            unsafe { device.raw.create_buffer_view(&info, None) }.doing("vkCreateBufferView")?;
        Ok(Self { view, buffer })
    }
}

impl Drop for TexelBuffer {
    fn drop(&mut self) {
        if self.buffer.device().hung() {
            return;
        }
        // SAFETY: no submission uses the view (as for its buffer: each
        // `OneShot::run` waits, and one that timed out leaks both); the
        // buffer is freed after this, by its own Drop.
        unsafe {
            self.buffer
                .device()
                .raw
                .destroy_buffer_view(self.view, None)
        };
    }
}
