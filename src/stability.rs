//! The stability table: each variant's error against the CPU f64 reference
//! on one scene, relative to the reference's peak so that a scene lit at
//! 1e30 reads on the same scale as one lit at 1.

use serde::Serialize;

use crate::accel::Accel;
use crate::cpu;
use crate::gpu::{GpuError, Intersect, RenderSettings, Renderer};
use crate::raster::diff::{figures, ErrorFigures, Tolerance};
use crate::scene::Scene;

/// One renderer's result on one extreme scene.
#[derive(Debug, Clone, Serialize)]
pub struct Row {
    /// Which renderer: `gpu robust`, `gpu naive`, `cpu f32`.
    pub variant: &'static str,
    /// Its error against the CPU f64 reference, relative to the reference's peak.
    pub error: ErrorFigures,
    /// Whether it is within the tolerance.
    pub pass: bool,
}

/// Every renderer's result on one extreme scene.
#[derive(Debug, Clone, Serialize)]
pub struct SceneRows {
    /// The largest finite value of the reference; errors are relative to it.
    pub peak: f64,
    /// One a renderer.
    pub rows: Vec<Row>,
}

/// GPU f32 robust, GPU f32 naive and CPU f32 against CPU f64 on `scene`.
pub fn evaluate(renderer: &mut Renderer, scene: &Scene) -> Result<SceneRows, GpuError> {
    let reference = cpu::reference(scene, Accel::Auto)?;
    let peak = reference.peak();
    let reference = reference.scaled(peak);
    let mut images = Vec::new();
    for (variant, form) in [
        ("gpu f32 robust", Intersect::Robust),
        ("gpu f32 naive", Intersect::Naive),
    ] {
        let how = RenderSettings {
            intersect: form,
            ..renderer.settings()
        };
        let rendered = renderer.prepare(scene, &how)?.render(None, &|_| {})?;
        images.push((variant, rendered.image));
    }
    let cpu32 = cpu::render::<f32>(scene);
    scene.within(&cpu32, "f32")?;
    images.push(("cpu f32", cpu32));
    let tolerance = Tolerance::default();
    let rows = images
        .into_iter()
        .map(|(variant, image)| {
            let error = figures(&image.scaled(peak), &reference).expect("same size");
            Row {
                variant,
                error,
                pass: tolerance.violations(&error).is_empty(),
            }
        })
        .collect();
    Ok(SceneRows { peak, rows })
}
