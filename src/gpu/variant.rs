//! What the shader is compiled with for a scene and device: the features
//! the scene needs (everything else is left out of the shader), the
//! constants that replace run-time counts, and the bindings that go with
//! them. `--generic` compiles the one shader that handles every feature.

use ash::vk;

use super::access::Form;
use super::layout::Uploads;
use super::vk::device::DeviceInfo;
use super::Intersect;
use crate::base::Precision;
use crate::prim::KINDS;
use crate::scene::{LightKind, Scene};

/// Unrolling the scene loops is worth its compile time up to this many
/// primitives (each loop body is copied once per object, at every
/// place the shader walks the scene). Also, lavapipe (Mesa 22.3) was seen to
/// miscompile the unrolled shadow loop of a scene with 103 objects; 60 were
/// right; `glint compare` and the tests catch such a thing.
const UNROLL_OBJECTS: usize = 64;
const UNROLL_LIGHTS: usize = 16;

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
    /// The counters of `--stats` (src/stats.rs), where the variant counts.
    Counts,
    /// The pixels adaptive sampling refines, with their corners.
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
            Block::Counts => "the counters",
            Block::Refine => "the pixels to refine",
            Block::PathReals => "the paths",
            Block::PathWords => "the paths' words",
            Block::Queues => "the path queues",
            Block::Pixels => "the output tile",
        }
    }
}

/// A shader variant: what one scene and its settings compile the shader
/// with (docs/shaders.md, Variants). Each is its own pipeline.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Variant {
    /// The intersection forms.
    pub intersect: Intersect,
    /// The shader's arithmetic.
    pub precision: Precision,
    /// The entries of the BVH walk's stack (shaders/bvh.glsl), three for
    /// each node on the tree's deepest path, where the bounded kinds are
    /// traced through one; 0: a linear scan.
    pub bvh_stack: usize,
    /// None: the generic shader.
    pub features: Option<Features>,
    /// Counts rays, tests and BVH nodes (shaders/count.glsl).
    pub count: bool,
    /// The robust forms' cheap filter (`power()` in shaders/exact.glsl),
    /// taken where the device skips a branch no invocation takes.
    pub power_filter: bool,
    /// Adaptive sampling's second pass (shaders/adaptive.glsl): the bits of
    /// the threshold in steps of 1/255, and the levels; None: a render of
    /// pixels.
    pub refine: Option<(u64, u32)>,
    /// The wavefront schedule (shaders/wavefront.glsl) rather than one
    /// invocation for each pixel's whole ray tree.
    pub wavefront: bool,
    /// How the scene's read-only arrays outside uniform blocks are read
    /// (src/gpu/access.rs): `Storage`, `Texels` or `Address`.
    pub reads: Form,
}

/// The width of the list of pixels adaptive sampling refines, as its
/// second pass dispatches it: entry i at (i % width, i / width).
pub const REFINE_WIDTH: u32 = 64;

/// What one scene needs of the shader.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Features {
    /// Primitives of each kind (`prim::KINDS`).
    pub kinds: Vec<usize>,
    /// Lights.
    pub lights: usize,
    /// Whether a point light is among them.
    pub point: bool,
    /// Whether a directional light is among them.
    pub directional: bool,
    /// Whether a spot light is among them.
    pub spot: bool,
    /// A point or spot light whose falloff is not [1, 0, 0].
    pub attenuation: bool,
    /// Shadows on, with lights and objects to cast them.
    pub shadows: bool,
    /// A material transmits: the shader keeps a stack of refraction rays.
    pub transmits: bool,
    /// The SPD's ray tree (`Scene::spd_rays`).
    pub spd_rays: bool,
    /// A material of the scene has a texture.
    pub textures: bool,
    /// One of them is an image.
    pub images: bool,
    /// And a triangle has uvs.
    pub uvs: bool,
    /// Ray segments traced: 1 where no material reflects or transmits.
    pub max_depth: u32,
    /// Samples a side of each pixel.
    pub samples: u32,
    /// The scene's arrays as uniform buffers of these lengths (each kind's,
    /// then materials, lights) where they fit; else storage buffers.
    pub uniform_slots: Option<Vec<usize>>,
    /// Whether the scene loops are unrolled (few objects and lights, all
    /// in uniform blocks).
    pub unroll: bool,
    /// Where the scene's arrays are not all uniform blocks: the materials,
    /// the lights and the textures in uniform blocks of these lengths, where
    /// each fits.
    pub table_slots: Option<[usize; 3]>,
    /// Whether the lights' loop alone is unrolled (few lights, in a
    /// uniform block).
    pub unroll_lights: bool,
    /// Whether the shader carries the loop-budget canary
    /// (`DeviceInfo::loop_budget`).
    pub canary: bool,
    /// BVH nodes; 0 without a BVH.
    pub nodes: usize,
}

