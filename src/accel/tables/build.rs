//! The tables' build (src/accel/tables.rs says what they are): each
//! primitive of the tree a leaf of its own, a plan of each grid's cells
//! sized to the work and the bytes they may take, and the lists filled.

use glam::{DMat3, DVec3};
use rayon::prelude::*;

use super::super::bvh::{Bvh, Child, EMPTY};
use super::super::spans::{
    cube_faces, f32_down, margin, narrowed, narrowed_parallel, parallel_span, perspective_span,
    Span,
};
use super::{
    CameraSpec, Cell, Entry, Grid, GridForm, LightSpec, Tables, CELL_CAP, COUNT_CHUNK, LIGHT_SCALE,
    MAX_SIDE, MIN_GRID_BYTES, TILE, WALK, WORK_FACTOR,
};
use crate::prim::Hull;

/// A primitive of the tree, as a leaf of its own, its padded box and its
/// hull.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Leaf {
    pub word: u32,
    pub lo: DVec3,
    pub hi: DVec3,
    pub hull: Hull,
}

/// Each primitive of the tree's leaves, as a leaf of its own (a word of
/// count 1), with its own padded box (`bvh::padded`): a list then names the
/// primitives whose boxes a cell's rays can meet, not their leaves'.
/// `boxes[kind][i]` is the box of primitive `i` of that kind in the scene.
pub(crate) fn leaves(
    tree: &Bvh,
    boxes: &[Vec<([f32; 3], [f32; 3])>],
    hulls: &[Vec<Hull>],
) -> Vec<Leaf> {
    let v = |c: [f32; 3]| DVec3::new(c[0].into(), c[1].into(), c[2].into());
    let mut out = Vec::new();
    for node in &tree.nodes {
        for &word in &node.child {
            if word == EMPTY {
                continue;
            }
            if let Child::Leaf(kind, range) = Child::of(word) {
                for slot in range {
                    let index = tree.orders[kind][slot] as usize;
                    let (lo, hi) = boxes[kind][index];
                    out.push(Leaf {
                        word: (slot as u32) << 8 | (kind as u32) << 4 | 1,
                        lo: v(lo),
                        hi: v(hi),
                        hull: hulls[kind][index],
                    });
                }
            }
        }
    }
    out
}

/// A grid under construction: its map and each primitive's span.
struct Plan {
    rows: DMat3,
    form: GridForm,
    reach: f64,
    /// The grid's extent in (a, b), where it is fixed (the eye's screen).
    domain: Option<((f64, f64), (f64, f64))>,
    /// The eye's pixels across a and b, `tile` to a cell; else the cells
    /// come from the spans' count.
    pixels: Option<(u32, u32)>,
    /// How far a fitted extent may reach (a cube face's: just past ±1).
    clamp: f64,
    spans: Vec<(u32, Span)>,
}

/// A plan at one resolution: where its cells are, and how many
/// primitives each lists.
struct Counted {
    a0: f32,
    b0: f32,
    sa: f32,
    sb: f32,
    na: u32,
    nb: u32,
    counts: Vec<u32>,
}

impl Counted {
    /// The entries it keeps: the lists no longer than `CELL_CAP`.
    fn entries(&self) -> usize {
        self.counts
            .iter()
            .filter(|&&n| n as usize <= CELL_CAP)
            .map(|&n| n as usize)
            .sum()
    }

    /// Its bytes on the device (`device_bytes`).
    fn bytes(&self) -> usize {
        80 + 8 * (self.counts.len() + self.entries())
    }

    /// The cells a span covers, from its (a, b) range widened by the
    /// lookup's margin, as the lookup computes them from the stored f32s.
    fn cover(&self, s: &Span) -> (std::ops::RangeInclusive<u32>, std::ops::RangeInclusive<u32>) {
        let index = |x: f64, x0: f32, sc: f32, n: u32| -> u32 {
            let c = ((x - f64::from(x0)) * f64::from(sc)).floor();
            c.clamp(0.0, f64::from(n - 1)) as u32
        };
        let a = index(s.a.0 - margin(s.a.0), self.a0, self.sa, self.na)
            ..=index(s.a.1 + margin(s.a.1), self.a0, self.sa, self.na);
        let b = index(s.b.0 - margin(s.b.0), self.b0, self.sb, self.nb)
            ..=index(s.b.1 + margin(s.b.1), self.b0, self.sb, self.nb);
        (a, b)
    }
}

