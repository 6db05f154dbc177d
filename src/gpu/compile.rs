//! GLSL to SPIR-V with glslang, at run time. The shader's files are built
//! into the binary; `#include "x.glsl"` resolves among them.

use std::path::PathBuf;

use glslang::include::{IncludeHandler, IncludeResult, IncludeType};
use glslang::{
    Compiler, CompilerOptions, ShaderInput, ShaderSource, ShaderStage, SourceLanguage,
    SpirvVersion, Target, VulkanVersion,
};

use super::error::GpuError;

/// The built-in shader files, by the name `#include` uses.
pub const BUILTIN: &[(&str, &str)] = &[
    ("main.comp", include_str!("../../shaders/main.comp")),
    ("bindings.glsl", include_str!("../../shaders/bindings.glsl")),
    ("ray.glsl", include_str!("../../shaders/ray.glsl")),
    (
        "intersect.glsl",
        include_str!("../../shaders/intersect.glsl"),
    ),
    ("shade.glsl", include_str!("../../shaders/shade.glsl")),
    ("trace.glsl", include_str!("../../shaders/trace.glsl")),
];

/// Finds shader files: in the user's directories first, in order, then
/// among the built-in files.
pub struct Sources {
    pub dirs: Vec<PathBuf>,
}

impl Sources {
    /// The file's path (as messages should name it) and its text.
    pub fn find(&self, name: &str) -> Option<(String, String)> {
        for dir in &self.dirs {
            let path = dir.join(name);
            if let Ok(text) = std::fs::read_to_string(&path) {
                return Some((path.display().to_string(), text));
            }
        }
        BUILTIN
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(n, text)| (format!("shaders/{n}"), (*text).to_owned()))
    }
}

impl IncludeHandler for Sources {
    fn include(
        &mut self,
        _ty: IncludeType,
        name: &str,
        _from: &str,
        _depth: usize,
    ) -> Option<IncludeResult> {
        self.find(name)
            .map(|(path, data)| IncludeResult { name: path, data })
    }
}

/// Compiles main.comp (the user's where `sources` has one) with `defines`.
pub fn compile(
    sources: &Sources,
    defines: &[(String, Option<String>)],
) -> Result<Vec<u32>, GpuError> {
    let defines: Vec<(&str, Option<&str>)> = defines
        .iter()
        .map(|(n, v)| (n.as_str(), v.as_deref()))
        .collect();
    let (_, main) = sources
        .find("main.comp")
        .ok_or_else(|| GpuError::Shader("main.comp not found".into()))?;
    compile_source(
        &main,
        &defines,
        &mut Sources {
            dirs: sources.dirs.clone(),
        },
    )
}

fn compile_source(
    source: &str,
    defines: &[(&str, Option<&str>)],
    includes: &mut dyn IncludeHandler,
) -> Result<Vec<u32>, GpuError> {
    let compiler = Compiler::acquire()
        .ok_or_else(|| GpuError::Shader("glslang failed to initialise".into()))?;
    let source = ShaderSource::from(source.to_owned());
    let options = CompilerOptions {
        source_language: SourceLanguage::GLSL,
        target: Target::Vulkan {
            version: VulkanVersion::Vulkan1_2,
            spirv_version: SpirvVersion::SPIRV1_5,
        },
        ..CompilerOptions::default()
    };
    let input = ShaderInput::new(
        &source,
        ShaderStage::Compute,
        &options,
        Some(defines),
        Some(includes),
    )
    .map_err(|e| GpuError::Shader(e.to_string()))?;
    let shader = compiler
        .create_shader(input)
        .map_err(|e| GpuError::Shader(e.to_string()))?;
    shader
        .compile()
        .map_err(|e| GpuError::Shader(e.to_string()))
}
