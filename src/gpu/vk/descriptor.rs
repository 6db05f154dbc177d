//! A descriptor set, in a pool of its own: what one prepared scene binds
//! to a pipeline, so that two scenes prepared with one pipeline never
//! rebind each other's buffers.

use std::sync::Arc;

use ash::vk;

use super::device::Device;
use super::pipeline::ComputePipeline;
use crate::gpu::error::{GpuError, VkContext};

/// One set of a pipeline's layout, and the pool it came from.
pub struct DescriptorSet {
    pub set: vk::DescriptorSet,
    pub pool: vk::DescriptorPool,
    bindings: Vec<(u32, vk::DescriptorType)>,
    device: Arc<Device>,
}

/// What one binding of the set sees: a whole buffer, or a texel buffer's
/// view.
#[derive(Debug, Clone, Copy)]
pub enum Resource {
    Buffer(vk::Buffer),
    Texels(vk::BufferView),
}

impl DescriptorSet {
    /// A set for `pipeline`'s layout, its bindings not yet written.
    pub fn new(device: &Arc<Device>, pipeline: &ComputePipeline) -> Result<Self, GpuError> {
        let bindings = pipeline.bindings.clone();
        let count = |t| bindings.iter().filter(|(_, x)| *x == t).count() as u32;
        let sizes: Vec<_> = [
            vk::DescriptorType::UNIFORM_BUFFER,
            vk::DescriptorType::STORAGE_BUFFER,
            vk::DescriptorType::UNIFORM_TEXEL_BUFFER,
        ]
        .into_iter()
        .filter(|t| count(*t) > 0)
        .map(|t| {
            vk::DescriptorPoolSize::default()
                .ty(t)
                .descriptor_count(count(t))
        })
        .collect();
        let mut s = Self {
            set: vk::DescriptorSet::null(),
            pool: vk::DescriptorPool::null(),
            bindings,
            device: device.clone(),
        };
        let pool_info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(1)
            .pool_sizes(&sizes);
        // SAFETY: a live device; the sizes cover the set's bindings.
        s.pool = unsafe { device.raw.create_descriptor_pool(&pool_info, None) }
            .doing("vkCreateDescriptorPool")?;
        let layouts = [pipeline.set_layout];
        let alloc = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(s.pool)
            .set_layouts(&layouts);
        // SAFETY: the pool was sized for this one set; the layout is live.
        s.set = unsafe { device.raw.allocate_descriptor_sets(&alloc) }
            .doing("vkAllocateDescriptorSets")?[0];
        Ok(s)
    }

    /// Points each binding at what it sees; `resources` follows the order
    /// of the pipeline's bindings.
    ///
    /// # Safety
    /// The set is not in use by a pending submission, and the buffers and
    /// views outlive every submission that uses the set until it is written
    /// again (the set refers to them by handle, not by Rust borrow).
    pub unsafe fn write(&self, resources: &[Resource]) {
        assert_eq!(
            resources.len(),
            self.bindings.len(),
            "one resource per binding"
        );
        let infos: Vec<[vk::DescriptorBufferInfo; 1]> = resources
            .iter()
            .map(|r| {
                [vk::DescriptorBufferInfo::default()
                    .buffer(match r {
                        Resource::Buffer(b) => *b,
                        Resource::Texels(_) => vk::Buffer::null(),
                    })
                    .offset(0)
                    .range(vk::WHOLE_SIZE)]
            })
            .collect();
        let views: Vec<[vk::BufferView; 1]> = resources
            .iter()
            .map(|r| match r {
                Resource::Texels(v) => [*v],
                Resource::Buffer(_) => [vk::BufferView::null()],
            })
            .collect();
        let writes: Vec<_> = resources
            .iter()
            .zip(infos.iter().zip(&views))
            .zip(&self.bindings)
            .map(|((r, (info, view)), (binding, ty))| {
                let write = vk::WriteDescriptorSet::default()
                    .dst_set(self.set)
                    .dst_binding(*binding)
                    .descriptor_type(*ty);
                match r {
                    Resource::Buffer(_) => write.buffer_info(info),
                    Resource::Texels(_) => write.texel_buffer_view(view),
                }
            })
            .collect();
        // SAFETY: the caller's contract above; the set, buffers and views
        // are live handles of this device.
        unsafe { self.device.raw.update_descriptor_sets(&writes, &[]) };
    }
}

impl Drop for DescriptorSet {
    fn drop(&mut self) {
        // A hung device may still read it: leaked, as the device is.
        if self.device.hung() {
            return;
        }
        // SAFETY: no submission uses the set (each `OneShot::run` waits, and
        // a wait that timed out marked the device hung); freeing the pool
        // frees its set; a null pool is ignored.
        unsafe { self.device.raw.destroy_descriptor_pool(self.pool, None) };
    }
}
