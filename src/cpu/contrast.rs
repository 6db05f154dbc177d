//! Contrast sampling on the CPU (docs/scene-format.md, Rays;
//! `crate::sampling::contrast`): the levels are `refine_levels`', which the
//! GPU runs too; this file traces a level's entries over the threads.
//! Mirrors shaders/contrast.glsl.

use rayon::prelude::*;

use super::ray::ray_through;
use super::trace::trace;
use super::world::World;
use crate::base::aov::EyeHit;
use crate::base::real::{Real, Vec3};
use crate::base::record::Event;
use crate::base::tally::tree_word;
use crate::raster::region::Region;
use crate::raster::Image;
use crate::sampling::contrast::{refine_levels, sample_at, Batch, Entry};
use crate::sampling::Log;
use crate::scene::Contrast;
use crate::stats::{Counter, RayType, Tally};

/// The pixels of `region`, sampled as `contrast` says, and the decisions
/// taken (its own, or replayed: `World::decider`).
pub fn render<R: Real, T: Tally>(
    w: &World<R>,
    region: Region,
    contrast: &Contrast,
    progress: &(dyn Fn(u64) + Sync),
) -> (Image, T, Log) {
    let mut counts = T::default();
    let trace_entries = |entries: &[Entry]| {
        let parts: Vec<(Vec<Batch<R>>, T)> = entries
            .par_chunks(64)
            .map(|chunk| {
                let mut tally = T::default();
                let batches = if w.stopped() {
                    vec![empty(); chunk.len()]
                } else {
                    chunk.iter().map(|e| samples(w, e, &mut tally)).collect()
                };
                (batches, tally)
            })
            .collect();
        let mut batches = Vec::with_capacity(entries.len());
        for (b, t) in parts {
            batches.extend(b);
            counts = std::mem::take(&mut counts).merge(t);
        }
        Ok::<_, std::convert::Infallible>(batches)
    };
    let size = (w.width, w.height);
    let Ok((pixels, log)) = refine_levels((contrast, w.decider()), region, size, trace_entries);
    progress(u64::from(region.height));
    (Image::new(region.width, region.height, pixels), counts, log)
}

/// A batch of nothing traced (a stopped render's).
fn empty<R: Real>() -> Batch<R> {
    Batch {
        sum: Vec3::zero(),
        least: [0.0; 3],
        most: [0.0; 3],
        word: tree_word::BASIS,
        differ: false,
    }
}

/// The samples of entry `e`, traced one after another. Mirrors
/// contrast_samples() in shaders/contrast.glsl.
fn samples<R: Real, T: Tally>(w: &World<R>, e: &Entry, tally: &mut T) -> Batch<R> {
    let grid = R::of(f64::from(Contrast::GRID));
    let (zero, one) = (R::zero(), R::one());
    let mut sum = Vec3::zero();
    let mut least = Vec3::splat(one);
    let mut most = Vec3::splat(zero);
    let mut first = None;
    let mut differ = false;
    for k in e.first..e.first + e.count {
        let (u, v) = sample_at(k);
        let px = R::of(f64::from(e.x)) + R::of(f64::from(u)) / grid;
        let py = R::of(f64::from(e.y)) + R::of(f64::from(v)) / grid;
        let mut signed = Signed {
            inner: std::mem::take(tally),
            word: tree_word::BASIS,
        };
        let c = trace(w, ray_through(w, px, py), &mut signed);
        *tally = signed.inner;
        sum += c;
        let clamp = |v: R| v.max(zero).min(one);
        let c = Vec3::new(clamp(c.x), clamp(c.y), clamp(c.z));
        least = Vec3::new(least.x.min(c.x), least.y.min(c.y), least.z.min(c.z));
        most = Vec3::new(most.x.max(c.x), most.y.max(c.y), most.z.max(c.z));
        differ |= *first.get_or_insert(signed.word) != signed.word;
    }
    Batch {
        sum,
        least: least.to_rgb(),
        most: most.to_rgb(),
        word: first.unwrap_or(tree_word::BASIS),
        differ,
    }
}

/// A tally that also hashes the ray tree's branches (`tree_word`), passing
/// everything else on to the tally inside.
#[derive(Default)]
struct Signed<T> {
    inner: T,
    word: u32,
}

impl<T: Tally> Tally for Signed<T> {
    #[inline(always)]
    fn count(&mut self, c: Counter) {
        self.inner.count(c);
    }
    #[inline(always)]
    fn ray_type(&mut self, t: RayType) {
        self.inner.ray_type(t);
    }
    fn merge(self, other: Self) -> Self {
        Self {
            inner: self.inner.merge(other.inner),
            word: self.word,
        }
    }
    #[inline(always)]
    fn record(&mut self, event: impl FnOnce() -> Event) {
        self.inner.record(event);
    }
    #[inline(always)]
    fn eye_hit(&mut self, hit: impl FnOnce() -> EyeHit) {
        self.inner.eye_hit(hit);
    }
    #[inline(always)]
    fn branch(&mut self, word: u32) {
        self.word = tree_word::fold(self.word, word);
    }
}
