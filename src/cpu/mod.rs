//! The CPU reference renderer: the model of docs/scene-format.md (Rays,
//! Shading) in f32 or f64, one function per stage of the shader (ray,
//! intersect, shade, trace) so that a disagreement points at one stage.

pub(crate) mod adaptive;
mod aov;
pub mod bound;
mod contrast;
pub(crate) mod intersect;
mod probe;
pub(crate) mod ray;
pub(crate) mod shade;
pub(crate) mod texture;
pub(crate) mod trace;
pub(crate) mod world;

use rayon::prelude::*;

use crate::accel::Accel;
use crate::raster::region::Region;
use crate::raster::Image;
use crate::sampling::Sampled;
use crate::scene::decisions::Kind;
use crate::scene::{PastBound, Scene};

pub use crate::base::real::Real;
use crate::stats::{Counts, Tally};
use world::World;

pub(crate) use probe::Probe;

/// Renders `scene` in precision `R`, rows in parallel, with the BVH where
/// `Accel::Auto` takes it (the image is the same either way).
pub fn render<R: Real>(scene: &Scene) -> Image {
    render_rows::<R>(scene, Accel::Auto, &|_| {})
}

/// As [`render`], with the given scene management, calling
/// `progress(rows_done)` as rows finish.
pub fn render_rows<R: Real>(scene: &Scene, accel: Accel, progress: &(dyn Fn(u64) + Sync)) -> Image {
    render_world(&World::<R>::new(scene, accel), progress)
}

/// As [`render_rows`], with what its sampling decided (`Scene::replay`):
/// None where the scene's sampling decides nothing.
pub fn render_sampled<R: Real>(
    scene: &Scene,
    accel: Accel,
    progress: &(dyn Fn(u64) + Sync),
) -> (Image, Option<Sampled>) {
    Prepared::<R>::new(scene, accel).render_sampled(progress)
}

/// The conditioning check's trial (`glint::condition`): `scene` in f64
/// with every hit point and the direction of every ray that leaves a
/// surface moved by `share` of its size, each its own way, as f32 rounds
/// them (`World::hit_move`); and what its sampling decided.
pub(crate) fn render_moved(
    scene: &Scene,
    accel: Accel,
    moves: (u64, f64),
    progress: &(dyn Fn(u64) + Sync),
) -> (Image, Option<Sampled>) {
    moved(scene, accel, moves).render_sampled(progress)
}

/// A conditioning trial's AOVs (`condition::judge_aovs`): `scene` in f64
/// with its hit points and leaving directions moved as `render_moved`
/// moves them.
pub(crate) fn aovs_moved(
    scene: &Scene,
    accel: Accel,
    moves: (u64, f64),
) -> Vec<crate::base::aov::Aov> {
    moved(scene, accel, moves).render_aovs(None, &|_| {}).1
}

/// `scene` laid out in f64 for a trial: its hit points and leaving
/// directions moved by `moves` (`World::hit_move`).
fn moved(scene: &Scene, accel: Accel, moves: (u64, f64)) -> Prepared<f64> {
    let mut world = World::<f64>::new(scene, accel);
    world.hit_move = Some(moves);
    Prepared(world)
}

/// The pixels of `region` of `scene`'s image (which must hold it): bit
/// for bit those of the whole render (docs/scale-out.md).
pub fn render_region<R: Real>(
    scene: &Scene,
    accel: Accel,
    region: Region,
    progress: &(dyn Fn(u64) + Sync),
) -> Image {
    Prepared::<R>::new(scene, accel).render_region(region, progress)
}

/// The f64 reference of `scene`, the oracle the other renders are measured
/// against: refused where a pixel leaves the model's bound ([`Scene::within`]).
pub fn reference(scene: &Scene, accel: Accel) -> Result<Image, PastBound> {
    let image = render_rows::<f64>(scene, accel, &|_| {});
    scene.within(&image, "f64")?;
    Ok(image)
}

/// A scene laid out for the CPU reference in precision `R`: the primitives
/// in `R`, the camera relative to the eye, and the BVH where `accel` takes
/// one. Making it is a render's setup; each render of it is the trace.
///
/// ```
/// use glint::accel::Accel;
/// use glint::cpu::Prepared;
/// use glint::scene::{Overrides, Scene};
///
/// let small = Overrides { width: Some(32), height: Some(24), ..Overrides::default() };
/// let scene = Scene::load("scenes/seed-fig5.toml".as_ref(), &small)?;
/// let prepared = Prepared::<f64>::new(&scene, Accel::Auto);
/// let (image, counts) = prepared.render_counted(&|_rows| {});
/// println!("{} shadow rays", counts.rays().shadow);
/// # assert_eq!(image.width, scene.width);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct Prepared<R: Real>(World<R>);

impl<R: Real> Prepared<R> {
    /// Lays `scene` out, building the BVH where `accel` takes one.
    pub fn new(scene: &Scene, accel: Accel) -> Self {
        Self(World::new(scene, accel))
    }

    /// Seconds spent building the light buffers and the eye's tiles
    /// (`Accel::Tables`); 0 without them.
    pub fn tables_s(&self) -> f64 {
        self.0.tables.as_ref().map_or(0.0, |t| t.build_s)
    }

    /// Renders skip the rows they have not begun once `flag` is set (a
    /// host's Ctrl-C, as the Python module's): such a render's image is
    /// incomplete, and whoever set the flag discards it. A later render
    /// runs whole once the flag is cleared.
    pub fn stop_when(&mut self, flag: std::sync::Arc<std::sync::atomic::AtomicBool>) {
        self.0.stop = Some(flag);
    }

