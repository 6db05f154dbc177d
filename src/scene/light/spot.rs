//! A spot light: a point light within a cone about its axis, falling off
//! towards the cone's edge; mirrors shaders/light/spot.glsl.

use serde::{Deserialize, Serialize};

use super::point::Point;
use super::{Light, LightAt, LightR, LightType, Placement, Toward};
use crate::base::real::{spec_pow, Real, Vec3};
use crate::input::error::SceneError;
use crate::input::field::Triple;
use crate::rng::Place;

pub struct Spot;

/// A spot light's keys.
#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SpotFile {
    /// Where it is.
    pub position: Option<Triple>,
    /// Its cone's axis.
    pub direction: Option<Triple>,
    /// As a point light's.
    pub attenuation: Option<Triple>,
    /// Its cone's half-angle, in degrees.
    pub cutoff: Option<f64>,
    /// Its falloff towards the cone's edge (default 0).
    pub exponent: Option<f64>,
}

/// Its own numbers (`Light::own`): a point light's in 0 to 3, then the
/// cosine of its cutoff and its exponent (`own1.xy` in the shader).
const COS_CUTOFF: usize = 4;
const EXPONENT: usize = 5;

impl LightType for Spot {
    type File = SpotFile;
    const NAME: &'static str = "spot";
    const GLSL: &'static str = include_str!("../../../shaders/light/spot.glsl");
    const POSITIONED: bool = true;
    const CONE: bool = true;

    fn check(file: SpotFile, at: &LightAt) -> Result<Placement, SceneError> {
        let position = at.position(file.position)?;
        let direction = at.direction(file.direction)?;
        let mut own = [0.0; super::OWN];
        own[..3].copy_from_slice(&Point::own(at, file.attenuation)?);
        let cutoff = match file.cutoff {
            Some(c) => at.number("cutoff", c)?,
            None => return at.err(None, "missing key `cutoff` (required for a spot light)"),
        };
        if !(cutoff > 0.0 && cutoff <= 90.0) {
            return at.err(
                Some("cutoff"),
                format!(
                    "must be in (0, 90] degrees, got {}",
                    crate::printable::number(cutoff)
                ),
            );
        }
        let exponent = at.number("exponent", file.exponent.unwrap_or(0.0))?;
        if exponent < 0.0 {
            return at.err(
                Some("exponent"),
                format!("must be >= 0, got {}", crate::printable::number(exponent)),
            );
        }
        own[COS_CUTOFF] = cutoff.to_radians().cos();
        own[EXPONENT] = exponent;
        Ok(Placement {
            position,
            direction,
            own,
        })
    }

    fn toward<R: Real>(l: &LightR<R>, p: Vec3<R>, n: Vec3<R>) -> Toward<R> {
        Point::toward(l, p, n)
    }

    fn cone<R: Real>(l: &LightR<R>, _p: Vec3<R>, _n: Vec3<R>, to: Vec3<R>) -> R {
        let cos_theta = (-to).dot(l.direction);
        if cos_theta >= l.own[COS_CUTOFF] {
            spec_pow(cos_theta, l.own[EXPONENT])
        } else {
            R::zero()
        }
    }

    fn attenuated(l: &Light) -> bool {
        Point::attenuated(l)
    }

    fn peak_divisor(l: &Light) -> f64 {
        Point::peak_divisor(l)
    }

    /// A spot above the place, aimed near its centre.
    fn sample(p: &mut Place) -> SpotFile {
        let at = p.center + p.upward() * (3.0 * p.size);
        let aim = p.center + p.unit() * (0.5 * p.size);
        let way = (aim - at).normalize();
        SpotFile {
            position: Some(Triple(Place::triple(at))),
            direction: Some(Triple(Place::triple(way))),
            attenuation: None,
            cutoff: Some(p.uniform(15.0, 70.0)),
            exponent: Some([0.0, 1.0, p.uniform(0.0, 16.0)][p.pick(3)]),
        }
    }

    #[cfg(test)]
    fn example() -> SpotFile {
        SpotFile {
            position: Some(Triple([1.0, 2.0, 3.0])),
            direction: Some(Triple([0.0, -1.0, 0.0])),
            cutoff: Some(30.0),
            exponent: Some(2.0),
            ..SpotFile::default()
        }
    }
}
