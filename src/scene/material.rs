//! Materials (docs/scene-format.md, Shading): a `[materials.NAME]` table,
//! its checks, an MTL material's translation, and its forms in the shader's
//! buffers and in the CPU reference.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::base::real::{Real, Vec3};
use crate::input::error::SceneError;
use crate::input::field::{Triple, Validator};
use crate::input::locate::KeyPath;

type Result<T> = std::result::Result<T, SceneError>;

/// `[materials.NAME]` as written.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialFile {
    /// Ka; None: black, or the texture's colour where the material has one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ambient: Option<Triple>,
    /// Kd (default 0).
    #[serde(default)]
    pub diffuse: Triple,
    /// Ks (default 0).
    #[serde(default)]
    pub specular: Triple,
    /// The specular exponent (default 1).
    #[serde(default = "one")]
    pub shininess: f64,
    /// The mirror ray's weight (default 0).
    #[serde(default)]
    pub reflectivity: f64,
    /// The refraction ray's weight (default 0).
    #[serde(default)]
    pub transmittance: f64,
    /// The index of refraction (default 1).
    #[serde(default = "one")]
    pub ior: f64,
    /// The name of the texture that gives the diffuse colour.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub texture: Option<String>,
    /// The name of the texture that gives the ambient colour; `texture` by
    /// default where `ambient` is not written.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ambient_texture: Option<String>,
}

