//! The scene file as written (docs/scene-format.md): typed serde structs, defaults applied,
//! nothing checked beyond types. `validate` turns this into a [`super::Scene`].

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::camera::CameraFile;
use super::light::LightFile;
use super::material::MaterialFile;
use super::sampling::Sampling;
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
    /// A PNG's levels are sRGB-encoded unless `srgb = false`
    /// (docs/scene-format.md, Colour).
    #[serde(default = "yes")]
    pub srgb: bool,
    #[serde(default)]
    pub sampling: Sampling,
    /// `"adaptive"`: the corners' contrast past which a square is split.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub threshold: Option<f64>,
    /// `"adaptive"`: how many times a pixel may be split.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_level: Option<i64>,
    /// `"contrast"`: per channel, the contrast past which a pixel takes
    /// more samples.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thresholds: Option<Triple>,
    /// `"contrast"`: the range test's bound, in place of `thresholds`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub range: Option<f64>,
    /// `"contrast"`: the samples a refined pixel takes in all.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_samples: Option<i64>,
    /// `"contrast"`: whether differing ray trees refine a pixel too.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub compare_trees: Option<bool>,
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

fn one() -> i64 {
    1
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
    /// table (shrink.rs kept its own list, and a kind left off it was never
    /// shrunk).
    #[test]
    fn every_kind_is_an_object_array() {
        let arrays = super::object_arrays();
        for k in crate::prim::KINDS {
            assert!(arrays.contains(&k.key), "{}", k.key);
        }
        assert!(arrays.contains(&"meshes") && arrays.contains(&"lights"));
    }
}