/// One grid laid out: its cells and entries count from 0.
struct Laid {
    grid: Grid,
    cells: Vec<Cell>,
    entries: Vec<Entry>,
}

/// Cells on a side of a light's grid for `n` primitives seen, at `scale`.
fn side_for(n: usize, scale: f64, max: u32) -> u32 {
    ((n as f64).sqrt() * scale)
        .round()
        .clamp(1.0, f64::from(max)) as u32
}

impl Plan {
    fn perspective(rows: DMat3, apex: DVec3, leaves: &[Leaf], pad: f64, reach: f64) -> Self {
        let spans = leaves
            .iter()
            .filter_map(|l| {
                let (lo, hi) = (l.lo - pad, l.hi + pad);
                perspective_span(&rows, apex, lo, hi).map(|s| {
                    let mut s = narrowed(s, &rows, apex, &l.hull, pad);
                    s.key -= pad;
                    (l.word, s)
                })
            })
            .collect();
        Plan {
            rows,
            form: GridForm::Perspective,
            reach,
            domain: None,
            pixels: None,
            clamp: 1.0 + 1.0 / 1024.0,
            spans,
        }
    }

    /// Its resolution at `side` cells a side (the eye's: `tile` pixels a
    /// cell), and each cell's count: a difference array over the spans'
    /// rectangles, summed.
    fn count(&self, side: u32, tile: u32) -> Counted {
        let ((a0, a1), (b0, b1)) = self.domain.unwrap_or_else(|| {
            let mut a = (f64::INFINITY, f64::NEG_INFINITY);
            let mut b = a;
            for (_, s) in &self.spans {
                a = (
                    a.0.min(s.a.0 - margin(s.a.0)),
                    a.1.max(s.a.1 + margin(s.a.1)),
                );
                b = (
                    b.0.min(s.b.0 - margin(s.b.0)),
                    b.1.max(s.b.1 + margin(s.b.1)),
                );
            }
            let fit = |r: (f64, f64)| {
                let (lo, hi) = (r.0.max(-self.clamp), r.1.min(self.clamp));
                if lo < hi {
                    (lo, hi)
                } else if r.0 <= r.1 {
                    (lo, lo + 1.0)
                } else {
                    (0.0, 1.0)
                }
            };
            (fit(a), fit(b))
        });
        let (na, nb) = self
            .pixels
            .map_or((side, side), |(w, h)| (w.div_ceil(tile), h.div_ceil(tile)));
        let (a0, b0) = (a0 as f32, b0 as f32);
        let mut c = Counted {
            a0,
            b0,
            sa: (f64::from(na) / (a1 - f64::from(a0))) as f32,
            sb: (f64::from(nb) / (b1 - f64::from(b0))) as f32,
            na,
            nb,
            counts: Vec::new(),
        };
        let (w, h) = (na as usize + 1, nb as usize + 1);
        let mut diff = vec![0i64; w * h];
        for (_, s) in &self.spans {
            let (ra, rb) = c.cover(s);
            let (i0, i1, j0, j1) = (
                *ra.start() as usize,
                *ra.end() as usize + 1,
                *rb.start() as usize,
                *rb.end() as usize + 1,
            );
            diff[j0 * w + i0] += 1;
            diff[j0 * w + i1] -= 1;
            diff[j1 * w + i0] -= 1;
            diff[j1 * w + i1] += 1;
        }
        for j in 0..h {
            for i in 0..w {
                let mut v = diff[j * w + i];
                if i > 0 {
                    v += diff[j * w + i - 1];
                }
                if j > 0 {
                    v += diff[(j - 1) * w + i];
                }
                if i > 0 && j > 0 {
                    v -= diff[(j - 1) * w + i - 1];
                }
                diff[j * w + i] = v;
            }
        }
        c.counts = (0..nb as usize)
            .flat_map(|j| (0..na as usize).map(move |i| (i, j)))
            .map(|(i, j)| diff[j * w + i] as u32)
            .collect();
        c
    }

