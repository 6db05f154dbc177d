//! A sample's tree on the GPU: the scene prepared with the recording
//! variant (shaders/record.glsl), the pixel rendered alone, the record read.

use super::{ExplainError, Explanation, Reference, Sample, Tree};
use crate::base::record::{decode, HEADER_WORDS};
use crate::base::Precision;
use crate::gpu::{GpuError, RenderSettings, Renderer};
use crate::raster::region::Region;
use crate::scene::Scene;
use crate::settings::Intersect;

/// What a main shader of a user's must do to be recorded.
const UNRECORDED: &str = "the shader recorded nothing for this sample: a main shader of your own \
     must call RECORD_BEGIN(x, y, i, j) before each trace() (docs/shaders.md)";

/// The record of `sample` of `scene` on `renderer`'s device under
/// `settings` (the megakernel, the recording variant): its header and the
/// entries written, as `tree_of_words` reads them.
pub fn record_words(
    renderer: &mut Renderer,
    scene: &Scene,
    settings: &RenderSettings,
    sample: Sample,
) -> Result<Vec<u32>, GpuError> {
    let settings = RenderSettings {
        record: Some(sample.traced),
        ..*settings
    };
    let mut prepared = renderer.prepare(scene, &settings)?;
    let [x, y] = sample.pixel;
    let region = Region {
        x,
        y,
        width: 1,
        height: 1,
    };
    Ok(prepared
        .render(Some(region), &|_| {})?
        .record
        .unwrap_or_default())
}

/// The tree, named `name`, of a record (`record_words`) made in `precision`.
pub fn tree_of_words(
    words: &[u32],
    precision: Precision,
    name: &str,
) -> Result<Tree, ExplainError> {
    if words.len() < HEADER_WORDS {
        return Err(ExplainError::Record(UNRECORDED.to_owned()));
    }
    let events = decode(words, precision == Precision::F64).map_err(ExplainError::Record)?;
    if events.is_empty() {
        return Err(ExplainError::Record(UNRECORDED.to_owned()));
    }
    Tree::of(name, &events).map_err(ExplainError::Record)
}

/// The tree of `sample` of `scene` on `renderer`'s device, named `name`,
/// in the reference's frame.
pub fn record_on_gpu(
    renderer: &mut Renderer,
    scene: &Scene,
    settings: &RenderSettings,
    sample: Sample,
    name: &str,
) -> Result<Tree, ExplainError> {
    let words = record_words(renderer, scene, settings, sample)?;
    tree_of_words(&words, settings.precision, name).map(|t| in_frame(t, scene, settings.intersect))
}

/// `sample` of `scene` explained: its tree on `renderer`'s device in f32
/// ("gpu f32", the recording variant of `settings`), then `others` (other
/// devices' trees, in the reference's frame), against the reference's.
pub fn explain_on_gpu(
    renderer: &mut Renderer,
    scene: &Scene,
    settings: &RenderSettings,
    sample: Sample,
    others: Vec<Tree>,
) -> Result<Explanation, ExplainError> {
    let settings = RenderSettings {
        precision: Precision::F32,
        ..*settings
    };
    let mut trees = vec![record_on_gpu(
        renderer, scene, &settings, sample, "gpu f32",
    )?];
    trees.extend(others);
    Ok(Reference::new(scene, settings.accel, sample)?.explain(trees))
}

/// `tree` in the reference's camera-relative coordinates: the naive forms
/// trace the scene as written (src/gpu/layout.rs).
pub fn in_frame(tree: Tree, scene: &Scene, intersect: Intersect) -> Tree {
    match intersect {
        Intersect::Robust => tree,
        Intersect::Naive => tree.relative_to(scene.camera.eye),
    }
}
