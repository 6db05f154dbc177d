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

pub mod interrupt;
pub(crate) mod partial;

use std::fs::{File, Metadata};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

pub use partial::{alive, remove_in_progress};

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
    /// An output folder, or a folder on its path, that is a file.
    #[error(
        "{}: cannot be an output folder: {} is not a folder",
        crate::printable::path(output),
        crate::printable::path(path)
    )]
    NotAFolder {
        /// What is there instead of a folder.
        path: PathBuf,
        /// The output folder asked for.
        output: PathBuf,
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
    Stream { target: Target, bytes: Vec<u8> },
}

/// Where an output's bytes go once its symbolic links are followed.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Target {
    /// A name in the file system.
    Path(PathBuf),
    /// One of this process's open descriptors, named as `/dev/stdout`,
    /// `/dev/fd/N` or `/proc/self/fd/N` (`>(cat)` too): written into at its
    /// own offset, never opened anew by the name it points to, which may be
    /// a pipe's (`pipe:[N]`) or a log the shell opened for appending.
    Descriptor(i32),
}

impl Target {
    /// The path the target's metadata is read from.
    fn stat_path(&self) -> PathBuf {
        match self {
            Target::Path(p) => p.clone(),
            Target::Descriptor(fd) => PathBuf::from(format!("/proc/self/fd/{fd}")),
        }
    }
}

/// What makes two outputs one: the same descriptor, or the same name in
/// the same folder however the path is spelled (`./x.png`, an absolute
/// path, a folder reached through a link).
#[derive(Debug, PartialEq, Eq)]
enum Name {
    Descriptor(i32),
    Entry(PathBuf, std::ffi::OsString),
    Spelled(PathBuf),
}

impl Name {
    fn of(target: &Target) -> Name {
        let path = match target {
            Target::Descriptor(fd) => return Name::Descriptor(*fd),
            Target::Path(p) => p,
        };
        let parent = crate::files::folder_of(path);
        match (std::fs::canonicalize(parent), path.file_name()) {
            (Ok(dir), Some(name)) => Name::Entry(dir, name.to_owned()),
            _ => Name::Spelled(path.clone()),
        }
    }
}

