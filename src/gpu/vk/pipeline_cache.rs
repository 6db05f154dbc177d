//! A Vulkan pipeline cache kept in a file between runs, sealed with a
//! checksum (`gpu::sealed`). The driver checks the data's header (vendor,
//! device, driver version) and ignores data made elsewhere, so a stale or
//! foreign file costs nothing but a cold compile.

use std::path::{Path, PathBuf};

use std::sync::Arc;

use ash::vk;

use super::device::Device;
use crate::gpu::error::{GpuError, VkContext};

/// A pipeline cache and the file it is saved to.
pub struct PipelineCache {
    pub raw: vk::PipelineCache,
    file: Option<PathBuf>,
    device: Arc<Device>,
}

impl PipelineCache {
    /// A cache seeded from `file` where it exists; saved back on drop.
    pub fn new(device: &Arc<Device>, file: Option<&Path>) -> Result<Self, GpuError> {
        // Sealed (`gpu::sealed`): the driver checks the data's header alone,
        // and damaged data past it is the driver's to misread.
        let data = file
            .and_then(|f| crate::gpu::sealed::read(f, "the Vulkan pipeline cache"))
            .unwrap_or_default();
        let info = vk::PipelineCacheCreateInfo::default().initial_data(&data);
        // SAFETY: a live device; initial data of any content is allowed (the
        // driver checks its header and ignores data that is not its own).
        let raw = unsafe { device.raw.create_pipeline_cache(&info, None) }
            .doing("vkCreatePipelineCache")?;
        Ok(Self {
            raw,
            file: file.map(Path::to_owned),
            device: device.clone(),
        })
    }
}

impl Drop for PipelineCache {
    fn drop(&mut self) {
        let d = &self.device.raw;
        if let Some(file) = &self.file {
            // SAFETY: a live cache of a live device.
            if let Ok(data) = unsafe { d.get_pipeline_cache_data(self.raw) } {
                crate::gpu::sealed::write(file, &data);
            }
        }
        // SAFETY: pipeline creation, the cache's only user, is synchronous.
        unsafe { d.destroy_pipeline_cache(self.raw, None) };
    }
}
