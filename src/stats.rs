//! What a render counts, as the SPD's procedure counts it (docs/spd.md):
//! every eye ray and those that hit, every reflection and refraction ray
//! spawned, every shadow ray cast; and the work they cost, ray/primitive
//! tests by kind and BVH nodes visited, by the type of the ray that did it.
//! Both renderers count the same events at the same places
//! (src/cpu/trace.rs and shaders/trace.glsl, and so on); the GPU keeps them
//! in a buffer of [`Counter::SLOTS`] 64-bit slots (shaders/count.glsl).

use std::collections::BTreeMap;

use serde::Serialize;

use crate::prim::KINDS;

pub use crate::base::count::{Counter, RayType};
pub(crate) use crate::base::tally::Tally;

impl Counter {
    /// The ray counters, one slot each, with their names in GLSL.
    pub const RAYS: [(Counter, &'static str); 5] = [
        (Counter::Eye, "COUNT_EYE"),
        (Counter::EyeHit, "COUNT_EYE_HIT"),
        (Counter::Reflect, "COUNT_REFLECT"),
        (Counter::Refract, "COUNT_REFRACT"),
        (Counter::Shadow, "COUNT_SHADOW"),
    ];
    /// Where the work of each ray type starts: its node visits, then its
    /// tests by kind.
    pub const WORK: usize = Self::RAYS.len();
    /// Slots of one ray type's work: its node visits, its cells read, its
    /// tests by kind.
    pub const PER_TYPE: usize = 2 + KINDS.len();
    /// Slots in all.
    pub const SLOTS: usize = Self::WORK + RayType::ALL.len() * Self::PER_TYPE;

    pub(crate) fn slot(self, as_type: RayType) -> usize {
        let work = Self::WORK + as_type as usize * Self::PER_TYPE;
        match self {
            Counter::Eye => 0,
            Counter::EyeHit => 1,
            Counter::Reflect => 2,
            Counter::Refract => 3,
            Counter::Shadow => 4,
            Counter::Node => work,
            Counter::Cell => work + 1,
            Counter::Test(k) => work + 2 + k as usize,
        }
    }
}

/// Every counter of a render.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Counts {
    slots: [u64; Counter::SLOTS],
    current: RayType,
}

impl Default for Counts {
    fn default() -> Self {
        Self::from_slots([0; Counter::SLOTS])
    }
}

impl Tally for Counts {
    #[inline(always)]
    fn count(&mut self, c: Counter) {
        self.slots[c.slot(self.current)] += 1;
    }

    #[inline(always)]
    fn ray_type(&mut self, t: RayType) {
        self.current = t;
    }

    fn merge(mut self, other: Self) -> Self {
        for (a, b) in self.slots.iter_mut().zip(other.slots) {
            *a += b;
        }
        self
    }
}

/// One ray type's work.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Work {
    /// The rays of this type.
    pub rays: u64,
    /// Tests by kind, under each kind's key, `bvh_nodes` and
    /// `table_cells`.
    pub tests: BTreeMap<&'static str, u64>,
}

impl Work {
    /// Tests of every kind, without the node visits.
    pub fn tests_total(&self) -> u64 {
        self.tests
            .iter()
            .filter(|(k, _)| **k != "bvh_nodes" && **k != "table_cells")
            .map(|(_, n)| n)
            .sum()
    }

    /// BVH node visits.
    pub fn nodes(&self) -> u64 {
        self.tests["bvh_nodes"]
    }
}

impl Counts {
    /// From the slots in [`Counter`]'s order (the GPU's buffer).
    pub fn from_slots(slots: [u64; Counter::SLOTS]) -> Self {
        Self {
            slots,
            current: RayType::Eye,
        }
    }

    /// A ray counter, or a test or node counter summed over the ray types.
    pub fn get(&self, c: Counter) -> u64 {
        match c {
            Counter::Node | Counter::Cell | Counter::Test(_) => {
                RayType::ALL.iter().map(|t| self.slots[c.slot(*t)]).sum()
            }
            _ => self.slots[c.slot(RayType::Eye)],
        }
    }

    /// The rays of each type.
    pub fn rays(&self) -> RayCounts {
        RayCounts {
            eye: self.get(Counter::Eye),
            eye_hit: self.get(Counter::EyeHit),
            reflect: self.get(Counter::Reflect),
            refract: self.get(Counter::Refract),
            shadow: self.get(Counter::Shadow),
        }
    }

    /// The tests by kind, under each kind's key, and the BVH nodes visited,
    /// of every ray.
    pub fn tests(&self) -> BTreeMap<&'static str, u64> {
        tests_by(|c| self.get(c))
    }

    /// The work of each ray type.
    pub fn by_ray(&self) -> BTreeMap<&'static str, Work> {
        let rays = self.rays();
        RayType::ALL
            .iter()
            .map(|t| {
                let n = match t {
                    RayType::Eye => rays.eye,
                    RayType::Reflect => rays.reflect,
                    RayType::Refract => rays.refract,
                    RayType::Shadow => rays.shadow,
                };
                let tests = tests_by(|c| self.slots[c.slot(*t)]);
                (t.name(), Work { rays: n, tests })
            })
            .collect()
    }

    /// The rays and the tests of every ray (as `--stats` has them at its
    /// top level), each by name, for comparisons.
    pub fn named(&self) -> Vec<(String, u64)> {
        let r = self.rays();
        let mut v: Vec<(String, u64)> = [
            ("eye", r.eye),
            ("eye_hit", r.eye_hit),
            ("reflect", r.reflect),
            ("refract", r.refract),
            ("shadow", r.shadow),
        ]
        .map(|(k, n)| (k.to_owned(), n))
        .into();
        v.extend(self.tests().into_iter().map(|(k, n)| (k.to_owned(), n)));
        v
    }

    /// Each ray type's tests and node visits by name (`shadow.spheres`).
    pub fn named_by_ray(&self) -> Vec<(String, u64)> {
        self.by_ray()
            .into_iter()
            .flat_map(|(t, work)| {
                work.tests
                    .into_iter()
                    .map(move |(k, n)| (format!("{t}.{k}"), n))
            })
            .collect()
    }
}

fn tests_by(get: impl Fn(Counter) -> u64) -> BTreeMap<&'static str, u64> {
    let mut m: BTreeMap<&'static str, u64> = KINDS
        .iter()
        .enumerate()
        .map(|(k, kind)| (kind.key, get(Counter::Test(k as u32))))
        .collect();
    m.insert("bvh_nodes", get(Counter::Node));
    m.insert("table_cells", get(Counter::Cell));
    m
}

/// The rays of a render, as `--stats` writes them.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct RayCounts {
    /// Eye rays.
    pub eye: u64,
    /// Eye rays that met something.
    pub eye_hit: u64,
    /// Mirror rays.
    pub reflect: u64,
    /// Refraction rays.
    pub refract: u64,
    /// Shadow rays.
    pub shadow: u64,
}
