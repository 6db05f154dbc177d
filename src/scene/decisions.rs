//! The choices adaptive and contrast sampling make (docs/guarantees.md,
//! Sampling decisions): which squares split, which pixels take more
//! samples. Each is a threshold on a contrast, so two renderers whose
//! colours differ by a rounding may choose otherwise at a near-tie, and
//! then trace different samples. `glint compare` holds the arithmetic to
//! the reference on the same samples: the renderer under test replays the
//! reference's decisions (`Scene::replay`, taken by
//! `sampling::decisions::Decider`), and the decisions it would have taken
//! otherwise on those samples are checked on their own
//! (`condition::decided`).

/// Where a decision is taken: its level and its place on that level's
/// lattice, in the whole image's coordinates. Adaptive sampling: a
/// square's top-left corner on the lattice of side 2^-level pixels (level
/// 0: the pixel); contrast sampling: the pixel, and the level it reached.
pub fn key(level: u32, x: u32, y: u32) -> u64 {
    u64::from(level) << 56 | u64::from(y) << 28 | u64::from(x)
}

/// Which sampling's decisions, which says where a key lies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Kind {
    /// Adaptive sampling's: a key's place is on its level's lattice.
    #[default]
    Adaptive,
    /// Contrast sampling's: a key's place is its pixel.
    Contrast,
}

/// A set of decisions, by their keys ([`key`]), sorted.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Decisions {
    kind: Kind,
    keys: Vec<u64>,
}

impl Decisions {
    /// The decisions `keys` of sampling `kind`, in any order.
    pub fn new(kind: Kind, mut keys: Vec<u64>) -> Self {
        keys.sort_unstable();
        keys.dedup();
        Self { kind, keys }
    }

    /// Whether it holds `key`.
    pub fn holds(&self, key: u64) -> bool {
        self.keys.binary_search(&key).is_ok()
    }

    /// How many it holds.
    pub fn len(&self) -> usize {
        self.keys.len()
    }

    /// Whether it holds none.
    pub fn is_empty(&self) -> bool {
        self.keys.is_empty()
    }

    /// Its keys, sorted.
    pub fn keys(&self) -> &[u64] {
        &self.keys
    }

    /// The pixel (column, row) a key's decision belongs to.
    pub fn pixel_of(&self, key: u64) -> (u32, u32) {
        let level = (key >> 56) as u32;
        let (x, y) = ((key & 0x0fff_ffff) as u32, (key >> 28 & 0x0fff_ffff) as u32);
        match self.kind {
            Kind::Adaptive => (x >> level, y >> level),
            Kind::Contrast => (x, y),
        }
    }

    /// The pixels, as places in a `width`-wide image, where `self` and
    /// `other` differ: a key one holds and the other does not.
    pub fn pixels_differing(&self, other: &Decisions, width: u32) -> Vec<usize> {
        let one_side = self.without(other);
        let other_side = other.without(self);
        let mut out: Vec<usize> = one_side
            .keys
            .iter()
            .chain(&other_side.keys)
            .map(|&key| {
                let (x, y) = self.pixel_of(key);
                (y * width + x) as usize
            })
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }

    /// Those of its keys `other` does not hold.
    pub fn without(&self, other: &Decisions) -> Decisions {
        Decisions {
            kind: self.kind,
            keys: self
                .keys
                .iter()
                .copied()
                .filter(|k| !other.holds(*k))
                .collect(),
        }
    }

    /// Both sets' keys, of the kind of the one that holds any (an empty
    /// set, as `Decisions::default()` starts one, has no kind to give).
    pub fn union(&self, other: &Decisions) -> Decisions {
        let kind = if self.keys.is_empty() {
            other.kind
        } else {
            self.kind
        };
        Decisions::new(kind, [&self.keys[..], &other.keys].concat())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A key's pixel: an adaptive square's at its level, a contrast
    /// pixel's itself; the pixels where two sets differ, once each.
    #[test]
    fn keys_name_their_pixels() {
        let a = Decisions::new(Kind::Adaptive, vec![key(0, 3, 2), key(2, 13, 9)]);
        assert_eq!(a.pixel_of(key(2, 13, 9)), (3, 2));
        assert_eq!(a.pixel_of(key(0, 5, 7)), (5, 7));
        let b = Decisions::new(Kind::Adaptive, vec![key(0, 3, 2), key(1, 8, 2)]);
        assert_eq!(a.pixels_differing(&b, 10), vec![10 + 4, 2 * 10 + 3]);
        assert_eq!(a.pixels_differing(&a, 10), Vec::<usize>::new());
        let c = Decisions::new(Kind::Contrast, vec![key(2, 13, 9)]);
        assert_eq!(c.pixel_of(key(2, 13, 9)), (13, 9));
        assert_eq!(a.without(&b).keys(), &[key(2, 13, 9)]);
        assert_eq!(a.union(&b).len(), 3);
        let empty = Decisions::default();
        assert_eq!(empty.union(&c).pixel_of(key(2, 13, 9)), (13, 9));
    }
}
