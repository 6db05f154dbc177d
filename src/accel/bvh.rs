//! A bounding volume hierarchy over the bounded primitives, built once on
//! the host with binned SAH (Wald 2007) as a binary tree and collapsed into
//! a 4-wide tree (Wald, Benthin and Boulos 2008; Ernst and Greiner 2008),
//! which both renderers walk the same way (shaders/bvh.glsl,
//! `cpu::intersect`).
//!
//! A node holds its four children's boxes together, one row of four a
//! coordinate (the low and high x of all four, then y, then z), and their
//! four child words; the shader reads it in 64 bytes, four 16-byte texels,
//! each bound a byte of steps from the node's origin (src/accel/quantize.rs),
//! so that one node is a few consecutive reads and its four slab tests run
//! on data already loaded. A child word is an inner node (its index << 4), a leaf (`first
//! << 8 | kind << 4 | count`: `count` primitives of one kind, from `first`
//! in that kind's leaf order) or `EMPTY`.
//!
//! The tree is stored once. A ray orders the children it enters by where it
//! enters them, nearest first, and keeps the others on a short stack with
//! their entry distances; a nearest-hit walk drops a popped child that
//! starts beyond the hit found so far, a shadow ray stops at the first hit.
//! (The binary tree it replaced was flattened eight times, once per octant
//! of ray directions, and walked without a stack by skip links.)
//!
//! Boxes are f32 for every precision, rounded outwards and padded so that a
//! box is never missed by a ray that hits what is inside it (docs/performance.md,
//! The BVH): the image does not depend on the tree.

use glam::DVec3;

pub use super::node::{Child, Node, EMPTY, MAX_PRIMS, WIDTH};
use super::quantize::{self, Packed};
use crate::base::aabb::Aabb;

/// Primitives in a leaf at most (the leaf word keeps the count in 4 bits).
pub const LEAF_MAX: usize = 4;
/// Beyond this depth the build splits at the median, which halves each
/// node, so no tree is deeper than `DEPTH_SWITCH + log2(count)`.
const DEPTH_SWITCH: u32 = 40;
/// The deepest tree the build makes (asserted): 40 + 24 levels of halving
/// cover 2^24 primitives, the most a leaf word can address.
pub const MAX_DEPTH: u32 = 64;
const BINS: usize = 16;
/// The SAH costs of one node visit and one primitive test. On lavapipe a
/// node visit costs about twice a sphere test: every iteration of the walk
/// runs the box test and, masked, the leaf's first sphere test. 3 : 1.5 made
/// seed-fig5 13 % faster than 1 : 1.5 (2 and 4 measured within noise of 3).
/// For the 4-wide tree, node cost 6 and leaves of 8 measured slower
/// (docs/performance.md, Reading the scene).
const COST_NODE: f64 = 3.0;
const COST_PRIM: f64 = 1.5;

/// The tree, and which primitive each leaf slot holds.
#[derive(Debug, Clone)]
pub struct Bvh {
    /// The nodes, the root first, with the boxes their bytes decode to.
    pub nodes: Vec<Node>,
    /// The same nodes in bytes, as the shader reads them.
    pub packed: Vec<Packed>,
    /// For each kind, the indices of its primitives (in the list given to
    /// `build`) in the order of the leaves that hold them.
    pub orders: Vec<Vec<u32>>,
    /// Nodes on the longest path from the root to a leaf, the root counted.
    pub depth: u32,
}

impl Bvh {
    /// The most entries a walk's stack holds: each node on the path to
    /// the one visited leaves at most three of its children waiting.
    pub fn stack_size(&self) -> usize {
        (WIDTH - 1) * self.depth as usize
    }

    /// The stack the shader declares: for the depth a tree of this many
    /// primitives has (`expected_depth`), or the tree's own where it is
    /// deeper. So moving a primitive, which changes the depth by a level
    /// or two, keeps the variant and its compiled shader (every position
    /// of a sphere in a mesh scene compiled anew), at the cost of a few
    /// entries more than the tree needs (a larger private array is slower
    /// on Mesa 22.3: 192 entries cost 16 %; docs/performance.md). `count`
    /// is the primitives the tree was built over.
    pub fn shader_stack(&self, count: usize) -> usize {
        (WIDTH - 1) * self.depth.max(expected_depth(count)) as usize
    }
}

