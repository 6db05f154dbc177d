//! Whitted's adaptive antialiasing, level by level (docs/scene-format.md,
//! Rays): each pass splits the squares chosen so far into quarters, and
//! traces the new points of all of them, each point once, though two
//! squares share it. Both renderers run this, with their own tracer: the
//! CPU over its threads, the GPU as one dispatch a level (one invocation a
//! point). So they split the same squares and sum each pixel in the same
//! order: depth first, the top-left quarter first.

use rayon::prelude::*;

use super::decisions::{Decider, Log};
use crate::base::real::{Real, Vec3};
use crate::raster::Image;
use crate::scene::decisions::key;
use crate::scene::Adaptive;

impl Adaptive {
    /// Colours are compared in steps of 1/255: the contrast of a square
    /// is counted in these, so that f32 and f64, whose colours differ by
    /// rounding, split the same squares but where a corner sits on a step.
    pub const STEPS: f64 = 255.0;

    /// The threshold in steps, as both renderers compare contrasts with it.
    pub fn threshold_steps(&self) -> f64 {
        self.threshold * Self::STEPS
    }

    /// Whether a pixel whose corners (top-left, top-right, bottom-left,
    /// bottom-right, as the corner grid gives them) are `c` is split: the
    /// choice of the pixels the second pass refines, made once, from the
    /// f32 corner image, for either renderer, by [`Adaptive::contrast`].
    pub fn splits(&self, c: &[[f32; 3]; 4]) -> bool {
        let corners = c.map(Vec3::<f64>::of_rgb);
        Self::contrast(&corners) > self.threshold_steps()
    }

    /// The largest minus the smallest of the corners `c`, in the channel
    /// where that is largest, in steps (`STEPS`): what both renderers
    /// compare with the threshold, as contrast() in shaders/adaptive.glsl.
    pub fn contrast<R: Real>(c: &[Vec3<R>; 4]) -> R {
        let steps = R::of(Self::STEPS);
        let half = R::of(0.5);
        let channel = |f: fn(&Vec3<R>) -> R| {
            let values = c.map(|v| (f(&v) * steps + half).floor());
            let hi = values.iter().fold(values[0], |m, v| m.max(*v));
            let lo = values.iter().fold(values[0], |m, v| m.min(*v));
            hi - lo
        };
        channel(|v| v.x).max(channel(|v| v.y)).max(channel(|v| v.z))
    }
}

/// The most pixels refined together: the lists of points, squares and
/// leaves are bounded by these, not by the image (at most 4^levels leaves
/// a pixel). Both renderers take the same runs, so they trace the same
/// points; a point two runs share is traced by each.
pub const RUN_PIXELS: usize = 1 << 16;

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

/// A square resolved: its pixel and path, as one key (the pixel above 8
/// bits of path), and its share of the pixel's colour.
type Leaf<R> = (u64, Vec3<R>);

/// What a run of squares became: the quarters split again, the leaves,
/// and the decisions taken.
type Quartered<R> = (Vec<Square<R>>, Vec<Leaf<R>>, Log);

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

/// Refines the pixels of a region whose corners are `corners` (the image
/// of the region's corners, its top-left at `origin` in the whole image):
/// those `adaptive` splits (`Adaptive::splits`, on the f32 corners), in
/// the image's order, in runs of at most `RUN_PIXELS`. `put(place,
/// colour)` receives each refined pixel's colour and its place in the
/// region's pixels. `decider` takes each split: the test's own, or the
/// decisions `Scene::replay` replays; the decisions taken come back.
pub fn refine_image<R: Real, E>(
    corners: &Image,
    origin: (u32, u32),
    (adaptive, decider): (&Adaptive, Decider),
    threshold: R,
    trace: impl FnMut(&[Point]) -> Result<Vec<Vec3<R>>, E>,
    put: impl FnMut(usize, Vec3<R>),
) -> Result<Log, E> {
    refine_in_runs(
        corners,
        origin,
        (adaptive, decider),
        threshold,
        RUN_PIXELS,
        trace,
        put,
    )
}

