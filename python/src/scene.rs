//! `glint.load`, `glint.loads`, `glint.Scene.from_dict` and the scene they
//! return.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, RwLock};

use pyo3::exceptions::{PyKeyError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use glint::scene::{self as lib, Overrides, SceneError as LibSceneError};

use crate::arrays::ArrayFiles;
use crate::dict::{self, to_python, top_level};
use crate::document::{Document, Place, Root};
use crate::errors::{self, guard};
use crate::keywords;
use crate::params::{self, Key};

/// A scene read and checked: what `glint.render` and `Renderer.prepare`
/// take. Its values change through `params` (`set_params`), each change a
/// new generation of the scene, which a prepared scene takes in place.
#[pyclass(module = "glint", name = "Scene", frozen)]
pub struct Scene {
    now: RwLock<Now>,
    /// Where it was read from, for its repr: a path, `<string>` or `<dict>`.
    pub source: String,
    /// The path its text is read as (whose folder its relative file names
    /// are of), when `params` reads it again.
    read_as: PathBuf,
    /// The folder its relative file names (meshes, textures) are of.
    pub base: PathBuf,
    /// The files a dict's arrays were written as (meshes, images), which
    /// its `to_dict` names: kept as long as the scene.
    pub _arrays: std::sync::Mutex<Vec<std::sync::Arc<tempfile::TempDir>>>,
    /// Its meshes' OBJ files, kept once `params` has read it again: a
    /// change of a value reads the scene file, not the meshes.
    meshes: lib::MeshCache,
    /// Held while a change is made.
    setting: std::sync::Mutex<()>,
    /// The scenes `render(width=, height=, samples=, max_depth=)` made of
    /// it, by their keywords, with the generation of this one each shows.
    derived: std::sync::Mutex<Vec<(Overrides, u64, Py<Scene>)>>,
    /// Which scene this is, among all made in the process (never reused):
    /// what a renderer keeps its last prepared scene by.
    pub id: u64,
}

/// A scene as its values are now.
struct Now {
    scene: Arc<lib::Scene>,
    /// The scene file's text (an OBJ's: the scene glint made around it),
    /// which `to_dict` gives back as a dict.
    file: FileText,
    /// How many times its values were changed.
    generation: u64,
    /// The keywords it was read with, which `to_dict` writes in: none
    /// once `params` has changed it (they are in its text then).
    overrides: Overrides,
}

/// The next scene's `id`.
static NEXT_ID: AtomicU64 = AtomicU64::new(0);

impl Scene {
    /// A scene read from `file` (read as the path `read_as`), its meshes
    /// those `meshes` keeps (`MeshCache::default()`: none yet).
    #[allow(clippy::too_many_arguments)]
    fn new(
        scene: lib::Scene,
        file: FileText,
        source: String,
        read_as: PathBuf,
        base: PathBuf,
        overrides: Overrides,
        arrays: Vec<std::sync::Arc<tempfile::TempDir>>,
        meshes: lib::MeshCache,
    ) -> Self {
        Scene {
            now: RwLock::new(Now {
                scene: Arc::new(scene),
                file,
                generation: 0,
                overrides,
            }),
            source,
            read_as,
            base,
            _arrays: std::sync::Mutex::new(arrays),
            meshes,
            setting: std::sync::Mutex::new(()),
            derived: std::sync::Mutex::new(Vec::new()),
            id: NEXT_ID.fetch_add(1, Ordering::Relaxed),
        }
    }

    fn now(&self) -> std::sync::RwLockReadGuard<'_, Now> {
        // A change is made whole before it is stored: nothing half-done.
        self.now.read().unwrap_or_else(|p| p.into_inner())
    }

    /// The scene as it is now, and its generation.
    pub fn current(&self) -> (Arc<lib::Scene>, u64) {
        let now = self.now();
        (now.scene.clone(), now.generation)
    }

    /// The scene as it is now.
    pub fn scene(&self) -> Arc<lib::Scene> {
        self.now().scene.clone()
    }

    /// The scene file's text as TOML (an NFF's converted), and the
    /// keywords it was read with, which its head's tables take
    /// ([`with_overrides`]).
    fn text(&self) -> PyResult<(String, Overrides)> {
        let now = self.now();
        Ok((now.file.toml()?.into_owned(), now.overrides))
    }
}

