//! Progress for work that takes seconds: bars for renders, a spinner for
//! waits of unknown length (opening the device, compiling a shader, the
//! driver's compile, building a BVH). Hidden when stderr is not a terminal,
//! so logs and tests keep to glint's one-line output.

use std::time::Duration;

use indicatif::{ProgressBar, ProgressStyle};

/// How often a bar redraws with no progress, so that its clock moves
/// through a wait that reports nothing (a driver compiling a shader).
const TICK: Duration = Duration::from_millis(200);

/// A bar over `total` steps, labelled `what`.
pub fn bar(total: u64, what: &str) -> ProgressBar {
    let bar = ProgressBar::new(total);
    bar.set_style(
        ProgressStyle::with_template(
            "[{bar:30}] {percent:>3}% {elapsed_precise} eta {eta:>3} {wide_msg}",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
    bar.set_message(what.to_owned());
    bar.enable_steady_tick(TICK);
    bar
}

/// Runs `f` under a spinner that says `what` and the seconds so far, and
/// clears it after.
pub fn waiting<T>(what: &str, f: impl FnOnce() -> T) -> T {
    let spinner = spinner(what);
    spinner.enable_steady_tick(TICK);
    let out = f();
    spinner.finish_and_clear();
    out
}

/// Runs `f` under a line that says `what`, drawn once, and clears it after:
/// for the device's open, which must start no thread just before its own.
/// A spinner's clock is a thread, and one that has not yet run when the
/// open's `dlopen` blocks holding the dynamic loader's lock (a driver
/// library that is a FIFO) cannot start, since a new thread's first step
/// takes that lock; the spinner's end waits for its clock, and `render`
/// never ended (CI, one run in twelve under load).
#[cfg(feature = "gpu")]
pub fn waiting_without_a_clock<T>(what: &str, f: impl FnOnce() -> T) -> T {
    let spinner = spinner(what);
    spinner.tick();
    let out = f();
    spinner.finish_and_clear();
    out
}

fn spinner(what: &str) -> ProgressBar {
    let spinner = ProgressBar::new_spinner();
    spinner.set_style(
        ProgressStyle::with_template("{spinner} {elapsed:>3} {wide_msg}").expect("valid template"),
    );
    spinner.set_message(what.to_owned());
    spinner
}
