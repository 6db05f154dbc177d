//! The checks of validate.rs that need a whole scene.

use super::*;

/// The bound, met at a count a test can build: 2^24 + 1 spheres are a
/// 168 MB file. Without the check the BVH's build panicked there.
#[test]
fn a_kind_past_the_bound_is_named() {
    let text = include_str!("../../scenes/seed-fig3.toml");
    let scene =
        crate::scene::parse(text, Path::new("seed-fig3.toml"), &Overrides::default()).unwrap();
    let spheres = scene.prims.counts()[0];
    assert!(spheres > 1 && crate::prim::KINDS[0].key == "spheres");
    let (kind, n) = over_count(&scene, spheres - 1).expect("past the bound");
    assert_eq!((kind.key, n), ("spheres", spheres));
    assert!(over_count(&scene, spheres).is_none());
    const { assert!(crate::accel::bvh::MAX_PRIMS == 1 << 24) };
}
