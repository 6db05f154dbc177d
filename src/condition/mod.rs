//! Which pixels an f32 renderer can be held to (docs/guide.md, Accuracy;
//! docs/spd.md, GPU against the reference).
//!
//! The robust forms are backward stable: the f32 image is, to a few
//! roundings, the exact image of a scene moved by a few units in the last
//! place of f32. Where the exact image itself changes by more than 1/255
//! under such a move (a mirror chain that amplifies every deviation, two
//! coincident faces of which either may be nearest, a ray that grazes a
//! silhouette) the pixel is ill-conditioned at f32: no f32 renderer can
//! reproduce the f64 value there, and the CPU's own f32 does not either.
//!
//! The f64 reference finds them by experiment, as Monte Carlo arithmetic
//! does (Parker, Pierce and Eggert, 2000). It renders the scene again
//! [`TRIALS`] times, in camera-relative coordinates, with the eye rays'
//! directions (the camera's screen vectors, each moved apart), every
//! primitive, every hit point and the direction of every ray that leaves a
//! surface moved at random by [`MOVE`] of their size: as much as f32
//! rounds a hit point (camera-relative coordinates are of the size of the
//! distance from the eye), a primitive's coordinates and a direction. The
//! directions matter over long rays: a shadow ray from a wall 1e6 away
//! crosses a ball's edge where f32 rounds its direction, as no move of the
//! ball or of the wall makes it (`World::hit_move`). One more trial is
//! the CPU's own f32 render: the same code as the reference, so whatever it
//! changes, rounding changed, and it samples f32's roundings as no random
//! move does (in balls, three bounces between small spheres can push a path
//! across a shadow's edge along the one direction f32 rounds it, which 16
//! random moves missed). A pixel that any trial changes by more than 1/255
//! is ill-conditioned.
//!
//! `glint compare` holds an image to the tolerance over every pixel, and
//! only where that fails, over the well-conditioned ones ([`judge`]).

mod aovs;
mod decided;

use glam::DVec3;

use crate::accel::Accel;
use crate::base::aabb::Aabb;
use crate::cpu;
use crate::raster::diff::{figures, figures_where, pixel_errors, ErrorFigures, Tolerance};
use crate::raster::Image;
use crate::rng::Xorshift;
use crate::sampling::Sampled;
use crate::scene::decisions::Decisions;
use crate::scene::Scene;

pub use aovs::{judge_aovs, AovCheck};
pub use decided::{judge_rendered, DecisionCheck};

/// Perturbed renders of the reference (and then the f32 one). Without the
/// f32 trial, on balls at 512×512, 4 trials of 2 ulp leave 0.21 % of its
/// pixels off and unexplained and 8 leave 0.06 %; 16 of 4 ulp leave 0.002 %
/// but call 7.1 % of it ill-conditioned (docs/spd.md).
pub const TRIALS: u32 = 8;

/// How far a trial moves the eye rays and each primitive, relative to
/// their size: 2 units in the last place of f32 (2^-24 each), a few
/// roundings' worth.
pub const MOVE: f64 = 2.0 / 16_777_216.0;

/// Trials beside [`TRIALS`] that move by [`DRIVER_MOVE`]: the driver's
/// trials (docs/guarantees.md, On any conformant driver), run where an
/// image fails over the pixels that f32's roundings leave well-conditioned
/// (`judge`).
pub const DRIVER_TRIALS: u32 = 6;

/// How far a driver's trial moves: 9 units in the last place, the most
/// that one operation on the renderer's path may be off on a conformant
/// Vulkan driver. That is `normalize`, inherited from x / length(x):
/// length is sqrt(dot(x, x)), sqrt is 1 / inversesqrt (2 ULP, then a
/// division, 2.5), which reaches the root as up to 6.5 ULP, and the
/// division by it adds 2.5 (the Vulkan spec, Precision and Operation of
/// SPIR-V Instructions; tests/spec_worst.rs measures each).
pub const DRIVER_MOVE: f64 = 9.0 / 16_777_216.0;

/// Every moved trial: [`TRIALS`] of f32's roundings, then
/// [`DRIVER_TRIALS`] of a driver's.
pub const MOVED_TRIALS: u32 = TRIALS + DRIVER_TRIALS;

