//! How a renderer is made and how a scene is rendered: the options of the
//! device and the shader, and the settings a scene is prepared with.

use std::path::PathBuf;
use std::time::Duration;

use super::GpuError;
use crate::accel::Accel;
use crate::base::Precision;
use crate::settings::{Intersect, Schedule};

/// How a [`Renderer`](super::Renderer) is made: the device, validation, the shader files and
/// defines, the caches, and the settings of [`Renderer::render`](super::Renderer::render).
#[derive(Debug, Clone, Default)]
pub struct GpuOptions {
    /// Pick the first device whose name contains this.
    pub device: Option<String>,
    /// Enable the Khronos validation layer and fail on any message.
    pub validate: bool,
    /// Directories searched for shader files ahead of the built-in ones.
    pub include_dirs: Vec<PathBuf>,
    /// A main shader to use instead of main.comp.
    pub main_shader: Option<PathBuf>,
    /// A built-in shader to use instead of main.comp (`glint bench` runs
    /// `ceiling.comp`).
    pub main_builtin: Option<String>,
    /// Defines added after the variant's own (-D NAME=VALUE).
    pub defines: Vec<(String, Option<String>)>,
    /// Run the shader as the least precise conformant driver may
    /// (`crate::spec_worst`; docs/guarantees.md).
    pub spec_worst: bool,
    /// The settings of `Renderer::render`; `Renderer::prepare` takes any.
    pub settings: RenderSettings,
    /// Where compiled SPIR-V and the Vulkan pipeline cache are kept between
    /// runs; None: compile every time.
    pub cache_dir: Option<PathBuf>,
    /// The longest wait for one tile; None: derived from the tile's work
    /// (`tile_timeout`).
    pub timeout: Option<Duration>,
    /// Upload the scene through a staging buffer into device-local memory
    /// the host does not map. None: where the device has such memory (a
    /// discrete GPU); GLINT_STAGE_UPLOADS=1 or 0 sets it.
    pub stage_uploads: Option<bool>,
}

/// Whether `name` (and `value`) can be a preprocessor define: a name of
/// letters, digits and _ that does not start with a digit, and a value
/// without a character that ends or breaks the line the define becomes
/// (glslang would blame a line of the shader for it). The reason where not.
pub fn check_define(name: &str, value: Option<&str>) -> Result<(), String> {
    let ok = name
        .chars()
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
    if !ok {
        return Err("a define is NAME or NAME=VALUE, NAME made of letters, digits and _".into());
    }
    if super::compile::reserved_define(name) {
        return Err(format!(
            "glint defines {name} itself for each scene (docs/shaders.md, Variants); choose another name"
        ));
    }
    let bad = value.and_then(|v| {
        v.chars()
            .find(|c| matches!(c, '"' | '\\' | '#') || c.is_control())
    });
    match bad {
        Some(c) => Err(format!(
            "a define's value may not hold {}",
            c.escape_default()
        )),
        None => Ok(()),
    }
}

/// Whether `dir` is a folder to search for shader files; the reason where
/// not (a file, or nothing there).
pub fn check_include_dir(dir: &std::path::Path) -> Result<(), String> {
    if dir.is_dir() {
        Ok(())
    } else {
        Err(format!(
            "include folder {}: {}",
            crate::printable::path(dir),
            if dir.exists() {
                "not a folder"
            } else {
                "no such folder"
            }
        ))
    }
}

impl GpuOptions {
    /// Refuses what every render with these options would refuse, before
    /// any device is opened: a `-D` of a name glint defines itself for each
    /// scene (the host's buffers and dispatch follow glint's value, not the
    /// user's), and a `GLINT_EXPERIMENT` glint does not have. `glint
    /// drivers` checks it once, in the parent, rather than in every
    /// driver's child.
    pub fn check(&self) -> Result<(), GpuError> {
        super::features::check_experiment()?;
        for (name, value) in &self.defines {
            check_define(name, value.as_deref()).map_err(|e| {
                GpuError::Unsupported(format!("-D {}: {e}", crate::printable::text(name)))
            })?;
        }
        for dir in &self.include_dirs {
            check_include_dir(dir).map_err(GpuError::Unsupported)?;
        }
        Ok(())
    }

    /// Validation is also switched on by GLINT_VALIDATION=1 (the tests set it).
    pub fn from_env(device: Option<String>) -> Self {
        let validate = std::env::var("GLINT_VALIDATION").is_ok_and(|v| v == "1");
        let stage_uploads = std::env::var("GLINT_STAGE_UPLOADS").ok().map(|v| v == "1");
        Self {
            device,
            stage_uploads,
            validate,
            ..Self::default()
        }
    }

    /// The platform's cache directory with `glint` in it: on Linux
    /// $XDG_CACHE_HOME/glint, or ~/.cache/glint.
    pub fn default_cache_dir() -> Option<PathBuf> {
        directories::BaseDirs::new().map(|d| d.cache_dir().join("glint"))
    }
}

/// How a scene is rendered: what [`Renderer::prepare`](super::Renderer::prepare) compiles it and lays
/// it out for. [`Renderer::render`](super::Renderer::render) takes the renderer's own
/// (`GpuOptions::settings`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub struct RenderSettings {
    /// The intersection forms.
    pub intersect: Intersect,
    /// The shader's arithmetic.
    pub precision: Precision,
    /// Which primitives each ray tests: every one, or through a BVH.
    pub accel: Accel,
    /// Render with the one shader that handles every feature.
    pub generic: bool,
    /// How the rays are laid on the device.
    pub schedule: Schedule,
    /// Compile the counting variant: each render also returns the shader's
    /// counts of rays, tests and BVH nodes (src/stats.rs), at some cost in
    /// speed.
    pub count: bool,
    /// Compile the recording variant (`glint explain`): each render also
    /// records the ray tree of this sample, (x, y, i, j) of the image's
    /// pixel (x, y), in the megakernel (shaders/record.glsl).
    pub record: Option<[u32; 4]>,
    /// Compile the AOV variant: each render also returns each pixel's
    /// AOVs (src/base/aov.rs, shaders/aov.glsl), in the megakernel, of a
    /// scene that samples its pixels' own points.
    pub aovs: bool,
}
