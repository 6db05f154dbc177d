//! Nearest hit over spheres and planes; mirrors shaders/intersect.glsl.
//!
//! Self-intersection is prevented without an epsilon: a ray that leaves a
//! surface carries that primitive's id. A plane cannot be met again; a sphere
//! is met again only by a ray that leaves it inwards, at t = -2 (o - c)·d.

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
/// own surface as described above.
pub fn intersect_scene<R: Real>(
    w: &World<R>,
    ray: &Ray<R>,
    from: usize,
    t_max: R,
) -> Option<Hit<R>> {
    let mut best: Option<Hit<R>> = None;
    let mut limit = t_max;
    for (i, s) in w.spheres.iter().enumerate() {
        if let Some(t) = intersect_sphere(ray, s.center, s.radius, from == i) {
            if t < limit {
                limit = t;
                best = Some(Hit { t, prim: i });
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
