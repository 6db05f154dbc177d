//! Where a padded leaf lies on one grid of the tables (tables.rs): its
//! range of cell coordinates seen from a light or the eye, or along a
//! directional light, with the key that orders the lists.

use glam::{DMat3, DVec3};

use crate::prim::Hull;

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

/// A parallel span narrowed by the primitive's hull, its balls grown by
/// `pad`: along each row a ball reaches its centre's coordinate plus or
/// minus its radius times the row's length.
pub(super) fn narrowed_parallel(span: Span, rows: &DMat3, hull: &Hull, pad: f64) -> Span {
    let balls = hull.balls();
    if balls.is_empty() {
        return span;
    }
    let range = |row: DVec3| {
        balls
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |acc, &(c, r)| {
                let (x, reach) = (row.dot(c), (r + pad) * row.length());
                (acc.0.min(x - reach), acc.1.max(x + reach))
            })
    };
    let along = range(rows.row(0)).1;
    Span {
        a: meet(span.a, range(rows.row(1))),
        b: meet(span.b, range(rows.row(2))),
        key: span.key.max(-along),
    }
}

/// Two ranges that both hold a primitive's: their intersection, or the
/// first where rounding leaves it empty.
fn meet(x: (f64, f64), y: (f64, f64)) -> (f64, f64) {
    let m = (x.0.max(y.0), x.1.min(y.1));
    if m.0 <= m.1 {
        m
    } else {
        x
    }
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

/// A perspective span narrowed by the primitive's hull (`prim::Hull`), its
/// balls grown by `pad`. Where every ball lies in front of the apex's plane
/// (λ above twice its radius, so that the roots below are well
/// conditioned), each bounds μ/λ and ν/λ by its two tangent planes through
/// the apex, and the hull's range is the balls' together: a half-space
/// through the apex holds the hull where it holds every ball. The key rises
/// to the hull's near distance. Both ranges hold the primitive, so their
/// intersection does.
pub(super) fn narrowed(span: Span, rows: &DMat3, apex: DVec3, hull: &Hull, pad: f64) -> Span {
    let balls = hull.balls();
    let r0 = rows.row(0);
    let in_front = |&(c, r): &(DVec3, f64)| r0.dot(c - apex) > 2.0 * (r + pad) * r0.length();
    if balls.is_empty() || !balls.iter().all(in_front) {
        return span;
    }
    let range = |row: DVec3| {
        balls
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |acc, &(c, r)| {
                let (lo, hi) = tangents(r0, row, c - apex, r + pad);
                (acc.0.min(lo), acc.1.max(hi))
            })
    };
    Span {
        a: meet(span.a, range(rows.row(1))),
        b: meet(span.b, range(rows.row(2))),
        key: span.key.max(near(apex, balls, pad)),
    }
}

/// The range of (row·p)/(r0·p) over the ball (c, r), c from the apex and
/// in front of it: the two a where the plane (row − a·r0)·p = 0 is tangent
/// to the ball, ((row − a·r0)·c)² = r²|row − a·r0|², a quadratic in a.
fn tangents(r0: DVec3, row: DVec3, c: DVec3, r: f64) -> (f64, f64) {
    let (l, m) = (r0.dot(c), row.dot(c));
    let qa = l * l - r * r * r0.length_squared();
    let qb = l * m - r * r * r0.dot(row);
    let qc = m * m - r * r * row.length_squared();
    let s = (qb * qb - qa * qc).max(0.0).sqrt();
    // The root away from cancellation first, then the other from their
    // product qc/qa.
    let q = qb + s.copysign(qb);
    if q == 0.0 {
        return (0.0, 0.0);
    }
    let (x, y) = (q / qa, qc / q);
    (x.min(y), x.max(y))
}

/// A lower bound on the distance from `apex` to the hull of `balls` grown
/// by `pad`: to the one ball, to the segment of two less the larger radius,
/// to the triangle of three less the largest.
fn near(apex: DVec3, balls: &[(DVec3, f64)], pad: f64) -> f64 {
    let grown = balls.iter().map(|b| b.1).fold(0.0f64, f64::max) + pad;
    let d = match balls {
        [(c, _)] => (*c - apex).length(),
        [(a, _), (b, _)] => segment_distance(apex, *a, *b),
        [(a, _), (b, _), (c, _)] => triangle_distance(apex, *a, *b, *c),
        _ => return f64::NEG_INFINITY,
    };
    d - grown
}

fn segment_distance(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t - p).length()
}

/// From `p` to the triangle (a, b, c): to its plane where p's foot lies
/// inside it, else to its nearest edge.
fn triangle_distance(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let edges = || {
        segment_distance(p, a, b)
            .min(segment_distance(p, b, c))
            .min(segment_distance(p, c, a))
    };
    let n = (b - a).cross(c - a);
    let len = n.length();
    if len.is_nan() || len <= 0.0 {
        return edges();
    }
    let n = n / len;
    let foot = p - n * n.dot(p - a);
    let inside = [(a, b), (b, c), (c, a)]
        .iter()
        .all(|&(u, v)| (v - u).cross(foot - u).dot(n) >= 0.0);
    if inside {
        n.dot(p - a).abs()
    } else {
        edges()
    }
}

#[cfg(test)]
#[path = "spans_tests.rs"]
mod tests;
