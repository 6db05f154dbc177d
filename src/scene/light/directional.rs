//! A directional light: from infinitely far, one way, not attenuated;
//! mirrors shaders/light/directional.glsl.

use serde::{Deserialize, Serialize};

use super::{LightAt, LightR, LightType, Placement, Toward};
use crate::base::real::{Real, Vec3};
use crate::input::error::SceneError;
use crate::input::field::Triple;
use crate::rng::Place;

pub struct Directional;

/// A directional light's keys.
#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DirectionalFile {
    /// The way its light travels.
    pub direction: Option<Triple>,
}

impl LightType for Directional {
    type File = DirectionalFile;
    const NAME: &'static str = "directional";
    const GLSL: &'static str = include_str!("../../../shaders/light/directional.glsl");
    const POSITIONED: bool = false;

    fn check(file: DirectionalFile, at: &LightAt) -> Result<Placement, SceneError> {
        Ok(Placement {
            direction: at.direction(file.direction)?,
            ..Placement::default()
        })
    }

    fn toward<R: Real>(l: &LightR<R>, _p: Vec3<R>, _n: Vec3<R>) -> Toward<R> {
        (-l.direction, R::infinity(), R::one())
    }

    fn sample(p: &mut Place) -> DirectionalFile {
        DirectionalFile {
            direction: Some(Triple(Place::triple(-p.upward()))),
        }
    }

    #[cfg(test)]
    fn example() -> DirectionalFile {
        DirectionalFile {
            direction: Some(Triple([0.0, -1.0, 0.0])),
        }
    }
}
