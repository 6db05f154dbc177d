//! What the shader is compiled with for a scene and device: the features
//! the scene needs (everything else is left out of the shader), the
//! constants that replace run-time counts, and the bindings that go with
//! them. `--generic` compiles the one shader that handles every feature.

use ash::vk;

pub use super::blocks::Block;
use super::blocks::Form;
pub use super::features::Features;
use super::features::{reads, Experiment};
use super::layout::Uploads;
use super::vk::device::DeviceInfo;
use super::Intersect;
use crate::base::Precision;
use crate::prim::KINDS;
use crate::scene::Scene;

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
    /// Whether shadow and eye rays read the light buffers and the eye's
    /// tiles (src/accel/tables.rs) before the walk.
    pub tables: bool,
    /// None: the generic shader.
    pub features: Option<Features>,
    /// Counts rays, tests and BVH nodes (shaders/count.glsl).
    pub count: bool,
    /// Records one sample's ray tree (shaders/record.glsl, `glint explain`).
    pub record: bool,
    /// Writes each pixel's AOVs (shaders/aov.glsl, src/base/aov.rs).
    pub aovs: bool,
    /// The robust forms' cheap filter (`power()` in shaders/exact.glsl),
    /// taken where the device skips a branch no invocation takes.
    pub power_filter: bool,
    /// Adaptive sampling's refinement (shaders/adaptive.glsl): one
    /// invocation a listed point of a level; false: one a pixel.
    pub refine: bool,
    /// Contrast sampling's levels (shaders/contrast.glsl), with the
    /// refinement's list: one invocation a listed entry; true where the
    /// samples' ray trees are compared.
    pub contrast: Option<bool>,
    /// The wavefront schedule (shaders/wavefront.glsl) rather than one
    /// invocation for each pixel's whole ray tree.
    pub wavefront: bool,
    /// How the scene's read-only arrays outside uniform blocks are read
    /// (src/gpu/access.rs): `Storage`, `Texels` or `Address`.
    pub reads: Form,
}

/// The width of the list of points adaptive sampling's refinement traces,
/// as each level dispatches it: invocation (i % width, i / width) traces
/// points `REFINE_POINTS`·i onwards.
pub const REFINE_WIDTH: u32 = 64;

/// The words one invocation of contrast sampling writes for its entry:
/// the samples' sum, least and greatest colour, and trees
/// (shaders/contrast.glsl).
pub const CONTRAST_OUTPUTS: u32 = 4;

/// The points one invocation of the refinement traces, one after another:
/// an invocation's fixed costs (and, counting, its atomic adds) are shared
/// by four ray trees, as a pixel's samples share them.
pub const REFINE_POINTS: u32 = 4;

/// What a render asks of its variant, besides its scene and its device.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Request {
    /// The intersection forms.
    pub intersect: Intersect,
    /// The arithmetic's precision.
    pub precision: Precision,
    /// The generic shader, not the scene's variant.
    pub generic: bool,
    /// The schedule asked for.
    pub schedule: crate::settings::Schedule,
    /// Whether it records a sample's ray tree (`glint explain`).
    pub record: bool,
    /// Whether it writes AOVs.
    pub aovs: bool,
    /// Whether it counts its rays (`--stats`).
    pub count: bool,
    /// Whether the main shader is glint's own (no `--shader`), the only one
    /// that knows the wavefront's stages.
    pub main_is_glints: bool,
}

