//! A bounding volume hierarchy over the bounded primitives (spheres),
//! built once on the host with binned SAH (Wald 2007) and flattened
//! depth-first into 32-byte nodes that both renderers walk the same way
//! (shaders/bvh.glsl, `cpu::intersect`).
//!
//! The walk needs no stack. Nodes are stored in pre-order and each one keeps
//! the index of the node that follows its subtree (`skip`): a ray that
//! misses a node's box, or has tested a leaf, goes on at `skip`; one that
//! enters an inner node goes on at the next index. A stack on lavapipe is
//! a per-lane array in memory; this walk keeps only an index in a register.
//!
//! A pre-order fixes which child comes first, so the tree is flattened
//! eight times, once per octant of ray directions: in the layout for an
//! octant, the child on the side a ray of that octant meets first along the
//! node's split axis comes first. A nearest-hit walk then finds near hits
//! early and skips boxes behind them. Ray direction d takes the layout
//! `octant(d)`; the eight layouts lie one after the other. Where eight
//! would take more than `OCTANT_BYTES_MAX`, there is one layout, walked by
//! every ray (a sphereflake of 597,871 spheres has 1.2 million nodes).
//!
//! Boxes are f32 for every precision, rounded outwards and padded so that a
//! box is never missed by a ray that hits what is inside it (docs/performance.md,
//! The BVH): the image does not depend on the tree.

use glam::DVec3;

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
const COST_NODE: f64 = 3.0;
const COST_PRIM: f64 = 1.5;

crate::base::interface::gpu_struct!(
    /// One node as both renderers read it: 32 bytes, f32 in both precisions.
    pub mod node: "Node" {
        lo: float3,
        /// The node after this one's subtree; the node count for the last.
        skip: uint,
        hi: float3,
        /// 0 for an inner node; for a leaf, first << 8 | kind << 4 | count:
        /// `count` primitives of one kind, from `first` in that kind's leaf order.
        leaf: uint,
    }
);

pub use node::Values as Node;

/// The most primitives of one kind a leaf word can address.
pub const MAX_PRIMS: usize = 1 << 24;

impl Node {
    /// The leaf's kind and its primitives' range in that kind's leaf order
    /// (`Bvh::orders`), or None for an inner node.
    pub fn prims(&self) -> Option<(usize, std::ops::Range<usize>)> {
        (self.leaf != 0).then(|| {
            let first = (self.leaf >> 8) as usize;
            let kind = (self.leaf >> 4 & 15) as usize;
            (kind, first..first + (self.leaf & 15) as usize)
        })
    }
}

/// The tree, and which primitive each leaf slot holds.
#[derive(Debug, Clone)]
pub struct Bvh {
    /// `layouts` layouts (`OCTANTS` or 1) of `layout_len` nodes each; skip
    /// links count from the start of their layout.
    pub nodes: Vec<Node>,
    pub layout_len: usize,
    pub layouts: usize,
    /// For each kind, the indices of its primitives (in the list given to
    /// `build`) in the order of the leaves that hold them.
    pub orders: Vec<Vec<u32>>,
    pub depth: u32,
}

/// Layouts: one per octant of ray directions.
pub const OCTANTS: usize = 8;
/// The most bytes the eight layouts may take together: half of the 128 MiB
/// storage buffer range that Vulkan guarantees.
pub const OCTANT_BYTES_MAX: usize = 64 << 20;

/// The layout a ray of direction (x, y, z) walks: bit k set where
/// component k is negative (-0 counts as positive, as in the shader). The
/// walks compute it in their own arithmetic (cpu/intersect.rs, the shader).
#[cfg(test)]
pub fn octant(x: f64, y: f64, z: f64) -> usize {
    usize::from(x < 0.0) | usize::from(y < 0.0) << 1 | usize::from(z < 0.0) << 2
}

impl Bvh {
    /// The nodes a ray of the given octant walks.
    pub fn layout(&self, octant: usize) -> &[Node] {
        let k = if self.layouts == 1 { 0 } else { octant };
        &self.nodes[k * self.layout_len..(k + 1) * self.layout_len]
    }
}

/// A node of the built tree, before it is flattened.
#[derive(Debug, Clone, Copy)]
enum Built {
    Leaf,
    /// The children's indices in the build list, split along `axis` (the
    /// first holds the lower centres).
    Inner {
        axis: usize,
        low: usize,
        high: usize,
    },
}

/// Builds the tree over `bounds`, one box per primitive (at least one), of
/// the kinds `kinds` (one each; each leaf holds one kind).
pub fn build(bounds: &[Aabb], kinds: &[u32]) -> Bvh {
    build_within(bounds, kinds, OCTANT_BYTES_MAX)
}

/// As `build`, with eight layouts only where they fit `octant_bytes_max`.
fn build_within(bounds: &[Aabb], kinds: &[u32], octant_bytes_max: usize) -> Bvh {
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
    let layout_len = b.built.len();
    let layouts = if OCTANTS * layout_len * std::mem::size_of::<Node>() <= octant_bytes_max {
        OCTANTS
    } else {
        1
    };
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
    for (built, node) in &mut b.built {
        if let Built::Leaf = built {
            let (start, count) = ((node.leaf >> 4) as usize, node.leaf & 15);
            let kind = kinds[b.order[start] as usize];
            node.leaf = at_in_kind[start] << 8 | kind << 4 | count;
        }
    }
    let mut nodes = Vec::with_capacity(layouts * layout_len);
    for oct in 0..layouts {
        let start = nodes.len();
        flatten(&b.built, 0, oct, start, &mut nodes);
    }
    Bvh {
        nodes,
        layout_len,
        layouts,
        orders,
        depth: b.depth,
    }
}

