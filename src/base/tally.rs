//! The trait a renderer counts and records through: what it counts
//! (`super::count`) and what it records (`super::record`), to a tally that
//! keeps them or to `()`, which keeps nothing at no cost.

use super::aov::EyeHit;
use super::count::{Counter, RayType};
use super::record::Event;

/// Where a renderer reports what it counts: `crate::stats::Counts`, or `()` to count
/// nothing at no cost.
pub(crate) trait Tally: Default + Send {
    /// One more of `c`.
    fn count(&mut self, c: Counter);
    /// The type of the ray whose tests and node visits follow.
    fn ray_type(&mut self, t: RayType);
    /// Both tallies' counts together (rows rendered apart).
    fn merge(self, other: Self) -> Self;
    /// One event of the ray tree, for `glint explain`: built only by a
    /// tally that records (`crate::explain`), dropped unbuilt by the others.
    #[inline(always)]
    fn record(&mut self, _event: impl FnOnce() -> Event) {}
    /// What an eye ray met first, for a render's AOVs: built only by a
    /// tally that keeps them (`cpu::aov`).
    #[inline(always)]
    fn eye_hit(&mut self, _hit: impl FnOnce() -> EyeHit) {}
}

impl Tally for () {
    #[inline(always)]
    fn count(&mut self, _: Counter) {}
    #[inline(always)]
    fn ray_type(&mut self, _: RayType) {}
    fn merge(self, _: Self) -> Self {}
}
