//! One pixel's ray tree on every renderer, side by side, down to the first
//! number that differs (`glint explain`; docs/guide.md, Why does this
//! pixel differ?).
//!
//! Each renderer records the same events of a sample's tree at the same
//! places (`crate::base::record`): the CPU reference through its tally,
//! the GPU through the recording variant (shaders/record.glsl), whose
//! image is the plain variant's. The trees are laid flat, quantity by
//! quantity, and each quantity of the f64 reference's gets an f32 bound
//! from the conditioning trials `glint compare` runs (`crate::condition`),
//! here on this one sample: the scene and every hit point moved by f32's
//! roundings, and the CPU's own f32. The first quantity where a renderer
//! leaves the reference by more than its bound is the divergence, and its
//! cause is named: a near-tie, a self-intersection, a grazing ray, or a
//! wrong value at one stage.

mod diverge;
mod flat;
#[cfg(feature = "gpu")]
mod gpu;
mod number;
pub mod table;
mod tree;
mod worst;

use serde::Serialize;

use crate::accel::Accel;
use crate::cpu::Probe;
use crate::raster::diff::pixel_errors;
use crate::raster::Image;
use crate::scene::{Sampling, Scene};

use crate::base::record::Event;
pub use diverge::Divergence;
#[cfg(feature = "gpu")]
pub use gpu::{
    check_renders, explain_on_gpu, in_frame, record_on_gpu, record_words, tree_of_words,
};
pub use tree::{Blocker, Hit, Light, Primitive, Shadow, Tree, TreeRay};

/// Why a pixel cannot be explained: one line each.
#[derive(Debug, thiserror::Error)]
pub enum ExplainError {
    /// The pixel is not in the image.
    #[error(
        "pixel {x},{y} is outside the {width}x{height} image (x in 0..{width}, y in 0..{height})"
    )]
    Outside {
        /// The pixel asked for.
        x: u32,
        /// Its row.
        y: u32,
        /// The image's size.
        width: u32,
        /// Its height.
        height: u32,
    },
    /// The sample is past the pixel's grid.
    #[error(
        "sample {sample} is past the pixel's {count} samples ({what}): give --sample 0..{count}"
    )]
    Sample {
        /// The sample asked for.
        sample: u32,
        /// The pixel's samples.
        count: u32,
        /// How they are laid out.
        what: String,
    },
    /// Adaptive sampling's points depend on the whole image.
    #[error("the scene samples adaptively, and the points it adds depend on the whole image's corners; explain the corners alone by setting sampling = \"corners\" in the scene")]
    Adaptive,
    /// Contrast sampling's samples depend on the neighbours' samples.
    #[error("the scene samples by contrast, and the samples a pixel takes depend on its neighbours'; explain its centre sample by setting samples = 1 and no sampling in the scene")]
    Contrast,
    /// Nothing to trace.
    #[error("the scene has no primitives: every ray meets the background, and there is no tree to explain")]
    Empty,
    /// A recording that could not be read.
    #[error("{0}")]
    Record(String),
    /// The device could not record the tree.
    #[cfg(feature = "gpu")]
    #[error(transparent)]
    Gpu(#[from] crate::gpu::GpuError),
}

/// One sample of a pixel: its index among the pixel's samples and the
/// sample as the renderers trace it, (x, y, i, j) of the traced image
/// (the corner grid's pixel, where the scene samples corners).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Sample {
    /// The pixel, in the image.
    pub pixel: [u32; 2],
    /// Its index: j·samples + i, or the corner (top-left, top-right,
    /// bottom-left, bottom-right).
    pub index: u32,
    /// (x, y, i, j) of the traced image.
    pub traced: [u32; 4],
}

