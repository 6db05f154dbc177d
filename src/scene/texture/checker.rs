//! The checkers: squares in a surface's own coordinates, and cubes in the
//! scene's; mirrors shaders/texture/checker.glsl.

use serde::{Deserialize, Serialize};

use super::{sample_colors, Look, Needs, PatternAt, PatternType, TextureFile, TextureR};
use crate::base::real::{Real, Vec3};
use crate::input::error::SceneError;
use crate::input::field::Triple;
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

/// A checker's keys.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CheckerFile {
    /// The side of a square, > 0.
    pub size: Option<f64>,
    /// Its two colours, the first at the origin's square.
    pub colors: Option<[Triple; 2]>,
    /// Turned by this many degrees about the normal, from the surface's u.
    pub angle: Option<f64>,
}

impl PatternType for Checker {
    const NAME: &'static str = "checker";
    const WHAT: &'static str = "a \"checker\"";
    const GLSL: &'static str = include_str!("../../../shaders/texture/checker.glsl");
    const INCLUDE: &'static str = "checker";
    type File = CheckerFile;
    const NEEDS: Needs = Needs::Frame;

    fn check(file: CheckerFile, at: &PatternAt) -> Result<Look, SceneError> {
        Ok(Look {
            size: at.size(file.size, None)?,
            colors: at.colors(file.colors)?,
            rotation: at.rotation(file.angle)?,
            ..Look::default()
        })
    }

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
        let own = CheckerFile {
            size: Some(p.size * p.uniform(0.2, 0.7)),
            colors: Some(sample_colors(p)),
            angle: Some(p.uniform(0.0, 90.0)),
        };
        TextureFile::new(Some(Self::NAME), None, &own)
    }
}

/// Cubes of side `size` in the scene's coordinates, from a corner at
/// `origin`, on any surface.
pub struct SolidChecker;

/// A solid checker's keys.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SolidCheckerFile {
    /// The side of a cube, > 0.
    pub size: Option<f64>,
    /// Its two colours, the first at the origin's cube.
    pub colors: Option<[Triple; 2]>,
    /// A corner of its cubes (default the scene's origin).
    pub origin: Option<Triple>,
}

impl PatternType for SolidChecker {
    const NAME: &'static str = "solid_checker";
    const WHAT: &'static str = "a \"solid_checker\"";
    const GLSL: &'static str = Checker::GLSL;
    const INCLUDE: &'static str = "checker";
    type File = SolidCheckerFile;
    const NEEDS: Needs = Needs::Nothing;

    fn check(file: SolidCheckerFile, at: &PatternAt) -> Result<Look, SceneError> {
        Ok(Look {
            size: at.size(file.size, None)?,
            colors: at.colors(file.colors)?,
            origin: at.origin(file.origin)?,
            ..Look::default()
        })
    }

    fn colour<R: Real>(t: &TextureR<R>, _: &[[f32; 3]], _: &dyn Shape<R>, p: Vec3<R>) -> Vec3<R> {
        let q = p - t.origin;
        pick(
            t,
            (q.x / t.size).floor() + (q.y / t.size).floor() + (q.z / t.size).floor(),
        )
    }

    fn sample(p: &mut Place) -> TextureFile {
        let corner = p.center + p.unit() * p.size;
        let own = SolidCheckerFile {
            size: Some(p.size * p.uniform(0.2, 0.7)),
            colors: Some(sample_colors(p)),
            origin: Some(Triple(Place::triple(corner))),
        };
        TextureFile::new(Some(Self::NAME), None, &own)
    }
}