    /// The pixels of `region` of the image: bit for bit those of the
    /// whole render.
    pub fn render_region(&self, region: Region, progress: &(dyn Fn(u64) + Sync)) -> Image {
        render_tallied::<R, ()>(&self.0, Some(region), progress).0
    }

    /// The image, calling `progress(rows_done)` as rows finish.
    pub fn render(&self, progress: &(dyn Fn(u64) + Sync)) -> Image {
        render_world(&self.0, progress)
    }

    /// The image, with what its sampling decided (`cpu::render_sampled`).
    pub fn render_sampled(&self, progress: &(dyn Fn(u64) + Sync)) -> (Image, Option<Sampled>) {
        let (image, (), sampled) = render_tallied(&self.0, None, progress);
        (image, sampled)
    }

    /// The image, with the rays it cast and the tests they cost.
    pub fn render_counted(&self, progress: &(dyn Fn(u64) + Sync)) -> (Image, Counts) {
        let (image, counts, _) = render_tallied(&self.0, None, progress);
        (image, counts)
    }

    /// `region` of the image and the render's counts of rays, tests and
    /// BVH nodes within it.
    pub fn render_region_counted(
        &self,
        region: Region,
        progress: &(dyn Fn(u64) + Sync),
    ) -> (Image, Counts) {
        let (image, counts, _) = render_tallied(&self.0, Some(region), progress);
        (image, counts)
    }

    /// The direction of the eye ray through sample (i, j) of pixel (x, y),
    /// as this precision computes it.
    pub fn eye_ray_direction(&self, x: u32, y: u32, i: u32, j: u32) -> glam::DVec3 {
        let d = ray::primary_ray(&self.0, x, y, i, j).dir;
        glam::DVec3::new(d.x.to_f64(), d.y.to_f64(), d.z.to_f64())
    }
}

/// Renders a prepared world (tests use it to alter the BVH).
pub(crate) fn render_world<R: Real>(world: &World<R>, progress: &(dyn Fn(u64) + Sync)) -> Image {
    render_tallied::<R, ()>(world, None, progress).0
}

/// As [`render_rows`], with the rays it cast and the tests they cost
/// (`glint render --stats`).
pub fn render_counted<R: Real>(
    scene: &Scene,
    accel: Accel,
    progress: &(dyn Fn(u64) + Sync),
) -> (Image, Counts) {
    Prepared::<R>::new(scene, accel).render_counted(progress)
}

/// Renders `region` of the world's image (None: all of it), with its
/// counts and what its sampling decided, where it decides.
fn render_tallied<R: Real, T: Tally>(
    world: &World<R>,
    region: Option<Region>,
    progress: &(dyn Fn(u64) + Sync),
) -> (Image, T, Option<Sampled>) {
    // The pixels traced: the region's corners where the world samples them.
    let traced = match region {
        Some(r) if world.corners => r.corners(),
        Some(r) => r,
        None => Region::whole(world.width, world.height),
    };
    if let Some(c) = &world.contrast {
        let (image, counts, log) = contrast::render(world, traced, c, progress);
        return (image, counts, Some(log.sampled(Kind::Contrast)));
    }
    let (width, height, samples) = (traced.width, traced.height, world.samples);
    let inv = R::one() / R::of(f64::from(samples * samples));
    let mut pixels = vec![[0.0f32; 3]; width as usize * height as usize];
    let counts = pixels
        .par_chunks_mut(width as usize)
        .enumerate()
        .map(|(row_index, row)| {
            let mut counts = T::default();
            if world.stopped() {
                progress(1);
                return counts;
            }
            let y = traced.y as usize + row_index;
            for (column, px) in row.iter_mut().enumerate() {
                let x = traced.x as usize + column;
                let mut sum = crate::base::real::Vec3::zero();
                for j in 0..samples {
                    for i in 0..samples {
                        let ray = ray::primary_ray(world, x as u32, y as u32, i, j);
                        sum += trace::trace(world, ray, &mut counts);
                    }
                }
                let c = sum * inv;
                *px = c.to_rgb();
            }
            progress(1);
            counts
        })
        .reduce(T::default, T::merge);
    let image = Image::new(width, height, pixels);
    if world.stopped() {
        return (image, counts, None);
    }
    match world.adaptive {
        Some((threshold, levels)) => {
            let (image, more, log) = adaptive::resolve(world, &image, traced, threshold, levels);
            (image, counts.merge(more), Some(log.sampled(Kind::Adaptive)))
        }
        None if world.corners => (image.corner_mean(), counts, None),
        None => (image, counts, None),
    }
}

#[cfg(test)]
mod bvh_tests;

#[cfg(test)]
mod stop_tests {
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::Arc;

    use super::Prepared;
    use crate::accel::Accel;
    use crate::scene::{Overrides, Scene};

    /// Once the stop flag is set no row is traced (a row's progress is
    /// still reported), and cleared, the same prepared scene renders the
    /// whole image again (the Python module's Ctrl-C).
    #[test]
    fn a_stop_skips_every_row_and_a_clear_renders_them_again() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/seed-fig4.toml");
        let small = Overrides {
            width: Some(24),
            height: Some(16),
            ..Overrides::default()
        };
        let scene = Scene::load(&path, &small).unwrap();
        let mut prepared = Prepared::<f64>::new(&scene, Accel::Auto);
        let whole = prepared.render(&|_| {});
        let stop = Arc::new(AtomicBool::new(true));
        prepared.stop_when(stop.clone());
        let (stopped, counts) = prepared.render_counted(&|_| {});
        assert_eq!(counts.rays().eye, 0, "no ray was cast");
        assert!(stopped != whole);
        stop.store(false, Ordering::Relaxed);
        assert!(prepared.render(&|_| {}) == whole);
    }
}
