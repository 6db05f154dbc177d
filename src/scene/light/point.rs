//! A point light: from a position, in every direction, attenuated with
//! distance; mirrors shaders/light/point.glsl.

use super::{LightAt, LightR, LightType, Placement, Toward};
use crate::base::real::{Real, Vec3};
use crate::input::error::SceneError;
use crate::input::field::Triple;
use crate::rng::Place;

pub struct Point;

impl LightType for Point {
    const NAME: &'static str = "point";
    const GLSL: &'static str = include_str!("../../../shaders/light/point.glsl");
    const KEYS: &'static [&'static str] = &["position", "attenuation"];
    const POSITIONED: bool = true;

    fn check(at: &LightAt) -> Result<Placement, SceneError> {
        Ok(Placement {
            position: at.position()?,
            attenuation: at.attenuation()?,
            ..Placement::default()
        })
    }

    fn toward<R: Real>(l: &LightR<R>, p: Vec3<R>) -> Toward<R> {
        let to_light = l.position - p;
        let dist = to_light.length();
        let a = l.attenuation;
        let att = (a.x + a.y * dist + a.z * dist * dist).recip();
        (to_light / dist, dist, att)
    }

    fn sample(p: &mut Place) -> super::LightFile {
        let at = p.center + p.upward() * (3.0 * p.size);
        let mut f = super::LightFile::placed(Self::NAME, Some(Place::triple(at)), None);
        if p.pick(2) == 1 {
            f.attenuation = Some(Triple([1.0, p.uniform(0.0, 0.2), p.uniform(0.0, 0.05)]));
        }
        f
    }

    #[cfg(test)]
    fn example() -> super::LightFile {
        super::contract_tests::file("point", Some([1.0, 2.0, 3.0]), None)
    }
}
