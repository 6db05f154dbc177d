use std::path::PathBuf;

/// A scene that cannot be read or is not valid. Each variant names where.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    // The cause is part of the message, not a `source`, so that a report
    // of the error chain does not print it twice.
    #[error("cannot read scene {}: {cause}", crate::printable::path(path))]
    Read {
        path: PathBuf,
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
        file: PathBuf,
        line: usize,
        column: usize,
        key: String,
        message: String,
    },
    /// The TOML itself does not parse (no key to name yet).
    #[error(
        "{}:{line}:{column}: {}",
        crate::printable::path(file),
        crate::printable::one_line(message)
    )]
    Syntax {
        file: PathBuf,
        line: usize,
        column: usize,
        message: String,
    },
    /// A command-line override out of range.
    #[error("{flag}: {message}")]
    Override { flag: &'static str, message: String },
}
