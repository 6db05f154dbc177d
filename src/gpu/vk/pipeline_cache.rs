//! A Vulkan pipeline cache kept in a file between runs. The driver checks
//! the data's header (vendor, device, driver version) and ignores data made
//! elsewhere, so a stale or foreign file costs nothing but a cold compile.

use std::path::{Path, PathBuf};

use ash::vk;

use crate::gpu::error::{GpuError, VkContext};

pub struct PipelineCache {
    pub raw: vk::PipelineCache,
    file: Option<PathBuf>,
    device: ash::Device,
}

impl PipelineCache {
    /// A cache seeded from `file` where it exists; saved back on drop.
    pub fn new(device: &ash::Device, file: Option<&Path>) -> Result<Self, GpuError> {
        let data = file.and_then(|f| std::fs::read(f).ok()).unwrap_or_default();
        let info = vk::PipelineCacheCreateInfo::default().initial_data(&data);
        let raw =
            unsafe { device.create_pipeline_cache(&info, None) }.doing("vkCreatePipelineCache")?;
        Ok(Self {
            raw,
            file: file.map(Path::to_owned),
            device: device.clone(),
        })
    }
}

impl Drop for PipelineCache {
    fn drop(&mut self) {
        if let Some(file) = &self.file {
            if let Ok(data) = unsafe { self.device.get_pipeline_cache_data(self.raw) } {
                // A cache that cannot be written is only a slower next start.
                let _ = file.parent().map(std::fs::create_dir_all);
                let _ = std::fs::write(file, data);
            }
        }
        unsafe { self.device.destroy_pipeline_cache(self.raw, None) };
    }
}
