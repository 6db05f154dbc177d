//! The scene space, listed: every small scene of a few factors (the full
//! product, for the long mode), the CI set (an exhaustive core and a
//! covering array of the rest), and random scenes over wider ranges.
//! Every factor's values come from the tables (kinds, light types,
//! patterns), so that a new entry is in every set with no code here.

use super::{mix, LightSpec, Object, Sampler, Spec};
use crate::prim::KINDS;
use crate::rng::Xorshift;
use crate::scene::texture::PATTERNS;
use crate::scene::LIGHT_TYPES;

/// The samplers, in the order the sets cycle through them.
pub const SAMPLINGS: [Sampler; 5] = [
    Sampler::Centers,
    Sampler::Corners,
    Sampler::Adaptive,
    Sampler::Contrast,
    Sampler::Range,
];

/// The small space's factors for one scene: the values a covering array
/// picks among.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Point {
    /// For each kind: 0, 1 or 2 objects.
    pub counts: [u8; MAX_KINDS],
    /// The lights: 0 none, 1..=types one of type k-1, types+1 two (the
    /// first and the last type, or two of the one type).
    pub lights: usize,
    /// Reflection on.
    pub reflect: bool,
    /// Transmission on.
    pub transmit: bool,
    /// The texture: 0 none, else pattern k-1.
    pub texture: usize,
    /// Shadows on.
    pub shadows: bool,
    /// A place in [`SAMPLINGS`].
    pub sampling: usize,
    /// Depth 1 (false) or 3 (true).
    pub deep: bool,
}

/// The most kinds a [`Point`] holds counts for (tested against the table).
pub const MAX_KINDS: usize = 8;

/// How many choices of lights there are: none, one of each type, two.
pub fn light_choices() -> usize {
    LIGHT_TYPES.len() + 2
}

impl Point {
    /// The scene, its placements drawn from `seed`, at `width`×`height`.
    pub fn spec(&self, seed: u64, width: u32, height: u32) -> Spec {
        let mut objects = Vec::new();
        for (k, &n) in self.counts.iter().take(KINDS.len()).enumerate() {
            for i in 0..u64::from(n) {
                objects.push(Object {
                    kind: k,
                    key: mix(seed, 100 + 16 * k as u64 + i),
                });
            }
        }
        let types = LIGHT_TYPES.len();
        let kinds: Vec<usize> = match self.lights {
            0 => vec![],
            l if l <= types => vec![l - 1],
            _ => vec![0, types - 1],
        };
        let lights = kinds
            .into_iter()
            .enumerate()
            .map(|(i, kind)| LightSpec {
                kind,
                key: mix(seed, 200 + i as u64),
                dark: false,
            })
            .collect();
        Spec {
            objects,
            lights,
            reflect: self.reflect,
            transmit: self.transmit,
            texture: self.texture.checked_sub(1),
            shadows: self.shadows,
            sampling: SAMPLINGS[self.sampling],
            samples: 1,
            depth: if self.deep { 3 } else { 1 },
            width,
            height,
            scale: 1.0,
            offset: [0.0; 3],
            eye_inside: false,
            grazing: false,
            seed,
        }
    }
}

/// The factors' sizes, in [`Point::from_levels`]'s order: a count for each
/// kind, then lights, reflect, transmit, texture, shadows, sampling, depth.
fn levels() -> Vec<usize> {
    let mut l = vec![3; KINDS.len()];
    l.extend([
        light_choices(),
        2,
        2,
        PATTERNS.len() + 1,
        2,
        SAMPLINGS.len(),
        2,
    ]);
    l
}

impl Point {
    fn from_levels(v: &[usize]) -> Self {
        let n = KINDS.len();
        let mut counts = [0u8; MAX_KINDS];
        for (c, &x) in counts.iter_mut().zip(&v[..n]) {
            *c = x as u8;
        }
        let f = &v[n..];
        Point {
            counts,
            lights: f[0],
            reflect: f[1] == 1,
            transmit: f[2] == 1,
            texture: f[3],
            shadows: f[4] == 1,
            sampling: f[5],
            deep: f[6] == 1,
        }
    }
}

/// Every point of the small space, in order: the full product (tens of
/// thousands of scenes; `glint fuzz --exhaustive`).
pub fn full() -> impl Iterator<Item = Point> {
    let sizes = levels();
    let total: usize = sizes.iter().product();
    (0..total).map(move |mut i| {
        let v: Vec<usize> = sizes
            .iter()
            .map(|&s| {
                let x = i % s;
                i /= s;
                x
            })
            .collect();
        Point::from_levels(&v)
    })
}

/// How many points [`full`] lists.
pub fn full_len() -> usize {
    levels().iter().product()
}

