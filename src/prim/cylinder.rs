//! The cylinder and the cone (NFF's `c`): an open surface of revolution
//! between two circles, with no caps, two-sided like the plane. Its
//! scene-file table, checks, GPU struct and bounds, and the CPU reference's
//! intersect and normal; mirrors shaders/prim/cylinder.glsl.
//!
//! Kept as its centre m (the axis' midpoint), unit axis a, half-length h,
//! the radius at the centre and the slope k (the radius grows by k per unit
//! along a): the radius at height y above m is r(y) = r_m + k·y, |y| ≤ h.
//! A cylinder is the cone with k = 0.
//!
//! Robust form. The quadric is solved from the point of the ray closest to
//! m rather than from its origin, so that its coefficients are of the
//! cylinder's own size however far away the origin is (an origin 1e4 away
//! from a cylinder of radius 1e-2 cancels every digit of b² − A·c in f32
//! otherwise), and c is the exact `power` of that point's distance from the
//! axis against the radius there. As with the sphere, a ray that leaves the
//! surface knows it: its origin's root is 0, and the other root is −2b/A.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::{Kind, Shape};
use crate::base::aabb::Aabb;
use crate::base::exact::power;
use crate::base::ray::Ray;
use crate::base::real::{Real, Vec3};
use crate::input::error::SceneError;
use crate::input::field::{unit_vector, At, Triple, MAX_COORDINATE};
use crate::rng::Place;

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CylinderFile {
    pub base: Triple,
    pub base_radius: f64,
    pub apex: Triple,
    pub apex_radius: f64,
    pub material: String,
}

/// A cylinder or a cone (a truncated one, or with an apex of radius 0),
/// open at both ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cylinder {
    /// The axis' midpoint.
    pub center: DVec3,
    /// Unit, from base to apex.
    pub axis: DVec3,
    /// Half the axis' length.
    pub half_length: f64,
    /// The radius at the centre: the mean of the two.
    pub radius: f64,
    /// The radius' growth per unit along the axis.
    pub slope: f64,
    /// The index of its material in `Scene::materials`.
    pub material: u32,
}

impl Cylinder {
    /// The surface between the circle of radius `base_radius` around
    /// `base` and that of `apex_radius` around `apex`, both at right angles
    /// to the axis from one to the other; None where the two centres are one.
    pub fn new(
        base: DVec3,
        base_radius: f64,
        apex: DVec3,
        apex_radius: f64,
        material: u32,
    ) -> Option<Self> {
        let axis = unit_vector(apex - base)?;
        let half_length = (apex - base).length() / 2.0;
        (half_length > 0.0 && half_length.is_finite()).then(|| Cylinder {
            center: base + (apex - base) / 2.0,
            axis,
            half_length,
            radius: (base_radius + apex_radius) / 2.0,
            slope: (apex_radius - base_radius) / (2.0 * half_length),
            material,
        })
    }

    /// The radii at the two ends, base then apex.
    pub fn end_radii(&self) -> [f64; 2] {
        let grow = self.slope * self.half_length;
        [self.radius - grow, self.radius + grow]
    }
}

crate::base::interface::gpu_struct!(
    /// The cylinder or cone in the shader's buffers.
    pub mod gpu: "Cylinder" {
        /// xyz the axis' midpoint, w the radius there
        center: real4,
        /// xyz the unit axis, w the half-length
        axis: real4,
        /// x the slope (the radius' growth per unit along the axis)
        slope: real4,
        /// x material, y index in the scene file
        meta: uvec4,
    }
);

pub struct CylinderR<R> {
    pub center: Vec3<R>,
    pub axis: Vec3<R>,
    pub half_length: R,
    pub radius: R,
    pub slope: R,
    pub material: usize,
}

/// A radius: finite, ≥ 0 and at most `MAX_COORDINATE`.
fn radius(at: &At, key: &str, v: f64) -> Result<f64, SceneError> {
    if !v.is_finite() || !(0.0..=MAX_COORDINATE).contains(&v) {
        return at.invalid(
            key,
            format!(
                "must be a number from 0 to {MAX_COORDINATE:e}, got {}",
                crate::printable::number(v)
            ),
        );
    }
    Ok(v)
}

impl Kind for Cylinder {
    type File = CylinderFile;
    type Gpu = gpu::Values;
    type Cpu<R: Real> = CylinderR<R>;
    const NAME: &'static str = "cylinder";
    const GLSL: &'static str = include_str!("../../shaders/prim/cylinder.glsl");
    const BOUNDED: bool = true;

    fn check(f: &CylinderFile, at: &At) -> Result<Self, SceneError> {
        let base = at.position("base", f.base)?;
        let base_radius = radius(at, "base_radius", f.base_radius)?;
        let apex = at.position("apex", f.apex)?;
        let apex_radius = radius(at, "apex_radius", f.apex_radius)?;
        let material = at.material("material", &f.material)?;
        if base_radius == 0.0 && apex_radius == 0.0 {
            return at.invalid("base_radius", "base_radius and apex_radius are both 0");
        }
        match Cylinder::new(base, base_radius, apex, apex_radius, material) {
            Some(c) => Ok(c),
            None => at.invalid("apex", "apex is base: the axis has no length"),
        }
    }

