//! numpy arrays in a scene's dict: a mesh given as `{"vertices": (N, 3),
//! "faces": (M, 3)}` (with optional per-vertex `"normals"` (N, 3) and
//! `"uvs"` (N, 2)) is written as an OBJ file, and an array given as a
//! texture's `image` as a PFM of its linear values; the scene reads them as
//! it reads any file, so an array loads at the OBJ path's speed and renders
//! the same bits as that file would. The files live in a folder that lasts
//! as long as the scene.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::sync::{Arc, Mutex, Weak};

use glint::scene::MeshArrays;

use numpy::{PyReadonlyArray2, PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors;

/// The keys of a mesh given as arrays, beside the mesh table's own.
pub const MESH_ARRAYS: &[&str] = &["vertices", "faces", "normals", "uvs"];

/// The folder a dict's arrays are written into, made at the first one.
#[derive(Default)]
pub struct ArrayFiles {
    dir: Option<Arc<tempfile::TempDir>>,
    written: usize,
    /// Each file written, and the key of the arrays it holds
    /// (`meshes[0]`, `textures.t.image`): what an error names.
    keys: Vec<(PathBuf, String)>,
    /// The meshes written, by file, as arrays: a scene's mesh cache takes
    /// them, so that the files are not parsed back (`MeshCache::insert_arrays`).
    meshes: Vec<(PathBuf, MeshArrays)>,
}

fn bad(at: &str, what: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(format!("{}: {what}", glint::printable::text(at)))
}

/// `v` as a C-contiguous numpy array of `dtype` (a list converts too).
fn as_array<'py>(v: &Bound<'py, PyAny>, dtype: &str) -> PyResult<Bound<'py, PyAny>> {
    v.py()
        .import("numpy")?
        .call_method1("ascontiguousarray", (v, dtype))
}

/// Rows of `width` numbers, as f64.
fn rows(v: &Bound<'_, PyAny>, width: usize, at: &str) -> PyResult<Vec<f64>> {
    // numpy would cast a complex array to its real parts, with a warning,
    // and bools to 0 and 1: neither is a coordinate.
    if let Ok(dtype) = v.getattr("dtype") {
        let kind: String = dtype.getattr("kind")?.extract()?;
        if !matches!(kind.as_str(), "f" | "i" | "u") {
            let name: String = dtype.getattr("name")?.extract()?;
            return Err(bad(
                at,
                format!(
                    "is an array of {}: it must hold real numbers",
                    glint::printable::text(&name)
                ),
            ));
        }
    }
    let a = as_array(v, "float64").map_err(|_| bad(at, "is not an array of numbers"))?;
    let a: PyReadonlyArray2<'_, f64> = a
        .extract()
        .map_err(|_| bad(at, format!("must be an array of shape (n, {width})")))?;
    if a.shape()[1] != width {
        return Err(bad(
            at,
            format!("has shape {}; it must be (n, {width})", shape(a.shape())),
        ));
    }
    let values = a.as_slice()?.to_vec();
    if let Some(x) = values.iter().find(|x| !x.is_finite()) {
        return Err(bad(at, format!("holds {x}: every value must be finite")));
    }
    Ok(values)
}

/// A shape as numpy prints it: `(3, 2)`.
fn shape(s: &[usize]) -> String {
    let items: Vec<String> = s.iter().map(usize::to_string).collect();
    format!("({})", items.join(", "))
}

/// A number for an OBJ line: the shortest decimal that reads back the same.
fn number(out: &mut String, x: f64) {
    let _ = write!(out, " {x:?}");
}

/// The folders of the arrays of every scene alive: a scene made from
/// another's `to_dict` names its files, and keeps them (a copy made as
/// docs/python.md makes one failed once the original was collected).
static LIVE: Mutex<Vec<Weak<tempfile::TempDir>>> = Mutex::new(Vec::new());

/// Whether `file` is one glint wrote from a dict's arrays (in a folder
/// of a scene alive).
pub fn is_written(file: &std::path::Path) -> bool {
    let live = LIVE.lock().unwrap_or_else(|p| p.into_inner());
    live.iter()
        .filter_map(Weak::upgrade)
        .any(|d| file.starts_with(d.path()))
}

