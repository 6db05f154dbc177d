//! `glint.load`, `glint.loads`, `glint.Scene.from_dict` and the scene they
//! return.

use std::path::{Path, PathBuf};

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use glint::scene::{self as lib, Overrides, SceneError as LibSceneError};

use crate::arrays::ArrayFiles;
use crate::dict::{to_python, top_level};
use crate::errors::{self, guard};

/// A scene read and checked: what `glint.render` and `Renderer.prepare` take.
#[pyclass(module = "glint", name = "Scene", frozen)]
pub struct Scene {
    pub inner: lib::Scene,
    /// Where it was read from, for its repr: a path, `<string>` or `<dict>`.
    pub source: String,
    /// The scene file's text (an OBJ's: the scene glint made around it),
    /// which `to_dict` gives back as a dict.
    pub file: FileText,
    /// The folder its relative file names (meshes, textures) are of.
    pub base: PathBuf,
    /// The keywords it was read with, which `to_dict` writes in.
    pub overrides: Overrides,
    /// The files a dict's arrays were written as (meshes, images), which
    /// its `to_dict` names: kept as long as the scene.
    pub _arrays: Option<tempfile::TempDir>,
}

/// A scene file's text as it was given: TOML, or NFF (converted to TOML
/// only when `to_dict` asks, as `glint convert` writes it).
pub enum FileText {
    Toml(String),
    Nff(String),
}

impl FileText {
    /// The text as TOML: an NFF's as `glint convert` writes it.
    fn toml(&self) -> PyResult<std::borrow::Cow<'_, str>> {
        match self {
            FileText::Toml(t) => Ok(t.into()),
            FileText::Nff(t) => {
                let read = lib::nff::read(t, Path::new("<nff>")).map_err(errors::scene)?;
                Ok(read.scene.to_toml().map_err(errors::other)?.into())
            }
        }
    }
}

/// The folder that relative names in the file at `path` are of.
fn folder_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_owned(),
        _ => PathBuf::from("."),
    }
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
                let (scene, text) = lib::Scene::load_with_text(&path, &o)?;
                let file = if lib::is_nff(&path) {
                    FileText::Nff(text)
                } else {
                    FileText::Toml(text)
                };
                Ok((scene, file))
            }
        });
        let (scene, file) = if is_obj(&path) {
            scene.map_err(|e| obj_error(&path, e))?
        } else {
            scene.map_err(errors::scene)?
        };
        Ok(Scene {
            inner: scene,
            source: path.display().to_string(),
            file,
            base: folder_of(&path),
            overrides: o,
            _arrays: None,
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
        let (scene, file) = match format {
            "toml" => (
                lib::parse(text, Path::new("<string>"), &o),
                FileText::Toml(text.to_owned()),
            ),
            "nff" => (
                lib::parse_nff(text, Path::new("<string>.nff"), &o),
                FileText::Nff(text.to_owned()),
            ),
            other => {
                return Err(PyValueError::new_err(format!(
                    "format {other:?}: glint reads \"toml\" and \"nff\" text"
                )))
            }
        };
        Ok(Scene {
            inner: scene.map_err(errors::scene)?,
            source: "<string>".to_owned(),
            file,
            base: PathBuf::from("."),
            overrides: o,
            _arrays: None,
        })
    })
}

fn is_obj(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("obj"))
}

/// An OBJ file as a scene: its mesh, with its MTL materials where it names
/// an `mtllib` (else one grey), seen from the front of its bounds by a
/// 40° look-at camera, lit by a light at the eye and one from above
/// (docs/python.md, Loading an OBJ file).
fn obj_scene(path: &Path, o: &Overrides) -> Result<(lib::Scene, FileText), LibSceneError> {
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
    let text = scene_toml(eye.to_array(), center.to_array());
    Ok((lib::parse(&text, path, o)?, FileText::Toml(text)))
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
    /// returns it, or `Scene.to_dict`), so that a test can build and
    /// perturb scenes in code. Relative file names (meshes, textures) are
    /// of `base` (default: the working directory). An error names the key
    /// (`spheres[0].radius`); its `.line` and `.column` are None, as a
    /// dict has none.
    #[staticmethod]
    #[pyo3(signature = (d, base=None, width=None, height=None, samples=None, max_depth=None))]
    fn from_dict(
        d: &Bound<'_, PyDict>,
        base: Option<PathBuf>,
        width: Option<u32>,
        height: Option<u32>,
        samples: Option<u32>,
        max_depth: Option<u32>,
    ) -> PyResult<Scene> {
        // The dict is written out as TOML and read as a file in `base` is.
        let o = overrides(width, height, samples, max_depth);
        let base = base.unwrap_or_else(|| PathBuf::from("."));
        guard(|| {
            let mut text = String::new();
            let mut files = ArrayFiles::default();
            top_level(d, &mut text, &mut files)?;
            let scene = lib::parse(&text, &base.join("<dict>"), &o).map_err(|e| match e {
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
                file: FileText::Toml(text),
                base,
                overrides: o,
                _arrays: files.into_dir(),
            })
        })
    }

    /// The scene as a dict shaped like its TOML file, with the keywords it
    /// was read with written in: `Scene.from_dict(s.to_dict(),
    /// base=s.base)` renders the same bits. An NFF scene comes as `glint
    /// convert` writes it, an OBJ with the view glint made around it.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        guard(|| {
            let text = self.file.toml()?;
            let mut table: toml::Table = toml::from_str(&text).map_err(errors::other)?;
            let o = &self.overrides;
            let mut set = |section: &str, key: &str, v: Option<u32>| {
                if let Some(v) = v {
                    let t = table
                        .entry(section)
                        .or_insert_with(|| toml::Value::Table(toml::Table::new()));
                    if let toml::Value::Table(t) = t {
                        t.insert(key.to_owned(), toml::Value::Integer(v.into()));
                    }
                }
            };
            set("image", "width", o.width);
            set("image", "height", o.height);
            set("image", "samples", o.samples);
            set("render", "max_depth", o.max_depth);
            let d = PyDict::new(py);
            for (k, v) in &table {
                d.set_item(k, to_python(py, v)?)?;
            }
            Ok(d)
        })
    }

    /// The folder the scene's relative file names are of: its file's, or
    /// the working directory (`loads`), or `from_dict`'s `base`.
    #[getter]
    fn base(&self) -> String {
        self.base.display().to_string()
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