/// The samples of pixel (x, y) of `scene` (`only`: just that one), each as
/// the renderers trace it; one clear error where the pixel, the sample or
/// the scene cannot be explained.
pub fn samples(
    scene: &Scene,
    (x, y): (u32, u32),
    only: Option<u32>,
) -> Result<Vec<Sample>, ExplainError> {
    if x >= scene.width || y >= scene.height {
        return Err(ExplainError::Outside {
            x,
            y,
            width: scene.width,
            height: scene.height,
        });
    }
    if scene.prims.is_empty() {
        return Err(ExplainError::Empty);
    }
    let all: Vec<Sample> = match scene.sampling {
        Sampling::Adaptive => return Err(ExplainError::Adaptive),
        Sampling::Contrast => return Err(ExplainError::Contrast),
        Sampling::Corners => (0..4)
            .map(|c| Sample {
                pixel: [x, y],
                index: c,
                traced: [x + c % 2, y + c / 2, 0, 0],
            })
            .collect(),
        Sampling::Centers => {
            let n = scene.samples;
            (0..n * n)
                .map(|s| Sample {
                    pixel: [x, y],
                    index: s,
                    traced: [x, y, s % n, s / n],
                })
                .collect()
        }
    };
    match only {
        None => Ok(all),
        Some(s) if (s as usize) < all.len() => Ok(vec![all[s as usize]]),
        Some(s) => Err(ExplainError::Sample {
            sample: s,
            count: all.len() as u32,
            what: if scene.sampling == Sampling::Corners {
                "its corners".to_owned()
            } else {
                format!("a {0}x{0} grid", scene.samples)
            },
        }),
    }
}

/// The `n` pixels of `image` farthest from `reference` (the largest
/// channel's difference; a non-finite value farthest of all), worst first,
/// among those that differ at all.
pub fn worst_pixels(image: &Image, reference: &Image, n: usize) -> Vec<(u32, u32)> {
    let Ok(errors) = pixel_errors(image, reference) else {
        return Vec::new();
    };
    let mut order: Vec<usize> = (0..errors.len()).filter(|&i| errors[i] != 0.0).collect();
    let key = |i: usize| {
        if errors[i].is_nan() {
            f64::INFINITY
        } else {
            errors[i]
        }
    };
    order.sort_by(|&a, &b| key(b).total_cmp(&key(a)).then(a.cmp(&b)));
    order
        .into_iter()
        .take(n)
        .map(|i| {
            (
                (i % image.width as usize) as u32,
                (i / image.width as usize) as u32,
            )
        })
        .collect()
}

/// What the reference says of one sample: the CPU's trees in f64 and f32,
/// and each quantity's f32 bound from the trials.
pub struct Reference {
    sample: Sample,
    f64: Tree,
    f32: Tree,
    entries: Vec<flat::Entry>,
    bounds: Vec<flat::Bound>,
    probe: Probe<f64>,
}

/// Answers where a reference ray meets a given primitive.
trait Geometry {
    /// The distance along `ray` (the reference's) to `prim`.
    fn distance(&self, prim: Primitive, ray: &TreeRay) -> Option<f64>;
}

impl Geometry for Reference {
    fn distance(&self, prim: Primitive, ray: &TreeRay) -> Option<f64> {
        let v = |a: [f64; 3]| glam::DVec3::from_array(a);
        self.probe.distance(
            prim.id,
            v(ray.origin),
            v(ray.direction),
            ray.leaves.map(|p| p.id),
        )
    }
}

impl Reference {
    /// Traces `sample` of `scene` on the CPU in f64 and f32 and under each
    /// conditioning trial, with the scene management `accel`.
    pub fn new(scene: &Scene, accel: Accel, sample: Sample) -> Result<Self, ExplainError> {
        let probe = Probe::<f64>::new(scene, accel);
        let tree =
            |name: &str, events: Vec<Event>| Tree::of(name, &events).map_err(ExplainError::Record);
        let f64 = tree("cpu f64", probe.record(sample.traced))?;
        let f32 = tree(
            "cpu f32",
            Probe::<f32>::new(scene, accel).record(sample.traced),
        )?;
        let entries = flat::entries(&f64);
        // The CPU's f32, then each trial, folded into the bounds one at a
        // time, each walked an entry at a time.
        let mut bounds = flat::floor_bounds(&entries);
        flat::widen(&mut bounds, &entries, &f32);
        for t in 0..crate::condition::TRIALS {
            let (moved, moves) = crate::condition::trial(scene, t);
            let events = Probe::<f64>::moved(&moved, accel, moves).record(sample.traced);
            flat::widen(&mut bounds, &entries, &tree("trial", events)?);
        }
        Ok(Self {
            sample,
            f64,
            f32,
            entries,
            bounds,
            probe,
        })
    }