/// A command's outputs: checked against its inputs and their targets,
/// staged, then committed together.
pub struct Outputs {
    inputs: Vec<(PathBuf, Metadata)>,
    force: bool,
    /// The outputs checked so far: a second check of one of them is refused.
    checked: Vec<Name>,
    /// Each staged output with its name, which a later one may not share.
    staged: Vec<(Name, Staged)>,
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
            checked: Vec::new(),
            staged: Vec::new(),
        }
    }

    /// Fails where `path` may not be written: it is one of the inputs (by
    /// device and inode, so links and other spellings count), a read-only
    /// file without `force`, not a file, character device or FIFO, or in a
    /// folder where no file can be made. A command calls it for every
    /// output before it starts its work.
    /// Two checks of one file (by its folder and name, or its descriptor)
    /// are refused: the second output would replace the first.
    pub fn check(&mut self, path: &Path) -> Result<TargetKind, OutputError> {
        let (kind, target, _, name) = self.target(path)?;
        if self.checked.contains(&name) {
            return Err(OutputError::Twice(path.to_owned()));
        }
        if let (TargetKind::File, Target::Path(file)) = (kind, &target) {
            // The folder takes a new file: proven by making one (removed at once).
            temp_beside(file, None)?;
        }
        self.checked.push(name);
        Ok(kind)
    }

    /// What `path` ends at, after its links, with its metadata where it
    /// exists and its name; every rule of `check` but the folder's and the
    /// repeat's.
    fn target(
        &self,
        path: &Path,
    ) -> Result<(TargetKind, Target, Option<Metadata>, Name), OutputError> {
        if path.as_os_str().as_encoded_bytes().ends_with(b"/") {
            return Err(OutputError::NotAFile {
                path: path.to_owned(),
                what: "a folder's name (it ends in /)",
            });
        }
        let target = resolve(path);
        let name = Name::of(&target);
        if self.staged.iter().any(|(staged, _)| *staged == name) {
            return Err(OutputError::Twice(path.to_owned()));
        }
        let meta = match std::fs::metadata(target.stat_path()) {
            Ok(m) => Some(m),
            Err(_) if matches!(target, Target::Descriptor(_)) => {
                return Err(OutputError::NotAFile {
                    path: path.to_owned(),
                    what: "a descriptor this process does not have open",
                })
            }
            Err(_) => None,
        };
        if let Some(meta) = &meta {
            if let Some((input, _)) = self.inputs.iter().find(|(_, m)| same_file(m, meta)) {
                return Err(OutputError::OverwritesInput {
                    output: path.to_owned(),
                    input: input.clone(),
                });
            }
        }
        let kind = match (&target, &meta) {
            // An open descriptor is written into, whatever it holds.
            (Target::Descriptor(_), _) => TargetKind::Stream,
            (Target::Path(_), None) => TargetKind::File,
            (Target::Path(p), Some(m)) => kind_of(p, m)?,
        };
        if let Target::Path(file) = &target {
            if kind == TargetKind::File
                && meta.as_ref().is_some_and(|m| m.permissions().readonly())
                && !self.force
            {
                return Err(OutputError::ReadOnly(file.clone()));
            }
        }
        Ok((kind, target, meta, name))
    }

    /// Checks `path` (as `check`), then has `fill` write its contents: into
    /// a temporary file beside a file target, or into memory for a stream.
    /// Nothing reaches `path` before `commit`.
    pub fn stage<E: From<OutputError>>(
        &mut self,
        path: &Path,
        fill: impl FnOnce(&mut dyn Write) -> Result<(), E>,
    ) -> Result<(), E> {
        let (kind, target, old, name) = self.target(path)?;
        match target {
            // `target` makes a descriptor a stream.
            Target::Path(target) if kind == TargetKind::File => {
                let tmp = temp_beside(&target, old.as_ref())?;
                {
                    let mut out = BufWriter::new(tmp.file());
                    fill(&mut out)?;
                    out.flush().map_err(io_err(&target))?;
                }
                tmp.file().sync_all().map_err(io_err(&target))?;
                self.staged.push((name, Staged::File { tmp, target }));
            }
            target => {
                let mut bytes = Vec::new();
                fill(&mut bytes)?;
                self.staged.push((name, Staged::Stream { target, bytes }));
            }
        }
        Ok(())
    }

    /// Puts every staged output in place, in the order staged (so a
    /// command stages its main output last). A failure here (the folder
    /// removed meanwhile) leaves the outputs after the failed one as they
    /// were, and removes their temporary files.
    pub fn commit(self) -> Result<(), OutputError> {
        for (_, staged) in self.staged {
            match staged {
                Staged::File { tmp, target } => tmp.persist(&target)?,
                Staged::Stream {
                    target: Target::Path(target),
                    bytes,
                } => {
                    // No create, no truncate: the device or FIFO stays what it is.
                    std::fs::OpenOptions::new()
                        .write(true)
                        .open(&target)
                        .and_then(|mut f| f.write_all(&bytes))
                        .map_err(io_err(&target))?;
                }
                Staged::Stream {
                    target: Target::Descriptor(fd),
                    bytes,
                } => write_descriptor(fd, &bytes).map_err(|cause| OutputError::Io {
                    path: PathBuf::from(format!("/dev/fd/{fd}")),
                    cause,
                })?,
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

/// Fails where `dir` cannot be a folder of outputs (`report -o`, `shader
/// dump -o`): it, or the nearest of its ancestors that exists, is not a
/// folder. A command calls it before its work, as it checks its files.
pub fn check_folder(dir: &Path) -> Result<(), OutputError> {
    let mut p = dir;
    loop {
        match std::fs::metadata(p) {
            Ok(m) if m.is_dir() => return Ok(()),
            Ok(_) => {
                return Err(OutputError::NotAFolder {
                    path: p.to_owned(),
                    output: dir.to_owned(),
                })
            }
            Err(_) => match p.parent() {
                Some(up) if !up.as_os_str().is_empty() => p = up,
                _ => return Ok(()),
            },
        }
    }
}

/// What `path` names after its links, where it exists and an output may
/// be written as it (a file, a character device or a FIFO); nothing is
/// made or opened.
pub fn target_kind(path: &Path) -> Option<TargetKind> {
    match resolve(path) {
        Target::Descriptor(fd) => std::fs::metadata(format!("/proc/self/fd/{fd}"))
            .ok()
            .map(|_| TargetKind::Stream),
        Target::Path(target) => {
            let meta = std::fs::metadata(&target).ok()?;
            kind_of(&target, &meta).ok()
        }
    }
}

/// Where `path` ends: a descriptor where its chain of links names one
/// (`/dev/stdout` → `/proc/self/fd/1`), else the file the chain ends at
/// (the path itself where it is none, or where a link cannot be read). A
/// dangling link ends at the name it points to, which the write then
/// creates.
fn resolve(path: &Path) -> Target {
    let mut p = path.to_owned();
    // Forty links, as Linux allows, before a loop is left to the write to report.
    for _ in 0..40 {
        if let Some(fd) = descriptor_named(&p) {
            return Target::Descriptor(fd);
        }
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
    Target::Path(p)
}

/// The descriptor `path` names: `/dev/fd/N`, `/proc/self/fd/N`,
/// `/proc/thread-self/fd/N` or `/proc/<this pid>/fd/N`.
fn descriptor_named(path: &Path) -> Option<i32> {
    let text = path.to_str()?;
    let own = format!("/proc/{}/fd/", std::process::id());
    let number = [
        "/dev/fd/",
        "/proc/self/fd/",
        "/proc/thread-self/fd/",
        own.as_str(),
    ]
    .iter()
    .find_map(|prefix| text.strip_prefix(prefix))?;
    number.parse().ok()
}

/// Writes `bytes` into this process's open descriptor `fd`, at its offset
/// (the end, for a file the shell opened with `>>`).
#[cfg(unix)]
fn write_descriptor(fd: i32, bytes: &[u8]) -> std::io::Result<()> {
    use std::os::fd::BorrowedFd;
    // The descriptor was seen open when the output was checked (its
    // /proc entry was read); a copy of it is written through, so the
    // process's own stays open. A descriptor closed since fails the dup.
    // SAFETY: borrow_raw needs `fd` open for the borrow's life, which ends
    // with this statement; dup of a closed one returns EBADF, not UB.
    let owned = unsafe { BorrowedFd::borrow_raw(fd) }.try_clone_to_owned()?;
    File::from(owned).write_all(bytes)
}

#[cfg(not(unix))]
fn write_descriptor(_: i32, _: &[u8]) -> std::io::Result<()> {
    Err(std::io::ErrorKind::Unsupported.into())
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
    let dir = crate::files::folder_of(target);
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
