//! The fixed-depth reflection loop (docs/scene-format.md, Shading); mirrors shaders/trace.glsl.

use super::intersect::{intersect_scene, lift, surface};
use super::ray::Ray;
use super::real::{Real, Vec3};
use super::shade::shade;
use super::world::World;
use crate::prim::PrimId;

pub fn trace<R: Real>(w: &World<R>, primary: Ray<R>) -> Vec3<R> {
    let mut color = Vec3::zero();
    let mut weight = R::one();
    let mut ray = primary;
    let mut from = PrimId::NONE;
    for depth in 1..=w.max_depth {
        let Some(hit) = intersect_scene(w, &ray, from, R::infinity()) else {
            color += w.background * weight;
            break;
        };
        let p = ray.at(hit.t);
        // The geometric normal says which side the ray is on; the shading
        // normal is turned with it to face the ray.
        let s = surface(w, hit.prim, p);
        let back = s.outward.dot(ray.dir) > R::zero();
        let n = if back { -s.shading } else { s.shading };
        // Where the rays that leave on the ray's side start.
        let face = if back { -s.outward } else { s.outward };
        let p = if s.lifted {
            lift(p, ray.origin, face)
        } else {
            p
        };
        let m = &w.materials[s.material];
        color += shade(w, p, n, -ray.dir, m, hit.prim) * weight;
        if depth == w.max_depth || m.reflectivity == R::zero() {
            break;
        }
        weight = weight * m.reflectivity;
        if weight == R::zero() {
            break;
        }
        let d = ray.dir - n * (R::of(2.0) * ray.dir.dot(n));
        ray = Ray {
            origin: p,
            dir: d.normalize(),
        };
        from = hit.prim;
    }
    color
}
