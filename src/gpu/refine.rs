//! Adaptive sampling's refinement on the GPU: each level's points as the
//! list the shader traces (shaders/adaptive.glsl), `REFINE_POINTS` an
//! invocation. The pixels to split and the levels themselves are
//! `scene::refine`'s, shared with the CPU.

use super::layout::refine::Values;
use super::Precision;
use crate::base::interface::{array, Array};
use crate::scene::refine::Point;

/// A level's points as the shader's list.
pub(crate) fn list(points: &[Point]) -> Array<'static> {
    let values = points.iter().map(|p| Values {
        point: [p.x, p.y, p.level, 0],
    });
    array(values, Precision::F32)
}
