//! The files of a directory, listed in the one order every command uses:
//! sorted by path; the folder a file is in; and what tells a file changed.

use std::path::{Path, PathBuf};

/// The entries directly in `dir` that `keep` accepts, sorted.
pub fn sorted(dir: &Path, keep: impl Fn(&Path) -> bool) -> std::io::Result<Vec<PathBuf>> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| keep(p))
        .collect();
    v.sort();
    Ok(v)
}

/// The folder `file` is in: its parent, or "." for a bare name (whose
/// parent is the empty path, which no call can open).
pub fn folder_of(file: &Path) -> &Path {
    match file.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// Every entry of each of `dirs` in turn, each directory's sorted; one
/// that cannot be read gives none (the user's shader directories: a
/// compile names what it cannot find).
pub fn in_dirs(dirs: &[PathBuf]) -> Vec<PathBuf> {
    dirs.iter()
        .flat_map(|d| sorted(d, |_| true).unwrap_or_default())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bare_names_folder_is_the_working_folder() {
        assert_eq!(folder_of(Path::new("s.toml")), Path::new("."));
        assert_eq!(folder_of(Path::new("scenes/s.toml")), Path::new("scenes"));
        assert_eq!(folder_of(Path::new("/s.toml")), Path::new("/"));
        assert_eq!(folder_of(Path::new("./s.toml")), Path::new("."));
    }
}

/// A file's modification time and size, and the two a writer cannot set:
/// its inode (a file renamed over it is another) and its change time (any
/// write sets it). Times and size alone missed a same-size edit that kept
/// the time (`cp -p`, `rsync -a`, `tar x`, two saves in one second of a
/// file system with 1-second times): `glint watch` and the mesh cache
/// behind the Python module's `params` both rendered the old file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Stamp {
    modified: Option<std::time::SystemTime>,
    len: u64,
    #[cfg(unix)]
    changed: (i64, i64),
    #[cfg(unix)]
    file: (u64, u64),
}

impl Stamp {
    /// The stamp of a file's metadata.
    pub fn of(m: &std::fs::Metadata) -> Self {
        #[cfg(unix)]
        use std::os::unix::fs::MetadataExt;
        Stamp {
            modified: m.modified().ok(),
            len: m.len(),
            #[cfg(unix)]
            changed: (m.ctime(), m.ctime_nsec()),
            #[cfg(unix)]
            file: (m.dev(), m.ino()),
        }
    }

    /// The stamp of the file at `path`, where it can be read.
    pub fn of_file(path: &Path) -> Option<Self> {
        std::fs::metadata(path).ok().map(|m| Self::of(&m))
    }
}
