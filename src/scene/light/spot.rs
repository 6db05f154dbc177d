//! A spot light: a point light within a cone about its axis, falling off
//! towards the cone's edge; mirrors shaders/light/spot.glsl.

use super::point::Point;
use super::{LightAt, LightR, LightType, Placement, Toward};
use crate::base::real::{spec_pow, Real, Vec3};
use crate::input::error::SceneError;
use crate::rng::Place;

pub struct Spot;

impl LightType for Spot {
    const NAME: &'static str = "spot";
    const GLSL: &'static str = include_str!("../../../shaders/light/spot.glsl");
    const KEYS: &'static [&'static str] =
        &["position", "direction", "attenuation", "cutoff", "exponent"];
    const POSITIONED: bool = true;
    const CONE: bool = true;

    fn check(at: &LightAt) -> Result<Placement, SceneError> {
        let position = at.position()?;
        let direction = at.direction()?;
        let attenuation = at.attenuation()?;
        let cutoff = match at.file.cutoff {
            Some(c) => at.number("cutoff", c)?,
            None => return at.err(None, "missing key `cutoff` (required for a spot light)"),
        };
        if !(cutoff > 0.0 && cutoff <= 90.0) {
            return at.err(
                Some("cutoff"),
                format!("must be in (0, 90] degrees, got {cutoff}"),
            );
        }
        let exponent = at.number("exponent", at.file.exponent.unwrap_or(0.0))?;
        if exponent < 0.0 {
            return at.err(Some("exponent"), format!("must be >= 0, got {exponent}"));
        }
        Ok(Placement {
            position,
            direction,
            attenuation,
            cos_cutoff: cutoff.to_radians().cos(),
            exponent,
        })
    }

    fn toward<R: Real>(l: &LightR<R>, p: Vec3<R>) -> Toward<R> {
        Point::toward(l, p)
    }

    fn cone<R: Real>(l: &LightR<R>, to: Vec3<R>) -> R {
        let cos_theta = (-to).dot(l.direction);
        if cos_theta >= l.cos_cutoff {
            spec_pow(cos_theta, l.exponent)
        } else {
            R::zero()
        }
    }

    /// A spot above the place, aimed near its centre.
    fn sample(p: &mut Place) -> super::LightFile {
        let at = p.center + p.upward() * (3.0 * p.size);
        let aim = p.center + p.unit() * (0.5 * p.size);
        let way = (aim - at).normalize();
        let mut f = super::LightFile::placed(
            Self::NAME,
            Some(Place::triple(at)),
            Some(Place::triple(way)),
        );
        f.cutoff = Some(p.uniform(15.0, 70.0));
        f.exponent = Some([0.0, 1.0, p.uniform(0.0, 16.0)][p.pick(3)]);
        f
    }

    #[cfg(test)]
    fn example() -> super::LightFile {
        let mut f =
            super::contract_tests::file("spot", Some([1.0, 2.0, 3.0]), Some([0.0, -1.0, 0.0]));
        f.cutoff = Some(30.0);
        f.exponent = Some(2.0);
        f
    }
}
