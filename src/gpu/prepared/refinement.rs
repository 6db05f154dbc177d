//! Adaptive sampling's refinement of a prepared scene: level by level, each
//! level's points a list dispatched on a stage of its own
//! (shaders/adaptive.glsl), after the corners' pass. Contrast sampling's
//! levels are lists too, bound on the scene's one stage (`trace_level`).

use std::time::Instant;

use super::{BoundStage, Prepared, Rendered};
use crate::base::interface::Array;
use crate::base::real::{Real, Vec3};
use crate::gpu::refine;
use crate::gpu::resident::StageInput;
use crate::gpu::times::RenderTimes;
use crate::gpu::variant::{self};
use crate::gpu::work::RAYS_PER_DISPATCH;
use crate::gpu::GpuError;
use crate::raster::region::Region;
use crate::raster::Image;
use crate::sampling::adaptive::Point;
use crate::sampling::Decider;
use crate::scene::decisions::Kind;
use crate::scene::Adaptive;
use crate::stats::{Counts, Tally};

impl Prepared {
    /// Adaptive sampling's refinement of `region`, whose corners are
    /// `corners`: level by level (`sampling::adaptive`), each level's points one
    /// list dispatched on the refinement's stage. The refined colours
    /// replace those pixels' corner means in `rendered`; the times and
    /// counts join the first pass's.
    pub(super) fn refine<R: Real>(
        &mut self,
        adaptive: &Adaptive,
        corners: &Image,
        region: Region,
        rendered: &mut Rendered,
    ) -> Result<(), GpuError> {
        let host = HostShare::start(&rendered.times);
        let threshold = R::of(adaptive.threshold_steps());
        let (times, counts) = (&mut rendered.times, &mut rendered.counts);
        let image = &mut rendered.image;
        let replay = self.replay.clone();
        let decider = Decider {
            replay: replay.as_deref(),
        };
        let log = crate::sampling::adaptive::refine_image(
            corners,
            (region.x, region.y),
            (adaptive, decider),
            threshold,
            |points| self.trace_points::<R>(points, times, counts),
            |place, v: Vec3<R>| image.pixels[place] = v.to_rgb(),
        )?;
        rendered.sampled = Some(log.sampled(Kind::Adaptive));
        host.end(&mut rendered.times);
        Ok(())
    }

    /// One level of the refinement: the colours of `points`, traced on the
    /// refinement's stage, made for this list (`REFINE_POINTS` an
    /// invocation, the invocations laid out `REFINE_WIDTH` wide).
    fn trace_points<R: Real>(
        &mut self,
        points: &[Point],
        times: &mut RenderTimes,
        counts: &mut Option<Counts>,
    ) -> Result<Vec<Vec3<R>>, GpuError> {
        let n = points.len() as u32;
        let per = variant::REFINE_POINTS;
        let list = refine::list(points);
        let pixels = self.trace_list(&list, n.div_ceil(per), per, times, counts)?;
        Ok(pixels[..n as usize]
            .iter()
            .map(|&c| Vec3::of_rgb(c))
            .collect())
    }

    /// Traces adaptive sampling's points, a list on the refinement's stage
    /// made for it, in `invocations` laid out `REFINE_WIDTH` wide, each
    /// tracing at most `rays` eye rays. What the invocations wrote, in
    /// order; their counts join `counts`.
    fn trace_list(
        &mut self,
        list: &Array<'static>,
        invocations: u32,
        rays: u32,
        times: &mut RenderTimes,
        counts: &mut Option<Counts>,
    ) -> Result<Vec<[f32; 3]>, GpuError> {
        let per = rays.max(1);
        let (entries, tile) = list_tiles(invocations, per);
        // The list is this call's alone: the stage binds it anew, with the
        // refinement's pipeline, looked up once for this prepared scene.
        let (pipeline, variant) = match self.refine.take() {
            Some(BoundStage {
                pipeline, variant, ..
            }) => (pipeline, variant),
            None => {
                let variant = self.main.variant.listing(None);
                let defines = self.shared.defines_of(&variant);
                let (pipeline, setup) = self.shared.pipeline(&variant, &defines)?;
                times.setup.compile_s += setup.compile_s;
                times.setup.pipeline_s += setup.pipeline_s;
                (pipeline, variant)
            }
        };
        let t0 = Instant::now();
        let stage = BoundStage::new(
            &self.shared,
            pipeline,
            variant,
            &self.scene,
            tile,
            StageInput::Refine(list),
        )?;
        self.refine = Some(stage);
        times.upload_s += t0.elapsed().as_secs_f64();
        times.setup.driver_compile_s += self.compile_on_driver(true)?;
        let (words, more) = self.tiles(true, entries, f64::from(per), times, &|_| {})?;
        merge_counts(counts, more);
        Ok(words)
    }