impl Variant {
    /// The variant of `scene`, laid out as `uploads`, on `device`, for
    /// `request`: everything that decides a variant is decided here, from
    /// what the scene needs (`Features::of`), what the device's driver
    /// needs worked around (`DeviceInfo`'s flags, from `workarounds.rs`)
    /// and what the render asks (its settings, counts, schedule).
    pub(crate) fn for_scene(
        scene: &Scene,
        uploads: &Uploads,
        device: &DeviceInfo,
        request: &Request,
    ) -> Self {
        // A tree is recorded by the megakernel alone, and one sample's tree
        // is all a recording render is for: it neither counts nor writes
        // AOVs. AOVs are a megakernel's, of a pixel's own samples; their
        // rays are the counting variant's counts of the pixel's invocation.
        let record = request.record;
        let aovs = request.aovs && !record;
        let count = (request.count || aovs) && !record;
        // A shader of the user's knows nothing of the wavefront's stages.
        let wavefront =
            request.main_is_glints && !record && !aovs && request.schedule.wavefront_for(scene);
        Self {
            intersect: request.intersect,
            precision: request.precision,
            bvh_stack: uploads.bvh_stack,
            tables: uploads.tables.is_some(),
            features: (!request.generic).then(|| Features::of(scene, uploads, device)),
            count,
            record,
            aovs,
            // The generic shader takes it too: a scene's variant renders the
            // generic shader's bits.
            power_filter: request.intersect == Intersect::Robust
                && device.skips_untaken_branches
                && !Experiment::from_env().no_filter,
            refine: false,
            contrast: None,
            wavefront,
            reads: reads(uploads, device),
        }
    }

    /// This variant made to trace a list: adaptive sampling's points, or
    /// contrast sampling's entries where `contrast` (its trees compared or
    /// not). A list is the megakernel's, and records no tree and writes no
    /// AOVs.
    pub(crate) fn listing(&self, contrast: Option<bool>) -> Self {
        Self {
            refine: true,
            contrast,
            wavefront: false,
            record: false,
            aovs: false,
            ..self.clone()
        }
    }

