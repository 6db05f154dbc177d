//! The scene as both renderers consume it, and its bounds.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::DVec3;

use super::decisions::Decisions;
use super::{texture, Adaptive, Camera, Contrast, Light, Material, Prims, Sampling};

/// The largest width or height, in pixels.
pub const MAX_SIZE: u32 = 16384;
/// The most samples a side of a pixel.
pub const MAX_SAMPLES: u32 = 16;
/// The deepest ray tree.
pub const MAX_DEPTH: u32 = 64;

/// A scene as both renderers consume it: validated, materials by index,
/// normals of unit length, the camera as an eye and a virtual screen.
///
/// ```
/// use glint::scene::{Overrides, Scene};
///
/// let small = Overrides { width: Some(64), height: Some(48), ..Overrides::default() };
/// let mut scene = Scene::load("scenes/seed-fig5.toml".as_ref(), &small)?;
/// scene.prims.spheres[0].radius *= 1.01; // a perturbed copy, for a test that must fail
/// # Ok::<(), glint::scene::SceneError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// The image's width in pixels.
    pub width: u32,
    /// The image's height in pixels.
    pub height: u32,
    /// Samples a side of each pixel: `samples²` eye rays a pixel.
    pub samples: u32,
    /// Where in a pixel its samples lie.
    pub sampling: Sampling,
    /// Where `sampling` is adaptive: its threshold and levels.
    pub adaptive: Option<Adaptive>,
    /// Where `sampling` is contrast: its thresholds and samples.
    pub contrast: Option<Contrast>,
    /// Whether a PNG is written sRGB-encoded.
    pub srgb: bool,
    /// The ray tree's depth: 1 is eye rays alone.
    pub max_depth: u32,
    /// Whether shadow rays are cast.
    pub shadows: bool,
    /// Whether the ray tree is the SPD's testing procedure's: a reflection
    /// ray wherever a surface reflects or transmits and a refraction ray
    /// wherever it transmits, also where the path's weight or the ray's own
    /// is 0 (docs/spd.md). Such rays change no pixel; they are traced and
    /// counted. NFF scenes set it.
    pub spd_rays: bool,
    /// The colour of a ray that meets nothing.
    pub background: DVec3,
    /// The eye and the virtual screen.
    pub camera: Camera,
    /// The materials, which primitives name by index.
    pub materials: Vec<Material>,
    /// The textures, which materials name by index (`[textures]`, sorted
    /// by name).
    pub textures: Vec<texture::Texture>,
    /// Every primitive, a list for each kind (`crate::prim`).
    pub prims: Prims,
    /// The lights.
    pub lights: Vec<Light>,
    /// The files read besides the scene file: the OBJ and MTL files of the
    /// `[[meshes]]` and the textures' images. Inputs of the run, which no
    /// output may replace.
    pub input_files: Vec<PathBuf>,
    /// The image textures' texels, rows top to bottom, image after image
    /// (`texture::Texels` says where each lies); linear RGB.
    pub texels: Arc<Vec<[f32; 3]>>,
    /// Where set, adaptive or contrast sampling replays these decisions
    /// rather than taking its own (`Scene::replaying`): how `glint
    /// compare` holds a renderer to the reference on the same samples.
    pub replay: Option<Arc<Decisions>>,
}

impl Scene {
    /// Whether a material has an image texture.
    pub fn has_image_textures(&self) -> bool {
        let image = |t: Option<u32>| {
            t.is_some_and(|t| self.textures[t as usize].pattern == texture::PatternId::Image)
        };
        self.materials
            .iter()
            .any(|m| image(m.texture) || image(m.ambient_texture))
    }

    /// The scene with its sampling's decisions replayed from `decisions`
    /// (a render's `Sampled::taken`), not taken anew.
    pub fn replaying(&self, decisions: &Decisions) -> Scene {
        Scene {
            replay: Some(Arc::new(decisions.clone())),
            ..self.clone()
        }
    }

    /// Whether its sampling takes decisions (adaptive or contrast
    /// sampling), which a render can replay.
    pub fn decides(&self) -> bool {
        matches!(self.sampling, Sampling::Adaptive | Sampling::Contrast)
    }

    /// The adaptive sampling the renderers follow: where `sampling` is
    /// adaptive, `adaptive` (or the defaults, 0.1 and 2 levels, where a
    /// scene made in code left it out); else none.
    pub fn adaptive_sampling(&self) -> Option<Adaptive> {
        (self.sampling == Sampling::Adaptive).then(|| {
            self.adaptive.unwrap_or(Adaptive {
                threshold: 0.1,
                levels: 2,
            })
        })
    }

    /// The contrast sampling the renderers follow: where `sampling` is
    /// contrast, `contrast` (or the defaults, where a scene made in code
    /// left it out); else none.
    pub fn contrast_sampling(&self) -> Option<Contrast> {
        (self.sampling == Sampling::Contrast).then(|| self.contrast.unwrap_or_default())
    }

    /// How a pixel is sampled, in a few words: `4 spp`, `corners`,
    /// `adaptive to 2 levels`, `contrast, 1 to 33 spp`.
    pub fn sampling_summary(&self) -> String {
        match self.sampling {
            Sampling::Centers => format!("{} spp", self.samples * self.samples),
            Sampling::Corners => "corners".to_owned(),
            Sampling::Adaptive => {
                let levels = self.adaptive_sampling().map_or(0, |a| a.levels);
                format!("adaptive to {levels} levels")
            }
            Sampling::Contrast => {
                let most = self.contrast_sampling().map_or(0, |c| c.max_samples);
                format!("contrast, 1 to {most} spp")
            }
        }
    }
}

/// Whether `path` names an NFF file (by its extension, `.nff` in any case).
pub fn is_nff(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("nff"))
}

/// Whether `path` names a scene file: TOML, or NFF by its extension.
pub fn is_scene(path: &Path) -> bool {
    path.extension().is_some_and(|e| e == "toml") || is_nff(path)
}

impl Scene {
    /// The image's pixels.
    pub fn pixel_count(&self) -> u64 {
        u64::from(self.width) * u64::from(self.height)
    }

    /// Primary rays per image.
    pub fn ray_count(&self) -> u64 {
        self.pixel_count() * u64::from(self.samples * self.samples)
    }
}