/// The folders of other scenes' arrays that `text` names: a scene read
/// from it keeps them as long as it lives.
pub fn named_in(text: &str) -> Vec<Arc<tempfile::TempDir>> {
    let mut live = LIVE.lock().unwrap_or_else(|p| p.into_inner());
    live.retain(|w| w.strong_count() > 0);
    live.iter()
        .filter_map(Weak::upgrade)
        .filter(|d| text.contains(&*d.path().to_string_lossy()))
        .collect()
}

impl ArrayFiles {
    /// The folder the arrays were written into, where any was: the scene
    /// keeps it as long as it lives.
    pub fn into_dir(self) -> Option<Arc<tempfile::TempDir>> {
        self.dir
    }

    /// `message` (an error of the scene the arrays were read into) with
    /// each file written named by the key of its arrays, not by its
    /// temporary path, which the user never gave.
    pub fn said(&self, message: &str) -> String {
        let mut out = message.to_owned();
        for (path, key) in &self.keys {
            let path = path.display().to_string();
            out = out.replace(&format!("{key}: {path}: "), &format!("{key}: "));
            out = out.replace(&format!("{path}: "), &format!("{key}: "));
            out = out.replace(&path, key);
        }
        out
    }

    /// The key of the arrays an error's key (`meshes[0].file`,
    /// `meshes[0].material`) is of, where it is of a mesh written from
    /// arrays.
    pub fn arrays_of(&self, key: &str) -> Option<String> {
        let (entry, _) = key.rsplit_once('.')?;
        self.keys
            .iter()
            .find(|(_, k)| k == entry)
            .map(|(_, k)| k.clone())
    }

    /// The meshes written, as `cache` takes them.
    pub fn cache_meshes(&mut self, cache: &glint::scene::MeshCache) {
        for (path, arrays) in self.meshes.drain(..) {
            cache.insert_arrays(&path, arrays);
        }
    }

    fn path(&mut self, extension: &str, key: &str) -> PyResult<PathBuf> {
        if self.dir.is_none() {
            let dir = Arc::new(
                tempfile::Builder::new()
                    .prefix("glint-arrays-")
                    .tempdir()
                    .map_err(errors::other)?,
            );
            LIVE.lock()
                .unwrap_or_else(|p| p.into_inner())
                .push(Arc::downgrade(&dir));
            self.dir = Some(dir);
        }
        self.written += 1;
        let dir = self.dir.as_ref().expect("made above");
        let path = dir.path().join(format!("{}.{extension}", self.written));
        self.keys.push((path.clone(), key.to_owned()));
        Ok(path)
    }

    /// The OBJ file of the mesh row `row` (at key path `at`), written.
    pub fn mesh(&mut self, row: &Bound<'_, PyDict>, at: &str) -> PyResult<String> {
        let get = |k: &str| row.get_item(k);
        let vertices = get("vertices")?.ok_or_else(|| bad(at, "has faces but no vertices"))?;
        let faces = get("faces")?.ok_or_else(|| bad(at, "has vertices but no faces"))?;
        let vertices = rows(&vertices, 3, &format!("{at}.vertices"))?;
        let n = vertices.len() / 3;
        let faces_at = format!("{at}.faces");
        // Read as numbers and held to whole ones: numpy's cast to integers
        // would quietly take 0.5 as vertex 0.
        let faces = rows(&faces, 3, &faces_at)?;
        if let Some(x) = faces.iter().find(|x| x.fract() != 0.0) {
            return Err(bad(
                &faces_at,
                format!("holds {x}: a vertex index is a whole number"),
            ));
        }
        if faces.is_empty() {
            return Err(bad(&faces_at, "is empty: a mesh has at least one face"));
        }
        let faces: Vec<i64> = faces.iter().map(|&x| x as i64).collect();
        if let Some(i) = faces.iter().find(|&&i| i < 0 || i as u64 >= n as u64) {
            return Err(bad(
                &faces_at,
                format!(
                    "vertex index {i} is outside the {n} vertices (0 to {})",
                    n.max(1) - 1
                ),
            ));
        }
        let per_vertex = |key: &str, width: usize| -> PyResult<Option<Vec<f64>>> {
            let Some(v) = get(key)? else { return Ok(None) };
            let p = format!("{at}.{key}");
            let values = rows(&v, width, &p)?;
            if values.len() / width != n {
                return Err(bad(
                    &p,
                    format!(
                        "has {} rows; it must have one a vertex ({n})",
                        values.len() / width
                    ),
                ));
            }
            Ok(Some(values))
        };
        let normals = per_vertex("normals", 3)?;
        let uvs = per_vertex("uvs", 2)?;

        let mut text = String::with_capacity(40 * (n + faces.len()));
        for v in vertices.chunks_exact(3) {
            text.push('v');
            v.iter().for_each(|&x| number(&mut text, x));
            text.push('\n');
        }
        for v in normals.iter().flat_map(|a| a.chunks_exact(3)) {
            text.push_str("vn");
            v.iter().for_each(|&x| number(&mut text, x));
            text.push('\n');
        }
        for v in uvs.iter().flat_map(|a| a.chunks_exact(2)) {
            text.push_str("vt");
            v.iter().for_each(|&x| number(&mut text, x));
            text.push('\n');
        }
        for f in faces.chunks_exact(3) {
            text.push('f');
            for &i in f {
                let i = i + 1;
                let _ = match (uvs.is_some(), normals.is_some()) {
                    (false, false) => write!(text, " {i}"),
                    (true, false) => write!(text, " {i}/{i}"),
                    (false, true) => write!(text, " {i}//{i}"),
                    (true, true) => write!(text, " {i}/{i}/{i}"),
                };
            }
            text.push('\n');
        }
        if get("file")?.is_some() {
            return Err(bad(
                at,
                "gives both a file and arrays (vertices, faces): give one",
            ));
        }
        let path = self.path("obj", at)?;
        std::fs::write(&path, text).map_err(errors::other)?;
        let arrays = MeshArrays {
            positions: vertices,
            faces: faces.iter().map(|&i| i as u32).collect(),
            normals,
            uvs,
        };
        self.meshes.push((path.clone(), arrays));
        Ok(path.display().to_string())
    }

