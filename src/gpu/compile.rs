//! GLSL to SPIR-V with glslang, at run time. The shader's files are built
//! into the binary; a user's directories (-I) and main file (--shader) come
//! first. Errors name the user's own file and line.

use std::hash::Hasher;
use std::path::{Path, PathBuf};

use glslang::error::GlslangError;
use glslang::include::{IncludeHandler, IncludeResult, IncludeType};
use glslang::{
    Compiler, CompilerOptions, ShaderInput, ShaderSource, ShaderStage, SourceLanguage,
    SpirvVersion, Target, VulkanVersion,
};

use super::error::GpuError;
use crate::fnv::Fnv;

/// The built-in shader files of `shaders/`, by the name `#include` uses.
macro_rules! builtin_files {
    ($($name:literal),* $(,)?) => {
        &[$(($name, include_str!(concat!("../../shaders/", $name)))),*]
    };
}

/// The built-in shader files, by the name `#include` uses.
pub const BUILTIN: &[(&str, &str)] = builtin_files![
    "main.comp",
    "bindings.glsl",
    "count.glsl",
    "record.glsl",
    "aov.glsl",
    "ray.glsl",
    "intersect.glsl",
    "exact.glsl",
    "own_math.glsl",
    "scans.glsl",
    "shade.glsl",
    "specular.glsl",
    "trace.glsl",
    "texture.glsl",
    "texture_dispatch.glsl",
    "light_dispatch.glsl",
    "adaptive.glsl",
    "contrast.glsl",
    "tree.glsl",
    "bvh.glsl",
    "tables.glsl",
    "budget.glsl",
    "wavefront.glsl",
    "ceiling.comp",
];

/// The built-in files with each kind's include (`prim/sphere.glsl`) and
/// each light type's (`light/point.glsl`) and pattern's
/// (`texture/image.glsl`; two patterns may share one).
pub fn builtin() -> impl Iterator<Item = (String, &'static str)> {
    BUILTIN
        .iter()
        .map(|(n, t)| ((*n).to_owned(), *t))
        .chain(crate::prim::KINDS.iter().map(|k| (k.include(), k.glsl)))
        .chain(
            crate::scene::LIGHT_TYPES
                .iter()
                .map(|t| (t.include(), t.glsl)),
        )
        .chain(
            // A shared include once: under the name of its own pattern.
            crate::scene::texture::PATTERNS
                .iter()
                .filter(|p| p.name == p.include)
                .map(|p| (p.include(), p.glsl)),
        )
}

/// Preprocessor defines: `-D NAME` (None) or `-D NAME=VALUE`.
pub type Defines = [(String, Option<String>)];

/// Finds shader files: the user's main file, then the user's directories in
/// order, then the files generated for the variant, then the built-in files
/// (shaders/ and each kind's include, shaders/prim/).
#[derive(Debug, Clone, Default)]
pub struct Sources {
    /// The user's include directories, searched in order before the built-in files.
    pub dirs: Vec<PathBuf>,
    /// Replaces main.comp.
    pub main: Option<PathBuf>,
    /// A built-in file that replaces main.comp (`ceiling.comp`), where
    /// `main` is None.
    pub main_builtin: Option<String>,
    /// The variant's generated files (`Variant::generated`), by name.
    pub generated: Vec<(String, String)>,
}

impl Sources {
    /// Whether the main shader is glint's own main.comp (no `--shader`, no
    /// other built-in main): the only one that knows the wavefront's stages.
    pub fn main_is_glints(&self) -> bool {
        self.main.is_none() && self.main_builtin.is_none()
    }

    /// The file's path (as messages should name it) and its text; an
    /// error where a user's file of that name is there but cannot be read
    /// as a shader (see `read_source`).
    pub fn find(&self, name: &str) -> Result<Option<(String, String)>, String> {
        if let Some(mine) = self.users(name) {
            return mine.map(Some);
        }
        if let Some((n, text)) = self.generated.iter().find(|(n, _)| n == name) {
            return Ok(Some((format!("(generated) {n}"), text.clone())));
        }
        Ok(builtin()
            .find(|(n, _)| n == name)
            .map(|(n, text)| (format!("shaders/{n}"), text.to_owned())))
    }

    /// The user's files that replace one of glint's that records a ray
    /// tree (calls a `RECORD_` hook: main.comp, trace.glsl, shade.glsl)
    /// and call no such hook themselves, as messages name them (`glint
    /// explain` says which file records nothing).
    pub fn unrecording(&self) -> Vec<String> {
        self.without_hooks("RECORD_")
    }

    /// The user's files that replace one of glint's that gives AOVs (calls
    /// an `AOV_` hook: main.comp, trace.glsl) and call none themselves: a
    /// render's AOVs would say that nothing was met.
    pub fn without_aovs(&self) -> Vec<String> {
        self.without_hooks("AOV_")
    }

