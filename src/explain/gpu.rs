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
     must call RECORD_BEGIN(x, y, i, j) before each trace(), and your trace.glsl and shade.glsl \
     their RECORD_ hooks (docs/shaders.md)";

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
    match tree_of_words(&words, settings.precision, name) {
        Ok(t) => Ok(in_frame(t, scene, settings.intersect)),
        // Name the file that records nothing (a replaced trace.glsl was
        // blamed on "a main shader of your own").
        Err(ExplainError::Record(e)) if e == UNRECORDED => {
            let files = renderer.unrecording();
            if files.is_empty() {
                Err(ExplainError::Record(e))
            } else {
                Err(ExplainError::Record(format!(
                    "the shader recorded nothing for this sample: {} replace{} glint's file{} of that name and call{} none of its RECORD_ hooks (docs/shaders.md)",
                    files.join(", "),
                    if files.len() == 1 { "s" } else { "" },
                    if files.len() == 1 { "" } else { "s" },
                    if files.len() == 1 { "s" } else { "" },
                )))
            }
        }
        Err(e) => Err(e),
    }
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
    let name = if renderer.spec_worst() {
        format!("gpu f32{}", super::worst::SUFFIX)
    } else {
        "gpu f32".to_owned()
    };
    let mut trees = vec![record_on_gpu(renderer, scene, &settings, sample, &name)?];
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

/// How far the plain variant's pixel may be from its recorded samples'
/// mean, relative to the larger channel (and at least this much of 1):
/// the same arithmetic in the same order writes the same bits, and this
/// leaves room only for a sum's rounding in another order.
const RENDER_SLACK: f64 = 1e-5;

/// The colours of every sample of `pixel` as the recording variant traces
/// them (`known` by index where already recorded), and their mean as the
/// shader takes it: summed in f32 in the samples' order, then scaled.
fn recorded_mean(
    renderer: &mut Renderer,
    scene: &Scene,
    settings: &RenderSettings,
    pixel: [u32; 2],
    known: &[(u32, [f64; 3])],
) -> Result<[f64; 3], ExplainError> {
    let all = super::samples(scene, (pixel[0], pixel[1]), None)?;
    let mut sum = [0.0f32; 3];
    for s in &all {
        let colour = match known.iter().find(|(i, _)| *i == s.index) {
            Some((_, c)) => *c,
            None => {
                let words = record_words(renderer, scene, settings, *s)?;
                tree_of_words(&words, settings.precision, "gpu f32")?.color
            }
        };
        for (acc, c) in sum.iter_mut().zip(colour) {
            *acc += c as f32;
        }
    }
    let scale = 1.0 / all.len() as f32;
    Ok(sum.map(|c| f64::from(c * scale)))
}

/// The pixel the plain variant (`settings` without the recording) writes.
fn plain_pixel(
    renderer: &mut Renderer,
    scene: &Scene,
    settings: &RenderSettings,
    [x, y]: [u32; 2],
) -> Result<[f32; 3], GpuError> {
    let plain = RenderSettings {
        record: None,
        count: false,
        ..*settings
    };
    let region = Region {
        x,
        y,
        width: 1,
        height: 1,
    };
    Ok(renderer
        .prepare(scene, &plain)?
        .render(Some(region), &|_| {})?
        .image
        .pixels[0])
}

/// Holds every explanation's pixel to the one the plain variant of
/// `settings` writes (explain judged the recorded tree alone, and said
/// "every tree agrees" of a render that was wrong): the mean of the
/// pixel's recorded samples must be that pixel, else each of its
/// explanations says the render differs from its recorded trees, and does
/// not agree.
pub fn check_renders(
    renderer: &mut Renderer,
    scene: &Scene,
    settings: &RenderSettings,
    explanations: &mut [Explanation],
) -> Result<(), ExplainError> {
    let settings = RenderSettings {
        precision: Precision::F32,
        ..*settings
    };
    let mut pixels: Vec<[u32; 2]> = explanations.iter().map(|e| e.sample.pixel).collect();
    pixels.dedup();
    for pixel in pixels {
        let known: Vec<(u32, [f64; 3])> = explanations
            .iter()
            .filter(|e| e.sample.pixel == pixel)
            .filter_map(|e| e.trees.first().map(|t| (e.sample.index, t.color)))
            .collect();
        let mean = recorded_mean(renderer, scene, &settings, pixel, &known)?;
        let wrote = plain_pixel(renderer, scene, &settings, pixel)?;
        let off = wrote.iter().zip(mean).any(|(&w, m)| {
            let w = f64::from(w);
            // NaN on either side is off too.
            let within = (w - m).abs() <= RENDER_SLACK * w.abs().max(m.abs()).max(1.0);
            !within
        });
        if off {
            let render = format!(
                "the render differs from its recorded tree: the plain variant wrote {:?} at pixel {},{}, \
                 where the mean of its recorded samples is {:?}",
                wrote, pixel[0], pixel[1], mean.map(|c| c as f32)
            );
            for e in explanations.iter_mut().filter(|e| e.sample.pixel == pixel) {
                e.render = Some(render.clone());
                e.agree = false;
            }
        }
    }
    Ok(())
}
