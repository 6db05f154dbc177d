//! The GLSL generated from the scene entities' tables: the light types'
//! (`crate::scene::LIGHT_TYPES`) and the patterns' (`PATTERNS`) codes,
//! switches and dispatch, as generated.rs does for the kinds of primitive.

use std::fmt::Write;

use super::variant::Variant;
use crate::scene::light::LightTypeInfo;
use crate::scene::texture::{Needs, PatternInfo, PATTERNS};
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

/// `body(t)` for the light whose type is one of `types`, chosen by its
/// code, else `otherwise`; no test where one type is all there is.
fn by_type(
    types: &[&LightTypeInfo],
    body: impl Fn(&LightTypeInfo) -> String,
    otherwise: &str,
) -> String {
    let mut s = String::from("    ");
    for t in types {
        let _ = write!(
            s,
            "if (kind == LIGHT_{}) {{\n        {}\n    }} else ",
            t.upper(),
            body(t)
        );
    }
    if types.is_empty() {
        let _ = writeln!(s, "{otherwise}");
    } else {
        let _ = writeln!(s, "{{\n        {otherwise}\n    }}");
    }
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

    /// lights.glsl: every type's include, and `light_toward` and
    /// `light_cone` over the variant's types, mirroring `LightKind::toward`
    /// and `LightKind::cone`.
    pub(super) fn lights(&self) -> String {
        let mut s = String::new();
        // Every include: one type's functions may call another's.
        for t in LIGHT_TYPES {
            let _ = writeln!(s, "#include \"{}\"", t.include());
        }
        let present = self.light_types();
        let call = |t: &LightTypeInfo| format!("{}_toward(light, p, l, dist, att);", t.name);
        s += "\n// How light `light` reaches p: l the unit way to it, dist the distance\n\
              // (INF without a position), att the attenuation.\n\
              void light_toward(Light light, vec3r p, out vec3r l, out real dist, out real att) {\n";
        s += &match present.split_last() {
            Some((last, [])) => format!("    {}\n", call(last)),
            Some((last, rest)) => {
                "    uint kind = light.meta.x;\n".to_owned() + &by_type(rest, call, &call(last))
            }
            None => "    l = vec3r(0.0);\n    dist = INF;\n    att = 1.0;\n".to_owned(),
        };
        s += "}\n\n// The share of the light in direction l (unit, towards it), 0..1: 1\n\
              // but for the types with a cone.\n\
              real light_cone(Light light, vec3r l) {\n";
        let cones: Vec<&LightTypeInfo> = present.iter().copied().filter(|t| t.cone).collect();
        let cone = |t: &LightTypeInfo| format!("return {}_cone(light, l);", t.name);
        s += &match cones.as_slice() {
            [only] if present.len() == 1 => format!("    {}\n", cone(only)),
            [] => "    return 1.0;\n".to_owned(),
            _ => {
                "    uint kind = light.meta.x;\n".to_owned() + &by_type(&cones, cone, "return 1.0;")
            }
        };
        s += "}\n";
        s
    }
}

/// The generated file of the textures, as `#include` names it.
pub const TEXTURES_FILE: &str = "textures.glsl";

/// textures.glsl: each pattern's code (`Texture.meta.x`) and include, and
/// `texture_colour` over the patterns, mirroring `Pattern::colour`. The
/// patterns that read uvs are compiled where the variant has images
/// (`HAS_IMAGES`), and tested first; of the others the last is what is
/// left.
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
    s += "\n// The colour of texture t at p, a point of the primitive hit.\n\
          vec3r texture_colour(uint t, Hit hit, vec3r p) {\n\
          \x20   Texture tx = texture_at(t);\n\
          \x20   uint pattern = tx.meta.x;\n";
    let call = |p: &PatternInfo| format!("{}_colour(tx, hit, p)", p.name);
    let test = |p: &PatternInfo| {
        format!(
            "    if (pattern == PATTERN_{}) {{\n        return {};\n    }}\n",
            p.upper(),
            call(p)
        )
    };
    let (uv, rest): (Vec<&PatternInfo>, Vec<&PatternInfo>) =
        PATTERNS.iter().partition(|p| p.needs == Needs::Uv);
    if !uv.is_empty() {
        s += "#if HAS_IMAGES\n";
        uv.iter().for_each(|p| s += &test(p));
        s += "#endif\n";
    }
    match rest.split_last() {
        Some((last, others)) => {
            others.iter().for_each(|p| s += &test(p));
            let _ = writeln!(s, "    return {};", call(last));
        }
        None => s += "    return vec3r(0.0);\n",
    }
    s += "}\n";
    s
}
