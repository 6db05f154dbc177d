//! What a render counts, as the SPD's procedure counts it (docs/spd.md):
//! every eye ray and those that hit, every reflection and refraction ray
//! spawned, every shadow ray cast; and the work they cost, ray/primitive
//! tests by kind and BVH nodes visited. Both renderers count the same
//! events at the same places (src/cpu/trace.rs and shaders/trace.glsl,
//! and so on); the GPU keeps them in a buffer of [`Counter::WORDS`] words.

use std::collections::BTreeMap;

use serde::Serialize;

use crate::prim::KINDS;

/// One counted event.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Counter {
    Eye,
    EyeHit,
    Reflect,
    Refract,
    Shadow,
    /// A BVH node visited.
    Node,
    /// A ray tested against a primitive of the kind `KINDS[k]`.
    Test(u32),
}

impl Counter {
    /// The counters, one per slot of the GPU's buffer, with their names in
    /// GLSL (shaders/count.glsl).
    pub const NAMED: [(Counter, &'static str); 6] = [
        (Counter::Eye, "COUNT_EYE"),
        (Counter::EyeHit, "COUNT_EYE_HIT"),
        (Counter::Reflect, "COUNT_REFLECT"),
        (Counter::Refract, "COUNT_REFRACT"),
        (Counter::Shadow, "COUNT_SHADOW"),
        (Counter::Node, "COUNT_NODE"),
    ];
    /// Where the per-kind test counts start.
    pub const TESTS: usize = Self::NAMED.len();
    /// Slots in all.
    pub const SLOTS: usize = Self::TESTS + KINDS.len();

    fn slot(self) -> usize {
        match self {
            Counter::Eye => 0,
            Counter::EyeHit => 1,
            Counter::Reflect => 2,
            Counter::Refract => 3,
            Counter::Shadow => 4,
            Counter::Node => 5,
            Counter::Test(k) => Self::TESTS + k as usize,
        }
    }
}

/// Where a renderer reports what it counts: [`Counts`], or `()` to count
/// nothing at no cost.
pub trait Tally: Default + Send {
    fn count(&mut self, c: Counter);
    fn merge(self, other: Self) -> Self;
}

impl Tally for () {
    #[inline(always)]
    fn count(&mut self, _: Counter) {}
    fn merge(self, _: Self) -> Self {}
}

/// Every counter of a render.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Counts {
    slots: [u64; Counter::SLOTS],
}

impl Default for Counts {
    fn default() -> Self {
        Self {
            slots: [0; Counter::SLOTS],
        }
    }
}

impl Tally for Counts {
    #[inline(always)]
    fn count(&mut self, c: Counter) {
        self.slots[c.slot()] += 1;
    }

    fn merge(mut self, other: Self) -> Self {
        for (a, b) in self.slots.iter_mut().zip(other.slots) {
            *a += b;
        }
        self
    }
}

impl Counts {
    /// From the slots in [`Counter`]'s order (the GPU's buffer).
    pub fn from_slots(slots: [u64; Counter::SLOTS]) -> Self {
        Self { slots }
    }

    pub fn get(&self, c: Counter) -> u64 {
        self.slots[c.slot()]
    }

    pub fn rays(&self) -> RayCounts {
        RayCounts {
            eye: self.get(Counter::Eye),
            eye_hit: self.get(Counter::EyeHit),
            reflect: self.get(Counter::Reflect),
            refract: self.get(Counter::Refract),
            shadow: self.get(Counter::Shadow),
        }
    }

    /// The tests by kind, under each kind's key, and the BVH nodes visited.
    pub fn tests(&self) -> BTreeMap<&'static str, u64> {
        let mut m: BTreeMap<&'static str, u64> = KINDS
            .iter()
            .enumerate()
            .map(|(k, kind)| (kind.key, self.get(Counter::Test(k as u32))))
            .collect();
        m.insert("bvh_nodes", self.get(Counter::Node));
        m
    }

    /// Each counter's name (as in `--stats`) and value, for comparisons.
    pub fn named(&self) -> Vec<(&'static str, u64)> {
        let r = self.rays();
        let mut v = vec![
            ("eye", r.eye),
            ("eye_hit", r.eye_hit),
            ("reflect", r.reflect),
            ("refract", r.refract),
            ("shadow", r.shadow),
        ];
        v.extend(self.tests());
        v
    }
}

/// The rays of a render, as `--stats` writes them.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct RayCounts {
    pub eye: u64,
    pub eye_hit: u64,
    pub reflect: u64,
    pub refract: u64,
    pub shadow: u64,
}
