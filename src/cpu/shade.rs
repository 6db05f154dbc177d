//! Local Blinn-Phong shading with hard shadows (docs/scene-format.md, Shading); mirrors
//! shaders/shade.glsl.

use crate::scene::LightKind;

use super::intersect::occluded;
use super::world::{MaterialR, World};
use crate::base::ray::Ray;
use crate::base::real::{Real, Vec3};
use crate::prim::PrimId;
use crate::stats::{Counter, RayType, Tally};

/// x^n with the scene format's conventions: x^0 = 1 (also for x = 0), and 0 for x <= 0
/// otherwise; GLSL's pow leaves both undefined. x is a cosine, taken at
/// most 1: the rounding of unit vectors can put their dot product an ulp
/// past it, and a large n would raise that past the shading's bound.
pub fn spec_pow<R: Real>(x: R, n: R) -> R {
    if n == R::zero() {
        R::one()
    } else if x <= R::zero() {
        R::zero()
    } else {
        x.min(R::one()).powf(n)
    }
}

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
        let (l, dist, att) = match light.kind {
            LightKind::Directional => (-light.direction, R::infinity(), R::one()),
            LightKind::Point | LightKind::Spot => {
                let to_light = light.position - p;
                let dist = to_light.length();
                let a = light.attenuation;
                let att = (a.x + a.y * dist + a.z * dist * dist).recip();
                (to_light / dist, dist, att)
            }
        };
        let ambient = light.ambient * m.ambient;
        // A light exactly at p has no direction: it adds its ambient term only.
        if dist == R::zero() {
            local += ambient * att;
            continue;
        }
        let spot = match light.kind {
            LightKind::Spot => {
                let cos_theta = (-l).dot(light.direction);
                if cos_theta >= light.cos_cutoff {
                    spec_pow(cos_theta, light.exponent)
                } else {
                    R::zero()
                }
            }
            _ => R::one(),
        };
        let mut contribution = ambient;
        let n_dot_l = n.dot(l);
        // No shadow ray where the direct term would be zero anyway: facing
        // away, outside a spot's cone, or a light without diffuse and specular.
        let direct = n_dot_l > R::zero() && spot > R::zero() && light.direct;
        // The SPD's procedure: a shadow ray only where the light is in
        // front of the surface (and here, lit at all).
        let shadowed = direct && w.shadows && {
            tally.count(Counter::Shadow);
            tally.ray_type(RayType::Shadow);
            let dir = w.moved_direction(l, p, 2 + index as u64);
            occluded(w, &Ray { origin: p, dir }, from, dist, index, tally)
        };
        if direct && !shadowed {
            // A cosine: at most 1, whatever the rounding (spec_pow).
            contribution += light.diffuse * m.diffuse * n_dot_l.min(R::one())
                + light.specular * m.specular * specular(n, l, v, m.shininess);
        }
        local += contribution * (att * spot);
    }
    local
}
