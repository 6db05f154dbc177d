//! The reproducers' folder names: readable, short, and unique to their
//! input.

use std::path::Path;

/// The longest readable part of a folder name.
const FOLDER_NAME: usize = 40;

/// A folder's name for `name`, unique to `key` (the path it came from, as
/// given): the name's letters, digits, '-', '_' and inner '.', at most
/// [`FOLDER_NAME`] of them, and 8 hex digits of `key`'s hash. Never "." or
/// "..", so never outside `repro/`; two inputs of one name, or of two
/// names that the letters alone make one, get two folders; and a name of
/// any length makes a short one.
pub(super) fn folder(name: &str, key: &Path) -> String {
    use std::hash::Hasher;
    use std::os::unix::ffi::OsStrExt;
    let safe: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "._-".contains(c) {
                c
            } else {
                '-'
            }
        })
        .collect();
    let mut readable: String = safe.trim_matches('.').chars().take(FOLDER_NAME).collect();
    if readable.is_empty() {
        readable.push('x');
    }
    let mut hash = glint::fnv::Fnv::default();
    hash.write(key.as_os_str().as_bytes());
    format!("{readable}-{:08x}", hash.finish() as u32)
}

#[cfg(test)]
mod tests {
    use super::folder;
    use std::path::Path;

    #[test]
    fn folders_stay_inside_are_short_and_unique_to_their_input() {
        for name in ["..", ".", "...", "", "a/../..", "/"] {
            let f = folder(name, Path::new(name));
            assert!(!f.starts_with('.') && !f.contains('/'), "{name:?}: {f}");
        }
        assert_ne!(
            folder("s", Path::new("a/s.toml")),
            folder("s", Path::new("b/s.toml"))
        );
        assert_ne!(
            folder("x y", Path::new("x y.json")),
            folder("x-y", Path::new("x-y.json"))
        );
        let long = "n".repeat(245);
        assert!(folder(&long, Path::new(&long)).len() <= 49);
    }
}
