//! The rays a render casts, counted as the SPD's procedure counts them
//! (docs/spd.md): every eye ray and those that hit, every reflection and
//! refraction ray spawned, and every shadow ray cast.

use serde::Serialize;

#[derive(Debug, Default, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct RayCounts {
    pub eye: u64,
    pub eye_hit: u64,
    pub reflect: u64,
    pub refract: u64,
    pub shadow: u64,
}

impl RayCounts {
    pub fn sum(self, o: RayCounts) -> RayCounts {
        RayCounts {
            eye: self.eye + o.eye,
            eye_hit: self.eye_hit + o.eye_hit,
            reflect: self.reflect + o.reflect,
            refract: self.refract + o.refract,
            shadow: self.shadow + o.shadow,
        }
    }
}
