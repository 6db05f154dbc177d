//! The BVH checks can fail: the CPU reference with an altered tree.

use super::{render_rows, render_world, world::World};
use crate::accel::bvh::{Child, WIDTH};
use crate::accel::Accel;
use crate::raster::Image;
use crate::scene::{Overrides, Scene};

/// tests/data/crowd.toml: 300 spheres, some coincident (ties on every hit).
fn crowd() -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/crowd.toml");
    Scene::load(&path, &Overrides::default()).unwrap()
}

/// The CPU check that images do not depend on the BVH (tests/accel.rs) can
/// fail: a tree whose boxes miss part of what they
/// hold, or whose tie rule is wrong, renders another image.
#[test]
fn a_broken_tree_changes_the_image() {
    let scene = crowd();
    let reference: Image = render_rows::<f64>(&scene, Accel::None, &|_| {});
    let mut world = World::<f64>::new(&scene, Accel::Bvh);
    let tree = world.bvh.as_mut().unwrap();
    // Shrink every leaf's box to its lower half in y.
    for node in &mut tree.nodes {
        for k in 0..WIDTH {
            if let Child::Leaf(..) = Child::of(node.child[k]) {
                node.hi_y[k] = (node.lo_y[k] + node.hi_y[k]) / 2.0;
            }
        }
    }
    assert!(render_world(&world, &|_| {}) != reference);
}

/// The tie rule, not the walk's order, decides between coincident spheres:
/// reversing the primitives of every leaf keeps the image.
#[test]
fn leaf_order_does_not_matter() {
    let scene = crowd();
    let reference: Image = render_rows::<f64>(&scene, Accel::None, &|_| {});
    let mut world = World::<f64>::new(&scene, Accel::Bvh);
    let tree = world.bvh.as_mut().unwrap();
    let leaves: Vec<_> = tree
        .nodes
        .iter()
        .flat_map(|n| n.child)
        .filter_map(|w| match Child::of(w) {
            Child::Leaf(kind, r) => Some((kind, r)),
            _ => None,
        })
        .collect();
    assert!(
        leaves.iter().any(|(_, r)| r.len() >= 2),
        "leaves of several spheres"
    );
    for (kind, r) in leaves {
        tree.orders[kind][r].reverse();
    }
    assert!(render_world(&world, &|_| {}) == reference);
}
