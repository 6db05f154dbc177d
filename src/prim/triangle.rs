//! The triangle: its scene-file table, checks, GPU struct and bounds, and the
//! CPU reference's intersect and normals; mirrors shaders/prim/triangle.glsl.
//! Meshes (`crate::prim::mesh`) load into triangles.
//!
//! Two-sided, like the plane. The intersection is watertight (Woop, Benthin
//! and Wald, "Watertight Ray/Triangle Intersection", JCGT 2013): the ray is
//! sheared onto +z and each edge function is computed from the edge's two
//! projected vertices alone, so two triangles that share an edge compute it
//! with the same products and opposite signs, and a ray through the edge
//! cannot pass between them. A zero edge function counts as inside: a ray
//! exactly through a shared edge or vertex meets each triangle there at the
//! same t, and the nearest hit is the earlier one (the tie rule).

use std::sync::Arc;

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::{Frame, Kind, Shape};
use crate::base::aabb::Aabb;
use crate::base::ray::Ray;
use crate::base::real::{Real, Vec3};
use crate::input::error::SceneError;
use crate::input::field::{unit_vector, At, Triple};
use crate::rng::Place;

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TriangleFile {
    pub vertices: [Triple; 3],
    /// Vertex normals for smooth shading; the geometric normal without.
    #[serde(default)]
    pub normals: Option<[Triple; 3]>,
    /// Texture coordinates at the vertices, for image textures.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uvs: Option<[[f64; 2]; 3]>,
    pub material: String,
}

/// A triangle's texture coordinates, a (u, v) pair at each vertex.
pub type Uvs = [[f64; 2]; 3];

/// The largest uv coordinate, in magnitude: a larger one repeats an image
/// more often than f32 can place a texel of it.
pub const MAX_UV: f64 = 1e6;

/// A triangle, flat or with vertex normals (smooth); a mesh is its
/// triangles placed. Not `Copy`: its vertex normals and uvs are shared, not
/// held inline, so that a triangle without them is 8 bytes larger for
/// each, not 80 and 56 (a flat million-face mesh is 120 MB, not 192; issue
/// 31).
#[derive(Debug, Clone, PartialEq)]
pub struct Triangle {
    /// Its corners, counter-clockwise seen from the side its normal faces.
    pub vertices: [DVec3; 3],
    /// normalize((v1 − v0) × (v2 − v0)), from the file's coordinates (a
    /// camera-relative rebase leaves it as it is).
    pub normal: DVec3,
    /// Unit vertex normals, where the triangle is smooth.
    pub normals: Option<Arc<[DVec3; 3]>>,
    /// Texture coordinates at the vertices, where it has them.
    pub uvs: Option<Arc<Uvs>>,
    /// The index of its material in `Scene::materials`.
    pub material: u32,
}

impl Triangle {
    /// The triangle through `vertices`, or None where they span no area.
    pub fn new(vertices: [DVec3; 3], normals: Option<[DVec3; 3]>, material: u32) -> Option<Self> {
        let [a, b, c] = vertices;
        unit_vector((b - a).cross(c - a)).map(|normal| Triangle {
            vertices,
            normal,
            normals: normals.map(Arc::new),
            uvs: None,
            material,
        })
    }
}

crate::base::interface::gpu_struct!(
    /// The triangle in the shader's buffers.
    pub mod gpu: "Triangle" {
        /// xyz the first vertex, w the geometric normal's x
        v0: real4,
        /// xyz the second vertex, w the geometric normal's y
        v1: real4,
        /// xyz the third vertex, w the geometric normal's z
        v2: real4,
        /// xyz the vertex normals (zero where the triangle is flat)
        n0: real4,
        n1: real4,
        n2: real4,
        /// x material, y index in the scene file, z 1 where smooth, w 1
        /// where it has uvs (the TriangleUvs block's entry y)
        meta: uvec4,
    }
);

crate::base::interface::gpu_struct!(
    /// A triangle's texture coordinates, in the shader's TriangleUvs block,
    /// by the triangle's index in the scene file (its `meta.y`).
    pub mod uvs: "TriangleUv" {
        /// xy the first vertex's uv, zw the second's
        uv01: real4,
        /// xy the third vertex's uv
        uv2: real4,
    }
);

pub struct TriangleR<R> {
    pub vertices: [Vec3<R>; 3],
    pub normal: Vec3<R>,
    /// Boxed, as the uvs: a flat triangle holds 8 bytes for them, not 80.
    pub normals: Option<Box<[Vec3<R>; 3]>>,
    /// Boxed: the reference holds a million triangles without uvs at 8
    /// bytes more each, not 56.
    pub uvs: Option<Box<[[R; 2]; 3]>>,
    pub material: usize,
}

