//! One node of the 4-wide tree as both renderers walk it, and the words
//! of its children (src/accel/bvh.rs builds the tree, quantize.rs packs a
//! node into bytes; both use this file, and neither the other's).

/// One node as both renderers walk it: its four children's boxes, a row
/// of four a coordinate, and their child words. The shader reads it in
/// bytes (`quantize::Packed`), which decode to these boxes exactly.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Node {
    pub lo_x: [f32; 4],
    pub hi_x: [f32; 4],
    pub lo_y: [f32; 4],
    pub hi_y: [f32; 4],
    pub lo_z: [f32; 4],
    pub hi_z: [f32; 4],
    /// Each child's word: an inner node, a leaf, or `EMPTY`.
    pub child: [u32; 4],
}

/// Children a node has at most.
pub const WIDTH: usize = 4;

/// The word of a child slot that holds nothing (its box is never entered).
pub const EMPTY: u32 = u32::MAX;

/// The most primitives of one kind a leaf word can address.
pub const MAX_PRIMS: usize = 1 << 24;

/// The most nodes a child word can address.
pub const MAX_NODES: usize = 1 << 28;

/// What a child word names.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Child {
    /// An inner node, by its index.
    Inner(usize),
    /// A leaf: its kind and its primitives' range in that kind's leaf
    /// order (`Bvh::orders`).
    Leaf(usize, std::ops::Range<usize>),
    Empty,
}

impl Child {
    /// The child a word names.
    pub fn of(word: u32) -> Self {
        if word == EMPTY {
            Child::Empty
        } else if word & 15 == 0 {
            Child::Inner((word >> 4) as usize)
        } else {
            let first = (word >> 8) as usize;
            let kind = (word >> 4 & 15) as usize;
            Child::Leaf(kind, first..first + (word & 15) as usize)
        }
    }

    /// An inner node's word.
    pub(crate) fn inner(index: usize) -> u32 {
        assert!(index < MAX_NODES, "a child word addresses 2^28 nodes");
        (index as u32) << 4
    }
}

impl Node {
    /// Child `k`'s box, low and high corners.
    pub fn child_box(&self, k: usize) -> ([f32; 3], [f32; 3]) {
        (
            [self.lo_x[k], self.lo_y[k], self.lo_z[k]],
            [self.hi_x[k], self.hi_y[k], self.hi_z[k]],
        )
    }

    /// Sets child `k`: its box and its word.
    pub(crate) fn set_child(&mut self, k: usize, (lo, hi): ([f32; 3], [f32; 3]), word: u32) {
        self.lo_x[k] = lo[0];
        self.lo_y[k] = lo[1];
        self.lo_z[k] = lo[2];
        self.hi_x[k] = hi[0];
        self.hi_y[k] = hi[1];
        self.hi_z[k] = hi[2];
        self.child[k] = word;
    }
}
