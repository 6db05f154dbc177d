//! Local Blinn-Phong shading with hard shadows (docs/scene-format.md, Shading); mirrors
//! shaders/shade.glsl.

use super::intersect::{intersect_scene, occluded};
use super::world::World;
use crate::base::ray::Ray;
use crate::base::real::{spec_pow, Real, Vec3};
use crate::base::record::Event;
use crate::base::tally::tree_word;
use crate::prim::PrimId;
use crate::scene::MaterialR;
use crate::stats::{Counter, RayType, Tally};

/// The specular term of one light: Blinn-Phong, (N·H)^n with H halfway
/// between L and V; mirrors shaders/specular.glsl.
pub fn specular<R: Real>(n: Vec3<R>, l: Vec3<R>, v: Vec3<R>, shininess: R) -> R {
    let h = (l + v).normalize();
    spec_pow(n.dot(h).max(R::zero()), shininess)
}

/// The sum of every light's contribution at `p`, where `n` faces the viewer.
pub fn shade<R: Real, T: Tally>(
    w: &World<R>,
    p: Vec3<R>,
    n: Vec3<R>,
    v: Vec3<R>,
    m: &MaterialR<R>,
    from: PrimId,
    tally: &mut T,
) -> Vec3<R> {
    let mut local = Vec3::zero();
    for (index, light) in w.lights.iter().enumerate() {
        let (l, dist, att) = light.kind.toward(light, p, n);
        let ambient = light.ambient * m.ambient;
        // A light exactly at p has no direction: it adds its ambient term only.
        if dist == R::zero() {
            local += ambient * att;
            continue;
        }
        let cone = light.kind.cone(light, p, n, l);
        let mut contribution = ambient;
        let n_dot_l = n.dot(l);
        // No shadow ray where the direct term would be zero anyway: facing
        // away, outside a light's cone, or a light without diffuse and specular.
        let direct = n_dot_l > R::zero() && cone > R::zero() && light.direct;
        // The SPD's procedure: a shadow ray only where the light is in
        // front of the surface (and here, lit at all).
        let shadowed = direct && w.shadows && {
            tally.count(Counter::Shadow);
            tally.ray_type(RayType::Shadow);
            let dir = w.moved_direction(l, p, 2 + index as u64);
            let ray = Ray { origin: p, dir };
            let blocked = occluded(w, &ray, from, dist, index, tally);
            tally.branch(tree_word::shadow(blocked));
            tally.record(|| Event::Shadow {
                light: index as u32,
                origin: p.to_dvec(),
                dir: dir.to_dvec(),
                dist: dist.to_f64(),
                blocked,
                // The nearest blocker, where the any-hit query found one.
                blocker: blocked
                    .then(|| intersect_scene(w, &ray, from, dist, &mut ()))
                    .flatten()
                    .map(|b| ((b.prim.kind, b.prim.index), b.t.to_f64())),
            });
            blocked
        };
        if direct && !shadowed {
            // A cosine: at most 1, whatever the rounding (spec_pow).
            contribution += light.diffuse * m.diffuse * n_dot_l.min(R::one())
                + light.specular * m.specular * specular(n, l, v, m.shininess);
        }
        tally.record(|| {
            let scale = att * cone;
            let lit = direct && !shadowed;
            let direct_term = |t: Vec3<R>| if lit { t * scale } else { Vec3::zero() };
            Event::Light {
                light: index as u32,
                n_dot_l: n_dot_l.to_f64(),
                cone: cone.to_f64(),
                lit,
                ambient: (ambient * scale).to_dvec(),
                diffuse: direct_term(light.diffuse * m.diffuse * n_dot_l.min(R::one())).to_dvec(),
                specular: direct_term(light.specular * m.specular * specular(n, l, v, m.shininess))
                    .to_dvec(),
            }
        });
        local += contribution * (att * cone);
    }
    tally.record(|| Event::Local {
        color: local.to_dvec(),
    });
    local
}
