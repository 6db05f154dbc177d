//! Sampling decisions in the oracle's model (docs/guarantees.md, Sampling
//! decisions). Adaptive and contrast sampling choose where to trace more
//! by a threshold on a contrast; an f32 renderer and the f64 reference may
//! choose otherwise at a near-tie, and then trace different samples, which
//! no comparison of arithmetic can judge. So the renderer under test
//! replays the reference's decisions and its image is judged on the same
//! samples; the decisions it would have taken otherwise on them are held
//! to the trials', which replay them too: a decision some trial also takes
//! otherwise is a near-tie. The plain render, the image the user got, is
//! the replayed image wherever its own decisions are the reference's.

use super::{judge, judge_replayed, Judgement};
use crate::accel::Accel;
use crate::raster::diff::{figures, ErrorFigures, Tolerance};
use crate::raster::Image;
use crate::sampling::Sampled;
use crate::scene::decisions::Decisions;
use crate::scene::Scene;

/// The renderer's own decisions, checked.
#[derive(Debug, Clone, serde::Serialize)]
pub struct DecisionCheck {
    /// How many decisions the replaying render took.
    pub decisions: usize,
    /// Those it would have taken otherwise on the reference's samples.
    pub otherwise: usize,
    /// Of those, how many no trial took otherwise too.
    pub unexplained: usize,
    /// The share of pixels such a decision lies in.
    pub unexplained_pixels: f64,
    /// The share of pixels the plain render sampled otherwise than the
    /// reference (0 where its decisions were the reference's).
    pub sampled_otherwise: f64,
    /// The plain render against the reference over every pixel, where it
    /// sampled otherwise (the figures judged are the replay's).
    pub plain: Option<ErrorFigures>,
    /// How it fails; empty when it passes.
    pub violations: Vec<String>,
}

impl DecisionCheck {
    /// The decisions of `sampled`, those it took otherwise explained by
    /// `explained` where the trials ran, in an image of `size`; an
    /// unexplained decision counts as a pixel off, held to the same share
    /// (`Tolerance::frac_over_1_255`).
    pub(super) fn of(
        sampled: &Sampled,
        explained: Option<&Decisions>,
        (width, height): (u32, u32),
        tolerance: &Tolerance,
    ) -> Self {
        let unexplained = match explained {
            Some(e) => sampled.otherwise.without(e),
            None => sampled.otherwise.clone(),
        };
        let pixels = unexplained.pixels_differing(&Decisions::default(), width);
        let share = pixels.len() as f64 / (f64::from(width) * f64::from(height)).max(1.0);
        let mut violations = Vec::new();
        if share > tolerance.frac_over_1_255 {
            violations.push(format!(
                "{} sampling decisions (in {:.4}% of pixels) went otherwise than the \
                 reference's on the same samples where no trial's did (at most {:.4}% allowed)",
                unexplained.len(),
                100.0 * share,
                100.0 * tolerance.frac_over_1_255
            ));
        }
        Self {
            decisions: sampled.count,
            otherwise: sampled.otherwise.len(),
            unexplained: unexplained.len(),
            unexplained_pixels: share,
            sampled_otherwise: 0.0,
            plain: None,
            violations,
        }
    }

    /// Whether its decisions pass.
    pub fn pass(&self) -> bool {
        self.violations.is_empty()
    }
}

/// Holds a renderer's image to the reference as `glint compare` does
/// ([`judge`]). Where the scene's sampling takes decisions, on the same
/// samples: `plain` is the renderer's own render and what its sampling
/// decided, `reference` the f64 render and its; where their decisions
/// differ, `replay` renders the scene it is given (`scene` replaying the
/// reference's decisions) as the renderer did `plain`, and that image is
/// judged, its own decisions checked on their own ([`DecisionCheck`]),
/// and `plain` held to it wherever its decisions are the reference's.
pub fn judge_rendered<E>(
    scene: &Scene,
    plain: (&Image, Option<&Sampled>),
    reference: (&Image, Option<&Sampled>),
    replay: impl FnOnce(&Scene) -> Result<(Image, Option<Sampled>), E>,
    tolerance: &Tolerance,
    accel: Accel,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Judgement, E> {
    let (Some(ours), Some(theirs)) = (plain.1, reference.1) else {
        return Ok(judge(
            scene,
            plain.0,
            reference.0,
            tolerance,
            accel,
            progress,
        ));
    };
    let replaying = scene.replaying(&theirs.taken);
    if ours.taken == theirs.taken {
        // Every decision the reference's: the same samples, and none
        // taken otherwise on them.
        let same = Sampled {
            otherwise: Decisions::default(),
            ..ours.clone()
        };
        let j = judge_replayed(
            &replaying,
            plain.0,
            Some(&same),
            reference.0,
            tolerance,
            accel,
            progress,
        );
        return Ok(j);
    }
    let (image, sampled) = replay(&replaying)?;
    let sampled = sampled.unwrap_or_default();
    let mut j = judge_replayed(
        &replaying,
        &image,
        Some(&sampled),
        reference.0,
        tolerance,
        accel,
        progress,
    );
    let width = plain.0.width;
    let differing = ours.taken.pixels_differing(&theirs.taken, width);
    let mut violations = Vec::new();
    if sampled.otherwise.is_empty() {
        violations.push(format!(
            "its own sampling decisions differ from the reference's in {} pixels, yet on the \
             reference's samples it takes each as the reference did: its sampling does not repeat",
            differing.len()
        ));
    }
    let kept = plain_off_replay(plain.0, &image, &differing);
    if kept > 0 {
        violations.push(format!(
            "the image differs from its replay of the reference's sampling decisions in {kept} \
             pixels where its own decisions are the reference's"
        ));
    }
    let unit = j.unit;
    if let Some(d) = j.decisions.as_mut() {
        d.sampled_otherwise = differing.len() as f64 / plain.0.pixels.len().max(1) as f64;
        d.plain = figures(&plain.0.scaled(unit), &reference.0.scaled(unit)).ok();
        d.violations.extend(violations.iter().cloned());
    }
    j.violations.extend(violations);
    Ok(j)
}

/// How many pixels of `plain` differ in their bits from `replayed`
/// outside `differing` (sorted places), where both traced the same
/// samples.
fn plain_off_replay(plain: &Image, replayed: &Image, differing: &[usize]) -> usize {
    let bits = |p: &[f32; 3]| p.map(f32::to_bits);
    plain
        .pixels
        .iter()
        .zip(&replayed.pixels)
        .enumerate()
        .filter(|(i, (a, b))| bits(a) != bits(b) && differing.binary_search(i).is_err())
        .count()
}