/// Appends the subtree of `built[i]` in pre-order for octant `oct`, its
/// skip links relative to `base`.
fn flatten(built: &[(Built, Node)], i: usize, oct: usize, base: usize, out: &mut Vec<Node>) {
    let (kind, node) = built[i];
    let at = out.len();
    out.push(node);
    if let Built::Inner { axis, low, high } = kind {
        // A ray going down the axis meets the high side first.
        let (first, second) = if oct >> axis & 1 == 1 {
            (high, low)
        } else {
            (low, high)
        };
        flatten(built, first, oct, base, out);
        flatten(built, second, oct, base, out);
    }
    out[at].skip = (out.len() - base) as u32;
}

struct Builder<'a> {
    bounds: &'a [Aabb],
    kinds: &'a [u32],
    centers: Vec<DVec3>,
    order: Vec<u32>,
    /// The tree with each node's box (skip links not yet set).
    built: Vec<(Built, Node)>,
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
        let (lo, hi) = padded(bounds);
        let count = end - start;
        let index = self.built.len();
        // The slot range, until the kinds are numbered apart (`build_within`).
        let leaf = Node {
            lo,
            skip: 0,
            hi,
            leaf: ((start as u32) << 4) | count as u32,
        };
        self.built.push((Built::Leaf, leaf));
        let split = if count == 1 {
            None
        } else if depth >= DEPTH_SWITCH {
            Some(self.median(start, end, centers))
        } else {
            self.sah(start, end, bounds, centers)
        }
        .or_else(|| self.by_kind(start, end));
        if let Some((mid, axis)) = split {
            let low = self.node(start, mid, depth + 1);
            let high = self.node(mid, end, depth + 1);
            self.built[index] = (Built::Inner { axis, low, high }, Node { leaf: 0, ..leaf });
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
fn padded(b: Aabb) -> ([f32; 3], [f32; 3]) {
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

fn round_down(x: f64) -> f32 {
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

    /// In every layout: every primitive is in exactly one leaf, every
    /// node's box holds its subtree, and the skip links close each subtree.
    fn check(b: &[Aabb], bvh: &Bvh) {
        assert_eq!(bvh.nodes.len(), bvh.layouts * bvh.layout_len);
        assert_eq!(bvh.orders.iter().map(Vec::len).sum::<usize>(), b.len());
        for oct in 0..OCTANTS {
            let nodes = bvh.layout(oct);
            let mut seen = vec![0; b.len()];
            assert_eq!(walk(bvh, nodes, b, 0, &mut seen), nodes.len() as u32);
            assert!(seen.iter().all(|&s| s == 1));
        }
    }

    fn walk(bvh: &Bvh, nodes: &[Node], b: &[Aabb], i: u32, seen: &mut [u32]) -> u32 {
        let node = nodes[i as usize];
        let inside = |a: Aabb| {
            (0..3).all(|k| f64::from(node.lo[k]) <= a.lo[k] && a.hi[k] <= f64::from(node.hi[k]))
        };
        let next = match node.prims() {
            Some((kind, r)) => {
                assert!(!r.is_empty() && r.len() <= LEAF_MAX);
                for at in r {
                    let p = bvh.orders[kind][at] as usize;
                    seen[p] += 1;
                    assert!(inside(b[p]));
                }
                i + 1
            }
            None => {
                let after_first = walk(bvh, nodes, b, i + 1, seen);
                walk(bvh, nodes, b, after_first, seen)
            }
        };
        assert_eq!(next, node.skip, "node {i}");
        next
    }

    #[test]
    fn each_octant_walks_the_near_child_first() {
        // Two clusters far apart along x: a ray going +x meets the low one
        // (spheres 0..8) first, a ray going -x the high one.
        let b: Vec<Aabb> = (0..16)
            .map(|i| {
                let x = if i < 8 { -100.0 } else { 100.0 };
                Aabb::sphere(DVec3::new(x, (i % 8) as f64 * 3.0, 0.0), 1.0)
            })
            .collect();
        let bvh = build(&b, &vec![0; b.len()]);
        check(&b, &bvh);
        let first_prim = |oct: usize| {
            let (kind, leaf) = bvh.layout(oct).iter().find_map(Node::prims).unwrap();
            bvh.orders[kind][leaf.start]
        };
        assert!(first_prim(octant(1.0, 0.5, -0.5)) < 8);
        assert!(first_prim(octant(-1.0, 0.5, -0.5)) >= 8);
    }

    #[test]
    fn every_primitive_is_in_one_leaf_inside_every_box_above_it() {
        for n in [1, 2, 3, 5, 17, 100, 1000] {
            let b = spheres(n);
            check(&b, &build(&b, &vec![0; b.len()]));
        }
    }

    #[test]
    fn a_tree_too_large_for_eight_layouts_keeps_one() {
        let b = spheres(1000);
        let eight = build(&b, &vec![0; b.len()]);
        assert_eq!(eight.layouts, OCTANTS);
        let bytes = OCTANTS * eight.layout_len * std::mem::size_of::<Node>();
        assert_eq!(build_within(&b, &vec![0; b.len()], bytes).layouts, OCTANTS);
        let one = build_within(&b, &vec![0; b.len()], bytes - 1);
        assert_eq!(one.layouts, 1);
        check(&b, &one);
        assert_eq!(one.layout(5).as_ptr(), one.layout(0).as_ptr());
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
            if let Some((kind, r)) = node.prims() {
                for at in r {
                    assert_eq!(kinds[bvh.orders[kind][at] as usize], kind as u32);
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