/// The depth of a 4-wide SAH tree over `count` primitives, with room: the
/// ceiling of log4(count), and four levels more (the scenes here are 0 to
/// 3.5 levels deeper than log4 of their count).
pub fn expected_depth(count: usize) -> u32 {
    let mut levels = 0;
    let mut reach = 1usize;
    while reach < count {
        reach = reach.saturating_mul(4);
        levels += 1;
    }
    levels + 4
}

/// A node of the binary tree the SAH builds, before it is collapsed.
#[derive(Debug, Clone, Copy)]
enum Built {
    /// A leaf of the slots `start..start + count` of the build order.
    Leaf { start: usize, count: usize },
    /// The children's indices in the build list.
    Inner { low: usize, high: usize },
}

/// A built node and its box, padded and rounded outwards to f32.
type Boxed = (Built, ([f32; 3], [f32; 3]));

/// Builds the tree over `bounds`, one box per primitive (at least one), of
/// the kinds `kinds` (one each; each leaf holds one kind).
pub fn build(bounds: &[Aabb], kinds: &[u32]) -> Bvh {
    assert!(!bounds.is_empty(), "a BVH needs a primitive");
    assert_eq!(bounds.len(), kinds.len());
    let mut b = Builder {
        bounds,
        kinds,
        centers: bounds.iter().map(Aabb::center).collect(),
        order: (0..bounds.len() as u32).collect(),
        built: Vec::with_capacity(2 * bounds.len() / LEAF_MAX + 1),
        depth: 0,
    };
    b.node(0, bounds.len(), 1);
    assert!(
        b.depth <= MAX_DEPTH,
        "BVH depth {} over {MAX_DEPTH}",
        b.depth
    );
    // Each leaf's slots, counted within its kind.
    let kind_count = kinds.iter().max().map_or(0, |k| *k as usize + 1);
    let mut orders = vec![Vec::new(); kind_count];
    let mut at_in_kind = Vec::with_capacity(b.order.len());
    for &i in &b.order {
        let order = &mut orders[kinds[i as usize] as usize];
        at_in_kind.push(order.len() as u32);
        order.push(i);
    }
    assert!(
        orders.iter().all(|o| o.len() <= MAX_PRIMS) && kind_count <= 16,
        "a leaf word addresses 2^24 primitives of each of 16 kinds"
    );
    let leaf_word = |start: usize, count: usize| {
        let kind = kinds[b.order[start] as usize];
        at_in_kind[start] << 8 | kind << 4 | count as u32
    };
    let mut nodes = Vec::with_capacity(b.built.len() / 2 + 1);
    let depth = collapse(&b.built, 0, &leaf_word, &mut nodes);
    let mut packed = Vec::with_capacity(nodes.len());
    for node in &mut nodes {
        let (bytes, boxes) = quantize::pack(node);
        packed.push(bytes);
        *node = boxes;
    }
    Bvh {
        nodes,
        packed,
        orders,
        depth,
    }
}

/// Appends the wide node whose children are the binary tree's nodes below
/// `built[i]`: its two children, then, while fewer than `WIDTH`, the inner
/// one of largest area opened into its two; then each inner child's own
/// node after it. Returns the depth of the subtree in wide nodes.
fn collapse(
    built: &[Boxed],
    i: usize,
    leaf_word: &dyn Fn(usize, usize) -> u32,
    nodes: &mut Vec<Node>,
) -> u32 {
    let mut kids = match built[i].0 {
        Built::Inner { low, high } => vec![low, high],
        // A tree of one leaf: the root holds it.
        Built::Leaf { .. } => vec![i],
    };
    let area = |k: usize| {
        let (lo, hi) = built[k].1;
        let e: Vec<f64> = (0..3)
            .map(|a| f64::from(hi[a]) - f64::from(lo[a]))
            .collect();
        e[0] * e[1] + e[1] * e[2] + e[2] * e[0]
    };
    while kids.len() < WIDTH {
        // The first of the largest, so that the build is deterministic.
        let widest = kids
            .iter()
            .enumerate()
            .filter(|(_, &k)| matches!(built[k].0, Built::Inner { .. }))
            .fold(None, |best: Option<(usize, f64)>, (at, &k)| {
                let a = area(k);
                match best {
                    Some((_, b)) if b >= a => best,
                    _ => Some((at, a)),
                }
            });
        let Some((at, _)) = widest else { break };
        let Built::Inner { low, high } = built[kids[at]].0 else {
            unreachable!("an inner child")
        };
        kids[at] = low;
        kids.insert(at + 1, high);
    }
    let index = nodes.len();
    nodes.push(Node {
        child: [EMPTY; WIDTH],
        ..Node::default()
    });
    let mut depth = 0;
    for (slot, &k) in kids.iter().enumerate() {
        let word = match built[k].0 {
            Built::Leaf { start, count } => leaf_word(start, count),
            Built::Inner { .. } => {
                let child = nodes.len();
                depth = depth.max(collapse(built, k, leaf_word, nodes));
                Child::inner(child)
            }
        };
        nodes[index].set_child(slot, built[k].1, word);
    }
    depth + 1
}

