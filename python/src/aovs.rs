//! `render(..., aovs=[...])`: the names a render takes, and its pixels'
//! AOVs (src/base/aov.rs) as numpy arrays by those names.

use numpy::PyArray1;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use glint::aov::{Aov, Values, AOVS};

/// The AOVs asked for, checked: known names, each once. None where none
/// was asked for (None or an empty list).
pub fn asked(aovs: Option<Vec<String>>) -> PyResult<Option<Vec<&'static str>>> {
    let Some(aovs) = aovs.filter(|a| !a.is_empty()) else {
        return Ok(None);
    };
    let mut names = Vec::new();
    for a in &aovs {
        let Some(name) = glint::aov::named(a).map(|t| &t.name) else {
            return Err(PyValueError::new_err(format!(
                "aovs: {a:?} is not an AOV glint gives: {}",
                glint::aov::names()
                    .map(|n| format!("{n:?}"))
                    .collect::<Vec<_>>()
                    .join(", ")
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

/// Refuses AOVs of a scene whose sampling takes none (`glint::sampling::MODES`):
/// corners and adaptive sampling trace the pixels' corners, and contrast
/// sampling chooses a pixel's samples level by level.
pub fn check_sampling(scene: &glint::scene::Scene) -> PyResult<()> {
    match glint::sampling::aovs_refused(scene) {
        Some(why) => Err(PyValueError::new_err(format!("aovs: {why}"))),
        None => Ok(()),
    }
}

/// The arrays of `names` for an image of `width` x `height` whose pixels'
/// AOVs are `aovs`, row by row, as the AOV table (`glint::aov::AOVS`)
/// reads them: (h, w) for one channel, else (h, w, channels); float32,
/// int32 or uint32 as the row's values are.
pub fn arrays<'py>(
    py: Python<'py>,
    names: &[&str],
    aovs: &[Aov],
    (width, height): (u32, u32),
) -> PyResult<Bound<'py, PyDict>> {
    let (w, h) = (width as usize, height as usize);
    let d = PyDict::new(py);
    for name in names {
        let t = AOVS
            .iter()
            .find(|t| t.name == *name)
            .expect("`asked` knows the names");
        let channels = aovs
            .iter()
            .flat_map(|a| (t.read)(a).into_iter().take(t.channels));
        let flat = match t.values {
            Values::Float => {
                PyArray1::from_vec(py, channels.map(|v| v as f32).collect::<Vec<f32>>()).into_any()
            }
            Values::Int => {
                PyArray1::from_vec(py, channels.map(|v| v as i32).collect::<Vec<i32>>()).into_any()
            }
            Values::Count => {
                PyArray1::from_vec(py, channels.map(|v| v as u32).collect::<Vec<u32>>()).into_any()
            }
        };
        let array = if t.channels == 1 {
            flat.call_method1("reshape", ((h, w),))?
        } else {
            flat.call_method1("reshape", ((h, w, t.channels),))?
        };
        d.set_item(*name, array)?;
    }
    Ok(d)
}
