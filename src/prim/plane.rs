//! The plane: its scene-file table, checks and GPU struct, and the CPU
//! reference's intersect and normal; mirrors shaders/prim/plane.glsl.
//! Unbounded, so never in the BVH: every ray scans the planes.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::{Frame, Kind, Shape};
use crate::base::aabb::Aabb;
use crate::base::ray::Ray;
use crate::base::real::{Real, Vec3};
use crate::input::error::SceneError;
use crate::input::field::{At, Triple};
use crate::rng::Place;

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PlaneFile {
    pub point: Triple,
    pub normal: Triple,
    pub material: String,
}

/// An infinite plane: the points p with (p − point) · normal = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    /// A point on it.
    pub point: DVec3,
    /// Unit length.
    pub normal: DVec3,
    /// Where its own coordinates (`Shape::frame`) start: the file's point,
    /// moved with the plane. `point` is not: a camera-relative plane takes
    /// its point nearest the eye, and a texture must not move with the eye.
    pub origin: DVec3,
    /// The index of its material in `Scene::materials`.
    pub material: u32,
}

crate::base::interface::gpu_struct!(
    /// The plane in the shader's buffers.
    pub mod gpu: "Plane" {
        /// xyz
        point: real4,
        /// xyz, unit length
        normal: real4,
        /// xyz where its own coordinates start (`Plane::origin`)
        origin: real4,
        /// x material, y index in the scene file
        meta: uvec4,
    }
);

pub struct PlaneR<R> {
    pub point: Vec3<R>,
    pub normal: Vec3<R>,
    pub origin: Vec3<R>,
    pub material: usize,
}

impl Kind for Plane {
    type File = PlaneFile;
    type Gpu = gpu::Values;
    type Cpu<R: Real> = PlaneR<R>;
    const NAME: &'static str = "plane";
    const GLSL: &'static str = include_str!("../../shaders/prim/plane.glsl");
    const BOUNDED: bool = false;
    const SHADING_ONLY: &'static [&'static str] = &["origin"];
    const FRAME: bool = true;
    const UV: bool = true;

    fn check(f: &PlaneFile, at: &At) -> Result<Self, SceneError> {
        let point = at.position("point", f.point)?;
        Ok(Plane {
            point,
            normal: at.direction("normal", f.normal)?,
            origin: point,
            material: at.material("material", &f.material)?,
        })
    }

    fn material(&self) -> u32 {
        self.material
    }

    fn relative_to(&self, origin: DVec3) -> Self {
        // The plane's point nearest the new origin: as small as a point of
        // the plane can be, whatever point the file gave.
        Plane {
            point: self.normal * (self.point - origin).dot(self.normal),
            origin: self.origin - origin,
            ..*self
        }
    }

    fn bounds(&self) -> Option<Aabb> {
        None
    }

    fn gpu(&self, file_index: u32) -> gpu::Values {
        let (p, n, o) = (self.point, self.normal, self.origin);
        gpu::Values {
            point: [p.x, p.y, p.z, 0.0],
            normal: [n.x, n.y, n.z, 0.0],
            origin: [o.x, o.y, o.z, 0.0],
            meta: [self.material, file_index, 0, 0],
        }
    }

    #[cfg(test)]
    fn example(material: u32) -> Self {
        Plane {
            point: DVec3::new(0.0, -1.0, 0.0),
            normal: DVec3::Y,
            origin: DVec3::new(0.5, -1.0, 0.25),
            material,
        }
    }

    /// A floor through the place, below its centre, tilted at random.
    fn sample(p: &mut Place) -> PlaneFile {
        let normal = p.upward();
        PlaneFile {
            point: Triple(Place::triple(p.center - normal * p.size)),
            normal: Triple(Place::triple(normal)),
            material: p.material.to_owned(),
        }
    }

    fn cpu<R: Real>(&self) -> PlaneR<R> {
        PlaneR {
            point: Vec3::of(self.point),
            normal: Vec3::of(self.normal),
            origin: Vec3::of(self.origin),
            material: self.material as usize,
        }
    }
}

impl<R: Real> Shape<R> for PlaneR<R> {
    fn intersect(&self, ray: &Ray<R>, from_self: bool) -> Option<R> {
        if from_self {
            return None;
        }
        let denom = ray.dir.dot(self.normal);
        if denom == R::zero() {
            return None;
        }
        let t = (self.point - ray.origin).dot(self.normal) / denom;
        (t > R::zero()).then_some(t)
    }

    fn normal(&self, _p: Vec3<R>) -> Vec3<R> {
        self.normal
    }

    /// From its origin (the file's point): u = normalize(a × n), with a the coordinate axis
    /// least along n (x, then y, on a tie), and v = n × u.
    fn frame(&self) -> Option<Frame<R>> {
        let n = self.normal;
        let m = Vec3::new(n.x.abs(), n.y.abs(), n.z.abs());
        let (zero, one) = (R::zero(), R::one());
        let a = if m.x <= m.y && m.x <= m.z {
            Vec3::new(one, zero, zero)
        } else if m.y <= m.z {
            Vec3::new(zero, one, zero)
        } else {
            Vec3::new(zero, zero, one)
        };
        let u = a.cross(n).normalize();
        Some(Frame {
            origin: self.origin,
            u,
            v: n.cross(u),
        })
    }

    /// Its own coordinates (`frame`) as uv.
    fn uv(&self, p: Vec3<R>) -> Option<[R; 2]> {
        let f = self.frame()?;
        let q = p - f.origin;
        Some([q.dot(f.u), q.dot(f.v)])
    }

    fn material(&self) -> usize {
        self.material
    }
}
