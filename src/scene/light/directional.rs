//! A directional light: from infinitely far, one way, not attenuated;
//! mirrors shaders/light/directional.glsl.

use super::{LightAt, LightR, LightType, Placement, Toward};
use crate::base::real::{Real, Vec3};
use crate::input::error::SceneError;
use crate::rng::Place;

pub struct Directional;

impl LightType for Directional {
    const NAME: &'static str = "directional";
    const GLSL: &'static str = include_str!("../../../shaders/light/directional.glsl");
    const KEYS: &'static [&'static str] = &["direction"];
    const POSITIONED: bool = false;

    fn check(at: &LightAt) -> Result<Placement, SceneError> {
        Ok(Placement {
            direction: at.direction()?,
            attenuation: at.attenuation()?,
            ..Placement::default()
        })
    }

    fn toward<R: Real>(l: &LightR<R>, _p: Vec3<R>) -> Toward<R> {
        (-l.direction, R::infinity(), R::one())
    }

    fn sample(p: &mut Place) -> super::LightFile {
        let way = -p.upward();
        super::LightFile::placed(Self::NAME, None, Some(Place::triple(way)))
    }

    #[cfg(test)]
    fn example() -> super::LightFile {
        super::contract_tests::file("directional", None, Some([0.0, -1.0, 0.0]))
    }
}