struct Builder<'a> {
    bounds: &'a [Aabb],
    kinds: &'a [u32],
    centers: Vec<DVec3>,
    order: Vec<u32>,
    /// The binary tree, with each node's box.
    built: Vec<Boxed>,
    depth: u32,
}

impl Builder<'_> {
    fn bounds_of(&self, start: usize, end: usize) -> (Aabb, Aabb) {
        let mut all = Aabb::EMPTY;
        let mut centers = Aabb::EMPTY;
        for &i in &self.order[start..end] {
            all = all.union(self.bounds[i as usize]);
            centers = centers.grow(self.centers[i as usize]);
        }
        (all, centers)
    }

    /// Builds the subtree of slots start..end; returns its index in `built`.
    fn node(&mut self, start: usize, end: usize, depth: u32) -> usize {
        self.depth = self.depth.max(depth);
        let (bounds, centers) = self.bounds_of(start, end);
        let count = end - start;
        let index = self.built.len();
        let boxed = padded(bounds);
        self.built.push((Built::Leaf { start, count }, boxed));
        let split = if count == 1 {
            None
        } else if depth >= DEPTH_SWITCH {
            Some(self.median(start, end, centers))
        } else {
            self.sah(start, end, bounds, centers)
        }
        .or_else(|| self.by_kind(start, end));
        if let Some((mid, _axis)) = split {
            let low = self.node(start, mid, depth + 1);
            let high = self.node(mid, end, depth + 1);
            self.built[index] = (Built::Inner { low, high }, boxed);
        }
        index
    }

    /// A leaf holds one kind: where start..end mixes kinds, splits off the
    /// first slot's kind (a stable partition).
    fn by_kind(&mut self, start: usize, end: usize) -> Option<(usize, usize)> {
        let kinds = self.kinds;
        let first = kinds[self.order[start] as usize];
        let slots = &mut self.order[start..end];
        if slots.iter().all(|&i| kinds[i as usize] == first) {
            return None;
        }
        let (mut same, other): (Vec<u32>, Vec<u32>) =
            slots.iter().partition(|&&i| kinds[i as usize] == first);
        let mid = same.len();
        same.extend(other);
        slots.copy_from_slice(&same);
        Some((start + mid, 0))
    }

    /// Splits at the median centre along the widest axis of the centres.
    fn median(&mut self, start: usize, end: usize, centers: Aabb) -> (usize, usize) {
        let axis = widest(centers);
        let c = &self.centers;
        let mid = start + (end - start) / 2;
        self.order[start..end].select_nth_unstable_by(mid - start, |a, b| {
            c[*a as usize][axis]
                .total_cmp(&c[*b as usize][axis])
                .then(a.cmp(b))
        });
        (mid, axis)
    }

    /// The binned SAH split over all three axes, or None where a leaf is
    /// cheaper and small enough.
    fn sah(
        &mut self,
        start: usize,
        end: usize,
        bounds: Aabb,
        centers: Aabb,
    ) -> Option<(usize, usize)> {
        let count = end - start;
        let extent = centers.hi - centers.lo;
        let mut best: Option<(f64, usize, usize)> = None; // cost, axis, bins left
        for axis in 0..3 {
            if extent[axis] <= 0.0 {
                continue;
            }
            let scale = BINS as f64 / extent[axis];
            let bin_of = |c: DVec3| (((c[axis] - centers.lo[axis]) * scale) as usize).min(BINS - 1);
            let mut boxes = [Aabb::EMPTY; BINS];
            let mut counts = [0usize; BINS];
            for &i in &self.order[start..end] {
                let b = bin_of(self.centers[i as usize]);
                boxes[b] = boxes[b].union(self.bounds[i as usize]);
                counts[b] += 1;
            }
            // Right-hand sweeps, then left-hand sweep with the costs.
            let mut right_area = [0.0; BINS];
            let mut right_count = [0usize; BINS];
            let (mut acc, mut n) = (Aabb::EMPTY, 0);
            for b in (1..BINS).rev() {
                acc = acc.union(boxes[b]);
                n += counts[b];
                right_area[b] = acc.half_area();
                right_count[b] = n;
            }
            let (mut acc, mut n) = (Aabb::EMPTY, 0);
            for b in 1..BINS {
                acc = acc.union(boxes[b - 1]);
                n += counts[b - 1];
                if n == 0 || right_count[b] == 0 {
                    continue;
                }
                let cost = acc.half_area() * n as f64 + right_area[b] * right_count[b] as f64;
                if best.is_none_or(|(c, _, _)| cost < c) {
                    best = Some((cost, axis, b));
                }
            }
        }
        let leaf_cost = COST_PRIM * count as f64;
        let Some((cost, axis, bin)) = best else {
            // Every centre is the same point: only a split by index is left.
            return (count > LEAF_MAX).then_some((start + count / 2, 0));
        };
        let split_cost = COST_NODE + COST_PRIM * cost / bounds.half_area().max(f64::MIN_POSITIVE);
        if count <= LEAF_MAX && leaf_cost <= split_cost {
            return None;
        }
        let scale = BINS as f64 / extent[axis];
        let lo = centers.lo[axis];
        let c = &self.centers;
        let slots = &mut self.order[start..end];
        // A stable partition keeps the build deterministic.
        let (mut left, right): (Vec<u32>, Vec<u32>) = slots
            .iter()
            .partition(|&&i| ((((c[i as usize][axis] - lo) * scale) as usize).min(BINS - 1)) < bin);
        let mid = left.len();
        left.extend(right);
        slots.copy_from_slice(&left);
        Some((start + mid, axis))
    }
}

