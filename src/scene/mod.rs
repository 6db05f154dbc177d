//! The scene: read from TOML (docs/scene-format.md), validated, and resolved into the
//! form both renderers consume (materials by index, unit normals, the camera
//! as an eye and a virtual screen).

mod brightness;
mod corners;
mod file;
pub mod images;
pub mod nff;
mod rebase;
pub mod refine;
mod split;
mod tables;
pub mod texture;
mod validate;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::DVec3;

use crate::base::real::{Real, Vec3};

pub use crate::input::error::SceneError;
pub use crate::input::field::{Triple, MAX_COORDINATE};
pub use brightness::PastBound;
pub use file::{object_arrays, Sampling};
pub use nff::parse_nff;
pub use validate::{parse, Overrides};

pub use crate::prim::cylinder::Cylinder;
pub use crate::prim::plane::Plane;
pub use crate::prim::sphere::Sphere;
pub use crate::prim::triangle::Triangle;
pub use crate::prim::Prims;

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
}

/// The camera of form (a) in docs/scene-format.md: an eye and a virtual
/// screen. Form (b) is converted to
/// this on load.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Where every eye ray starts.
    pub eye: DVec3,
    /// The screen's centre.
    pub screen_center: DVec3,
    /// From the centre to the middle of the screen's right edge.
    pub screen_right: DVec3,
    /// From the centre to the middle of the screen's top edge.
    pub screen_up: DVec3,
}

/// A material (docs/scene-format.md, Shading).
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    /// Its name in the scene file.
    pub name: String,
    /// The ambient coefficient, per channel.
    pub ambient: DVec3,
    /// The diffuse coefficient, per channel.
    pub diffuse: DVec3,
    /// The specular coefficient, per channel.
    pub specular: DVec3,
    /// The specular exponent.
    pub shininess: f64,
    /// The mirror ray's weight, 0..1.
    pub reflectivity: f64,
    /// The refraction ray's weight, 0..1 (docs/scene-format.md, Shading).
    pub transmittance: f64,
    /// Index of refraction, > 0: inside over outside.
    pub ior: f64,
    /// The texture, in `Scene::textures`, that gives the diffuse colour in
    /// place of `diffuse`.
    pub texture: Option<u32>,
    /// The texture that gives the ambient colour in place of `ambient`.
    pub ambient_texture: Option<u32>,
}

/// Whitted's adaptive antialiasing (docs/scene-format.md, Rays): a square
/// of a pixel whose corners' contrast passes `threshold` is split into
/// four, at most `levels` times from the pixel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Adaptive {
    /// The largest difference between two corners in one channel that a
    /// square keeps unsplit.
    pub threshold: f64,
    /// How many times a pixel may be split: 1..=`MAX_LEVELS`.
    pub levels: u32,
}

impl Adaptive {
    /// The deepest split allowed: 4⁴ = 256 squares to a pixel.
    pub const MAX_LEVELS: u32 = 4;

    /// Colours are compared in steps of 1/255: the contrast of a square
    /// is counted in these, so that f32 and f64, whose colours differ by
    /// rounding, split the same squares but where a corner sits on a step.
    pub const STEPS: f64 = 255.0;

    /// The threshold in steps, as both renderers compare contrasts with it.
    pub fn threshold_steps(&self) -> f64 {
        self.threshold * Self::STEPS
    }

    /// Whether a pixel whose corners (top-left, top-right, bottom-left,
    /// bottom-right, as the corner grid gives them) are `c` is split: the
    /// choice of the pixels the second pass refines, made once, from the
    /// f32 corner image, for either renderer, by [`Adaptive::contrast`].
    pub fn splits(&self, c: &[[f32; 3]; 4]) -> bool {
        let corners = c.map(Vec3::<f64>::of_rgb);
        Self::contrast(&corners) > self.threshold_steps()
    }

