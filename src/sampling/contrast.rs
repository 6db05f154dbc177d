//! Contrast sampling's algorithm (the keys are `scene::Contrast`'s),
//! after Mitchell's "Generating antialiased images at low sampling
//! densities" (SIGGRAPH 1987): one sample at every pixel's centre, then
//! more, level by level, where the samples so far (the pixel's own, or
//! with a neighbour's) pass a per-channel contrast threshold, or where
//! their ray trees differ.
//!
//! What both renderers share, so that they trace the same samples and
//! sum them alike: where each sample lies (`sample_at`), which pixels go
//! on at each level (`Contrast::next`) and the levels themselves
//! (`refine_levels`), which take each renderer's tracer of a list of
//! entries (src/cpu/contrast.rs; the GPU's shaders/contrast.glsl, one
//! invocation an entry).

use rayon::prelude::*;

use super::decisions::{Decider, Log};
use crate::base::real::{Real, Vec3};
use crate::base::tally::tree_word;
use crate::raster::region::Region;
use crate::scene::decisions::key;
use crate::scene::Contrast;

impl Contrast {
    /// The samples a pixel has after each level, before `max_samples`
    /// caps them: the centre, then 4, 16 and 64 more (odd counts, each
    /// centred in the pixel: `sample_at`).
    pub const LEVELS: [u32; 4] = [1, 5, 17, 65];
    /// A threshold is compared in units of 1/`SCALE`, in integers, so that
    /// every renderer and precision makes the same choice from the same
    /// quantised colours.
    pub const SCALE: u32 = 4096;
    /// The range test counts a range in units of 1/`RANGE_SCALE` of a
    /// step of 1/255.
    pub const RANGE_SCALE: u32 = 16;
    /// A sample's place in its pixel is counted in units of 1/`GRID` pixel:
    /// exact in f32 for every image size (`MAX_SIZE` · `GRID` < 2²⁴).
    pub const GRID: u32 = 512;
    /// The pixels around a region that its levels trace too, so that a
    /// region's choices are the whole image's: a pixel's second level
    /// looks at its neighbours' first, which look at theirs.
    pub const MARGIN: u32 = 2;

    /// The samples a pixel has after each level: `LEVELS` below
    /// `max_samples`, then `max_samples`.
    pub fn levels(&self) -> Vec<u32> {
        let mut out: Vec<u32> = Self::LEVELS
            .into_iter()
            .filter(|&n| n < self.max_samples)
            .collect();
        out.push(self.max_samples);
        out
    }

    /// The thresholds in units of 1/`SCALE`, rounded; one past `SCALE`
    /// where a threshold is 1 or more (no contrast passes it).
    pub fn scaled_thresholds(&self) -> [u32; 3] {
        let scale = f64::from(Self::SCALE);
        self.thresholds
            .map(|t| (t * scale).round().clamp(0.0, scale + 1.0) as u32)
    }

    /// `range` in units of 1/(255 · `RANGE_SCALE`), rounded: the range
    /// test compares in integers too. One past the widest range (255
    /// steps) where a bound is 1 or more, so that no range passes it and
    /// its square times a pixel's samples stays far inside a u64 (a bound
    /// of 1e6, say, would overflow it).
    fn scaled_range(&self) -> Option<u64> {
        let most = f64::from(255 * Self::RANGE_SCALE + 1);
        self.range.map(|r| {
            (r * 255.0 * f64::from(Self::RANGE_SCALE))
                .round()
                .clamp(0.0, most) as u64
        })
    }

    /// Whether the quantised range `lo..=hi` (per channel, in steps of
    /// 1/255) passes the thresholds: (hi − lo)/(hi + lo) > t in a channel,
    /// compared in integers.
    pub fn passes(&self, lo: [u8; 3], hi: [u8; 3]) -> bool {
        passes(&self.scaled_thresholds(), lo, hi)
    }

