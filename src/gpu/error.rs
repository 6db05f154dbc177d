use ash::vk;

const INSTALL_HINT: &str =
    "on Debian or Ubuntu run `sudo apt-get install libvulkan1 mesa-vulkan-drivers` \
     for lavapipe (Vulkan on the CPU), or render with --backend cpu";

#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    #[error("cannot load the Vulkan loader (libvulkan.so.1): {0}; {INSTALL_HINT}")]
    NoLoader(String),
    #[error("no Vulkan 1.2 device with a compute queue was found; {INSTALL_HINT}")]
    NoDevice,
    #[error("no Vulkan device matches \"{wanted}\"; the devices are: {available}")]
    NoMatchingDevice { wanted: String, available: String },
    #[error("validation was asked for but VK_LAYER_KHRONOS_validation is not installed (Debian: apt-get install vulkan-validationlayers)")]
    NoValidationLayer,
    #[error("{what} failed: {result}")]
    Vk {
        what: &'static str,
        result: vk::Result,
    },
    #[error("no memory type for {0} on this device")]
    NoMemoryType(&'static str),
    /// glslang's errors, one a line: the first line says what and where.
    #[error("the shader does not compile: {0}")]
    Shader(String),
    #[error("the Vulkan validation layer reported {} message(s):\n{}", .0.len(), .0.join("\n"))]
    Validation(Vec<String>),
    #[error("{0}")]
    Unsupported(String),
    #[error("the shader's loops were cut short at pixel ({x}, {y}) of {device}: the scene needs more loop iterations per pixel than the driver allows (llvmpipe: about 65,535), so the image would be wrong; render with --accel bvh, fewer samples or a smaller max_depth, or with --backend cpu")]
    LoopBudget { x: u32, y: u32, device: String },
    #[error("the GPU did not finish the tile at ({x}, {y}), {w}x{h} pixels, within {seconds:.3} s; stopped (set another limit with --timeout SECONDS)")]
    Timeout {
        x: u32,
        y: u32,
        w: u32,
        h: u32,
        seconds: f64,
    },
    #[error("an earlier render on this renderer timed out; open a new one")]
    Lost,
    #[error("the shader wrote nothing at pixel ({x}, {y}): a main shader must write every pixel of its tile, with alpha 1 (docs/shaders.md, The loop budget)")]
    Unwritten { x: u32, y: u32 },
}

/// Attaches what was being done to a raw Vulkan result.
pub trait VkContext<T> {
    fn doing(self, what: &'static str) -> Result<T, GpuError>;
}

impl<T> VkContext<T> for Result<T, vk::Result> {
    fn doing(self, what: &'static str) -> Result<T, GpuError> {
        self.map_err(|result| GpuError::Vk { what, result })
    }
}
