//! `glint.load`, `glint.loads`, `glint.Scene.from_dict` and the scene they
//! return.

use std::path::{Path, PathBuf};

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};

use glint::scene::{self as lib, Overrides, SceneError as LibSceneError};

use crate::errors::{self, guard};

/// A scene read and checked: what `glint.render` and `Renderer.prepare` take.
#[pyclass(module = "glint", name = "Scene", frozen)]
pub struct Scene {
    pub inner: lib::Scene,
    /// Where it was read from, for its repr: a path, `<string>` or `<dict>`.
    pub source: String,
}

fn overrides(
    width: Option<u32>,
    height: Option<u32>,
    samples: Option<u32>,
    max_depth: Option<u32>,
) -> Overrides {
    Overrides {
        width,
        height,
        samples,
        max_depth,
    }
}

#[pyfunction]
#[pyo3(signature = (path, width=None, height=None, samples=None, max_depth=None))]
pub fn load(
    py: Python<'_>,
    path: PathBuf,
    width: Option<u32>,
    height: Option<u32>,
    samples: Option<u32>,
    max_depth: Option<u32>,
) -> PyResult<Scene> {
    let o = overrides(width, height, samples, max_depth);
    guard(|| {
        let scene = py.detach(|| {
            if is_obj(&path) {
                obj_scene(&path, &o)
            } else {
                lib::Scene::load(&path, &o)
            }
        });
        let scene = if is_obj(&path) {
            scene.map_err(|e| obj_error(&path, e))?
        } else {
            scene.map_err(errors::scene)?
        };
        Ok(Scene {
            inner: scene,
            source: path.display().to_string(),
        })
    })
}

/// The tables of the scene file `obj_scene` writes around a mesh.
const MADE_AROUND_A_MESH: &[&str] = &["image", "render", "camera", "materials", "meshes", "lights"];

/// An error of an OBJ file loaded as a scene, said of the OBJ: one found
/// in the OBJ keeps its line; one the scene glint made around the mesh
/// gives names no line of that scene, which the caller never sees (issue
/// 57: errors at lines 20 or 25 of a 3-line OBJ, a light glint placed
/// blamed).
fn obj_error(path: &Path, e: LibSceneError) -> PyErr {
    match e {
        LibSceneError::Invalid { key, message, .. }
            if MADE_AROUND_A_MESH
                .iter()
                .any(|t| key.split(['.', '[']).next() == Some(*t)) =>
        {
            let named = format!("{}: ", glint::printable::path(path));
            let what = if key.starts_with("meshes") {
                message.strip_prefix(&named).unwrap_or(&message).to_owned()
            } else {
                format!(
                    "the view glint makes of the mesh cannot be placed ({}: {message})",
                    glint::printable::text(&key)
                )
            };
            errors::scene_at(
                format!(
                    "{}: {}",
                    glint::printable::path(path),
                    glint::printable::one_line(&what)
                ),
                Some(path.display().to_string()),
                None,
                None,
            )
        }
        e => errors::scene(e),
    }
}

#[pyfunction]
#[pyo3(signature = (text, format="toml", width=None, height=None, samples=None, max_depth=None))]
pub fn loads(
    text: &str,
    format: &str,
    width: Option<u32>,
    height: Option<u32>,
    samples: Option<u32>,
    max_depth: Option<u32>,
) -> PyResult<Scene> {
    let o = overrides(width, height, samples, max_depth);
    guard(|| {
        // Relative file names in the text (meshes, textures) are of the
        // working directory.
        let scene = match format {
            "toml" => lib::parse(text, Path::new("<string>"), &o),
            "nff" => lib::parse_nff(text, Path::new("<string>.nff"), &o),
            other => {
                return Err(PyValueError::new_err(format!(
                    "format {other:?}: glint reads \"toml\" and \"nff\" text"
                )))
            }
        };
        Ok(Scene {
            inner: scene.map_err(errors::scene)?,
            source: "<string>".to_owned(),
        })
    })
}

/// How deep a scene's dict may nest: a scene file's tables go 3 deep; past
/// this a dict or list holds itself, or was built to crash the reader
/// (issue 57: 10,000 levels overflowed the stack, SIGSEGV).
const MAX_NESTING: usize = 64;