/// How far moved trial `trial` moves.
fn move_of(trial: u32) -> f64 {
    if trial < TRIALS {
        MOVE
    } else {
        DRIVER_MOVE
    }
}

/// The unit errors are measured in: 1, or the reference's peak where that
/// is above 1. 1/255 of 1 is one 8-bit level of a displayable image; a
/// scene lit at 1e15 is judged as one lit at 1 (as `glint stability`
/// judges every scene).
pub fn unit(reference: &Image) -> f64 {
    reference.peak().max(1.0)
}

/// Pixels an f32 renderer cannot be held to, by index; `reference` is the
/// f64 image of `scene`, and errors count in units of `unit`.
pub fn ill_conditioned(
    scene: &Scene,
    reference: &Image,
    unit: f64,
    accel: Accel,
    progress: &(dyn Fn(u64) + Sync),
) -> Vec<bool> {
    trials(scene, reference, unit, accel, progress).ill
}

/// What the trials found: the pixels they move past 1/255, and where the
/// scene replays the reference's sampling decisions (`Scene::replay`),
/// the decisions some trial would have taken otherwise on those samples.
struct Found {
    ill: Vec<bool>,
    otherwise: Decisions,
}

/// One render of the conditioning check: a moved f64 render (its index
/// among [`MOVED_TRIALS`], which says how far it moves), or the CPU's own
/// f32.
#[derive(Debug, Clone, Copy)]
enum Trial {
    Moved(u32),
    F32,
}

/// f32's roundings' trials, in the order they run: the moved renders,
/// then the CPU's own f32.
fn rounding_trials() -> impl Iterator<Item = Trial> {
    (0..TRIALS).map(Trial::Moved).chain([Trial::F32])
}

/// A conformant driver's trials ([`DRIVER_TRIALS`]), which run after
/// f32's roundings' where those leave an image failing.
fn conformant_trials() -> impl Iterator<Item = Trial> {
    (TRIALS..MOVED_TRIALS).map(Trial::Moved)
}

impl Trial {
    /// Its render of `scene`, with what its sampling decided.
    fn render(
        self,
        scene: &Scene,
        accel: Accel,
        progress: &(dyn Fn(u64) + Sync),
    ) -> (Image, Option<Sampled>) {
        match self {
            Trial::Moved(t) => {
                let (moved, moves) = trial(scene, t);
                cpu::render_moved(&moved, accel, moves, progress)
            }
            Trial::F32 => cpu::render_sampled::<f32>(scene, accel, progress),
        }
    }
}

/// The trials of f32's roundings, as [`ill_conditioned`] runs them.
fn trials(
    scene: &Scene,
    reference: &Image,
    unit: f64,
    accel: Accel,
    progress: &(dyn Fn(u64) + Sync),
) -> Found {
    let mut found = Found {
        ill: vec![false; reference.pixels.len()],
        otherwise: Decisions::default(),
    };
    for t in rounding_trials() {
        found.add(t.render(scene, accel, progress), reference, unit);
    }
    found
}

impl Found {
    /// Marks what a trial's render moved.
    fn add(&mut self, (moved, sampled): (Image, Option<Sampled>), reference: &Image, unit: f64) {
        mark(&mut self.ill, &moved, reference, unit);
        if let Some(s) = sampled {
            self.otherwise = self.otherwise.union(&s.otherwise);
        }
    }
}

/// The driver's trials, added to `found`.
fn driver_trials(
    scene: &Scene,
    reference: &Image,
    unit: f64,
    accel: Accel,
    progress: &(dyn Fn(u64) + Sync),
    found: &mut Found,
) {
    for t in conformant_trials() {
        found.add(t.render(scene, accel, progress), reference, unit);
    }
}

/// Marks the pixels `moved` puts more than 1/255 from `reference`.
fn mark(ill: &mut [bool], moved: &Image, reference: &Image, unit: f64) {
    let errors = pixel_errors(moved, reference).expect("the same size");
    for (flag, e) in ill.iter_mut().zip(errors) {
        *flag |= e / unit > 1.0 / 255.0;
    }
}

