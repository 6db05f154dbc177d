//! A render's AOVs on the CPU (src/base/aov.rs): each pixel traced as a
//! render traces it, with a tally of its own that counts its rays and
//! keeps its first eye ray's first hit, as shaders/aov.glsl does.

use rayon::prelude::*;

use super::{ray, trace, Prepared};
use crate::base::aov::{Aov, EyeHit};
use crate::base::real::{Real, Vec3};
use crate::base::tally::Tally;
use crate::raster::region::Region;
use crate::raster::Image;
use crate::stats::{Counter, Counts, RayType};

/// One pixel's tally: the rays its samples traced, and what its first
/// sample's eye ray met first; the counts go on to `inner` (the render's
/// `--stats`, or `()`).
#[derive(Default)]
struct Pixel<T> {
    inner: T,
    rays: u32,
    /// Whether the sample being traced is the pixel's first.
    first: bool,
    hit: Option<EyeHit>,
}

impl<T: Tally> Tally for Pixel<T> {
    fn count(&mut self, c: Counter) {
        if matches!(
            c,
            Counter::Eye | Counter::Reflect | Counter::Refract | Counter::Shadow
        ) {
            self.rays += 1;
        }
        self.inner.count(c);
    }
    fn ray_type(&mut self, t: RayType) {
        self.inner.ray_type(t);
    }
    fn merge(self, _: Self) -> Self {
        unreachable!("a pixel's tally is its own")
    }
    fn eye_hit(&mut self, hit: impl FnOnce() -> EyeHit) {
        if self.first {
            self.hit = Some(hit());
        }
    }
}

impl<R: Real> Prepared<R> {
    /// Whether its pixels are their own samples' means, which AOVs are
    /// of: not a corner grid's (corners and adaptive sampling).
    pub fn has_pixel_samples(&self) -> bool {
        !self.0.corners
    }

    /// `region` of the image (None: all of it), the same pixels as a
    /// render's, and each pixel's AOVs, row by row as rows finish
    /// (`progress`). The scene samples its pixels' own points
    /// (`has_pixel_samples`).
    pub fn render_aovs(
        &self,
        region: Option<Region>,
        progress: &(dyn Fn(u64) + Sync),
    ) -> (Image, Vec<Aov>) {
        let (image, aovs, ()) = self.aovs_tallied(region, progress);
        (image, aovs)
    }

    /// As `render_aovs`, with the render's counts (`--stats`).
    pub fn render_aovs_counted(
        &self,
        region: Option<Region>,
        progress: &(dyn Fn(u64) + Sync),
    ) -> (Image, Vec<Aov>, Counts) {
        self.aovs_tallied(region, progress)
    }

    /// As `render_aovs`, with the counts as `T` keeps them.
    fn aovs_tallied<T: Tally>(
        &self,
        region: Option<Region>,
        progress: &(dyn Fn(u64) + Sync),
    ) -> (Image, Vec<Aov>, T) {
        let world = &self.0;
        assert!(
            self.has_pixel_samples(),
            "AOVs are of a pixel's own samples"
        );
        let r = region.unwrap_or_else(|| Region::whole(world.width, world.height));
        let (width, samples) = (r.width as usize, world.samples);
        let inv = R::one() / R::of(f64::from(samples * samples));
        let n = width * r.height as usize;
        let mut pixels = vec![[0.0f32; 3]; n];
        let mut aovs = vec![Aov { hit: None, rays: 0 }; n];
        let counts = pixels
            .par_chunks_mut(width)
            .zip(aovs.par_chunks_mut(width))
            .enumerate()
            .map(|(row, (colours, values))| {
                let mut counts = T::default();
                if world.stopped() {
                    progress(1);
                    return counts;
                }
                let y = r.y + row as u32;
                for (column, (px, aov)) in colours.iter_mut().zip(values).enumerate() {
                    let x = r.x + column as u32;
                    let mut tally = Pixel::<T>::default();
                    let mut sum = Vec3::zero();
                    for j in 0..samples {
                        for i in 0..samples {
                            tally.first = i == 0 && j == 0;
                            let eye = ray::primary_ray(world, x, y, i, j);
                            sum += trace::trace(world, eye, &mut tally);
                        }
                    }
                    *px = (sum * inv).to_rgb();
                    *aov = Aov {
                        hit: tally.hit,
                        rays: tally.rays,
                    };
                    counts = counts.merge(tally.inner);
                }
                progress(1);
                counts
            })
            .reduce(T::default, T::merge);
        (Image::new(r.width, r.height, pixels), aovs, counts)
    }
}
