//! The watchdog separates the driver's compile of a new pipeline (on
//! lavapipe, LLVM at its first dispatch, inside the fence wait) from the
//! render (part 5): a render limit shorter than the compile does not fire
//! on it. A runaway shader is still stopped at the limit
//! (tests/watchdog.rs).

#![cfg(feature = "gpu")]

mod common;

use std::time::Duration;

use glint::gpu::{GpuOptions, Renderer};
use glint::scene::{Overrides, Scene};

#[test]
fn the_drivers_compile_is_not_timed_by_the_renders_watchdog() {
    // Mesa's disk cache would hand back the machine code of an earlier
    // run, and no compile would happen at all. This binary holds this one
    // test, so no other thread reads the environment meanwhile.
    std::env::set_var("MESA_SHADER_CACHE_DISABLE", "true");
    // A limit far below lavapipe's compile of the generic f64 shader (2.3 s
    // on Mesa 25.0, 0.4 s on 22.3, on 2 cores), far above rendering its 8x6
    // pixels.
    let limit = Duration::from_millis(100);
    let mut r = Renderer::new(&GpuOptions {
        validate: true,
        timeout: Some(limit),
        cache_dir: None,
        settings: glint::gpu::RenderSettings {
            generic: true,
            precision: glint::gpu::Precision::F64,
            ..Default::default()
        },
        ..GpuOptions::default()
    })
    .expect("device");
    if !r.device_info().shader_float64 {
        common::skip("the f64 generic shader's cold compile", "no shaderFloat64");
        return;
    }
    let scene = Scene::load(
        &common::repo().join("scenes/seed-fig3.toml"),
        &Overrides {
            width: Some(8),
            height: Some(6),
            ..Overrides::default()
        },
    )
    .unwrap();
    let (_, times) = r
        .render(&scene, &|_| {})
        .expect("the compile is not the render");
    let compile = times.setup.driver_compile_s;
    eprintln!(
        "the driver's compile took {compile:.3} s; the render {:.4} s",
        times.dispatch_s
    );
    if r.device_info().name.contains("llvmpipe") {
        // Without the compile apart, this render would have timed out.
        assert!(
            compile > limit.as_secs_f64(),
            "lavapipe compiled in {compile} s"
        );
    }
    assert!(times.dispatch_s < limit.as_secs_f64());
    // The second render of the same pipeline compiles nothing.
    let (_, again) = r.render(&scene, &|_| {}).unwrap();
    assert_eq!(again.setup.driver_compile_s, 0.0);
}
