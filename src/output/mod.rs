//! The files a command writes (docs/guarantees.md, Outputs), committed
//! together or not at all.
//!
//! A command names its inputs and stages each output into an [`Outputs`]:
//! a regular file (or a name not yet taken) is written to a temporary file
//! beside it, `.glint-<pid>-*.tmp`; [`Outputs::commit`] then renames them
//! over their targets in the order staged, so that a run that fails before
//! the commit leaves every old output whole. A character device or a FIFO
//! (`/dev/null`, a pipe) is never replaced: what is staged for it is written
//! into it at the commit. A directory, a block device or a socket is
//! refused. Every rule applies to the file a chain of symbolic links ends
//! at.

pub(crate) mod partial;

use std::fs::{File, Metadata};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

pub use partial::remove_in_progress;

/// An output that may not be written; each names the file.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// An output that is one of the run's inputs.
    #[error(
        "{}: is the input {}; refusing to overwrite an input (name another output)",
        crate::printable::path(output),
        crate::printable::path(input)
    )]
    OverwritesInput {
        /// The output asked for.
        output: PathBuf,
        /// The input it is.
        input: PathBuf,
    },
    /// An output file that is read-only (replaced only with `--force`).
    #[error("{}: is read-only; refusing to replace it (remove it, or use --force)", crate::printable::path(.0))]
    ReadOnly(PathBuf),
    /// A target that no file can be written as: a directory, a block
    /// device or a socket.
    #[error(
        "{}: is {what}; an output must be a file, a character device or a FIFO",
        crate::printable::path(path)
    )]
    NotAFile {
        /// The target.
        path: PathBuf,
        /// What it is instead.
        what: &'static str,
    },
    /// Two outputs of one run that are the same file (through a link,
    /// say): the second would replace the first.
    #[error("{}: is another output of this run too; name two files", crate::printable::path(.0))]
    Twice(PathBuf),
    /// The file system refused (a missing folder, no permission, a full disk).
    // The cause is part of the message rather than a `source`, so that a
    // report of the error chain does not print it twice.
    #[error("{}: {cause}", crate::printable::path(path))]
    Io {
        /// The file.
        path: PathBuf,
        /// What the system said.
        cause: std::io::Error,
    },
}

/// The `OutputError::Io` of `path`, for `map_err`.
pub fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> OutputError + '_ {
    move |cause| OutputError::Io {
        path: path.to_owned(),
        cause,
    }
}

/// What an output's path names, after its symbolic links.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TargetKind {
    /// A regular file, or nothing yet: replaced by a rename.
    File,
    /// A character device or a FIFO: written into, never replaced.
    Stream,
}

/// An output written but not yet committed.
enum Staged {
    File { tmp: Temp, target: PathBuf },
    Stream { target: PathBuf, bytes: Vec<u8> },
}

impl Staged {
    fn target(&self) -> &Path {
        match self {
            Staged::File { target, .. } | Staged::Stream { target, .. } => target,
        }
    }
}

/// A command's outputs: checked against its inputs and their targets,
/// staged, then committed together.
pub struct Outputs {
    inputs: Vec<(PathBuf, Metadata)>,
    force: bool,
    staged: Vec<Staged>,
}

impl Outputs {
    /// Outputs of a run that reads `inputs` (an input that does not exist
    /// is left out: no output can be it). With `force`, a read-only file
    /// is replaced too.
    pub fn new<P: AsRef<Path>>(inputs: impl IntoIterator<Item = P>, force: bool) -> Self {
        let inputs = inputs
            .into_iter()
            .filter_map(|p| {
                let p = p.as_ref();
                std::fs::metadata(p).ok().map(|m| (p.to_owned(), m))
            })
            .collect();
        Self {
            inputs,
            force,
            staged: Vec::new(),
        }
    }