impl Kind for Triangle {
    type File = TriangleFile;
    type Gpu = gpu::Values;
    type Cpu<R: Real> = TriangleR<R>;
    const NAME: &'static str = "triangle";
    const GLSL: &'static str = include_str!("../../shaders/prim/triangle.glsl");
    const BOUNDED: bool = true;
    const SHADING: bool = true;
    const SHADING_ONLY: &'static [&'static str] = &["n0", "n1", "n2"];
    const LIFT: bool = true;
    const FRAME: bool = true;
    const UV: bool = true;

    fn check(f: &TriangleFile, at: &At) -> Result<Self, SceneError> {
        let mut vertices = [DVec3::ZERO; 3];
        for (i, v) in f.vertices.iter().enumerate() {
            vertices[i] = at.element("vertices", i).position_here(*v)?;
        }
        let normals = match &f.normals {
            Some(ns) => {
                let mut out = [DVec3::ZERO; 3];
                for (i, n) in ns.iter().enumerate() {
                    out[i] = at.element("normals", i).direction_here(*n)?;
                }
                Some(out)
            }
            None => None,
        };
        let uvs = match f.uvs {
            Some(uvs) => {
                for (i, uv) in uvs.iter().enumerate() {
                    if uv.iter().any(|c| !c.is_finite() || c.abs() > MAX_UV) {
                        return at.element("uvs", i).invalid_here(format!(
                            "[{}, {}] is not finite or beyond ±{MAX_UV:e}",
                            uv[0], uv[1]
                        ));
                    }
                }
                Some(uvs)
            }
            None => None,
        };
        let material = at.material("material", &f.material)?;
        match Triangle::new(vertices, normals, material) {
            Some(t) => Ok(Triangle {
                uvs: uvs.map(Arc::new),
                ..t
            }),
            None => at.invalid(
                "vertices",
                "the three vertices lie on one line: the triangle has no area",
            ),
        }
    }

    fn material(&self) -> u32 {
        self.material
    }

    fn has_uv(&self) -> bool {
        self.uvs.is_some()
    }

    fn relative_to(&self, origin: DVec3) -> Self {
        Triangle {
            vertices: self.vertices.map(|v| v - origin),
            ..self.clone()
        }
    }

    fn bounds(&self) -> Option<Aabb> {
        let [a, b, c] = self.vertices;
        Some(Aabb {
            lo: a.min(b).min(c),
            hi: a.max(b).max(c),
        })
    }

    fn hull(&self) -> super::Hull {
        super::Hull::of(&self.vertices.map(|v| (v, 0.0)))
    }

    fn gpu(&self, file_index: u32) -> gpu::Values {
        let [a, b, c] = self.vertices;
        let g = self.normal;
        let [n0, n1, n2] = self.normals.as_deref().copied().unwrap_or([DVec3::ZERO; 3]);
        let four = |v: DVec3, w: f64| [v.x, v.y, v.z, w];
        gpu::Values {
            v0: four(a, g.x),
            v1: four(b, g.y),
            v2: four(c, g.z),
            n0: four(n0, 0.0),
            n1: four(n1, 0.0),
            n2: four(n2, 0.0),
            meta: [
                self.material,
                file_index,
                u32::from(self.normals.is_some()),
                u32::from(self.uvs.is_some()),
            ],
        }
    }

    #[cfg(test)]
    fn example(material: u32) -> Self {
        let vertices = [
            DVec3::new(-1.0, -0.5, 1.0),
            DVec3::new(1.5, -0.25, 1.5),
            DVec3::new(0.0, 1.0, 2.0),
        ];
        Triangle::new(vertices, None, material).expect("a triangle with area")
    }

    /// An equilateral triangle turned at random, with uvs (so that an
    /// image texture has something to read) and, half the time, vertex
    /// normals leaning out of its plane.
    fn sample(p: &mut Place) -> TriangleFile {
        let normal = p.unit();
        let (u, v) = Place::frame(normal);
        let turn = p.uniform(0.0, std::f64::consts::TAU);
        let corner = |k: f64| {
            let a = turn + k * std::f64::consts::TAU / 3.0;
            p.center + (u * a.cos() + v * a.sin()) * p.size
        };
        let vertices = [0.0, 1.0, 2.0].map(|k| Triple(Place::triple(corner(k))));
        let normals = (p.pick(2) == 1).then(|| {
            [0, 1, 2].map(|_| {
                let lean = p.unit() * 0.3;
                Triple(Place::triple((normal + lean).normalize()))
            })
        });
        TriangleFile {
            vertices,
            normals,
            uvs: Some([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]),
            material: p.material.to_owned(),
        }
    }

    fn cpu<R: Real>(&self) -> TriangleR<R> {
        TriangleR {
            vertices: self.vertices.map(Vec3::of),
            normal: Vec3::of(self.normal),
            normals: self.normals.as_deref().map(|ns| Box::new(ns.map(Vec3::of))),
            uvs: self
                .uvs
                .as_ref()
                .map(|uvs| Box::new(uvs.map(|uv| uv.map(R::of)))),
            material: self.material as usize,
        }
    }
}