    /// A level of contrast sampling, a list of `invocations` laid out
    /// `REFINE_WIDTH` wide, each tracing at most `rays` eye rays, traced on
    /// the main stage, which is the levels' own (`Gather::stage`): its list
    /// bound in place of the last, its output and counters kept, so that a
    /// level makes no buffer but its list's, and first touches no output.
    /// What the invocations wrote, in order; their counts join `counts`.
    pub(super) fn trace_level(
        &mut self,
        list: &Array<'static>,
        invocations: u32,
        rays: u32,
        times: &mut RenderTimes,
        counts: &mut Option<Counts>,
    ) -> Result<Vec<[f32; 3]>, GpuError> {
        let per = rays.max(1);
        let (entries, tile) = list_tiles(invocations, per);
        // The stage's output was sized for the first level, one entry a
        // pixel of the image (`Prepared::new`): no later level's tile is
        // wider or taller, since it lists fewer entries of more rays.
        assert!(
            self.main.variant.contrast.is_some() && self.main.holds(tile),
            "a contrast scene's stage holds each level"
        );
        let t0 = Instant::now();
        self.main.bind_list(&self.shared, &self.scene, list)?;
        times.upload_s += t0.elapsed().as_secs_f64();
        // The level's tile, within the stage's output; the stage keeps its
        // own for the next level.
        let made = std::mem::replace(&mut self.main.tile, tile);
        let traced = self.tiles(false, entries, f64::from(per), times, &|_| {});
        self.main.tile = made;
        let (words, more) = traced?;
        merge_counts(counts, more);
        Ok(words)
    }
}

/// A level's counts joined to the levels' before it.
fn merge_counts(counts: &mut Option<Counts>, more: Option<Counts>) {
    *counts = match (counts.take(), more) {
        (Some(a), Some(b)) => Some(Tally::merge(a, b)),
        (a, b) => a.or(b),
    };
}

/// A list of `invocations`, each tracing at most `per` eye rays, laid out
/// `REFINE_WIDTH` wide (the region the stage dispatches), and the tile it
/// is dispatched in: as many rows as `RAYS_PER_DISPATCH` rays allow.
pub(super) fn list_tiles(invocations: u32, per: u32) -> (Region, (u32, u32)) {
    let width = variant::REFINE_WIDTH.min(invocations);
    let entries = Region::whole(width, invocations.div_ceil(width));
    let rows = (RAYS_PER_DISPATCH / u64::from(width * per.max(1))) as u32;
    (entries, (width, rows.clamp(1, entries.height)))
}

/// The host's share of a pass over levels (adaptive sampling's refinement,
/// contrast sampling): its time, less what its dispatches, readbacks,
/// uploads and compiles took, goes to `refine_s`.
pub(super) struct HostShare {
    start: Instant,
    accounted: f64,
}

impl HostShare {
    /// Starts counting, with `times` as they are.
    pub(super) fn start(times: &RenderTimes) -> Self {
        Self {
            start: Instant::now(),
            accounted: Self::accounted(times),
        }
    }

    /// Adds the host's share since the start to `times.refine_s`.
    pub(super) fn end(self, times: &mut RenderTimes) {
        let spent = Self::accounted(times) - self.accounted;
        times.refine_s += (self.start.elapsed().as_secs_f64() - spent).max(0.0);
    }

    /// What the dispatches, readbacks, uploads and compiles took so far.
    fn accounted(t: &RenderTimes) -> f64 {
        t.total_s() + t.setup.compile_s + t.setup.pipeline_s + t.setup.driver_compile_s
    }
}
