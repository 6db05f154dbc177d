//! `glint --version`: the version and commit, then the Vulkan devices this
//! machine offers with their drivers, since which driver ran a render is
//! half of what a bug report needs. `-V` prints the first line alone.

/// `0.1.0 (commit 1e5aac2d9f0b)`: the version clap prints for `-V`.
pub const SHORT: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (commit ",
    env!("GLINT_COMMIT"),
    ")"
);

/// Whether the command line asks for the long version (`glint --version`).
pub fn asked(args: &[std::ffi::OsString]) -> bool {
    args.get(1).is_some_and(|a| a == "--version")
}

/// The long version: `SHORT`, then one line for each Vulkan device.
pub fn long() -> String {
    format!("{SHORT}\n{}", devices())
}

#[cfg(feature = "gpu")]
fn devices() -> String {
    match glint::gpu::list_devices() {
        Ok(devices) if devices.is_empty() => {
            "Vulkan: no devices (--backend cpu still renders)".into()
        }
        Ok(devices) => devices
            .iter()
            .enumerate()
            .map(|(i, d)| {
                let default = if i == 0 { ", the default" } else { "" };
                format!(
                    "Vulkan {i}: {} ({}{default}), driver {}, Vulkan {}",
                    d.name, d.kind, d.driver, d.api_version
                )
            })
            .collect::<Vec<_>>()
            .join("\n"),
        Err(e) => format!("Vulkan: unavailable ({e})"),
    }
}

#[cfg(not(feature = "gpu"))]
fn devices() -> String {
    "Vulkan: not built in (this binary renders on the CPU only)".into()
}
