//! The compute pipeline: shader module, descriptor layout, pipeline layout,
//! pipeline, and the descriptor set that binds the scene's buffers and
//! texel buffers.

use std::sync::Arc;

use ash::vk;

use super::device::Device;
use crate::gpu::error::{GpuError, VkContext};

/// One descriptor set of buffers and texel buffers, at the given bindings
/// and types.
pub struct ComputePipeline {
    pub pipeline: vk::Pipeline,
    pub layout: vk::PipelineLayout,
    pub set_layout: vk::DescriptorSetLayout,
    pub pool: vk::DescriptorPool,
    pub set: vk::DescriptorSet,
    bindings: Vec<(u32, vk::DescriptorType)>,
    device: Arc<Device>,
}

impl ComputePipeline {
    /// Binds the pipeline and its descriptor set for the dispatches after.
    ///
    /// # Safety
    /// `cb` is a command buffer of `dev` (this pipeline's device) in the
    /// recording state.
    pub unsafe fn record_bind(&self, dev: &ash::Device, cb: vk::CommandBuffer) {
        // SAFETY: the caller's contract; the pipeline, layout and set are live.
        unsafe {
            dev.cmd_bind_pipeline(cb, vk::PipelineBindPoint::COMPUTE, self.pipeline);
            dev.cmd_bind_descriptor_sets(
                cb,
                vk::PipelineBindPoint::COMPUTE,
                self.layout,
                0,
                &[self.set],
                &[],
            );
        }
    }

    /// The pipeline of `spirv`'s `main`, with one descriptor set of
    /// `bindings` and `push_constant_bytes` of push constants.
    pub fn new(
        device: &Arc<Device>,
        spirv: &[u32],
        bindings: &[(u32, vk::DescriptorType)],
        push_constant_bytes: u32,
        cache: vk::PipelineCache,
    ) -> Result<Self, GpuError> {
        let mut p = Self {
            pipeline: vk::Pipeline::null(),
            layout: vk::PipelineLayout::null(),
            set_layout: vk::DescriptorSetLayout::null(),
            pool: vk::DescriptorPool::null(),
            set: vk::DescriptorSet::null(),
            bindings: bindings.to_vec(),
            device: device.clone(),
        };
        let device = &device.raw;
        // Built up field by field so that Drop frees whatever was made if a
        // later step fails.
        let layout_bindings: Vec<_> = bindings
            .iter()
            .map(|(b, ty)| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(*b)
                    .descriptor_type(*ty)
                    .descriptor_count(1)
                    .stage_flags(vk::ShaderStageFlags::COMPUTE)
            })
            .collect();
        let set_info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&layout_bindings);
        // SAFETY: a live device; the create infos below and what they point
        // to live until each call returns.
        p.set_layout = unsafe { device.create_descriptor_set_layout(&set_info, None) }
            .doing("vkCreateDescriptorSetLayout")?;

        let ranges = [vk::PushConstantRange::default()
            .stage_flags(vk::ShaderStageFlags::COMPUTE)
            .offset(0)
            .size(push_constant_bytes)];
        let set_layouts = [p.set_layout];
        let layout_info = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(&set_layouts)
            .push_constant_ranges(&ranges);
        // SAFETY: as above; the set layout was made just above.
        p.layout = unsafe { device.create_pipeline_layout(&layout_info, None) }
            .doing("vkCreatePipelineLayout")?;

        let module_info = vk::ShaderModuleCreateInfo::default().code(spirv);
        // SAFETY: `spirv` is whole SPIR-V words from glslang (the driver
        // validates the module; the validation layer checks it in tests).
        let module = unsafe { device.create_shader_module(&module_info, None) }
            .doing("vkCreateShaderModule")?;
        let stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(module)
            .name(c"main");
        let info = vk::ComputePipelineCreateInfo::default()
            .stage(stage)
            .layout(p.layout);
        // SAFETY: the module, layout and cache are live handles of this
        // device; the module may be destroyed once the pipeline is created.
        let created = unsafe { device.create_compute_pipelines(cache, &[info], None) };
        // SAFETY: as above.
        unsafe { device.destroy_shader_module(module, None) };
        p.pipeline = created.map_err(|(_, result)| GpuError::Vk {
            what: "vkCreateComputePipelines",
            result,
        })?[0];

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
        let pool_info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(1)
            .pool_sizes(&sizes);
        // SAFETY: a live device; the sizes cover the set's bindings.
        p.pool = unsafe { device.create_descriptor_pool(&pool_info, None) }
            .doing("vkCreateDescriptorPool")?;
        let alloc = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(p.pool)
            .set_layouts(&set_layouts);
        // SAFETY: the pool was sized for this one set.
        p.set = unsafe { device.allocate_descriptor_sets(&alloc) }
            .doing("vkAllocateDescriptorSets")?[0];
        Ok(p)
    }

    /// Points each binding at what it sees; `resources` follows the order
    /// of the bindings given to `new`.
    ///
    /// # Safety
    /// The set is not in use by a pending submission, and the buffers and
    /// views outlive every submission that uses the set until it is bound
    /// again (the set refers to them by handle, not by Rust borrow).
    pub unsafe fn bind(&self, resources: &[Resource]) {
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

/// What one binding of the set sees: a whole buffer, or a texel buffer's
/// view.
#[derive(Debug, Clone, Copy)]
pub enum Resource {
    Buffer(vk::Buffer),
    Texels(vk::BufferView),
}

impl Drop for ComputePipeline {
    fn drop(&mut self) {
        // A hung device may still run it: leaked, as the device is.
        if self.device.hung() {
            return;
        }
        let d = &self.device.raw;
        // SAFETY: no submission uses the pipeline (each `OneShot::run` waits,
        // and a wait that timed out marked the device hung). Null handles
        // are ignored by vkDestroy*, so a half-built pipeline frees cleanly.
        unsafe {
            d.destroy_descriptor_pool(self.pool, None);
            d.destroy_pipeline(self.pipeline, None);
            d.destroy_pipeline_layout(self.layout, None);
            d.destroy_descriptor_set_layout(self.set_layout, None);
        }
    }
}
