//! The arguments that several commands share (the scene and its
//! overrides, the device and shader options, the backend) and the small
//! helpers over them: what a run reads, a scene's name and line.

use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};

use glint::files::folder_of;
#[cfg(feature = "gpu")]
use glint::gpu::GpuOptions;
use glint::scene::{Overrides, Scene};
use glint::settings::{Accel, Intersect, Schedule};

use super::choice;

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Backend {
    Gpu,
    Cpu,
}

pub use glint::settings::Precision;

/// The scene and the settings that override its own.
#[derive(Args, Clone)]
pub struct SceneArgs {
    /// The scene file: TOML, or NFF by its .nff extension (docs/scene-format.md).
    pub scene: PathBuf,
    #[command(flatten)]
    pub overrides: OverrideArgs,
}

/// The settings that override a scene's own.
#[derive(Args, Clone)]
pub struct OverrideArgs {
    /// Image width in pixels (1..=16384).
    #[arg(long)]
    width: Option<u32>,
    /// Image height in pixels (1..=16384).
    #[arg(long)]
    height: Option<u32>,
    /// Supersampling grid side: samples² rays per pixel (1..=16).
    #[arg(long)]
    samples: Option<u32>,
    /// Ray segments per pixel: 1 = primary rays only (1..=64).
    #[arg(long)]
    max_depth: Option<u32>,
}

impl OverrideArgs {
    /// As the scene's loader takes them.
    pub fn overrides(&self) -> Overrides {
        Overrides {
            width: self.width,
            height: self.height,
            samples: self.samples,
            max_depth: self.max_depth,
        }
    }

    /// As the words of a command line, for a child glint.
    #[cfg(feature = "gpu")]
    pub fn forward(&self) -> Vec<std::ffi::OsString> {
        let mut v = Vec::new();
        for (flag, value) in [
            ("--width", self.width),
            ("--height", self.height),
            ("--samples", self.samples),
            ("--max-depth", self.max_depth),
        ] {
            if let Some(n) = value {
                v.extend([flag.into(), n.to_string().into()]);
            }
        }
        v
    }
}

impl SceneArgs {
    /// The scene file, absolute, and its overrides as the words of a
    /// command line, for a child glint.
    #[cfg(feature = "gpu")]
    pub fn forward(&self) -> Vec<std::ffi::OsString> {
        let mut v = vec![std::path::absolute(&self.scene).map_or_else(
            |_| self.scene.clone().into_os_string(),
            PathBuf::into_os_string,
        )];
        v.extend(self.overrides.forward());
        v
    }

    pub fn load(&self) -> anyhow::Result<Scene> {
        Ok(Scene::load(&self.scene, &self.overrides.overrides())?)
    }
}

/// Which Vulkan device to use, and where to find shader files.
#[derive(Args, Clone)]
pub struct DeviceArgs {
    /// Use the first Vulkan device whose name contains NAME (see `glint info`).
    #[arg(long, value_name = "NAME")]
    device: Option<String>,
    /// Look for shader files (main.comp, shade.glsl, ...) in DIR before the built-in ones; repeatable.
    #[arg(short = 'I', long = "include", value_name = "DIR")]
    pub include: Vec<PathBuf>,
    /// The GPU's intersection forms: robust, or the textbook ones for comparison.
    #[arg(long, value_parser = choice::of::<Intersect>(), default_value = "robust")]
    intersect: Intersect,
    /// Use FILE as the main shader instead of the built-in main.comp.
    #[arg(long, value_name = "FILE")]
    pub shader: Option<PathBuf>,
    /// Add a preprocessor define to the shader; repeatable.
    #[arg(short = 'D', value_name = "NAME[=VALUE]")]
    define: Vec<String>,
    /// Render with the one shader that handles every feature, not the scene's own variant.
    #[arg(long)]
    generic: bool,
    /// Scene management: a BVH over the bounded primitives (spheres, triangles and cylinders; planes are scanned), none (every ray tests every object), or auto (by the count of bounded primitives). The CPU renderer follows it too.
    #[arg(long, value_parser = choice::of::<Accel>(), default_value = "auto")]
    pub accel: Accel,
    /// How the GPU lays out the rays: one invocation per pixel tracing its whole ray tree (megakernel), a dispatch per ray segment over a compacted queue of live paths (wavefront), or auto (the one measured faster for scenes like this; docs/performance.md, Schedules). Both give the same image, bit for bit.
    #[arg(long, value_parser = choice::of::<Schedule>(), default_value = "auto")]
    pub schedule: Schedule,
    /// Compile the shader afresh and keep no SPIR-V or pipeline cache.
    #[arg(long)]
    no_cache: bool,
    /// Run the shader as the least precise conformant Vulkan driver may: each instruction the Vulkan spec bounds off by its bound, products fused or not, denormals flushed (docs/guarantees.md). Slow; for checking that a scene holds on any driver.
    #[arg(long)]
    pub spec_worst: bool,
    /// Wait at most SECONDS for the GPU to finish one tile [default: from the tile's work, at least 10 s].
    #[arg(long, value_name = "SECONDS")]
    timeout: Option<f64>,
}

