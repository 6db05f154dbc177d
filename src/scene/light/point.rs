//! A point light: from a position, in every direction, attenuated with
//! distance; mirrors shaders/light/point.glsl.

use serde::{Deserialize, Serialize};

use super::{Light, LightAt, LightR, LightType, Placement, Toward};
use crate::base::real::{Real, Vec3};
use crate::input::error::SceneError;
use crate::input::field::Triple;
use crate::rng::Place;

pub struct Point;

/// A point light's keys.
#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PointFile {
    /// Where it is.
    pub position: Option<Triple>,
    /// [c, l, q]: 1 / (c + l d + q d²) (default [1, 0, 0]).
    pub attenuation: Option<Triple>,
}

/// Its own numbers (`Light::own`): c, l and q of its attenuation in 0 to 2
/// (`own0.xyz` in the shader).
const ATTENUATION: usize = 0;

impl Point {
    /// Its own numbers, from its checked keys: a spot light's too.
    pub(super) fn own(at: &LightAt, attenuation: Option<Triple>) -> Result<[f64; 3], SceneError> {
        Ok(at.attenuation(attenuation)?.to_array())
    }

    fn attenuation<R: Real>(own: &[R]) -> Vec3<R> {
        Vec3::new(own[ATTENUATION], own[ATTENUATION + 1], own[ATTENUATION + 2])
    }
}

impl LightType for Point {
    type File = PointFile;
    const NAME: &'static str = "point";
    const GLSL: &'static str = include_str!("../../../shaders/light/point.glsl");
    const POSITIONED: bool = true;

    fn check(file: PointFile, at: &LightAt) -> Result<Placement, SceneError> {
        let mut own = [0.0; super::OWN];
        let position = at.position(file.position)?;
        own[ATTENUATION..ATTENUATION + 3].copy_from_slice(&Point::own(at, file.attenuation)?);
        Ok(Placement {
            position,
            own,
            ..Placement::default()
        })
    }

    fn toward<R: Real>(l: &LightR<R>, p: Vec3<R>, _n: Vec3<R>) -> Toward<R> {
        let to_light = l.position - p;
        let dist = to_light.length();
        let a = Point::attenuation(&l.own);
        let att = (a.x + a.y * dist + a.z * dist * dist).recip();
        (to_light / dist, dist, att)
    }

    fn attenuated(l: &Light) -> bool {
        Point::attenuation(&l.own) != Vec3::new(1.0, 0.0, 0.0)
    }

    fn peak_divisor(l: &Light) -> f64 {
        l.own[ATTENUATION]
    }

    fn sample(p: &mut Place) -> PointFile {
        let at = p.center + p.upward() * (3.0 * p.size);
        let mut f = PointFile {
            position: Some(Triple(Place::triple(at))),
            attenuation: None,
        };
        if p.pick(2) == 1 {
            f.attenuation = Some(Triple([1.0, p.uniform(0.0, 0.2), p.uniform(0.0, 0.05)]));
        }
        f
    }

    #[cfg(test)]
    fn example() -> PointFile {
        PointFile {
            position: Some(Triple([1.0, 2.0, 3.0])),
            attenuation: None,
        }
    }
}
