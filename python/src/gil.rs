//! Work done with the GIL released, and the interpreter's exit.
//!
//! A daemon thread inside a glint call when the interpreter exits comes
//! back for the GIL after finalization has begun, and CPython (before
//! 3.14) ends it there with `pthread_exit`, a forced unwind. That unwind
//! met the `catch_unwind` of `errors::guard` (and PyO3's own), which took
//! it for a foreign exception and deleted it: glibc's "FATAL: exception not
//! rethrown", SIGABRT, exit 134. So the thread does not come back: once
//! the interpreter is exiting (its `atexit` callbacks run before
//! finalization ends daemon threads), a thread that finishes work without
//! the GIL parks for good, as CPython 3.14 and PyO3 park such threads,
//! and the process exits under it.

use std::sync::atomic::{AtomicBool, Ordering};

use pyo3::prelude::*;
use pyo3::types::PyCFunction;

/// Set by the `atexit` callback that [`register`] installs.
static EXITING: AtomicBool = AtomicBool::new(false);

/// Installs the `atexit` callback that tells [`detach`] the interpreter
/// is exiting.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    let exiting = PyCFunction::new_closure(py, None, None, |_args, _kwargs| {
        EXITING.store(true, Ordering::SeqCst);
    })?;
    py.import("atexit")?.call_method1("register", (exiting,))?;
    Ok(())
}

/// `f` run with the GIL released, as `Python::detach`; where the
/// interpreter began to exit meanwhile, the thread never returns.
pub fn detach<T: Send>(py: Python<'_>, f: impl Send + FnOnce() -> T) -> T {
    py.detach(|| {
        let out = f();
        while EXITING.load(Ordering::SeqCst) {
            std::thread::park();
        }
        out
    })
}
