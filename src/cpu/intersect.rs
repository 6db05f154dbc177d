//! Nearest hit over spheres and planes; mirrors shaders/intersect.glsl.
//!
//! Self-intersection is prevented without an epsilon: a ray that leaves a
//! surface carries that primitive's id. A plane cannot be met again; a sphere
//! is met again only by a ray that leaves it inwards, at t = -2 (o - c)·d.

use crate::accel::bvh::{Bvh, Node};

use super::ray::Ray;
use super::real::{Real, Vec3};
use super::world::World;

/// Primitive ids: spheres first, then planes; `NONE` for an eye ray.
pub const NONE: usize = usize::MAX;

#[derive(Debug, Clone, Copy)]
pub struct Hit<R> {
    pub t: R,
    pub prim: usize,
}

/// a + b as hi + lo exactly (Knuth's TwoSum).
fn two_sum<R: Real>(a: R, b: R) -> (R, R) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// a² as hi + lo exactly, by Veltkamp's split of a into two halves whose
/// products are exact (as the shader does it: llvmpipe may not fuse fma).
fn two_square<R: Real>(a: R) -> (R, R) {
    let c = R::of(R::SPLIT) * a;
    let hi = c - (c - a);
    let lo = a - hi;
    let p = a * a;
    (p, ((hi * hi - p) + R::of(2.0) * hi * lo) + lo * lo)
}

/// f·f - r², the origin's power with respect to the sphere, with every
/// rounding of the squares and sums carried along. The plain form cancels
/// where it matters most: an origin near the surface of a huge sphere (a
/// camera one unit above a ground sphere of radius 1e6 has f·f ≈ 1e12 and a
/// power of 2e6, and f32 spaces 1e12 by 65536).
pub fn power<R: Real>(f: Vec3<R>, r: R) -> R {
    let (x, ex) = two_square(f.x);
    let (y, ey) = two_square(f.y);
    let (z, ez) = two_square(f.z);
    let (rr, er) = two_square(r);
    let (s1, e1) = two_sum(x, y);
    let (s2, e2) = two_sum(s1, z);
    let (s3, e3) = two_sum(s2, -rr);
    s3 + (((e1 + e2) + e3) + ((ex + ey) + ez - er))
}

/// Distance along a unit-direction ray to a sphere, or None.
pub fn intersect_sphere<R: Real>(
    ray: &Ray<R>,
    center: Vec3<R>,
    radius: R,
    from_self: bool,
) -> Option<R> {
    let f = ray.origin - center;
    let b = f.dot(ray.dir);
    if from_self {
        let t = R::of(-2.0) * b;
        return (t > R::zero()).then_some(t);
    }
    // The discriminant from the perpendicular distance to the centre rather
    // than b² - c, which loses every digit when the sphere is small against
    // its distance (Ray Tracing Gems ch. 7).
    let l = f - ray.dir * b;
    let disc = radius * radius - l.dot(l);
    if disc < R::zero() {
        return None;
    }
    let c = power(f, radius);
    let root = disc.sqrt();
    // The stable root pair: q never cancels, and t0 = c/q is the other root.
    let q = if b >= R::zero() { -b - root } else { -b + root };
    let t0 = c / q;
    let t1 = q;
    let (near, far) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
    if near > R::zero() {
        Some(near)
    } else if far > R::zero() {
        Some(far)
    } else {
        None
    }
}

pub fn intersect_plane<R: Real>(
    ray: &Ray<R>,
    point: Vec3<R>,
    normal: Vec3<R>,
    from_self: bool,
) -> Option<R> {
    if from_self {
        return None;
    }
    let denom = ray.dir.dot(normal);
    if denom == R::zero() {
        return None;
    }
    let t = (point - ray.origin).dot(normal) / denom;
    (t > R::zero()).then_some(t)
}

/// The nearest hit with t in (0, t_max), skipping the originating primitive's
/// own surface as described above. Ties in t go to the lower primitive id.
pub fn intersect_scene<R: Real>(
    w: &World<R>,
    ray: &Ray<R>,
    from: usize,
    t_max: R,
) -> Option<Hit<R>> {
    let mut best: Option<Hit<R>> = None;
    let mut limit = t_max;
    match &w.bvh {
        Some(tree) => {
            limit = walk(tree, ray, limit, |id, limit| {
                let s = &w.spheres[id];
                if let Some(t) = intersect_sphere(ray, s.center, s.radius, from == id) {
                    let tie = t == *limit && best.is_some_and(|b| id < b.prim);
                    if t < *limit || tie {
                        *limit = t;
                        best = Some(Hit { t, prim: id });
                    }
                }
                true
            })
        }
        None => {
            for (i, s) in w.spheres.iter().enumerate() {
                if let Some(t) = intersect_sphere(ray, s.center, s.radius, from == i) {
                    if t < limit {
                        limit = t;
                        best = Some(Hit { t, prim: i });
                    }
                }
            }
        }
    }
    let base = w.spheres.len();
    for (i, p) in w.planes.iter().enumerate() {
        if let Some(t) = intersect_plane(ray, p.point, p.normal, from == base + i) {
            if t < limit {
                limit = t;
                best = Some(Hit { t, prim: base + i });
            }
        }
    }
    best
}

/// Whether any sphere lies on the ray strictly between 0 and `dist`: the
/// shadow rays' any-hit walk of the BVH.
pub fn bvh_occluded<R: Real>(w: &World<R>, tree: &Bvh, ray: &Ray<R>, from: usize, dist: R) -> bool {
    let mut blocked = false;
    walk(tree, ray, dist, |id, _| {
        let s = &w.spheres[id];
        blocked = intersect_sphere(ray, s.center, s.radius, from == id).is_some_and(|t| t < dist);
        !blocked
    });
    blocked
}

/// Walks the tree in `ray`'s order: for each sphere of every leaf whose box
/// the ray meets within `limit`, calls `visit(id, &mut limit)`, which may
/// lower the limit, and returns false to end the walk. Returns the limit.
fn walk<R: Real>(
    tree: &Bvh,
    ray: &Ray<R>,
    mut limit: R,
    mut visit: impl FnMut(usize, &mut R) -> bool,
) -> R {
    let boxes = BoxWalk::new(ray);
    let nodes = boxes.layout(tree);
    let mut i = 0;
    while i < nodes.len() {
        let node = &nodes[i];
        if boxes.enters(node, limit) {
            let Some(slots) = node.prims() else {
                i += 1;
                continue;
            };
            for slot in slots {
                if !visit(tree.order[slot] as usize, &mut limit) {
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

/// The outward surface normal at `p` and the hit primitive's material.
pub fn surface<R: Real>(w: &World<R>, prim: usize, p: Vec3<R>) -> (Vec3<R>, usize) {
    match w.spheres.get(prim) {
        Some(s) => ((p - s.center) / s.radius, s.material),
        None => {
            let plane = &w.planes[prim - w.spheres.len()];
            (plane.normal, plane.material)
        }
    }
}
