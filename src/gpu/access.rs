//! How the shader reads the scene's read-only arrays: each is declared in
//! one of three forms, and read through one accessor (`sphere_at(i)`,
//! `material_at(i)`, `node_at(i)`) whatever the form, so that the shader's
//! own files never name a form.
//!
//! - A uniform block, where the scene's arrays fit the device's uniform
//!   range: llvmpipe reads one at a constant offset once for all lanes.
//! - A uniform texel buffer of four-word texels (`utextureBuffer`, read
//!   without a sampler: GL_EXT_samplerless_texture_functions), which
//!   llvmpipe fetches for all lanes of a SIMD group at once, where it
//!   reads a storage buffer at per-lane indices lane by lane
//!   (docs/performance.md, Reading the scene). The accessor fetches the
//!   struct's 16-byte words and rebuilds its members bit for bit.
//! - A storage buffer, where a texel buffer would be longer than the
//!   device's `maxTexelBufferElements`.
//! - (An experiment: a buffer read through its device address, which
//!   llvmpipe reads with `llvm.masked.gather`; LLVM turned that into a
//!   branch a lane on the machine measured.)

use std::fmt::Write;

use super::blocks::{Block, Form};
use super::layout::{table_word, texel};
use crate::accel::quantize::packed;
use crate::base::interface::{words, GpuStruct, Member};
use crate::base::Precision;
use crate::prim::{triangle, KINDS};
use crate::scene::light::gpu as light;
use crate::scene::material::gpu as material;
use crate::scene::texture::gpu as texture;

/// One read-only array as the shader declares it.
#[derive(Debug, Clone)]
pub struct ArrayDecl {
    /// The block's name: `Spheres`.
    pub block: String,
    /// The array's name: `spheres` (`spheres_texels` for a texel buffer).
    pub array: &'static str,
    /// Its element's struct: `Sphere`.
    pub item: &'static str,
    /// The stem of its accessor: `sphere` for `sphere_at(i)`.
    pub stem: &'static str,
    /// The struct's members.
    pub fields: &'static [(&'static str, Member)],
    /// Where it is a kind's, which the scans read through
    /// `{stem}_test_at(i)`: the members it reads for shading alone
    /// (`Kind::SHADING_ONLY`), which that accessor leaves zero.
    pub test: Option<&'static [&'static str]>,
    /// Whether the uniform and storage forms also hold 16-byte words
    /// (`uvec4 nodes_words[]`) rather than structs: llvmpipe loads a
    /// vec4 at once, a struct's vec3 and uint apart.
    pub by_words: bool,
}

impl ArrayDecl {
    /// The read-only array that `block` is, or None for the other blocks.
    pub fn of(block: Block) -> Option<Self> {
        fn of<S: GpuStruct>(block: &str, array: &'static str, stem: &'static str) -> ArrayDecl {
            ArrayDecl {
                block: block.to_owned(),
                array,
                item: S::NAME,
                stem,
                fields: S::FIELDS,
                test: None,
                by_words: false,
            }
        }
        Some(match block {
            Block::Kind(k) => {
                let kind = &KINDS[k];
                ArrayDecl {
                    block: block_name(kind.key),
                    array: kind.key,
                    item: kind.struct_name,
                    stem: kind.name,
                    fields: kind.struct_fields,
                    test: Some(kind.shading_only),
                    by_words: false,
                }
            }
            Block::Materials => of::<material::Values>("Materials", "materials", "material"),
            Block::Lights => of::<light::Values>("Lights", "lights", "light"),
            Block::Textures => of::<texture::Values>("Textures", "textures", "texture"),
            Block::Texels => of::<texel::Values>("Texels", "texels", "texel"),
            Block::Uvs => of::<triangle::uvs::Values>("TriangleUvs", "triangle_uvs", "triangle_uv"),
            Block::Nodes => ArrayDecl {
                by_words: true,
                ..of::<packed::Values>("Nodes", "nodes", "node")
            },
            Block::Tables => ArrayDecl {
                by_words: true,
                ..of::<table_word::Values>("Tables", "tables", "table")
            },
            _ => return None,
        })
    }
}

/// A kind's block name: its key, capitalised (`Spheres`).
fn block_name(key: &str) -> String {
    let mut c = key.chars();
    c.next()
        .map(|f| f.to_uppercase().chain(c).collect())
        .unwrap_or_default()
}