/// Overrides of the variant choice, for measuring it on a driver
/// (docs/performance.md, Two lavapipes): `GLINT_EXPERIMENT` holds a
/// comma-separated list of `storage` (never uniform buffers),
/// `uniforms-always` (uniform buffers for the scenes that take storage
/// buffers to dodge Mesa 22.3's crash), `no-unroll` and `unroll-all` (no
/// cap on the objects and lights unrolled), `canary` (the loop-budget
/// canary on a driver that needs none), `no-filter` (the robust forms'
/// exact power everywhere, also where the device skips untaken branches),
/// `no-uniform-tables` (the small tables read as the large arrays where
/// these are no uniform blocks), `storage-reads`, `texel-reads`,
/// `address-reads` (the arrays outside
/// uniform blocks read that way, where the device can). Not for
/// rendering: a name it does not know is ignored.
#[derive(Debug, Default, Clone, Copy)]
struct Experiment {
    storage: bool,
    uniforms_always: bool,
    no_unroll: bool,
    unroll_all: bool,
    canary: bool,
    no_filter: bool,
    no_uniform_tables: bool,
    reads: Option<Form>,
}

impl Experiment {
    fn from_env() -> Self {
        let v = std::env::var("GLINT_EXPERIMENT").unwrap_or_default();
        let has = |name: &str| v.split(',').any(|f| f.trim() == name);
        Self {
            storage: has("storage"),
            uniforms_always: has("uniforms-always"),
            no_unroll: has("no-unroll"),
            unroll_all: has("unroll-all"),
            canary: has("canary"),
            no_filter: has("no-filter"),
            no_uniform_tables: has("no-uniform-tables"),
            reads: if has("storage-reads") {
                Some(Form::Storage)
            } else if has("texel-reads") {
                Some(Form::Texels)
            } else if has("address-reads") {
                Some(Form::Address)
            } else {
                None
            },
        }
    }
}

