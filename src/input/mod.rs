//! What users give glint, and how it is taken: files read within bounds
//! (`read`), and the vocabulary every layer above checks its input with:
//! the errors that name a file, line, column and key (`error`), where in a
//! file each key was written (`locate`), and the checks of single values
//! (`field`).

pub(crate) mod error;
pub(crate) mod field;
pub(crate) mod keys;
pub(crate) mod locate;
mod read;
pub(crate) mod triangles;

pub use read::{check, open, read, read_text, ReadAs, MAX_PIXELS, MAX_SIDE};