/// The array's declaration at `binding` in `form`, and its accessor
/// (`{stem}_at(i)`), in GLSL for a shader of `precision`.
pub fn declare(a: &ArrayDecl, binding: u32, form: Form, precision: Precision) -> String {
    let mut s = String::new();
    let stride = words(a.fields, precision);
    let (block, array, item, stem) = (&a.block, a.array, a.item, a.stem);
    let words_decl = |layout: &str, kind: &str, len: &str| {
        format!("layout({layout}, set = 0, binding = {binding}) {kind} {block} {{ uvec4 {array}_words[{len}]; }};\n")
    };
    let fetch: Box<dyn Fn(usize) -> String> = match form {
        Form::Address => {
            let _ = writeln!(
                s,
                "layout(buffer_reference, std430, buffer_reference_align = 16) restrict readonly buffer {block}Words {{ uvec4 w[]; }};\n\
                 layout(std140, set = 0, binding = {binding}) uniform {block}Address {{ {block}Words {array}_words; }};"
            );
            Box::new(move |k| format!("{array}_words.w[at + {k}]"))
        }
        Form::Texels => {
            let _ = writeln!(
                s,
                "layout(set = 0, binding = {binding}) uniform utextureBuffer {array}_texels;"
            );
            Box::new(move |k| format!("texelFetch({array}_texels, at + {k})"))
        }
        Form::Uniform(n) if a.by_words => {
            s += &words_decl("std140", "uniform", &(n * stride).to_string());
            Box::new(move |k| format!("{array}_words[at + {k}]"))
        }
        Form::Storage if a.by_words => {
            s += &words_decl("std430", "readonly buffer", "");
            Box::new(move |k| format!("{array}_words[at + {k}]"))
        }
        Form::Uniform(n) => {
            let _ = writeln!(
                s,
                "layout(std140, set = 0, binding = {binding}) uniform {block} {{ {item} {array}[{n}]; }};"
            );
            Box::new(|_| String::new())
        }
        Form::Storage => {
            let _ = writeln!(
                s,
                "layout(std430, set = 0, binding = {binding}) readonly buffer {block} {{ {item} {array}[]; }};"
            );
            Box::new(|_| String::new())
        }
    };
    let structs = matches!(form, Form::Uniform(_) | Form::Storage) && !a.by_words;
    if structs {
        // A load of a struct whose members go unused loads none of them.
        let _ = writeln!(s, "{item} {stem}_at(uint i) {{\n    return {array}[i];\n}}");
    } else {
        s += &loader(a, "_at", &[], precision, &fetch);
    }
    if let Some(skip) = a.test {
        if structs {
            let _ = writeln!(
                s,
                "{item} {stem}_test_at(uint i) {{\n    return {array}[i];\n}}"
            );
        } else {
            // A texel fetch is a call: a ray test fetches what it reads alone.
            s += &loader(a, "_test_at", skip, precision, &fetch);
        }
    }
    s
}

