//! The checkers: squares in a surface's own coordinates, and cubes in the
//! scene's; mirrors shaders/texture/checker.glsl.

use super::{sample_colors, Needs, PatternType, TextureFile, TextureR};
use crate::base::real::{Real, Vec3};
use crate::prim::Shape;
use crate::rng::Place;

/// The first colour where the cells' indices sum to an even number.
fn pick<R: Real>(t: &TextureR<R>, cells: R) -> Vec3<R> {
    let odd = cells - R::of(2.0) * (cells * R::of(0.5)).floor() != R::zero();
    t.colors[usize::from(odd)]
}

/// Squares of side `size` in the surface's own coordinates, turned by the
/// angle.
pub struct Checker;

impl PatternType for Checker {
    const NAME: &'static str = "checker";
    const WHAT: &'static str = "a \"checker\"";
    const GLSL: &'static str = include_str!("../../../shaders/texture/checker.glsl");
    const INCLUDE: &'static str = "checker";
    const KEYS: &'static [&'static str] = &["size", "colors", "angle"];
    const NEEDS: Needs = Needs::Frame;

    fn colour<R: Real>(
        t: &TextureR<R>,
        _: &[[f32; 3]],
        surface: &dyn Shape<R>,
        p: Vec3<R>,
    ) -> Vec3<R> {
        // The scene's checks give it only to kinds with a frame.
        let f = surface.frame().expect("a surface with a frame");
        let q = p - f.origin;
        let (a, b) = (q.dot(f.u), q.dot(f.v));
        let [c, s] = t.rotation;
        pick(
            t,
            ((c * a + s * b) / t.size).floor() + ((c * b - s * a) / t.size).floor(),
        )
    }

    fn sample(p: &mut Place) -> TextureFile {
        TextureFile {
            pattern: Some(Self::NAME.to_owned()),
            size: Some(p.size * p.uniform(0.2, 0.7)),
            colors: Some(sample_colors(p)),
            angle: Some(p.uniform(0.0, 90.0)),
            ..TextureFile::default()
        }
    }
}

/// Cubes of side `size` in the scene's coordinates, from a corner at
/// `origin`, on any surface.
pub struct SolidChecker;

impl PatternType for SolidChecker {
    const NAME: &'static str = "solid_checker";
    const WHAT: &'static str = "a \"solid_checker\"";
    const GLSL: &'static str = Checker::GLSL;
    const INCLUDE: &'static str = "checker";
    const KEYS: &'static [&'static str] = &["size", "colors", "origin"];
    const NEEDS: Needs = Needs::Nothing;

    fn colour<R: Real>(t: &TextureR<R>, _: &[[f32; 3]], _: &dyn Shape<R>, p: Vec3<R>) -> Vec3<R> {
        let q = p - t.origin;
        pick(
            t,
            (q.x / t.size).floor() + (q.y / t.size).floor() + (q.z / t.size).floor(),
        )
    }

    fn sample(p: &mut Place) -> TextureFile {
        let corner = p.center + p.unit() * p.size;
        TextureFile {
            pattern: Some(Self::NAME.to_owned()),
            size: Some(p.size * p.uniform(0.2, 0.7)),
            colors: Some(sample_colors(p)),
            origin: Some(crate::input::field::Triple(Place::triple(corner))),
            ..TextureFile::default()
        }
    }
}
