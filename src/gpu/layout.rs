//! What the shader reads, laid out for upload: the structs of the
//! interface (declared once, `gpu_struct!`, with their GLSL), and the
//! scene's arrays in them.

use bytemuck::{Pod, Zeroable};
use glam::UVec4;

use super::Intersect;
use crate::accel::refit::Shape;
use crate::accel::tables::{grid_record, Tables};
use crate::accel::{self, Accel};
use crate::base::interface::{self, Array, GpuStruct};
use crate::base::Precision;
use crate::prim::KINDS;
use crate::scene::Scene;

crate::base::interface::gpu_struct!(
    /// The uniform block.
    pub mod globals: "Globals" {
        eye: real4,
        /// screen_center - eye, taken in f64 on the host
        to_screen: real4,
        screen_right: real4,
        screen_up: real4,
        background: real4,
        /// width, height, samples, max_depth
        size: uvec4,
        /// x lights, y shadows (0 or 1), z the SPD's ray tree (0 or 1),
        /// w 1 where the scene has texels (image textures): a recording
        /// holds the hits' uvs then, as the CPU's does
        lights: uvec4,
        /// primitives of kinds 0..4 of `prim::KINDS`
        kinds_lo: uvec4,
        /// primitives of kinds 4..8
        kinds_hi: uvec4,
        /// x the first word of the tables' cells, y of their entries, z 1
        /// where the eye has its tiles (shaders/tables.glsl)
        tables: uvec4,
        /// The eye's grid (src/accel/tables.rs): a0, b0, sa, sb
        eye_range: float4,
        /// its first cell, na, nb, its form (`GridForm::Perspective`)
        eye_cells: uvec4,
        /// the rows of its map from a direction to (λ, μ, ν)
        eye_r0: float4,
        eye_r1: float4,
        eye_r2: float4,
    }
);

crate::base::interface::gpu_struct!(
    /// A 16-byte word of the light buffers and the eye's tiles
    /// (src/accel/tables.rs, shaders/tables.glsl).
    pub mod table_word: "TableWord" {
        w: uvec4,
    }
);

crate::base::interface::gpu_struct!(
    /// A point adaptive sampling's refinement traces (sampling::adaptive::Point).
    pub mod refine: "Refine" {
        /// x, y the point in 2^-level pixels of the whole image; z the level
        point: uvec4,
    }
);

crate::base::interface::gpu_struct!(
    /// A texel of an image texture: f32 in both precisions, as the files
    /// hold them at most (and the CPU reference reads them).
    pub mod texel: "Texel" {
        /// the linear colour
        rgb: float3,
        unused: uint,
    }
);

fn xyz(v: glam::DVec3) -> [f64; 4] {
    [v.x, v.y, v.z, 0.0]
}

/// The globals of `scene` translated by `-origin` (as `camera_relative`
/// moves the camera where `origin` is the eye).
fn globals(scene: &Scene, origin: glam::DVec3, tables: Option<&Tables>) -> globals::Values {
    let cam = &scene.camera;
    let (eye, screen_center) = (cam.eye - origin, cam.screen_center - origin);
    // Its record, zero where eye rays read no grid.
    let eye_grid = tables
        .and_then(|t| Some(t.grids[t.eye? as usize].gpu()))
        .unwrap_or_default();
    let mut kinds = [0u32; 8];
    for (n, c) in kinds.iter_mut().zip(scene.prims.counts()) {
        *n = c as u32;
    }
    globals::Values {
        eye: xyz(eye),
        to_screen: xyz(screen_center - eye),
        screen_right: xyz(cam.screen_right),
        screen_up: xyz(cam.screen_up),
        background: xyz(scene.background),
        size: [scene.width, scene.height, scene.samples, scene.max_depth],
        lights: [
            scene.lights.len() as u32,
            u32::from(scene.shadows),
            u32::from(scene.spd_rays),
            u32::from(!scene.texels.is_empty()),
        ],
        kinds_lo: [kinds[0], kinds[1], kinds[2], kinds[3]],
        kinds_hi: [kinds[4], kinds[5], kinds[6], kinds[7]],
        tables: tables.map_or([0; 4], |t| {
            let (cells, entries) = table_bases(t);
            [cells, entries, u32::from(t.eye.is_some()), 0]
        }),
        eye_range: eye_grid.range,
        eye_cells: eye_grid.cells,
        eye_r0: eye_grid.row0,
        eye_r1: eye_grid.row1,
        eye_r2: eye_grid.row2,
    }
}