/// `{stem}{suffix}(i)` from 16-byte words: `word(k)` is the GLSL
/// expression of the element's k-th word (a uvec4), with `at` its first
/// word's index. Floats and doubles are rebuilt from their bits, so the
/// struct is the one the host wrote, bit for bit; the members named in
/// `skip` are not fetched, and are zero.
fn loader(
    a: &ArrayDecl,
    suffix: &str,
    skip: &[&str],
    precision: Precision,
    word: &dyn Fn(usize) -> String,
) -> String {
    let stride = words(a.fields, precision);
    let mut fetches = String::new();
    let mut members = Vec::new();
    let mut k = 0;
    for (name, member) in a.fields {
        let (value, used) = match (member, precision) {
            (Member::Real4, Precision::F32) => (format!("uintBitsToFloat(w{k})"), 1),
            (Member::Real4, Precision::F64) => {
                let (lo, hi) = (k, k + 1);
                (
                    format!(
                        "dvec4(packDouble2x32(w{lo}.xy), packDouble2x32(w{lo}.zw), \
                         packDouble2x32(w{hi}.xy), packDouble2x32(w{hi}.zw))"
                    ),
                    2,
                )
            }
            (Member::Uvec4, _) => (format!("w{k}"), 1),
            (Member::Float4, _) => (format!("uintBitsToFloat(w{k})"), 1),
            // A Float3 shares its word with the Uint after it, which
            // fetches it.
            (Member::Float3, _) => (format!("uintBitsToFloat(w{k}.xyz)"), 0),
            (Member::Uint, _) => (format!("w{k}.w"), 1),
        };
        if skip.contains(name) {
            let zero = match (member, precision) {
                (Member::Real4, Precision::F64) => "dvec4(0.0)",
                (Member::Real4 | Member::Float4, _) => "vec4(0.0)",
                (Member::Uvec4, _) => "uvec4(0u)",
                (Member::Float3, _) => "vec3(0.0)",
                (Member::Uint, _) => "0u",
            };
            members.push(zero.to_owned());
        } else {
            for w in k..k + used {
                let _ = writeln!(fetches, "    uvec4 w{w} = {};", word(w));
            }
            members.push(value);
        }
        k += used;
    }
    format!(
        "{} {}{suffix}(uint i) {{\n    int at = int(i) * {stride};\n{fetches}    return {}({});\n}}\n",
        a.item,
        a.stem,
        a.item,
        members.join(", ")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A read-only array by its block's, array's, struct's and accessor's
    /// names, of a struct with `fields`.
    fn array(
        [block, array, item, stem]: [&'static str; 4],
        fields: &'static [(&'static str, Member)],
    ) -> ArrayDecl {
        ArrayDecl {
            block: block.to_owned(),
            array,
            item,
            stem,
            fields,
            test: None,
            by_words: false,
        }
    }

    fn node() -> ArrayDecl {
        let fields = &[
            ("lo", Member::Float3),
            ("skip", Member::Uint),
            ("hi", Member::Float3),
            ("leaf", Member::Uint),
        ];
        ArrayDecl {
            by_words: true,
            ..array(["Nodes", "nodes", "Node", "node"], fields)
        }
    }

    /// A kind's struct as gpu_struct! lays it out (the reals first), with
    /// `c` read for shading alone.
    fn probe() -> ArrayDecl {
        let fields = &[
            ("a", Member::Real4),
            ("c", Member::Real4),
            ("meta", Member::Uvec4),
        ];
        ArrayDecl {
            test: Some(&["c"]),
            ..array(["Probes", "probes", "Probe", "probe"], fields)
        }
    }

    #[test]
    fn a_texel_accessor_rebuilds_each_member_from_its_words() {
        let f32 = declare(&probe(), 3, Form::Texels, Precision::F32);
        assert!(f32.contains("binding = 3) uniform utextureBuffer probes_texels;"));
        assert!(f32.contains("int at = int(i) * 3;"));
        assert!(
            f32.contains("return Probe(uintBitsToFloat(w0), uintBitsToFloat(w1), w2);"),
            "{f32}"
        );
        let f64 = declare(&probe(), 3, Form::Texels, Precision::F64);
        // A dvec4 takes two words; the struct is padded to six.
        assert!(f64.contains("int at = int(i) * 6;"));
        assert!(f64.contains("uvec4 w4 = texelFetch(probes_texels, at + 4);"));
        assert!(f64.contains("packDouble2x32(w3.zw)), w4);"), "{f64}");
        let node = declare(&node(), 0, Form::Texels, Precision::F64);
        assert!(
            node.contains(
                "return Node(uintBitsToFloat(w0.xyz), w0.w, uintBitsToFloat(w1.xyz), w1.w);"
            ),
            "{node}"
        );
    }

    #[test]
    fn a_ray_test_fetches_no_shading_only_member() {
        let f32 = declare(&probe(), 3, Form::Texels, Precision::F32);
        let test = &f32[f32.find("probe_test_at").expect("a test accessor")..];
        assert!(test.contains("uvec4 w0 = texelFetch(probes_texels, at + 0);"));
        assert!(test.contains("uvec4 w2 = texelFetch(probes_texels, at + 2);"));
        assert!(!test.contains("at + 1"), "{test}");
        assert!(
            test.contains("return Probe(uintBitsToFloat(w0), vec4(0.0), w2);"),
            "{test}"
        );
        let f64 = declare(&probe(), 3, Form::Texels, Precision::F64);
        let test = &f64[f64.find("probe_test_at").expect("a test accessor")..];
        assert!(
            test.contains("at + 1);") && test.contains("at + 4);"),
            "{test}"
        );
        assert!(
            !test.contains("at + 2") && !test.contains("at + 3"),
            "{test}"
        );
        assert!(test.contains(", dvec4(0.0), w4);"), "{test}");
        // Where a load of an unused member costs nothing, the whole struct.
        let uniform = declare(&probe(), 3, Form::Uniform(4), Precision::F32);
        assert!(uniform.contains("Probe probe_test_at(uint i) {\n    return probes[i];"));
    }

    #[test]
    fn each_form_declares_its_block() {
        let uniform = declare(&probe(), 1, Form::Uniform(5), Precision::F32);
        assert!(uniform.contains("uniform Probes { Probe probes[5]; };"));
        assert!(uniform.contains("return probes[i];"));
        let storage = declare(&probe(), 1, Form::Storage, Precision::F32);
        assert!(storage.contains("readonly buffer Probes { Probe probes[]; };"));
        let words = declare(&node(), 2, Form::Uniform(7), Precision::F32);
        assert!(
            words.contains("uniform Nodes { uvec4 nodes_words[14]; };"),
            "{words}"
        );
        assert!(words.contains("uvec4 w1 = nodes_words[at + 1];"));
        let address = declare(&node(), 4, Form::Address, Precision::F32);
        assert!(address.contains("uniform NodesAddress { NodesWords nodes_words; };"));
        assert!(
            address.contains("uvec4 w1 = nodes_words.w[at + 1];"),
            "{address}"
        );
    }
}
