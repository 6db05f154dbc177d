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

/// The crowd's image without scene management, and a world of it with
/// its BVH, to alter.
fn crowd_and_its_tree() -> (Image, World<f64>) {
    let scene = crowd();
    let reference = render_rows::<f64>(&scene, Accel::None, &|_| {});
    (reference, World::<f64>::new(&scene, Accel::Bvh))
}

/// The CPU check that images do not depend on the BVH (tests/accel.rs) can
/// fail: a tree whose boxes miss part of what they
/// hold, or whose tie rule is wrong, renders another image.
#[test]
fn a_broken_tree_changes_the_image() {
    let (reference, mut world) = crowd_and_its_tree();
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
    let (reference, mut world) = crowd_and_its_tree();
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

/// The check that images do not depend on the tables (tests/accel.rs) can
/// fail: lists that leave out a cell's last primitive, or an eye tile's,
/// render another image; whole lists in reversed order render the same.
#[test]
fn lists_that_miss_a_primitive_change_the_image() {
    let scene = crowd();
    let reference: Image = render_rows::<f64>(&scene, Accel::None, &|_| {});
    let whole = World::<f64>::new(&scene, Accel::Tables);
    assert!(whole.tables.is_some());
    assert!(render_world(&whole, &|_| {}) == reference);
    for eye in [false, true] {
        let mut world = World::<f64>::new(&scene, Accel::Tables);
        let t = world.tables.as_mut().unwrap();
        let first_eye = t
            .eye
            .map(|g| t.grids[g as usize].first_cell as usize)
            .unwrap();
        let range = if eye {
            first_eye..t.cells.len()
        } else {
            0..first_eye
        };
        for cell in &mut t.cells[range] {
            if cell.count != crate::accel::tables::WALK && cell.count > 0 {
                cell.count -= 1;
            }
        }
        assert!(render_world(&world, &|_| {}) != reference, "eye {eye}");
    }
    let mut world = World::<f64>::new(&scene, Accel::Tables);
    let t = world.tables.as_mut().unwrap();
    let walk = crate::accel::tables::WALK;
    for cell in t.cells.clone() {
        if cell.count != walk {
            let (f, n) = (cell.first as usize, cell.count as usize);
            t.entries[f..f + n].reverse();
        }
    }
    // Reversed, a list's keys no longer end its scan early where they
    // should: each entry is tested, so the image stays.
    for e in &mut t.entries {
        e.key = f32::NEG_INFINITY;
    }
    assert!(render_world(&world, &|_| {}) == reference);
}
