//! The Vulkan drivers a machine has: the ICD manifest files the loader
//! would enumerate (docs/drivers.md, Which drivers), those `ci/old-lavapipe`
//! unpacked, and any named on the command line.

use std::path::{Path, PathBuf};

/// Refuses an `--icd` that is not a manifest file, saying what the path is
/// (a directory, a FIFO and a loop of links were all "no such file";
/// `explain --icd` took a folder or a FIFO and waited on it), before any
/// child starts.
pub fn check_given(files: &[PathBuf]) -> anyhow::Result<()> {
    for f in files {
        glint::input::check(f, glint::input::ReadAs::Manifest)
            .map_err(|e| anyhow::anyhow!("--icd {}: {e}", glint::printable::path(f)))?;
    }
    Ok(())
}

/// Where the Vulkan loader looks for ICD manifests on Linux, in its order:
/// `VK_DRIVER_FILES` (or the older `VK_ICD_FILENAMES`) alone where set,
/// else the `vulkan/icd.d` folder of each XDG config and data folder and
/// /etc.
pub fn loader_files() -> Vec<PathBuf> {
    for var in ["VK_DRIVER_FILES", "VK_ICD_FILENAMES"] {
        if let Some(v) = std::env::var_os(var).filter(|v| !v.is_empty()) {
            return std::env::split_paths(&v)
                .flat_map(|p| if p.is_dir() { manifests(&p) } else { vec![p] })
                .collect();
        }
    }
    let env_dirs = |var: &str, default: &str| -> Vec<PathBuf> {
        let v = std::env::var_os(var).filter(|v| !v.is_empty());
        match v {
            Some(v) => std::env::split_paths(&v).collect(),
            None => std::env::split_paths(default).collect(),
        }
    };
    let home = std::env::var_os("HOME").map(PathBuf::from);
    let mut dirs = env_dirs("XDG_CONFIG_DIRS", "/etc/xdg");
    dirs.push(PathBuf::from("/etc"));
    if let Some(h) = std::env::var_os("XDG_DATA_HOME")
        .map(PathBuf::from)
        .or_else(|| home.map(|h| h.join(".local/share")))
    {
        dirs.push(h);
    }
    dirs.extend(env_dirs("XDG_DATA_DIRS", "/usr/local/share:/usr/share"));
    dirs.iter()
        .flat_map(|d| manifests(&d.join("vulkan/icd.d")))
        .collect()
}

/// The lavapipes `ci/old-lavapipe` unpacked (`<cache>/glint-drivers/*/*.json`)
/// and the one of Debian unstable's tree `ci/sid-lavapipe` made
/// (`<cache>/glint-sid`, run through its loader: `glint::drivers::tree`).
pub fn unpacked_files() -> Vec<PathBuf> {
    let cache = std::env::var_os("XDG_CACHE_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")));
    let Some(cache) = cache else {
        return Vec::new();
    };
    let mut files: Vec<PathBuf> =
        glint::files::sorted(&cache.join("glint-drivers"), |p| p.is_dir())
            .unwrap_or_default()
            .iter()
            .flat_map(|d| manifests(d))
            .collect();
    files.extend(glint::drivers::tree::icd_files(&cache.join("glint-sid")));
    files
}

/// The .json files in `dir`, by name; none where it cannot be read.
fn manifests(dir: &Path) -> Vec<PathBuf> {
    glint::files::sorted(dir, |p| p.extension().is_some_and(|e| e == "json")).unwrap_or_default()
}

/// `files` with each file once (by its resolved path), in their order.
pub fn once(files: impl IntoIterator<Item = PathBuf>) -> Vec<PathBuf> {
    let mut seen = std::collections::HashSet::new();
    files
        .into_iter()
        .filter(|f| seen.insert(std::fs::canonicalize(f).unwrap_or_else(|_| f.clone())))
        .collect()
}

/// A short name for an ICD file, for folder names and the table:
/// `lvp_icd` for /usr/share/vulkan/icd.d/lvp_icd.json, and the folder too
/// where `ci/old-lavapipe` unpacked it (`mesa-22.3.6-1+deb12u2/lvp_icd`),
/// and the tree's for a driver of another system's tree (`glint-sid/lvp_icd`).
pub fn short_name(file: &Path) -> String {
    let stem = file
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "icd".into());
    let stem = stem.strip_suffix(".x86_64").unwrap_or(&stem).to_owned();
    if let Some(root) = glint::drivers::tree::root_of(file) {
        let tree = root
            .file_name()
            .map_or("tree".into(), |n| n.to_string_lossy());
        return format!("{tree}/{stem}");
    }
    match file.parent().and_then(|p| p.file_name()) {
        Some(parent) if parent != "icd.d" => format!("{}/{stem}", parent.to_string_lossy()),
        _ => stem,
    }
}

/// The driver library a manifest names, where it names it by a path
/// (`library_path` with a '/', relative to the manifest's folder); None for
/// a bare name, which the dynamic loader looks up in the system's folders,
/// or a manifest that cannot be read as one.
pub fn library(manifest: &Path) -> Option<PathBuf> {
    let text = glint::input::read_text(manifest, glint::input::ReadAs::Manifest).ok()?;
    let json: serde_json::Value = serde_json::from_str(&text).ok()?;
    let named = json.get("ICD")?.get("library_path")?.as_str()?;
    named
        .contains('/')
        .then(|| glint::files::folder_of(manifest).join(named))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_manifests_library_is_found_beside_it() {
        let dir = tempfile::tempdir().unwrap();
        let m = dir.path().join("a.json");
        let write = |lib: &str| {
            std::fs::write(&m, format!(r#"{{"ICD": {{"library_path": "{lib}"}}}}"#)).unwrap()
        };
        write("./libx.so");
        assert_eq!(library(&m), Some(dir.path().join("./libx.so")));
        write("/usr/lib/liby.so");
        assert_eq!(library(&m), Some(PathBuf::from("/usr/lib/liby.so")));
        write("libvulkan_lvp.so");
        assert_eq!(library(&m), None);
    }

    #[test]
    fn short_names_say_which_driver() {
        assert_eq!(
            short_name(Path::new("/usr/share/vulkan/icd.d/lvp_icd.json")),
            "lvp_icd"
        );
        assert_eq!(
            short_name(Path::new(
                "/root/.cache/glint-drivers/mesa-22.3.6/lvp_icd.x86_64.json"
            )),
            "mesa-22.3.6/lvp_icd"
        );
    }

    #[test]
    fn a_file_named_twice_is_kept_once() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a.json");
        std::fs::write(&a, "{}").unwrap();
        let again = dir.path().join(".").join("a.json");
        assert_eq!(once([a.clone(), again, a.clone()]), vec![a]);
    }
}
