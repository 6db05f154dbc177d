//! Adaptive sampling's refinement on the GPU: each level's points as the
//! list the shader traces (shaders/adaptive.glsl), `REFINE_POINTS` an
//! invocation. The pixels to split and the levels themselves are
//! `sampling::adaptive`'s, shared with the CPU. Contrast sampling's levels are
//! lists of the same words (shaders/contrast.glsl; `sampling::contrast`).

use super::layout::refine::Values;
use super::Precision;
use crate::base::interface::{array, Array};
use crate::sampling::adaptive::Point;
use crate::sampling::contrast::Entry;

/// A level's points as the shader's list.
pub(crate) fn list(points: &[Point]) -> Array<'static> {
    let values = points.iter().map(|p| Values {
        point: [p.x, p.y, p.level, 0],
    });
    array(values, Precision::F32)
}

/// A level of contrast sampling's entries as the shader's list: (x, y,
/// first sample, count), one invocation an entry (shaders/contrast.glsl).
pub(crate) fn entries(entries: &[Entry]) -> Array<'static> {
    let values = entries.iter().map(|e| Values {
        point: [e.x, e.y, e.first, e.count],
    });
    array(values, Precision::F32)
}