    /// Fails where `path` may not be written: it is one of the inputs (by
    /// device and inode, so links and other spellings count), a read-only
    /// file without `force`, not a file, character device or FIFO, or in a
    /// folder where no file can be made. A command calls it for every
    /// output before it starts its work.
    pub fn check(&self, path: &Path) -> Result<TargetKind, OutputError> {
        let (kind, target, _) = self.target(path)?;
        if kind == TargetKind::File {
            // The folder takes a new file: proven by making one (removed at once).
            temp_beside(&target, None)?;
        }
        Ok(kind)
    }

    /// What `path` ends at, after its links, with its metadata where it
    /// exists; every rule of `check` but the folder's.
    fn target(&self, path: &Path) -> Result<(TargetKind, PathBuf, Option<Metadata>), OutputError> {
        let target = follow_links(path);
        if self.staged.iter().any(|s| s.target() == target) {
            return Err(OutputError::Twice(path.to_owned()));
        }
        let meta = std::fs::metadata(&target).ok();
        if let Some(meta) = &meta {
            if let Some((input, _)) = self.inputs.iter().find(|(_, m)| same_file(m, meta)) {
                return Err(OutputError::OverwritesInput {
                    output: path.to_owned(),
                    input: input.clone(),
                });
            }
        }
        let kind = match &meta {
            None => TargetKind::File,
            Some(m) => kind_of(&target, m)?,
        };
        if kind == TargetKind::File
            && meta.as_ref().is_some_and(|m| m.permissions().readonly())
            && !self.force
        {
            return Err(OutputError::ReadOnly(target));
        }
        Ok((kind, target, meta))
    }

    /// Checks `path` (as `check`), then has `fill` write its contents: into
    /// a temporary file beside a file target, or into memory for a stream.
    /// Nothing reaches `path` before `commit`.
    pub fn stage<E: From<OutputError>>(
        &mut self,
        path: &Path,
        fill: impl FnOnce(&mut dyn Write) -> Result<(), E>,
    ) -> Result<(), E> {
        let (kind, target, old) = self.target(path)?;
        match kind {
            TargetKind::Stream => {
                let mut bytes = Vec::new();
                fill(&mut bytes)?;
                self.staged.push(Staged::Stream { target, bytes });
            }
            TargetKind::File => {
                let tmp = temp_beside(&target, old.as_ref())?;
                {
                    let mut out = BufWriter::new(tmp.file());
                    fill(&mut out)?;
                    out.flush().map_err(io_err(&target))?;
                }
                tmp.file().sync_all().map_err(io_err(&target))?;
                self.staged.push(Staged::File { tmp, target });
            }
        }
        Ok(())
    }

    /// Puts every staged output in place, in the order staged (so a
    /// command stages its main output last). A failure here (the folder
    /// removed meanwhile) leaves the outputs after the failed one as they
    /// were, and removes their temporary files.
    pub fn commit(self) -> Result<(), OutputError> {
        for staged in self.staged {
            match staged {
                Staged::File { tmp, target } => tmp.persist(&target)?,
                Staged::Stream { target, bytes } => {
                    // No create, no truncate: the device or FIFO stays what it is.
                    std::fs::OpenOptions::new()
                        .write(true)
                        .open(&target)
                        .and_then(|mut f| f.write_all(&bytes))
                        .map_err(io_err(&target))?;
                }
            }
        }
        Ok(())
    }
}

/// A temporary file, listed for removal on a signal (`partial`) until it
/// is renamed over its target or dropped (which removes it). It leaves the
/// list only once it is gone from its name: a signal in between then finds
/// it listed, never an unlisted file.
struct Temp(Option<tempfile::NamedTempFile>);

impl Temp {
    fn file(&self) -> &File {
        self.0.as_ref().expect("held until persisted").as_file()
    }

    fn persist(mut self, target: &Path) -> Result<(), OutputError> {
        let tmp = self.0.take().expect("held until persisted");
        let path = tmp.path().to_owned();
        // A failed rename hands the file back; dropping it removes it.
        let renamed = tmp.persist(target).map(drop).map_err(|e| e.error);
        partial::unregister(&path);
        renamed.map_err(io_err(target))
    }
}