/// The seed of a trial's moves of hit points.
fn hit_seed(trial: u32) -> u64 {
    0x51_7cc1_b727_220a ^ u64::from(trial + 1).wrapping_mul(0x9e37_79b9_7f4a_7c15)
}

/// `scene` in camera-relative coordinates (as both renderers trace it)
/// with its screen vectors, and then each primitive, moved by [`MOVE`] of
/// their size in directions of the trial's own: the eye rays' directions
/// by as much as f32 rounds them, and each primitive by as much as f32
/// rounds its coordinates (where two coincident faces meet, which is
/// nearer is then the trial's).
fn perturbed(scene: &Scene, trial: u32) -> Scene {
    let mut rng = Xorshift(0x9e37_79b9_7f4a_7c15 ^ (u64::from(trial + 1) * 0x2545_f491_4f6c_dd1d));
    let mut s = scene.camera_relative();
    let cam = &mut s.camera;
    let step = move_of(trial);
    let mut moved = |v: DVec3, size: f64| v + rng.unit() * (step * size);
    cam.screen_center = moved(cam.screen_center, cam.screen_center.length());
    cam.screen_right = moved(cam.screen_right, cam.screen_right.length());
    cam.screen_up = moved(cam.screen_up, cam.screen_up.length());
    let largest = |b: &Aabb| b.lo.abs().max(b.hi.abs()).max_element();
    // An unbounded primitive moves as much as the largest bounded one.
    let scale = s.prims.bounds().iter().map(largest).fold(1.0, f64::max);
    s.prims = s
        .prims
        .each_moved(|b| moved(DVec3::ZERO, b.as_ref().map_or(scale, largest)));
    s
}

/// Trial `trial`'s scene and its moves of hit points and leaving
/// directions (`World::hit_move`): the whole image's (`ill_conditioned`),
/// or one sample's (`glint explain`, `cpu::Probe::moved`).
pub(crate) fn trial(scene: &Scene, trial: u32) -> (Scene, (u64, f64)) {
    (perturbed(scene, trial), (hit_seed(trial), move_of(trial)))
}

/// At most this share of an image may be ill-conditioned for it to be held
/// to its well-conditioned pixels alone: past it the check would say too
/// little. The SPD's worst are balls and gears, at about 4.5 %.
pub const MAX_ILL: f64 = 0.10;

/// An image against the reference over the well-conditioned pixels.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Conditioned {
    /// The share of pixels ill-conditioned at f32.
    pub ill: f64,
    /// The share of pixels both off by more than 1/255 and ill-conditioned.
    pub over_and_ill: f64,
    /// The figures over the well-conditioned pixels.
    pub error: ErrorFigures,
    /// How it breaks the tolerance; empty when it passes.
    pub violations: Vec<String>,
    /// Whether the driver's trials were added: the f32 roundings' alone
    /// left the image failing (`judge`).
    pub driver_trials: bool,
    /// Which pixels are ill-conditioned, row by row (the Python module's
    /// mask; not in `compare --json`, which gives the share).
    #[serde(skip)]
    pub pixels: Vec<bool>,
}

impl Conditioned {
    /// `img` against `reference`, with the pixels `ill` marks left out of
    /// the figures, held to `tolerance`.
    pub fn of(img: &Image, reference: &Image, ill: &[bool], tolerance: &Tolerance) -> Self {
        let n = ill.len().max(1) as f64;
        let errors = pixel_errors(img, reference).expect("the same size");
        let over_and_ill = errors
            .iter()
            .zip(ill)
            .filter(|(e, ill)| **ill && **e > 1.0 / 255.0)
            .count();
        let share = ill.iter().filter(|b| **b).count() as f64 / n;
        let error = figures_where(img, reference, |i| !ill[i]).expect("the same size");
        let mut violations = tolerance.violations(&error);
        // A non-finite value is wrong wherever it is.
        let nonfinite = figures(img, reference).expect("the same size").nonfinite;
        if nonfinite > error.nonfinite {
            violations.push(format!(
                "{} non-finite values where the reference is ill-conditioned",
                nonfinite - error.nonfinite
            ));
        }
        if share > MAX_ILL {
            violations.push(format!(
                "{:.2}% of pixels are ill-conditioned at f32 (at most {:.0}% may be)",
                100.0 * share,
                100.0 * MAX_ILL
            ));
        }
        Self {
            ill: share,
            driver_trials: false,
            over_and_ill: over_and_ill as f64 / n,
            error,
            violations,
            pixels: ill.to_vec(),
        }
    }
}

