//! The scene: read from TOML (docs/scene-format.md), validated, and resolved into the
//! form both renderers consume (materials by index, unit normals, the camera
//! as an eye and a virtual screen).

mod brightness;
pub mod camera;
mod contrast;
pub mod decisions;
mod file;
pub mod images;
pub mod light;
mod load;
pub mod material;
mod model;
pub mod nff;
mod rebase;
mod sampling;
mod split;
mod tables;
pub mod texture;
mod toml;
mod validate;

pub use crate::input::error::SceneError;
pub use crate::input::field::{Triple, MAX_COORDINATE};
pub use crate::prim::mesh::{Arrays as MeshArrays, Cache as MeshCache};
pub use brightness::PastBound;
pub use camera::Camera;
pub use contrast::Contrast;
pub use file::object_arrays;
pub use light::{Light, LightTypeId, LIGHT_TYPES};
pub use material::{Material, MaterialR};
pub use model::{is_nff, is_scene, Scene, MAX_DEPTH, MAX_SAMPLES, MAX_SIZE};
pub use nff::parse_nff;
pub use sampling::{Adaptive, Sampling};
pub use split::sphere_blocks;
pub use toml::{parse, parse_cached};
pub use validate::Overrides;

pub use crate::prim::cylinder::Cylinder;
pub use crate::prim::plane::Plane;
pub use crate::prim::sphere::Sphere;
pub use crate::prim::triangle::Triangle;
pub use crate::prim::Prims;