    /// Which of `reached`, the pixels of a `width`-wide image of `pixels`
    /// that reached `level` (0: the centres), go on from it, by their
    /// place: each whose own samples pass the test (`Test`), or whose
    /// trees differ where trees are compared; after the centres, each
    /// whose centre passes it together with a neighbour's (any of eight):
    /// an edge between two centres lies in one pixel or the other. After
    /// the next level, by Mitchell's test each whose samples pass it
    /// together with a neighbour's (any of four); by the range test each
    /// beside one (of four) whose own samples pass, since the edge its
    /// five samples caught may lie in that neighbour too.
    pub fn next(&self, level: usize, pixels: &[Pixel], width: u32, reached: &[u32]) -> Vec<u32> {
        let test = match self.scaled_range() {
            Some(r) => Test::Range(r),
            None => Test::Contrast(self.scaled_thresholds()),
        };
        let w = width as usize;
        let h = pixels.len() / w.max(1);
        let own =
            |p: &Pixel| self.compare_trees && p.trees_differ || test.passes(p.lo, p.hi, p.samples);
        // Two pixels' samples together, each pixel's range weighed as one
        // sample's: the range test's weight for a centre and its
        // neighbour's (Mitchell's test has none).
        let together = |p: &Pixel, q: &Pixel| {
            let lo = [0, 1, 2].map(|k| p.lo[k].min(q.lo[k]));
            let hi = [0, 1, 2].map(|k| p.hi[k].max(q.hi[k]));
            test.passes(lo, hi, 1)
        };
        let neighbours = |i: usize, around: &'static [(isize, isize)]| {
            let (x, y) = ((i % w) as isize, (i / w) as isize);
            around.iter().filter_map(move |&(dx, dy)| {
                let (x, y) = (x + dx, y + dy);
                (x >= 0 && y >= 0 && x < w as isize && y < h as isize)
                    .then(|| &pixels[y as usize * w + x as usize])
            })
        };
        let goes = |i: usize| {
            let p = &pixels[i];
            own(p)
                || match (level, test) {
                    (0, _) => neighbours(i, &EIGHT).any(|q| together(p, q)),
                    (1, Test::Contrast(_)) => neighbours(i, &EIGHT[..4]).any(|q| together(p, q)),
                    (1, Test::Range(_)) => {
                        neighbours(i, &EIGHT[..4]).any(|q| q.samples > 1 && own(q))
                    }
                    _ => false,
                }
        };
        // In order, over the threads: the first level looks at every pixel.
        reached
            .par_iter()
            .copied()
            .filter(|&i| goes(i as usize))
            .collect()
    }
}

/// The test that sends a pixel on, scaled to compare in integers.
#[derive(Debug, Clone, Copy)]
enum Test {
    /// Mitchell's contrast, `Contrast::scaled_thresholds`.
    Contrast([u32; 3]),
    /// The range test, `Contrast::scaled_range`: where Mitchell's
    /// contrast is relative, so that a dim pixel passes on a step or two
    /// of difference, this one weighs a difference by what it adds to the
    /// pixel's squared error, since an image's RMSE is what it aims at
    /// (docs/performance.md, Contrast sampling).
    Range(u64),
}

impl Test {
    /// Whether the quantised range `lo..=hi` of `samples` samples passes:
    /// by Mitchell's contrast in some channel, or by a channel's range
    /// over √`samples`.
    fn passes(self, lo: [u8; 3], hi: [u8; 3], samples: u32) -> bool {
        match self {
            Test::Contrast(t) => passes(&t, lo, hi),
            Test::Range(r) => (0..3).any(|c| {
                let d = u64::from(hi[c].saturating_sub(lo[c])) * u64::from(Contrast::RANGE_SCALE);
                d * d > r * r * u64::from(samples)
            }),
        }
    }
}

/// `Contrast::passes` with the thresholds `t` scaled.
fn passes(t: &[u32; 3], lo: [u8; 3], hi: [u8; 3]) -> bool {
    (0..3).any(|c| {
        let (lo, hi) = (u32::from(lo[c]), u32::from(hi[c]));
        hi > lo && (hi - lo) * Contrast::SCALE > t[c] * (hi + lo)
    })
}

/// A pixel's neighbours, the four that share an edge first.
const EIGHT: [(isize, isize); 8] = [
    (-1, 0),
    (1, 0),
    (0, -1),
    (0, 1),
    (-1, -1),
    (1, -1),
    (-1, 1),
    (1, 1),
];

