//! Scene management: which primitives a ray tests. `none` tests every
//! object; `bvh` walks a bounding volume hierarchy over the spheres
//! (planes are unbounded and stay outside it); `auto` picks by the count.
//! The choice never changes the image: ties in t go to the primitive that
//! comes first in the scene file, whatever order a walk meets them in.

pub mod bvh;

use crate::scene::Scene;

/// From this many spheres up `auto` takes the BVH (docs/performance.md,
/// The BVH: where the linear scan stops winning on lavapipe).
pub const AUTO_MIN_SPHERES: usize = 16;

#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Accel {
    /// The BVH from `AUTO_MIN_SPHERES` spheres up, else the linear scan.
    #[default]
    Auto,
    Bvh,
    /// Every ray tests every object.
    None,
}

impl Accel {
    /// Whether `scene` is traced through a BVH.
    pub fn uses_bvh(self, scene: &Scene) -> bool {
        match self {
            Accel::Auto => scene.spheres.len() >= AUTO_MIN_SPHERES,
            Accel::Bvh => !scene.spheres.is_empty(),
            Accel::None => false,
        }
    }
}

/// The BVH over `scene`'s spheres, as the renderers trace it (the scene
/// already in the coordinates it is traced in).
pub fn sphere_bvh(scene: &Scene) -> bvh::Bvh {
    let bounds: Vec<bvh::Aabb> = scene
        .spheres
        .iter()
        .map(|s| bvh::Aabb::sphere(s.center, s.radius))
        .collect();
    bvh::build(&bounds)
}
