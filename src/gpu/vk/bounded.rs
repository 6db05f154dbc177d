//! Opening the device within a time limit. The loader reads every driver
//! manifest it finds and loads the library each one names; a manifest or a
//! library that is a FIFO, or a driver that hangs in its own setup, would
//! block the caller for ever, and no Vulkan call can be cancelled. The
//! open runs on a thread of its own, and the caller stops waiting at the
//! limit: that thread is left behind, and whatever it opens in the end is
//! closed again when its answer finds no one to take it.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Condvar, Mutex, PoisonError};
use std::time::Duration;

use crate::gpu::error::GpuError;

/// How long opening the loader, the instance and the device may take. A
/// real open takes 0.1 s on lavapipe and about 1 s on a GPU whose driver
/// builds its caches the first time.
pub const OPEN_LIMIT: Duration = Duration::from_secs(20);

/// Opens started in this process whose thread has not yet come back.
static UNFINISHED: AtomicUsize = AtomicUsize::new(0);

/// Whether an open in this process is still running: one given up at its
/// limit, or one a signal interrupts. Its thread may hold the dynamic
/// loader's lock for ever (a `dlopen` of a FIFO), and the C library's exit
/// takes that lock: the command line then ends with `_exit`, on its way
/// out and in its signal handler alike.
pub fn open_unfinished() -> bool {
    UNFINISHED.load(Ordering::SeqCst) > 0
}

/// `open()`'s answer, or [`GpuError::OpenTimeout`] where it takes longer than
/// `limit`.
pub fn bounded<T: Send + 'static>(
    limit: Duration,
    open: impl FnOnce() -> Result<T, GpuError> + Send + 'static,
) -> Result<T, GpuError> {
    Opening::start(open)?.wait(limit)
}

/// An open running on a thread of its own, its answer not yet taken.
///
/// The caller waits on a mutex and a condition variable, not a channel:
/// std's channels set up a thread-local with a destructor the first time a
/// thread waits on one, and glibc registers that destructor under the
/// dynamic loader's lock, which the opening thread may hold for ever inside
/// `dlopen`. A caller that reached its wait after that never reached its
/// limit. (No thread can be started under that lock either: glibc's thread
/// creation takes it too, so the opening thread is started first.)
struct Opening<T> {
    answer: Arc<Answer<T>>,
}

/// The open's answer once it has one, and the signal that it has.
type Answer<T> = (Mutex<Option<Result<T, GpuError>>>, Condvar);

impl<T: Send + 'static> Opening<T> {
    fn start(
        open: impl FnOnce() -> Result<T, GpuError> + Send + 'static,
    ) -> Result<Self, GpuError> {
        let answer = Arc::new((Mutex::new(None), Condvar::new()));
        let shared = Arc::clone(&answer);
        UNFINISHED.fetch_add(1, Ordering::SeqCst);
        std::thread::Builder::new()
            .name("glint-vulkan-open".to_owned())
            .spawn(move || {
                let got = std::panic::catch_unwind(std::panic::AssertUnwindSafe(open))
                    .unwrap_or_else(|_| {
                        Err(GpuError::Unsupported(
                            "opening the Vulkan device failed inside the driver (its thread ended without an answer)"
                                .to_owned(),
                        ))
                    });
                UNFINISHED.fetch_sub(1, Ordering::SeqCst);
                let (slot, ready) = &*shared;
                *slot.lock().unwrap_or_else(PoisonError::into_inner) = Some(got);
                ready.notify_one();
                // Where the caller has stopped waiting, this thread holds
                // the last reference: the answer (an instance or device) is
                // dropped here, and closed.
            })
            .map_err(|e| {
                UNFINISHED.fetch_sub(1, Ordering::SeqCst);
                GpuError::Unsupported(format!("cannot start a thread to open Vulkan: {e}"))
            })?;
        Ok(Opening { answer })
    }

    fn wait(self, limit: Duration) -> Result<T, GpuError> {
        let (slot, ready) = &*self.answer;
        let slot = slot.lock().unwrap_or_else(PoisonError::into_inner);
        let (mut slot, _) = ready
            .wait_timeout_while(slot, limit, |s| s.is_none())
            .unwrap_or_else(PoisonError::into_inner);
        slot.take().unwrap_or_else(|| {
            exit_past_a_stuck_open();
            Err(GpuError::OpenTimeout {
                seconds: limit.as_secs_f64(),
            })
        })
    }
}