    /// Lays the plan out at the resolution `c` counted: each list nearest
    /// key first, a list longer than `CELL_CAP` left to the walk.
    fn fill(&self, c: Counted) -> Laid {
        let mut cells: Vec<Cell> = Vec::with_capacity(c.counts.len());
        let mut at = 0u32;
        for &n in &c.counts {
            if n as usize > CELL_CAP {
                cells.push(Cell {
                    first: 0,
                    count: WALK,
                });
            } else {
                cells.push(Cell {
                    first: at,
                    count: 0,
                });
                at += n;
            }
        }
        let mut entries = vec![Entry { leaf: 0, key: 0.0 }; at as usize];
        // Filled in the order of their entries, each list comes out sorted
        // nearest key first (ties to the lower word), with no sort a cell.
        let mut order: Vec<(Entry, &Span)> = self
            .spans
            .iter()
            .map(|(leaf, s)| {
                let key = f32_down(s.key);
                (Entry { leaf: *leaf, key }, s)
            })
            .collect();
        order.par_sort_unstable_by(|(x, _), (y, _)| {
            x.key.total_cmp(&y.key).then(x.leaf.cmp(&y.leaf))
        });
        for (entry, s) in order {
            let (ra, rb) = c.cover(s);
            for j in rb {
                for i in ra.clone() {
                    let cell = &mut cells[(j * c.na + i) as usize];
                    if cell.count != WALK {
                        entries[(cell.first + cell.count) as usize] = entry;
                        cell.count += 1;
                    }
                }
            }
        }
        let r = |v: DVec3| [v.x as f32, v.y as f32, v.z as f32];
        Laid {
            grid: Grid {
                rows: [
                    r(self.rows.row(0)),
                    r(self.rows.row(1)),
                    r(self.rows.row(2)),
                ],
                a0: c.a0,
                b0: c.b0,
                sa: c.sa,
                sb: c.sb,
                first_cell: 0,
                na: c.na,
                nb: c.nb,
                reach: self.reach as f32,
                form: self.form,
            },
            cells,
            entries,
        }
    }
}

/// The bytes the tables take on the device: grids of five 16-byte words,
/// cells and entries two to a word.
pub fn device_bytes(t: &Tables) -> usize {
    16 * (5 * t.grids.len() + t.cells.len().div_ceil(2) + t.entries.len().div_ceil(2))
}

