//! The validation layer is on in the tests, and a message from it fails the
//! render: a shader whose binding 0 is a storage buffer, where the host binds
//! a uniform buffer, must not render quietly.

mod common;

use glint::gpu::{GpuError, GpuOptions, Renderer};

#[test]
fn a_validation_message_fails_the_render() {
    let dir = tempfile::tempdir().unwrap();
    let bindings = std::fs::read_to_string(common::repo().join("shaders/bindings.glsl")).unwrap();
    let wrong = bindings.replace(
        "layout(std140, set = 0, binding = 0) uniform Globals {",
        "layout(std430, set = 0, binding = 0) readonly buffer Globals {",
    );
    assert_ne!(bindings, wrong);
    std::fs::write(dir.path().join("bindings.glsl"), wrong).unwrap();
    let options = GpuOptions {
        validate: true,
        include_dirs: vec![dir.path().to_owned()],
        ..GpuOptions::default()
    };
    let mut renderer = Renderer::new(&options).expect("device with validation");
    let scene = common::scene(common::SMALL);
    match renderer.render(&scene, &|_| {}) {
        Err(GpuError::Validation(messages)) => assert!(!messages.is_empty()),
        Err(other) => panic!("expected a validation failure, got: {other}"),
        Ok(_) => panic!("a mismatched descriptor type rendered without a validation message"),
    }
}