/// `refine_image`, in runs of at most `run_pixels`.
fn refine_in_runs<R: Real, E>(
    corners: &Image,
    origin: (u32, u32),
    (adaptive, decider): (&Adaptive, Decider),
    threshold: R,
    run_pixels: usize,
    mut trace: impl FnMut(&[Point]) -> Result<Vec<Vec3<R>>, E>,
    mut put: impl FnMut(usize, Vec3<R>),
) -> Result<Log, E> {
    let (w, h) = (corners.width - 1, corners.height - 1);
    let (mut run, mut places) = (Vec::new(), Vec::new());
    let mut log = Log::default();
    for y in 0..h {
        for x in 0..w {
            let c = corners.corners_of(x, y);
            let (px, py) = (origin.0 + x, origin.1 + y);
            if decider.decide(key(0, px, py), adaptive.splits(&c), &mut log) {
                let c = c.map(Vec3::of_rgb);
                run.push(((px, py), c));
                places.push((y * w + x) as usize);
            }
            let last = y + 1 == h && x + 1 == w;
            if run.len() == run_pixels || last && !run.is_empty() {
                let (colours, more) =
                    refine(&run, threshold, adaptive.levels, decider, &mut trace)?;
                log = log.merge(more);
                for (&place, colour) in places.iter().zip(colours) {
                    put(place, colour);
                }
                run.clear();
                places.clear();
            }
        }
    }
    Ok(log)
}

/// The colours of `pixels`, every one split, its squares split again where
/// their contrast passes `threshold` steps, down to `levels` splits.
/// `trace` gives the colours of a level's points, in their order;
/// `decider` takes each split. The colours, and the decisions taken.
pub fn refine<R: Real, E>(
    pixels: &[Pixel<R>],
    threshold: R,
    levels: u32,
    decider: Decider,
    mut trace: impl FnMut(&[Point]) -> Result<Vec<Vec3<R>>, E>,
) -> Result<(Vec<Vec3<R>>, Log), E> {
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
    let mut leaves: Vec<Leaf<R>> = Vec::new();
    let mut log = Log::default();
    let quarter = R::of(0.25);
    while let Some(first) = splitting.first() {
        let k = first.level + 1;
        let (points, five) = level_points(&mut splitting, k);
        let colours = trace(&points)?;
        let side = R::one() / R::of(f64::from(1u32 << k));
        let shift = 2 * (Adaptive::MAX_LEVELS - k);
        // The four quarters of each square: split again, or leaves. In
        // chunks over the threads, kept in order.
        let chunk = 1024;
        let parts: Vec<Quartered<R>> = splitting
            .par_chunks(chunk)
            .zip(five.par_chunks(chunk))
            .map(|(squares, fives)| {
                let (mut next, mut shares) = (Vec::new(), Vec::new());
                let mut log = Log::default();
                for (s, five) in squares.iter().zip(fives) {
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
                        let split = k < levels
                            && decider.decide(
                                key(k, x, y),
                                Adaptive::contrast(&corners) > threshold,
                                &mut log,
                            );
                        if split {
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
                            let share = (a + b + c + d) * (side * side * quarter);
                            shares.push(((s.pixel as u64) << 8 | u64::from(path), share));
                        }
                    }
                }
                (next, shares, log)
            })
            .collect();
        let mut next = Vec::new();
        for (squares, shares, more) in parts {
            next.extend(squares);
            leaves.extend(shares);
            log = log.merge(more);
        }
        splitting = next;
    }
    Ok((sums_in_order(leaves, pixels.len()), log))
}

