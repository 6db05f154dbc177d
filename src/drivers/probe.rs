//! What a probe (`glint driver-probe`, a driver's run in a child process
//! of its own) saw, and how it ended as its parent sees it: the child
//! writes [`ProbeReport`] as JSON beside its image, [`IMAGE`].

use serde::{Deserialize, Serialize};

/// A device as the driver names it.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
pub struct Identity {
    /// The device's name (`llvmpipe (LLVM 15.0.6, 256 bits)`).
    pub name: String,
    /// CPU, discrete GPU, ...
    pub kind: String,
    /// The driver's name and version.
    pub driver: String,
    /// The Vulkan version the device offers.
    pub api_version: String,
}

/// How one probe ended, as the child saw it.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(tag = "outcome", rename_all = "snake_case")]
pub enum Seen {
    /// The device was opened (and the scene rendered, unless identifying).
    Rendered {
        /// The scene's shader variant.
        variant: Option<String>,
        /// Upload, dispatch and readback of the render, seconds.
        seconds: f64,
        /// The driver's compile of the variant, seconds.
        driver_compile_s: f64,
    },
    /// This ICD gives no device that glint can use.
    NoDevice {
        /// What glint or the driver said.
        message: String,
    },
    /// The driver or device cannot render this scene as it is: a limit
    /// glint knows (the loop budget, no f64, a buffer too large).
    Refused {
        /// What glint or the driver said.
        message: String,
    },
    /// glint's own watchdog gave up waiting on the device.
    Hung {
        /// What glint or the driver said.
        message: String,
    },
    /// The validation layer spoke.
    Validation {
        /// The layer's messages.
        messages: Vec<String>,
    },
    /// The driver did what no correct driver does: lost the device, left
    /// the image unwritten or garbled, or returned an error that is not a
    /// limit.
    Fault {
        /// What glint or the driver said.
        message: String,
    },
    /// Anything else went wrong.
    Error {
        /// What glint or the driver said.
        message: String,
    },
}

/// What the child writes: the device, and how the probe ended.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ProbeReport {
    /// The device, where the driver named one.
    pub device: Option<Identity>,
    #[serde(flatten)]
    /// How the probe ended.
    pub seen: Seen,
}

/// The image a probe writes beside its probe.json.
pub const IMAGE: &str = "gpu.pfm";
/// How a child process ended, as the parent sees it.
pub enum Ended {
    /// It wrote its probe.json.
    Wrote(ProbeReport),
    /// It died of a signal (its number), or exited without a report.
    Crashed {
        /// The signal that killed it, if one did.
        signal: Option<i32>,
        /// Its exit status, in words.
        status: String,
        /// The last of what it wrote on stderr.
        stderr: String,
    },
    /// It ran past the parent's deadline and was killed.
    Hung {
        /// How long it ran, seconds.
        seconds: f64,
    },
}