    /// The user's files that replace one of glint's that calls a hook
    /// whose name starts with `hook`, and call none themselves.
    fn without_hooks(&self, hook: &str) -> Vec<String> {
        let records = |text: &str| text.contains(hook);
        let mut out = Vec::new();
        for (name, glints) in BUILTIN {
            if !records(glints) {
                continue;
            }
            let mine = match &self.main {
                Some(path) if *name == "main.comp" => Some(read_source(path)),
                _ => self.users(name),
            };
            if let Some(Ok((path, text))) = mine {
                if !records(&text) {
                    out.push(path);
                }
            }
        }
        out
    }

    /// The user's file `name` from the include folders, where one has it.
    fn users(&self, name: &str) -> Option<Result<(String, String), String>> {
        self.dirs
            .iter()
            .map(|dir| dir.join(name))
            .find(|path| std::fs::metadata(path).is_ok())
            .map(|path| read_source(&path))
    }

    /// These sources with the files generated for `variant`.
    pub fn for_variant(&self, variant: &super::variant::Variant) -> Sources {
        Sources {
            generated: variant.generated(),
            ..self.clone()
        }
    }

    fn main_source(&self) -> Result<(String, String), GpuError> {
        match &self.main {
            Some(path) => read_source(path).map_err(GpuError::Shader),
            None => {
                let name = self.main_builtin.as_deref().unwrap_or("main.comp");
                self.find(name)
                    .map_err(GpuError::Shader)?
                    .ok_or_else(|| GpuError::Shader(format!("{name} not found")))
            }
        }
    }

    /// A hash of everything a compile can read: which file is the main
    /// shader, the built-in files, the user's main file and every file in
    /// the user's directories. A change to any of them makes a new pipeline
    /// and a new cache entry.
    pub fn fingerprint(&self) -> u64 {
        let mut h = Fnv::default();
        h.write(env!("CARGO_PKG_VERSION").as_bytes());
        // The main file's choice first: the bench's ceiling.comp and the
        // stock main.comp read the same files, and a one-sphere scene with
        // no light is the ceiling's own variant, so without it the two
        // shared a cache entry and such a scene rendered the ceiling's
        // output. A user's main file is hashed, path and text, with the
        // files below.
        h.write(b"main");
        h.write(
            self.main_builtin
                .as_deref()
                .unwrap_or("main.comp")
                .as_bytes(),
        );
        for (name, text) in builtin() {
            h.write(name.as_bytes());
            h.write(text.as_bytes());
        }
        for (name, text) in &self.generated {
            h.write(name.as_bytes());
            h.write(text.as_bytes());
        }
        // The user's files by content and by where the compile finds
        // them (which folder of the list, by its place, and the name in
        // it), not by their paths: the same texts in another temporary
        // folder (the Python module's `include={...}`, one a renderer)
        // are the same compile, and found in the cache.
        let mut files: Vec<(usize, std::ffi::OsString, PathBuf)> = self
            .main
            .iter()
            .map(|m| (usize::MAX, "main".into(), m.clone()))
            .collect();
        for (i, dir) in self.dirs.iter().enumerate() {
            for f in crate::files::sorted(dir, |_| true).unwrap_or_default() {
                let name = f.file_name().unwrap_or_default().to_owned();
                files.push((i, name, f));
            }
        }
        // Read as every input is (a FIFO is not opened, a device not read
        // past the bound); a file that cannot be read is hashed by its error,
        // and refused only if a compile includes it.
        for (dir, name, f) in files {
            h.write(&dir.to_le_bytes());
            h.write(name.as_encoded_bytes());
            match crate::input::read(&f, crate::input::ReadAs::Shader) {
                Ok(bytes) => h.write(&bytes),
                Err(e) => h.write(e.to_string().as_bytes()),
            }
        }
        h.finish()
    }
}

/// A user's shader file: its path as messages name it, and its text: a
/// regular file within `Kind::Shader`'s bound, UTF-8, without NUL bytes
/// (glslang takes C strings).
fn read_source(path: &Path) -> Result<(String, String), String> {
    let shown = crate::printable::path(path);
    let text = crate::input::read_text(path, crate::input::ReadAs::Shader)
        .map_err(|e| format!("{shown}: {e}"))?;
    if let Some(at) = text.find('\0') {
        let line = text[..at].matches('\n').count() + 1;
        return Err(format!(
            "{shown}:{line}: error: a NUL byte (offset {at}); a shader is text"
        ));
    }
    Ok((path.display().to_string(), text))
}

/// Nested `#include`s deeper than this are refused: a file that includes
/// itself, or two that include each other, would otherwise recurse until
/// memory runs out.
pub const MAX_INCLUDE_DEPTH: usize = 32;

