//! `glint.compare`: `glint compare`'s check of an f32 render against the
//! f64 reference, with its tolerance and conditioning (docs/guide.md,
//! Accuracy), and the pixels that break it.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use numpy::{PyArray1, PyArray2, PyArray3, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use glint::accel::Accel;
use glint::condition;
use glint::cpu;
use glint::raster::diff::{self, Tolerance};
use glint::raster::Image;

use crate::errors::{self, guard};
use crate::image::to_numpy;
use crate::render::interruptible;
use crate::scene::Scene;

/// What `glint.compare` returns before its Python wrapper: the image
/// checked, the reference, the judgement as JSON, the pixels over 1/255
/// and the ill-conditioned ones (None where the check never needed them).
type Compared<'py> = (
    Bound<'py, PyArray3<f32>>,
    Bound<'py, PyArray3<f32>>,
    String,
    Bound<'py, PyArray2<bool>>,
    Option<Bound<'py, PyArray2<bool>>>,
);

fn mask(
    py: Python<'_>,
    flags: Vec<bool>,
    (w, h): (u32, u32),
) -> PyResult<Bound<'_, PyArray2<bool>>> {
    PyArray1::from_vec(py, flags).reshape([h as usize, w as usize])
}

#[pyfunction]
#[pyo3(signature = (scene, image, frac_over_1_255=None, rmse=None))]
pub fn compare_raw<'py>(
    py: Python<'py>,
    scene: &Scene,
    image: numpy::PyReadonlyArray3<'_, f32>,
    frac_over_1_255: Option<f64>,
    rmse: Option<f64>,
) -> PyResult<Compared<'py>> {
    let mut tolerance = Tolerance::default();
    for (value, slot, name) in [
        (
            frac_over_1_255,
            &mut tolerance.frac_over_1_255,
            "frac_over_1_255",
        ),
        (rmse, &mut tolerance.rmse, "rmse"),
    ] {
        if let Some(v) = value {
            if !(v >= 0.0 && v.is_finite()) {
                return Err(PyValueError::new_err(format!(
                    "{name} {v}: a tolerance is finite and >= 0"
                )));
            }
            *slot = v;
        }
    }
    let image: Image = crate::image::from_numpy(&image, "image")?;
    guard(|| {
        let scene = scene.scene();
        let scene = &*scene;
        if (image.width, image.height) != (scene.width, scene.height) {
            return Err(PyValueError::new_err(format!(
                "image is {}x{}, the scene {}x{}",
                image.width, image.height, scene.width, scene.height
            )));
        }
        cpu::bound::check(scene).map_err(errors::other)?;
        let stop = Arc::new(AtomicBool::new(false));
        let (reference, judgement, over) = interruptible(py, &stop, || {
            let mut prepared = cpu::Prepared::<f64>::new(scene, Accel::Auto);
            prepared.stop_when(stop.clone());
            let reference = prepared.render(&|_| {});
            if stop.load(Ordering::Relaxed) {
                // Cut short: `interruptible` raises KeyboardInterrupt.
                return Err(errors::other("interrupted"));
            }
            scene.within(&reference, "f64").map_err(errors::other)?;
            // The conditioning trials, where the whole image fails, are
            // not cut short: Ctrl-C takes effect when they end.
            let judgement =
                condition::judge(scene, &image, &reference, &tolerance, Accel::Auto, &|_| {});
            let unit = judgement.unit;
            let over: Vec<bool> = diff::pixel_errors(&image, &reference)
                .map_err(|e| PyValueError::new_err(e.to_string()))?
                .into_iter()
                .map(|e| e / unit > 1.0 / 255.0)
                .collect();
            Ok((reference, judgement, over))
        })?;
        let size = (scene.width, scene.height);
        let ill = match &judgement.conditioned {
            Some(c) => Some(mask(py, c.pixels.clone(), size)?),
            None => None,
        };
        let json = serde_json::json!({
            "passed": judgement.pass(),
            "unit": judgement.unit,
            "error": judgement.error,
            "conditioned": judgement.conditioned,
            "violations": judgement.violations,
            "tolerance": tolerance,
        });
        Ok((
            to_numpy(py, image)?,
            to_numpy(py, reference)?,
            json.to_string(),
            mask(py, over, size)?,
            ill,
        ))
    })
}