fn one() -> f64 {
    1.0
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

impl Material {
    /// Its struct in the shader's buffers.
    pub(crate) fn gpu(&self) -> gpu::Values {
        let xyz = |v: DVec3| [v.x, v.y, v.z, 0.0];
        gpu::Values {
            ambient: xyz(self.ambient),
            diffuse: xyz(self.diffuse),
            specular: xyz(self.specular),
            params: [
                self.shininess,
                self.reflectivity,
                self.transmittance,
                self.ior,
            ],
            textures: [
                self.texture.map_or(0, |t| t + 1),
                self.ambient_texture.map_or(0, |t| t + 1),
                0,
                0,
            ],
        }
    }

    /// The material in the CPU reference's arithmetic.
    pub fn cpu<R: Real>(&self) -> MaterialR<R> {
        MaterialR {
            ambient: Vec3::of(self.ambient),
            diffuse: Vec3::of(self.diffuse),
            specular: Vec3::of(self.specular),
            shininess: R::of(self.shininess),
            reflectivity: R::of(self.reflectivity),
            transmittance: R::of(self.transmittance),
            ior: R::of(self.ior),
            texture: self.texture.map(|t| t as usize),
            ambient_texture: self.ambient_texture.map(|t| t as usize),
        }
    }
}

crate::base::interface::gpu_struct!(
    pub(crate) mod gpu: "Material" {
        /// rgb Ka
        ambient: real4,
        /// rgb Kd
        diffuse: real4,
        /// rgb Ks
        specular: real4,
        /// x shininess, y reflectivity, z transmittance, w ior
        params: real4,
        /// x the diffuse texture + 1, y the ambient texture + 1 (0: none)
        textures: uvec4,
    }
);

/// A material in the CPU reference's arithmetic.
#[derive(Debug, Clone, Copy)]
pub struct MaterialR<R> {
    /// `Material::ambient`.
    pub ambient: Vec3<R>,
    /// `Material::diffuse`.
    pub diffuse: Vec3<R>,
    /// `Material::specular`.
    pub specular: Vec3<R>,
    /// `Material::shininess`.
    pub shininess: R,
    /// `Material::reflectivity`.
    pub reflectivity: R,
    /// `Material::transmittance`.
    pub transmittance: R,
    /// `Material::ior`.
    pub ior: R,
    /// `Material::texture`, an index in the world's textures.
    pub texture: Option<usize>,
    /// `Material::ambient_texture`.
    pub ambient_texture: Option<usize>,
}

/// An OBJ's MTL material as glint's (docs/scene-format.md, Meshes), after
/// the MTL format's illumination models: 0 colour alone (no ambient), 1
/// with ambient, 2 with highlights (Ks, Ns); 3 and 5 add reflection by ray
/// tracing, of weight Ks (its mean over the channels); 4, 6 and 7 add
/// refraction too, of weight 1 − d with index Ni, and 9 refraction without
/// the reflection; 8 and 10 (reflection maps, shadows on invisible
/// surfaces) shade as 2.
pub(crate) fn from_mtl(m: &crate::prim::mesh::MtlMaterial) -> Material {
    let ambient = if m.illum >= 1 { m.ka } else { DVec3::ZERO };
    let highlight = m.illum >= 2;
    let reflects = matches!(m.illum, 3..=7);
    let transmits = matches!(m.illum, 4 | 6 | 7 | 9);
    Material {
        name: m.name.clone(),
        ambient,
        diffuse: m.kd,
        specular: if highlight { m.ks } else { DVec3::ZERO },
        shininess: if highlight { m.ns } else { 1.0 },
        reflectivity: if reflects {
            ((m.ks.x + m.ks.y + m.ks.z) / 3.0).clamp(0.0, 1.0)
        } else {
            0.0
        },
        transmittance: if transmits { 1.0 - m.d } else { 0.0 },
        ior: if transmits { m.ni } else { 1.0 },
        texture: None,
        ambient_texture: None,
    }
}

/// The largest index of refraction: the square of the ratio of two iors,
/// (1e6 / 1e-6)², is 1e24, inside f32's 3.4e38.
const MAX_IOR: f64 = 1e6;
/// The smallest.
const MIN_IOR: f64 = 1e-6;

impl Validator<'_> {
    /// The material `name` at `path`; `textures` are the names of the
    /// scene's textures, sorted.
    pub(crate) fn material(
        &self,
        path: &KeyPath,
        name: &str,
        m: &MaterialFile,
        textures: &[String],
    ) -> Result<Material> {
        let texture = m
            .texture
            .as_deref()
            .map(|t| self.texture_index(&path.key("texture"), t, textures))
            .transpose()?;
        let ambient_texture = match (&m.ambient_texture, m.ambient) {
            (Some(t), _) => Some(self.texture_index(&path.key("ambient_texture"), t, textures)?),
            (None, None) => texture,
            (None, Some(_)) => None,
        };
        let shininess = self.non_negative(&path.key("shininess"), m.shininess)?;
        let reflectivity = self.finite(&path.key("reflectivity"), m.reflectivity)?;
        if !(0.0..=1.0).contains(&reflectivity) {
            return self.err(
                &path.key("reflectivity"),
                format!(
                    "must be in [0, 1], got {}",
                    crate::printable::number(reflectivity)
                ),
            );
        }
        let transmittance = self.finite(&path.key("transmittance"), m.transmittance)?;
        if !(0.0..=1.0).contains(&transmittance) {
            return self.err(
                &path.key("transmittance"),
                format!(
                    "must be in [0, 1], got {}",
                    crate::printable::number(transmittance)
                ),
            );
        }
        let ior = self.finite(&path.key("ior"), m.ior)?;
        if ior <= 0.0 {
            return self.err(
                &path.key("ior"),
                format!("must be > 0, got {}", crate::printable::number(ior)),
            );
        }
        // Both renderers square the ratio of two iors: it must stay finite,
        // and non-zero, in f32 (the f32 overflow rule of every other value).
        if !(MIN_IOR..=MAX_IOR).contains(&ior) {
            return self.err(
                &path.key("ior"),
                format!("must be in [{MIN_IOR:e}, {MAX_IOR:e}] so that its square fits f32, got {ior:e}"),
            );
        }
        Ok(Material {
            name: name.to_owned(),
            ambient: self.colour(&path.key("ambient"), m.ambient.unwrap_or_default())?,
            diffuse: self.colour(&path.key("diffuse"), m.diffuse)?,
            specular: self.colour(&path.key("specular"), m.specular)?,
            shininess,
            reflectivity,
            transmittance,
            ior,
            texture,
            ambient_texture,
        })
    }
}
