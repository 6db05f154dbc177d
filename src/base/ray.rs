//! A ray: an origin and a unit direction, in either real type; mirrors
//! `struct Ray` in shaders/ray.glsl.

use super::real::{Real, Vec3};

/// A half-line from `origin` along `dir`.
#[derive(Debug, Clone, Copy)]
pub struct Ray<R> {
    /// Where it starts.
    pub origin: Vec3<R>,
    /// Unit length.
    pub dir: Vec3<R>,
}

impl<R: Real> Ray<R> {
    /// The point at distance `t` along it.
    pub fn at(&self, t: R) -> Vec3<R> {
        self.origin + self.dir * t
    }
}
