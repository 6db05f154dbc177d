//! The one error of the drivers' judgement: a file it could not read or
//! write, each named.

use std::path::{Path, PathBuf};

/// What went wrong writing a reproducer or shrinking a scene.
#[derive(Debug, thiserror::Error)]
pub enum DriversError {
    /// A file or folder that could not be read, written, made or copied.
    #[error("cannot {action} {}: {cause}", crate::printable::path(path))]
    File {
        /// What was being done: "read", "write", "create", "copy".
        action: &'static str,
        /// The file or folder.
        path: PathBuf,
        /// What the system said.
        cause: std::io::Error,
    },
    /// An image that could not be written.
    #[error(transparent)]
    Image(#[from] crate::raster::io::ImageIoError),
    /// A heat map of two images of different sizes.
    #[error(transparent)]
    Size(#[from] crate::raster::diff::SizeMismatch),
    /// A record that could not be written as JSON.
    #[error("cannot write JSON: {0}")]
    Json(#[from] serde_json::Error),
    /// A shrunk scene that could not be written as TOML.
    #[error("cannot write the shrunk scene as TOML: {0}")]
    Toml(#[from] toml::ser::Error),
}

impl DriversError {
    /// The error of `action` on `path`, as a closure for `map_err`.
    pub(crate) fn file(
        action: &'static str,
        path: impl Into<PathBuf>,
    ) -> impl FnOnce(std::io::Error) -> Self {
        let path = path.into();
        move |cause| Self::File {
            action,
            path,
            cause,
        }
    }
}

/// Writes `contents` to `path`, naming the file where that fails.
pub(crate) fn write(path: &Path, contents: impl AsRef<[u8]>) -> Result<(), DriversError> {
    std::fs::write(path, contents).map_err(DriversError::file("write", path))
}
