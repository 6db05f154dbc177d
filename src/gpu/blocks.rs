//! The shader's blocks, and how it reads a read-only one: the names the
//! variant (variant.rs), the read forms (access.rs, features.rs) and the
//! uploads share, kept below all of them.

use crate::prim::KINDS;

/// The shader's blocks, in binding order (src/gpu/generated.rs declares them).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Block {
    /// The uniform block: camera, settings, counts.
    Globals,
    /// One kind of primitive's array, by its place in `prim::KINDS`.
    Kind(usize),
    /// The materials.
    Materials,
    /// The lights.
    Lights,
    /// The textures, where a material has one.
    Textures,
    /// The images' texels, where a material has an image texture.
    Texels,
    /// The triangles' uvs, where an image texture may need them.
    Uvs,
    /// The BVH's nodes.
    Nodes,
    /// The light buffers and the eye's tiles (src/accel/tables.rs).
    Tables,
    /// The counters of `--stats` (src/stats.rs), where the variant counts.
    Counts,
    /// The ray tree of one sample, where the variant records
    /// (shaders/record.glsl).
    Record,
    /// The points of a level of adaptive sampling's refinement.
    Refine,
    /// The wavefront's paths: their rays, weights, colours and sums, and
    /// their waiting refraction rays (shaders/wavefront.glsl).
    PathReals,
    /// The same paths' indices, depths, samples and stack tops.
    PathWords,
    /// The wavefront's two queues of live paths, with their counts and
    /// indirect dispatch sizes.
    Queues,
    /// The output tile the shader writes.
    Pixels,
    /// The output tile's AOVs, where the variant writes them
    /// (shaders/aov.glsl).
    Aovs,
}

impl Block {
    /// Its name in GLSL and in messages.
    pub fn name(self) -> &'static str {
        match self {
            Block::Globals => "Globals",
            Block::Kind(k) => KINDS[k].key,
            Block::Materials => "materials",
            Block::Lights => "lights",
            Block::Textures => "textures",
            Block::Texels => "texels",
            Block::Uvs => "uvs",
            Block::Nodes => "BVH nodes",
            Block::Tables => "tables",
            Block::Counts => "the counters",
            Block::Record => "the recorded ray tree",
            Block::Refine => "the points to refine",
            Block::PathReals => "the paths",
            Block::PathWords => "the paths' words",
            Block::Queues => "the path queues",
            Block::Pixels => "the output tile",
            Block::Aovs => "the output tile's AOVs",
        }
    }

    /// A read-write or write-only storage block's declaration after its
    /// `layout(...)`: its qualifier, its GLSL name and its members.
    /// The read-only arrays (access.rs) and the uniform block have none.
    pub fn storage(self) -> Option<&'static str> {
        Some(match self {
            Block::Counts => "buffer Counts { uint count_words[]; }",
            Block::Record => "buffer Record { uvec4 record_at; uint record_count; uint record_pad[3]; uint record_words[]; }",
            Block::Refine => "readonly buffer RefineList { Refine refine_list[]; }",
            Block::PathReals => "buffer PathReals { vec4r path_reals[]; }",
            Block::PathWords => "buffer PathWords { uvec4 path_words[]; }",
            Block::Queues => "buffer Queues { uint wave_header[8]; uint wave_queue[]; }",
            Block::Pixels => "writeonly buffer Pixels { vec4 pixels[]; }",
            Block::Aovs => "writeonly buffer Aovs { uvec4 aov_words[]; }",
            Block::Globals
            | Block::Kind(_)
            | Block::Materials
            | Block::Lights
            | Block::Textures
            | Block::Texels
            | Block::Uvs
            | Block::Nodes
            | Block::Tables => return None,
        })
    }
}

/// How the shader reads one read-only array.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Form {
    /// A uniform block of this many elements.
    Uniform(usize),
    /// A storage buffer.
    Storage,
    /// A uniform texel buffer.
    Texels,
    /// A buffer read through its device address (GL_EXT_buffer_reference),
    /// which a uniform block at the binding holds.
    Address,
}
