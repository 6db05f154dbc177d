//! A built tree fitted again to primitives that moved: the same nodes and
//! leaves, each box recomputed bottom-up by the build's own rule (the
//! padded box of every primitive below it). A notebook that moves a sphere
//! in a mesh scene pays for this, not for a new SAH build.
//!
//! The image does not depend on the tree (src/accel/mod.rs), only the time
//! does: a tree refitted after large moves is walked more slowly than a new
//! one would be, never wrongly. Fitted to primitives that did not move, it
//! is the built tree bit for bit.

use super::bvh::{padded, Bvh, Child, Node, EMPTY, WIDTH};
use super::quantize::{self, Packed};
use crate::base::aabb::Aabb;

/// What a refit keeps of a tree: each node's child words and each kind's
/// leaf order (indices in the list `boxes` gives `refit` of that kind),
/// and after a refit its nodes' boxes, so that the next one packs again
/// only the nodes whose boxes changed (a moved sphere's path to the root;
/// packing every node was most of a refit).
#[derive(Debug, Clone)]
pub struct Shape {
    words: Vec<[u32; WIDTH]>,
    orders: Vec<Vec<u32>>,
    depth: u32,
    fitted: Option<Fitted>,
}

/// A refitted tree's nodes before and after packing.
#[derive(Debug, Clone)]
struct Fitted {
    boxes: Vec<Node>,
    packed: Vec<Packed>,
    decoded: Vec<Node>,
}

impl Shape {
    /// The shape of `tree`, whose orders are still in it.
    pub fn of(tree: &Bvh) -> Self {
        Shape {
            words: tree.nodes.iter().map(|n| n.child).collect(),
            orders: tree.orders.clone(),
            depth: tree.depth,
            fitted: None,
        }
    }
}

/// The tree of `shape` over `boxes` (each kind's primitives' boxes, None
/// for one that is unbounded), and its shape for the next refit; None
/// where the primitives are not those the tree was built over: another
/// count of some kind, or one of its leaves' primitives without a box.
pub fn refit(shape: &Shape, boxes: &[Vec<Option<Aabb>>]) -> Option<(Bvh, Shape)> {
    let bounded = |k: usize| boxes.get(k).map_or(0, |b| b.iter().flatten().count());
    let same = (0..shape.orders.len().max(boxes.len()))
        .all(|k| shape.orders.get(k).map_or(0, Vec::len) == bounded(k));
    if !same {
        return None;
    }
    let n = shape.words.len();
    let mut below = vec![Aabb::EMPTY; n];
    let mut raw = vec![Node::default(); n];
    // Children come after their parent (bvh::collapse), so a walk from the
    // last node back has every child's box before its parent's.
    for i in (0..n).rev() {
        let mut all = Aabb::EMPTY;
        for (k, &word) in shape.words[i].iter().enumerate() {
            let b = match Child::of(word) {
                Child::Empty => {
                    raw[i].child[k] = EMPTY;
                    continue;
                }
                Child::Inner(c) => below[c],
                Child::Leaf(kind, range) => {
                    let mut b = Aabb::EMPTY;
                    for &p in &shape.orders[kind][range] {
                        b = b.union((*boxes[kind].get(p as usize)?)?);
                    }
                    b
                }
            };
            raw[i].set_child(k, padded(b), word);
            all = all.union(b);
        }
        below[i] = all;
    }
    let mut packed = Vec::with_capacity(n);
    let mut decoded = Vec::with_capacity(n);
    for (i, node) in raw.iter().enumerate() {
        let (bytes, boxes) = match &shape.fitted {
            Some(f) if f.boxes[i] == *node => (f.packed[i], f.decoded[i]),
            _ => quantize::pack(node),
        };
        packed.push(bytes);
        decoded.push(boxes);
    }
    let tree = Bvh {
        nodes: decoded.clone(),
        packed: packed.clone(),
        orders: shape.orders.clone(),
        depth: shape.depth,
    };
    let next = Shape {
        fitted: Some(Fitted {
            boxes: raw,
            packed,
            decoded,
        }),
        ..shape.clone_unfitted()
    };
    Some((tree, next))
}

