//! The BVH checks can fail: the CPU reference with an altered tree.

use super::{render_rows, render_world, world::World};
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
    for node in tree.nodes.iter_mut().filter(|n| n.leaf != 0) {
        node.hi[1] = (node.lo[1] + node.hi[1]) / 2.0;
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
    // Every layout holds the same leaves; take them once.
    let leaves: Vec<_> = tree.layout(0).iter().filter_map(|n| n.prims()).collect();
    assert!(
        leaves.iter().any(|(_, r)| r.len() >= 2),
        "leaves of several spheres"
    );
    for (kind, r) in leaves {
        tree.orders[kind][r].reverse();
    }
    assert!(render_world(&world, &|_| {}) == reference);
}