/// The first words of the tables' cells and entries in their array.
fn table_bases(t: &Tables) -> (u32, u32) {
    let cells = GRID_WORDS * t.grids.len();
    (cells as u32, (cells + t.cells.len().div_ceil(2)) as u32)
}

/// The 16-byte words of a grid's record (`grid_record`).
pub(crate) const GRID_WORDS: usize = std::mem::size_of::<grid_record::F32>() / 16;

/// The GLSL of the tables' grid record: its struct, its words, the forms'
/// codes, `TABLE_GRID_AT(word)`, which reads a record from its first word
/// of the tables' array, and `TABLE_GRID_<MEMBER>(word)`, which reads one
/// member (macros: defined before `table_at`, expanded after).
pub(crate) fn grid_record_glsl() -> String {
    use crate::accel::tables::GridForm;
    use crate::base::interface::{declaration, Member};
    let mut s = declaration::<grid_record::Values>();
    s += &format!("const uint TABLE_GRID_WORDS = {GRID_WORDS}u;\n");
    for (form, name) in GridForm::ALL {
        s += &format!("const uint TABLE_{name} = {}u;\n", form as u32);
    }
    // One macro a member, so that a reader of some members loads only
    // their words (a load through a texel buffer is a call on lavapipe).
    let mut members = Vec::new();
    for (i, (name, member)) in <grid_record::Values as GpuStruct>::FIELDS
        .iter()
        .enumerate()
    {
        let word = format!("table_at((at) + {i}u).w");
        let read = match member {
            Member::Float4 => format!("uintBitsToFloat({word})"),
            Member::Uvec4 => word,
            other => unreachable!("a grid record holds no {other:?}"),
        };
        let upper = name.to_uppercase();
        s += &format!("#define TABLE_GRID_{upper}(at) {read}\n");
        members.push(format!("TABLE_GRID_{upper}(at)"));
    }
    s += &format!(
        "#define TABLE_GRID_AT(at) TableGrid({})\n",
        members.join(", ")
    );
    s
}

/// The tables as the shader reads them: each grid's record
/// (`tables::grid_record`), then the cells and the entries two to a word
/// (shaders/tables.glsl).
fn table_words(t: &Tables) -> Vec<table_word::Values> {
    let mut words = Vec::with_capacity(crate::accel::tables::device_bytes(t) / 16);
    let f = |x: f32| x.to_bits();
    for gr in &t.grids {
        let record = [gr.gpu().f32()];
        words.extend(bytemuck::cast_slice::<_, [u32; 4]>(&record));
    }
    for pair in t.cells.chunks(2) {
        let b = pair.get(1).copied().unwrap_or_default();
        words.push([pair[0].first, pair[0].count, b.first, b.count]);
    }
    for pair in t.entries.chunks(2) {
        let b = pair.get(1).map_or([0, 0], |e| [e.leaf, f(e.key)]);
        words.push([pair[0].leaf, f(pair[0].key), b[0], b[1]]);
    }
    words
        .into_iter()
        .map(|w| table_word::Values { w })
        .collect()
}

/// The word the output tile is filled with before each dispatch: a NaN,
/// which the host reads as a pixel no shader wrote (passes.rs,
/// schedule.rs).
pub(crate) const UNWRITTEN: u32 = 0xffff_ffff;

/// The push constant: the tile's origin x, y, width and height, and the
/// wavefront's stage and queue (shaders/wavefront.glsl; zero for the
/// megakernel).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct TileRect {
    pub rect: UVec4,
    pub stage: UVec4,
}

/// Everything the shader reads, laid out for upload.
pub struct Uploads<'a> {
    pub globals: Vec<u8>,
    /// Each kind's array (`prim::KINDS`), in the BVH's leaf order where
    /// the kind is in it.
    pub kinds: Vec<Array<'a>>,
    pub materials: Array<'a>,
    pub lights: Array<'a>,
    pub textures: Array<'a>,
    /// The images' texels (at least one).
    pub texels: Array<'a>,
    /// The triangles' uvs by their index in the file, where any has them.
    pub uvs: Array<'a>,
    /// The BVH's nodes, where the scene is traced through one.
    pub nodes: Option<Array<'a>>,
    /// The entries its walk's stack is declared with (`Bvh::shader_stack`);
    /// 0 without one.
    pub bvh_stack: usize,
    /// Seconds spent building (or refitting) the BVH.
    pub bvh_s: f64,
    /// The BVH's shape, which a later layout of the scene with its
    /// primitives moved refits (`Uploads::fitted`).
    pub shape: Option<Shape>,
    /// What a ray costs through the BVH (`Bvh::ray_cost`), where the scene
    /// has one: the watchdog's measure of the tree that was built.
    pub ray_cost: Option<f64>,
    /// The light buffers and the eye's tiles (`accel::tables`), where the
    /// scene reads them.
    pub tables: Option<Array<'a>>,
    /// Seconds spent building them.
    pub tables_s: f64,
}