impl Features {
    /// What `scene`, laid out as `uploads`, needs on `device`.
    pub(crate) fn of(scene: &Scene, uploads: &Uploads, device: &DeviceInfo) -> Self {
        let has = |k: LightKind| scene.lights.iter().any(|l| l.kind == k);
        let kinds = scene.prims.counts();
        let objects = !scene.prims.is_empty();
        let lights = scene.lights.len();
        let reflects = scene.materials.iter().any(|m| m.reflectivity > 0.0);
        let transmits = scene.materials.iter().any(|m| m.transmittance > 0.0);
        // Lavapipe (Mesa 22.3) crashes in a worker thread rendering the
        // uniform-buffer variant of two kinds of scene: without spheres
        // (planes and lights only), and with spheres as the only primitives
        // and directional lights as the only lights (tests/variants.rs
        // renders every mix of kinds and light types). Those take storage
        // buffers.
        let range = device.max_uniform_buffer_range as usize;
        let spheres = scene.prims.spheres.len();
        let spheres_only = spheres == scene.prims.len();
        let positioned = has(LightKind::Point) || has(LightKind::Spot);
        let experiment = Experiment::from_env();
        let images = objects && scene.has_image_textures();
        let uniforms = (experiment.uniforms_always
            || spheres > 0 && !(spheres_only && lights > 0 && !positioned))
            && !experiment.storage;
        let fits = uniforms
            && uploads.array_bytes().iter().all(|b| *b <= range)
            && uploads
                .nodes
                .as_ref()
                .is_none_or(|n| n.bytes.len() <= range);
        // Where the arrays do not all fit, the small tables still do: each
        // read in uniform blocks, and the lights' loop unrolled, so that a
        // light is read at a constant offset (docs/performance.md, Reading
        // the scene).
        let tables = [&uploads.materials, &uploads.lights, &uploads.textures];
        let table_slots = (uniforms
            && !fits
            && !experiment.no_uniform_tables
            && tables.iter().all(|t| t.bytes.len() <= range))
        .then(|| tables.map(|t| t.len));
        Self {
            unroll: fits
                && !experiment.no_unroll
                && (experiment.unroll_all
                    || scene.prims.len() <= UNROLL_OBJECTS && lights <= UNROLL_LIGHTS),
            unroll_lights: table_slots.is_some()
                && !experiment.no_unroll
                && lights <= UNROLL_LIGHTS,
            table_slots,
            canary: device.loop_budget || experiment.canary,
            kinds,
            lights,
            point: has(LightKind::Point),
            directional: has(LightKind::Directional),
            spot: has(LightKind::Spot),
            attenuation: scene.lights.iter().any(|l| {
                l.kind != LightKind::Directional && l.attenuation != glam::DVec3::new(1.0, 0.0, 0.0)
            }),
            shadows: scene.shadows && objects && lights > 0,
            transmits: transmits && scene.max_depth > 1,
            spd_rays: scene.spd_rays,
            textures: objects
                && scene
                    .materials
                    .iter()
                    .any(|m| m.texture.is_some() || m.ambient_texture.is_some()),
            images,
            uvs: images && scene.prims.triangles.iter().any(|t| t.uvs.is_some()),
            max_depth: if reflects || transmits {
                scene.max_depth
            } else {
                1
            },
            samples: scene.samples,
            uniform_slots: fits.then(|| uploads.array_lengths()),
            nodes: uploads.nodes.as_ref().map_or(0, |n| n.len),
        }
    }

    fn defines(&self, d: &mut Vec<(String, Option<String>)>) {
        let mut def = |name: &str, value: String| d.push((name.to_owned(), Some(value)));
        let flag = |b: bool| u8::from(b).to_string();
        for (kind, n) in KINDS.iter().zip(&self.kinds) {
            def(&format!("HAS_{}", kind.upper()), flag(*n > 0));
            def(&format!("{}_COUNT", kind.upper()), format!("{n}u"));
        }
        def("HAS_POINT", flag(self.point));
        def("HAS_DIRECTIONAL", flag(self.directional));
        def("HAS_SPOT", flag(self.spot));
        def("HAS_ATTENUATION", flag(self.attenuation));
        def("HAS_SHADOWS", flag(self.shadows));
        def("HAS_TRANSMISSION", flag(self.transmits));
        def("SHADOWS_ON", "true".to_owned());
        def("SPD_RAYS", self.spd_rays.to_string());
        def("HAS_TEXTURES", flag(self.textures));
        def("HAS_IMAGES", flag(self.images));
        def("HAS_UVS", flag(self.uvs));
        def("MAX_DEPTH", format!("{}u", self.max_depth));
        def("SAMPLES", format!("{}u", self.samples));
        def("LIGHT_COUNT", format!("{}u", self.lights));
        if let Some(slots) = &self.uniform_slots {
            d.push(("SCENE_IN_UNIFORMS".to_owned(), None));
            let names = KINDS
                .iter()
                .map(|k| k.upper())
                .chain(["MATERIALS", "LIGHTS", "TEXTURES"].map(String::from));
            for (name, n) in names.zip(slots) {
                d.push((format!("{name}_SLOTS"), Some(format!("{n}u"))));
            }
        }
        if self.unroll {
            d.push(("UNROLL_LOOPS".to_owned(), None));
        }
        if self.unroll_lights {
            d.push(("UNROLL_LIGHTS".to_owned(), None));
        }
        if !self.canary {
            d.push(("NO_LOOP_CANARY".to_owned(), None));
        }
    }
}