/// `table` (a scene file's head) with the keywords `o` written in: what
/// `to_dict` gives and `params` reads.
fn with_overrides(mut table: toml::Table, o: &Overrides) -> toml::Table {
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
    table
}

/// Whether any keyword was given.
fn any(o: &Overrides) -> bool {
    o.width.is_some() || o.height.is_some() || o.samples.is_some() || o.max_depth.is_some()
}

/// Takes `m`, waiting for it with the GIL released: its holder may be
/// waiting for the GIL (a change of `params` reads the scene without it),
/// and two threads changing one scene's `params` deadlocked the
/// interpreter when the second waited with the GIL held. A signal
/// (Ctrl-C) ends the wait.
fn lock_without_the_gil<'m, T>(
    py: Python<'_>,
    m: &'m std::sync::Mutex<T>,
) -> PyResult<std::sync::MutexGuard<'m, T>> {
    loop {
        match m.try_lock() {
            Ok(held) => return Ok(held),
            // A change that panicked stored nothing half-done.
            Err(std::sync::TryLockError::Poisoned(p)) => return Ok(p.into_inner()),
            Err(std::sync::TryLockError::WouldBlock) => {
                crate::gil::detach(py, || {
                    std::thread::sleep(std::time::Duration::from_micros(200))
                });
                py.check_signals()?;
            }
        }
    }
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

/// `path` made absolute against the working directory now (as given
/// where that cannot be read).
fn absolute(path: &Path) -> PathBuf {
    std::path::absolute(path).unwrap_or_else(|_| path.to_owned())
}

/// The folder that relative names in the file at `path` are of.
fn folder_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_owned(),
        _ => PathBuf::from("."),
    }
}

