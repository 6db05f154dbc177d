//! What one scene needs of the shader: its kinds, lights and materials'
//! features, the counts that become constants, and how its arrays are
//! read. Everything else is left out of its variant (variant.rs).

use super::blocks::Form;
use super::layout::Uploads;
use super::vk::device::DeviceInfo;
use super::GpuError;
use crate::prim::KINDS;
use crate::scene::{Scene, LIGHT_TYPES};

/// Unrolling the scene loops is worth its compile time up to this many
/// primitives (each loop body is copied once per object, at every
/// place the shader walks the scene). Also, lavapipe (Mesa 22.3) was seen to
/// miscompile the unrolled shadow loop of a scene with 103 objects; 60 were
/// right; `glint compare` and the tests catch such a thing.
const UNROLL_OBJECTS: usize = 64;
const UNROLL_LIGHTS: usize = 16;

/// What one scene needs of the shader.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Features {
    /// Primitives of each kind (`prim::KINDS`).
    pub kinds: Vec<usize>,
    /// Lights.
    pub lights: usize,
    /// Whether a light of each type (`scene::LIGHT_TYPES`) is among them.
    pub light_types: Vec<bool>,
    /// A positioned light whose falloff is not [1, 0, 0].
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
    /// The nodes' uniform block's length (the most nodes a tree of the
    /// scene's primitives has), where they are one; else 0.
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
/// rendering. A name it does not know is refused (`check_experiment`,
/// through `GpuOptions::check`): a
/// misspelt experiment would measure the default shaders under its name.
#[derive(Debug, Default, Clone, Copy)]
pub(super) struct Experiment {
    storage: bool,
    uniforms_always: bool,
    no_unroll: bool,
    unroll_all: bool,
    canary: bool,
    pub(super) no_filter: bool,
    no_uniform_tables: bool,
    pub(super) reads: Option<Form>,
}

/// The names `GLINT_EXPERIMENT` may hold (`Experiment`).
pub const EXPERIMENTS: &[&str] = &[
    "storage",
    "uniforms-always",
    "no-unroll",
    "unroll-all",
    "canary",
    "no-filter",
    "no-uniform-tables",
    "storage-reads",
    "texel-reads",
    "address-reads",
];

/// Refuses a `GLINT_EXPERIMENT` that names an experiment glint does not
/// have (it was ignored, so a test of a misspelt one passed).
pub(super) fn check_experiment() -> Result<(), GpuError> {
    let v = std::env::var("GLINT_EXPERIMENT").unwrap_or_default();
    let unknown: Vec<&str> = v
        .split(',')
        .map(str::trim)
        .filter(|f| !f.is_empty() && !EXPERIMENTS.contains(f))
        .collect();
    if unknown.is_empty() {
        return Ok(());
    }
    Err(GpuError::Unsupported(format!(
        "GLINT_EXPERIMENT: no experiment {} (the experiments: {})",
        unknown
            .iter()
            .map(|u| format!("\"{}\"", crate::printable::text(u)))
            .collect::<Vec<_>>()
            .join(", "),
        EXPERIMENTS.join(", ")
    )))
}