/// Resolves a compile's `#include`s and remembers the first problem: one
/// nested too deep, a file that cannot be read, macros past their bound.
struct Includes<'a> {
    sources: &'a Sources,
    /// Read after glslang fails, while it still holds the handler.
    problem: &'a std::cell::RefCell<Option<String>>,
    /// The defines of the files read so far (`macros::Macros`).
    macros: &'a std::cell::RefCell<super::macros::Macros>,
}

impl IncludeHandler for Includes<'_> {
    fn include(
        &mut self,
        _ty: IncludeType,
        name: &str,
        from: &str,
        depth: usize,
    ) -> Option<IncludeResult> {
        if depth > MAX_INCLUDE_DEPTH {
            self.problem.borrow_mut().get_or_insert_with(|| {
                format!(
                    "{}: error: #include \"{}\" nests deeper than {MAX_INCLUDE_DEPTH} files: \
                     an include cycle?",
                    crate::printable::text(from),
                    crate::printable::text(name)
                )
            });
            return None;
        }
        let found = self.sources.find(name).and_then(|found| {
            if let Some((path, data)) = &found {
                self.macros.borrow_mut().add(path, data)?;
            }
            Ok(found)
        });
        match found {
            Ok(found) => found.map(|(path, data)| IncludeResult { name: path, data }),
            Err(problem) => {
                self.problem.borrow_mut().get_or_insert(problem);
                None
            }
        }
    }
}

/// Names glint defines for its own variants (src/gpu/variant.rs); a user's
/// `-D` may not redefine them, since the host's buffers and dispatch follow
/// glint's values, not the user's.
pub fn reserved_define(name: &str) -> bool {
    const NAMES: &[&str] = &[
        "SHADOWS_ON",
        "MAX_DEPTH",
        "SAMPLES",
        "SCENE_IN_UNIFORMS",
        "UNROLL_LOOPS",
        "UNROLL_LIGHTS",
        "NO_LOOP_CANARY",
        "POWER_FILTER",
        "INTERSECT_NAIVE",
        "GLINT_F64",
        "USE_BVH",
        "BVH_STACK",
        "USE_TABLES",
        "COUNT_RAYS",
        "RECORD_TREE",
        "REFINE_POINTS",
        "REFINE_WIDTH",
        "WAVEFRONT",
        "WAVE_REALS",
        "WAVE_WORDS",
    ];
    NAMES.contains(&name)
        || crate::base::record::glsl_defines()
            .iter()
            .any(|(n, _)| n == name)
        || name.starts_with("HAS_")
        || name.ends_with("_COUNT")
        || name.ends_with("_SLOTS")
        || name.ends_with("_BINDING")
}

/// The cache key of one compile.
pub fn cache_key(fingerprint: u64, defines: &Defines) -> String {
    let mut h = Fnv::from_state(fingerprint);
    for (name, value) in defines {
        h.write(name.as_bytes());
        h.write(value.as_deref().unwrap_or("").as_bytes());
        // `-D A` and `-D A=` are not the same define.
        h.write(&[u8::from(value.is_some())]);
    }
    format!("{:016x}", h.finish())
}

/// A compiled shader, with the preprocessed text (`glint shader dump`).
pub struct Compiled {
    /// The SPIR-V words.
    pub spirv: Vec<u32>,
    /// The source after glslang's preprocessor: every include and define resolved.
    pub preprocessed: String,
}

/// The stack glslang compiles on. Its passes recurse once per level of an
/// expression's tree, and a sum of 20,001 terms overflowed the main
/// thread's 8 MiB (an abort). Only the pages it touches are memory; the
/// sources' bound (`MAX_SOURCE_BYTES`) bounds the depth, and
/// `tests/shaders.rs` compiles the deepest sum that fits.
pub const COMPILE_STACK: usize = 1 << 30;

/// Compiles the main shader with `defines`, on a thread with a stack made
/// for glslang's recursion (`COMPILE_STACK`).
pub fn compile(sources: &Sources, defines: &Defines) -> Result<Compiled, GpuError> {
    std::thread::scope(|scope| {
        std::thread::Builder::new()
            .name("glslang".into())
            .stack_size(COMPILE_STACK)
            .spawn_scoped(scope, || compile_here(sources, defines))
            .map_err(|e| {
                GpuError::Shader(format!("cannot start the shader compiler's thread: {e}"))
            })?
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
    })
}