impl Drop for Temp {
    fn drop(&mut self) {
        if let Some(tmp) = self.0.take() {
            let path = tmp.path().to_owned();
            drop(tmp);
            partial::unregister(&path);
        }
    }
}

/// Writes one output at once (`stage` then `commit`), checked against
/// `inputs`.
pub fn write_one<E: From<OutputError>>(
    path: &Path,
    inputs: &[&Path],
    force: bool,
    fill: impl FnOnce(&mut dyn Write) -> Result<(), E>,
) -> Result<(), E> {
    let mut outputs = Outputs::new(inputs, force);
    outputs.stage(path, fill)?;
    Ok(outputs.commit()?)
}

/// What `path` names after its links, where it exists and an output may
/// be written as it (a file, a character device or a FIFO); nothing is
/// made or opened.
pub fn target_kind(path: &Path) -> Option<TargetKind> {
    let target = follow_links(path);
    let meta = std::fs::metadata(&target).ok()?;
    kind_of(&target, &meta).ok()
}

/// What an existing target is, or why no output can be written as it.
fn kind_of(target: &Path, meta: &Metadata) -> Result<TargetKind, OutputError> {
    let refuse = |what| {
        Err(OutputError::NotAFile {
            path: target.to_owned(),
            what,
        })
    };
    let t = meta.file_type();
    if t.is_file() {
        return Ok(TargetKind::File);
    }
    if t.is_dir() {
        return refuse("a directory");
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_char_device() || t.is_fifo() {
            return Ok(TargetKind::Stream);
        }
        if t.is_block_device() {
            return refuse("a block device");
        }
        if t.is_socket() {
            return refuse("a socket");
        }
    }
    refuse("not a regular file")
}

/// A new temporary file in `target`'s folder, registered for removal on a
/// signal, with `old`'s permissions where it replaces a file (else those
/// of any new file).
fn temp_beside(target: &Path, old: Option<&Metadata>) -> Result<Temp, OutputError> {
    let dir = match target.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    partial::remove_stale(dir);
    let prefix = partial::prefix();
    // Each name is listed before its file is made: a signal at any moment
    // finds every temporary file of this process listed.
    let made = tempfile::Builder::new()
        .prefix(&prefix)
        .suffix(".tmp")
        .make_in(dir, |path| {
            partial::register(path);
            let mut open = std::fs::OpenOptions::new();
            open.write(true).create_new(true);
            // As readable as any new file (tempfile's own are private).
            #[cfg(unix)]
            std::os::unix::fs::OpenOptionsExt::mode(&mut open, 0o666);
            open.open(path).inspect_err(|_| partial::unregister(path))
        });
    // tempfile's error names the temporary file; the user named the target.
    let tmp = made.map_err(|e| {
        let cause = e
            .raw_os_error()
            .map_or(e, std::io::Error::from_raw_os_error);
        io_err(target)(cause)
    })?;
    let tmp = Temp(Some(tmp));
    if let Some(meta) = old {
        tmp.file()
            .set_permissions(meta.permissions())
            .map_err(io_err(target))?;
    }
    Ok(tmp)
}

/// The file a chain of symbolic links ends at (the path itself where it is
/// none, or where a link cannot be read). A dangling link ends at the name
/// it points to, which the write then creates.
pub fn follow_links(path: &Path) -> PathBuf {
    let mut p = path.to_owned();
    // Forty links, as Linux allows, before a loop is left to the write to report.
    for _ in 0..40 {
        match std::fs::read_link(&p) {
            Ok(next) => {
                p = match p.parent() {
                    Some(dir) if next.is_relative() => dir.join(next),
                    _ => next,
                }
            }
            Err(_) => break,
        }
    }
    p
}

#[cfg(unix)]
fn same_file(a: &Metadata, b: &Metadata) -> bool {
    use std::os::unix::fs::MetadataExt;
    a.dev() == b.dev() && a.ino() == b.ino()
}

#[cfg(not(unix))]
fn same_file(_: &Metadata, _: &Metadata) -> bool {
    false
}

#[cfg(test)]
mod tests;
