//! A material's textured colours at a hit (docs/scene-format.md,
//! Textures); mirrors apply_textures() in shaders/texture.glsl. Each
//! pattern's colour is its own (`crate::scene::texture`).

use super::world::World;
use crate::base::real::{Real, Vec3};
use crate::prim::PrimId;
use crate::scene::MaterialR;

/// The colour of texture `t` at `p`, a point of the primitive `prim`.
fn texture_colour<R: Real>(w: &World<R>, t: usize, prim: PrimId, p: Vec3<R>) -> Vec3<R> {
    let t = &w.textures[t];
    t.pattern.colour(t, &w.texels, w.prims.get(prim), p)
}

/// `m` at the hit point `p` of `prim`: its textured colours in place of
/// its own.
pub fn at_hit<R: Real>(w: &World<R>, m: &MaterialR<R>, prim: PrimId, p: Vec3<R>) -> MaterialR<R> {
    let mut m = *m;
    if let Some(t) = m.texture {
        m.diffuse = texture_colour(w, t, prim, p);
    }
    if let Some(t) = m.ambient_texture {
        m.ambient = if Some(t) == m.texture {
            m.diffuse
        } else {
            texture_colour(w, t, prim, p)
        };
    }
    m
}
