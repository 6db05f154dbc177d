//! The scene file as written (docs/scene-format.md): typed serde structs, defaults applied,
//! nothing checked beyond types. `validate` turns this into a [`super::Scene`].

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::input::field::Triple;

/// The scene file's tables, with an array for each kind of primitive
/// (`crate::prim`'s table; serde's `flatten` would not work with
/// `deny_unknown_fields`).
macro_rules! scene_file {
    ($($key:ident : $kind:ty),* $(,)?) => {
        #[derive(Debug, Deserialize, Serialize)]
        #[serde(deny_unknown_fields)]
        pub struct SceneFile {
            pub image: ImageFile,
            #[serde(default)]
            pub render: RenderFile,
            pub camera: CameraFile,
            #[serde(default)]
            pub materials: BTreeMap<String, MaterialFile>,
            #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
            pub textures: BTreeMap<String, super::texture::TextureFile>,
            $(
                #[serde(default, skip_serializing_if = "Vec::is_empty")]
                pub $key: Vec<<$kind as crate::prim::Kind>::File>,
            )*
            /// OBJ files, read into triangles (`crate::prim::mesh`).
            #[serde(default, skip_serializing_if = "Vec::is_empty")]
            pub meshes: Vec<crate::prim::mesh::MeshFile>,
            #[serde(default, skip_serializing_if = "Vec::is_empty")]
            pub lights: Vec<LightFile>,
        }

        /// The arrays of a scene file whose rows are its objects: each
        /// primitive kind's (from the kinds' table, so a new kind is in it),
        /// then the meshes and the lights (`glint drivers` leaves rows of
        /// these out to shrink a failing scene).
        pub fn object_arrays() -> &'static [&'static str] {
            &[$(stringify!($key),)* "meshes", "lights"]
        }

        impl SceneFile {
            /// The file as TOML text, written a few hundred tables at a
            /// time: a document of the whole scene would hold some 2.6 KB a
            /// table (`glint convert` peaked at 170 times its NFF).
            pub fn to_toml(&self) -> Result<String, toml::ser::Error> {
                #[derive(Serialize)]
                struct Head<'a> {
                    image: &'a ImageFile,
                    render: &'a RenderFile,
                    camera: &'a CameraFile,
                    materials: &'a BTreeMap<String, MaterialFile>,
                }
                let mut out = toml::to_string(&Head {
                    image: &self.image,
                    render: &self.render,
                    camera: &self.camera,
                    materials: &self.materials,
                })?;
                $(tables(&mut out, stringify!($key), &self.$key)?;)*
                tables(&mut out, "meshes", &self.meshes)?;
                tables(&mut out, "lights", &self.lights)?;
                Ok(out)
            }

            /// The primitives' tables, moved out.
            pub fn take_prims(&mut self) -> crate::prim::PrimFiles {
                crate::prim::PrimFiles {
                    $($key: std::mem::take(&mut self.$key),)*
                }
            }
        }
    };
}

crate::prim::with_kinds!(scene_file);

/// Appends `rows` as the array of tables `key`, 256 at a time.
fn tables<T: Serialize>(out: &mut String, key: &str, rows: &[T]) -> Result<(), toml::ser::Error> {
    for chunk in rows.chunks(256) {
        out.push('\n');
        out.push_str(&toml::to_string(&BTreeMap::from([(key, chunk)]))?);
    }
    Ok(())
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ImageFile {
    pub width: i64,
    pub height: i64,
    #[serde(default = "one")]
    pub samples: i64,
    #[serde(default)]
    pub srgb: bool,
    #[serde(default)]
    pub sampling: Sampling,
    /// `"adaptive"`: the corners' contrast past which a square is split.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub threshold: Option<f64>,
    /// `"adaptive"`: how many times a pixel may be split.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_level: Option<i64>,
}

/// Where a pixel's eye rays go (docs/scene-format.md, Rays).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Sampling {
    /// samples × samples rays through the centres of a grid over the pixel.
    #[default]
    Centers,
    /// One ray through each pixel corner, (w+1)×(h+1), four averaged per
    /// pixel: the SPD's procedure.
    Corners,
    /// Whitted's adaptive antialiasing: the corners, and a pixel whose
    /// corners differ by more than a threshold split into four, again
    /// and again up to a level (`crate::scene::Adaptive`).
    Adaptive,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RenderFile {
    #[serde(default = "three")]
    pub max_depth: i64,
    #[serde(default = "yes")]
    pub shadows: bool,
    #[serde(default)]
    pub background: Triple,
    /// The SPD's ray tree: a ray wherever a surface reflects or transmits,
    /// whatever its weight (docs/spd.md). Written only where set.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub spd_rays: bool,
}

impl Default for RenderFile {
    fn default() -> Self {
        Self {
            max_depth: three(),
            shadows: yes(),
            background: Triple::default(),
            spd_rays: false,
        }
    }
}

/// Both camera forms share one table; which keys are present picks the form.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CameraFile {
    pub eye: Triple,
    pub screen_center: Option<Triple>,
    pub screen_right: Option<Triple>,
    pub screen_up: Option<Triple>,
    pub look_at: Option<Triple>,
    pub up: Option<Triple>,
    pub vfov: Option<f64>,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialFile {
    /// None: black, or the texture's colour where the material has one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ambient: Option<Triple>,
    #[serde(default)]
    pub diffuse: Triple,
    #[serde(default)]
    pub specular: Triple,
    #[serde(default = "one_f")]
    pub shininess: f64,
    #[serde(default)]
    pub reflectivity: f64,
    #[serde(default)]
    pub transmittance: f64,
    #[serde(default = "one_f")]
    pub ior: f64,
    /// The name of the texture that gives the diffuse colour.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub texture: Option<String>,
    /// The name of the texture that gives the ambient colour; `texture` by
    /// default where `ambient` is not written.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ambient_texture: Option<String>,
}

/// One flat table for every light type: `validate` checks that each key
/// present belongs to the light's type and that its required keys are there.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct LightFile {
    #[serde(rename = "type")]
    pub kind: String,
    pub position: Option<Triple>,
    pub direction: Option<Triple>,
    #[serde(default)]
    pub ambient: Triple,
    #[serde(default)]
    pub diffuse: Triple,
    #[serde(default)]
    pub specular: Triple,
    pub attenuation: Option<Triple>,
    pub cutoff: Option<f64>,
    pub exponent: Option<f64>,
}

fn one() -> i64 {
    1
}
fn one_f() -> f64 {
    1.0
}
fn three() -> i64 {
    3
}
fn yes() -> bool {
    true
}

#[cfg(test)]
mod tests {
    /// Every primitive kind's array is one that `drivers` shrinks, from the
    /// table (issue 43: shrink.rs kept its own list, and a kind left off
    /// it was never shrunk).
    #[test]
    fn every_kind_is_an_object_array() {
        let arrays = super::object_arrays();
        for k in crate::prim::KINDS {
            assert!(arrays.contains(&k.key), "{}", k.key);
        }
        assert!(arrays.contains(&"meshes") && arrays.contains(&"lights"));
    }
}