/// Sample `k` of a pixel: its place from the pixel's top-left corner, in
/// units of 1/`Contrast::GRID` pixel. Sample 0 is the centre; the others
/// come in pairs mirrored through it, so that every odd count of samples
/// is centred in the pixel (a sample set off-centre moves every edge it
/// sees). Samples 1..=64 are the centres of an 8×8 lattice over the
/// pixel, level by level (`LATTICE`): 1..=4 a rotated grid; 1..=16 one in
/// each cell of a 4×4 grid, two in each row and column of the lattice;
/// 1..=32 a checkerboard of it; 1..=64 all of it. Past 64, the first of
/// each pair is a point of the Sobol (0,2) sequence, off the lattice.
/// Mirrors sample_at() in shaders/contrast.glsl.
pub fn sample_at(k: u32) -> (u32, u32) {
    if k == 0 {
        return (Contrast::GRID / 2, Contrast::GRID / 2);
    }
    let j = (k - 1) / 2;
    let (x, y) = if let Some(&cell) = LATTICE.get(j as usize) {
        let step = Contrast::GRID / 8;
        let (cx, cy) = (u32::from(cell / 8), u32::from(cell % 8));
        (cx * step + step / 2, cy * step + step / 2)
    } else {
        let (sx, sy) = sobol(j);
        ((2 * sx + 1) % Contrast::GRID, (2 * sy + 3) % Contrast::GRID)
    };
    if k % 2 == 1 {
        (x, y)
    } else {
        (Contrast::GRID - x, Contrast::GRID - y)
    }
}

/// The first of each mirrored pair of samples 1..=64: cells of the
/// pixel's 8×8 lattice, numbered x·8 + y. Each level's cells are chosen
/// far from those before them. Until this lattice the pairs were Sobol
/// points moved off their own lattice by a small offset, which put a
/// point and its pair's mirror a few 1/512 apart: 33 such samples had
/// more error than uniform 4×4's 16 (docs/performance.md, Contrast
/// sampling).
const LATTICE: [u8; 32] = [
    16, 50, 2, 31, 6, 9, 20, 27, 0, 4, 11, 15, 18, 22, 25, 29, 1, 3, 5, 7, 8, 10, 12, 14, 17, 19,
    21, 23, 24, 26, 30, 28,
];

/// Point `k` (< 256) of the Sobol (0,2) sequence, both coordinates in
/// units of 1/256: the van der Corput radical inverse and Sobol's second
/// dimension, whose first 2^m points are stratified in every 2^-a × 2^-b
/// box with a + b = m.
pub fn sobol(k: u32) -> (u32, u32) {
    let x = (k & 0xff).reverse_bits() >> 24;
    let (mut y, mut v) = (0, 0x80);
    for bit in 0..8 {
        if k >> bit & 1 == 1 {
            y ^= v;
        }
        v ^= v >> 1;
    }
    (x, y)
}

/// Samples `first..first + count` of pixel (x, y) of the image: what a
/// renderer traces for one entry of a level's list.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Entry {
    /// The pixel's column in the image.
    pub x: u32,
    /// The pixel's row in the image.
    pub y: u32,
    /// The first sample's index (`sample_at`).
    pub first: u32,
    /// How many samples.
    pub count: u32,
}

/// What an entry's samples gave: their colours' sum, in sample order;
/// per channel their least and greatest colour clamped to 0..=1; the
/// first sample's tree word (`tree_word`) and whether the others' differ
/// from it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Batch<R> {
    /// The sum of the samples' colours, the first first.
    pub sum: Vec3<R>,
    /// The least clamped value per channel.
    pub least: [f32; 3],
    /// The greatest clamped value per channel.
    pub most: [f32; 3],
    /// The first sample's tree word.
    pub word: u32,
    /// Whether another sample's tree word differs from the first's.
    pub differ: bool,
}

/// A pixel's samples so far, for the next level's choice.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pixel {
    /// How many it has.
    pub samples: u32,
    /// Per channel, the least of its samples' clamped values, in steps of
    /// 1/255 (rounded to the nearest: quantising is monotonic, so this is
    /// the least of the samples' quantised values).
    pub lo: [u8; 3],
    /// Per channel, the greatest, as `lo`.
    pub hi: [u8; 3],
    /// The first sample's tree word.
    pub word: u32,
    /// Whether two of its samples' trees differ.
    pub trees_differ: bool,
}

impl Pixel {
    /// A pixel with no samples yet.
    const EMPTY: Pixel = Pixel {
        samples: 0,
        lo: [u8::MAX; 3],
        hi: [0; 3],
        word: tree_word::BASIS,
        trees_differ: false,
    };

