//! A light once checked: its type, placement and colours; its struct in
//! the shader's buffers and its form in the CPU reference's arithmetic.

use glam::DVec3;

use super::LightTypeId;
use crate::base::real::{Real, Vec3};

/// A light (docs/scene-format.md, Lights).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Light {
    /// What type.
    pub kind: LightTypeId,
    /// Where a positioned light is; zero for the others.
    pub position: DVec3,
    /// Unit length: the way a directional light travels, a cone's axis;
    /// zero for the others.
    pub direction: DVec3,
    /// Its ambient intensity, per channel.
    pub ambient: DVec3,
    /// Its diffuse intensity, per channel.
    pub diffuse: DVec3,
    /// Its specular intensity, per channel.
    pub specular: DVec3,
    /// Its type's own numbers (a point light's attenuation, a cone's
    /// cutoff), laid out by its type's module; 0 where it has none.
    pub own: Own,
}

/// A light type's own numbers: its record in the shader (`own0`, `own1`)
/// and in the CPU reference (`LightR::own`). Its module names the places.
pub type Own = [f64; OWN];

/// How many numbers a light type may keep of its own.
pub const OWN: usize = 8;

/// What a type's check gives: everything of a light but its colours.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Placement {
    /// `Light::position`.
    pub position: DVec3,
    /// `Light::direction`.
    pub direction: DVec3,
    /// `Light::own`.
    pub own: Own,
}

impl Light {
    /// Whether the light has a diffuse or specular term: a shadow ray
    /// towards a light without one could change nothing.
    pub fn has_direct_term(&self) -> bool {
        self.diffuse != DVec3::ZERO || self.specular != DVec3::ZERO
    }

    /// Whether its intensity falls with distance (its type says).
    pub fn attenuated(&self) -> bool {
        self.kind.attenuated(self)
    }

    /// What its intensity is divided by at its brightest (its type says).
    pub fn peak_divisor(&self) -> f64 {
        self.kind.peak_divisor(self)
    }

    /// Its position, where its type has one.
    pub fn position(&self) -> Option<DVec3> {
        self.kind.info().positioned.then_some(self.position)
    }

    /// Its struct in the shader's buffers, in coordinates moved by
    /// `-origin`, with its light buffer's first grid and reach where it has
    /// one (`crate::accel::tables`).
    pub(crate) fn gpu(&self, origin: DVec3, buffer: Option<(u32, f32)>) -> gpu::Values {
        let (table, reach) = buffer.map_or((0, 0), |(first, reach)| (first + 1, reach.to_bits()));
        let xyz = |v: DVec3| [v.x, v.y, v.z, 0.0];
        gpu::Values {
            position: xyz(self.position - origin),
            direction: xyz(self.direction),
            ambient: xyz(self.ambient),
            diffuse: xyz(self.diffuse),
            specular: xyz(self.specular),
            own0: [self.own[0], self.own[1], self.own[2], self.own[3]],
            own1: [self.own[4], self.own[5], self.own[6], self.own[7]],
            meta: [
                self.kind as u32,
                u32::from(self.has_direct_term()),
                table,
                reach,
            ],
        }
    }

    /// The light in the CPU reference's arithmetic, moved by `-origin`.
    pub fn cpu<R: Real>(&self, origin: DVec3) -> LightR<R> {
        LightR {
            kind: self.kind,
            position: Vec3::of(self.position - origin),
            direction: Vec3::of(self.direction),
            ambient: Vec3::of(self.ambient),
            diffuse: Vec3::of(self.diffuse),
            specular: Vec3::of(self.specular),
            own: self.own.map(R::of),
            direct: self.has_direct_term(),
        }
    }
}

crate::base::interface::gpu_struct!(
    pub(crate) mod gpu: "Light" {
        /// xyz (positioned types)
        position: real4,
        /// xyz unit (directional: travel; a cone's axis)
        direction: real4,
        /// rgb Ia
        ambient: real4,
        /// rgb Id
        diffuse: real4,
        /// rgb Is
        specular: real4,
        /// its type's own numbers 0 to 3 (`Own`)
        own0: real4,
        /// its type's own numbers 4 to 7
        own1: real4,
        /// x LIGHT_* (its type), y 1 if it has a diffuse or specular term,
        /// z its light buffer's first grid + 1 (0: none), w the buffer's
        /// reach (f32 bits)
        meta: uvec4,
    }
);

/// A light in the CPU reference's arithmetic, in camera-relative
/// coordinates; what the shader's `Light` holds.
#[derive(Debug, Clone, Copy)]
pub struct LightR<R> {
    /// `Light::kind`.
    pub kind: LightTypeId,
    /// `Light::position`, moved.
    pub position: Vec3<R>,
    /// `Light::direction`.
    pub direction: Vec3<R>,
    /// `Light::ambient`.
    pub ambient: Vec3<R>,
    /// `Light::diffuse`.
    pub diffuse: Vec3<R>,
    /// `Light::specular`.
    pub specular: Vec3<R>,
    /// `Light::own`.
    pub own: [R; OWN],
    /// Whether it has a diffuse or specular term.
    pub direct: bool,
}

/// How light reaches a point: the unit way towards the light, the distance
/// to it (infinite for a light without a position) and the attenuation.
pub type Toward<R> = (Vec3<R>, R, R);
