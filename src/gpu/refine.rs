//! Adaptive sampling's refinement on the GPU: the pixels to split, chosen
//! from the corner image as the CPU chooses them, and each level's points
//! as the list the shader traces (shaders/adaptive.glsl), one invocation a
//! point. The levels themselves are `scene::refine`'s, shared with the CPU.

use super::layout::refine::Values;
use super::Precision;
use crate::base::interface::{array, Array};
use crate::base::real::{Real, Vec3};
use crate::raster::region::Region;
use crate::raster::Image;
use crate::scene::refine::{Pixel, Point};
use crate::scene::Adaptive;

/// The pixels of `region` to split, in the image's order: each its place
/// in the whole image and its corners (from `corners`, the region's image
/// of its corners), and beside them each one's place in the region's
/// pixels.
pub(crate) fn split<R: Real>(
    corners: &Image,
    region: Region,
    adaptive: &Adaptive,
) -> (Vec<Pixel<R>>, Vec<usize>) {
    let (w, h) = (corners.width - 1, corners.height - 1);
    let (mut split, mut places) = (Vec::new(), Vec::new());
    for y in 0..h {
        for x in 0..w {
            let c = corners.corners_of(x, y);
            if adaptive.splits(&c) {
                let c = c.map(|p| {
                    Vec3::new(
                        R::of(f64::from(p[0])),
                        R::of(f64::from(p[1])),
                        R::of(f64::from(p[2])),
                    )
                });
                split.push(((region.x + x, region.y + y), c));
                places.push((y * w + x) as usize);
            }
        }
    }
    (split, places)
}

/// A level's points as the shader's list.
pub(crate) fn list(points: &[Point]) -> Array {
    let values = points.iter().map(|p| Values {
        point: [p.x, p.y, p.level, 0],
    });
    array(values, Precision::F32)
}