impl DeviceArgs {
    /// The files the shader is read from: `--shader` and those in the
    /// include directories.
    /// Of the include folders' files (the `-I` folders and the shader's
    /// own), those a shader can include: .glsl and .comp. An output written
    /// beside them (`-I .`) is not taken for one.
    pub fn inputs(&self) -> Vec<PathBuf> {
        let mut dirs = self.include.clone();
        dirs.extend(self.shader.as_deref().map(|s| folder_of(s).to_owned()));
        let mut v: Vec<PathBuf> = self.shader.iter().cloned().collect();
        v.extend(
            glint::files::in_dirs(&dirs)
                .into_iter()
                .filter(|f| f.extension().is_some_and(|e| e == "glsl" || e == "comp")),
        );
        v
    }

    /// These options as the words of a command line, for a child glint
    /// (`glint drivers`), all but `--device`: the child's device is the one
    /// its driver offers. Paths are made absolute, so that the words mean the
    /// same from any folder (a reproducer's command repeated `-I ../inc` as
    /// typed, relative to where the run was).
    #[cfg(feature = "gpu")]
    pub fn forward(&self) -> Vec<std::ffi::OsString> {
        use glint::settings::Choice;
        let absolute =
            |p: &Path| std::path::absolute(p).map_or_else(|_| p.into(), PathBuf::into_os_string);
        let mut v: Vec<std::ffi::OsString> = Vec::new();
        for dir in &self.include {
            v.extend(["-I".into(), absolute(dir)]);
        }
        if let Some(shader) = &self.shader {
            v.extend(["--shader".into(), absolute(shader)]);
        }
        for d in &self.define {
            v.extend(["-D".into(), d.into()]);
        }
        v.extend(["--intersect".into(), self.intersect.name().into()]);
        v.extend(["--accel".into(), self.accel.name().into()]);
        v.extend(["--schedule".into(), self.schedule.name().into()]);
        if self.generic {
            v.push("--generic".into());
        }
        if self.no_cache {
            v.push("--no-cache".into());
        }
        if self.spec_worst {
            v.push("--spec-worst".into());
        }
        if let Some(t) = self.timeout {
            v.extend(["--timeout".into(), t.to_string().into()]);
        }
        v
    }

    /// Whether `--device` was given.
    #[cfg(feature = "gpu")]
    pub fn names_a_device(&self) -> bool {
        self.device.is_some()
    }

    /// Fails where a shader option is given to a run that reads no shader
    /// (`--backend cpu`): it would be ignored without a word.
    pub fn refuse_shader_options(&self, why: &str) -> anyhow::Result<()> {
        let given = [
            (self.shader.is_some(), "--shader"),
            (!self.include.is_empty(), "-I"),
            (!self.define.is_empty(), "-D"),
            (self.spec_worst, "--spec-worst"),
        ];
        if let Some((_, name)) = given.iter().find(|(set, _)| *set) {
            anyhow::bail!(
                "{name} applies to the GPU's shader, and {why} reads none (drop {name}, or render on the GPU)"
            );
        }
        Ok(())
    }