impl<'a> Uploads<'a> {
    /// The robust forms trace the scene in camera-relative coordinates (see
    /// `Scene::camera_relative`); the naive ones trace it as written.
    /// Everything is moved item by item as it is laid out: no translated
    /// copy of the scene is held (a million triangles are 192 MB).
    pub fn new(scene: &'a Scene, intersect: Intersect, precision: Precision, accel: Accel) -> Self {
        Self::fitted(scene, intersect, precision, accel, None)
    }

    /// As `new`, the BVH refitted from `shape` (the tree a scene of the
    /// same primitives was built with: `Uploads::shape`) where the
    /// primitives are those it holds, else built.
    pub fn fitted(
        scene: &'a Scene,
        intersect: Intersect,
        precision: Precision,
        accel: Accel,
        shape: Option<&Shape>,
    ) -> Self {
        // A plane's rebase moves its point, so the naive forms take the
        // primitives as written; elsewhere subtracting zero keeps every bit.
        let relative = matches!(intersect, Intersect::Robust).then_some(scene.camera.eye);
        let origin = relative.unwrap_or_default();
        let t0 = std::time::Instant::now();
        let fitted = accel.uses_bvh(&scene.prims).then(|| {
            shape
                .and_then(|s| accel::relative_refit(s, &scene.prims, origin))
                .unwrap_or_else(|| {
                    let tree = accel::relative_bvh(&scene.prims, origin);
                    let shape = Shape::of(&tree);
                    (tree, shape)
                })
        });
        let (mut bvh, shape) = fitted.unzip();
        let bvh_s = t0.elapsed().as_secs_f64();
        let tables = bvh
            .as_ref()
            .filter(|_| accel.uses_tables(&scene.prims))
            .and_then(|tree| scene.tables(tree, origin, (scene.width, scene.height)));
        // Moved out of the BVH, not copied: a million triangles' order is 4 MB.
        let orders: Vec<Option<Vec<u32>>> = (0..KINDS.len())
            .map(|k| {
                let order = std::mem::take(bvh.as_mut()?.orders.get_mut(k)?);
                (!order.is_empty()).then_some(order)
            })
            .collect();
        let bounded = scene.prims.bounded_count();
        let globals = globals(scene, origin, tables.as_ref());
        let globals = match precision {
            Precision::F32 => bytemuck::bytes_of(&globals.f32()).to_vec(),
            Precision::F64 => bytemuck::bytes_of(&globals.f64()).to_vec(),
        };
        let textures = scene.textures.iter().map(|t| t.gpu(origin));
        let texels = interface::array(
            scene
                .texels
                .iter()
                .map(|&rgb| texel::Values { rgb, unused: 0 }),
            precision,
        );
        // By each triangle's index in the file, where any has uvs.
        let uvs = if scene.prims.triangles.iter().any(|t| t.uvs.is_some()) {
            scene
                .prims
                .triangles
                .iter()
                .map(|t| {
                    let [a, b, c] = t.uvs.as_deref().copied().unwrap_or_default();
                    crate::prim::triangle::uvs::Values {
                        uv01: [a[0], a[1], b[0], b[1]],
                        uv2: [c[0], c[1], 0.0, 0.0],
                    }
                })
                .collect()
        } else {
            Vec::new()
        };
        let uvs = interface::array(uvs.into_iter(), precision);
        // Each light with its light buffer (its first grid and reach),
        // where it has one.
        let lights = scene.lights.iter().enumerate().map(|(i, l)| {
            let buffer = tables.as_ref().and_then(|t| {
                let first = t.lights.get(i).copied().flatten()?;
                Some((first, t.grids[first as usize].reach))
            });
            l.gpu(origin, buffer)
        });
        Uploads {
            globals,
            kinds: scene.prims.gpu_arrays(orders, precision, relative),
            materials: interface::array(scene.materials.iter().map(|m| m.gpu()), precision),
            lights: interface::array(lights, precision),
            textures: interface::array(textures, precision),
            texels,
            uvs,
            bvh_stack: bvh.as_ref().map_or(0, |b| b.shader_stack(bounded)),
            ray_cost: bvh.as_ref().map(|b| b.ray_cost()),
            // Written from the BVH's own nodes, which the array keeps.
            nodes: bvh.map(|b| {
                let packed = b.packed;
                let len = packed.len();
                interface::written(
                    len,
                    move |f| packed.iter().for_each(|&n| f(n)),
                    Precision::F32,
                )
            }),
            bvh_s,
            shape,
            tables_s: tables.as_ref().map_or(0.0, |t| t.build_s),
            tables: tables
                .as_ref()
                .map(|t| interface::array(table_words(t).into_iter(), Precision::F32)),
        }
    }