impl<R: Real> TriangleR<R> {
    /// The barycentric coordinates of `p`, a point in its plane: the
    /// weights of its three vertices.
    pub fn barycentric(&self, p: Vec3<R>) -> [R; 3] {
        let [v0, v1, v2] = self.vertices;
        let (e1, e2, q) = (v1 - v0, v2 - v0, p - v0);
        let c = e1.cross(e2);
        let inv = R::one() / c.dot(c);
        let b1 = q.cross(e2).dot(c) * inv;
        let b2 = e1.cross(q).dot(c) * inv;
        [R::one() - b1 - b2, b1, b2]
    }
}

/// `v` with its axes turned so that `kz` (the ray's dominant axis) comes
/// last, and x and y swapped where the ray runs down that axis (so that the
/// shear keeps the triangle's winding).
fn permute<R: Real>(v: Vec3<R>, kz: usize, swap: bool) -> Vec3<R> {
    let p = match kz {
        0 => Vec3::new(v.y, v.z, v.x),
        1 => Vec3::new(v.z, v.x, v.y),
        _ => v,
    };
    if swap {
        Vec3::new(p.y, p.x, p.z)
    } else {
        p
    }
}

impl<R: Real> Shape<R> for TriangleR<R> {
    /// From its first vertex: u along the edge to the second, v = n × u.
    fn frame(&self) -> Option<Frame<R>> {
        let [v0, v1, _] = self.vertices;
        let u = (v1 - v0).normalize();
        Some(Frame {
            origin: v0,
            u,
            v: self.normal.cross(u),
        })
    }

    fn intersect(&self, ray: &Ray<R>, from_self: bool) -> Option<R> {
        // Flat: a ray that leaves a triangle cannot meet it again.
        if from_self {
            return None;
        }
        let d = ray.dir;
        let ad = Vec3::new(d.x.abs(), d.y.abs(), d.z.abs());
        let kz = if ad.x > ad.y {
            if ad.x > ad.z {
                0
            } else {
                2
            }
        } else if ad.y > ad.z {
            1
        } else {
            2
        };
        let dz = permute(d, kz, false).z;
        let swap = dz < R::zero();
        let d = permute(d, kz, swap);
        let sx = d.x / d.z;
        let sy = d.y / d.z;
        let sz = R::one() / d.z;
        let [a, b, c] = self.vertices.map(|v| permute(v - ray.origin, kz, swap));
        let (ax, ay) = (a.x - sx * a.z, a.y - sy * a.z);
        let (bx, by) = (b.x - sx * b.z, b.y - sy * b.z);
        let (cx, cy) = (c.x - sx * c.z, c.y - sy * c.z);
        let u = cx * by - cy * bx;
        let v = ax * cy - ay * cx;
        let w = bx * ay - by * ax;
        let zero = R::zero();
        if (u < zero || v < zero || w < zero) && (u > zero || v > zero || w > zero) {
            return None;
        }
        let det = u + v + w;
        if det == zero {
            return None;
        }
        let t = (u * (sz * a.z) + v * (sz * b.z) + w * (sz * c.z)) / det;
        (t > zero).then_some(t)
    }

    fn normal(&self, _p: Vec3<R>) -> Vec3<R> {
        self.normal
    }

    /// The vertex normals interpolated at `p` by its barycentric
    /// coordinates, normalised; the geometric normal where the triangle is flat.
    fn shading(&self, p: Vec3<R>, geometric: Vec3<R>) -> Vec3<R> {
        let Some(&[n0, n1, n2]) = self.normals.as_deref() else {
            return geometric;
        };
        let [b0, b1, b2] = self.barycentric(p);
        (n0 * b0 + n1 * b1 + n2 * b2).normalize()
    }

    /// The vertices' uvs interpolated at `p` by its barycentric coordinates.
    fn uv(&self, p: Vec3<R>) -> Option<[R; 2]> {
        let [t0, t1, t2] = *self.uvs.as_deref()?;
        let [b0, b1, b2] = self.barycentric(p);
        Some([0, 1].map(|i| t0[i] * b0 + t1[i] * b1 + t2[i] * b2))
    }

    fn material(&self) -> usize {
        self.material
    }
}

#[cfg(test)]
#[path = "triangle_tests.rs"]
mod intersect_tests;
