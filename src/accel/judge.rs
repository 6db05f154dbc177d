//! Which cells of a perspective table pay for their lists: a cell whose
//! list costs more than the walk would, for the ray through its centre,
//! walks instead. Either answers exactly, so the choice moves only time,
//! never a pixel.
//!
//! The ray through a cell's centre from the grid's apex (a light, or the
//! eye) stands for the rays that read the cell: it meets the scene first at
//! `d` (its list's scan finds that, with the unbounded kinds tested too),
//! and the receivers of the cell's shadow rays, or the points its eye rays
//! see, lie about there. A scan that reaches `d` tests every entry whose key
//! is within it; a walk along the same segment enters every inner node
//! whose box the segment crosses, and tests every primitive of each leaf it
//! crosses. Those two counts, weighed, decide.

use glam::{DMat3, DVec3};
use rayon::prelude::*;

use super::bvh::{Bvh, Child, EMPTY, WIDTH};
use super::tables::{Cell, Entry, KEY_SLACK, WALK};
use crate::base::ray::Ray;
use crate::base::real::Vec3;
use crate::prim::{CpuPrims, PrimId};

/// A list's entry against a test in the walk: the scan reads the entry's
/// word before it tests the primitive.
const ENTRY_COST: f64 = 1.25;

/// An inner node's visit against a primitive's test: its word and four
/// boxes read, four slab tests, the sort of the children entered.
const NODE_COST: f64 = 1.5;

/// Lists this short are kept without a look: the walk reads at least one
/// node and tests a leaf.
const JUDGE_FROM: u32 = 3;

/// A perspective grid as the judge reads it: its apex, the inverse of its
/// map (so that (1, a, b) gives a direction), and its cells' extent.
pub(crate) struct Frame {
    pub apex: DVec3,
    pub inverse: DMat3,
    pub a0: f32,
    pub b0: f32,
    pub sa: f32,
    pub sb: f32,
    pub na: u32,
}

/// Marks `WALK` each cell of `cells` (over `entries`, lists sorted by key)
/// whose list would cost more than the walk for the ray through its
/// centre; returns how many it marked.
pub(crate) fn judge(
    frame: &Frame,
    cells: &mut [Cell],
    entries: &[Entry],
    tree: &Bvh,
    prims: &CpuPrims<f64>,
) -> usize {
    cells
        .par_iter_mut()
        .enumerate()
        .map(|(c, cell)| {
            if cell.count == WALK || cell.count < JUDGE_FROM {
                return 0;
            }
            let (i, j) = (c as u32 % frame.na, c as u32 / frame.na);
            let a = f64::from(frame.a0) + (f64::from(i) + 0.5) / f64::from(frame.sa);
            let b = f64::from(frame.b0) + (f64::from(j) + 0.5) / f64::from(frame.sb);
            let d = (frame.inverse * DVec3::new(1.0, a, b)).normalize();
            if !d.is_finite() {
                return 0;
            }
            let (f, n) = (cell.first as usize, cell.count as usize);
            let list = &entries[f..f + n];
            let reach = first_hit(frame.apex, d, list, tree, prims);
            let bound = reach * KEY_SLACK;
            let scanned = list.partition_point(|e| f64::from(e.key) <= bound);
            let (nodes, tests) = walk_cost(tree, frame.apex, d, reach);
            if ENTRY_COST * scanned as f64 > NODE_COST * nodes as f64 + tests as f64 {
                cell.count = WALK;
                1
            } else {
                0
            }
        })
        .sum()
}

/// Where the ray from `o` along unit `d` first meets the scene: the list's
/// primitives taken nearest key first (a key is a distance from the apex,
/// rounded down), then the kinds the tree does not hold; infinity where it
/// meets nothing.
fn first_hit(o: DVec3, d: DVec3, list: &[Entry], tree: &Bvh, prims: &CpuPrims<f64>) -> f64 {
    let ray = Ray {
        origin: Vec3::of(o),
        dir: Vec3::of(d),
    };
    let mut best = f64::INFINITY;
    for e in list {
        if f64::from(e.key) > best {
            break;
        }
        if let Child::Leaf(kind, range) = Child::of(e.leaf) {
            for slot in range {
                let id = PrimId {
                    kind: kind as u32,
                    index: tree.orders[kind][slot],
                };
                if let Some(t) = prims.intersect(id, &ray, PrimId::NONE) {
                    best = best.min(t);
                }
            }
        }
    }
    prims.scan(true, &ray, PrimId::NONE, &mut (), |_, t| {
        best = best.min(t);
        true
    });
    best
}

/// The inner nodes a walk along the segment from `o` (unit `d`) up to
/// `t_max` enters, and the primitives of the leaves it crosses.
fn walk_cost(tree: &Bvh, o: DVec3, d: DVec3, t_max: f64) -> (usize, usize) {
    let inv = d.recip();
    let crosses = |(lo, hi): ([f32; 3], [f32; 3])| {
        let t0 = (DVec3::from(lo.map(f64::from)) - o) * inv;
        let t1 = (DVec3::from(hi.map(f64::from)) - o) * inv;
        let near = t0.min(t1).max_element().max(0.0);
        let far = t0.max(t1).min_element().min(t_max);
        near <= far
    };
    let (mut nodes, mut tests) = (0, 0);
    if tree.nodes.is_empty() {
        return (0, 0);
    }
    let mut stack = vec![0usize];
    while let Some(index) = stack.pop() {
        nodes += 1;
        let node = &tree.nodes[index];
        for k in 0..WIDTH {
            let word = node.child[k];
            if word == EMPTY || !crosses(node.child_box(k)) {
                continue;
            }
            match Child::of(word) {
                Child::Inner(i) => stack.push(i),
                Child::Leaf(_, range) => tests += range.len(),
                Child::Empty => {}
            }
        }
    }
    (nodes, tests)
}
