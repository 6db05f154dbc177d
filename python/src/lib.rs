//! glint as a Python module (docs/python.md): `glint._glint`, the Rust half
//! of the package `glint`, whose Python half (python/pysrc/glint/) adds the
//! result types and the docstrings a reader sees first.
//!
//! Every entry point runs inside [`errors::guard`], so a Rust panic is a
//! `glint.Error` and never unwinds into Python. Renders run on a thread of
//! their own while this one waits without the GIL and polls for Ctrl-C
//! (`render::interruptible`).

mod aovs;
mod arrays;
mod compare;
mod dict;
mod document;
mod errors;
mod gil;
mod image;
mod keywords;
mod mesh_params;
mod params;
mod render;
#[cfg(feature = "gpu")]
mod renderer;
mod scene;

use pyo3::prelude::*;

#[pymodule]
fn _glint(m: &Bound<'_, PyModule>) -> PyResult<()> {
    errors::register(m)?;
    gil::register(m)?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<render::Renderer>()?;
    m.add_class::<render::PreparedScene>()?;
    m.add_function(wrap_pyfunction!(scene::load, m)?)?;
    m.add_function(wrap_pyfunction!(scene::loads, m)?)?;
    m.add_function(wrap_pyfunction!(render::render_cpu, m)?)?;
    m.add_function(wrap_pyfunction!(render::devices_json, m)?)?;
    m.add_function(wrap_pyfunction!(image::read, m)?)?;
    m.add_function(wrap_pyfunction!(image::write, m)?)?;
    m.add_function(wrap_pyfunction!(image::write_plane, m)?)?;
    m.add_function(wrap_pyfunction!(image::diff_json, m)?)?;
    m.add_function(wrap_pyfunction!(compare::compare_raw, m)?)?;
    m.add_function(wrap_pyfunction!(test_panic, m)?)?;
    m.add("GPU_BUILT", cfg!(feature = "gpu"))?;
    Ok(())
}

/// Panics on the calling thread, or on the thread a render runs on: the
/// tests' proof that a panic reaches Python as `glint.Error` and not as an
/// abort or PyO3's `PanicException` (no call of the API is known to panic).
#[pyfunction]
#[pyo3(name = "_test_panic")]
fn test_panic(py: Python<'_>, on_render_thread: bool) -> PyResult<()> {
    errors::guard(|| {
        if on_render_thread {
            let stop = std::sync::atomic::AtomicBool::new(false);
            render::interruptible(py, &stop, || -> PyResult<()> { panic!("a test's panic") })
        } else {
            panic!("a test's panic")
        }
    })
}