fn widest(b: Aabb) -> usize {
    let e = b.hi - b.lo;
    if e.x >= e.y && e.x >= e.z {
        0
    } else if e.y >= e.z {
        1
    } else {
        2
    }
}

/// The box in f32, padded and rounded outwards. The pad (2^-14 of the box's
/// extent plus 2^-18 of its largest coordinate, hundreds of f32 ulps)
/// covers the rounding of the slab test and of the primitive's own t, so a
/// ray that the primitive test would call a hit always enters the box.
pub(crate) fn padded(b: Aabb) -> ([f32; 3], [f32; 3]) {
    let mut lo = [0.0f32; 3];
    let mut hi = [0.0f32; 3];
    for a in 0..3 {
        let size = b.lo[a].abs().max(b.hi[a].abs());
        let pad = (b.hi[a] - b.lo[a]) * (1.0 / 16384.0) + size * (1.0 / 262144.0);
        lo[a] = round_down(b.lo[a] - pad);
        hi[a] = round_up(b.hi[a] + pad);
    }
    (lo, hi)
}

pub(crate) fn round_down(x: f64) -> f32 {
    let f = x as f32;
    if f64::from(f) > x {
        next_toward_neg(f)
    } else {
        f
    }
}

fn round_up(x: f64) -> f32 {
    -round_down(-x)
}