    /// The largest minus the smallest of the corners `c`, in the channel
    /// where that is largest, in steps (`STEPS`): what both renderers
    /// compare with the threshold, as contrast() in shaders/adaptive.glsl.
    pub fn contrast<R: Real>(c: &[Vec3<R>; 4]) -> R {
        let steps = R::of(Self::STEPS);
        let half = R::of(0.5);
        let channel = |f: fn(&Vec3<R>) -> R| {
            let values = c.map(|v| (f(&v) * steps + half).floor());
            let hi = values.iter().fold(values[0], |m, v| m.max(*v));
            let lo = values.iter().fold(values[0], |m, v| m.min(*v));
            hi - lo
        };
        channel(|v| v.x).max(channel(|v| v.y)).max(channel(|v| v.z))
    }

    /// The most eye rays one pixel can add to its corners: 5 a split, and
    /// (4^levels − 1)/3 splits.
    pub fn most_rays_per_pixel(&self) -> f64 {
        5.0 * (4f64.powi(self.levels as i32) - 1.0) / 3.0
    }
}

/// What kind of light.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LightKind {
    /// From a point, in every direction, attenuated with distance.
    Point,
    /// From infinitely far, one direction, not attenuated.
    Directional,
    /// A point light within a cone about its axis.
    Spot,
}

/// A light (docs/scene-format.md, Lights).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Light {
    /// What kind.
    pub kind: LightKind,
    /// Point and spot lights; zero for directional ones.
    pub position: DVec3,
    /// Unit length: the way a directional light travels, a spot light's axis.
    pub direction: DVec3,
    /// Its ambient intensity, per channel.
    pub ambient: DVec3,
    /// Its diffuse intensity, per channel.
    pub diffuse: DVec3,
    /// Its specular intensity, per channel.
    pub specular: DVec3,
    /// [c, l, q]: 1 / (c + l d + q d²).
    pub attenuation: DVec3,
    /// cos(cutoff) of a spot light.
    pub cos_cutoff: f64,
    /// A spot light's falloff towards its cone's edge: cos(angle)^exponent.
    pub exponent: f64,
}

impl Light {
    /// Whether the light has a diffuse or specular term: a shadow ray
    /// towards a light without one could change nothing.
    pub fn has_direct_term(&self) -> bool {
        self.diffuse != DVec3::ZERO || self.specular != DVec3::ZERO
    }
}

impl Scene {
    /// Whether a material has an image texture.
    pub fn has_image_textures(&self) -> bool {
        let image = |t: Option<u32>| {
            t.is_some_and(|t| self.textures[t as usize].pattern == texture::Pattern::Image)
        };
        self.materials
            .iter()
            .any(|m| image(m.texture) || image(m.ambient_texture))
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

    /// How a pixel is sampled, in a few words: `4 spp`, `corners`,
    /// `adaptive to 2 levels`.
    pub fn sampling_summary(&self) -> String {
        match (self.sampling, self.adaptive_sampling()) {
            (_, Some(a)) => format!("adaptive to {} levels", a.levels),
            (Sampling::Corners, _) => "corners".to_owned(),
            _ => format!("{} spp", self.samples * self.samples),
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
    /// Reads and validates a scene file, then applies command-line overrides.
    pub fn load(path: &Path, overrides: &Overrides) -> Result<Scene, SceneError> {
        let text = crate::input::read_text(path, crate::input::Kind::Scene).map_err(|cause| {
            SceneError::Read {
                path: path.to_owned(),
                cause,
            }
        })?;
        if is_nff(path) {
            nff::parse_nff(&text, path, overrides)
        } else {
            parse(&text, path, overrides)
        }
    }

    /// The image's pixels.
    pub fn pixel_count(&self) -> u64 {
        u64::from(self.width) * u64::from(self.height)
    }

    /// Primary rays per image.
    pub fn ray_count(&self) -> u64 {
        self.pixel_count() * u64::from(self.samples * self.samples)
    }
}
