//! SIGINT, SIGTERM and SIGHUP, taken by a thread of glint's own.
//!
//! The signals are blocked in every thread (each inherits the mask of the
//! main thread, which blocks them before it starts any) and one thread
//! waits for them with `sigwait`, so its handler runs as plain code, outside
//! the signal context. The thread is running before `set_handler` returns:
//! a new thread's first step takes the dynamic loader's lock, and one that
//! had not yet taken it when the device's open blocked in the `dlopen` of a
//! FIFO (docs/guarantees.md) never ran, so a SIGTERM then did nothing until
//! the open's limit. (ctrlc, which glint used before, starts its thread and
//! returns.) Child processes start with no signal blocked: std's `Command`
//! clears the mask.

use std::io;

const SIGNALS: [libc::c_int; 3] = [libc::SIGINT, libc::SIGTERM, libc::SIGHUP];

/// Runs `handler` on a thread of its own when the process is sent SIGINT,
/// SIGTERM or SIGHUP; the handler ends the process. Call it before any
/// other thread is started.
pub fn set_handler(handler: impl FnOnce() + Send + 'static) -> io::Result<()> {
    let set = signal_set()?;
    // SAFETY: a valid set, and no old mask asked for.
    let blocked = unsafe { libc::pthread_sigmask(libc::SIG_BLOCK, &set, std::ptr::null_mut()) };
    if blocked != 0 {
        return Err(io::Error::from_raw_os_error(blocked));
    }
    let (started, running) = std::sync::mpsc::channel();
    let spawned = std::thread::Builder::new()
        .name("glint-signals".to_owned())
        .spawn(move || {
            let _ = started.send(());
            let mut signal = 0;
            // SAFETY: a valid set and a place for the signal's number;
            // sigwait returns 0 once one of the set is pending.
            while unsafe { libc::sigwait(&set, &mut signal) } != 0 {}
            handler();
        });
    match spawned.map(|_| running.recv()) {
        Ok(Ok(())) => Ok(()),
        Ok(Err(_)) => Err(io::Error::other("the signal thread ended as it started")),
        Err(e) => {
            // Without the thread, the signals end the process as before.
            // SAFETY: as above.
            unsafe { libc::pthread_sigmask(libc::SIG_UNBLOCK, &set, std::ptr::null_mut()) };
            Err(e)
        }
    }
}

fn signal_set() -> io::Result<libc::sigset_t> {
    // SAFETY: sigemptyset initialises the set it is given; sigaddset adds
    // valid signal numbers to it.
    unsafe {
        let mut set = std::mem::zeroed::<libc::sigset_t>();
        if libc::sigemptyset(&mut set) != 0 {
            return Err(io::Error::last_os_error());
        }
        for s in SIGNALS {
            if libc::sigaddset(&mut set, s) != 0 {
                return Err(io::Error::last_os_error());
            }
        }
        Ok(set)
    }
}
