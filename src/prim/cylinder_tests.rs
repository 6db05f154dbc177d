//! The cylinder's intersect: hits on the surface and within its span, the
//! robust form far from the origin, rays along the axis and the surface.

use glam::DVec3;

use super::{Cylinder, CylinderR};
use crate::base::ray::Ray;
use crate::base::real::{Real, Vec3};
use crate::prim::{Kind, Shape};
use crate::rng::Xorshift;

/// A random point in the cube of half-side `size` around 0.
fn point(rng: &mut Xorshift, size: f64) -> DVec3 {
    DVec3::new(rng.next(), rng.next(), rng.next()) * (2.0 * size) - size
}

fn ray<R: Real>(origin: DVec3, dir: DVec3) -> Ray<R> {
    Ray {
        origin: Vec3::of(origin),
        dir: Vec3::of(dir.normalize()),
    }
}

/// How far `p` is off the surface of `c` (the distance from the axis less
/// the radius at its height), and how far beyond its span, in f64.
fn off_surface(c: &Cylinder, p: DVec3) -> (f64, f64) {
    let q = p - c.center;
    let y = q.dot(c.axis);
    let across = (q - c.axis * y).length();
    (
        (across - (c.radius + c.slope * y)).abs(),
        (y.abs() - c.half_length).max(0.0),
    )
}

/// Random cylinders and cones, random rays at them: every hit lies on the
/// surface within its span, and a ray leaving a hit point never meets the
/// surface again at that point.
#[test]
fn hits_lie_on_the_surface_within_its_span() {
    let mut rng = Xorshift(0x2545_f491_4f6c_dd1d);
    let mut hits = 0;
    for _ in 0..2000 {
        let base = point(&mut rng, 2.0);
        let apex = point(&mut rng, 2.0);
        let (rb, ra) = (rng.next() + 0.05, rng.next() * 1.5);
        let c = Cylinder::new(base, rb, apex, ra, 0).unwrap();
        let shape: CylinderR<f64> = c.cpu();
        let origin = point(&mut rng, 6.0);
        let target = c.center + point(&mut rng, 1.5);
        let r = ray::<f64>(origin, target - origin);
        let Some(t) = shape.intersect(&r, false) else {
            continue;
        };
        hits += 1;
        let p = origin + (target - origin).normalize() * t;
        let (off, beyond) = off_surface(&c, p);
        assert!(
            off < 1e-9 && beyond < 1e-9,
            "{c:?} {r:?} t {t}: {off} {beyond}"
        );
        // Leaving the hit point onward, the ray meets the far side or nothing.
        let on = Ray {
            origin: Vec3::of(p),
            dir: r.dir,
        };
        if let Some(t2) = shape.intersect(&on, true) {
            assert!(t2 > 1e-9, "{t2}");
            let (off, _) = off_surface(&c, p + DVec3::new(r.dir.x, r.dir.y, r.dir.z) * t2);
            assert!(off < 1e-9, "{off}");
        }
    }
    assert!(hits > 500, "only {hits} of the rays hit");
}

/// The quadric from the ray's origin, as textbooks write it: what the robust
/// form replaces.
fn plain_intersect(c: &CylinderR<f32>, r: &Ray<f32>) -> Option<f32> {
    let f = r.origin - c.center;
    let (a, k) = (c.axis, c.slope);
    let (fy, dy) = (f.dot(a), r.dir.dot(a));
    let (fx, dx) = (f - a * fy, r.dir - a * dy);
    let rad = c.radius + k * fy;
    let qa = dx.dot(dx) - k * k * dy * dy;
    let b = fx.dot(dx) - k * dy * rad;
    let cc = fx.dot(fx) - rad * rad;
    let disc = b * b - qa * cc;
    (disc >= 0.0).then(|| (-b - disc.sqrt()) / qa)
}

/// A rod of radius 0.01 seen from 1e4 away: the robust form finds it at the
/// right distance in f32, and the plain quadric from the origin does not.
#[test]
fn a_thin_rod_far_away_is_hit_in_f32_where_the_plain_quadric_fails() {
    let c = Cylinder::new(
        DVec3::new(1e4, -1.0, 0.0),
        0.01,
        DVec3::new(1e4, 1.0, 0.0),
        0.01,
        0,
    )
    .unwrap();
    let shape: CylinderR<f32> = c.cpu();
    let mut robust_worst = 0.0f64;
    let mut plain_worst = 0.0f64;
    for i in 0..=16 {
        let z = -0.0095 + 0.019 * f64::from(i) / 16.0;
        let r = ray::<f32>(DVec3::new(0.0, 0.3, z), DVec3::X);
        let exact = 1e4 - (1e-4 - z * z).sqrt();
        let err = |t: Option<f32>| t.map_or(f64::INFINITY, |t| (f64::from(t) - exact).abs());
        robust_worst = robust_worst.max(err(shape.intersect(&r, false)));
        plain_worst = plain_worst.max(err(plain_intersect(&shape, &r)));
    }
    // f32 spaces 1e4 by 1e-3: the robust error is that rounding.
    assert!(robust_worst < 2e-3, "robust {robust_worst}");
    assert!(plain_worst > 5e-3, "plain {plain_worst}");
}

/// Rays parallel to a cylinder's axis never meet it (inside, outside and
/// exactly on the surface), and return no NaN; a ray along a cone's side,
/// through its inside, meets it once.
#[test]
fn rays_along_the_axis_and_along_the_surface() {
    let c: CylinderR<f32> = Cylinder::new(DVec3::ZERO, 1.0, DVec3::Z * 4.0, 1.0, 0)
        .unwrap()
        .cpu();
    for origin in [
        DVec3::new(0.0, 0.0, -3.0),
        DVec3::new(0.5, 0.2, 1.0),
        DVec3::new(1.0, 0.0, -3.0),
        DVec3::new(0.0, 1.0, 2.0),
        DVec3::new(3.0, 0.0, -3.0),
    ] {
        for dir in [DVec3::Z, DVec3::NEG_Z] {
            assert_eq!(
                c.intersect(&ray(origin, dir), false),
                None,
                "{origin} {dir}"
            );
            assert_eq!(c.intersect(&ray(origin, dir), true), None, "{origin} {dir}");
        }
    }
    // A cone of half-angle 45°: radius 2 at z = 0 to 0 at z = 2. The ray
    // from (-1, 0, -1) along (1, 0, 1) runs parallel to its side x = z - 2
    // (A = 0 in the quadric) and meets the opposite side once, at (1, 0, 1).
    let cone: CylinderR<f64> = Cylinder::new(DVec3::ZERO, 2.0, DVec3::Z * 2.0, 0.0, 0)
        .unwrap()
        .cpu();
    let r = ray::<f64>(DVec3::new(-1.0, 0.0, -1.0), DVec3::new(1.0, 0.0, 1.0));
    let t = cone.intersect(&r, false).expect("meets the opposite side");
    assert!((t - 2.0 * 2f64.sqrt()).abs() < 1e-12, "{t}");
}