#[pyfunction]
#[pyo3(signature = (path, width=None, height=None, samples=None, max_depth=None))]
pub fn load(
    py: Python<'_>,
    path: PathBuf,
    width: Option<Bound<'_, PyAny>>,
    height: Option<Bound<'_, PyAny>>,
    samples: Option<Bound<'_, PyAny>>,
    max_depth: Option<Bound<'_, PyAny>>,
) -> PyResult<Scene> {
    let o = keywords::overrides(
        width.as_ref(),
        height.as_ref(),
        samples.as_ref(),
        max_depth.as_ref(),
    )?;
    guard(|| {
        let scene = crate::gil::detach(py, || {
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
        // Absolute now: a later `params` change reads it again from here,
        // whatever the working directory is by then (it read another
        // folder's mesh after `os.chdir`).
        let read_as = absolute(&path);
        let base = folder_of(&read_as);
        Ok(Scene::new(
            scene,
            file,
            path.display().to_string(),
            read_as,
            base,
            o,
            Vec::new(),
            lib::MeshCache::default(),
        ))
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
    width: Option<Bound<'_, PyAny>>,
    height: Option<Bound<'_, PyAny>>,
    samples: Option<Bound<'_, PyAny>>,
    max_depth: Option<Bound<'_, PyAny>>,
) -> PyResult<Scene> {
    let o = keywords::overrides(
        width.as_ref(),
        height.as_ref(),
        samples.as_ref(),
        max_depth.as_ref(),
    )?;
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
        let base = absolute(Path::new("."));
        Ok(Scene::new(
            scene.map_err(errors::scene)?,
            file,
            "<string>".to_owned(),
            base.join("<string>"),
            base,
            o,
            Vec::new(),
            lib::MeshCache::default(),
        ))
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
    let text = glint::input::read_text(path, glint::input::ReadAs::Mesh).map_err(|cause| {
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

/// An error of a scene made from a dict, its arrays' files named by the
/// arrays' keys (`meshes[0]`), and a mesh of arrays (which has no MTL
/// file) told to take a material.
fn arrays_named(e: LibSceneError, files: &ArrayFiles) -> LibSceneError {
    let LibSceneError::Invalid {
        file,
        line,
        column,
        key,
        message,
    } = e
    else {
        return e;
    };
    let Some(arrays) = files.arrays_of(&key) else {
        return LibSceneError::Invalid {
            file,
            line,
            column,
            key,
            message: files.said(&message),
        };
    };
    // The OBJ glint wrote has one unnamed object and no MTL file.
    let message = if message.contains("(usemtl)") {
        format!("{arrays}: the mesh has no material: add material = \"NAME\"")
    } else {
        files
            .said(&message)
            .replace("object \"unnamed_object\", ", "")
            .replace("object \"unnamed_object\" ", "")
    };
    LibSceneError::Invalid {
        file,
        line,
        column,
        key: arrays,
        message,
    }
}

/// An error of a scene's TOML that the caller never saw (a dict's, or a
/// scene read again with its values changed): said by its key, without
/// the line and column of that text.
fn by_key(e: LibSceneError, source: &str) -> PyErr {
    match e {
        LibSceneError::Invalid { key, message, .. } => errors::scene_at(
            format!(
                "{source}: {}: {}",
                glint::printable::text(&key),
                glint::printable::one_line(&message)
            ),
            Some(source.into()),
            None,
            None,
        ),
        e => errors::scene(e),
    }
}

impl Scene {
    /// The primitives by kind, in the kinds' table's order.
    fn kind_counts(&self) -> Vec<(&'static str, usize)> {
        lib::object_arrays()
            .iter()
            .copied()
            .zip(self.scene().prims.counts())
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
        width: Option<Bound<'_, PyAny>>,
        height: Option<Bound<'_, PyAny>>,
        samples: Option<Bound<'_, PyAny>>,
        max_depth: Option<Bound<'_, PyAny>>,
    ) -> PyResult<Scene> {
        // The dict is written out as TOML and read as a file in `base` is.
        let o = keywords::overrides(
            width.as_ref(),
            height.as_ref(),
            samples.as_ref(),
            max_depth.as_ref(),
        )?;
        let base = absolute(&base.unwrap_or_else(|| PathBuf::from(".")));
        guard(|| {
            let mut text = String::new();
            let mut files = ArrayFiles::default();
            top_level(d, &mut text, &mut files)?;
            let read_as = base.join("<dict>");
            // Its numpy meshes are taken as arrays, not parsed back.
            let meshes = lib::MeshCache::default();
            files.cache_meshes(&meshes);
            let scene = lib::parse_cached(&text, &read_as, &o, Some(&meshes))
                .map_err(|e| by_key(arrays_named(e, &files), "<dict>"))?;
            // Another scene's arrays that this one names (a copy from its
            // `to_dict`), and its own.
            let mut kept = crate::arrays::named_in(&text);
            kept.extend(files.into_dir());
            Ok(Scene::new(
                scene,
                FileText::Toml(text),
                "<dict>".to_owned(),
                read_as,
                base,
                o,
                kept,
                meshes,
            ))
        })
    }

    /// The scene as a dict shaped like its TOML file, with the keywords it
    /// was read with written in: `Scene.from_dict(s.to_dict(),
    /// base=s.base)` renders the same bits. An NFF scene comes as `glint
    /// convert` writes it, an OBJ with the view glint made around it.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        guard(|| {
            let (text, o) = self.text()?;
            let doc = Document::new(&text);
            let head = with_overrides(doc.head()?, &o);
            let d = PyDict::new(py);
            for root in doc.roots(&head) {
                match root {
                    Root::Head(k, v) => d.set_item(k, to_python(py, v)?)?,
                    Root::Spheres => {
                        // A block at a time: no document of them all.
                        let spheres = PyList::empty(py);
                        for i in 0..doc.spheres() {
                            if let Some(t) = doc.sphere(i)? {
                                spheres.append(to_python(py, &toml::Value::Table(t))?)?;
                            }
                        }
                        d.set_item(params::SPHERES, spheres)?;
                    }
                }
            }
            Ok(d)
        })
    }

    /// `params`' keys and their values, as a dict: every number and list
    /// of numbers of the scene file but the image's settings and the ray
    /// tree's depth (`params::list`).
    fn _params<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        guard(|| {
            let (text, o) = self.text()?;
            let doc = Document::new(&text);
            let d = PyDict::new(py);
            doc.list(&with_overrides(doc.head()?, &o), &mut |k, v| {
                d.set_item(k, to_python(py, v)?)
            })?;
            Ok(d)
        })
    }

    /// The value at `key`, listed by `params` or not; KeyError where the
    /// scene file has none.
    fn _param<'py>(&self, py: Python<'py>, key: &str) -> PyResult<Bound<'py, PyAny>> {
        guard(|| {
            let (text, o) = self.text()?;
            let doc = Document::new(&text);
            if crate::mesh_params::array_key(key).is_some() {
                let head = with_overrides(doc.head()?, &o);
                return crate::mesh_params::get(py, &head, &self.base, &self.meshes, key);
            }
            let parsed = Key::parse(key)?;
            let value = match doc.place(&parsed) {
                Place::Head => params::get(&with_overrides(doc.head()?, &o), &parsed).cloned(),
                Place::Sphere(i) => doc
                    .sphere(i)?
                    .and_then(|t| params::get_in_sphere(&t, &parsed).cloned()),
                Place::Whole => params::get(&doc.whole()?, &parsed).cloned(),
            };
            match value {
                Some(v) => to_python(py, &v),
                None => Err(PyKeyError::new_err(key.to_owned())),
            }
        })
    }

    /// Sets each key of `items` to its value (None: removes the key) and
    /// reads the scene again, whole, with every check a file gets (its
    /// meshes from the scene's cache of them). On an error (KeyError,
    /// TypeError, SceneError naming the key) nothing has changed.
    /// With `create`, the entries on a key's way that the scene lacks are
    /// made (`params.add`); else such a key is a KeyError.
    #[pyo3(signature = (items, create=false))]
    fn _set_params(&self, py: Python<'_>, items: &Bound<'_, PyDict>, create: bool) -> PyResult<()> {
        guard(|| {
            // One change at a time: each starts from the last one's text.
            let _one = lock_without_the_gil(py, &self.setting)?;
            let (old, o) = self.text()?;
            let mut keys = Vec::with_capacity(items.len());
            for (k, v) in items.iter() {
                let key: String = k.extract().map_err(|_| {
                    PyTypeError::new_err(format!(
                        "params: a key is a string, got {}",
                        k.repr().map_or_else(|_| "?".into(), |r| r.to_string())
                    ))
                })?;
                keys.push((key, v));
            }
            let mut doc = Document::new(&old);
            let parsed = keys
                .iter()
                .map(|(k, _)| Key::parse(k))
                .collect::<PyResult<Vec<_>>>()?;
            if parsed.iter().any(|k| matches!(doc.place(k), Place::Whole)) {
                // A key of the spheres' array itself: the file read as one.
                doc = Document::whole_of(&old);
            }
            // The head's tables, read where a change needs them (and where
            // the keywords the scene was read with are to be written in).
            let mut head = if any(&o) {
                Some(with_overrides(doc.head()?, &o))
            } else {
                None
            };
            let mut changed = BTreeMap::new();
            // A numpy mesh's arrays first: its OBJ file written anew.
            let arrays: Vec<_> = keys
                .iter()
                .filter(|(k, _)| crate::mesh_params::array_key(k).is_some())
                .map(|(k, v)| (k.clone(), v.clone()))
                .collect();
            let mut files = ArrayFiles::default();
            if !arrays.is_empty() {
                let head = match &mut head {
                    Some(h) => h,
                    None => head.insert(doc.head()?),
                };
                crate::mesh_params::set(py, head, &self.base, &self.meshes, &arrays, &mut files)?;
            }
            for ((key, v), parsed) in keys.iter().zip(&parsed) {
                if crate::mesh_params::array_key(key).is_some() {
                    continue;
                }
                let value = if v.is_none() {
                    None
                } else {
                    Some(dict::value(v, key)?)
                };
                match doc.place(parsed) {
                    Place::Sphere(i) => {
                        let sphere = match changed.entry(i) {
                            std::collections::btree_map::Entry::Occupied(e) => e.into_mut(),
                            std::collections::btree_map::Entry::Vacant(e) => {
                                e.insert(doc.sphere(i)?.ok_or_else(|| parsed.no_sphere())?)
                            }
                        };
                        params::set_in_sphere(sphere, parsed, value, create)?;
                    }
                    Place::Head | Place::Whole => {
                        let head = match &mut head {
                            Some(h) => h,
                            None => head.insert(doc.head()?),
                        };
                        params::set(head, parsed, value, create)?;
                    }
                }
            }
            let text = doc.written(head.as_ref(), &changed)?;
            // Only the new text, the scene now and the one read next are
            // kept while it is read.
            drop((changed, head));
            drop(old);
            let scene = crate::gil::detach(py, || {
                lib::parse_cached(
                    &text,
                    &self.read_as,
                    &Overrides::default(),
                    Some(&self.meshes),
                )
            })
            .map_err(|e| by_key(arrays_named(e, &files), &self.source))?;
            // The new files live as long as the scene.
            if let Some(dir) = files.into_dir() {
                self._arrays
                    .lock()
                    .unwrap_or_else(|p| p.into_inner())
                    .push(dir);
            }
            let mut now = self.now.write().unwrap_or_else(|p| p.into_inner());
            now.scene = Arc::new(scene);
            now.file = FileText::Toml(text);
            now.generation += 1;
            now.overrides = Overrides::default();
            Ok(())
        })
    }

    /// The scene as it is now with the keywords in place of its own size,
    /// sampling and depth (`render(scene, samples=...)`), the scene itself
    /// unchanged. Kept by the keywords: the same ones give the same scene
    /// again, which follows this one's changes as a new generation of its
    /// own, so that a renderer updates it in place.
    #[pyo3(signature = (width=None, height=None, samples=None, max_depth=None))]
    fn _overridden(
        slf: &Bound<'_, Self>,
        width: Option<Bound<'_, PyAny>>,
        height: Option<Bound<'_, PyAny>>,
        samples: Option<Bound<'_, PyAny>>,
        max_depth: Option<Bound<'_, PyAny>>,
    ) -> PyResult<Py<Scene>> {
        let py = slf.py();
        let this = slf.get();
        let asked = keywords::overrides(
            width.as_ref(),
            height.as_ref(),
            samples.as_ref(),
            max_depth.as_ref(),
        )?;
        guard(|| {
            let (text, generation, own) = {
                let now = this.now();
                (now.file.toml()?.into_owned(), now.generation, now.overrides)
            };
            let o = Overrides {
                width: asked.width.or(own.width),
                height: asked.height.or(own.height),
                samples: asked.samples.or(own.samples),
                max_depth: asked.max_depth.or(own.max_depth),
            };
            let same = |a: &Overrides| {
                (a.width, a.height, a.samples, a.max_depth)
                    == (o.width, o.height, o.samples, o.max_depth)
            };
            let mut derived = this.derived.lock().unwrap_or_else(|p| p.into_inner());
            if let Some((_, shown, scene)) = derived.iter_mut().find(|(k, _, _)| same(k)) {
                if *shown != generation {
                    let read = lib::parse_cached(&text, &this.read_as, &o, Some(&this.meshes))
                        .map_err(|e| by_key(e, &this.source))?;
                    let mut now = scene.get().now.write().unwrap_or_else(|p| p.into_inner());
                    now.scene = Arc::new(read);
                    now.file = FileText::Toml(text);
                    now.generation += 1;
                    *shown = generation;
                }
                return Ok(scene.clone_ref(py));
            }
            let read = lib::parse_cached(&text, &this.read_as, &o, Some(&this.meshes))
                .map_err(|e| by_key(e, &this.source))?;
            let scene = Py::new(
                py,
                Scene::new(
                    read,
                    FileText::Toml(text),
                    this.source.clone(),
                    this.read_as.clone(),
                    this.base.clone(),
                    o,
                    this._arrays
                        .lock()
                        .unwrap_or_else(|p| p.into_inner())
                        .clone(),
                    lib::MeshCache::default(),
                ),
            )?;
            // A few sizes at a time: a sweep over many keeps the latest.
            if derived.len() >= 4 {
                derived.remove(0);
            }
            derived.push((o, generation, scene.clone_ref(py)));
            Ok(scene)
        })
    }

    /// The scene's values by their keys in the scene file
    /// (`"spheres[0].center"`): a `glint.Params`, a mutable mapping.
    /// Set one and render again; the scene is read again at each change.
    #[getter]
    fn params<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        slf.py().import("glint")?.getattr("Params")?.call1((slf,))
    }

    /// How many times its values were changed through `params`.
    #[getter]
    fn generation(&self) -> u64 {
        self.now().generation
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
        self.scene().width
    }
    /// Height of the image in pixels.
    #[getter]
    fn height(&self) -> u32 {
        self.scene().height
    }
    /// Samples a side of each pixel.
    #[getter]
    fn samples(&self) -> u32 {
        self.scene().samples
    }
    /// The ray tree's depth.
    #[getter]
    fn max_depth(&self) -> u32 {
        self.scene().max_depth
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
        self.scene()
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
        let scene = self.scene();
        format!(
            "<glint.Scene {:?} {}x{}, {}, max_depth {}, {}, lights [{}]>",
            self.source,
            scene.width,
            scene.height,
            scene.sampling_summary(),
            scene.max_depth,
            if counts.is_empty() {
                "no primitives".to_owned()
            } else {
                counts.join(", ")
            },
            self.lights().join(", ")
        )
    }
}