/// A Python value as TOML text, appended to `out` (a dict's entries as
/// inline tables): written as it is walked, with no tree of values beside
/// the text (issue 57: 200,000 spheres took 630 MB as `toml::Value`s, 40
/// MB as text). `at` is its key path, for the error.
fn to_toml(v: &Bound<'_, PyAny>, at: &str, depth: usize, out: &mut String) -> PyResult<()> {
    let shown = || {
        if at.is_empty() {
            "the scene".to_owned()
        } else {
            glint::printable::text(at)
        }
    };
    let named = |what: &str| {
        PyTypeError::new_err(format!(
            "{}: {what} has no TOML form (numbers, strings, booleans, lists and dicts do)",
            shown()
        ))
    };
    if depth > MAX_NESTING {
        return Err(PyValueError::new_err(format!(
            "{}: nested more than {MAX_NESTING} deep (a dict or list that holds itself?)",
            shown()
        )));
    }
    if v.is_none() {
        return Err(named("None"));
    }
    if let Ok(b) = v.cast::<pyo3::types::PyBool>() {
        out.push_str(if b.is_true() { "true" } else { "false" });
        return Ok(());
    }
    if let Ok(d) = v.cast::<PyDict>() {
        out.push('{');
        for (n, (k, item)) in d.iter().enumerate() {
            let (k, path) = key_of(&k, at, &named)?;
            if n > 0 {
                out.push_str(", ");
            }
            toml_key(&k, out);
            out.push_str(" = ");
            to_toml(&item, &path, depth + 1, out)?;
        }
        out.push('}');
        return Ok(());
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        out.push('[');
        for (i, item) in v.try_iter()?.enumerate() {
            if i > 0 {
                out.push_str(", ");
            }
            to_toml(&item?, &format!("{at}[{i}]"), depth + 1, out)?;
        }
        out.push(']');
        return Ok(());
    }
    if let Ok(s) = v.extract::<String>() {
        quoted(&s, out);
        return Ok(());
    }
    // A numpy array or scalar: its plain Python form.
    if v.hasattr("tolist")? && !v.is_instance_of::<pyo3::types::PyFloat>() {
        return to_toml(&v.call_method0("tolist")?, at, depth + 1, out);
    }
    if let Ok(i) = v.extract::<i64>() {
        out.push_str(&i.to_string());
        return Ok(());
    }
    if let Ok(f) = v.extract::<f64>() {
        out.push_str(&toml::Value::Float(f).to_string());
        return Ok(());
    }
    Err(named(&format!("a {}", v.get_type().name()?)))
}

/// A dict's key as a string, and its key path under `at`.
fn key_of(
    k: &Bound<'_, PyAny>,
    at: &str,
    named: &dyn Fn(&str) -> PyErr,
) -> PyResult<(String, String)> {
    let k: String = k.extract().map_err(|_| {
        named(&format!(
            "the key {}",
            k.repr().map_or_else(|_| "?".into(), |r| r.to_string())
        ))
    })?;
    let path = if at.is_empty() {
        k.clone()
    } else {
        format!("{at}.{k}")
    };
    Ok((k, path))
}

/// The scene's dict as a TOML file reads: a table's plain values first,
/// then a `[table]` for each dict in it and a `[[table]]` for each list of
/// dicts (the primitives and lights), their entries a line each, nested
/// dicts as sections of their own. glint's parser reads a file of this
/// shape in about the text's size; one with inline tables took 10 times
/// that (issue 57: 200,000 spheres took 430 MB with one `m = {...}`).
fn top_level(d: &Bound<'_, PyDict>, out: &mut String) -> PyResult<()> {
    section(d, &[], "", 0, out)
}

/// Whether `v` is a non-empty list of dicts: an array of tables.
fn is_rows(v: &Bound<'_, PyAny>) -> bool {
    v.cast::<PyList>()
        .is_ok_and(|l| !l.is_empty() && l.iter().all(|i| i.cast::<PyDict>().is_ok()))
}

