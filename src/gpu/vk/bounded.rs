//! Opening the device within a time limit. The loader reads every driver
//! manifest it finds and loads the library each one names; a manifest or
//! a library that is a FIFO, or a driver that hangs in its own setup,
//! would block the caller for ever (issue 41), and no Vulkan call can be
//! cancelled. The open runs on a thread of its own, and the caller stops
//! waiting at the limit: that thread is left behind, and whatever it opens
//! in the end is closed again when its answer finds no one to take it.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

use crate::gpu::error::GpuError;

/// How long opening the loader, the instance and the device may take. A
/// real open takes 0.1 s on lavapipe and about 1 s on a GPU whose driver
/// builds its caches the first time.
pub const OPEN_LIMIT: Duration = Duration::from_secs(20);

static ABANDONED: AtomicBool = AtomicBool::new(false);

/// Whether an open was given up in this process. Its thread may hold the
/// dynamic loader's lock for ever (a `dlopen` of a FIFO), and the C
/// library's exit takes that lock: the command line then ends with
/// `_exit`.
pub fn open_abandoned() -> bool {
    ABANDONED.load(Ordering::Relaxed)
}

/// `open()`'s answer, or [`GpuError::OpenTimeout`] where it takes longer than
/// `limit`.
pub fn bounded<T: Send + 'static>(
    limit: Duration,
    open: impl FnOnce() -> Result<T, GpuError> + Send + 'static,
) -> Result<T, GpuError> {
    let (tx, rx) = mpsc::sync_channel(1);
    std::thread::Builder::new()
        .name("glint-vulkan-open".to_owned())
        .spawn(move || {
            // The receiver has gone where the caller stopped waiting; the
            // answer (an instance or device) is then dropped, and closed.
            let _ = tx.send(open());
        })
        .map_err(|e| GpuError::Unsupported(format!("cannot start a thread to open Vulkan: {e}")))?;
    match rx.recv_timeout(limit) {
        Ok(answer) => answer,
        Err(mpsc::RecvTimeoutError::Timeout) => {
            ABANDONED.store(true, Ordering::Relaxed);
            Err(GpuError::OpenTimeout {
                seconds: limit.as_secs_f64(),
            })
        }
        // The thread ended without an answer: it panicked inside a driver.
        Err(mpsc::RecvTimeoutError::Disconnected) => Err(GpuError::Unsupported(
            "opening the Vulkan device failed inside the driver (its thread ended without an answer)"
                .to_owned(),
        )),
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
}