    #[cfg(feature = "gpu")]
    pub fn options(&self) -> anyhow::Result<GpuOptions> {
        for dir in &self.include {
            anyhow::ensure!(dir.is_dir(), "-I {}: not a directory", dir.display());
        }
        let mut options = GpuOptions::from_env(self.device.clone());
        options.include_dirs = self.include.clone();
        if let Some(shader) = &self.shader {
            anyhow::ensure!(
                shader.is_file(),
                "--shader {}: no such file",
                shader.display()
            );
            options.main_shader = Some(shader.clone());
            // As a C compiler does: a file the shader includes may sit
            // beside it (searched after the -I folders).
            options.include_dirs.push(folder_of(shader).to_owned());
        }
        options.defines = self
            .define
            .iter()
            .map(|d| parse_define(d))
            .collect::<anyhow::Result<_>>()?;
        options.settings.generic = self.generic;
        options.spec_worst = self.spec_worst;
        options.settings.accel = self.accel;
        options.settings.schedule = self.schedule;
        if let Some(t) = self.timeout {
            anyhow::ensure!(
                t.is_finite() && t > 0.0 && t <= 1e6,
                "--timeout {t:?}: must be in (0, 1e6] seconds"
            );
            options.timeout = Some(std::time::Duration::from_secs_f64(t));
        }
        options.cache_dir = if self.no_cache {
            None
        } else {
            GpuOptions::default_cache_dir()
        };
        options.settings.intersect = self.intersect;
        Ok(options)
    }
}

/// The most timed runs `bench` and `report` take: a thousand of the
/// slowest scene is hours already, and a larger count is a typo.
#[cfg(feature = "gpu")]
pub const MAX_RUNS: usize = 1000;

/// A scene's name in tables and file names: its file's, without the extension.
#[cfg(feature = "gpu")]
pub fn scene_name(path: &Path) -> String {
    path.file_stem()
        .unwrap_or_default()
        .to_string_lossy()
        .into_owned()
}

/// The first line of `compare` and `explain`: the scene file, its size,
/// sampling and depth.
#[cfg(feature = "gpu")]
pub fn scene_line(path: &Path, scene: &Scene) -> String {
    format!(
        "scene      {} ({}x{}, {}, depth {})",
        path.display(),
        scene.width,
        scene.height,
        scene.sampling_summary(),
        scene.max_depth
    )
}

/// Every file a run of `scene` (read from `path`) with `device` reads:
/// none of them may be one of its outputs.
pub fn inputs(path: &Path, scene: &Scene, device: &DeviceArgs) -> Vec<PathBuf> {
    let mut v = vec![path.to_owned()];
    v.extend(scene.input_files.iter().cloned());
    v.extend(device.inputs());
    v
}

/// The scene files (TOML or NFF) in `dir`, sorted; for commands that default to a
/// directory of the repository.
#[cfg(feature = "gpu")]
pub fn scene_files(dir: &str) -> anyhow::Result<Vec<PathBuf>> {
    use anyhow::Context;
    glint::files::sorted(Path::new(dir), glint::scene::is_scene).with_context(|| {
        format!("cannot list {dir}/ (name scene files, or run from the repository)")
    })
}

/// NAME or NAME=VALUE, NAME a C identifier.
#[cfg(feature = "gpu")]
pub fn parse_define(d: &str) -> anyhow::Result<(String, Option<String>)> {
    let (name, value) = match d.split_once('=') {
        Some((n, v)) => (n, Some(v.to_owned())),
        None => (d, None),
    };
    glint::gpu::check_define(name, value.as_deref())
        .map_err(|e| anyhow::anyhow!("-D {}: {e}", glint::printable::text(d)))?;
    Ok((name.to_owned(), value))
}