/// The entries of table `d`, whose header is `keys` (none: the top), at
/// key path `at`, `depth` tables down.
fn section(
    d: &Bound<'_, PyDict>,
    keys: &[String],
    at: &str,
    depth: usize,
    out: &mut String,
) -> PyResult<()> {
    let named = |what: &str| {
        PyTypeError::new_err(format!(
            "{}: {what} has no TOML form (numbers, strings, booleans, lists and dicts do)",
            if at.is_empty() {
                "the scene".to_owned()
            } else {
                glint::printable::text(at)
            }
        ))
    };
    if depth > MAX_NESTING {
        return Err(PyValueError::new_err(format!(
            "{}: nested more than {MAX_NESTING} deep (a dict or list that holds itself?)",
            glint::printable::text(at)
        )));
    }
    let mut later = Vec::new();
    for (k, item) in d.iter() {
        let (name, path) = key_of(&k, at, &named)?;
        if item.cast::<PyDict>().is_ok() || is_rows(&item) {
            later.push((name, path, item));
        } else {
            toml_key(&name, out);
            out.push_str(" = ");
            to_toml(&item, &path, depth + 1, out)?;
            out.push('\n');
        }
    }
    let header = |out: &mut String, keys: &[String], rows: bool| {
        out.push_str(if rows { "\n[[" } else { "\n[" });
        for (n, k) in keys.iter().enumerate() {
            if n > 0 {
                out.push('.');
            }
            toml_key(k, out);
        }
        out.push_str(if rows { "]]\n" } else { "]\n" });
    };
    for (name, path, item) in later {
        let mut keys = keys.to_vec();
        keys.push(name);
        if let Ok(table) = item.cast::<PyDict>() {
            // A table of tables alone takes no header of its own: its
            // sections define it, and glint's parser reads a table named
            // both ways (`[materials]`, then `[materials.m]`) 10 times
            // slower.
            let plain = table
                .iter()
                .any(|(_, v)| v.cast::<PyDict>().is_err() && !is_rows(&v));
            if plain || table.is_empty() {
                header(out, &keys, false);
            }
            section(table, &keys, &path, depth + 1, out)?;
        } else {
            for (i, row) in item.try_iter()?.enumerate() {
                let row = row?;
                header(out, &keys, true);
                let row = row.cast::<PyDict>().map_err(|_| named("a row"))?;
                // A row's own dicts go inline: a section under a row of an
                // array would need its header after every row.
                for (k, v) in row.iter() {
                    let (k, p) = key_of(&k, &format!("{path}[{i}]"), &named)?;
                    toml_key(&k, out);
                    out.push_str(" = ");
                    to_toml(&v, &p, depth + 2, out)?;
                    out.push('\n');
                }
            }
        }
    }
    Ok(())
}

/// `k` as a TOML key: bare where TOML allows one (a quoted key costs the
/// parser more: each keeps its own text), else quoted.
fn toml_key(k: &str, out: &mut String) {
    if !k.is_empty()
        && k.chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    {
        out.push_str(k);
    } else {
        quoted(k, out);
    }
}

/// `s` as a TOML basic string on one line (inside an inline table a
/// multi-line string may not stand).
fn quoted(s: &str, out: &mut String) {
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if c.is_control() => out.push_str(&format!("\\u{:04X}", u32::from(c))),
            c => out.push(c),
        }
    }
    out.push('"');
}

fn is_obj(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("obj"))
}

/// An OBJ file as a scene: its mesh, with its MTL materials where it names
/// an `mtllib` (else one grey), seen from the front of its bounds by a
/// 40° look-at camera, lit by a light at the eye and one from above
/// (docs/python.md, Loading an OBJ file).
fn obj_scene(path: &Path, o: &Overrides) -> Result<lib::Scene, LibSceneError> {
    let text = glint::input::read_text(path, glint::input::Kind::Mesh).map_err(|cause| {
        LibSceneError::Read {
            path: path.to_owned(),
            cause,
        }
    })?;
    let has_mtl = text.lines().any(|l| l.trim_start().starts_with("mtllib"));
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_owned());
    let scene_toml = |eye: [f64; 3], look_at: [f64; 3]| {
        let file = toml::Value::String(absolute.display().to_string());
        let material = if has_mtl {
            String::new()
        } else {
            "material = \"grey\"\n".to_owned()
        };
        format!(
            "[image]\nwidth = 640\nheight = 480\n\n[render]\nbackground = [0.05, 0.05, 0.08]\n\n\
             [camera]\neye = {eye:?}\nlook_at = {look_at:?}\nvfov = 40.0\n\n\
             [materials.grey]\nambient = [0.1, 0.1, 0.1]\ndiffuse = [0.7, 0.7, 0.7]\n\
             specular = [0.3, 0.3, 0.3]\nshininess = 30.0\n\n\
             [[meshes]]\nfile = {file}\n{material}\n\
             [[lights]]\ntype = \"point\"\nposition = {eye:?}\ndiffuse = [0.8, 0.8, 0.8]\nspecular = [0.5, 0.5, 0.5]\n\n\
             [[lights]]\ntype = \"directional\"\ndirection = [0.3, -1.0, -0.4]\ndiffuse = [0.3, 0.3, 0.3]\n"
        )
    };
    // Read once to find the bounds, then again with the camera they give.
    let first = lib::parse(
        &scene_toml([0.0, 0.0, 1.0], [0.0; 3]),
        path,
        &Overrides::default(),
    )?;
    let (mut lo, mut hi) = (
        glam::DVec3::splat(f64::INFINITY),
        glam::DVec3::splat(f64::NEG_INFINITY),
    );
    for t in &first.prims.triangles {
        for v in t.vertices {
            lo = lo.min(v);
            hi = hi.max(v);
        }
    }
    if !lo.is_finite() {
        return Err(LibSceneError::Invalid {
            file: path.to_owned(),
            line: 1,
            column: 1,
            key: "f".to_owned(),
            message: "the OBJ file has no face with area: nothing to see".to_owned(),
        });
    }
    let center = (lo + hi) / 2.0;
    let radius = ((hi - lo).length() / 2.0).max(1e-9);
    // Far enough that the bounding sphere fills 40° vertically.
    let distance = radius / (20f64.to_radians()).sin();
    let eye = center + glam::DVec3::new(0.35, 0.25, 1.0).normalize() * distance;
    lib::parse(&scene_toml(eye.to_array(), center.to_array()), path, o)
}