    /// The generic shader in f32 with the robust forms and no BVH (`glint
    /// shader check` compiles a user's file against its interface).
    pub fn generic() -> Self {
        Self {
            intersect: Intersect::Robust,
            precision: Precision::F32,
            bvh_stack: 0,
            tables: false,
            features: None,
            count: false,
            record: false,
            aovs: false,
            power_filter: false,
            refine: false,
            contrast: None,
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
            if self.tables {
                d.push(("USE_TABLES".to_owned(), None));
            }
        }
        if self.count {
            d.push(("COUNT_RAYS".to_owned(), None));
        }
        if self.record {
            d.push(("RECORD_TREE".to_owned(), None));
            d.extend(crate::base::record::glsl_defines());
        }
        if self.aovs {
            d.push(("AOVS".to_owned(), None));
        }
        if let Some(trees) = self.contrast {
            d.push(("CONTRAST".to_owned(), None));
            if trees {
                d.push(("CONTRAST_TREES".to_owned(), None));
            }
            d.push(("REFINE_WIDTH".to_owned(), Some(format!("{REFINE_WIDTH}u"))));
        } else if self.refine {
            d.push((
                "REFINE_POINTS".to_owned(),
                Some(format!("{REFINE_POINTS}u")),
            ));
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

    /// The colours one invocation writes: `REFINE_POINTS` for the
    /// refinement, else one (its pixel's).
    pub fn outputs_per_invocation(&self) -> u32 {
        if self.contrast.is_some() {
            CONTRAST_OUTPUTS
        } else if self.refine {
            REFINE_POINTS
        } else {
            1
        }
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
        blocks.extend(
            [
                (Block::Materials, objects),
                (Block::Textures, textures),
                (Block::Texels, images),
                (Block::Uvs, uvs),
                (Block::Lights, lights),
                (Block::Nodes, self.bvh_stack > 0),
                (Block::Tables, self.bvh_stack > 0 && self.tables),
            ]
            .map(|(block, used)| (block, used, scene_type(block))),
        );
        // The run's own buffers (counters, records, the wavefront's queues,
        // the image), each a storage buffer.
        blocks.extend(
            [
                (Block::Counts, self.count),
                (Block::Record, self.record),
                (Block::Refine, self.refine),
                (Block::PathReals, self.wavefront),
                (Block::PathWords, self.wavefront),
                (Block::Queues, self.wavefront),
                (Block::Pixels, true),
                (Block::Aovs, self.aovs),
            ]
            .map(|(block, used)| (block, used, vk::DescriptorType::STORAGE_BUFFER)),
        );
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

    /// What differs between this variant and `had`, a field each, as
    /// `spd_rays true (was false)`: two variants of one name (which leaves
    /// out what a scene rarely changes) are still told apart.
    pub fn difference(&self, had: &Variant) -> String {
        let mut out = Vec::new();
        macro_rules! differing {
            ($now:expr, $was:expr, [$($field:ident),*]) => {{
                $(
                    if $now.$field != $was.$field {
                        out.push(format!(
                            "{} {:?} (was {:?})",
                            stringify!($field),
                            $now.$field,
                            $was.$field
                        ));
                    }
                )*
            }};
        }
        differing!(
            self,
            had,
            [
                intersect,
                precision,
                bvh_stack,
                tables,
                count,
                record,
                aovs,
                power_filter,
                refine,
                contrast,
                wavefront,
                reads
            ]
        );
        match (&self.features, &had.features) {
            (Some(now), Some(was)) => {
                // Each kind and light type by its name: "spheres 41 (was 40)".
                for ((kind, n), w) in KINDS.iter().zip(&now.kinds).zip(&was.kinds) {
                    if n != w {
                        out.push(format!("{} {n} (was {w})", kind.key));
                    }
                }
                let types = crate::scene::LIGHT_TYPES.iter();
                for ((t, n), w) in types.zip(&now.light_types).zip(&was.light_types) {
                    if n != w {
                        out.push(format!("{} lights {n} (was {w})", t.name));
                    }
                }
                differing!(
                    now,
                    was,
                    [
                        lights,
                        attenuation,
                        shadows,
                        transmits,
                        spd_rays,
                        textures,
                        images,
                        uvs,
                        max_depth,
                        samples,
                        uniform_slots,
                        unroll,
                        table_slots,
                        unroll_lights,
                        canary,
                        nodes
                    ]
                );
            }
            (now, was) if now.is_some() != was.is_some() => {
                out.push(format!("generic {} (was {})", now.is_none(), was.is_none()));
            }
            _ => {}
        }
        out.join(", ")
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
            if self.tables {
                parts.push("tables".to_owned());
            }
        }
        if self.count {
            parts.push("counted".to_owned());
        }
        if self.record {
            parts.push("recording".to_owned());
        }
        if self.aovs {
            parts.push("aovs".to_owned());
        }
        if self.contrast.is_some() {
            parts.push("contrast".to_owned());
        } else if self.refine {
            parts.push("refine".to_owned());
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
                for (t, on) in crate::scene::LIGHT_TYPES.iter().zip(&f.light_types) {
                    if *on {
                        parts.push(t.name.to_owned());
                    }
                }
                for (on, name) in [
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

    /// A read form the device cannot give is refused, naming it, not
    /// replaced by another.
    #[test]
    fn a_read_form_the_device_lacks_is_refused() {
        use super::super::features::refused_reads;
        let scene = super::super::layout::tests::row();
        let up = Uploads::new(&scene, Intersect::Robust, Precision::F32, Accel::Bvh);
        let mut device = DeviceInfo {
            max_texel_buffer_elements: 127,
            buffer_device_address: false,
            ..DeviceInfo::default()
        };
        let why = refused_reads(Some(Form::Address), &up, &device).expect("refused");
        assert!(why.contains("address-reads"), "{why}");
        let why = refused_reads(Some(Form::Texels), &up, &device).expect("refused");
        assert!(why.contains("texel-reads"), "{why}");
        assert_eq!(refused_reads(Some(Form::Storage), &up, &device), None);
        assert_eq!(refused_reads(None, &up, &device), None);
        device.buffer_device_address = true;
        device.max_texel_buffer_elements = 128;
        assert_eq!(refused_reads(Some(Form::Address), &up, &device), None);
        assert_eq!(refused_reads(Some(Form::Texels), &up, &device), None);
    }
}
