//! What the matrix concludes of one driver on one scene: the probe's end
//! (probe.rs) and, where it rendered, `compare`'s judgement of the image
//! against the CPU f64 reference, with its conditioning rule.

use std::path::Path;

use serde::Serialize;

use crate::accel::Accel;
use crate::condition;
use crate::raster::diff::{ErrorFigures, Tolerance};
use crate::raster::{io, Image};
use crate::scene::Scene;

use super::probe::{Ended, Seen, IMAGE};

/// One cell of the matrix.
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "result", rename_all = "snake_case")]
pub enum Verdict {
    /// Within `compare`'s tolerance (over the well-conditioned pixels where
    /// the whole image is not).
    Pass {
        /// The image's error figures against the reference.
        error: ErrorFigures,
        /// How long it ran, seconds.
        seconds: f64,
        /// The scene's shader variant.
        variant: String,
    },
    /// Over it: a wrong image.
    Fail {
        /// The image's error figures against the reference.
        error: ErrorFigures,
        /// The tolerance's limits the image breaks.
        violations: Vec<String>,
        /// How long it ran, seconds.
        seconds: f64,
        /// The scene's shader variant.
        variant: String,
    },
    /// Within the tolerance over the well-conditioned pixels, but these are
    /// too few to hold the image to (`condition::MAX_ILL`): the scene is
    /// not well-conditioned at f32, on any renderer.
    IllConditioned {
        /// The image's error figures against the reference.
        error: ErrorFigures,
        /// The share of ill-conditioned pixels.
        ill: f64,
        /// How long it ran, seconds.
        seconds: f64,
        /// The scene's shader variant.
        variant: String,
    },
    /// A limit glint knows refused the scene on this driver.
    Refused {
        /// Why.
        reason: String,
    },
    /// The child died: a signal, or an exit with no report.
    Crashed {
        /// How it died: the signal, or the exit status.
        how: String,
        /// The last of what it wrote on stderr.
        stderr: String,
    },
    /// glint's watchdog, or the parent's deadline, ran out.
    Hung {
        /// How long it ran, and what gave up on it.
        message: String,
    },
    /// The validation layer spoke.
    Validation {
        /// Each message the layer printed, in order.
        messages: Vec<String>,
    },
    /// The driver did what no correct driver does (`probe::Seen::Fault`):
    /// a failure like a wrong image, and counted as one ("FAIL").
    Fault {
        /// The renderer's error that names the fault.
        message: String,
    },
    /// glint could not run the scene there for another reason.
    Error {
        /// What stopped the run.
        message: String,
    },
    /// Not run: the run's --budget ran out first.
    NotRun {
        /// Why.
        reason: String,
    },
}

/// Every cell's word (`Verdict::word`), in the order a summary counts them.
pub const WORDS: [&str; 9] = [
    "pass",
    "FAIL",
    "ill-conditioned",
    "refused",
    "crashed",
    "hung",
    "validation",
    "error",
    "not run",
];

impl Verdict {
    /// The cell's word, one of `WORDS`.
    pub fn word(&self) -> &'static str {
        match self {
            Verdict::Pass { .. } => "pass",
            Verdict::Fail { .. } => "FAIL",
            Verdict::IllConditioned { .. } => "ill-conditioned",
            Verdict::Refused { .. } => "refused",
            Verdict::Crashed { .. } => "crashed",
            Verdict::Hung { .. } => "hung",
            Verdict::Validation { .. } => "validation",
            Verdict::Fault { .. } => "FAIL",
            Verdict::Error { .. } => "error",
            Verdict::NotRun { .. } => "not run",
        }
    }

    /// Whether this is a driver's fault to report (and a reason for exit
    /// status 1): a wrong image, a crash, a hang, a validation message or a fault.
    /// A refusal is glint knowing a limit; an error is glint's or the input's.
    pub fn is_failure(&self) -> bool {
        matches!(
            self,
            Verdict::Fail { .. }
                | Verdict::Crashed { .. }
                | Verdict::Hung { .. }
                | Verdict::Validation { .. }
                | Verdict::Fault { .. }
        )
    }

    /// Whether `other` is the same kind of outcome: what shrinking keeps
    /// (a fault that becomes a wrong image is another failure).
    pub fn same_kind(&self, other: &Verdict) -> bool {
        std::mem::discriminant(self) == std::mem::discriminant(other)
    }

    /// The detail shown under the word: the error figures and time, or
    /// the reason.
    pub fn detail(&self) -> String {
        match self {
            Verdict::Pass { error, seconds, .. } => figures(error, *seconds),
            Verdict::Fail {
                error,
                violations,
                seconds,
                ..
            } => format!(
                "{}; {}",
                violations.first().map_or("", String::as_str),
                figures(error, *seconds)
            ),
            Verdict::IllConditioned {
                error,
                ill,
                seconds,
                ..
            } => format!(
                "{:.1}% of pixels ill-conditioned at f32; over the rest {}",
                100.0 * ill,
                figures(error, *seconds)
            ),
            Verdict::Refused { reason } => reason.clone(),
            Verdict::Crashed { how, .. } => how.clone(),
            Verdict::Hung { message } => message.clone(),
            Verdict::Validation { messages } => messages.first().cloned().unwrap_or_default(),
            Verdict::Fault { message } | Verdict::Error { message } => message.clone(),
            Verdict::NotRun { reason } => reason.clone(),
        }
    }
}

