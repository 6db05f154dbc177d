//! Work done with the GIL released, and the interpreter's exit.
//!
//! A daemon thread inside a glint call when the interpreter exits comes
//! back for the GIL after finalization has begun, and CPython (before
//! 3.14) ends it there with `pthread_exit`, a forced unwind. That unwind
//! met the `catch_unwind` of `errors::guard` (and PyO3's own), which took
//! it for a foreign exception and deleted it: glibc's "FATAL: exception not
//! rethrown", SIGABRT, exit 134. So no thread comes back for the GIL from
//! inside glint once the interpreter is exiting:
//!
//! - an `atexit` callback (run before finalization ends daemon threads)
//!   sets [`EXITING`], then lets through, GIL released, every thread that
//!   was already on its way back for the GIL ([`RETURNING`]);
//! - a thread that finishes work without the GIL after that parks for
//!   good, as CPython 3.14 and PyO3 park such threads, and so does one
//!   that enters a glint call; the process exits under them.
//!
//! A thread counts itself as returning before it looks at the flag, and
//! the callback sets the flag before it counts them, so one of the two
//! always sees the other.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use pyo3::prelude::*;
use pyo3::types::PyCFunction;

/// Set by the `atexit` callback that [`register`] installs.
static EXITING: AtomicBool = AtomicBool::new(false);

/// Threads between the end of their work without the GIL and having it
/// back.
static RETURNING: AtomicUsize = AtomicUsize::new(0);

/// How long the exit waits for the threads on their way back: a bound,
/// so that the exit never hangs on a thread that does not come.
const LET_THROUGH: Duration = Duration::from_secs(2);

/// Installs the `atexit` callback.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    let exiting = PyCFunction::new_closure(py, None, None, |args, _kwargs| {
        EXITING.store(true, Ordering::SeqCst);
        let py = args.py();
        let start = Instant::now();
        while RETURNING.load(Ordering::SeqCst) > 0 && start.elapsed() < LET_THROUGH {
            py.detach(|| std::thread::sleep(Duration::from_millis(1)));
        }
    })?;
    py.import("atexit")?.call_method1("register", (exiting,))?;
    Ok(())
}

/// Whether the interpreter has begun to exit.
pub fn exiting() -> bool {
    EXITING.load(Ordering::SeqCst)
}

/// Releases the GIL and never returns: the thread waits for the process
/// to exit under it.
pub fn park(py: Python<'_>) -> ! {
    py.detach(|| loop {
        std::thread::park();
    })
}

/// `f` run with the GIL released, as `Python::detach`; where the
/// interpreter began to exit meanwhile, the thread never returns.
pub fn detach<T: Send>(py: Python<'_>, f: impl Send + FnOnce() -> T) -> T {
    let out = py.detach(|| {
        let out = f();
        RETURNING.fetch_add(1, Ordering::SeqCst);
        if EXITING.load(Ordering::SeqCst) {
            RETURNING.fetch_sub(1, Ordering::SeqCst);
            loop {
                std::thread::park();
            }
        }
        out
    });
    RETURNING.fetch_sub(1, Ordering::SeqCst);
    out
}
