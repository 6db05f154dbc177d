//! A light's table in the scene file, as read: every type's keys on one
//! flat table, which the light's type then checks (check.rs).

use serde::{Deserialize, Serialize};

use crate::input::field::Triple;

/// One flat table for every light type: `check` takes the keys of the
/// light's type alone and refuses the others by name.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct LightFile {
    /// `type`: a name of the table of light types.
    #[serde(rename = "type")]
    pub kind: String,
    /// Where a positioned light is.
    pub position: Option<Triple>,
    /// The way a directional light travels; a cone's axis.
    pub direction: Option<Triple>,
    /// Its ambient intensity (default 0).
    #[serde(default)]
    pub ambient: Triple,
    /// Its diffuse intensity (default 0).
    #[serde(default)]
    pub diffuse: Triple,
    /// Its specular intensity (default 0).
    #[serde(default)]
    pub specular: Triple,
    /// A positioned light's [c, l, q] (default [1, 0, 0]).
    pub attenuation: Option<Triple>,
    /// A cone's half-angle, in degrees.
    pub cutoff: Option<f64>,
    /// A cone's falloff exponent (default 0).
    pub exponent: Option<f64>,
}

impl LightFile {
    /// A light of type `kind` at `position` or along `direction`, white,
    /// with a little ambient, and its other keys left out.
    pub(crate) fn placed(
        kind: &str,
        position: Option<[f64; 3]>,
        direction: Option<[f64; 3]>,
    ) -> Self {
        LightFile {
            kind: kind.to_owned(),
            position: position.map(Triple),
            direction: direction.map(Triple),
            ambient: Triple([0.1; 3]),
            diffuse: Triple([1.0; 3]),
            specular: Triple([0.5; 3]),
            attenuation: None,
            cutoff: None,
            exponent: None,
        }
    }

    /// The keys a type may take (beside `type` and the three colours),
    /// each with whether this table has it.
    pub(super) fn typed_keys(&self) -> [(&'static str, bool); 5] {
        [
            ("position", self.position.is_some()),
            ("direction", self.direction.is_some()),
            ("attenuation", self.attenuation.is_some()),
            ("cutoff", self.cutoff.is_some()),
            ("exponent", self.exponent.is_some()),
        ]
    }
}