/// The verdict on the probe that ended as `ended`, whose image (where it
/// rendered) is in `dir`; `reference` is the scene's CPU f64 image.
pub fn judge(
    ended: Ended,
    dir: &Path,
    scene: &Scene,
    reference: &Image,
    accel: Accel,
) -> (Verdict, Option<Image>) {
    let probe = match ended {
        Ended::Wrote(p) => p,
        other => return (judge_ended(other), None),
    };
    let (variant, seconds) = match rendered(probe.seen) {
        Ok(r) => r,
        Err(v) => return (v, None),
    };
    let image = match io::read(&dir.join(IMAGE)) {
        Ok(i) => i,
        Err(e) => {
            let message = format!("the probe's image cannot be read: {e}");
            return (Verdict::Error { message }, None);
        }
    };
    let tolerance = Tolerance::default();
    let j = condition::judge(scene, &image, reference, &tolerance, accel, &|_| {});
    let error = j.conditioned.as_ref().map_or(j.error, |c| c.error);
    let ill = j
        .conditioned
        .as_ref()
        .filter(|c| c.ill > condition::MAX_ILL && tolerance.violations(&c.error).is_empty())
        .filter(|c| c.violations.len() == 1 && error.nonfinite == 0);
    let verdict = if let Some(c) = ill {
        Verdict::IllConditioned {
            error,
            ill: c.ill,
            seconds,
            variant,
        }
    } else if j.pass() {
        Verdict::Pass {
            error,
            seconds,
            variant,
        }
    } else {
        Verdict::Fail {
            error,
            violations: j.violations,
            seconds,
            variant,
        }
    };
    (verdict, Some(image))
}

/// A probe that rendered: its variant (none where it only named the
/// device) and its seconds; else the verdict on how it ended.
pub fn rendered(seen: Seen) -> Result<(String, f64), Verdict> {
    match seen {
        Seen::Rendered {
            variant, seconds, ..
        } => Ok((variant.unwrap_or_default(), seconds)),
        Seen::Refused { message } => Err(Verdict::Refused { reason: message }),
        Seen::Hung { message } => Err(Verdict::Hung { message }),
        Seen::Validation { messages } => Err(Verdict::Validation { messages }),
        Seen::Fault { message } => Err(Verdict::Fault { message }),
        Seen::NoDevice { message } | Seen::Error { message } => Err(Verdict::Error { message }),
    }
}

/// Error figures and a time, in a few words.
fn figures(error: &ErrorFigures, seconds: f64) -> String {
    format!(
        "rmse {:.1e}, {:.2}% over 1/255, {:.3} s",
        error.rmse,
        100.0 * error.frac_over_1_255,
        seconds
    )
}

/// The verdict on a child that wrote no report: it crashed or hung.
pub fn judge_ended(ended: Ended) -> Verdict {
    match ended {
        Ended::Crashed {
            signal,
            status,
            stderr,
        } => {
            let how = match signal {
                Some(s) => format!("killed by signal {s} ({})", signal_name(s)),
                None => format!("exited without a report ({status})"),
            };
            Verdict::Crashed { how, stderr }
        }
        Ended::Hung { seconds } => Verdict::Hung {
            message: format!("still running after {seconds:.0} s: killed"),
        },
        Ended::Wrote(_) => Verdict::Error {
            message: "a report where none was expected".into(),
        },
    }
}

/// The usual name of a Linux signal.
fn signal_name(s: i32) -> &'static str {
    match s {
        4 => "SIGILL",
        6 => "SIGABRT",
        7 => "SIGBUS",
        8 => "SIGFPE",
        9 => "SIGKILL",
        11 => "SIGSEGV",
        15 => "SIGTERM",
        _ => "signal",
    }
}
