//! Shrinking a failing TOML scene by its objects: whole chunks of its
//! primitives, meshes and lights are left out while the driver still fails
//! the same way, halving the chunks down to one object (the simplest kind
//! of delta debugging), within a budget of runs.

use std::path::Path;

use super::error::{write, DriversError};

/// The most runs one scene's shrinking may take.
pub const MAX_RUNS: usize = 12;

/// Leaves out of the TOML scene at `path` (rewritten in place) every chunk
/// of objects whose absence `still_fails` confirms (its errors are the
/// caller's, `E`). The objects before and after; None where the file is
/// not TOML or has fewer than two objects.
pub fn objects<E: From<DriversError>>(
    path: &Path,
    still_fails: &mut dyn FnMut(&Path) -> Result<bool, E>,
) -> Result<Option<(usize, usize)>, E> {
    let text = std::fs::read_to_string(path).map_err(DriversError::file("read", path))?;
    let Ok(table) = text.parse::<toml::Table>() else {
        return Ok(None);
    };
    let entries: Vec<(&str, usize)> = crate::scene::object_arrays()
        .iter()
        .flat_map(|&key| {
            let n = table
                .get(key)
                .and_then(toml::Value::as_array)
                .map_or(0, Vec::len);
            (0..n).map(move |i| (key, i))
        })
        .collect();
    let n = entries.len();
    if n < 2 {
        return Ok(None);
    }
    let mut keep = vec![true; n];
    let (mut runs, mut chunk) = (0, n.div_ceil(2));
    'halving: loop {
        let mut start = 0;
        while start < n {
            if runs >= MAX_RUNS {
                break 'halving;
            }
            let end = (start + chunk).min(n);
            let mut candidate = keep.clone();
            candidate[start..end].fill(false);
            if candidate != keep && candidate.contains(&true) {
                write(path, without(&table, &entries, &candidate)?)?;
                runs += 1;
                if still_fails(path)? {
                    keep = candidate;
                }
            }
            start = end;
        }
        if chunk == 1 {
            break;
        }
        chunk = chunk.div_ceil(2);
    }
    let kept = keep.iter().filter(|k| **k).count();
    // Nothing left out: the file as it was, comments and all.
    let last = if kept == n {
        text
    } else {
        without(&table, &entries, &keep)?
    };
    write(path, last)?;
    Ok(Some((n, kept)))
}

/// `table` with only the objects `keep` marks, as TOML text.
fn without(
    table: &toml::Table,
    entries: &[(&str, usize)],
    keep: &[bool],
) -> Result<String, DriversError> {
    let mut t = table.clone();
    for &key in crate::scene::object_arrays() {
        if let Some(toml::Value::Array(rows)) = t.get_mut(key) {
            let mut i = 0;
            rows.retain(|_| {
                let k = entries
                    .iter()
                    .zip(keep)
                    .find(|((e, j), _)| *e == key && *j == i)
                    .is_none_or(|(_, k)| *k);
                i += 1;
                k
            });
            if rows.is_empty() {
                t.remove(key);
            }
        }
    }
    Ok(toml::to_string(&t)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A failure that needs spheres b and d alone is shrunk to them.
    #[test]
    fn chunks_shrink_to_the_objects_the_failure_needs() {
        let file = tempfile::Builder::new().suffix(".toml").tempfile().unwrap();
        let path = file.path();
        let mut text = String::from("[image]\nwidth = 4\nheight = 3\n");
        for name in ["a", "b", "c", "d", "e"] {
            text += &format!("[[spheres]]\nmaterial = \"{name}\"\n");
        }
        text += "[[lights]]\ntype = \"point\"\n";
        std::fs::write(path, &text).unwrap();
        let mut runs = 0;
        let got = objects::<DriversError>(path, &mut |p| {
            runs += 1;
            let t = std::fs::read_to_string(p).unwrap();
            Ok(t.contains("\"b\"") && t.contains("\"d\""))
        })
        .unwrap();
        assert_eq!(got, Some((6, 2)));
        let left = std::fs::read_to_string(path).unwrap();
        assert!(left.contains("\"b\"") && left.contains("\"d\"") && !left.contains("\"a\""));
        assert!(!left.contains("lights") && left.contains("width = 4"));
        assert!(runs <= MAX_RUNS);
    }
}
