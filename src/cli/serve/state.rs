//! What the page shows, as the render and reference threads leave it: the
//! newest GPU image, the newest reference and the verdict of the two, the
//! last error; each change a new version, which the event streams wait on.

use std::sync::{Condvar, Mutex, MutexGuard};
use std::time::Duration;

use serde::Serialize;

use glint::raster::Image;

/// An image as the page takes it: the tone-mapped PNG it shows, and the
/// float data, so that a pixel's value under the cursor is exact.
pub struct Frame {
    /// Which render it is of (the GPU's renders are counted from 1).
    pub generation: u64,
    pub png: Vec<u8>,
    /// The pixels as little-endian f32, RGB, row by row from the top.
    pub floats: Vec<u8>,
}

impl Frame {
    pub fn of(generation: u64, image: &Image, srgb: bool) -> Frame {
        let floats = image
            .pixels
            .iter()
            .flatten()
            .flat_map(|c| c.to_le_bytes())
            .collect();
        Frame {
            generation,
            png: glint::raster::io::png_bytes(image, srgb),
            floats,
        }
    }
}

/// What the page reads as JSON (`/state` and each event).
#[derive(Debug, Clone, Default, Serialize)]
pub struct Status {
    /// Counts every change of what is shown.
    pub version: u64,
    /// The scene file, as given.
    pub scene: String,
    pub width: u32,
    pub height: u32,
    /// The newest GPU image's render, if any has succeeded.
    pub gpu: Option<GpuStatus>,
    /// The newest reference, and which GPU render it was made for.
    pub reference: Option<ReferenceStatus>,
    /// The check of a GPU image against its reference, `glint compare`'s,
    /// for the render `generation` names: shown only while that render is
    /// the newest.
    pub verdict: Option<Verdict>,
    /// The error of the last attempt, as the command line prints it; the
    /// last good images stay.
    pub error: Option<String>,
    /// Whether a render or a reference is under way.
    pub rendering: bool,
    pub referencing: bool,
}

#[derive(Debug, Clone, Serialize)]
pub struct GpuStatus {
    pub generation: u64,
    pub device: String,
    /// The render's own time, and the part of it that traced.
    pub render_s: f64,
    pub trace_s: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct ReferenceStatus {
    pub generation: u64,
    /// The CPU f64 reference's time.
    pub seconds: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct Verdict {
    pub generation: u64,
    pub pass: bool,
    /// compare's lines: the error figures, the conditioning, the verdict.
    pub lines: Vec<String>,
    pub max_abs: f64,
    pub rmse: f64,
    pub frac_over_1_255: f64,
    /// The share of pixels ill-conditioned at f32, where the check ran the
    /// conditioning trials.
    pub ill: Option<f64>,
    pub violations: Vec<String>,
    /// The reference's rays by type (none where it sampled adaptively or
    /// by contrast, whose render does not count).
    pub rays: Option<glint::stats::RayCounts>,
}

/// Everything shared, behind one lock.
#[derive(Default)]
pub struct Shown {
    pub status: Status,
    pub gpu: Option<Frame>,
    pub reference: Option<Frame>,
    /// The error map of the GPU image of the verdict's generation.
    pub error_map: Option<Frame>,
}

/// The shared state and the condition its readers wait on.
#[derive(Default)]
pub struct State {
    shown: Mutex<Shown>,
    changed: Condvar,
}

impl State {
    pub fn lock(&self) -> MutexGuard<'_, Shown> {
        self.shown.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Changes what is shown, as one new version, and wakes the streams.
    pub fn change(&self, f: impl FnOnce(&mut Shown)) {
        let mut shown = self.lock();
        f(&mut shown);
        shown.status.version += 1;
        drop(shown);
        self.changed.notify_all();
    }

    /// The status once its version is past `seen`, or None after `wait`.
    pub fn after(&self, seen: u64, wait: Duration) -> Option<Status> {
        let shown = self.lock();
        let (shown, _) = self
            .changed
            .wait_timeout_while(shown, wait, |s| s.status.version <= seen)
            .unwrap_or_else(|p| p.into_inner());
        (shown.status.version > seen).then(|| shown.status.clone())
    }
}
