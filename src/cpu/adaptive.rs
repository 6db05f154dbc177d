//! Whitted's adaptive antialiasing (docs/scene-format.md, Rays): a pixel
//! whose corners differ by more than the threshold is split into four,
//! each quarter in turn, down to the scene's level, and its colour is the
//! mean of its squares' corners weighted by their areas. The pixels to
//! split are chosen from the corner grid (`Adaptive::splits`); the levels
//! are `sampling::adaptive`'s, which the GPU runs too, with this file's tracer
//! swapped for one dispatch a level (shaders/adaptive.glsl).

use rayon::prelude::*;

use super::ray::ray_through;
use super::trace::trace;
use super::world::World;
use crate::base::real::{Real, Vec3};
use crate::raster::region::Region;
use crate::raster::Image;
use crate::sampling::adaptive::{refine_image, Point};
use crate::sampling::Log;
use crate::scene::Adaptive;
use crate::stats::Tally;

/// The pixels of the image of corners `grid` (traced over `traced`, the
/// corners of a region): each the mean of its corners, or refined where
/// they differ by more than `threshold` steps (chosen as the GPU chooses,
/// by `Adaptive::splits` on the f32 corners, or replayed: `World::decider`),
/// and the decisions taken.
pub fn resolve<R: Real, T: Tally>(
    w: &World<R>,
    grid: &Image,
    traced: Region,
    threshold: R,
    levels: u32,
) -> (Image, T, Log) {
    let choice = Adaptive {
        threshold: threshold.to_f64() / Adaptive::STEPS,
        levels,
    };
    let mut image = grid.corner_mean();
    let mut counts = T::default();
    let trace = |points: &[Point]| {
        let (colours, tally) = trace_points(w, points);
        counts = std::mem::take(&mut counts).merge(tally);
        Ok::<_, std::convert::Infallible>(colours)
    };
    let put = |place: usize, v: Vec3<R>| {
        image.pixels[place] = v.to_rgb();
    };
    let origin = (traced.x, traced.y);
    let Ok(log) = refine_image(grid, origin, (&choice, w.decider()), threshold, trace, put);
    (image, counts, log)
}

/// The colours of `points` (in pixels of the image, as the corner grid's
/// continuous coordinates, whose pixel centres are the image's corners),
/// traced over the threads, and what they cost.
fn trace_points<R: Real, T: Tally>(w: &World<R>, points: &[Point]) -> (Vec<Vec3<R>>, T) {
    let half = R::of(0.5);
    // In chunks, each with one tally: a tally a point would cost more to
    // merge than some points cost to trace.
    let chunks: Vec<(Vec<Vec3<R>>, T)> = points
        .par_chunks(256)
        .map(|chunk| {
            let mut tally = T::default();
            let colours = chunk
                .iter()
                .map(|p| {
                    let (px, py) = p.at::<R>();
                    trace(w, ray_through(w, px + half, py + half), &mut tally)
                })
                .collect();
            (colours, tally)
        })
        .collect();
    let mut colours = Vec::with_capacity(points.len());
    let mut tally = T::default();
    for (c, t) in chunks {
        colours.extend(c);
        tally = tally.merge(t);
    }
    (colours, tally)
}
