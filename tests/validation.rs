//! The validation layer is on in the tests, and a message from it fails the
//! render: a shader whose binding 0 is a storage buffer, where the host binds
//! a uniform buffer, must not render quietly.

#![cfg(feature = "gpu")]

mod common;

use glint::gpu::{GpuError, GpuOptions, Renderer};

#[test]
fn a_validation_message_fails_the_render() {
    let dir = tempfile::tempdir().unwrap();
    let scene = common::scene(common::SMALL);
    // The interface glint generates for the scene, with binding 0 made a
    // storage buffer, given in its place (-I finds it first).
    let probe = Renderer::new(&GpuOptions::default()).expect("device");
    let (variant, _) = common::variant(&probe, &scene);
    let (name, interface) = variant.generated().remove(0);
    let wrong = interface.replace(
        "layout(std140, set = 0, binding = 0) uniform Globals {",
        "layout(std430, set = 0, binding = 0) readonly buffer Globals {",
    );
    assert_ne!(interface, wrong);
    std::fs::write(dir.path().join(name), wrong).unwrap();
    let options = GpuOptions {
        validate: true,
        include_dirs: vec![dir.path().to_owned()],
        ..GpuOptions::default()
    };
    let mut renderer = Renderer::new(&options).expect("device with validation");
    match renderer.render(&scene, &|_| {}) {
        Err(GpuError::Validation(messages)) => assert!(!messages.is_empty()),
        Err(other) => panic!("expected a validation failure, got: {other}"),
        Ok(_) => panic!("a mismatched descriptor type rendered without a validation message"),
    }
}
