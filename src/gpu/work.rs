//! How much work a tile is: the size of the tiles a scene is cut into, and
//! how long the watchdog waits for one.

use std::time::Duration;

use super::variant::Variant;
use super::WORKGROUP;
use crate::scene::Scene;

/// Rays per dispatch at most: small enough that no single dispatch runs long
/// enough to trip a desktop GPU's watchdog, large enough to fill one.
pub(crate) const RAYS_PER_DISPATCH: u64 = 1 << 22;
/// The most a tile's wavefront paths may take of device memory.
const PATH_BYTES: u64 = 256 << 20;

/// The slowest rate glint expects of any device, in ray–primitive tests
/// (or BVH node visits) per second: a tenth of what lavapipe reached on 2
/// cores before the BVH. A tile's wait is its work at this rate, and at
/// least `MIN_TIMEOUT`.
const SLOWEST_TESTS_PER_S: f64 = 2e7;
const MIN_TIMEOUT: Duration = Duration::from_secs(10);

/// The longest wait for a driver's compile of one pipeline (its first
/// dispatch, which shades no pixel): lavapipe took up to 12 s for the f64
/// generic shader on 2 cores. Past it the device is taken to be hung.
pub const COMPILE_TIMEOUT: Duration = Duration::from_secs(300);

/// What a traced scene asks of each pixel, kept from the scene when it is
/// prepared so that the prepared object holds no copy of it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PixelWork {
    pub width: u32,
    pub height: u32,
    samples: u32,
    max_depth: u32,
    lights: usize,
    objects: usize,
    unbounded: usize,
    /// Node visits and tests a ray makes through the built BVH
    /// (`Bvh::ray_cost`), where it is known.
    tree: Option<f64>,
}

impl PixelWork {
    pub fn of(scene: &Scene) -> Self {
        Self {
            width: scene.width,
            height: scene.height,
            samples: scene.samples,
            max_depth: scene.max_depth,
            lights: scene.lights.len(),
            objects: scene.prims.len(),
            unbounded: scene.prims.len() - scene.prims.bounded_count(),
            tree: None,
        }
    }

    /// The same work, traced through a tree of `ray_cost` (the BVH that was
    /// built, where there is one).
    pub fn through(self, ray_cost: Option<f64>) -> Self {
        Self {
            tree: ray_cost,
            ..self
        }
    }

    /// The longest wait for a tile of `pixels`: its rays (samples, bounces,
    /// a shadow ray a light) times the tests a ray makes (every object, or
    /// about 64 node visits and 8 a doubling of the spheres through a BVH,
    /// or what the built tree costs where that is more: a tree of a million
    /// identical faces costs a million).
    pub fn timeout(&self, pixels: u64, bvh: bool) -> Duration {
        let rays = pixels as f64
            * f64::from(self.samples * self.samples)
            * f64::from(self.max_depth)
            * (1.0 + self.lights as f64);
        let objects = self.objects.max(1) as f64;
        let per_ray = if bvh {
            // A walk visits at most every node (2 a primitive) and tests every one.
            let good = (64.0 + 8.0 * objects.log2()).min(3.0 * objects);
            good.max(self.tree.unwrap_or(0.0)) + self.unbounded as f64
        } else {
            objects
        };
        Duration::from_secs_f64(rays * per_ray / SLOWEST_TESTS_PER_S).max(MIN_TIMEOUT)
    }

    /// Segments a wavefront submission advances every path by: a pixel's
    /// whole tree where it is a reflection chain, so that most tiles take
    /// one submission.
    pub fn rounds_per_submit(&self) -> u32 {
        (self.samples * self.samples * self.max_depth).clamp(1, 256)
    }

    /// Tile size in pixels: within the rays-per-dispatch budget and the
    /// device's storage buffer range (`range`), whole rows where the image
    /// is narrow.
    pub fn tile_size(&self, variant: &Variant, range: u32) -> (u32, u32) {
        let rays_per_pixel = u64::from(self.samples * self.samples);
        let range = u64::from(range);
        let mut by_range = range / 16;
        if variant.wavefront {
            // The paths' buffers: within the range, and within PATH_BYTES.
            let (reals, words) = variant.path_bytes();
            let path = reals + words;
            by_range = by_range.min(range / path).min(PATH_BYTES / path);
        }
        let pixels = (RAYS_PER_DISPATCH / rays_per_pixel)
            .min(by_range)
            .max(u64::from(WORKGROUP * WORKGROUP));
        let width = self.width.min(2048);
        let height = (pixels / u64::from(width)).clamp(1, u64::from(self.height)) as u32;
        (width, height)
    }
}

/// The longest wait for a tile of `pixels` of `scene`, traced through a
/// BVH where `bvh` (`PixelWork::timeout`).
pub fn tile_timeout(scene: &Scene, pixels: u64, bvh: bool) -> Duration {
    PixelWork::of(scene).timeout(pixels, bvh)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tile of a tree that costs a million a ray (identical
    /// faces) waits for that cost, not for a good tree's.
    #[test]
    fn the_watchdog_waits_for_the_tree_that_was_built() {
        let work = PixelWork {
            width: 64,
            height: 48,
            samples: 1,
            max_depth: 3,
            lights: 1,
            objects: 1_000_000,
            unbounded: 0,
            tree: None,
        };
        let pixels = 64 * 48;
        let rays = pixels as f64 * 3.0 * 2.0;
        let good = work.timeout(pixels, true);
        assert_eq!(good, MIN_TIMEOUT);
        let bad = work.through(Some(1.1e6)).timeout(pixels, true);
        assert!(
            bad.as_secs_f64() >= rays * 1.1e6 / SLOWEST_TESTS_PER_S,
            "{bad:?}"
        );
        // A good tree keeps its wait.
        assert_eq!(work.through(Some(30.0)).timeout(pixels, true), good);
    }
}
