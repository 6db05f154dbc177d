//! A pixel the page clicked, explained by the same library call as `glint
//! explain`: every sample's trees on the GPU and both CPU precisions, as
//! the rows of its table (each quantity beside its f32 bound), the first
//! divergence of each judged tree and its cause.

use serde::Serialize;

use glint::explain::table::Row;
use glint::explain::{samples, Divergence, Sample};
use glint::gpu::Renderer;
use glint::scene::Scene;

/// One sample explained, as the page shows it.
#[derive(Serialize)]
struct Shown<'e> {
    sample: Sample,
    agree: bool,
    verdict: String,
    /// The renderers, in the columns' order (the f64 reference last).
    renderers: Vec<&'e str>,
    /// Each tree's sample colour, in the same order.
    colors: Vec<[f64; 3]>,
    divergences: &'e [Option<Divergence>],
    rows: &'e [Row],
    /// Each shown ray's title (`ray 2 (reflect ray, depth 2)`), by its
    /// place in the tree.
    titles: Vec<(usize, String)>,
    /// How many rays the reference's tree has; those not in the rows are
    /// summed up by `glint explain --json`.
    rays: usize,
}

#[derive(Serialize)]
struct Page<'e> {
    pixel: [u32; 2],
    samples: Vec<Shown<'e>>,
}

/// The JSON of pixel `(x, y)` of `scene` explained on `renderer`.
pub fn json(renderer: &mut Renderer, scene: &Scene, (x, y): (u32, u32)) -> anyhow::Result<String> {
    let chosen = samples(scene, (x, y), None)?;
    let settings = renderer.settings();
    let others = crate::cli::explain::Others {
        icds: Vec::new(),
        forward: Vec::new(),
    };
    let explained = crate::cli::explain::explain(renderer, scene, &settings, &chosen, &others)?;
    let shown = explained
        .iter()
        .map(|e| {
            let reference = e.trees.last().expect("the reference's tree");
            let mut titles: Vec<(usize, String)> = e
                .rows
                .iter()
                .filter_map(|r| r.ray)
                .map(|n| {
                    let t = &reference.rays[n];
                    (
                        n,
                        format!("ray {} ({} ray, depth {})", n + 1, t.kind, t.depth),
                    )
                })
                .collect();
            titles.dedup();
            Shown {
                sample: e.sample,
                agree: e.agree,
                verdict: e.verdict(),
                renderers: e.trees.iter().map(|t| t.renderer.as_str()).collect(),
                colors: e.trees.iter().map(|t| t.color).collect(),
                divergences: &e.divergences,
                rows: &e.rows,
                titles,
                rays: reference.rays.len(),
            }
        })
        .collect();
    Ok(serde_json::to_string(&Page {
        pixel: [x, y],
        samples: shown,
    })?)
}