/// Once an open is given up, the process's exit must not wait for ever on
/// the loader's lock that its thread may hold: glibc's `exit` runs the
/// handlers registered with it, the latest first, and only then
/// `_dl_fini`, which takes that lock. So a handler registered here ends
/// the process with `_exit` and the exit's own status while an open is
/// unfinished, after flushing C's streams. The command line ends that way
/// already (src/main.rs); this is for every other caller, such as the
/// Python module, whose interpreter hung at exit after an open it gave up.
fn exit_past_a_stuck_open() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        extern "C" {
            fn on_exit(
                handler: extern "C" fn(libc::c_int, *mut libc::c_void),
                arg: *mut libc::c_void,
            ) -> libc::c_int;
        }
        extern "C" fn leave(status: libc::c_int, _: *mut libc::c_void) {
            if open_unfinished() {
                // SAFETY: fflush(NULL) and _exit may be called at any time;
                // _exit does not return.
                unsafe {
                    libc::fflush(std::ptr::null_mut());
                    libc::_exit(status);
                }
            }
        }
        static REGISTERED: std::sync::Once = std::sync::Once::new();
        // SAFETY: `leave` is a plain function that lives as long as the
        // process; glibc keeps the pointer and calls it once, from `exit`.
        REGISTERED.call_once(|| unsafe {
            on_exit(leave, std::ptr::null_mut());
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_open_that_never_ends_is_stopped_at_the_limit() {
        let start = std::time::Instant::now();
        let e = bounded::<()>(Duration::from_millis(50), || loop {
            std::thread::sleep(Duration::from_secs(1));
        })
        .unwrap_err();
        assert!(matches!(e, GpuError::OpenTimeout { .. }), "{e}");
        assert!(start.elapsed() < Duration::from_secs(5));
        assert_eq!(bounded(Duration::from_secs(5), || Ok(7)).unwrap(), 7);
    }

    #[test]
    fn an_open_that_panics_is_an_error_not_a_wait() {
        let e = bounded::<()>(Duration::from_secs(20), || panic!("inside a driver")).unwrap_err();
        assert!(e.to_string().contains("ended without an answer"), "{e}");
    }

    const CHILD: &str = "GLINT_TEST_STUCK_LOADER";
    /// The child's status once its wait has stopped at the limit.
    const STOPPED: i32 = 17;
    const NAME: &str = "gpu::vk::bounded::tests::a_wait_begun_while_the_loader_is_held_still_ends";

    /// A caller that reaches its wait only after the opening thread holds the
    /// dynamic loader's lock for ever (a `dlopen` of a FIFO) still stops at
    /// its limit. A waiting channel took that lock (std's thread-local
    /// destructor, registered by glibc under it), so a slow caller hung.
    /// The child process this runs in is left with a thread stuck in
    /// `dlopen`, and ends with `_exit`, as glint does.
    #[test]
    fn a_wait_begun_while_the_loader_is_held_still_ends() {
        if std::env::var_os(CHILD).is_some() {
            stuck_loader_child();
        }
        let dir = tempfile::tempdir().unwrap();
        let mut child = std::process::Command::new(std::env::current_exe().unwrap())
            .args([NAME, "--exact", "--nocapture", "--test-threads=1"])
            .env(CHILD, dir.path())
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        let start = std::time::Instant::now();
        let status = loop {
            if let Some(status) = child.try_wait().unwrap() {
                break status;
            }
            if start.elapsed() > Duration::from_secs(30) {
                let _ = child.kill();
                let _ = child.wait();
                panic!("the wait begun under the loader's lock did not end within 30 s");
            }
            std::thread::sleep(Duration::from_millis(20));
        };
        // Its own status: the test harness never reports in the child.
        assert_eq!(status.code(), Some(STOPPED), "{status}");
    }

    fn stuck_loader_child() -> ! {
        use std::ffi::CString;
        use std::os::unix::ffi::OsStrExt;
        let fifo = std::path::PathBuf::from(std::env::var_os(CHILD).unwrap()).join("lib.so");
        let name = CString::new(fifo.as_os_str().as_bytes()).unwrap();
        // SAFETY: mkfifo reads a NUL-terminated path.
        assert_eq!(unsafe { libc::mkfifo(name.as_ptr(), 0o600) }, 0);
        // A caller that has never waited on anything, running before the
        // lock is taken (a thread cannot start under it).
        let started = Arc::new(std::sync::Barrier::new(2));
        let caller_started = Arc::clone(&started);
        let caller = std::thread::spawn(move || {
            caller_started.wait();
            let opening = Opening::<()>::start(move || {
                // SAFETY: dlopen of a NUL-terminated path; it blocks in
                // open(2) for ever, holding the loader's lock, as the Vulkan
                // loader's dlopen of a FIFO library does.
                unsafe { libc::dlopen(name.as_ptr(), libc::RTLD_NOW) };
                Ok(())
            })
            .unwrap();
            // The caller comes to its wait after the open holds the lock,
            // as a slow main thread did.
            std::thread::sleep(Duration::from_millis(500));
            opening.wait(Duration::from_millis(200))
        });
        started.wait();
        let e = caller.join().unwrap().unwrap_err();
        assert!(matches!(e, GpuError::OpenTimeout { .. }), "{e}");
        // SAFETY: ends the process at once; an exit's handlers would wait
        // for the loader's lock.
        unsafe { libc::_exit(STOPPED) }
    }
}