    /// The PFM file of the image array `v` (at key path `at`), written:
    /// floats as linear values, uint8 and uint16 as sRGB levels decoded
    /// as a PNG's are (docs/scene-format.md, Colour).
    pub fn image(&mut self, v: &Bound<'_, PyAny>, at: &str) -> PyResult<String> {
        let dtype = v.getattr("dtype")?.getattr("name")?.extract::<String>()?;
        let top = match dtype.as_str() {
            "uint8" => Some(255.0),
            "uint16" => Some(65535.0),
            d if d.starts_with("float") => None,
            // Levels of 200 in an int16 array were texels of 200.0.
            other => {
                return Err(bad(
                    at,
                    format!(
                        "is an array of {}: an image is floats (linear values) or uint8 or uint16 (sRGB levels)",
                        glint::printable::text(other)
                    ),
                ))
            }
        };
        let a = as_array(v, "float64").map_err(|_| bad(at, "is not an array of numbers"))?;
        let a: PyReadonlyArray3<'_, f64> = a
            .extract()
            .map_err(|_| bad(at, "must be an image of shape (height, width, 3)"))?;
        let (h, w, c) = (a.shape()[0], a.shape()[1], a.shape()[2]);
        if c != 3 || h == 0 || w == 0 {
            return Err(bad(
                at,
                format!(
                    "has shape {}; an image is (height, width, 3)",
                    shape(a.shape())
                ),
            ));
        }
        let side = |s: usize| u32::try_from(s).map_err(|_| bad(at, "is too large"));
        let (w32, h32) = (side(w)?, side(h)?);
        let values = a.as_slice()?;
        // Said of the array: the file it is written as is not the user's.
        if let Some(x) = values.iter().find(|x| !x.is_finite() || **x < 0.0) {
            return Err(bad(
                at,
                format!("holds {x}: every value must be finite and >= 0"),
            ));
        }
        let pixels = values
            .chunks_exact(3)
            .map(|p| {
                p.iter()
                    .map(|&x| match top {
                        // As a PNG's levels are read: level / top in f32.
                        Some(top) => glint::raster::srgb_decode_level(x as f32 / top as f32),
                        None => x as f32,
                    })
                    .collect::<Vec<f32>>()
                    .try_into()
                    .expect("three channels")
            })
            .collect();
        let image = glint::raster::Image::new(w32, h32, pixels);
        let path = self.path("pfm", at)?;
        glint::raster::io::write(&path, &image, false).map_err(errors::image)?;
        Ok(path.display().to_string())
    }
}