    /// The scene's arrays: each kind's, then the materials, the lights
    /// and the textures.
    pub fn arrays(&self) -> impl Iterator<Item = &Array<'a>> {
        self.kinds
            .iter()
            .chain([&self.materials, &self.lights, &self.textures])
    }

    /// Bytes of each scene array, in the order of `arrays`.
    pub fn array_bytes(&self) -> Vec<usize> {
        self.arrays().map(|a| a.byte_len()).collect()
    }

    /// Elements of each scene array, as uploaded, in the order of `arrays`.
    pub fn array_lengths(&self) -> Vec<usize> {
        self.arrays().map(|a| a.len).collect()
    }

    /// Every read-only array, with its name in messages: each kind's, the
    /// materials, the lights, the textures, the BVH's nodes, the texels and
    /// the uvs.
    fn named_arrays(&self) -> impl Iterator<Item = (&'static str, &Array<'a>)> {
        let names = KINDS
            .iter()
            .map(|k| k.key)
            .chain(["materials", "lights", "textures"]);
        // The nodes and the tables where the scene has them, under their
        // names (a name is never given to the array after a missing one).
        let nodes = self.nodes.as_ref().map(|n| ("BVH nodes", n));
        let tables = self.tables.as_ref().map(|t| ("tables", t));
        names
            .zip(self.arrays())
            .chain(nodes)
            .chain([("texels", &self.texels), ("uvs", &self.uvs)])
            .chain(tables)
    }

    /// Whether every read-only array fits a texel buffer of at most
    /// `max_texels` 16-byte texels (the device's maxTexelBufferElements).
    pub fn fit_texels(&self, max_texels: u32) -> bool {
        self.named_arrays()
            .all(|(_, a)| a.byte_len() as u64 / 16 <= u64::from(max_texels))
    }

    /// Fails, naming the array and the limits, where one array is larger
    /// than a storage buffer of this device can be (lavapipe: 128 MiB,
    /// about four million spheres in f32 and two million in f64); the
    /// arrays are storage buffers where one is longer than a texel buffer
    /// can be (`max_texels`).
    pub fn check_storage_range(&self, limit: u32, max_texels: u32) -> Result<(), String> {
        for (name, array) in self.named_arrays() {
            let bytes = array.byte_len();
            if bytes as u64 > u64::from(limit) {
                return Err(format!(
                    "the scene's {name} take {bytes} bytes, more than this device's \
                     maxStorageBufferRange of {limit} bytes (and its maxTexelBufferElements \
                     of {max_texels} texels of 16 bytes); render fewer objects, in f32 \
                     rather than f64, or with --backend cpu"
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::base::interface::Member;

    #[test]
    fn f64_structs_are_rounded_to_dvec4_alignment() {
        use crate::prim::{plane, sphere};
        use std::mem::size_of;
        assert_eq!(size_of::<globals::F64>(), 5 * 32 + 10 * 16);
        assert_eq!(size_of::<sphere::gpu::F64>(), 64);
        assert_eq!(size_of::<plane::gpu::F64>(), 128);
        assert_eq!(size_of::<crate::scene::material::gpu::F64>(), 160);
        assert_eq!(size_of::<crate::scene::light::gpu::F64>(), 256);
        assert_eq!(size_of::<sphere::gpu::F32>(), 32);
        assert_eq!(size_of::<crate::scene::light::gpu::F32>(), 128);
        assert_eq!(size_of::<crate::accel::quantize::packed::F64>(), 64);
        assert_eq!(size_of::<super::texel::F64>(), 16);
    }

    /// Each member's offset in bytes by the std430 (and std140) rules, and
    /// the struct's size; those of the packed Rust layouts `gpu_struct!`
    /// makes (each member right after the last, the struct padded to its
    /// alignment); equal for every struct the shader reads.
    fn offsets(fields: &[(&str, Member)], precision: Precision, glsl: bool) -> (Vec<usize>, usize) {
        let (mut at, mut align_all, mut out) = (0usize, 16usize, Vec::new());
        for (_, m) in fields {
            let (size, align) = match (m, precision) {
                (Member::Real4, Precision::F64) => (32, 32),
                (Member::Real4 | Member::Uvec4 | Member::Float4, _) => (16, 16),
                (Member::Float3, _) => (12, 16),
                (Member::Uint, _) => (4, 4),
            };
            let align = if glsl { align } else { 4 };
            align_all = align_all.max(align);
            at = at.next_multiple_of(align);
            out.push(at);
            at += size;
        }
        let rust_align =
            if fields.iter().any(|(_, m)| *m == Member::Real4) && precision == Precision::F64 {
                32
            } else {
                16
            };
        (
            out,
            at.next_multiple_of(if glsl { align_all } else { rust_align }),
        )
    }

    #[test]
    fn every_struct_is_laid_out_as_the_shader_reads_it() {
        use crate::accel::quantize::packed;
        use crate::base::interface::words;
        let mut all: Vec<(&str, &[(&str, Member)])> = vec![
            ("Globals", <globals::Values as GpuStruct>::FIELDS),
            (
                "Material",
                <crate::scene::material::gpu::Values as GpuStruct>::FIELDS,
            ),
            (
                "Light",
                <crate::scene::light::gpu::Values as GpuStruct>::FIELDS,
            ),
            (
                "Texture",
                <crate::scene::texture::gpu::Values as GpuStruct>::FIELDS,
            ),
            ("Texel", <texel::Values as GpuStruct>::FIELDS),
            ("Refine", <refine::Values as GpuStruct>::FIELDS),
            ("PackedNode", <packed::Values as GpuStruct>::FIELDS),
            ("TableWord", <table_word::Values as GpuStruct>::FIELDS),
            ("TableGrid", <grid_record::Values as GpuStruct>::FIELDS),
            (
                "TriangleUv",
                <crate::prim::triangle::uvs::Values as GpuStruct>::FIELDS,
            ),
        ];
        all.extend(KINDS.iter().map(|k| (k.struct_name, k.struct_fields)));
        for (name, fields) in all {
            for precision in [Precision::F32, Precision::F64] {
                let glsl = offsets(fields, precision, true);
                assert_eq!(
                    glsl,
                    offsets(fields, precision, false),
                    "{name} in {precision:?}"
                );
                assert_eq!(
                    glsl.1,
                    16 * words(fields, precision),
                    "{name} in {precision:?}"
                );
            }
        }
        // A dvec4 after a lone uvec4 is where the two disagree.
        let bad = [("meta", Member::Uvec4), ("n", Member::Real4)];
        assert_ne!(
            offsets(&bad, Precision::F64, true),
            offsets(&bad, Precision::F64, false)
        );
    }

    /// 64 spheres in a row, for what a BVH scene uploads.
    pub(in crate::gpu) fn row() -> Scene {
        let mut text = String::from(
            "[image]\nwidth = 4\nheight = 4\n[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nvfov = 40\n\
             [materials.m]\n",
        );
        for i in 0..64 {
            text += &format!(
                "[[spheres]]\ncenter = [{}, 0, 0]\nradius = 1\nmaterial = \"m\"\n",
                3 * i
            );
        }
        crate::scene::parse(
            &text,
            std::path::Path::new("t.toml"),
            &crate::scene::Overrides::default(),
        )
        .unwrap()
    }

    #[test]
    fn arrays_over_the_storage_range_are_named() {
        let scene = row();
        for (precision, sphere_bytes) in [(Precision::F32, 32), (Precision::F64, 64)] {
            let up = Uploads::new(&scene, Intersect::Robust, precision, Accel::Bvh);
            let nodes = up.nodes.as_ref().unwrap().byte_len();
            let spheres = up.kinds[0].byte_len();
            assert_eq!(spheres, 64 * sphere_bytes);
            let biggest = up.array_bytes().into_iter().chain([nodes]).max().unwrap();
            assert!(up.check_storage_range(biggest as u32, 0).is_ok());
            assert!(up.fit_texels(biggest as u32 / 16));
            assert!(!up.fit_texels(biggest as u32 / 16 - 1));
            let err = up.check_storage_range(spheres as u32 - 1, 0).unwrap_err();
            assert!(
                err.contains(&format!("spheres take {spheres} bytes")),
                "{err}"
            );
            if nodes > spheres {
                let err = up.check_storage_range(nodes as u32 - 1, 0).unwrap_err();
                assert!(err.contains("BVH nodes"), "{err}");
            }
        }
    }
}