    fn material(&self) -> u32 {
        self.material
    }

    fn relative_to(&self, origin: DVec3) -> Self {
        Cylinder {
            center: self.center - origin,
            ..*self
        }
    }

    /// The box of the two end circles: a circle of radius r at right angles
    /// to the unit a reaches r·√(1 − aᵢ²) along axis i.
    fn bounds(&self) -> Option<Aabb> {
        let reach = (DVec3::ONE - self.axis * self.axis).max(DVec3::ZERO);
        let reach = DVec3::new(reach.x.sqrt(), reach.y.sqrt(), reach.z.sqrt());
        let [rb, ra] = self.end_radii();
        let base = self.center - self.axis * self.half_length;
        let apex = self.center + self.axis * self.half_length;
        Some(Aabb {
            lo: (base - reach * rb).min(apex - reach * ra),
            hi: (base + reach * rb).max(apex + reach * ra),
        })
    }

    /// The balls of its two end circles.
    fn hull(&self) -> super::Hull {
        let [rb, ra] = self.end_radii();
        super::Hull::of(&[
            (self.center - self.axis * self.half_length, rb.abs()),
            (self.center + self.axis * self.half_length, ra.abs()),
        ])
    }

    fn gpu(&self, file_index: u32) -> gpu::Values {
        let (c, a) = (self.center, self.axis);
        gpu::Values {
            center: [c.x, c.y, c.z, self.radius],
            axis: [a.x, a.y, a.z, self.half_length],
            slope: [self.slope, 0.0, 0.0, 0.0],
            meta: [self.material, file_index, 0, 0],
        }
    }

    #[cfg(test)]
    fn example(material: u32) -> Self {
        let (base, apex) = (DVec3::new(-1.0, 0.0, 0.5), DVec3::new(1.0, 0.5, 1.0));
        Cylinder::new(base, 0.5, apex, 0.25, material).expect("a cylinder with an axis")
    }

    /// A cylinder, a cone or a truncated cone along a random axis.
    fn sample(p: &mut Place) -> CylinderFile {
        let axis = p.unit() * p.size;
        let base_radius = p.size * 0.5;
        let apex_radius = [base_radius, 0.0, base_radius * 0.3][p.pick(3)];
        CylinderFile {
            base: Triple(Place::triple(p.center - axis)),
            base_radius,
            apex: Triple(Place::triple(p.center + axis)),
            apex_radius,
            material: p.material.to_owned(),
        }
    }

    fn cpu<R: Real>(&self) -> CylinderR<R> {
        CylinderR {
            center: Vec3::of(self.center),
            axis: Vec3::of(self.axis),
            half_length: R::of(self.half_length),
            radius: R::of(self.radius),
            slope: R::of(self.slope),
            material: self.material as usize,
        }
    }
}

impl<R: Real> CylinderR<R> {
    /// The quadric A t² + 2 b t + c = 0 of the ray from f (its origin less
    /// the centre) along d, as (A, b, the height of f, f's part across the
    /// axis, the radius at f's height).
    fn quadric(&self, f: Vec3<R>, d: Vec3<R>) -> (R, R, R, Vec3<R>, R) {
        let (a, k) = (self.axis, self.slope);
        let fy = f.dot(a);
        let dy = d.dot(a);
        let fx = f - a * fy;
        let dx = d - a * dy;
        let r = self.radius + k * fy;
        (
            dx.dot(dx) - k * k * dy * dy,
            fx.dot(dx) - k * dy * r,
            fy,
            fx,
            r,
        )
    }

    /// Whether the point at height `y` above the centre lies on the
    /// surface's span.
    fn spans(&self, y: R) -> bool {
        y.abs() <= self.half_length
    }
}

impl<R: Real> Shape<R> for CylinderR<R> {
    fn intersect(&self, ray: &Ray<R>, from_self: bool) -> Option<R> {
        let d = ray.dir;
        let zero = R::zero();
        if from_self {
            let (qa, b, fy, _, _) = self.quadric(ray.origin - self.center, d);
            if qa == zero {
                return None;
            }
            let t = R::of(-2.0) * b / qa;
            return (t > zero && self.spans(fy + t * d.dot(self.axis))).then_some(t);
        }
        // Solve from the ray's point closest to the centre.
        let tm = (self.center - ray.origin).dot(d);
        let f = ray.origin + d * tm - self.center;
        let (qa, b, fy, fx, r) = self.quadric(f, d);
        let c = power(fx, r);
        let dy = d.dot(self.axis);
        let (t0, t1) = if qa == zero {
            // A ray along a cone's side meets the double cone once.
            if b == zero {
                return None;
            }
            let t = -c / (R::of(2.0) * b);
            (t, t)
        } else {
            let disc = b * b - qa * c;
            if disc < zero {
                return None;
            }
            let root = disc.sqrt();
            // The stable root pair, as for the sphere.
            let q = if b >= zero { -b - root } else { -b + root };
            if q == zero {
                return None;
            }
            let (u, v) = (c / q, q / qa);
            if u <= v {
                (u, v)
            } else {
                (v, u)
            }
        };
        [t0, t1]
            .into_iter()
            .find(|&t| tm + t > zero && self.spans(fy + t * dy))
            .map(|t| tm + t)
    }