/// How `device` reads the scene's arrays that are no uniform blocks
/// (docs/performance.md, Reading the scene): through texel buffers where
/// every array fits one, else as storage buffers. (Device addresses, an
/// experiment, measured slower on llvmpipe where LLVM turns their gathers
/// into a branch a lane.)
fn reads(uploads: &Uploads, device: &DeviceInfo) -> Form {
    let texels = uploads.fit_texels(device.max_texel_buffer_elements);
    let wanted = Experiment::from_env().reads.unwrap_or(Form::Texels);
    match wanted {
        Form::Address if device.buffer_device_address => Form::Address,
        Form::Address | Form::Texels if texels => Form::Texels,
        _ => Form::Storage,
    }
}

impl Variant {
    /// The variant of `scene`, laid out as `uploads`, with these settings:
    /// the generic shader where `generic`, the counting one where `count`.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn for_scene(
        scene: &Scene,
        uploads: &Uploads,
        intersect: Intersect,
        precision: Precision,
        device: &DeviceInfo,
        generic: bool,
        count: bool,
    ) -> Self {
        Self {
            intersect,
            precision,
            bvh_stack: uploads.bvh_stack,
            features: (!generic).then(|| Features::of(scene, uploads, device)),
            count,
            // The generic shader takes it too: a scene's variant renders the
            // generic shader's bits.
            power_filter: intersect == Intersect::Robust
                && device.skips_untaken_branches
                && !Experiment::from_env().no_filter,
            refine: None,
            wavefront: false,
            reads: reads(uploads, device),
        }
    }

    /// The generic shader in f32 with the robust forms and no BVH (`glint
    /// shader check` compiles a user's file against its interface).
    pub fn generic() -> Self {
        Self {
            intersect: Intersect::Robust,
            precision: Precision::F32,
            bvh_stack: 0,
            features: None,
            count: false,
            power_filter: false,
            refine: None,
            wavefront: false,
            reads: Form::Storage,
        }
    }

    /// The defines that select this variant in the shader's source.
    pub fn defines(&self) -> Vec<(String, Option<String>)> {
        let mut d = Vec::new();
        if self.intersect == Intersect::Naive {
            d.push(("INTERSECT_NAIVE".to_owned(), None));
        }
        if self.precision == Precision::F64 {
            d.push(("GLINT_F64".to_owned(), None));
        }
        if self.power_filter {
            d.push(("POWER_FILTER".to_owned(), None));
        }
        if self.bvh_stack > 0 {
            d.push(("USE_BVH".to_owned(), None));
            d.push(("BVH_STACK".to_owned(), Some(format!("{}u", self.bvh_stack))));
        }
        if self.count {
            d.push(("COUNT_RAYS".to_owned(), None));
        }
        if let Some((bits, levels)) = self.refine {
            // Shortest digits that give the f64 back: f32 rounds them as the
            // CPU's f32 does, and `lf` keeps all of them in f64.
            let suffix = if self.precision == Precision::F64 {
                "lf"
            } else {
                ""
            };
            let threshold = format!("{:e}{suffix}", f64::from_bits(bits));
            d.push(("ADAPTIVE_LEVELS".to_owned(), Some(format!("{levels}u"))));
            d.push(("ADAPTIVE_THRESHOLD".to_owned(), Some(threshold)));
            d.push(("REFINE_WIDTH".to_owned(), Some(format!("{REFINE_WIDTH}u"))));
        }
        if self.wavefront {
            let (reals, words) = self.path_strides();
            d.push(("WAVEFRONT".to_owned(), None));
            d.push(("WAVE_REALS".to_owned(), Some(format!("{reals}u"))));
            d.push(("WAVE_WORDS".to_owned(), Some(format!("{words}u"))));
        }
        if let Some(f) = &self.features {
            f.defines(&mut d);
        }
        d
    }

    /// A wavefront path's vec4s in `PathReals` and uvec4s in `PathWords`:
    /// four and two, and two and one more for each refraction ray its stack
    /// holds (shaders/wavefront.glsl).
    pub(crate) fn path_strides(&self) -> (u64, u64) {
        let stack = match &self.features {
            Some(f) if !f.transmits => 0,
            Some(f) => u64::from(f.max_depth),
            None => u64::from(crate::scene::MAX_DEPTH),
        };
        (4 + 2 * stack, 2 + stack)
    }

    /// Bytes a wavefront path takes in `PathReals` and in `PathWords`.
    pub(crate) fn path_bytes(&self) -> (u64, u64) {
        let (reals, words) = self.path_strides();
        let real = match self.precision {
            Precision::F32 => 16,
            Precision::F64 => 32,
        };
        (reals * real, words * 16)
    }

    /// The blocks the shader declares, with their binding numbers (dense
    /// from 0, in the order of docs/shaders.md's table).
    pub fn blocks(&self) -> Vec<(Block, u32)> {
        self.bindings()
            .into_iter()
            .map(|(b, n, _)| (b, n))
            .collect()
    }

    /// The blocks the shader declares, numbered densely from 0, with their
    /// descriptor types.
    pub(crate) fn bindings(&self) -> Vec<(Block, u32, vk::DescriptorType)> {
        let scene_type = |block| match self.form(block) {
            // An address's block holds the array's address.
            Form::Uniform(_) | Form::Address => vk::DescriptorType::UNIFORM_BUFFER,
            Form::Storage => vk::DescriptorType::STORAGE_BUFFER,
            Form::Texels => vk::DescriptorType::UNIFORM_TEXEL_BUFFER,
        };
        let (kinds, lights, textures, images, uvs) = match &self.features {
            Some(f) => (
                f.kinds.iter().map(|n| *n > 0).collect(),
                f.lights > 0,
                f.textures,
                f.images,
                f.uvs,
            ),
            None => (vec![true; KINDS.len()], true, true, true, true),
        };
        let objects = kinds.iter().any(|k| *k);
        let mut blocks = vec![(Block::Globals, true, vk::DescriptorType::UNIFORM_BUFFER)];
        blocks.extend(
            kinds
                .iter()
                .enumerate()
                .map(|(k, used)| (Block::Kind(k), *used, scene_type(Block::Kind(k)))),
        );
        blocks.extend([
            (Block::Materials, objects, scene_type(Block::Materials)),
            (Block::Textures, textures, scene_type(Block::Textures)),
            (Block::Texels, images, scene_type(Block::Texels)),
            (Block::Uvs, uvs, scene_type(Block::Uvs)),
            (Block::Lights, lights, scene_type(Block::Lights)),
            (Block::Nodes, self.bvh_stack > 0, scene_type(Block::Nodes)),
            (
                Block::Counts,
                self.count,
                vk::DescriptorType::STORAGE_BUFFER,
            ),
            (
                Block::Refine,
                self.refine.is_some(),
                vk::DescriptorType::STORAGE_BUFFER,
            ),
            (
                Block::PathReals,
                self.wavefront,
                vk::DescriptorType::STORAGE_BUFFER,
            ),
            (
                Block::PathWords,
                self.wavefront,
                vk::DescriptorType::STORAGE_BUFFER,
            ),
            (
                Block::Queues,
                self.wavefront,
                vk::DescriptorType::STORAGE_BUFFER,
            ),
            (Block::Pixels, true, vk::DescriptorType::STORAGE_BUFFER),
        ]);
        blocks
            .into_iter()
            .filter(|(_, used, _)| *used)
            .enumerate()
            .map(|(i, (block, _, ty))| (block, i as u32, ty))
            .collect()
    }

    /// The place of `block` among the bindings, where the shader declares it.
    pub fn binding_of(&self, block: Block) -> Option<usize> {
        self.bindings().iter().position(|(b, _, _)| *b == block)
    }

    /// (binding, descriptor type) for the descriptor set layout.
    pub(crate) fn descriptor_layout(&self) -> Vec<(u32, vk::DescriptorType)> {
        self.bindings()
            .into_iter()
            .map(|(_, b, t)| (b, t))
            .collect()
    }

    /// Whether the scene's arrays are uniform buffers (else texel or
    /// storage buffers).
    pub fn in_uniforms(&self) -> bool {
        self.features
            .as_ref()
            .is_some_and(|f| f.uniform_slots.is_some())
    }

    /// How the shader reads `block`, one of the scene's read-only arrays
    /// (src/gpu/access.rs): a uniform block where the scene's arrays fit
    /// the uniform range (the images' texels and the triangles' uvs never
    /// do), else a texel buffer where the device takes them, else a storage
    /// buffer.
    pub fn form(&self, block: Block) -> Form {
        let slots = self.features.as_ref().and_then(|f| {
            if let Some([materials, lights, textures]) = f.table_slots {
                match block {
                    Block::Materials => return Some(materials),
                    Block::Lights => return Some(lights),
                    Block::Textures => return Some(textures),
                    _ => return None,
                }
            }
            let slots = f.uniform_slots.as_ref()?;
            let kinds = KINDS.len();
            match block {
                Block::Kind(k) => Some(slots[k]),
                Block::Materials => Some(slots[kinds]),
                Block::Lights => Some(slots[kinds + 1]),
                Block::Textures => Some(slots[kinds + 2]),
                Block::Nodes => Some(f.nodes),
                _ => None,
            }
        });
        match slots {
            Some(n) => Form::Uniform(n),
            None => self.reads,
        }
    }

    /// A short name for files and messages: the generic shader, or the
    /// features this variant keeps.
    pub fn name(&self) -> String {
        let mut parts = vec![match self.intersect {
            Intersect::Robust => "robust",
            Intersect::Naive => "naive",
        }
        .to_owned()];
        if self.precision == Precision::F64 {
            parts.push("f64".to_owned());
        }
        if self.bvh_stack > 0 {
            parts.push(format!("bvh{}", self.bvh_stack));
        }
        if self.count {
            parts.push("counted".to_owned());
        }
        if let Some((_, levels)) = self.refine {
            parts.push(format!("refine{levels}"));
        }
        if self.wavefront {
            parts.push("wavefront".to_owned());
        }
        match self.reads {
            Form::Texels => parts.push("texels".to_owned()),
            Form::Address => parts.push("address".to_owned()),
            _ => {}
        }
        if self.power_filter {
            parts.push("filtered".to_owned());
        }
        match &self.features {
            None => parts.push("generic".to_owned()),
            Some(f) => {
                let counts: Vec<String> = KINDS
                    .iter()
                    .zip(&f.kinds)
                    .map(|(k, n)| format!("{}{n}", k.key))
                    .collect();
                parts.push(format!("{}-l{}", counts.join("-"), f.lights));
                for (on, name) in [
                    (f.point, "point"),
                    (f.directional, "dir"),
                    (f.spot, "spot"),
                    (f.attenuation, "att"),
                    (f.shadows, "shadows"),
                    (f.transmits, "refract"),
                    (f.uniform_slots.is_some(), "ubo"),
                    (f.table_slots.is_some(), "tables"),
                    (f.unroll, "unrolled"),
                    (f.unroll_lights, "lights"),
                    (!f.canary, "nocanary"),
                ] {
                    if on {
                        parts.push(name.to_owned());
                    }
                }
                parts.push(format!("d{}-ss{}", f.max_depth, f.samples));
            }
        }
        parts.join("-")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::Accel;

    #[test]
    fn an_array_longer_than_a_texel_buffer_makes_them_storage_buffers() {
        let scene = super::super::layout::tests::row();
        let up = Uploads::new(&scene, Intersect::Robust, Precision::F32, Accel::Bvh);
        let mut device = DeviceInfo {
            max_texel_buffer_elements: u32::MAX,
            ..DeviceInfo::default()
        };
        assert_eq!(reads(&up, &device), Form::Texels);
        // The 64 spheres are 128 texels; the nodes fewer.
        device.max_texel_buffer_elements = 127;
        assert_eq!(reads(&up, &device), Form::Storage);
        device.max_texel_buffer_elements = 128;
        assert_eq!(reads(&up, &device), Form::Texels);
    }
}
