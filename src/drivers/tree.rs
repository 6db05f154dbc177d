//! A driver in a system tree of its own (docs/drivers.md, A driver of
//! another system): an ICD file at `ROOT/usr/share/vulkan/icd.d/`, where
//! ROOT is not `/` and holds its own dynamic loader, as `ci/sid-lavapipe`
//! makes Debian unstable's lavapipe. Its libraries need that tree's C
//! library, newer than this machine's, so glint runs on it through the
//! tree's loader, with the tree's library folders first: no chroot, and
//! every path of the machine still means what it says.

use std::ffi::OsString;
use std::path::{Path, PathBuf};

/// The dynamic loader a tree must hold, from its root.
pub const LOADER: &str = "lib64/ld-linux-x86-64.so.2";

/// Where ICD files lie in a tree, from its root.
const ICD_DIR: &str = "usr/share/vulkan/icd.d";

/// The root of the tree `icd` lies in, where it lies in one; None for the
/// machine's own drivers.
pub fn root_of(icd: &Path) -> Option<PathBuf> {
    let dir = std::path::absolute(icd).ok()?.parent()?.to_path_buf();
    let root = dir
        .to_str()?
        .strip_suffix(ICD_DIR)?
        .strip_suffix('/')
        .filter(|r| !r.is_empty())?;
    let root = PathBuf::from(root);
    root.join(LOADER).is_file().then_some(root)
}

/// The words that run a program on the tree at `root`, before the
/// program's path: its loader and its library folders.
pub fn launcher(root: &Path) -> Vec<OsString> {
    let arch = format!("{}-linux-gnu", std::env::consts::ARCH);
    let folders = [format!("lib/{arch}"), format!("usr/lib/{arch}")];
    let paths = std::env::join_paths(folders.iter().map(|f| root.join(f)))
        .unwrap_or_else(|_| root.join(&folders[1]).into_os_string());
    vec![
        root.join(LOADER).into_os_string(),
        "--library-path".into(),
        paths,
    ]
}

/// The ICD files of the tree at `root`, by name; none where it is not a
/// tree (no loader) or holds none.
pub fn icd_files(root: &Path) -> Vec<PathBuf> {
    if !root.join(LOADER).is_file() {
        return Vec::new();
    }
    crate::files::sorted(&root.join(ICD_DIR), |p| {
        p.extension().is_some_and(|e| e == "json")
    })
    .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A manifest under a tree's icd.d whose root holds a loader is the
    /// tree's, and its files are listed; the machine's own, one outside
    /// icd.d, or a tree without a loader are not.
    #[test]
    fn a_tree_is_known_by_its_loader() {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path().join("sid");
        let icd_dir = root.join(ICD_DIR);
        std::fs::create_dir_all(&icd_dir).unwrap();
        let icd = icd_dir.join("lvp_icd.json");
        std::fs::write(&icd, "{}").unwrap();
        assert_eq!(root_of(&icd), None, "no loader yet");
        assert!(icd_files(&root).is_empty());
        std::fs::create_dir_all(root.join("lib64")).unwrap();
        std::fs::write(root.join(LOADER), "").unwrap();
        assert_eq!(root_of(&icd), Some(root.clone()));
        assert_eq!(icd_files(&root), vec![icd]);
        assert_eq!(root_of(&root.join("lvp_icd.json")), None);
        assert_eq!(
            root_of(Path::new("/usr/share/vulkan/icd.d/lvp_icd.json")),
            None
        );
        let words = launcher(&root);
        assert_eq!(words[0], root.join(LOADER).into_os_string());
        assert_eq!(words[1], "--library-path");
    }
}