/// The points of level `k` that `squares` (of level k - 1) split into:
/// each square's top, left, middle, right and bottom, by their places in
/// the list, which holds each point once. A square's top is the bottom of
/// the square above it, its left the right of the square to its left, where
/// those split too; no other point is shared. The squares are put in rows
/// first, so that both neighbours are found in one walk.
fn level_points<R>(squares: &mut [Square<R>], k: u32) -> (Vec<Point>, Vec<[usize; 5]>) {
    let key = |x: u32, y: u32| u64::from(y) << 32 | u64::from(x);
    squares.sort_unstable_by_key(|s| key(s.x, s.y));
    let mut points = Vec::with_capacity(4 * squares.len());
    let mut five: Vec<[usize; 5]> = Vec::with_capacity(squares.len());
    // The first square at or after the one above the current square.
    let mut up = 0;
    for (i, s) in squares.iter().enumerate() {
        let mut point = |x: u32, y: u32| {
            points.push(Point { x, y, level: k });
            points.len() - 1
        };
        let (x, y) = (2 * s.x, 2 * s.y);
        let top = match s.y.checked_sub(1) {
            Some(above) => {
                let wanted = key(s.x, above);
                while up < i && key(squares[up].x, squares[up].y) < wanted {
                    up += 1;
                }
                let found = up < i && key(squares[up].x, squares[up].y) == wanted;
                if found {
                    five[up][4]
                } else {
                    point(x + 1, y)
                }
            }
            None => point(x + 1, y),
        };
        let left = match i.checked_sub(1) {
            Some(p) if squares[p].y == s.y && squares[p].x + 1 == s.x => five[p][3],
            _ => point(x, y + 1),
        };
        let middle = point(x + 1, y + 1);
        let right = point(x + 2, y + 1);
        let bottom = point(x + 1, y + 2);
        five.push([top, left, middle, right, bottom]);
    }
    (points, five)
}

