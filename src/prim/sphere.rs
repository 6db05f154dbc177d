//! The sphere: its scene-file table, checks, GPU struct and bounds, and the
//! CPU reference's intersect and normal; mirrors shaders/prim/sphere.glsl.
//!
//! Self-intersection is prevented without an epsilon: a ray that leaves a
//! surface knows which primitive it left, and meets a sphere again only
//! when it leaves it inwards, at t = -2 (o - c)·d.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::{Kind, Shape};
use crate::base::aabb::Aabb;
use crate::base::exact::power;
use crate::base::ray::Ray;
use crate::base::real::{Real, Vec3};
use crate::input::error::SceneError;
use crate::input::field::{At, Triple};
use crate::rng::Place;

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SphereFile {
    pub center: Triple,
    pub radius: f64,
    pub material: String,
}

/// A sphere.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere {
    /// Its centre.
    pub center: DVec3,
    /// Its radius, > 0.
    pub radius: f64,
    /// The index of its material in `Scene::materials`.
    pub material: u32,
}

crate::base::interface::gpu_struct!(
    /// The sphere in the shader's buffers.
    pub mod gpu: "Sphere" {
        /// xyz centre, w radius
        center_radius: real4,
        /// x material, y index in the scene file
        meta: uvec4,
    }
);

/// How far |(p − c)/r|² may be from 1 before the normal is taken as the
/// direction of p − c instead: about 5e-4 of the radius off the surface,
/// far past the rounding of a hit placed as well as its ray allows, so
/// that such hits keep their bits. Mirrors shaders/prim/sphere.glsl.
pub const OFF_SURFACE: f64 = 1.0 / 1024.0;

pub struct SphereR<R> {
    pub center: Vec3<R>,
    pub radius: R,
    pub material: usize,
}

impl Kind for Sphere {
    type File = SphereFile;
    type Gpu = gpu::Values;
    type Cpu<R: Real> = SphereR<R>;
    const NAME: &'static str = "sphere";
    const GLSL: &'static str = include_str!("../../shaders/prim/sphere.glsl");
    const BOUNDED: bool = true;
    const UV: bool = true;

    fn check(f: &SphereFile, at: &At) -> Result<Self, SceneError> {
        Ok(Sphere {
            center: at.position("center", f.center)?,
            radius: at.length("radius", f.radius)?,
            material: at.material("material", &f.material)?,
        })
    }

    fn material(&self) -> u32 {
        self.material
    }

    fn relative_to(&self, origin: DVec3) -> Self {
        Sphere {
            center: self.center - origin,
            ..*self
        }
    }

    fn bounds(&self) -> Option<Aabb> {
        Some(Aabb {
            lo: self.center - self.radius,
            hi: self.center + self.radius,
        })
    }

    fn hull(&self) -> super::Hull {
        super::Hull::of(&[(self.center, self.radius)])
    }

    fn gpu(&self, file_index: u32) -> gpu::Values {
        let c = self.center;
        gpu::Values {
            center_radius: [c.x, c.y, c.z, self.radius],
            meta: [self.material, file_index, 0, 0],
        }
    }

    #[cfg(test)]
    fn example(material: u32) -> Self {
        Sphere {
            center: DVec3::new(0.5, -1.0, 2.0),
            radius: 0.75,
            material,
        }
    }

    fn sample(p: &mut Place) -> SphereFile {
        SphereFile {
            center: Triple(Place::triple(p.center)),
            radius: p.size,
            material: p.material.to_owned(),
        }
    }

    fn cpu<R: Real>(&self) -> SphereR<R> {
        SphereR {
            center: Vec3::of(self.center),
            radius: R::of(self.radius),
            material: self.material as usize,
        }
    }
}

impl<R: Real> Shape<R> for SphereR<R> {
    fn intersect(&self, ray: &Ray<R>, from_self: bool) -> Option<R> {
        let f = ray.origin - self.center;
        let b = f.dot(ray.dir);
        if from_self {
            let t = R::of(-2.0) * b;
            return (t > R::zero()).then_some(t);
        }
        // The discriminant from the perpendicular distance to the centre
        // rather than b² - c, which loses every digit when the sphere is
        // small against its distance (Ray Tracing Gems ch. 7).
        let l = f - ray.dir * b;
        let disc = self.radius * self.radius - l.dot(l);
        if disc < R::zero() {
            return None;
        }
        let c = power(f, self.radius);
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

    /// (p − c)/r, or the direction of p − c where p is off the surface by
    /// more than [`OFF_SURFACE`] of the radius: a ray from far away (a
    /// reflection off a sphere of radius 1e17) places its hit only to the
    /// rounding of its origin, and a normal of length 7 would shade 7^n
    /// times too bright. Mirrors sphere_normal in shaders/prim/sphere.glsl.
    fn normal(&self, p: Vec3<R>) -> Vec3<R> {
        let n = (p - self.center) / self.radius;
        if (n.dot(n) - R::one()).abs() > R::of(OFF_SURFACE) {
            n.normalize()
        } else {
            n
        }
    }

    /// Latitude and longitude (docs/scene-format.md, Textures): u runs
    /// about the y axis from 0 at −z through −x (¼), +z (½) and +x (¾),
    /// so that an image faces +z unmirrored; v from 0 at the −y pole to 1
    /// at the +y pole. glint's own atan2 and asin in f32, as the shader.
    fn uv(&self, p: Vec3<R>) -> Option<[R; 2]> {
        let n = self.normal(p);
        let half = R::of(0.5);
        let pi = R::of(std::f64::consts::PI);
        let y = n.y.max(-R::one()).min(R::one());
        Some([
            half + n.x.atan2_shader(n.z) / (pi + pi),
            half + y.asin_shader() / pi,
        ])
    }

    fn material(&self) -> usize {
        self.material
    }
}