impl Shape {
    fn clone_unfitted(&self) -> Shape {
        Shape {
            words: self.words.clone(),
            orders: self.orders.clone(),
            depth: self.depth,
            fitted: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::bvh::build;
    use glam::DVec3;

    fn scatter(n: usize, shift: f64) -> Vec<Aabb> {
        (0..n)
            .map(|i| {
                let t = i as f64;
                let c = DVec3::new((t * 0.7).sin() * 50.0, (t * 1.3).cos() * 20.0, shift);
                Aabb::sphere(c, 0.1 + (i % 5) as f64 * 0.3)
            })
            .collect()
    }

    fn by_kind(b: &[Aabb]) -> Vec<Vec<Option<Aabb>>> {
        vec![b.iter().copied().map(Some).collect()]
    }

    #[test]
    fn fitted_to_the_same_primitives_it_is_the_built_tree() {
        for n in [1, 2, 5, 100, 1000] {
            let b = scatter(n, 0.0);
            let tree = build(&b, &vec![0; n]);
            let (fitted, again) = refit(&Shape::of(&tree), &by_kind(&b)).unwrap();
            assert_eq!(fitted.nodes, tree.nodes, "{n} primitives");
            assert_eq!(fitted.packed, tree.packed);
            // Again from a fitted shape, which packs no node anew.
            let (twice, _) = refit(&again, &by_kind(&b)).unwrap();
            assert_eq!(twice.nodes, tree.nodes);
            assert_eq!(twice.packed, tree.packed);
        }
    }

    #[test]
    fn every_box_holds_the_moved_primitives_below_it() {
        let b = scatter(300, 0.0);
        let tree = build(&b, &vec![0; b.len()]);
        let mut moved = b.clone();
        moved[17] = Aabb::sphere(DVec3::new(400.0, -3.0, 9.0), 2.0);
        moved[200] = Aabb::sphere(DVec3::new(-1e3, 0.0, 0.0), 0.5);
        // Moved from the built tree, then moved back and again from the
        // fitted shapes (which pack only the nodes whose boxes changed):
        // each as a refit of the built tree's shape would be.
        let (_, fitted_shape) = refit(&Shape::of(&tree), &by_kind(&b)).unwrap();
        let (fitted, _) = refit(&fitted_shape, &by_kind(&moved)).unwrap();
        let (direct, _) = refit(&Shape::of(&tree), &by_kind(&moved)).unwrap();
        assert_eq!(fitted.nodes, direct.nodes);
        assert_eq!(fitted.packed, direct.packed);
        // Each leaf's primitives lie in every box on the path to it.
        let mut stack = vec![(0usize, Vec::<([f32; 3], [f32; 3])>::new())];
        let mut seen = 0;
        while let Some((i, above)) = stack.pop() {
            for k in 0..WIDTH {
                let node = fitted.nodes[i];
                let mut path = above.clone();
                path.push(node.child_box(k));
                match Child::of(node.child[k]) {
                    Child::Empty => {}
                    Child::Inner(c) => stack.push((c, path)),
                    Child::Leaf(_, range) => {
                        for &p in &fitted.orders[0][range] {
                            seen += 1;
                            let a = moved[p as usize];
                            for (lo, hi) in &path {
                                assert!((0..3)
                                    .all(|x| f64::from(lo[x]) <= a.lo[x]
                                        && a.hi[x] <= f64::from(hi[x])));
                            }
                        }
                    }
                }
            }
        }
        assert_eq!(seen, moved.len());
    }

    #[test]
    fn other_primitives_are_refused() {
        let b = scatter(40, 0.0);
        let shape = Shape::of(&build(&b, &vec![0; b.len()]));
        assert!(refit(&shape, &by_kind(&b[..39])).is_none());
        let mut unbounded = by_kind(&b);
        unbounded[0][3] = None;
        assert!(refit(&shape, &unbounded).is_none());
        assert!(refit(&shape, &[by_kind(&b)[0].clone(), vec![Some(b[0])]]).is_none());
    }
}