/// A covering array of strength 2 over `sizes`: rows in which every pair
/// of values of every two factors appears (greedy, after AETG: each row
/// the best of a few candidates, by the pairs it newly covers). Fixed:
/// the candidates come from a fixed seed.
pub fn pairwise(sizes: &[usize], seed: u64) -> Vec<Vec<usize>> {
    let n = sizes.len();
    let mut uncovered = std::collections::BTreeSet::new();
    for a in 0..n {
        for b in a + 1..n {
            for x in 0..sizes[a] {
                for y in 0..sizes[b] {
                    uncovered.insert((a, x, b, y));
                }
            }
        }
    }
    let mut rng = Xorshift(mix(seed, 3));
    let mut rows = Vec::new();
    while let Some(&(a, x, b, y)) = uncovered.iter().next() {
        let mut best: Option<(usize, Vec<usize>)> = None;
        for _ in 0..24 {
            let mut row: Vec<usize> = sizes
                .iter()
                .map(|&s| (rng.next() * s as f64) as usize % s)
                .collect();
            row[a] = x;
            row[b] = y;
            // Improve each factor in turn towards the most new pairs.
            for f in 0..n {
                if f == a || f == b {
                    continue;
                }
                let gain = |row: &Vec<usize>| covers(row, &uncovered);
                let mut top = (gain(&row), row[f]);
                for v in 0..sizes[f] {
                    row[f] = v;
                    let g = gain(&row);
                    if g > top.0 {
                        top = (g, v);
                    }
                }
                row[f] = top.1;
            }
            let g = covers(&row, &uncovered);
            if best.as_ref().is_none_or(|(bg, _)| g > *bg) {
                best = Some((g, row));
            }
        }
        let (_, row) = best.expect("24 candidates");
        for a in 0..n {
            for b in a + 1..n {
                uncovered.remove(&(a, row[a], b, row[b]));
            }
        }
        rows.push(row);
    }
    rows
}

/// How many of `uncovered`'s pairs `row` holds.
fn covers(
    row: &[usize],
    uncovered: &std::collections::BTreeSet<(usize, usize, usize, usize)>,
) -> usize {
    let n = row.len();
    let mut c = 0;
    for a in 0..n {
        for b in a + 1..n {
            c += usize::from(uncovered.contains(&(a, row[a], b, row[b])));
        }
    }
    c
}

/// How many of [`ci`]'s points, at its end, are its covering array's own
/// rows.
pub fn pairwise_rows() -> usize {
    pairwise(&levels(), 56).len()
}

/// The CI set: the core exhaustively (each kind absent or present, every
/// choice of lights, reflection and transmission each on and off: where
/// the no-lights fault of the generated scenes lived), with the other factors (a
/// present kind's count of 1 or 2, the texture, shadows, sampling and
/// depth) from a covering array of strength 2 over every factor, row by
/// row; then that covering array's own rows.
pub fn ci() -> Vec<Point> {
    let sizes = levels();
    let n = KINDS.len();
    let array = pairwise(&sizes, 56);
    let mut out = Vec::new();
    let mut row = array.iter().cycle();
    for mask in 0..1usize << n {
        for lights in 0..light_choices() {
            for material in 0..4 {
                let mut v = row.next().expect("a row").clone();
                for (k, c) in v[..n].iter_mut().enumerate() {
                    *c = if mask & (1 << k) == 0 { 0 } else { (*c).max(1) };
                }
                v[n] = lights;
                v[n + 1] = material & 1;
                v[n + 2] = material >> 1;
                out.push(Point::from_levels(&v));
            }
        }
    }
    out.extend(array.iter().map(|v| Point::from_levels(v)));
    out
}

/// The most objects a generated scene holds (`glint fuzz --objects`): a
/// scene far past the BVH's reach, whose file is still a few megabytes.
pub const MAX_OBJECTS: usize = 100_000;

/// A random scene over the wide ranges: up to `max_objects` objects of
/// any kinds (past the BVH's threshold), up to 4 lights of any types,
/// scales and offsets from the extreme suite's ranges, the eye inside an
/// object, grazing lights, depth up to 6.
pub fn random(seed: u64, max_objects: usize, width: u32, height: u32) -> Spec {
    let mut rng = Xorshift(mix(seed, 4));
    let mut pick = |n: usize| ((rng.next() * n as f64) as usize).min(n - 1);
    let count = pick(max_objects + 1);
    let objects = (0..count)
        .map(|i| Object {
            kind: pick(KINDS.len()),
            key: mix(seed, 1000 + i as u64),
        })
        .collect();
    let lights = (0..pick(5))
        .map(|i| LightSpec {
            kind: pick(LIGHT_TYPES.len()),
            key: mix(seed, 2000 + i as u64),
            dark: false,
        })
        .collect();
    let scale = [1.0, 1e-3, 1e3, 0.05, 40.0][pick(5)];
    let offset = match pick(4) {
        0 | 1 => [0.0; 3],
        2 => [3.0 * scale, -2.0 * scale, 1.5 * scale],
        _ => [1e4 * scale, 0.0, -1e4 * scale],
    };
    let sampling = SAMPLINGS[pick(SAMPLINGS.len())];
    Spec {
        objects,
        lights,
        reflect: pick(2) == 1,
        transmit: pick(3) == 1,
        texture: [None, Some(pick(PATTERNS.len()))][pick(2)],
        shadows: pick(4) != 0,
        sampling,
        // More than one sample a pixel is the centres' alone.
        samples: if sampling == Sampler::Centers {
            [1, 1, 2][pick(3)]
        } else {
            1
        },
        depth: 1 + pick(6) as u32,
        width,
        height,
        scale,
        offset,
        eye_inside: pick(8) == 0,
        grazing: pick(6) == 0,
        seed,
    }
}
