//! Exact sums and squares for the robust intersections (the sphere's and the
//! cylinder's); mirrors shaders/exact.glsl.

use super::real::{Real, Vec3};

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
