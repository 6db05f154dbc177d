//! An axis-aligned box, the bound every bounded kind gives (`crate::prim`)
//! and the BVH is built from (`crate::accel::bvh`).

use glam::DVec3;

/// The box from `lo` to `hi`, corner by corner.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// The least corner.
    pub lo: DVec3,
    /// The greatest corner.
    pub hi: DVec3,
}

impl Aabb {
    /// The box of nothing: a union with it changes nothing.
    pub const EMPTY: Aabb = Aabb {
        lo: DVec3::splat(f64::INFINITY),
        hi: DVec3::splat(f64::NEG_INFINITY),
    };

    /// The box around the sphere at `center` of `radius`.
    pub fn sphere(center: DVec3, radius: f64) -> Aabb {
        Aabb {
            lo: center - radius,
            hi: center + radius,
        }
    }

    /// The box around both.
    pub fn union(self, o: Aabb) -> Aabb {
        Aabb {
            lo: self.lo.min(o.lo),
            hi: self.hi.max(o.hi),
        }
    }

    /// The box around this one and `p`.
    pub fn grow(self, p: DVec3) -> Aabb {
        Aabb {
            lo: self.lo.min(p),
            hi: self.hi.max(p),
        }
    }

    /// Half the surface area, the SAH's measure.
    pub fn half_area(&self) -> f64 {
        let d = (self.hi - self.lo).max(DVec3::ZERO);
        d.x * d.y + d.y * d.z + d.z * d.x
    }

    /// The middle.
    pub fn center(&self) -> DVec3 {
        (self.lo + self.hi) * 0.5
    }
}
