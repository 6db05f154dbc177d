//! The one way the command line prints. Every line of every command goes
//! through [`to_stdout`] or [`to_stderr`] (the macros `outln!`, `out!` and `errln!`),
//! so that no command can forget what a failed write means
//! (docs/guarantees.md, Printing):
//!
//! - stdout closed by its reader (`glint info | head -1`): glint stops
//!   quietly, with the status a shell gives a command that SIGPIPE ends
//!   (141);
//! - stdout refusing the bytes (`> /dev/full`): one line
//!   `error: cannot write to stdout: …` on stderr, status 2;
//! - stderr refusing them: nothing more can be said; status 2.
//!
//! A failed write unwinds to `main` (not a panic: no hook runs, no
//! backtrace), so that every destructor on the way runs: a staged
//! output's temporary file is removed, the device is freed.

use std::fmt;
use std::io::{self, Write};
use std::process::ExitCode;

/// Which stream a write failed on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stream {
    Out,
    Err,
}

/// A write to stdout or stderr that failed; carried by an unwind to `main`.
#[derive(Debug)]
pub struct Unwritable {
    stream: Stream,
    cause: io::Error,
}

impl Unwritable {
    /// Says what failed where it still can, and the exit status.
    pub fn report(&self) -> ExitCode {
        match (self.stream, self.cause.kind()) {
            (Stream::Out, io::ErrorKind::BrokenPipe) => ExitCode::from(141),
            (Stream::Out, _) => {
                last_words(format_args!(
                    "error: cannot write to stdout: {}\n",
                    self.cause
                ));
                ExitCode::from(2)
            }
            (Stream::Err, _) => ExitCode::from(2),
        }
    }
}

/// Writes `args` on stdout, or unwinds with [`Unwritable`].
pub fn to_stdout(args: fmt::Arguments) {
    let mut s = io::stdout().lock();
    if let Err(cause) = s.write_fmt(args).and_then(|()| s.flush()) {
        drop(s);
        unwind(Stream::Out, cause);
    }
}

/// Writes `args` on stderr, or unwinds with [`Unwritable`].
pub fn to_stderr(args: fmt::Arguments) {
    let mut s = io::stderr().lock();
    if let Err(cause) = s.write_fmt(args).and_then(|()| s.flush()) {
        drop(s);
        unwind(Stream::Err, cause);
    }
}

/// Writes `bytes` on stdout (a man page, a completion script), or unwinds.
pub fn out_bytes(bytes: &[u8]) {
    let mut s = io::stdout().lock();
    if let Err(cause) = s.write_all(bytes).and_then(|()| s.flush()) {
        drop(s);
        unwind(Stream::Out, cause);
    }
}

/// Writes `args` on stderr where nothing can be done if that fails: the
/// closing error line, the line a signal handler prints.
pub fn last_words(args: fmt::Arguments) {
    let _ = io::stderr().lock().write_fmt(args);
}

fn unwind(stream: Stream, cause: io::Error) -> ! {
    std::panic::resume_unwind(Box::new(Unwritable { stream, cause }))
}

/// Ends the process with `code` (0, or 2 for any failure) without running
/// its exit handlers, where an open of the Vulkan device was given up
/// (`glint::gpu::vk::bounded`): the thread left in it may hold the dynamic
/// loader's lock (a `dlopen` of a FIFO), which a normal exit waits on for
/// ever. Everything glint prints is already written (each write flushes),
/// and nothing is staged before the device is open.
#[cfg(feature = "gpu")]
pub fn exit_past_a_stuck_open(code: ExitCode) -> ! {
    exit_without_handlers(if code == ExitCode::SUCCESS { 0 } else { 2 })
}

/// Ends an interrupted run with status 130, once its clean-up is done: with
/// `_exit` while an open of the device is unfinished (its thread may hold
/// the dynamic loader's lock, and the C library's exit waited on it for
/// ever: a `render` stopped by SIGTERM during a stuck open never ended).
pub fn exit_interrupted() -> ! {
    #[cfg(feature = "gpu")]
    if glint::gpu::open_unfinished() || AT_ONCE.load(std::sync::atomic::Ordering::SeqCst) {
        exit_without_handlers(130);
    }
    std::process::exit(130)
}

/// Whether an interrupt ends the process with `_exit`.
#[cfg(feature = "gpu")]
static AT_ONCE: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Makes an interrupt end the process with `_exit`, for a command whose
/// threads use the device while the signal thread ends it (`serve`): the
/// C library's exit runs the driver's own exit handlers under them, and a
/// SIGTERM during a render ended `glint serve` by a crash, not 130. Its
/// clean-up is done by then, and everything it prints is written.
#[cfg(feature = "gpu")]
pub fn exit_at_once_when_interrupted() {
    AT_ONCE.store(true, std::sync::atomic::Ordering::SeqCst);
}

#[cfg(feature = "gpu")]
fn exit_without_handlers(status: i32) -> ! {
    // SAFETY: _exit ends the process at once; nothing of Rust's runs after.
    unsafe { libc::_exit(status) }
}

/// Runs `f`, turning an [`Unwritable`] unwind into its exit status; any
/// other panic goes on unwinding.
pub fn catching(f: impl FnOnce() -> ExitCode) -> ExitCode {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)) {
        Ok(code) => code,
        Err(payload) => match payload.downcast::<Unwritable>() {
            Ok(u) => u.report(),
            Err(other) => std::panic::resume_unwind(other),
        },
    }
}

/// `println!` through [`to_stdout`].
macro_rules! outln {
    () => { $crate::cli::console::to_stdout(format_args!("\n")) };
    ($($t:tt)*) => { $crate::cli::console::to_stdout(format_args!("{}\n", format_args!($($t)*))) };
}

/// `print!` through [`to_stdout`].
#[cfg_attr(not(feature = "gpu"), allow(unused_macros))]
macro_rules! out {
    ($($t:tt)*) => { $crate::cli::console::to_stdout(format_args!($($t)*)) };
}

/// `eprintln!` through [`to_stderr`].
macro_rules! errln {
    () => { $crate::cli::console::to_stderr(format_args!("\n")) };
    ($($t:tt)*) => { $crate::cli::console::to_stderr(format_args!("{}\n", format_args!($($t)*))) };
}

#[cfg_attr(not(feature = "gpu"), allow(unused_imports))]
pub(crate) use {errln, out, outln};
