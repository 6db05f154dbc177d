//! The compute pipeline: shader module, descriptor set layout, pipeline
//! layout and pipeline. The sets that bind buffers to it are each
//! prepared scene's own (descriptor.rs).

use std::sync::Arc;

use ash::vk;

use super::device::Device;
use crate::gpu::error::{GpuError, VkContext};

/// A pipeline of one descriptor set of buffers and texel buffers, at the
/// given bindings and types.
pub struct ComputePipeline {
    pub pipeline: vk::Pipeline,
    pub layout: vk::PipelineLayout,
    pub set_layout: vk::DescriptorSetLayout,
    /// The set layout's bindings and types, in order.
    pub bindings: Vec<(u32, vk::DescriptorType)>,
    device: Arc<Device>,
}

impl ComputePipeline {
    /// Binds the pipeline and `set` for the dispatches after.
    ///
    /// # Safety
    /// `cb` is a command buffer of `dev` (this pipeline's device) in the
    /// recording state; `set` was made for this pipeline's set layout.
    pub unsafe fn record_bind(
        &self,
        dev: &ash::Device,
        cb: vk::CommandBuffer,
        set: vk::DescriptorSet,
    ) {
        // SAFETY: the caller's contract; the pipeline, layout and set are live.
        unsafe {
            dev.cmd_bind_pipeline(cb, vk::PipelineBindPoint::COMPUTE, self.pipeline);
            dev.cmd_bind_descriptor_sets(
                cb,
                vk::PipelineBindPoint::COMPUTE,
                self.layout,
                0,
                &[set],
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
        p.pipeline =
            created.map_err(|(_, result)| GpuError::vk("vkCreateComputePipelines", result))?[0];

        Ok(p)
    }
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
            d.destroy_pipeline(self.pipeline, None);
            d.destroy_pipeline_layout(self.layout, None);
            d.destroy_descriptor_set_layout(self.set_layout, None);
        }
    }
}