/// The next f32 below `f` (finite `f`).
fn next_toward_neg(f: f32) -> f32 {
    if f == 0.0 {
        return -f32::from_bits(1);
    }
    let bits = f.to_bits();
    f32::from_bits(if f > 0.0 { bits - 1 } else { bits + 1 })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spheres(n: usize) -> Vec<Aabb> {
        // A deterministic scatter with clusters and duplicates.
        (0..n)
            .map(|i| {
                let t = i as f64;
                let c = DVec3::new(
                    (t * 0.7).sin() * 50.0,
                    (t * 1.3).cos() * 20.0,
                    (i % 7) as f64,
                );
                Aabb::sphere(c, 0.1 + (i % 5) as f64 * 0.3)
            })
            .collect()
    }

    /// Every primitive is in exactly one leaf, every child's box holds the
    /// primitives of its subtree, every node is reached once, and `depth`
    /// is the deepest path.
    fn check(b: &[Aabb], bvh: &Bvh) {
        assert_eq!(bvh.orders.iter().map(Vec::len).sum::<usize>(), b.len());
        assert_eq!(bvh.packed.len(), bvh.nodes.len());
        let mut seen = vec![0; b.len()];
        let mut reached = vec![0; bvh.nodes.len()];
        let (depth, _) = walk(bvh, b, 0, &mut seen, &mut reached);
        assert_eq!(depth, bvh.depth);
        assert!(seen.iter().all(|&s| s == 1));
        assert!(reached.iter().all(|&r| r == 1));
    }

    /// Checks node `i`: its depth and the primitives below it.
    fn walk(
        bvh: &Bvh,
        b: &[Aabb],
        i: usize,
        seen: &mut [u32],
        reached: &mut [u32],
    ) -> (u32, Vec<usize>) {
        reached[i] += 1;
        let node = bvh.nodes[i];
        let mut depth = 0;
        let mut below = Vec::new();
        for k in 0..WIDTH {
            let (lo, hi) = node.child_box(k);
            let inside = |a: &Aabb| {
                (0..3).all(|x| f64::from(lo[x]) <= a.lo[x] && a.hi[x] <= f64::from(hi[x]))
            };
            let prims = match Child::of(node.child[k]) {
                Child::Empty => continue,
                Child::Leaf(kind, r) => {
                    assert!(!r.is_empty() && r.len() <= LEAF_MAX);
                    r.map(|at| bvh.orders[kind][at] as usize).collect()
                }
                Child::Inner(c) => {
                    assert!(c > i, "children come after their parent");
                    let (d, prims) = walk(bvh, b, c, seen, reached);
                    depth = depth.max(d);
                    prims
                }
            };
            for &p in &prims {
                assert!(inside(&b[p]), "node {i} child {k} misses primitive {p}");
            }
            if matches!(Child::of(node.child[k]), Child::Leaf(..)) {
                for &p in &prims {
                    seen[p] += 1;
                }
            }
            below.extend(prims);
        }
        assert!(!below.is_empty());
        (depth + 1, below)
    }

    #[test]
    fn every_primitive_is_in_one_leaf_inside_every_box_above_it() {
        for n in [1, 2, 3, 5, 17, 100, 1000] {
            let b = spheres(n);
            check(&b, &build(&b, &vec![0; b.len()]));
        }
    }

    #[test]
    fn nodes_are_filled_and_the_tree_is_shallow() {
        let b = spheres(1000);
        let bvh = build(&b, &vec![0; b.len()]);
        // A binary tree's nodes would hold two children each; leaves of
        // up to four spheres leave some slots of the last levels empty.
        let slots: usize = bvh
            .nodes
            .iter()
            .map(|n| n.child.iter().filter(|&&w| w != EMPTY).count())
            .sum();
        assert!(
            slots as f64 >= 2.8 * bvh.nodes.len() as f64,
            "{slots} in {}",
            bvh.nodes.len()
        );
        assert!(bvh.depth <= 8, "depth {}", bvh.depth);
        assert_eq!(bvh.stack_size(), 3 * bvh.depth as usize);
    }

    #[test]
    fn child_words_name_what_they_hold() {
        assert_eq!(Child::of(EMPTY), Child::Empty);
        assert_eq!(Child::of(Child::inner(7)), Child::Inner(7));
        assert_eq!(Child::of(5 << 8 | 2 << 4 | 3), Child::Leaf(2, 5..8));
    }

    #[test]
    fn identical_primitives_still_make_a_shallow_tree() {
        let b = vec![Aabb::sphere(DVec3::ONE, 1.0); 10_000];
        let bvh = build(&b, &vec![0; b.len()]);
        check(&b, &bvh);
        assert!(bvh.depth <= 16, "depth {}", bvh.depth);
    }

    #[test]
    fn each_leaf_holds_one_kind() {
        let b = spheres(300);
        let kinds: Vec<u32> = (0..b.len()).map(|i| (i % 3 == 0) as u32 * 2).collect();
        let bvh = build(&b, &kinds);
        check(&b, &bvh);
        for node in &bvh.nodes {
            for word in node.child {
                if let Child::Leaf(kind, r) = Child::of(word) {
                    for at in r {
                        assert_eq!(kinds[bvh.orders[kind][at] as usize], kind as u32);
                    }
                }
            }
        }
        assert!(bvh.orders[1].is_empty());
    }

    #[test]
    fn boxes_are_rounded_outwards() {
        let b = Aabb::sphere(DVec3::new(0.1, 1e6 + 0.3, -7.7), 1e-3);
        let (lo, hi) = padded(b);
        for a in 0..3 {
            assert!(f64::from(lo[a]) < b.lo[a] && b.hi[a] < f64::from(hi[a]));
        }
    }
}