    /// The pixel with one more batch of `count` samples.
    fn add<R>(&mut self, b: &Batch<R>, count: u32) {
        if self.samples == 0 {
            self.word = b.word;
        }
        self.trees_differ |= b.differ || b.word != self.word;
        let (least, most) = (b.least.map(quantise), b.most.map(quantise));
        self.lo = [0, 1, 2].map(|c| self.lo[c].min(least[c]));
        self.hi = [0, 1, 2].map(|c| self.hi[c].max(most[c]));
        self.samples += count;
    }
}

/// A colour value in 0..=1 in steps of 1/255, rounded to the nearest.
fn quantise(v: f32) -> u8 {
    // Non-negative (a NaN casts to 0 either way), so the cast's truncation
    // is the floor, with no call to libm's floor on x86-64's baseline: the
    // first level quantises six values a pixel.
    (f64::from(v).clamp(0.0, 1.0) * 255.0 + 0.5) as u8
}

/// The colours of `region` of a `size` image, sampled so: each level's
/// entries traced by `trace` (their batches in the entries' order), over
/// the region and `Contrast::MARGIN` pixels around it within the image,
/// so that a region's pixels are the whole image's. Each pixel's colour is
/// the sum of its batches, in order, times one over its samples.
/// `decider` takes the choice of each pixel of the region at each level
/// (the margin's replay it too, or take their own); the decisions come
/// back with the colours.
pub fn refine_levels<R: Real, E>(
    (contrast, decider): (&Contrast, Decider),
    region: Region,
    size: (u32, u32),
    mut trace: impl FnMut(&[Entry]) -> Result<Vec<Batch<R>>, E>,
) -> Result<(Vec<[f32; 3]>, Log), E> {
    let m = Contrast::MARGIN;
    let (x0, y0) = (region.x.saturating_sub(m), region.y.saturating_sub(m));
    let x1 = (region.x + region.width + m).min(size.0);
    let y1 = (region.y + region.height + m).min(size.1);
    let (w, h) = (x1 - x0, y1 - y0);
    let mut pixels = vec![Pixel::EMPTY; (w * h) as usize];
    let mut sums = vec![Vec3::<R>::zero(); (w * h) as usize];
    let mut going: Vec<u32> = (0..w * h).collect();
    let levels = contrast.levels();
    let mut log = Log::default();
    let inside = |x: u32, y: u32| region.contains(x, y);
    for (level, &reach) in levels.iter().enumerate() {
        // One entry a pixel: its new samples, summed in order on either
        // renderer, then added to its sum.
        let entries: Vec<Entry> = going
            .iter()
            .map(|&i| Entry {
                x: x0 + i % w,
                y: y0 + i / w,
                first: pixels[i as usize].samples,
                count: reach - pixels[i as usize].samples,
            })
            .collect();
        let batches = trace(&entries)?;
        // Each pixel once a level: its new state made over the threads,
        // then put in place.
        let added: Vec<(Pixel, Vec3<R>)> = going
            .par_iter()
            .zip(&entries)
            .zip(&batches)
            .map(|((&i, e), b)| {
                let mut p = pixels[i as usize];
                p.add(b, e.count);
                (p, sums[i as usize] + b.sum)
            })
            .collect();
        for (&i, (p, sum)) in going.iter().zip(added) {
            pixels[i as usize] = p;
            sums[i as usize] = sum;
        }
        if level + 1 == levels.len() {
            break;
        }
        let own = contrast.next(level, &pixels, w, &going);
        let mut own = own.into_iter().peekable();
        going.retain(|&i| {
            let goes = own.next_if_eq(&i).is_some();
            let (x, y) = (x0 + i % w, y0 + i / w);
            let k = key(level as u32, x, y);
            match decider.replay {
                _ if inside(x, y) => decider.decide(k, goes, &mut log),
                Some(r) => r.holds(k),
                None => goes,
            }
        });
        if going.is_empty() {
            break;
        }
    }
    let mut out = Vec::with_capacity(region.pixel_count() as usize);
    for y in region.y..region.y + region.height {
        for x in region.x..region.x + region.width {
            let i = ((y - y0) * w + (x - x0)) as usize;
            let n = R::of(f64::from(pixels[i].samples));
            out.push((sums[i] * (R::one() / n)).to_rgb());
        }
    }
    Ok((out, log))
}

#[cfg(test)]
#[path = "contrast_tests.rs"]
mod tests;
