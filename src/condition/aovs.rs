//! AOVs in the oracle's model (docs/guarantees.md, Sampling decisions):
//! what a pixel's first eye ray met first and how many rays its samples
//! traced are choices too. At a near-tie (two faces that meet, a light in
//! a surface's plane) an f32 renderer may meet another primitive, or
//! cast a shadow ray where the reference casts none, and no tolerance
//! applies to an index or a count. So a renderer's AOVs are held to the
//! reference's where the trials, which move the scene as f32 rounds it,
//! leave them alone; where some trial changes them too, a difference is
//! a near-tie.

use super::{conformant_trials, rounding_trials, trial, Trial};
use crate::accel::Accel;
use crate::base::aov::Aov;
use crate::cpu;
use crate::scene::Scene;

/// A renderer's AOVs against the reference's.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AovCheck {
    /// The pixels whose primitive met, or rays traced, differ from the
    /// reference's, by place.
    pub differing: Vec<usize>,
    /// Those no trial changes: where the renderer is wrong.
    pub unexplained: Vec<usize>,
}

impl AovCheck {
    /// Whether every difference is a near-tie.
    pub fn pass(&self) -> bool {
        self.unexplained.is_empty()
    }
}

/// Whether two pixels' AOVs met the same primitive (or none) and traced
/// the same rays: the AOVs that have no tolerance.
fn same_choices(a: &Aov, b: &Aov) -> bool {
    a.rays == b.rays && a.hit.map(|h| h.prim) == b.hit.map(|h| h.prim)
}

/// Holds `aovs`, a renderer's AOVs of `scene` (which samples its pixels'
/// own points), to the f64 reference's: each pixel whose primitive or
/// rays differ must be one that a trial changes too (the trials of f32's
/// roundings, the CPU's own f32 among them, then the driver's).
pub fn judge_aovs(scene: &Scene, aovs: &[Aov], accel: Accel) -> AovCheck {
    let reference = cpu::Prepared::<f64>::new(scene, accel)
        .render_aovs(None, &|_| {})
        .1;
    let differing: Vec<usize> = (0..aovs.len())
        .filter(|&i| !same_choices(&aovs[i], &reference[i]))
        .collect();
    let mut unexplained = differing.clone();
    for t in rounding_trials().chain(conformant_trials()) {
        if unexplained.is_empty() {
            break;
        }
        let moved = match t {
            Trial::Moved(t) => {
                let (moved, moves) = trial(scene, t);
                cpu::aovs_moved(&moved, accel, moves)
            }
            Trial::F32 => {
                cpu::Prepared::<f32>::new(scene, accel)
                    .render_aovs(None, &|_| {})
                    .1
            }
        };
        unexplained.retain(|&i| same_choices(&moved[i], &reference[i]));
    }
    AovCheck {
        differing,
        unexplained,
    }
}
