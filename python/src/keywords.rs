//! Whole-number keywords (`width=`, `samples=`, `sample=`), checked in
//! Python's words: a ValueError naming the keyword and its range. Taken
//! as u32 by PyO3, `width=-1` and `samples=2**40` raised OverflowError
//! "out of range integral type conversion attempted", naming nothing.

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

use glint::scene::{Overrides, MAX_DEPTH, MAX_SAMPLES, MAX_SIZE};

/// `value` of keyword `name` as a whole number in `lo..=hi`.
pub fn whole(value: &Bound<'_, PyAny>, name: &str, lo: u32, hi: u32) -> PyResult<u32> {
    let shown = || {
        value.repr().map_or_else(
            |_| "?".to_owned(),
            |r| glint::printable::text(&r.to_string()),
        )
    };
    if value.is_instance_of::<pyo3::types::PyBool>() {
        return Err(PyTypeError::new_err(format!(
            "{name}={}: must be a whole number",
            shown()
        )));
    }
    let n: i128 = match value.extract::<i128>() {
        Ok(n) => n,
        // Past i128 (10**40): out of range all the same.
        Err(_) if value.is_instance_of::<pyo3::types::PyInt>() => i128::MAX,
        Err(_) => {
            return Err(PyTypeError::new_err(format!(
                "{name}={}: must be a whole number",
                shown()
            )))
        }
    };
    if n < i128::from(lo) || n > i128::from(hi) {
        return Err(PyValueError::new_err(format!(
            "{name}={}: must be a whole number in {lo}..={hi}",
            shown()
        )));
    }
    Ok(n as u32)
}

/// An optional keyword, as [`whole`].
pub fn optional(
    value: Option<&Bound<'_, PyAny>>,
    name: &str,
    lo: u32,
    hi: u32,
) -> PyResult<Option<u32>> {
    value
        .filter(|v| !v.is_none())
        .map(|v| whole(v, name, lo, hi))
        .transpose()
}

/// The size, sampling and depth keywords (`glint.load`'s, `render`'s), as
/// the command line's overrides.
pub fn overrides(
    width: Option<&Bound<'_, PyAny>>,
    height: Option<&Bound<'_, PyAny>>,
    samples: Option<&Bound<'_, PyAny>>,
    max_depth: Option<&Bound<'_, PyAny>>,
) -> PyResult<Overrides> {
    Ok(Overrides {
        width: optional(width, "width", 1, MAX_SIZE)?,
        height: optional(height, "height", 1, MAX_SIZE)?,
        samples: optional(samples, "samples", 1, MAX_SAMPLES)?,
        max_depth: optional(max_depth, "max_depth", 1, MAX_DEPTH)?,
    })
}
