//! Nearest hit and any hit over every primitive; mirrors shaders/intersect.glsl
//! and the scans that src/gpu/generated.rs writes for the shader. Each
//! kind's own intersect and normal are in its module of `crate::prim`.

use crate::accel::bvh::{Bvh, Node};
use crate::prim::{PrimId, KINDS};
use crate::stats::{Counter, Tally};

use super::world::World;
use crate::base::ray::Ray;
use crate::base::real::{Real, Vec3};

#[derive(Debug, Clone, Copy)]
pub struct Hit<R> {
    pub t: R,
    pub prim: PrimId,
}

/// The nearest hit with t in (0, t_max), skipping the surface the ray
/// leaves (`from`). Ties in t go to the lower id: the earlier kind, then the
/// earlier primitive in the file. `tally` counts the tests and nodes.
pub fn intersect_scene<R: Real, T: Tally>(
    w: &World<R>,
    ray: &Ray<R>,
    from: PrimId,
    t_max: R,
    tally: &mut T,
) -> Option<Hit<R>> {
    let mut best: Option<Hit<R>> = None;
    let mut limit = t_max;
    if let Some(tree) = &w.bvh {
        limit = walk(tree, ray, limit, tally, |id, limit, tally| {
            tally.count(Counter::Test(id.kind));
            if let Some(t) = w.prims.intersect(id, ray, from) {
                let tie = t == *limit && best.is_some_and(|b| id < b.prim);
                if t < *limit || tie {
                    *limit = t;
                    best = Some(Hit { t, prim: id });
                }
            }
            true
        });
    }
    // The kinds the tree does not hold, in the table's order: a strict `<`
    // leaves a tie to the earlier.
    w.prims.scan(w.bvh.is_some(), ray, from, tally, |id, t| {
        if t < limit {
            limit = t;
            best = Some(Hit { t, prim: id });
        }
        true
    });
    best
}

/// Whether anything lies on the shadow ray strictly between 0 and `dist`:
/// the any-hit walk of the BVH, then the scan of what it does not hold.
pub fn occluded<R: Real, T: Tally>(
    w: &World<R>,
    ray: &Ray<R>,
    from: PrimId,
    dist: R,
    tally: &mut T,
) -> bool {
    let mut blocked = false;
    if let Some(tree) = &w.bvh {
        walk(tree, ray, dist, tally, |id, _, tally| {
            tally.count(Counter::Test(id.kind));
            blocked = w.prims.intersect(id, ray, from).is_some_and(|t| t < dist);
            !blocked
        });
    }
    if !blocked {
        w.prims.scan(w.bvh.is_some(), ray, from, tally, |_, t| {
            blocked = t < dist;
            !blocked
        });
    }
    blocked
}

/// Walks the tree in `ray`'s order: for each primitive of every leaf whose
/// box the ray meets within `limit`, calls `visit(id, &mut limit)`, which
/// may lower the limit, and returns false to end the walk. Returns the limit.
fn walk<R: Real, T: Tally>(
    tree: &Bvh,
    ray: &Ray<R>,
    mut limit: R,
    tally: &mut T,
    mut visit: impl FnMut(PrimId, &mut R, &mut T) -> bool,
) -> R {
    let boxes = BoxWalk::new(ray);
    let nodes = boxes.layout(tree);
    let mut i = 0;
    while i < nodes.len() {
        let node = &nodes[i];
        tally.count(Counter::Node);
        if boxes.enters(node, limit) {
            let Some((kind, range)) = node.prims() else {
                i += 1;
                continue;
            };
            for &index in &tree.orders[kind][range] {
                let id = PrimId {
                    kind: kind as u32,
                    index,
                };
                if !visit(id, &mut limit, tally) {
                    return limit;
                }
            }
        }
        i = node.skip as usize;
    }
    limit
}

/// A ray's slab test against node boxes; mirrors shaders/bvh.glsl.
struct BoxWalk<R> {
    origin: Vec3<R>,
    inv: Vec3<R>,
    octant: usize,
}

