//! The ray tree to a fixed depth (docs/scene-format.md, Shading); mirrors
//! shaders/trace.glsl, in the same order: the reflection ray is followed at
//! once, and refraction rays wait on a stack, the most recent first.

use super::intersect::{intersect_eye, intersect_scene, lift, surface};
use super::shade::shade;
use super::texture::at_hit;
use super::world::World;
use crate::base::aov::EyeHit;
use crate::base::ray::Ray;
use crate::base::real::{Real, Vec3};
use crate::base::record::Event;
use crate::base::tally::tree_word;
use crate::prim::PrimId;
use crate::stats::{Counter, RayType, Tally};

/// A refraction ray waiting to be traced.
struct Branch<R> {
    ray: Ray<R>,
    from: PrimId,
    depth: u32,
    weight: R,
}

/// The direction of the ray refracted at a surface with unit normal `n`
/// facing the incoming unit direction `d`, for eta = n_incoming /
/// n_outgoing; None under total internal reflection. eta 1 passes `d`
/// through unchanged.
pub fn refract<R: Real>(d: Vec3<R>, n: Vec3<R>, eta: R) -> Option<Vec3<R>> {
    if eta == R::one() {
        return Some(d);
    }
    let cos_i = -d.dot(n);
    let k = R::one() - eta * eta * (R::one() - cos_i * cos_i);
    if k < R::zero() {
        return None;
    }
    Some((d * eta + n * (eta * cos_i - k.sqrt())).normalize())
}

/// The colour the eye ray `primary` brings back; `tally` counts its tree.
pub fn trace<R: Real, T: Tally>(w: &World<R>, primary: Ray<R>, tally: &mut T) -> Vec3<R> {
    tally.count(Counter::Eye);
    let mut color = Vec3::zero();
    let mut weight = R::one();
    let mut ray = primary;
    let mut from = PrimId::NONE;
    let mut depth = 1;
    let mut ray_type = RayType::Eye;
    let mut stack: Vec<Branch<R>> = Vec::new();
    loop {
        // Whether this path goes on with the reflection ray.
        let mut follow = false;
        tally.ray_type(ray_type);
        tally.record(|| Event::Ray {
            kind: ray_type,
            depth,
            from: from.recorded(),
            origin: ray.origin.to_dvec(),
            dir: ray.dir.to_dvec(),
            weight: weight.to_f64(),
        });
        // An eye ray reads its tile's list where the scene has them.
        let met = if depth == 1 {
            intersect_eye(w, &ray, tally)
        } else {
            intersect_scene(w, &ray, from, R::infinity(), tally)
        };
        match met {
            None => {
                color += w.background * weight;
                tally.branch(tree_word::MISS);
                tally.record(|| Event::Miss {
                    color: (w.background * weight).to_dvec(),
                });
            }
            Some(hit) => {
                if depth == 1 {
                    tally.count(Counter::EyeHit);
                }
                let p = w.moved_point(ray.at(hit.t));
                // The geometric normal says which side the ray is on; the
                // shading normal is turned with it to face the ray.
                let s = surface(w, hit.prim, p);
                let back = s.outward.dot(ray.dir) > R::zero();
                let n = if back { -s.shading } else { s.shading };
                let face = if back { -s.outward } else { s.outward };
                // Where the rays that leave on a side start.
                let leave = |side: Vec3<R>| {
                    if s.lifted {
                        lift(p, ray.origin, side)
                    } else {
                        p
                    }
                };
                let above = leave(face);
                let textured;
                let mut m = &w.materials[s.material];
                if m.texture.is_some() || m.ambient_texture.is_some() {
                    textured = at_hit(w, m, hit.prim, p);
                    m = &textured;
                }
                tally.branch(tree_word::hit(s.material as u32));
                tally.record(|| Event::Hit {
                    prim: (hit.prim.kind, hit.prim.index),
                    material: s.material as u32,
                    t: hit.t.to_f64(),
                    point: p.to_dvec(),
                    normal: s.outward.to_dvec(),
                    shading: s.shading.to_dvec(),
                    uv: (!w.texels.is_empty())
                        .then(|| w.prims.get(hit.prim).uv(p))
                        .flatten()
                        .map(|[u, v]| glam::DVec2::new(u.to_f64(), v.to_f64())),
                });
                if depth == 1 {
                    tally.eye_hit(|| EyeHit {
                        depth: hit.t.to_f64(),
                        normal: n.to_dvec().to_array(),
                        albedo: m.diffuse.to_dvec().to_array(),
                        prim: (hit.prim.kind, hit.prim.index),
                    });
                }
                color += shade(w, above, n, -ray.dir, m, hit.prim, tally) * weight;
                let mut kr = m.reflectivity;
                let kt = m.transmittance;
                // The SPD's procedure spawns a ray wherever the surface
                // reflects or transmits, whatever the weight, and a
                // reflection ray at a transmitter too.
                let spd_reflects = w.spd_rays && (kr != R::zero() || kt > R::zero());
                if depth < w.max_depth && kt > R::zero() {
                    // Entering where the ray meets the outward side: eta = 1/ior.
                    let eta = if back { m.ior } else { R::one() / m.ior };
                    match refract(ray.dir, n, eta) {
                        None => kr += kt,
                        Some(t) if w.spd_rays || weight * kt != R::zero() => {
                            tally.count(Counter::Refract);
                            stack.push(Branch {
                                ray: Ray {
                                    origin: leave(-face),
                                    dir: w.moved_direction(t, p, 1),
                                },
                                from: hit.prim,
                                depth: depth + 1,
                                weight: weight * kt,
                            });
                        }
                        Some(_) => {}
                    }
                }
                follow = depth < w.max_depth
                    && (kr != R::zero() && weight * kr != R::zero() || spd_reflects);
                tally.record(|| Event::Branch {
                    kr: kr.to_f64(),
                    kt: kt.to_f64(),
                    follow,
                });
                if follow {
                    tally.count(Counter::Reflect);
                    weight = weight * kr;
                    let d = ray.dir - n * (R::of(2.0) * ray.dir.dot(n));
                    ray = Ray {
                        origin: above,
                        dir: w.moved_direction(d.normalize(), p, 0),
                    };
                    from = hit.prim;
                    depth += 1;
                    ray_type = RayType::Reflect;
                }
            }
        }
        if !follow {
            let Some(b) = stack.pop() else {
                break;
            };
            (ray, from, depth, weight) = (b.ray, b.from, b.depth, b.weight);
            ray_type = RayType::Refract;
        }
    }
    tally.record(|| Event::End {
        color: color.to_dvec(),
    });
    color
}
