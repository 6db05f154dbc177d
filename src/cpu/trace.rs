//! The fixed-depth reflection loop (docs/scene-format.md, Shading); mirrors shaders/trace.glsl.

use super::intersect::{intersect_scene, surface};
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
        let (outward, material) = surface(w, hit.prim, p);
        let n = if outward.dot(ray.dir) > R::zero() {
            -outward
        } else {
            outward
        };
        let m = &w.materials[material];
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
