//! Scene management: which primitives a ray tests. `none` tests every
//! object; `bvh` walks a bounding volume hierarchy over the bounded kinds
//! (spheres; planes are unbounded and stay outside it); `auto` picks by the
//! count. The choice never changes the image: ties in t go to the earlier
//! kind in `prim::KINDS`, then to the primitive that comes first in the
//! scene file, whatever order a walk meets them in.

pub(crate) mod bvh;
mod cost;
pub(crate) mod node;
pub(crate) mod quantize;
pub mod refit;
mod spans;
pub(crate) mod tables;

use crate::prim::Prims;

/// From this many bounded primitives up `auto` takes the BVH
/// (docs/performance.md, The BVH: where the linear scan stops winning on
/// lavapipe, measured with random fields of spheres).
pub const AUTO_MIN_BOUNDED: usize = 16;

/// Which primitives each ray tests (scene management). The image is the
/// same either way, bit for bit; only the time differs.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Accel {
    /// The BVH from 16 bounded primitives up (`AUTO_MIN_BOUNDED`), else the
    /// linear scan. Never the tables: measured, they do not yet pay back
    /// their build and compile in a whole render (docs/performance.md).
    #[default]
    Auto,
    /// A BVH over the bounded primitives; the unbounded ones (planes) are
    /// scanned.
    Bvh,
    /// Every ray tests every object.
    None,
    /// The BVH, with a light buffer for shadow rays and a screen-tile list
    /// for eye rays (`tables`): the walk serves reflection and refraction
    /// rays, and the cells whose lists would be too long.
    Tables,
}

impl Accel {
    /// Whether a scene of `prims` is traced through a BVH.
    pub fn uses_bvh(self, prims: &Prims) -> bool {
        let bounded = prims.bounded_count();
        match self {
            Accel::Auto => bounded >= AUTO_MIN_BOUNDED,
            Accel::Bvh | Accel::Tables => bounded > 0,
            Accel::None => false,
        }
    }

    /// Whether a scene of `prims` reads tables for its shadow and eye rays
    /// (where it is traced through a BVH): with `tables` alone.
    pub fn uses_tables(self, prims: &Prims) -> bool {
        self == Accel::Tables && self.uses_bvh(prims)
    }
}

/// The bytes the tables may take on the device: 16 MiB, and as much again
/// as the tree and the bounded primitives take (at 32 bytes each).
pub(crate) fn tables_budget(prims: &Prims, tree: &bvh::Bvh) -> usize {
    (16 << 20) + 64 * tree.nodes.len() + 32 * prims.bounded_count()
}

/// Each bounded primitive's padded box (`bvh::padded`), translated by
/// `-origin`, by kind and index in the scene.
pub(crate) fn prim_boxes(prims: &Prims, origin: glam::DVec3) -> Vec<Vec<([f32; 3], [f32; 3])>> {
    let (bounds, ids) = prims.relative_bounds(origin);
    let mut boxes: Vec<Vec<([f32; 3], [f32; 3])>> = prims
        .counts()
        .into_iter()
        .map(|n| vec![([0.0; 3], [0.0; 3]); n])
        .collect();
    for (b, id) in bounds.into_iter().zip(ids) {
        boxes[id.kind as usize][id.index as usize] = bvh::padded(b);
    }
    boxes
}
/// The BVH over the bounded ones of `prims`, as the renderers trace it
/// (the scene already in the coordinates it is traced in). Its `orders`
/// hold each kind's indices in the scene.
pub fn scene_bvh(prims: &Prims) -> bvh::Bvh {
    relative_bvh(prims, glam::DVec3::ZERO)
}

/// The BVH of `prims` translated by `-origin`, refitted from `shape` (a
/// tree built over the same primitives where they were before): None
/// where they are not the same ones (`refit::refit`); with its shape for
/// the next refit.
pub fn relative_refit(
    shape: &refit::Shape,
    prims: &Prims,
    origin: glam::DVec3,
) -> Option<(bvh::Bvh, refit::Shape)> {
    let (bounds, ids) = prims.relative_bounds(origin);
    let mut boxes: Vec<Vec<Option<crate::base::aabb::Aabb>>> =
        prims.counts().into_iter().map(|n| vec![None; n]).collect();
    for (b, id) in bounds.into_iter().zip(ids) {
        boxes[id.kind as usize][id.index as usize] = Some(b);
    }
    refit::refit(shape, &boxes)
}

/// The BVH of `prims` translated by `-origin` (that of the scene's
/// `camera_relative()` where `origin` is the eye).
pub fn relative_bvh(prims: &Prims, origin: glam::DVec3) -> bvh::Bvh {
    let (bounds, ids) = prims.relative_bounds(origin);
    let kinds: Vec<u32> = ids.iter().map(|id| id.kind).collect();
    let mut tree = bvh::build(&bounds, &kinds);
    for order in &mut tree.orders {
        for i in order.iter_mut() {
            *i = ids[*i as usize].index;
        }
    }
    tree
}