/// Each pixel's sum of its leaves' shares, in the order of their keys
/// (pixel, then path: depth first, the top-left quarter first): the leaves
/// bucketed by pixel, then each pixel's few sorted by path.
fn sums_in_order<R: Real>(leaves: Vec<Leaf<R>>, pixels: usize) -> Vec<Vec3<R>> {
    let pixel_of = |key: u64| (key >> 8) as usize;
    let mut start = vec![0usize; pixels + 1];
    for (key, _) in &leaves {
        start[pixel_of(*key) + 1] += 1;
    }
    for p in 0..pixels {
        start[p + 1] += start[p];
    }
    let mut placed = vec![(0u64, Vec3::zero()); leaves.len()];
    let mut next = start.clone();
    for leaf in leaves {
        let p = pixel_of(leaf.0);
        placed[next[p]] = leaf;
        next[p] += 1;
    }
    (0..pixels)
        .into_par_iter()
        .map(|p| {
            let mut own = placed[start[p]..start[p + 1]].to_vec();
            own.sort_unstable_by_key(|(key, _)| *key);
            own.iter().fold(Vec3::zero(), |mut sum, (_, share)| {
                sum += *share;
                sum
            })
        })
        .collect()
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
        let own = Decider { replay: None };
        let (sums, _) = refine(
            &[((3, 2), corners), ((4, 2), corners)],
            1.0,
            1,
            own,
            |points| {
                traced.extend_from_slice(points);
                Ok::<_, ()>(vec![grey(0.5); points.len()])
            },
        )
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

    /// Runs of any length give the same colours; a point two runs share is
    /// traced by each.
    #[test]
    fn runs_give_the_same_colours() {
        // Corners alternating black and white: every pixel splits.
        let corners = Image::new(5, 4, (0..20).map(|i| [((i % 2) as f32); 3]).collect());
        let adaptive = Adaptive {
            threshold: 0.1,
            levels: 2,
        };
        let colour_at = |p: &Point| {
            let (x, y) = p.at::<f64>();
            grey((x * 0.37 + y * 0.11).fract())
        };
        let mut results = Vec::new();
        for run in [1, 3, 1000] {
            let mut traced = 0;
            let mut image = vec![grey(-1.0); 12];
            refine_in_runs(
                &corners,
                (10, 20),
                (&adaptive, Decider { replay: None }),
                adaptive.threshold_steps(),
                run,
                |points| {
                    traced += points.len();
                    Ok::<_, ()>(points.iter().map(colour_at).collect())
                },
                |place, v| image[place] = v,
            )
            .unwrap();
            assert!(image.iter().all(|v| v.x >= 0.0), "every pixel refined");
            results.push((image, traced));
        }
        assert_eq!(results[0].0, results[2].0);
        assert_eq!(results[1].0, results[2].0);
        assert!(results[0].1 > results[1].1 && results[1].1 > results[2].1);
    }

    /// A refinement that replays another's decisions splits the squares
    /// it was given, whatever its own colours say, and notes where its own
    /// test said otherwise; replaying its own decisions changes nothing.
    #[test]
    fn a_replay_splits_the_replayed_squares() {
        use crate::scene::decisions::{Decisions, Kind};
        let corners = Image::new(
            3,
            2,
            vec![[0.0; 3], [1.0; 3], [0.0; 3], [0.0; 3], [1.0; 3], [0.0; 3]],
        );
        let adaptive = Adaptive {
            threshold: 0.1,
            levels: 3,
        };
        let colour_at = |p: &Point| {
            let (x, y) = p.at::<f64>();
            grey(if x + 0.3 * y > 1.1 { 1.0 } else { 0.0 })
        };
        let run = |decider: Decider| {
            let mut image = vec![grey(-1.0); 2];
            let log = refine_image(
                &corners,
                (0, 0),
                (&adaptive, decider),
                adaptive.threshold_steps(),
                |points| Ok::<_, ()>(points.iter().map(colour_at).collect()),
                |place, v| image[place] = v,
            )
            .unwrap();
            (image, log.sampled(Kind::Adaptive))
        };
        let (own_image, own) = run(Decider { replay: None });
        assert!(own.otherwise.is_empty() && own.taken.len() > 2);
        let (again, replayed) = run(Decider {
            replay: Some(&own.taken),
        });
        assert_eq!((again, &replayed.taken), (own_image.clone(), &own.taken));
        assert!(replayed.otherwise.is_empty());
        // The first pixel alone split, at its first level only.
        let fewer = Decisions::new(Kind::Adaptive, vec![key(0, 0, 0)]);
        let (image, sampled) = run(Decider {
            replay: Some(&fewer),
        });
        assert_eq!(sampled.taken, fewer);
        assert_ne!(image, own_image);
        assert_eq!(image[1], grey(-1.0), "the second pixel is not refined");
        // Its own test is noted wherever the replay decided: the second
        // pixel, and the first pixel's quarters, whose own test split some;
        // not the squares the replay never reached.
        let reached = |k: &u64| match k >> 56 {
            0 => true,
            1 => own.taken.pixel_of(*k) == (0, 0),
            _ => false,
        };
        let at_reached = own.taken.keys().iter().copied().filter(reached);
        let expected = Decisions::new(Kind::Adaptive, at_reached.collect()).without(&fewer);
        assert!(expected.len() >= 2 && expected.len() < own.taken.len() - 1);
        assert_eq!(sampled.otherwise, expected);
    }

    /// A square splits again where its corners differ, down to the levels
    /// asked for and no further.
    #[test]
    fn contrast_splits_down_to_the_levels() {
        let corners = [grey(0.0), grey(1.0), grey(0.0), grey(1.0)];
        for levels in 1..=Adaptive::MAX_LEVELS {
            let mut passes = 0;
            let own = Decider { replay: None };
            refine(&[((0, 0), corners)], 1.0, levels, own, |points| {
                passes += 1;
                Ok::<_, ()>(points.iter().map(|p| grey(f64::from(p.x % 2))).collect())
            })
            .unwrap();
            assert_eq!(passes, levels);
        }
    }
}
