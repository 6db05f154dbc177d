//! The triangle's intersect is watertight: rays through shared edges and
//! vertices of a closed mesh never leak, where the textbook test does; its
//! interpolated normals are the vertex normals at the vertices.

use glam::DVec3;

use super::{Triangle, TriangleR};
use crate::base::ray::Ray;
use crate::base::real::{Real, Vec3};
use crate::prim::{Kind, Shape};
use crate::rng::Xorshift;

/// The unit octahedron, closed: every edge is shared by two faces.
fn octahedron() -> Vec<Triangle> {
    let v = [
        DVec3::X,
        DVec3::NEG_X,
        DVec3::Y,
        DVec3::NEG_Y,
        DVec3::Z,
        DVec3::NEG_Z,
    ];
    let faces = [
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    faces
        .iter()
        .map(|f| Triangle::new(f.map(|i| v[i]), None, 0).unwrap())
        .collect()
}

/// Rays from inside the octahedron aimed exactly at its edges (at points
/// along them) and at its vertices: each must leave through some face.
fn rays_at_edges_and_vertices<R: Real>(n: usize) -> Vec<Ray<R>> {
    let tris = octahedron();
    let mut rng = Xorshift(0x9e37_79b9_7f4a_7c15);
    let mut rays = Vec::new();
    for _ in 0..n {
        for t in &tris {
            for (a, b) in [(0, 1), (1, 2), (2, 0)] {
                let (a, b) = (t.vertices[a], t.vertices[b]);
                for target in [a, a + (b - a) * rng.next()] {
                    let origin = DVec3::new(rng.next(), rng.next(), rng.next()) * 0.6 - 0.3;
                    let origin = Vec3::of(origin);
                    let dir = (Vec3::of(target) - origin).normalize();
                    rays.push(Ray { origin, dir });
                }
            }
        }
    }
    rays
}

fn leaks<R: Real>(hit: impl Fn(&TriangleR<R>, &Ray<R>) -> bool) -> usize {
    let tris: Vec<TriangleR<R>> = octahedron().iter().map(|t| t.cpu()).collect();
    rays_at_edges_and_vertices::<R>(400)
        .iter()
        .filter(|r| !tris.iter().any(|t| hit(t, r)))
        .count()
}

#[test]
fn rays_through_shared_edges_and_vertices_never_leak() {
    assert_eq!(leaks::<f32>(|t, r| t.intersect(r, false).is_some()), 0);
    assert_eq!(leaks::<f64>(|t, r| t.intersect(r, false).is_some()), 0);
}

/// The check above can fail: the textbook Möller–Trumbore test, which
/// computes each edge test from barycentric coordinates of its own, lets
/// some of the same rays through in f32.
#[test]
fn a_test_that_is_not_watertight_leaks_on_the_same_rays() {
    let moller_trumbore = |t: &TriangleR<f32>, r: &Ray<f32>| {
        let [v0, v1, v2] = t.vertices;
        let (e1, e2) = (v1 - v0, v2 - v0);
        let p = r.dir.cross(e2);
        let det = e1.dot(p);
        if det == 0.0 {
            return false;
        }
        let tv = r.origin - v0;
        let u = tv.dot(p) / det;
        let q = tv.cross(e1);
        let v = r.dir.dot(q) / det;
        u >= 0.0 && v >= 0.0 && u + v <= 1.0 && e2.dot(q) / det > 0.0
    };
    assert!(leaks::<f32>(moller_trumbore) > 0);
}

#[test]
fn interpolated_normals_are_the_vertex_normals_at_the_vertices() {
    let normals = [
        DVec3::new(0.0, 0.0, 1.0),
        DVec3::new(1.0, 0.0, 1.0).normalize(),
        DVec3::new(0.0, 1.0, 1.0).normalize(),
    ];
    let vertices = [DVec3::ZERO, DVec3::X, DVec3::Y];
    let t: TriangleR<f64> = Triangle::new(vertices, Some(normals), 0).unwrap().cpu();
    for (v, n) in vertices.iter().zip(normals) {
        let s = t.shading(Vec3::of(*v), t.normal(Vec3::of(*v)));
        assert!(
            (DVec3::new(s.x, s.y, s.z) - n).length() < 1e-12,
            "{s:?} {n}"
        );
    }
    // Halfway along the first edge: the normalised mean of its ends.
    let s = t.shading(Vec3::new(0.5, 0.0, 0.0), t.normal(Vec3::zero()));
    let want = (normals[0] + normals[1]).normalize();
    assert!((DVec3::new(s.x, s.y, s.z) - want).length() < 1e-12);
}
