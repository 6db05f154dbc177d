//! `render(..., aovs=[...])`: the names a render takes, and its pixels'
//! AOVs (src/base/aov.rs) as numpy arrays by those names.

use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use glint::aov::{Aov, NAMES};

/// The AOVs asked for, checked: known names, each once. None where none
/// was asked for (None or an empty list).
pub fn asked(aovs: Option<Vec<String>>) -> PyResult<Option<Vec<&'static str>>> {
    let Some(aovs) = aovs.filter(|a| !a.is_empty()) else {
        return Ok(None);
    };
    let mut names = Vec::new();
    for a in &aovs {
        let Some(name) = NAMES.iter().find(|n| **n == a.as_str()) else {
            return Err(PyValueError::new_err(format!(
                "aovs: {a:?} is not an AOV glint gives: {}",
                NAMES.map(|n| format!("{n:?}")).join(", ")
            )));
        };
        if names.contains(name) {
            return Err(PyValueError::new_err(format!(
                "aovs: {a:?} is asked for twice"
            )));
        }
        names.push(*name);
    }
    Ok(Some(names))
}

/// Refuses AOVs of a scene that samples its pixels' corners (corners and
/// adaptive sampling): they are of a pixel's own samples; and of one
/// sampled by contrast, whose pixels' samples are chosen level by level.
pub fn check_sampling(scene: &glint::scene::Scene) -> PyResult<()> {
    use glint::scene::Sampling;
    if matches!(scene.sampling, Sampling::Corners | Sampling::Adaptive) {
        return Err(PyValueError::new_err(format!(
            "aovs: AOVs are of a pixel's own samples, and this scene samples its pixels' \
             corners (sampling = {:?}): render it with sampling = \"centers\"",
            format!("{:?}", scene.sampling).to_lowercase()
        )));
    }
    if scene.sampling == Sampling::Contrast {
        return Err(PyValueError::new_err(
            "aovs: AOVs are of the first samples of a pixel's grid, and this scene samples by \
             contrast (sampling = \"contrast\"), level by level: render it with sampling = \
             \"centers\"",
        ));
    }
    Ok(())
}

/// The arrays of `names` for an image of `width` x `height` whose pixels'
/// AOVs are `aovs`, row by row: depth (h, w) float32 (inf where nothing
/// was met), normal and albedo (h, w, 3) float32 (0 there), prim_id
/// (h, w, 2) int32 (kind and index; -1, -1 there), rays (h, w) uint32.
pub fn arrays<'py>(
    py: Python<'py>,
    names: &[&str],
    aovs: &[Aov],
    (width, height): (u32, u32),
) -> PyResult<Bound<'py, PyDict>> {
    let (w, h) = (width as usize, height as usize);
    let d = PyDict::new(py);
    for name in names {
        let array = match *name {
            "depth" => {
                let v: Vec<f32> = aovs.iter().map(Aov::depth).collect();
                PyArray1::from_vec(py, v).reshape([h, w])?.into_any()
            }
            "normal" => {
                let v: Vec<f32> = aovs.iter().flat_map(Aov::normal).collect();
                PyArray1::from_vec(py, v).reshape([h, w, 3])?.into_any()
            }
            "albedo" => {
                let v: Vec<f32> = aovs.iter().flat_map(Aov::albedo).collect();
                PyArray1::from_vec(py, v).reshape([h, w, 3])?.into_any()
            }
            "prim_id" => {
                let v: Vec<i32> = aovs.iter().flat_map(Aov::prim_id).collect();
                PyArray1::from_vec(py, v).reshape([h, w, 2])?.into_any()
            }
            "rays" => {
                let v: Vec<u32> = aovs.iter().map(|a| a.rays).collect();
                PyArray1::from_vec(py, v).reshape([h, w])?.into_any()
            }
            other => unreachable!("{other}: `asked` knows the names"),
        };
        d.set_item(*name, array)?;
    }
    Ok(d)
}
