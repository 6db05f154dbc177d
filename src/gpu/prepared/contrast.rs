//! Contrast sampling of a prepared scene: level by level
//! (`sampling::contrast::refine_levels`, as the CPU runs them), each level's
//! entries a list bound on the scene's one stage (`Prepared::trace_level`,
//! shaders/contrast.glsl), whose words become the level's batches.

use rayon::prelude::*;

use super::refinement::HostShare;
use super::{Prepared, Rendered};
use crate::base::real::{Real, Vec3};
use crate::gpu::refine;
use crate::gpu::times::RenderTimes;
use crate::gpu::variant::CONTRAST_OUTPUTS;
use crate::gpu::GpuError;
use crate::raster::region::Region;
use crate::raster::Image;
use crate::sampling::contrast::{refine_levels, Batch, Entry};
use crate::sampling::Decider;
use crate::scene::decisions::Kind;
use crate::scene::Contrast;
use crate::stats::Counts;

impl Prepared {
    /// `region` sampled as `contrast` says, with the levels' times and
    /// counts; the host's share (listing, choosing, summing) is
    /// `refine_s`.
    pub(super) fn contrast<R: Real>(
        &mut self,
        contrast: &Contrast,
        region: Region,
        mut times: RenderTimes,
    ) -> Result<Rendered, GpuError> {
        let host = HostShare::start(&times);
        let mut counts: Option<Counts> = None;
        let size = self.size;
        let replay = self.replay.clone();
        let decider = Decider {
            replay: replay.as_deref(),
        };
        let (pixels, log) = refine_levels((contrast, decider), region, size, |entries| {
            self.trace_entries::<R>(entries, &mut times, &mut counts)
        })?;
        host.end(&mut times);
        Ok(Rendered {
            image: Image::new(region.width, region.height, pixels),
            times,
            counts,
            record: None,
            aovs: None,
            sampled: Some(log.sampled(Kind::Contrast)),
        })
    }

    /// One level: the batches of `entries`, one invocation an entry.
    fn trace_entries<R: Real>(
        &mut self,
        entries: &[Entry],
        times: &mut RenderTimes,
        counts: &mut Option<Counts>,
    ) -> Result<Vec<Batch<R>>, GpuError> {
        let n = entries.len() as u32;
        let rays = entries.iter().map(|e| e.count).max().unwrap_or(1);
        let list = refine::entries(entries);
        let words = self.trace_level(&list, n, rays, times, counts)?;
        let per = CONTRAST_OUTPUTS as usize;
        Ok(words[..n as usize * per]
            .par_chunks_exact(per)
            .map(|w| Batch {
                sum: Vec3::of_rgb(w[0]),
                least: w[1],
                most: w[2],
                word: w[3][0] as u32 | (w[3][1] as u32) << 16,
                differ: w[3][2] != 0.0,
            })
            .collect())
    }
}
