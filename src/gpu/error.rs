use ash::vk;

const INSTALL_HINT: &str =
    "on Debian or Ubuntu run `sudo apt-get install libvulkan1 mesa-vulkan-drivers` \
     for lavapipe (Vulkan on the CPU), or render with --backend cpu";

/// Why the GPU path could not render; each message says what to do.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// The Vulkan loader library is missing: the loader's own words.
    #[error("cannot load the Vulkan loader (libvulkan.so.1): {0}; {INSTALL_HINT}")]
    NoLoader(String),
    /// No Vulkan 1.2 device with a compute queue.
    #[error("no Vulkan 1.2 device with a compute queue was found; {INSTALL_HINT}")]
    NoDevice,
    /// No device's name contains the one asked for.
    #[error("no Vulkan device matches \"{wanted}\"; the devices are: {available}")]
    NoMatchingDevice {
        /// What `--device` asked for.
        wanted: String,
        /// The devices there are, by name.
        available: String,
    },
    /// Validation was asked for and the Khronos layer is not installed.
    #[error("validation was asked for but VK_LAYER_KHRONOS_validation is not installed (Debian: apt-get install vulkan-validationlayers)")]
    NoValidationLayer,
    /// A Vulkan call failed.
    #[error("{what} failed: {result}")]
    Vk {
        /// The Vulkan call.
        what: &'static str,
        /// What it returned.
        result: VkCode,
    },
    /// The device has no memory of the kind one buffer (named) needs.
    #[error("no memory type for {0} on this device")]
    NoMemoryType(&'static str),
    /// glslang's errors, one a line: the first line says what and where.
    /// Shown as that first line and a count of the rest, so that a render
    /// keeps to one line; `glint shader check` prints them all.
    #[error("the shader does not compile: {}", first_of_log(.0))]
    Shader(String),
    /// The validation layer spoke (with `GpuOptions::validate`): its messages.
    #[error("the Vulkan validation layer reported {} message(s):\n{}", .0.len(), .0.join("\n"))]
    Validation(Vec<String>),
    /// The scene or settings ask for what this device or renderer cannot do.
    #[error("{0}")]
    Unsupported(String),
    /// The driver cut the shader's loops short at a pixel: its image would be wrong.
    #[error("the shader's loops were cut short at pixel ({x}, {y}) of {device}: the scene needs more loop iterations per pixel than the driver allows (llvmpipe: about 65,535), so the image would be wrong; render with --accel bvh, fewer samples or a smaller max_depth, or with --backend cpu")]
    LoopBudget {
        /// The pixel's column.
        x: u32,
        /// The pixel's row.
        y: u32,
        /// The device's name.
        device: String,
    },
    /// A tile did not finish in time; the renderer is then lost (`Lost`).
    #[error("the GPU did not finish the tile at ({x}, {y}), {w}x{h} pixels, within {seconds:.3} s; stopped (set another limit with --timeout SECONDS)")]
    Timeout {
        /// The tile's left column.
        x: u32,
        /// The tile's top row.
        y: u32,
        /// The tile's width.
        w: u32,
        /// The tile's height.
        h: u32,
        /// The wait that ran out.
        seconds: f64,
    },
    /// The driver did not finish its compile of a new pipeline (its first
    /// dispatch, which shades no pixel) in time; the renderer is then lost.
    #[error("the Vulkan driver did not finish compiling the shader within {seconds:.0} s (its first dispatch, which shades no pixel); the device is taken to be hung")]
    CompileTimeout {
        /// The wait that ran out.
        seconds: f64,
    },
    /// Opening the Vulkan loader, instance and device took longer than its
    /// limit (`vk::bounded::OPEN_LIMIT`).
    #[error("opening the Vulkan device did not finish within {seconds:.0} s: a driver manifest or library the loader reads may be a FIFO or a driver may hang (see VK_DRIVER_FILES and the manifests in /usr/share/vulkan/icd.d); stopped")]
    OpenTimeout {
        /// The limit that ran out.
        seconds: f64,
    },
    /// The render was stopped between tiles ([`super::Prepared::stop_when`]).
    #[error("interrupted")]
    Interrupted,
    /// An earlier wait on this device timed out: nothing more is submitted to it.
    #[error("an earlier render on this renderer timed out; open a new one")]
    Lost,
    /// A main shader left a pixel of its tile unwritten.
    #[error("the shader wrote nothing at pixel ({x}, {y}): a main shader must write every pixel of its tile, with alpha 1 (docs/shaders.md, The loop budget)")]
    Unwritten {
        /// The pixel's column.
        x: u32,
        /// The pixel's row.
        y: u32,
    },
    /// The device returned a pixel whose alpha the shader never writes
    /// (1: its loops finished; 0: they were cut short; NaN: unwritten):
    /// the image is not the shader's, a driver fault.
    #[error("the device returned alpha {alpha} at pixel ({x}, {y}), which no shader run writes (1: finished, 0: cut short): the image is not the shader's")]
    Garbled {
        /// The pixel's column.
        x: u32,
        /// The pixel's row.
        y: u32,
        /// The alpha it had.
        alpha: f32,
    },
    /// The CPU reference that a GPU render is measured against left the
    /// model's bound (`report`, `stability`): no figure is made of it.
    #[error(transparent)]
    Reference(#[from] crate::scene::PastBound),
}

/// A Vulkan result code, by its name and number, so that no type of the
/// Vulkan bindings shows in glint's API.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VkCode {
    /// VkResult's value: negative for an error, 2 (`VK_TIMEOUT`) for a wait
    /// that ran out.
    pub code: i32,
    /// Its name without the `VK_` prefix (`ERROR_DEVICE_LOST`).
    pub name: String,
    /// What the specification says it means, where it says; else the name.
    pub meaning: String,
}