impl Experiment {
    pub(super) fn from_env() -> Self {
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
        let kinds = scene.prims.counts();
        let objects = !scene.prims.is_empty();
        let lights = scene.lights.len();
        let reflects = scene.materials.iter().any(|m| m.reflectivity > 0.0);
        let transmits = scene.materials.iter().any(|m| m.transmittance > 0.0);
        // Uniform blocks where the driver reads them safely (the
        // workaround NO_UNIFORM_ARRAYS in workarounds.rs: not llvmpipe
        // before Mesa 25.0). Two mixes of kinds crashed Mesa 22.3 before
        // that row was known, and still take storage buffers on every
        // driver: no spheres (planes and lights only), and spheres as the
        // only primitives with directional lights as the only lights
        // (tests/variants.rs renders every mix of kinds and light types).
        let range = device.max_uniform_buffer_range as usize;
        let spheres = scene.prims.spheres.len();
        let spheres_only = spheres == scene.prims.len();
        let positioned = scene.lights.iter().any(|l| l.position().is_some());
        let experiment = Experiment::from_env();
        let images = objects && scene.has_image_textures();
        let uniforms = (experiment.uniforms_always
            || device.reads_uniform_arrays
                && spheres > 0
                && !(spheres_only && lights > 0 && !positioned))
            && !experiment.storage;
        // As a uniform block, the nodes' array is declared with the most
        // nodes a tree of the scene's primitives can have (one fewer than
        // them: a node has two children or more), and padded to it: its
        // length is in the shader, and the tree's own count, which moving
        // a primitive changes, would make each position a new variant.
        let node_slots = uploads.nodes.as_ref().map(|n| {
            let most = scene.prims.bounded_count().saturating_sub(1).max(1);
            (most.max(n.len), n.byte_len() / n.len.max(1))
        });
        let fits = uniforms
            && uploads.array_bytes().iter().all(|b| *b <= range)
            && node_slots.is_none_or(|(slots, bytes)| slots * bytes <= range);
        // Where the arrays do not all fit, the small tables still do: each
        // read in uniform blocks, and the lights' loop unrolled, so that a
        // light is read at a constant offset (docs/performance.md, Reading
        // the scene).
        let tables = [&uploads.materials, &uploads.lights, &uploads.textures];
        let table_slots = (uniforms
            && !fits
            && !experiment.no_uniform_tables
            && tables.iter().all(|t| t.byte_len() <= range))
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
            light_types: LIGHT_TYPES
                .iter()
                .map(|t| scene.lights.iter().any(|l| l.kind == t.kind))
                .collect(),
            attenuation: scene.lights.iter().any(|l| l.attenuated()),
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
            // The nodes' count is in the shader only as a uniform block's
            // length (above); elsewhere it would make a moved sphere a new
            // variant.
            nodes: match node_slots {
                Some((slots, _)) if fits => slots,
                _ => 0,
            },
        }
    }

    pub(super) fn defines(&self, d: &mut Vec<(String, Option<String>)>) {
        let mut def = |name: &str, value: String| d.push((name.to_owned(), Some(value)));
        let flag = |b: bool| u8::from(b).to_string();
        for (kind, n) in KINDS.iter().zip(&self.kinds) {
            def(&format!("HAS_{}", kind.upper()), flag(*n > 0));
            def(&format!("{}_COUNT", kind.upper()), format!("{n}u"));
        }
        for (t, on) in LIGHT_TYPES.iter().zip(&self.light_types) {
            def(&format!("HAS_{}", t.upper()), flag(*on));
        }
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

/// Where `wanted`, the read form `GLINT_EXPERIMENT` asks for, is one that `device` cannot give
/// the scene laid out as `uploads`, the reason: device addresses on a device without them,
/// texel buffers for an array longer than one. Such a run is refused rather than given another
/// form (a test of address reads compared texel buffers with texel buffers where a device
/// lacked addresses).
pub(super) fn refused_reads(
    wanted: Option<Form>,
    uploads: &Uploads,
    device: &DeviceInfo,
) -> Option<String> {
    match wanted? {
        Form::Address if !device.buffer_device_address => Some(
            "GLINT_EXPERIMENT=address-reads: this device has no buffer device addresses \
             (bufferDeviceAddress)"
                .to_owned(),
        ),
        Form::Texels if !uploads.fit_texels(device.max_texel_buffer_elements) => Some(format!(
            "GLINT_EXPERIMENT=texel-reads: an array of this scene is longer than this \
             device's texel buffers ({} texels)",
            device.max_texel_buffer_elements
        )),
        _ => None,
    }
}

/// How `device` reads the scene's arrays that are no uniform blocks
/// (docs/performance.md, Reading the scene): through texel buffers where
/// every array fits one, else as storage buffers. (Device addresses, an
/// experiment, measured slower on llvmpipe where LLVM turns their gathers
/// into a branch a lane.)
pub(super) fn reads(uploads: &Uploads, device: &DeviceInfo) -> Form {
    let texels = uploads.fit_texels(device.max_texel_buffer_elements);
    let wanted = Experiment::from_env().reads.unwrap_or(Form::Texels);
    match wanted {
        Form::Address if device.buffer_device_address => Form::Address,
        Form::Address | Form::Texels if texels => Form::Texels,
        _ => Form::Storage,
    }
}
