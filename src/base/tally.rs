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
    /// One branch of the ray tree, as a word (`tree_word`): kept only by
    /// a tally that tells trees apart (contrast sampling, `cpu::contrast`).
    #[inline(always)]
    fn branch(&mut self, _word: u32) {}
}

/// The word of a branch of the ray tree, for contrast sampling's
/// comparison of trees (docs/scene-format.md, Rays): a miss, the material
/// a ray met, or a shadow ray's verdict. Mirrors shaders/tree.glsl.
pub(crate) mod tree_word {
    /// A ray that met nothing.
    pub const MISS: u32 = 0;
    /// A ray that met a surface of material `m`.
    pub fn hit(m: u32) -> u32 {
        m + 1
    }
    /// A shadow ray, blocked or not.
    pub fn shadow(blocked: bool) -> u32 {
        0x8000_0000 | u32::from(blocked)
    }
    /// The hash of a tree before its first branch.
    pub const BASIS: u32 = 0x811c_9dc5;
    /// The hash `h` with one more branch `word`.
    pub fn fold(h: u32, word: u32) -> u32 {
        (h ^ word).wrapping_mul(0x0100_0193)
    }
}

impl Tally for () {
    #[inline(always)]
    fn count(&mut self, _: Counter) {}
    #[inline(always)]
    fn ray_type(&mut self, _: RayType) {}
    fn merge(self, _: Self) -> Self {}
}
