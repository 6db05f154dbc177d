use super::*;
use crate::rng::Xorshift;

/// Points on the sphere (c, r) and on the segments between the balls of a
/// hull: what a narrowed span must hold.
fn surface(rng: &mut Xorshift, balls: &[(DVec3, f64)]) -> Vec<DVec3> {
    (0..4000)
        .map(|_| {
            let u = rng.unit();
            let n = balls.len() as f64;
            let (i, j) = ((rng.next() * n) as usize, (rng.next() * n) as usize);
            let t = rng.next();
            let (c, r) = (
                balls[i].0.lerp(balls[j].0, t),
                balls[i].1 + (balls[j].1 - balls[i].1) * t,
            );
            c + u * r
        })
        .collect()
}

fn eye_rows() -> DMat3 {
    let m = DMat3::from_cols(
        DVec3::new(0.1, -0.2, -1.0),
        DVec3::new(0.4, 0.05, 0.0),
        DVec3::new(0.0, 0.3, 0.1),
    );
    m.inverse()
}

/// A hull's narrowed range holds every point of the hull, seen from the
/// apex, and is tighter than the box's where the box is seen obliquely;
/// its key is at most the nearest point's distance.
#[test]
fn a_narrowed_span_holds_its_hull_and_is_tighter_than_the_box() {
    let mut rng = Xorshift(7);
    let apex = DVec3::new(0.3, -0.1, 0.2);
    let hulls = [
        vec![(DVec3::new(1.5, 2.0, -6.0), 0.7)],
        vec![
            (DVec3::new(-1.0, 1.0, -5.0), 0.2),
            (DVec3::new(2.0, -1.5, -8.0), 0.5),
        ],
        vec![
            (DVec3::new(-1.0, 1.0, -5.0), 0.0),
            (DVec3::new(2.0, -1.5, -8.0), 0.0),
            (DVec3::new(0.5, 2.5, -4.0), 0.0),
        ],
    ];
    for rows in [eye_rows(), cube_faces()[5]] {
        for balls in &hulls {
            let hull = Hull::of(balls);
            let points = surface(&mut rng, balls);
            let lo = points.iter().fold(DVec3::INFINITY, |a, p| a.min(*p));
            let hi = points.iter().fold(DVec3::NEG_INFINITY, |a, p| a.max(*p));
            let boxed = perspective_span(&rows, apex, lo, hi).unwrap();
            let s = narrowed(boxed, &rows, apex, &hull, 0.0);
            let (mut a, mut b, mut near) = (
                (f64::INFINITY, f64::NEG_INFINITY),
                (f64::INFINITY, f64::NEG_INFINITY),
                f64::INFINITY,
            );
            for p in &points {
                let m = rows * (*p - apex);
                let (u, v) = (m.y / m.x, m.z / m.x);
                let e = 1e-12 * (1.0 + u.abs() + v.abs());
                assert!(
                    s.a.0 - e <= u && u <= s.a.1 + e,
                    "{balls:?}: a {u} outside {:?}",
                    s.a
                );
                assert!(
                    s.b.0 - e <= v && v <= s.b.1 + e,
                    "{balls:?}: b {v} outside {:?}",
                    s.b
                );
                a = (a.0.min(u), a.1.max(u));
                b = (b.0.min(v), b.1.max(v));
                near = near.min((*p - apex).length());
            }
            assert!(
                s.key <= near + 1e-12,
                "{balls:?}: key {} past {near}",
                s.key
            );
            let width = |r: (f64, f64)| r.1 - r.0;
            // Sampled points fall inside the exact range, and close to it.
            assert!(
                width(s.a) <= width(a) * 1.05 + 1e-9,
                "{balls:?}: a {:?} against {a:?}",
                s.a
            );
            assert!(
                width(s.b) <= width(b) * 1.05 + 1e-9,
                "{balls:?}: b {:?} against {b:?}",
                s.b
            );
            assert!(
                width(s.a) * width(s.b) < width(boxed.a) * width(boxed.b),
                "{balls:?}"
            );
        }
    }
}

/// The parallel form: a ball's range along a row is its centre's plus or
/// minus its radius, and the key is minus its far end.
#[test]
fn a_narrowed_parallel_span_is_the_balls_reach() {
    let rows = DMat3::IDENTITY;
    let hull = Hull::of(&[(DVec3::new(1.0, 2.0, 3.0), 0.5)]);
    let boxed = parallel_span(&rows, DVec3::new(0.0, 1.0, 2.0), DVec3::new(2.0, 3.0, 4.0));
    let s = narrowed_parallel(boxed, &rows, &hull, 0.25);
    assert_eq!(s.a, (1.25, 2.75));
    assert_eq!(s.b, (2.25, 3.75));
    assert_eq!(s.key, -1.75);
}

#[test]
fn a_triangle_is_as_near_as_its_plane_or_an_edge() {
    let (a, b, c) = (DVec3::ZERO, DVec3::X, DVec3::Y);
    assert!((triangle_distance(DVec3::new(0.2, 0.2, 3.0), a, b, c) - 3.0).abs() < 1e-15);
    assert!((triangle_distance(DVec3::new(-1.0, 0.0, 0.0), a, b, c) - 1.0).abs() < 1e-15);
    let far = DVec3::new(1.0, 1.0, 0.0);
    assert!((triangle_distance(far, a, b, c) - 0.5f64.sqrt()).abs() < 1e-15);
}
