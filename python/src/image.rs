//! Images between glint and numpy: `(height, width, 3)` float32 arrays in
//! linear RGB, handed over without a copy; `glint.read`, `glint.write` and
//! the figures of `glint.diff`.

use std::path::PathBuf;

use numpy::{
    PyArray1, PyArray3, PyArrayMethods, PyReadonlyArray2, PyReadonlyArray3, PyUntypedArrayMethods,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use glint::raster::{diff, io, plane, Image};

use crate::errors::{self, guard};

/// `image`'s pixels as a numpy array that owns them: the vector is handed
/// to numpy as it is (`[f32; 3]` and `f32` share their alignment, so the
/// cast moves no byte).
pub fn to_numpy(py: Python<'_>, image: Image) -> PyResult<Bound<'_, PyArray3<f32>>> {
    let (w, h) = (image.width as usize, image.height as usize);
    let flat: Vec<f32> = bytemuck::allocation::cast_vec(image.pixels);
    PyArray1::from_vec(py, flat).reshape([h, w, 3])
}

/// A `(height, width, 3)` float32 array as glint's image (a copy: glint's
/// images own their pixels).
pub fn from_numpy(a: &PyReadonlyArray3<'_, f32>, what: &str) -> PyResult<Image> {
    let shape = a.shape();
    if shape[2] != 3 || shape[0] == 0 || shape[1] == 0 {
        return Err(PyValueError::new_err(format!(
            "{what}: shape {shape:?}; an image is (height, width, 3) with height, width > 0"
        )));
    }
    let (h, w) = (shape[0], shape[1]);
    let too_big = |_| PyValueError::new_err(format!("{what}: {w}x{h} is too large an image"));
    let (w32, h32) = (
        u32::try_from(w).map_err(too_big)?,
        u32::try_from(h).map_err(too_big)?,
    );
    let pixels = match a.as_slice() {
        Ok(s) => bytemuck::cast_slice::<f32, [f32; 3]>(s).to_vec(),
        Err(_) => {
            let v = a.as_array();
            (0..h)
                .flat_map(|y| (0..w).map(move |x| (y, x)))
                .map(|(y, x)| [v[[y, x, 0]], v[[y, x, 1]], v[[y, x, 2]]])
                .collect()
        }
    };
    Ok(Image::new(w32, h32, pixels))
}

#[pyfunction]
#[pyo3(signature = (path, srgb=true))]
pub fn read(py: Python<'_>, path: PathBuf, srgb: bool) -> PyResult<Bound<'_, PyAny>> {
    guard(|| {
        // A one-channel PFM or EXR (an AOV written by `write`) comes back
        // as the (height, width) array it was.
        if plane::is_plane(&path).unwrap_or(false) {
            let p = crate::gil::detach(py, || plane::read_plane(&path)).map_err(errors::image)?;
            let shape = [p.height as usize, p.width as usize];
            return Ok(PyArray1::from_vec(py, p.values).reshape(shape)?.into_any());
        }
        let image = crate::gil::detach(py, || io::read_as(&path, srgb)).map_err(errors::image)?;
        Ok(to_numpy(py, image)?.into_any())
    })
}

/// Writes a `(height, width)` float32 array as a one-channel PFM or EXR.
#[pyfunction]
pub fn write_plane(
    py: Python<'_>,
    values: PyReadonlyArray2<'_, f32>,
    path: PathBuf,
) -> PyResult<()> {
    guard(|| {
        let shape = values.shape();
        let side = |s: usize| {
            u32::try_from(s).map_err(|_| PyValueError::new_err("image: too large an image"))
        };
        if shape[0] == 0 || shape[1] == 0 {
            return Err(PyValueError::new_err(format!(
                "image: shape {shape:?}; an image has height, width > 0"
            )));
        }
        let p = plane::Plane {
            width: side(shape[1])?,
            height: side(shape[0])?,
            values: values.as_array().iter().copied().collect(),
        };
        crate::gil::detach(py, || plane::write_plane(&path, &p)).map_err(errors::image)
    })
}

#[pyfunction]
#[pyo3(signature = (image, path, srgb=true))]
pub fn write(
    py: Python<'_>,
    image: PyReadonlyArray3<'_, f32>,
    path: PathBuf,
    srgb: bool,
) -> PyResult<()> {
    guard(|| {
        let image = from_numpy(&image, "image")?;
        crate::gil::detach(py, || io::write(&path, &image, srgb)).map_err(errors::image)
    })
}

/// `glint.diff`'s figures, as JSON (`glint raster::diff::ErrorFigures`).
#[pyfunction]
pub fn diff_json(a: PyReadonlyArray3<'_, f32>, b: PyReadonlyArray3<'_, f32>) -> PyResult<String> {
    guard(|| {
        let (a, b) = (from_numpy(&a, "a")?, from_numpy(&b, "b")?);
        let f = diff::figures(&a, &b).map_err(|e| PyValueError::new_err(e.to_string()))?;
        serde_json::to_string(&f).map_err(errors::other)
    })
}