/// What `glint compare` concludes of an f32 image against the f64 reference.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Judgement {
    /// The unit of the figures ([`unit()`]).
    pub unit: f64,
    /// Over every pixel.
    pub error: ErrorFigures,
    /// Over the well-conditioned pixels, where the whole image fails.
    pub conditioned: Option<Conditioned>,
    /// Where the scene's sampling takes decisions: the image judged is the
    /// renderer's replay of the reference's, and this checks its own
    /// ([`judge_rendered`]).
    pub decisions: Option<DecisionCheck>,
    /// Empty when it passes.
    pub violations: Vec<String>,
}

impl Judgement {
    /// Whether the image is within the tolerance.
    pub fn pass(&self) -> bool {
        self.violations.is_empty()
    }
}

/// Holds `img` to `tolerance` against `reference`, the f64 image of
/// `scene`, in units of [`unit()`]: over every pixel, and where that fails,
/// over the well-conditioned ones (`progress(rows)` as the trials render).
/// Where the scene's sampling takes decisions, [`judge_rendered`] holds
/// the renderer to the reference on the same samples.
pub fn judge(
    scene: &Scene,
    img: &Image,
    reference: &Image,
    tolerance: &Tolerance,
    accel: Accel,
    progress: &(dyn Fn(u64) + Sync),
) -> Judgement {
    judge_replayed(scene, img, None, reference, tolerance, accel, progress)
}

/// [`judge`], where `img` replayed the reference's sampling decisions
/// (`scene.replay`) and `sampled` says which it would have taken
/// otherwise: those are held to the trials', which replay them too.
fn judge_replayed(
    scene: &Scene,
    img: &Image,
    sampled: Option<&Sampled>,
    reference: &Image,
    tolerance: &Tolerance,
    accel: Accel,
    progress: &(dyn Fn(u64) + Sync),
) -> Judgement {
    let unit = unit(reference);
    let (img_u, reference_u) = (&img.scaled(unit), &reference.scaled(unit));
    let error = figures(img_u, reference_u).expect("the same size");
    let passes_whole = tolerance.violations(&error).is_empty();
    let undecided = sampled.is_none_or(|s| s.otherwise.is_empty());
    let decisions = |found: Option<&Found>| {
        sampled.map(|s| {
            DecisionCheck::of(
                s,
                found.map(|f| &f.otherwise),
                (img.width, img.height),
                tolerance,
            )
        })
    };
    if passes_whole && undecided {
        return Judgement {
            unit,
            error,
            conditioned: None,
            decisions: decisions(None),
            violations: Vec::new(),
        };
    }
    let mut found = trials(scene, reference, unit, accel, progress);
    let mut c = Conditioned::of(img_u, reference_u, &found.ill, tolerance);
    let mut d = decisions(Some(&found));
    // Held to f32's roundings first; where that fails, to a conformant
    // driver's errors too (docs/guarantees.md, On any conformant driver).
    // An image the first accepts, the second would.
    let fails = |c: &Conditioned, d: &Option<DecisionCheck>| {
        !passes_whole && !c.violations.is_empty() || d.as_ref().is_some_and(|d| !d.pass())
    };
    if fails(&c, &d) {
        driver_trials(scene, reference, unit, accel, progress, &mut found);
        c = Conditioned {
            driver_trials: true,
            ..Conditioned::of(img_u, reference_u, &found.ill, tolerance)
        };
        d = decisions(Some(&found));
    }
    let conditioned = (!passes_whole).then_some(c);
    let mut violations = conditioned
        .as_ref()
        .map_or_else(Vec::new, |c| c.violations.clone());
    violations.extend(d.iter().flat_map(|d| d.violations.clone()));
    Judgement {
        unit,
        error,
        conditioned,
        decisions: d,
        violations,
    }
}
