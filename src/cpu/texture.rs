//! The colour of a procedural texture at a hit (docs/scene-format.md,
//! Textures); mirrors shaders/texture.glsl.

use super::world::{MaterialR, World};
use crate::base::real::{Real, Vec3};
use crate::prim::PrimId;
use crate::scene::texture::Pattern;

/// A texture in the reference's arithmetic, in camera-relative coordinates.
#[derive(Debug, Clone, Copy)]
pub struct TextureR<R> {
    pub pattern: Pattern,
    pub size: R,
    pub colors: [Vec3<R>; 2],
    /// The cosine and sine of a checker's angle.
    pub rotation: [R; 2],
    pub origin: Vec3<R>,
}

/// The colour of `t` at `p`, a point of the primitive `prim`: of the
/// square (or cube) p is in, the first colour where the cells' indices sum
/// to an even number.
pub fn texture_colour<R: Real>(w: &World<R>, t: &TextureR<R>, prim: PrimId, p: Vec3<R>) -> Vec3<R> {
    let cells = match t.pattern {
        Pattern::Checker => {
            // The scene's checks give a checker only to kinds with a frame.
            let f = w.prims.get(prim).frame().expect("a surface with a frame");
            let q = p - f.origin;
            let (a, b) = (q.dot(f.u), q.dot(f.v));
            let [c, s] = t.rotation;
            (((c * a + s * b) / t.size).floor()) + (((c * b - s * a) / t.size).floor())
        }
        Pattern::SolidChecker => {
            let q = p - t.origin;
            (q.x / t.size).floor() + (q.y / t.size).floor() + (q.z / t.size).floor()
        }
    };
    let odd = cells - R::of(2.0) * (cells * R::of(0.5)).floor() != R::zero();
    t.colors[usize::from(odd)]
}

/// `m` at the hit point `p` of `prim`: its textured colours in place of
/// its own. Mirrors apply_textures() in shaders/texture.glsl.
pub fn at_hit<R: Real>(w: &World<R>, m: &MaterialR<R>, prim: PrimId, p: Vec3<R>) -> MaterialR<R> {
    let mut m = *m;
    if let Some(t) = m.texture {
        m.diffuse = texture_colour(w, &w.textures[t], prim, p);
    }
    if let Some(t) = m.ambient_texture {
        m.ambient = if Some(t) == m.texture {
            m.diffuse
        } else {
            texture_colour(w, &w.textures[t], prim, p)
        };
    }
    m
}
