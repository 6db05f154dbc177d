//! Whitted's adaptive antialiasing, level by level (docs/scene-format.md,
//! Rays): each pass splits the squares chosen so far into quarters, and
//! traces the new points of all of them, each point once, though two
//! squares share it. Both renderers run this, with their own tracer: the
//! CPU over its threads, the GPU as one dispatch a level (one invocation a
//! point). So they split the same squares and sum each pixel in the same
//! order: depth first, the top-left quarter first.

use std::collections::HashMap;

use super::Adaptive;
use crate::base::real::{Real, Vec3};

/// A point of the image to trace: (x, y) on the lattice of side 2^-level
/// pixels, in the whole image's coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Point {
    /// Its column, in 2^-level pixels.
    pub x: u32,
    /// Its row, in 2^-level pixels.
    pub y: u32,
    /// The level of splitting that made it, 1..=`Adaptive::MAX_LEVELS`.
    pub level: u32,
}

impl Point {
    /// Its place in pixels of the image: exact, a dyadic fraction.
    pub fn at<R: Real>(self) -> (R, R) {
        let scale = R::one() / R::of(f64::from(1u32 << self.level));
        (
            R::of(f64::from(self.x)) * scale,
            R::of(f64::from(self.y)) * scale,
        )
    }
}

/// A pixel to split: its column and row in the image, and its corners'
/// colours (top-left, top-right, bottom-left, bottom-right).
pub type Pixel<R> = ((u32, u32), [Vec3<R>; 4]);

/// A square waiting to be resolved: the pixel it belongs to (its place in
/// the list), its corner on its level's lattice, its level, its place in
/// the pixel's quadtree (two bits a level, the first level highest), and
/// its corners' colours (top-left, top-right, bottom-left, bottom-right).
struct Square<R> {
    pixel: usize,
    x: u32,
    y: u32,
    level: u32,
    path: u32,
    corners: [Vec3<R>; 4],
}

/// The colours of `pixels`, every one split, its squares split again where
/// their contrast passes `threshold` steps, down to `levels` splits.
/// `trace` gives the colours of a level's points, in their order.
pub fn refine<R: Real, E>(
    pixels: &[Pixel<R>],
    threshold: R,
    levels: u32,
    mut trace: impl FnMut(&[Point]) -> Result<Vec<Vec3<R>>, E>,
) -> Result<Vec<Vec3<R>>, E> {
    debug_assert!(levels <= Adaptive::MAX_LEVELS);
    let mut splitting: Vec<Square<R>> = pixels
        .iter()
        .enumerate()
        .map(|(pixel, &((x, y), corners))| Square {
            pixel,
            x,
            y,
            level: 0,
            path: 0,
            corners,
        })
        .collect();
    // Each leaf: its pixel, its path, and its share of the pixel's colour.
    let mut leaves: Vec<(usize, u32, Vec3<R>)> = Vec::new();
    let quarter = R::of(0.25);
    while let Some(first) = splitting.first() {
        let k = first.level + 1;
        // The level's points, each once, in the order first asked for.
        let mut index: HashMap<(u32, u32), usize> = HashMap::new();
        let mut points = Vec::new();
        let mut point = |x: u32, y: u32| {
            *index.entry((x, y)).or_insert_with(|| {
                points.push(Point { x, y, level: k });
                points.len() - 1
            })
        };
        // Top, left, middle, right, bottom of each square.
        let five: Vec<[usize; 5]> = splitting
            .iter()
            .map(|s| {
                let (x, y) = (2 * s.x, 2 * s.y);
                [
                    point(x + 1, y),
                    point(x, y + 1),
                    point(x + 1, y + 1),
                    point(x + 2, y + 1),
                    point(x + 1, y + 2),
                ]
            })
            .collect();
        let colours = trace(&points)?;
        let side = R::one() / R::of(f64::from(1u32 << k));
        let shift = 2 * (Adaptive::MAX_LEVELS - k);
        let mut next = Vec::new();
        for (s, five) in splitting.iter().zip(five) {
            let [t, l, m, r, b] = five.map(|i| colours[i]);
            let [tl, tr, bl, br] = s.corners;
            let (x, y) = (2 * s.x, 2 * s.y);
            let quarters = [
                (x, y, [tl, t, l, m]),
                (x + 1, y, [t, tr, m, r]),
                (x, y + 1, [l, m, bl, b]),
                (x + 1, y + 1, [m, r, b, br]),
            ];
            for (q, (x, y, corners)) in quarters.into_iter().enumerate() {
                let path = s.path | (q as u32) << shift;
                if k < levels && Adaptive::contrast(&corners) > threshold {
                    next.push(Square {
                        pixel: s.pixel,
                        x,
                        y,
                        level: k,
                        path,
                        corners,
                    });
                } else {
                    let [a, b, c, d] = corners;
                    leaves.push((s.pixel, path, (a + b + c + d) * (side * side * quarter)));
                }
            }
        }
        splitting = next;
    }
    // Depth first, the top-left quarter first: the order of the paths.
    leaves.sort_unstable_by_key(|&(pixel, path, _)| (pixel, path));
    let mut sums = vec![Vec3::zero(); pixels.len()];
    for (pixel, _, share) in leaves {
        sums[pixel] += share;
    }
    Ok(sums)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grey(v: f64) -> Vec3<f64> {
        Vec3::new(v, v, v)
    }

    /// A pixel whose points are all one colour is that colour, traced with
    /// five points at one level; two pixels side by side share the points
    /// of their common edge, traced once.
    #[test]
    fn shared_points_are_traced_once() {
        let corners = [grey(0.5); 4];
        let mut traced = Vec::new();
        let sums = refine(&[((3, 2), corners), ((4, 2), corners)], 1.0, 1, |points| {
            traced.extend_from_slice(points);
            Ok::<_, ()>(vec![grey(0.5); points.len()])
        })
        .unwrap();
        assert_eq!(sums, vec![grey(0.5); 2]);
        // 5 + 5, less the right midpoint of the first, the left of the second.
        assert_eq!(traced.len(), 9);
        assert_eq!(
            traced[3],
            Point {
                x: 8,
                y: 5,
                level: 1
            }
        );
        assert_eq!(traced[3].at::<f64>(), (4.0, 2.5));
    }

    /// A square splits again where its corners differ, down to the levels
    /// asked for and no further.
    #[test]
    fn contrast_splits_down_to_the_levels() {
        let corners = [grey(0.0), grey(1.0), grey(0.0), grey(1.0)];
        for levels in 1..=Adaptive::MAX_LEVELS {
            let mut passes = 0;
            refine(&[((0, 0), corners)], 1.0, levels, |points| {
                passes += 1;
                Ok::<_, ()>(points.iter().map(|p| grey(f64::from(p.x % 2))).collect())
            })
            .unwrap();
            assert_eq!(passes, levels);
        }
    }
}
