//! Whitted's adaptive antialiasing (docs/scene-format.md, Rays): a pixel
//! whose corners differ by more than the threshold is split into four,
//! each quarter in turn, down to the scene's level, and its colour is the
//! mean of its squares' corners weighted by their areas. The pixels to
//! split are chosen from the corner grid (`Adaptive::splits`);
//! mirrors shaders/adaptive.glsl, which the GPU runs over the list of them.

use rayon::prelude::*;

use super::ray::ray_through;
use super::trace::trace;
use super::world::World;
use crate::base::real::{Real, Vec3};
use crate::raster::region::Region;
use crate::raster::Image;
use crate::scene::Adaptive;
use crate::stats::Tally;

/// The pixels of the image of corners `grid` (traced over `traced`, the
/// corners of a region): each the mean of its corners, or refined where
/// they differ by more than `threshold` steps (chosen as the GPU chooses,
/// by `Adaptive::splits` on the f32 corners).
pub fn resolve<R: Real, T: Tally>(
    w: &World<R>,
    grid: &Image,
    traced: Region,
    threshold: R,
    levels: u32,
) -> (Image, T) {
    let choice = Adaptive {
        threshold: threshold.to_f64() / Adaptive::STEPS,
        levels,
    };
    let mean = grid.corner_mean();
    let (width, height) = (mean.width, mean.height);
    let mut pixels = mean.pixels;
    let counts = pixels
        .par_chunks_mut(width as usize)
        .enumerate()
        .map(|(row, out)| {
            let mut counts = T::default();
            for (column, px) in out.iter_mut().enumerate() {
                let (x, y) = (column as u32, row as u32);
                let c = grid.corners_of(x, y);
                if choice.splits(&c) {
                    let at = (traced.x + x, traced.y + y);
                    let corners = c.map(|p| {
                        Vec3::new(
                            R::of(f64::from(p[0])),
                            R::of(f64::from(p[1])),
                            R::of(f64::from(p[2])),
                        )
                    });
                    let v = refine(w, at, corners, threshold, levels, &mut counts);
                    *px = [v.x.to_f32(), v.y.to_f32(), v.z.to_f32()];
                }
            }
            counts
        })
        .reduce(T::default, T::merge);
    debug_assert_eq!(pixels.len(), width as usize * height as usize);
    (Image::new(width, height, pixels), counts)
}

/// One square of a pixel waiting to be resolved: its top-left corner in
/// pixels of the image, its side, its level of splitting, and its corners'
/// colours (top-left, top-right, bottom-left, bottom-right).
#[derive(Clone, Copy)]
struct Square<R> {
    x: R,
    y: R,
    size: R,
    level: u32,
    corners: [Vec3<R>; 4],
}

/// The colour of pixel (x, y), which the first pass chose to split, from
/// its corners `corners`; its squares split where their contrast passes
/// `threshold` steps, down to `levels` splits from the pixel.
pub fn refine<R: Real, T: Tally>(
    w: &World<R>,
    (x, y): (u32, u32),
    corners: [Vec3<R>; 4],
    threshold: R,
    levels: u32,
    tally: &mut T,
) -> Vec3<R> {
    // The point (px, py) of the image, in pixels, as the corner grid's
    // continuous coordinates (its pixel centres are the image's corners).
    let half = R::of(0.5);
    let mut at = |px: R, py: R| trace(w, ray_through(w, px + half, py + half), tally);
    let mut stack = vec![Square {
        x: R::of(f64::from(x)),
        y: R::of(f64::from(y)),
        size: R::one(),
        level: 0,
        corners,
    }];
    let mut sum = Vec3::zero();
    while let Some(s) = stack.pop() {
        // The pixel itself is split: the first pass chose it.
        if s.level == 0 || s.level < levels && Adaptive::contrast(&s.corners) > threshold {
            let h = s.size * half;
            let [tl, tr, bl, br] = s.corners;
            // The five new points, in this order on both renderers.
            let top = at(s.x + h, s.y);
            let left = at(s.x, s.y + h);
            let centre = at(s.x + h, s.y + h);
            let right = at(s.x + s.size, s.y + h);
            let bottom = at(s.x + h, s.y + s.size);
            let square = |x, y, corners| Square {
                x,
                y,
                size: h,
                level: s.level + 1,
                corners,
            };
            // Pushed last to first: the top-left quarter is resolved first.
            stack.push(square(s.x + h, s.y + h, [centre, right, bottom, br]));
            stack.push(square(s.x, s.y + h, [left, centre, bl, bottom]));
            stack.push(square(s.x + h, s.y, [top, tr, centre, right]));
            stack.push(square(s.x, s.y, [tl, top, left, centre]));
        } else {
            let [a, b, c, d] = s.corners;
            sum += (a + b + c + d) * (s.size * s.size * R::of(0.25));
        }
    }
    sum
}