fn compile_here(sources: &Sources, defines: &Defines) -> Result<Compiled, GpuError> {
    let (main_path, main) = sources.main_source()?;
    let macros = std::cell::RefCell::new(super::macros::Macros::default());
    macros
        .borrow_mut()
        .add(&main_path, &main)
        .map_err(GpuError::Shader)?;
    let defines: Vec<(&str, Option<&str>)> = defines
        .iter()
        .map(|(n, v)| (n.as_str(), v.as_deref()))
        .collect();
    let compiler = Compiler::acquire()
        .ok_or_else(|| GpuError::Shader("glslang failed to initialise".into()))?;
    let source = ShaderSource::from(main);
    let options = CompilerOptions {
        source_language: SourceLanguage::GLSL,
        target: Target::Vulkan {
            version: VulkanVersion::Vulkan1_2,
            spirv_version: SpirvVersion::SPIRV1_5,
        },
        ..CompilerOptions::default()
    };
    let problem = std::cell::RefCell::new(None);
    let mut includes = Includes {
        sources,
        problem: &problem,
        macros: &macros,
    };
    let fail = |e: GlslangError| {
        GpuError::Shader(
            problem
                .borrow()
                .clone()
                .unwrap_or_else(|| format_log(&e, &main_path)),
        )
    };
    let input = ShaderInput::new(
        &source,
        ShaderStage::Compute,
        &options,
        Some(&defines),
        Some(&mut includes),
    )
    .map_err(fail)?;
    let shader = compiler.create_shader(input).map_err(fail)?;
    let spirv = shader.compile().map_err(fail)?;
    Ok(Compiled {
        spirv,
        preprocessed: shader.get_preprocessed_code(),
    })
}

/// Compiles through a cache of SPIR-V files in `dir`, keyed by the sources'
/// fingerprint (`Sources::fingerprint`) and the defines. Returns whether the
/// cache had it.
pub fn compile_cached(
    sources: &Sources,
    fingerprint: u64,
    defines: &Defines,
    dir: Option<&Path>,
) -> Result<(Vec<u32>, bool), GpuError> {
    let Some(dir) = dir else {
        return Ok((compile(sources, defines)?.spirv, false));
    };
    // Sealed (`sealed`): a damaged entry is compiled again and replaced,
    // never handed to the driver.
    let file = dir.join(format!("{}.spv.sealed", cache_key(fingerprint, defines)));
    if let Some(bytes) = super::sealed::read(&file, "the cached SPIR-V") {
        if bytes.len() % 4 == 0 && bytes.len() >= 20 {
            let words: Vec<u32> = bytes
                .chunks_exact(4)
                .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
                .collect();
            if words[0] == 0x0723_0203 {
                return Ok((words, true));
            }
        }
    }
    let spirv = compile(sources, defines)?.spirv;
    super::sealed::write(&file, &spirv_bytes(&spirv));
    Ok((spirv, false))
}

/// SPIR-V words as the bytes of a .spv file (little-endian).
pub fn spirv_bytes(words: &[u32]) -> Vec<u8> {
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}

/// glslang's log as `file:line: error: message` lines, the main file named
/// by its path (glslang calls it "0").
fn format_log(e: &GlslangError, main_path: &str) -> String {
    let log = match e {
        GlslangError::PreprocessError(l)
        | GlslangError::ParseError(l)
        | GlslangError::LinkError(l)
        | GlslangError::MapIoError(l) => l.log.clone(),
        other => return other.to_string(),
    };
    let mut out = Vec::new();
    for line in log.lines() {
        let (kind, rest) = if let Some(r) = line.strip_prefix("ERROR: ") {
            ("error", r)
        } else if let Some(r) = line.strip_prefix("WARNING: ") {
            ("warning", r)
        } else {
            continue;
        };
        // "<file>:<line>: <message>", where <file> may itself hold colons.
        let parsed = rest.split_once(": ").and_then(|(place, message)| {
            let (file, line_no) = place.rsplit_once(':')?;
            line_no.parse::<u32>().ok().map(|n| (file, n, message))
        });
        match parsed {
            // glslang's trailer after the first error: it names nothing.
            Some((_, _, message)) if message.trim() == "'' : compilation terminated" => {}
            Some((file, n, message)) => {
                // "0" is the main file, "-1" the preamble of -D defines.
                let file = match file {
                    "0" => main_path,
                    "-1" => "-D",
                    f => f,
                };
                out.push(format!("{file}:{n}: {kind}: {}", message.trim_end()));
            }
            // "ERROR: 1 compilation errors.  No code generated." and the like.
            None if rest.contains("compilation errors") => {}
            None => out.push(format!("{main_path}: {kind}: {}", rest.trim_end())),
        }
    }
    if out.is_empty() {
        log.trim().to_owned()
    } else {
        out.join("\n")
    }
}

#[cfg(test)]
mod tests {
    /// glint's own shaders keep far within the preprocessor's bound
    /// (macros.rs); here, as this file lists them.
    #[test]
    fn glints_own_shaders_are_far_within_the_bound() {
        let mut m = super::super::macros::Macros::default();
        for (name, text) in super::builtin() {
            m.add(&name, text).unwrap();
        }
    }
}
