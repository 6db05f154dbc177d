//! The files of a directory, listed in the one order every command uses:
//! sorted by path.

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

/// Every entry of each of `dirs` in turn, each directory's sorted; one
/// that cannot be read gives none (the user's shader directories: a
/// compile names what it cannot find).
pub fn in_dirs(dirs: &[PathBuf]) -> Vec<PathBuf> {
    dirs.iter()
        .flat_map(|d| sorted(d, |_| true).unwrap_or_default())
        .collect()
}