impl Scene {
    /// The primitives by kind, in the kinds' table's order.
    fn kind_counts(&self) -> Vec<(&'static str, usize)> {
        lib::object_arrays()
            .iter()
            .copied()
            .zip(self.inner.prims.counts())
            .collect()
    }
}

#[pymethods]
impl Scene {
    /// A scene from a dict shaped like the TOML file (as `tomllib.load`
    /// returns it), so that a test can build and perturb scenes in code.
    /// An error names the key (`spheres[0].radius`); its `.line` and
    /// `.column` are None, as a dict has none.
    #[staticmethod]
    #[pyo3(signature = (d, width=None, height=None, samples=None, max_depth=None))]
    fn from_dict(
        d: &Bound<'_, PyDict>,
        width: Option<u32>,
        height: Option<u32>,
        samples: Option<u32>,
        max_depth: Option<u32>,
    ) -> PyResult<Scene> {
        // The dict is written out as TOML and read as a file is.
        let o = overrides(width, height, samples, max_depth);
        guard(|| {
            let mut text = String::new();
            top_level(d, &mut text)?;
            let scene = lib::parse(&text, Path::new("<dict>"), &o).map_err(|e| match e {
                // The line and column are of the TOML the dict was written
                // as, which the caller never sees: the key says where.
                LibSceneError::Invalid { key, message, .. } => errors::scene_at(
                    format!(
                        "<dict>: {}: {}",
                        glint::printable::text(&key),
                        glint::printable::one_line(&message)
                    ),
                    Some("<dict>".into()),
                    None,
                    None,
                ),
                e => errors::scene(e),
            })?;
            Ok(Scene {
                inner: scene,
                source: "<dict>".to_owned(),
            })
        })
    }

    /// Width of the image in pixels.
    #[getter]
    fn width(&self) -> u32 {
        self.inner.width
    }
    /// Height of the image in pixels.
    #[getter]
    fn height(&self) -> u32 {
        self.inner.height
    }
    /// Samples a side of each pixel.
    #[getter]
    fn samples(&self) -> u32 {
        self.inner.samples
    }
    /// The ray tree's depth.
    #[getter]
    fn max_depth(&self) -> u32 {
        self.inner.max_depth
    }
    /// The primitives by kind: `{"spheres": 3, "planes": 1, ...}`.
    #[getter]
    fn counts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (kind, n) in self.kind_counts() {
            d.set_item(kind, n)?;
        }
        Ok(d)
    }
    /// The lights' types, in the file's order.
    #[getter]
    fn lights(&self) -> Vec<&'static str> {
        self.inner
            .lights
            .iter()
            .map(|l| l.kind.info().name)
            .collect()
    }
    /// Where the scene was read from: a path, `<string>` or `<dict>`.
    #[getter]
    fn source(&self) -> &str {
        &self.source
    }

    fn __repr__(&self) -> String {
        let counts: Vec<String> = self
            .kind_counts()
            .into_iter()
            .filter(|(_, n)| *n > 0)
            .map(|(k, n)| format!("{k}={n}"))
            .collect();
        format!(
            "<glint.Scene {:?} {}x{}, {}, max_depth {}, {}, lights [{}]>",
            self.source,
            self.inner.width,
            self.inner.height,
            self.inner.sampling_summary(),
            self.inner.max_depth,
            if counts.is_empty() {
                "no primitives".to_owned()
            } else {
                counts.join(", ")
            },
            self.lights().join(", ")
        )
    }
}