impl std::fmt::Display for VkCode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.meaning)
    }
}

impl From<vk::Result> for VkCode {
    fn from(result: vk::Result) -> Self {
        Self {
            code: result.as_raw(),
            name: format!("{result:?}"),
            meaning: format!("{result}"),
        }
    }
}

impl GpuError {
    /// The error of the Vulkan call `what`, which returned `result`.
    pub(crate) fn vk(what: &'static str, result: vk::Result) -> Self {
        GpuError::Vk {
            what,
            result: result.into(),
        }
    }

    /// Whether this is a wait that ran out (`VK_TIMEOUT`).
    pub(crate) fn timed_out(&self) -> bool {
        matches!(self, GpuError::Vk { result, .. } if result.code == vk::Result::TIMEOUT.as_raw())
    }
}

/// Attaches what was being done to a raw Vulkan result.
pub(crate) trait VkContext<T> {
    /// The error of the call `what`, where the result is one.
    fn doing(self, what: &'static str) -> Result<T, GpuError>;
}

impl<T> VkContext<T> for Result<T, vk::Result> {
    fn doing(self, what: &'static str) -> Result<T, GpuError> {
        self.map_err(|result| GpuError::vk(what, result))
    }
}

impl GpuError {
    /// Whether the renderer that returned it takes no more work: a wait
    /// timed out (the work may still run), or an earlier one did.
    pub fn device_lost(&self) -> bool {
        matches!(
            self,
            GpuError::Timeout { .. } | GpuError::CompileTimeout { .. } | GpuError::Lost
        )
    }
}

/// A compiler log's first line, and how many more there are.
fn first_of_log(log: &str) -> String {
    let mut lines = log.lines().filter(|l| !l.trim().is_empty());
    let first = lines.next().unwrap_or("(glslang gave no message)");
    match lines.count() {
        0 => first.to_owned(),
        more => format!("{first} (and {more} more line(s): `glint shader check` prints them all)"),
    }
}
