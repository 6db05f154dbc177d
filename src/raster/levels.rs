//! The sRGB curve's 8-bit levels by table: `quantize(c, true)` is
//! round(255 · srgb_encode(c)), one `powf` a channel, which took 40 ms of
//! a 1920×1080 PNG's writing. The level is a step function of c, so each
//! step's first value, found once with that same formula, gives every
//! level: the same bytes, no `powf`. A second table, of the level at
//! each 1/4096, starts the count one step or none below it (no step but
//! level 0's, which ends inside the first 1/4096, is narrower than
//! that), where a search of the 255
//! thresholds cost more branches than the `powf` it replaced saved.

use std::sync::OnceLock;

use super::srgb_encode;

/// The level of a linear value in [0, 1] through the sRGB curve: the
/// formula that the table is built from and held to.
pub(super) fn srgb_level_by_formula(c: f32) -> u8 {
    (255.0 * srgb_encode(c)).round() as u8
}

/// Level k's threshold at index k - 1 (k = 1..=255): the least value in
/// [0, 1] whose level by the formula is k or more, found by bisection
/// over the f32 bit patterns, which non-negative values order as they do
/// the values.
fn thresholds() -> &'static [f32; 255] {
    static TABLE: OnceLock<[f32; 255]> = OnceLock::new();
    TABLE.get_or_init(|| {
        std::array::from_fn(|i| {
            let level = i as u8 + 1;
            let (mut lo, mut hi) = (0u32, 1.0f32.to_bits());
            // Invariant: the level at `hi` is at least `level` (255 at 1.0),
            // the level at `lo` (0 at 0.0) is below it.
            while hi - lo > 1 {
                let mid = lo + (hi - lo) / 2;
                if srgb_level_by_formula(f32::from_bits(mid)) >= level {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            f32::from_bits(hi)
        })
    })
}

/// How many values of [0, 1] the second table starts from: a power of
/// two, so that c · BUCKETS and its floor are exact.
const BUCKETS: usize = 4096;

/// The level at b / BUCKETS for each b: how many thresholds it reaches.
fn starts() -> &'static [u8; BUCKETS] {
    static TABLE: OnceLock<[u8; BUCKETS]> = OnceLock::new();
    TABLE.get_or_init(|| {
        std::array::from_fn(|b| {
            let c = b as f32 / BUCKETS as f32;
            thresholds().partition_point(|&t| t <= c) as u8
        })
    })
}

/// The level of a linear value in [0, 1] through the sRGB curve, by the
/// tables: how many thresholds it reaches, counted on from the level at
/// the 1/4096 below it.
pub(super) fn srgb_level(c: f32) -> u8 {
    let t = thresholds();
    let mut level = starts()[((c * BUCKETS as f32) as usize).min(BUCKETS - 1)];
    while level < 255 && c >= t[level as usize] {
        level += 1;
    }
    level
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every value within 4096 steps of a float of each threshold, and a
    /// stride through all of [0, 1]: the table gives the formula's level.
    /// (Every one of the 1,065,353,217 floats in [0, 1] was checked once,
    /// by the same comparison, when the table was written.)
    #[test]
    fn the_table_gives_the_formulas_level() {
        let one = 1.0f32.to_bits();
        let near = thresholds()
            .iter()
            .flat_map(|t| t.to_bits().saturating_sub(4096)..=(t.to_bits() + 4096).min(one));
        let stride = (0..=one).step_by(997);
        for bits in near.chain(stride) {
            let c = f32::from_bits(bits);
            assert_eq!(srgb_level(c), srgb_level_by_formula(c), "{c:e}");
        }
    }

    #[test]
    fn the_thresholds_rise_and_the_ends_are_the_ends() {
        let t = thresholds();
        assert!(t.windows(2).all(|w| w[0] < w[1]));
        // No step between two thresholds narrower than a bucket (level 0's
        // ends inside the first): a count goes on at most once.
        assert!(t.windows(2).all(|w| w[1] - w[0] > 1.0 / BUCKETS as f32));
        assert_eq!(srgb_level(0.0), 0);
        assert_eq!(srgb_level(1.0), 255);
        assert_eq!(srgb_level(t[127]), 128);
        assert_eq!(srgb_level(f32::from_bits(t[127].to_bits() - 1)), 127);
    }
}