    /// The sample explained, with the trees of `others` (the GPU's, then
    /// any other devices') in the columns before the CPU's. Each tree is
    /// walked beside the reference's entries, an entry at a time, so that
    /// only the reference's are held whole; the table lays flat only the
    /// rays it shows.
    pub fn explain(self, others: Vec<Tree>) -> Explanation {
        let mut divergences = Vec::new();
        let mut marks = Vec::new();
        let mut focus = Vec::new();
        let mut look = |t: &Tree, marks: &mut Vec<Vec<bool>>| {
            marks.push(table::marks(t, &self.entries, &self.bounds));
            if let Some(k) = diverge::first(t, &self.entries, &self.bounds) {
                focus.extend(self.entries.get(k).and_then(flat::Entry::ray));
            }
        };
        for t in &others {
            divergences.push(diverge::divergence(
                t,
                &self.f64,
                &self.entries,
                &self.bounds,
                &self,
                &self.f32,
            ));
            look(t, &mut marks);
        }
        // The CPU's own f32 is one of the trials: it is shown, not judged.
        look(&self.f32, &mut marks);
        marks.push(vec![false; self.entries.len()]);
        let shown = table::shown_rays(&self.f64, &focus);
        let Reference {
            sample,
            f64,
            f32,
            entries,
            bounds,
            ..
        } = self;
        let mut trees = others;
        trees.push(f32);
        let keep = |n: usize| shown.as_ref().is_none_or(|s| s[n]);
        let flats: Vec<Vec<flat::Entry>> =
            trees.iter().map(|t| flat::entries_of(t, keep)).collect();
        trees.push(f64);
        let mut columns: Vec<&[flat::Entry]> = flats.iter().map(Vec::as_slice).collect();
        columns.push(&entries);
        let rows = table::rows(&columns, &bounds, &marks, shown.as_deref());
        let table = table::render(&trees, &rows, &entries, &marks, shown.as_deref());
        Explanation {
            sample,
            agree: divergences.iter().all(Option::is_none),
            render: None,
            divergences,
            table,
            rows,
            trees,
        }
    }
}

/// One sample explained: every renderer's tree, and the first divergence
/// of each that is judged (every tree but the CPU's).
#[derive(Debug, Clone, Serialize)]
pub struct Explanation {
    /// The sample.
    pub sample: Sample,
    /// Whether no judged tree leaves the reference past a bound, and the
    /// render's pixel is its recorded samples' mean.
    pub agree: bool,
    /// Where the pixel the plain variant wrote is not the mean of its
    /// recorded samples (`check_renders`): a divergence of its own kind.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub render: Option<String>,
    /// The first divergence of each judged tree (the GPU's, then any other
    /// devices'), in the order of `trees`.
    pub divergences: Vec<Option<Divergence>>,
    /// The trees: the judged ones, then the CPU's f32 and f64 (the reference).
    pub trees: Vec<Tree>,
    /// The table a person reads.
    #[serde(skip)]
    pub table: String,
    /// The table's rows: the rays it shows, each quantity with every
    /// tree's value and its bound (`glint serve`'s page shows them).
    #[serde(skip)]
    pub rows: Vec<table::Row>,
}

impl Explanation {
    /// The verdict in a line or a few: every tree agrees, or each
    /// divergence and its cause.
    pub fn verdict(&self) -> String {
        if self.agree && self.render.is_none() {
            return format!(
                "every tree agrees: no quantity of {} leaves the f64 reference by more than its f32 bound",
                names(&self.trees[..self.divergences.len()])
            );
        }
        let mut lines: Vec<String> = self.render.iter().cloned().collect();
        for (t, d) in self.trees.iter().zip(&self.divergences) {
            match d {
                None => lines.push(format!("{}: agrees with the f64 reference", t.renderer)),
                Some(d) => lines.push(format!(
                    "{}: first divergence at {}: {}",
                    t.renderer, d.quantity, d.cause
                )),
            }
        }
        lines.join("\n")
    }
}

fn names(trees: &[Tree]) -> String {
    trees
        .iter()
        .map(|t| t.renderer.as_str())
        .collect::<Vec<_>>()
        .join(", ")
}
