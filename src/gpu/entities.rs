//! The GLSL generated from the scene entities' tables: the light types'
//! (`crate::scene::LIGHT_TYPES`) and the patterns' (`PATTERNS`) codes,
//! switches and dispatch, as generated.rs does for the kinds of primitive.

use std::fmt::Write;

use super::variant::Variant;
use crate::scene::light::LightTypeInfo;
use crate::scene::texture::{Needs, PATTERNS};
use crate::scene::LIGHT_TYPES;

/// The generated file of the lights, as `#include` names it.
pub const LIGHTS_FILE: &str = "lights.glsl";

/// For interface.glsl: each light type's code (`Light.meta.x`), its
/// switch for the generic shader (a variant defines it), and the switches
/// of any light and of a positioned one.
pub fn light_constants() -> String {
    let mut s = String::new();
    for t in LIGHT_TYPES {
        let _ = writeln!(s, "const uint LIGHT_{} = {}u;", t.upper(), t.kind as u32);
    }
    for t in LIGHT_TYPES {
        let upper = t.upper();
        let _ = writeln!(s, "#ifndef HAS_{upper}\n#define HAS_{upper} 1\n#endif");
    }
    let any = |filter: fn(&LightTypeInfo) -> bool| {
        let on: Vec<String> = LIGHT_TYPES
            .iter()
            .filter(|t| filter(t))
            .map(|t| format!("HAS_{} != 0", t.upper()))
            .collect();
        if on.is_empty() {
            "false".to_owned()
        } else {
            on.join(" || ")
        }
    };
    let _ = writeln!(s, "#define HAS_LIGHTS ({})", any(|_| true));
    let _ = writeln!(s, "#define HAS_POSITIONED ({})", any(|t| t.positioned));
    // A light buffer's form follows from it (shaders/tables.glsl): a cube
    // of perspective grids around a positioned light, one parallel grid
    // for the others.
    let _ = writeln!(s, "#define HAS_UNPOSITIONED ({})", any(|t| !t.positioned));
    s
}

impl Variant {
    /// The light types this variant's lights take: the scene's, or every
    /// one for the generic shader.
    fn light_types(&self) -> Vec<&'static LightTypeInfo> {
        match &self.features {
            Some(f) => LIGHT_TYPES
                .iter()
                .zip(&f.light_types)
                .filter(|(_, on)| **on)
                .map(|(t, _)| t)
                .collect(),
            None => LIGHT_TYPES.iter().collect(),
        }
    }

    /// lights.glsl: every type's include (one type's functions may call
    /// another's), and the lists of the variant's types that
    /// shaders/light_dispatch.glsl's `light_toward` and `light_cone` run
    /// over, mirroring `LightTypeId::toward` and `LightTypeId::cone`.
    pub(super) fn lights(&self) -> String {
        let mut s = String::new();
        for t in LIGHT_TYPES {
            let _ = writeln!(s, "#include \"{}\"", t.include());
        }
        let present = self.light_types();
        let _ = writeln!(s, "\nconst bool ONE_LIGHT_TYPE = {};", present.len() == 1);
        let args = |t: &&LightTypeInfo| format!("{}, {}", t.upper(), t.name);
        s += &x_list("LIGHTS_PRESENT", present.iter().map(args));
        s += &x_list("LIGHTS_CONE", present.iter().filter(|t| t.cone).map(args));
        s
    }
}

/// `#define <name>(X)` calling `X(<args>)` for each of `entries`' argument
/// lists: the lists of a table's entries that the real shader files run
/// over (scans.glsl, light_dispatch.glsl, texture_dispatch.glsl).
pub(super) fn x_list(name: &str, entries: impl IntoIterator<Item = String>) -> String {
    let mut s = format!("#define {name}(X)");
    for args in entries {
        let _ = write!(s, " X({args})");
    }
    s + "\n"
}

/// The generated file of the textures, as `#include` names it.
pub const TEXTURES_FILE: &str = "textures.glsl";

/// textures.glsl: each pattern's code (`Texture.meta.x`) and include, and
/// the lists of patterns that shaders/texture_dispatch.glsl's
/// `texture_colour` runs over, mirroring `PatternId::colour`: those that read
/// uvs (compiled where the variant has images, `HAS_IMAGES`), then the
/// others.
pub fn textures() -> String {
    let mut s = String::new();
    for p in PATTERNS {
        let _ = writeln!(
            s,
            "const uint PATTERN_{} = {}u;",
            p.upper(),
            p.pattern.code()
        );
    }
    let mut includes: Vec<String> = PATTERNS.iter().map(|p| p.include()).collect();
    includes.dedup();
    for include in includes {
        let _ = writeln!(s, "#include \"{include}\"");
    }
    let entries = |uv: bool| {
        PATTERNS
            .iter()
            .filter(move |p| (p.needs == Needs::Uv) == uv)
            .map(|p| format!("{}, {}", p.upper(), p.name))
    };
    s += &x_list("PATTERNS_UV", entries(true));
    s += &x_list("PATTERNS_OTHER", entries(false));
    s
}

/// The generated file of the AOVs' words (shaders/aov.glsl includes it).
pub const AOVS_FILE: &str = "aovs.glsl";

/// `aovs.glsl`: a variable a word of the AOV table (`base::aov::AOVS`),
/// each starting as the row's word for nothing met; `AOV_CAPTURE_HIT(hit,
/// n, m)` and `AOV_CAPTURE_PIXEL()`, each row's capture; `AOV_STORE(at)`,
/// the words as pixel `at`'s uvec4s in the `Aovs` block.
pub fn aovs() -> String {
    use crate::base::aov::{Capture, AOVS, WORDS};
    let mut s = String::new();
    let (mut hit, mut pixel) = (Vec::new(), Vec::new());
    let mut k = 0;
    for t in AOVS {
        let _ = writeln!(s, "// {}: {}", t.name, t.doc);
        for expr in t.capture.words() {
            let _ = writeln!(s, "uint aov_word{k} = {}u;", t.missed_word);
            let capture = format!("aov_word{k} = {expr};");
            match t.capture {
                Capture::Hit(_) => hit.push(capture),
                Capture::Pixel(_) => pixel.push(capture),
            }
            k += 1;
        }
    }
    let word = |i: usize| {
        if i < k {
            format!("aov_word{i}")
        } else {
            "0u".to_owned()
        }
    };
    let _ = writeln!(s, "#define AOV_CAPTURE_HIT(hit, n, m) {}", hit.join(" "));
    let _ = writeln!(s, "#define AOV_CAPTURE_PIXEL() {}", pixel.join(" "));
    let stores: Vec<String> = (0..WORDS / 4)
        .map(|v| {
            format!(
                "aov_words[{}u * (at) + {v}u] = uvec4({}, {}, {}, {});",
                WORDS / 4,
                word(4 * v),
                word(4 * v + 1),
                word(4 * v + 2),
                word(4 * v + 3)
            )
        })
        .collect();
    let _ = writeln!(s, "#define AOV_STORE(at) {}", stores.join(" "));
    s
}
