//! glint's errors as Python exceptions, all under `glint.Error`; each
//! message is the one line the binary prints for the same error.

use std::panic::{catch_unwind, AssertUnwindSafe};

use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;

use glint::raster::io::ImageIoError;
use glint::scene::SceneError as LibSceneError;

create_exception!(
    glint,
    Error,
    PyException,
    "Any error glint reports; every other is a subclass."
);
create_exception!(glint, SceneError, Error, "A scene that cannot be read or breaks docs/scene-format.md; `.file`, `.line`, `.column` say where (None where unknown).");
create_exception!(glint, ShaderError, Error, "A shader that does not compile; the message is glslang's first `file:line: error:` line and `.log` holds them all.");
create_exception!(
    glint,
    DeviceError,
    Error,
    "No Vulkan device, a device that failed, or a build without the GPU renderer."
);
create_exception!(
    glint,
    ImageError,
    Error,
    "An image that cannot be read or written."
);

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("Error", py.get_type::<Error>())?;
    m.add("SceneError", py.get_type::<SceneError>())?;
    m.add("ShaderError", py.get_type::<ShaderError>())?;
    m.add("DeviceError", py.get_type::<DeviceError>())?;
    m.add("ImageError", py.get_type::<ImageError>())?;
    Ok(())
}

/// Runs `f`, turning a panic into `glint.Error` (with the panic's words)
/// rather than PyO3's `PanicException`, which is not a `glint.Error` and
/// which a test's `except glint.Error` would miss.
pub fn guard<T>(f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    // Once the interpreter is exiting, a call (a daemon thread's) parks
    // here: inside, it could come back for the GIL after finalization
    // began (`gil`).
    if crate::gil::exiting() {
        Python::attach(|py| crate::gil::park(py));
    }
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(payload) => Err(Error::new_err(format!(
            "internal error (a bug in glint; please report it): {}",
            panic_words(&*payload)
        ))),
    }
}

pub fn panic_words(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| (*s).to_owned())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic without words".to_owned())
}

/// The command line's advice in a message, and Python's words for it: a
/// Python user has no `--force` or `--timeout`.
const ADVICE: &[(&str, &str)] = &[
    ("(remove it, or use --force)", "(remove it first)"),
    ("give --sample ", "give sample="),
    ("with --timeout SECONDS", "with Renderer(timeout=SECONDS)"),
    (
        "(--width, --height, --samples)",
        "(width=, height=, samples= of glint.load)",
    ),
    ("--backend cpu", "backend=\"cpu\""),
    ("--max-depth", "max_depth"),
    ("--samples", "samples"),
    ("--width", "width"),
    ("--height", "height"),
];

/// `message` with the command line's advice in Python's words.
pub fn in_python(message: String) -> String {
    ADVICE
        .iter()
        .fold(message, |m, (cli, py)| m.replace(cli, py))
}

/// A `ValueError` saying `message` in Python's words.
pub fn value(message: impl std::fmt::Display) -> PyErr {
    pyo3::exceptions::PyValueError::new_err(in_python(message.to_string()))
}

/// A scene error with where it is, as attributes.
pub fn scene(e: LibSceneError) -> PyErr {
    let (file, line, column) = match &e {
        LibSceneError::Invalid {
            file, line, column, ..
        }
        | LibSceneError::Syntax {
            file, line, column, ..
        } => (Some(file.clone()), Some(*line), Some(*column)),
        LibSceneError::Read { path, .. } => (Some(path.clone()), None, None),
        _ => (None, None, None),
    };
    scene_at(
        in_python(e.to_string()),
        file.map(|f| f.display().to_string()),
        line,
        column,
    )
}

/// A `glint.SceneError` saying `message`, with where it is.
pub fn scene_at(
    message: String,
    file: Option<String>,
    line: Option<usize>,
    column: Option<usize>,
) -> PyErr {
    let err = SceneError::new_err(message);
    Python::attach(|py| {
        let value = err.value(py);
        // Setting attributes on a fresh exception instance cannot fail.
        let _ = value.setattr("file", file);
        let _ = value.setattr("line", line);
        let _ = value.setattr("column", column);
    });
    err
}

pub fn image(e: ImageIoError) -> PyErr {
    ImageError::new_err(in_python(e.to_string()))
}

/// Images that would not fit: a `MemoryError`, before they are allocated,
/// so that the interpreter lives.
pub fn memory(e: glint::raster::memory::TooLarge) -> PyErr {
    pyo3::exceptions::PyMemoryError::new_err(in_python(e.to_string()))
}

/// Any other error of glint's, as the binary words it.
pub fn other(e: impl std::fmt::Display) -> PyErr {
    Error::new_err(in_python(e.to_string()))
}

#[cfg(feature = "gpu")]
pub fn gpu(e: glint::gpu::GpuError) -> PyErr {
    use glint::gpu::GpuError as G;
    match e {
        G::Interrupted => pyo3::exceptions::PyKeyboardInterrupt::new_err(()),
        G::Shader(log) => {
            let err = ShaderError::new_err(in_python(G::Shader(log.clone()).to_string()));
            Python::attach(|py| {
                let _ = err.value(py).setattr("log", log);
            });
            err
        }
        e @ (G::Unsupported(_) | G::Reference(_)) => Error::new_err(in_python(e.to_string())),
        e => DeviceError::new_err(in_python(e.to_string())),
    }
}

/// What a GPU call raises in a build without the GPU renderer: the
/// binary's own line (src/cli/without_gpu.rs).
#[cfg(not(feature = "gpu"))]
pub fn unbuilt(what: &str) -> PyErr {
    DeviceError::new_err(format!(
        "{what} needs the GPU renderer, and this glint was built without it \
         (--no-default-features); build it with the default features, or render with backend=\"cpu\""
    ))
}