/// Widens a box's far distance against the rounding of the slab test
/// (1 + 2γ₃ of Ize, "Robust BVH Ray Traversal", JCGT 2013, for f32 with
/// room to spare; the boxes are padded besides).
const BOX_SLACK: f64 = 1.000_002;

impl<R: Real> BoxWalk<R> {
    fn new(ray: &Ray<R>) -> Self {
        // ±1e30 for a zero component: (lo - o) * inv is then never 0 * inf.
        let inv = |d: R| {
            if d.abs() > R::of(1e-30) {
                d.recip()
            } else if d >= R::zero() {
                R::of(1e30)
            } else {
                R::of(-1e30)
            }
        };
        let d = ray.dir;
        Self {
            origin: ray.origin,
            inv: Vec3::new(inv(d.x), inv(d.y), inv(d.z)),
            // As bvh::octant, in R: a negative component sets its bit.
            octant: usize::from(d.x < R::zero())
                | usize::from(d.y < R::zero()) << 1
                | usize::from(d.z < R::zero()) << 2,
        }
    }

    /// The nodes in the order this ray's octant walks them.
    fn layout<'t>(&self, tree: &'t Bvh) -> &'t [Node] {
        tree.layout(self.octant)
    }

    /// Whether the ray meets the node's box somewhere in [0, t_max].
    fn enters(&self, node: &Node, t_max: R) -> bool {
        let lo = Vec3::new(
            R::of(node.lo[0].into()),
            R::of(node.lo[1].into()),
            R::of(node.lo[2].into()),
        );
        let hi = Vec3::new(
            R::of(node.hi[0].into()),
            R::of(node.hi[1].into()),
            R::of(node.hi[2].into()),
        );
        let t0 = (lo - self.origin) * self.inv;
        let t1 = (hi - self.origin) * self.inv;
        let near = t0.x.min(t1.x).max(t0.y.min(t1.y)).max(t0.z.min(t1.z));
        let far = t0.x.max(t1.x).min(t0.y.max(t1.y)).min(t0.z.max(t1.z)) * R::of(BOX_SLACK);
        near <= far && far >= R::zero() && near <= t_max * R::of(BOX_SLACK)
    }
}

/// What shading needs of the primitive hit at `p`.
pub struct Surface<R> {
    /// The outward (geometric) normal: which side the ray is on.
    pub outward: Vec3<R>,
    /// The normal shading uses, on the side of `outward`.
    pub shading: Vec3<R>,
    pub material: usize,
    /// Whether rays leaving it start lifted off it ([`lift`]).
    pub lifted: bool,
}

pub fn surface<R: Real>(w: &World<R>, prim: PrimId, p: Vec3<R>) -> Surface<R> {
    let shape = w.prims.get(prim);
    let outward = shape.normal(p);
    Surface {
        outward,
        shading: shape.shading(p, outward),
        material: shape.material(),
        lifted: KINDS[prim.kind as usize].lift,
    }
}

/// How far rays leaving a triangle start off it, relative to the size of
/// their coordinates ([`lift`]): 512 ulps in f32.
pub const LIFT: f64 = 1.0 / 16384.0;

/// `p` moved off the surface along the unit `side`, by [`LIFT`] of the
/// largest coordinate of `p` and of the ray's origin `o`: more than the
/// rounding of p = o + t·d and of t can put it behind a neighbouring
/// triangle's plane. The same distance in f64, so that both precisions
/// trace the same model. Mirrors lift() in shaders/intersect.glsl.
pub fn lift<R: Real>(p: Vec3<R>, o: Vec3<R>, side: Vec3<R>) -> Vec3<R> {
    let largest = |v: Vec3<R>| v.x.abs().max(v.y.abs()).max(v.z.abs());
    p + side * (largest(p).max(largest(o)) * R::of(LIFT))
}
