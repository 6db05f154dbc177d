//! Where a padded leaf lies on one grid of the tables (tables.rs): its
//! range of cell coordinates seen from a light or the eye, or along a
//! directional light, with the key that orders the lists.

use glam::{DMat3, DVec3};

/// A leaf's place in one grid: its (a, b) range and its key.
#[derive(Debug, Clone, Copy)]
pub(super) struct Span {
    pub(super) a: (f64, f64),
    pub(super) b: (f64, f64),
    pub(super) key: f64,
}

/// `x` rounded to f32, never up.
pub(super) fn f32_down(x: f64) -> f32 {
    super::bvh::round_down(x)
}

/// The distance from `p` to the box (lo, hi); 0 inside it.
fn box_distance(p: DVec3, lo: DVec3, hi: DVec3) -> f64 {
    (lo - p).max(p - hi).max(DVec3::ZERO).length()
}

fn corners(lo: DVec3, hi: DVec3) -> [DVec3; 8] {
    std::array::from_fn(|i| {
        DVec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    })
}

const FULL: (f64, f64) = (f64::NEG_INFINITY, f64::INFINITY);

/// A padded leaf seen through the perspective map `rows` from `apex`:
/// None where it lies wholly behind; the whole grid where it reaches
/// behind the apex's plane.
pub(super) fn perspective_span(rows: &DMat3, apex: DVec3, lo: DVec3, hi: DVec3) -> Option<Span> {
    let key = box_distance(apex, lo, hi);
    let mapped = corners(lo, hi).map(|c| *rows * (c - apex));
    let (mut lam_min, mut lam_max) = (f64::INFINITY, f64::NEG_INFINITY);
    for m in &mapped {
        lam_min = lam_min.min(m.x);
        lam_max = lam_max.max(m.x);
    }
    if lam_max <= 0.0 {
        return None;
    }
    if lam_min <= 0.0 {
        return Some(Span {
            a: FULL,
            b: FULL,
            key,
        });
    }
    // μ/λ over a box in front of the apex is extreme at its corners.
    let (mut a, mut b) = (
        (f64::INFINITY, f64::NEG_INFINITY),
        (f64::INFINITY, f64::NEG_INFINITY),
    );
    for m in &mapped {
        let (u, v) = (m.y / m.x, m.z / m.x);
        a = (a.0.min(u), a.1.max(u));
        b = (b.0.min(v), b.1.max(v));
    }
    Some(Span { a, b, key })
}

/// A padded leaf seen along `rows` (along, a, b).
pub(super) fn parallel_span(rows: &DMat3, lo: DVec3, hi: DVec3) -> Span {
    let (mut along, mut a, mut b) = (
        f64::NEG_INFINITY,
        (f64::INFINITY, f64::NEG_INFINITY),
        (f64::INFINITY, f64::NEG_INFINITY),
    );
    for c in corners(lo, hi) {
        let m = *rows * c;
        along = along.max(m.x);
        a = (a.0.min(m.y), a.1.max(m.y));
        b = (b.0.min(m.z), b.1.max(m.z));
    }
    Span { a, b, key: -along }
}

/// The lookup's margin around a coordinate: far beyond its rounding.
pub(super) fn margin(x: f64) -> f64 {
    (1.0 + x.abs()) / 4096.0
}

/// The six faces of a direction cube: +x, -x, +y, -y, +z, -z, each the map
/// from a direction to (λ, μ, ν) with λ along the face's axis.
pub(super) fn cube_faces() -> [DMat3; 6] {
    std::array::from_fn(|f| {
        let axis = f / 2;
        let sign = if f % 2 == 0 { 1.0 } else { -1.0 };
        let e = |i: usize| DVec3::AXES[i % 3];
        DMat3::from_cols(e(axis) * sign, e(axis + 1), e(axis + 2)).transpose()
    })
}