/// Builds the tables of `tree` for the `lights` that cast shadow rays and
/// for `camera`'s eye rays (all in the coordinates the tree is in), within
/// `budget` bytes on the device; None where neither asks for one or nothing
/// fits. `boxes[kind][i]` is the padded box of primitive `i` of that kind
/// in the scene, `hulls[kind][i]` its hull (`prim::Hull`).
pub fn build(
    tree: &Bvh,
    boxes: &[Vec<([f32; 3], [f32; 3])>],
    hulls: &[Vec<Hull>],
    lights: &[LightSpec],
    camera: Option<&CameraSpec>,
    budget: usize,
) -> Option<Tables> {
    let t0 = std::time::Instant::now();
    let leaves = leaves(tree, boxes, hulls);
    if leaves.is_empty() || !(camera.is_some() || lights.iter().any(|l| l.casts)) {
        return None;
    }
    let mut scale = 0.0f64;
    for l in &leaves {
        scale = scale
            .max(l.lo.abs().max_element())
            .max(l.hi.abs().max_element());
    }
    for l in lights {
        if let Some(p) = l.position {
            scale = scale.max(p.abs().max_element());
        }
    }
    if let Some(c) = camera {
        scale = scale.max(c.eye.abs().max_element());
    }
    if !scale.is_finite() {
        return None;
    }
    let pad = (scale / 16384.0).max(f64::from(f32::MIN_POSITIVE));
    let reach = 16.0 * scale.max(pad);

    // The plans: each light's six faces or one parallel grid, then the eye's.
    // Their spans are the build's working memory: at most WORK_FACTOR
    // budgets, however many lights there are (3,000 lights over 3,000 spheres
    // took 2.3 GB before).
    let span_bytes = std::mem::size_of::<(u32, Span)>();
    let held = |plans: &[(Option<usize>, Plan)]| {
        plans.iter().map(|(_, p)| p.spans.len()).sum::<usize>() * span_bytes
    };
    let mut plans: Vec<(Option<usize>, Plan)> = Vec::new();
    for (i, l) in lights.iter().enumerate() {
        if !l.casts {
            continue;
        }
        if held(&plans) > WORK_FACTOR * budget || MIN_GRID_BYTES * plans.len() > budget {
            return None;
        }
        match l.position {
            Some(apex) => plans.extend(
                cube_faces()
                    .into_par_iter()
                    .map(|rows| (Some(i), Plan::perspective(rows, apex, &leaves, pad, reach)))
                    .collect::<Vec<_>>(),
            ),
            None => {
                let w = -l.direction.normalize();
                if !w.is_finite() {
                    continue;
                }
                let (u, v) = w.any_orthonormal_pair();
                let rows = DMat3::from_cols(w, u, v).transpose();
                let spans = leaves
                    .par_iter()
                    .map(|leaf| {
                        let s = parallel_span(&rows, leaf.lo - pad, leaf.hi + pad);
                        let mut s = narrowed_parallel(s, &rows, &leaf.hull, pad);
                        s.key -= pad;
                        (leaf.word, s)
                    })
                    .collect();
                plans.push((
                    Some(i),
                    Plan {
                        rows,
                        form: GridForm::Parallel,
                        reach,
                        domain: None,
                        pixels: None,
                        clamp: f64::INFINITY,
                        spans,
                    },
                ));
            }
        }
    }
    if let Some(c) = camera {
        let m = DMat3::from_cols(c.to_screen, c.right, c.up);
        let det = m.determinant();
        if det.is_finite() && det.abs() > 0.0 {
            let mut plan = Plan::perspective(m.inverse(), c.eye, &leaves, pad, f64::INFINITY);
            plan.domain = Some(((-1.0, 1.0), (-1.0, 1.0)));
            plan.pixels = Some((c.width.max(1), c.height.max(1)));
            plans.push((None, plan));
        }
    }

    // The finest resolution that fits the budget: each try halves the
    // lights' cells a side and doubles the eye's tile.
    if held(&plans) > WORK_FACTOR * budget || MIN_GRID_BYTES * plans.len() > budget {
        return None;
    }
    let mut light_scale = LIGHT_SCALE;
    let mut tile = TILE;
    for _ in 0..12 {
        // Laid end to end, the cells and the entries each round up to a
        // whole word once (`device_bytes`): 32 bytes at most. The plans are
        // counted a few at a time, and a resolution whose counts pass the
        // budget is left at once: the counts held stay within it.
        let mut bytes = 32;
        let mut counted: Vec<Counted> = Vec::with_capacity(plans.len());
        for chunk in plans.chunks(COUNT_CHUNK) {
            let c: Vec<Counted> = chunk
                .par_iter()
                .map(|(_, plan)| {
                    let side = match plan.form {
                        GridForm::Perspective => side_for(plan.spans.len(), light_scale, MAX_SIDE),
                        GridForm::Parallel => side_for(plan.spans.len(), light_scale, 4 * MAX_SIDE),
                    };
                    plan.count(side, tile)
                })
                .collect();
            bytes += c.iter().map(Counted::bytes).sum::<usize>();
            counted.extend(c);
            if bytes > budget {
                break;
            }
        }
        if bytes <= budget {
            let laid: Vec<Laid> = plans
                .par_iter()
                .zip(counted)
                .map(|((_, plan), c)| plan.fill(c))
                .collect();
            let mut t = Tables {
                lights: vec![None; lights.len()],
                ..Tables::default()
            };
            for ((light, _), mut l) in plans.iter().zip(laid) {
                let g = t.grids.len() as u32;
                match light {
                    Some(i) => {
                        t.lights[*i].get_or_insert(g);
                    }
                    None => t.eye = Some(g),
                }
                let (cells, entries) = (t.cells.len() as u32, t.entries.len() as u32);
                l.grid.first_cell = cells;
                t.grids.push(l.grid);
                t.cells.extend(l.cells.into_iter().map(|c| match c.count {
                    WALK => c,
                    _ => Cell {
                        first: c.first + entries,
                        ..c
                    },
                }));
                t.entries.extend(l.entries);
            }
            t.build_s = t0.elapsed().as_secs_f64();
            return Some(t);
        }
        light_scale /= 2.0;
        tile *= 2;
    }
    None
}
