//! The error of a scene that cannot be read or is not valid, naming where.

use std::path::PathBuf;

/// A scene that cannot be read or is not valid. Each variant names where.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    // The cause is part of the message, not a `source`, so that a report
    // of the error chain does not print it twice.
    /// The file cannot be read.
    #[error("cannot read scene {}: {cause}", crate::printable::path(path))]
    Read {
        /// The scene file.
        path: PathBuf,
        /// What the system said.
        cause: std::io::Error,
    },
    /// A value that breaks docs/scene-format.md: the file, the line and column, the key.
    #[error(
        "{}:{line}:{column}: {}: {}",
        crate::printable::path(file),
        crate::printable::text(key),
        crate::printable::one_line(message)
    )]
    Invalid {
        /// The file (or the mesh file) the value is in.
        file: PathBuf,
        /// Its line, from 1.
        line: usize,
        /// Its column, from 1.
        column: usize,
        /// The key, as a path: `spheres[2].radius`.
        key: String,
        /// What is wrong.
        message: String,
    },
    /// The TOML itself does not parse (no key to name yet).
    #[error(
        "{}:{line}:{column}: {}",
        crate::printable::path(file),
        crate::printable::one_line(message)
    )]
    Syntax {
        /// The file.
        file: PathBuf,
        /// The line, from 1.
        line: usize,
        /// The column, from 1.
        column: usize,
        /// The parser's message.
        message: String,
    },
    /// A command-line override out of range.
    #[error("{flag}: {message}")]
    Override {
        /// The flag, as `--width`.
        flag: &'static str,
        /// What is wrong.
        message: String,
    },
}