    fn normal(&self, p: Vec3<R>) -> Vec3<R> {
        let q = p - self.center;
        let a = self.axis;
        let across = q - a * q.dot(a);
        let len = across.length();
        if len == R::zero() {
            // A cone's tip: the mean of the normals around it.
            return a * -self.slope.signum();
        }
        (across / len - a * self.slope).normalize()
    }

    fn material(&self) -> usize {
        self.material
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cylinder(base: DVec3, rb: f64, apex: DVec3, ra: f64) -> CylinderR<f64> {
        Cylinder::new(base, rb, apex, ra, 0).unwrap().cpu()
    }

    fn ray(o: [f64; 3], d: [f64; 3]) -> Ray<f64> {
        Ray {
            origin: Vec3::new(o[0], o[1], o[2]),
            dir: Vec3::new(d[0], d[1], d[2]).normalize(),
        }
    }

    #[test]
    fn a_ray_across_a_cylinder_meets_its_near_side() {
        let c = cylinder(DVec3::ZERO, 1.0, DVec3::Z * 2.0, 1.0);
        let t = c.intersect(&ray([-5.0, 0.0, 1.0], [1.0, 0.0, 0.0]), false);
        assert_eq!(t, Some(4.0));
        // From inside, the far side; open ends let a ray through.
        let t = c.intersect(&ray([0.0, 0.0, 1.0], [1.0, 0.0, 0.0]), false);
        assert_eq!(t, Some(1.0));
        assert_eq!(
            c.intersect(&ray([0.0, 0.0, 1.0], [0.0, 0.0, 1.0]), false),
            None
        );
    }

    #[test]
    fn a_ray_leaving_the_surface_meets_only_its_other_side() {
        let c = cylinder(DVec3::ZERO, 1.0, DVec3::Z * 2.0, 1.0);
        let inward = ray([-1.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
        assert_eq!(c.intersect(&inward, true), Some(2.0));
        let outward = ray([-1.0, 0.0, 1.0], [-1.0, 0.0, 0.0]);
        assert_eq!(c.intersect(&outward, true), None);
    }

    #[test]
    fn a_cone_narrows_toward_its_apex_and_tilts_its_normal() {
        // Radius 1 at z = 0 to 0 at z = 1: at z = 0.5 the radius is 0.5.
        let c = cylinder(DVec3::ZERO, 1.0, DVec3::Z, 0.0);
        let t = c.intersect(&ray([-3.0, 0.0, 0.5], [1.0, 0.0, 0.0]), false);
        assert!((t.unwrap() - 2.5).abs() < 1e-12, "{t:?}");
        let n = c.normal(Vec3::new(-0.5, 0.0, 0.5));
        let s = 0.5f64.sqrt();
        assert!((n - Vec3::new(-s, 0.0, s)).length() < 1e-12, "{n:?}");
    }

    #[test]
    fn a_small_cylinder_far_away_is_hit_at_the_right_distance_in_f32() {
        // b² − A·c from the origin would cancel every digit here in f32.
        let c: CylinderR<f32> = Cylinder::new(
            DVec3::new(1e4, -1.0, 0.0),
            0.01,
            DVec3::new(1e4, 1.0, 0.0),
            0.01,
            0,
        )
        .unwrap()
        .cpu();
        let r = Ray {
            origin: Vec3::new(0.0f32, 0.0, 0.005),
            dir: Vec3::new(1.0f32, 0.0, 0.0),
        };
        let t = c.intersect(&r, false).unwrap();
        let exact = 1e4 - (0.01f64.powi(2) - 0.005f64.powi(2)).sqrt();
        assert!((f64::from(t) - exact).abs() < 2e-3, "{t} against {exact}");
    }

    #[test]
    fn the_box_holds_both_end_circles() {
        let c = Cylinder::new(DVec3::ZERO, 2.0, DVec3::X * 4.0, 1.0, 0).unwrap();
        let b = c.bounds().unwrap();
        assert_eq!(b.lo, DVec3::new(0.0, -2.0, -2.0));
        assert_eq!(b.hi, DVec3::new(4.0, 2.0, 2.0));
    }
}

#[cfg(test)]
#[path = "cylinder_tests.rs"]
mod intersect_tests;
