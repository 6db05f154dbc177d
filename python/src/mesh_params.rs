//! A numpy mesh's arrays through `scene.params`: `"meshes[0].vertices"`
//! (and `faces`, `normals`, `uvs`) read as arrays and set as arrays. A new
//! array writes the mesh's OBJ file anew and names it in the scene, which
//! is then read as any change is: a prepared scene takes moved vertices in
//! place (a refit, nothing compiled).

use std::path::{Path, PathBuf};

use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyKeyError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use glint::scene::{MeshArrays, MeshCache};

use crate::arrays::{ArrayFiles, MESH_ARRAYS};

/// The mesh index and array name of a key such as `meshes[2].vertices`.
pub fn array_key(key: &str) -> Option<(usize, &str)> {
    let rest = key.strip_prefix("meshes[")?;
    let (index, name) = rest.split_once("].")?;
    let index = index.parse().ok()?;
    MESH_ARRAYS.contains(&name).then_some((index, name))
}

/// The file mesh `index` is read from, in `table`.
fn file_of(table: &toml::Table, index: usize, base: &Path) -> Option<PathBuf> {
    let file = table
        .get("meshes")?
        .as_array()?
        .get(index)?
        .get("file")?
        .as_str()?;
    Some(base.join(file))
}

/// The arrays of mesh `index`: those a dict gave it (kept by `cache`).
fn arrays_of(
    table: &toml::Table,
    index: usize,
    base: &Path,
    cache: &MeshCache,
    key: &str,
) -> PyResult<MeshArrays> {
    let not_arrays = || {
        PyKeyError::new_err(format!(
            "{key:?}: meshes[{index}] is not a mesh given as arrays (its triangles are its OBJ \
             file's; a mesh made from vertices and faces takes new ones)"
        ))
    };
    let file = file_of(table, index, base).ok_or_else(not_arrays)?;
    if !crate::arrays::is_written(&file) {
        return Err(not_arrays());
    }
    cache.arrays(&file).ok_or_else(not_arrays)
}

/// Rows of `width` numbers as an (n, width) numpy array.
fn matrix<'py, T: numpy::Element>(
    py: Python<'py>,
    values: Vec<T>,
    width: usize,
) -> PyResult<Bound<'py, PyAny>> {
    let n = values.len() / width;
    Ok(PyArray1::from_vec(py, values)
        .reshape([n, width])?
        .into_any())
}

/// The array `name` of mesh `index` (`params["meshes[0].vertices"]`).
pub fn get<'py>(
    py: Python<'py>,
    table: &toml::Table,
    base: &Path,
    cache: &MeshCache,
    key: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let (index, name) = array_key(key).ok_or_else(|| PyKeyError::new_err(key.to_owned()))?;
    let a = arrays_of(table, index, base, cache, key)?;
    let missing = || PyKeyError::new_err(format!("{key:?}: the mesh has no {name}"));
    match name {
        "vertices" => matrix(py, a.positions, 3),
        "faces" => matrix(py, a.faces.iter().map(|&i| i64::from(i)).collect(), 3),
        "normals" => matrix(py, a.normals.ok_or_else(missing)?, 3),
        _ => matrix(py, a.uvs.ok_or_else(missing)?, 2),
    }
}

/// Sets the arrays of `items` (each `meshes[i].NAME`, value an array) in
/// `table`: each mesh's OBJ file written anew with its other arrays as
/// they are, into `files`, and named in the table.
pub fn set(
    py: Python<'_>,
    table: &mut toml::Table,
    base: &Path,
    cache: &MeshCache,
    items: &[(String, Bound<'_, PyAny>)],
    files: &mut ArrayFiles,
) -> PyResult<()> {
    let mut meshes: Vec<usize> = items
        .iter()
        .filter_map(|(k, _)| array_key(k).map(|(i, _)| i))
        .collect();
    meshes.sort_unstable();
    meshes.dedup();
    for index in meshes {
        let key = format!("meshes[{index}]");
        let a = arrays_of(table, index, base, cache, &key)?;
        let row = PyDict::new(py);
        row.set_item("vertices", matrix(py, a.positions, 3)?)?;
        row.set_item(
            "faces",
            matrix(py, a.faces.iter().map(|&i| i64::from(i)).collect(), 3)?,
        )?;
        if let Some(n) = a.normals {
            row.set_item("normals", matrix(py, n, 3)?)?;
        }
        if let Some(uv) = a.uvs {
            row.set_item("uvs", matrix(py, uv, 2)?)?;
        }
        for (k, v) in items {
            if let Some((i, name)) = array_key(k) {
                if i == index {
                    if v.is_none() {
                        row.del_item(name)?;
                    } else {
                        row.set_item(name, v)?;
                    }
                }
            }
        }
        let file = files.mesh(&row, &key)?;
        let entry = table
            .get_mut("meshes")
            .and_then(|m| m.as_array_mut())
            .and_then(|m| m.get_mut(index))
            .and_then(|m| m.as_table_mut())
            .ok_or_else(|| PyKeyError::new_err(key.clone()))?;
        entry.insert("file".into(), toml::Value::String(file));
    }
    files.cache_meshes(cache);
    Ok(())
}
