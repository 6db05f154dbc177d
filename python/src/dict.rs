//! A scene's dict and its TOML text, both ways: `Scene.from_dict` writes
//! a dict as the TOML file it stands for, `Scene.to_dict` reads a scene
//! file's TOML into a dict.

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};

use crate::arrays::{ArrayFiles, MESH_ARRAYS};

/// A TOML value as Python's: a table a dict, an array a list.
pub fn to_python<'py>(py: Python<'py>, v: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        toml::Value::String(s) => s.into_pyobject(py)?.into_any(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        toml::Value::Float(f) => f.into_pyobject(py)?.into_any(),
        toml::Value::Boolean(b) => b.into_pyobject(py)?.to_owned().into_any(),
        toml::Value::Datetime(d) => d.to_string().into_pyobject(py)?.into_any(),
        toml::Value::Array(a) => {
            let list = PyList::empty(py);
            for x in a {
                list.append(to_python(py, x)?)?;
            }
            list.into_any()
        }
        toml::Value::Table(t) => {
            let d = PyDict::new(py);
            for (k, x) in t {
                d.set_item(k, to_python(py, x)?)?;
            }
            d.into_any()
        }
    })
}

/// How deep a scene's dict may nest: a scene file's tables go 3 deep; past
/// this a dict or list holds itself, or was built to crash the reader
/// (10,000 levels overflowed the stack, SIGSEGV).
const MAX_NESTING: usize = 64;

/// A Python value as TOML text, appended to `out` (a dict's entries as
/// inline tables): written as it is walked, with no tree of values beside
/// the text (200,000 spheres took 630 MB as `toml::Value`s, 40 MB as
/// text). `at` is its key path, for the error.
fn to_toml(v: &Bound<'_, PyAny>, at: &str, depth: usize, out: &mut String) -> PyResult<()> {
    let shown = || {
        if at.is_empty() {
            "the scene".to_owned()
        } else {
            glint::printable::text(at)
        }
    };
    let named = |what: &str| {
        PyTypeError::new_err(format!(
            "{}: {what} has no TOML form (numbers, strings, booleans, lists and dicts do)",
            shown()
        ))
    };
    if depth > MAX_NESTING {
        return Err(PyValueError::new_err(format!(
            "{}: nested more than {MAX_NESTING} deep (a dict or list that holds itself?)",
            shown()
        )));
    }
    if v.is_none() {
        return Err(named("None"));
    }
    if let Ok(b) = v.cast::<pyo3::types::PyBool>() {
        out.push_str(if b.is_true() { "true" } else { "false" });
        return Ok(());
    }
    if let Ok(d) = v.cast::<PyDict>() {
        out.push('{');
        for (n, (k, item)) in d.iter().enumerate() {
            let (k, path) = key_of(&k, at, &named)?;
            if n > 0 {
                out.push_str(", ");
            }
            toml_key(&k, out);
            out.push_str(" = ");
            to_toml(&item, &path, depth + 1, out)?;
        }
        out.push('}');
        return Ok(());
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        out.push('[');
        for (i, item) in v.try_iter()?.enumerate() {
            if i > 0 {
                out.push_str(", ");
            }
            to_toml(&item?, &format!("{at}[{i}]"), depth + 1, out)?;
        }
        out.push(']');
        return Ok(());
    }
    if let Ok(s) = v.extract::<String>() {
        quoted(&s, out);
        return Ok(());
    }
    // A numpy array or scalar: its plain Python form.
    if v.hasattr("tolist")? && !v.is_instance_of::<pyo3::types::PyFloat>() {
        return to_toml(&v.call_method0("tolist")?, at, depth + 1, out);
    }
    if let Ok(i) = v.extract::<i64>() {
        out.push_str(&i.to_string());
        return Ok(());
    }
    if let Ok(f) = v.extract::<f64>() {
        out.push_str(&toml::Value::Float(f).to_string());
        return Ok(());
    }
    Err(named(&format!("a {}", v.get_type().name()?)))
}

/// A Python value as a TOML value (`Scene.params`' values): as `to_toml`
/// writes it, read back. `at` is its key, for the error.
pub fn value(v: &Bound<'_, PyAny>, at: &str) -> PyResult<toml::Value> {
    let mut text = String::from("v = ");
    to_toml(v, at, 0, &mut text)?;
    let mut table: toml::Table = toml::from_str(&text)
        .map_err(|e| PyValueError::new_err(format!("{at}: {}", e.message())))?;
    Ok(table.remove("v").expect("the value was written as v"))
}

/// A dict's key as a string, and its key path under `at`.
fn key_of(
    k: &Bound<'_, PyAny>,
    at: &str,
    named: &dyn Fn(&str) -> PyErr,
) -> PyResult<(String, String)> {
    let k: String = k.extract().map_err(|_| {
        named(&format!(
            "the key {}",
            k.repr().map_or_else(|_| "?".into(), |r| r.to_string())
        ))
    })?;
    let path = if at.is_empty() {
        k.clone()
    } else {
        format!("{at}.{k}")
    };
    Ok((k, path))
}

/// The scene's dict as a TOML file reads: a table's plain values first,
/// then a `[table]` for each dict in it and a `[[table]]` for each list of
/// dicts (the primitives and lights), their entries a line each, nested
/// dicts as sections of their own. glint's parser reads a file of this
/// shape in about the text's size; one with inline tables took 10 times
/// that (200,000 spheres took 430 MB with one `m = {...}`).
pub fn top_level(d: &Bound<'_, PyDict>, out: &mut String, files: &mut ArrayFiles) -> PyResult<()> {
    section(d, &[], "", 0, out, files)
}

/// Whether `v` is a non-empty list of dicts: an array of tables.
fn is_rows(v: &Bound<'_, PyAny>) -> bool {
    v.cast::<PyList>()
        .is_ok_and(|l| !l.is_empty() && l.iter().all(|i| i.cast::<PyDict>().is_ok()))
}

/// The entries of table `d`, whose header is `keys` (none: the top), at
/// key path `at`, `depth` tables down.
fn section(
    d: &Bound<'_, PyDict>,
    keys: &[String],
    at: &str,
    depth: usize,
    out: &mut String,
    files: &mut ArrayFiles,
) -> PyResult<()> {
    let named = |what: &str| {
        PyTypeError::new_err(format!(
            "{}: {what} has no TOML form (numbers, strings, booleans, lists and dicts do)",
            if at.is_empty() {
                "the scene".to_owned()
            } else {
                glint::printable::text(at)
            }
        ))
    };
    if depth > MAX_NESTING {
        return Err(PyValueError::new_err(format!(
            "{}: nested more than {MAX_NESTING} deep (a dict or list that holds itself?)",
            glint::printable::text(at)
        )));
    }
    let mut later = Vec::new();
    for (k, item) in d.iter() {
        let (name, path) = key_of(&k, at, &named)?;
        if item.cast::<PyDict>().is_ok() || is_rows(&item) {
            later.push((name, path, item));
        } else if name == "image" && item.hasattr("shape")? {
            // A texture's image as an array: a file of its own.
            let file = files.image(&item, &path)?;
            out.push_str("image = ");
            quoted(&file, out);
            out.push('\n');
        } else {
            toml_key(&name, out);
            out.push_str(" = ");
            to_toml(&item, &path, depth + 1, out)?;
            out.push('\n');
        }
    }
    let header = |out: &mut String, keys: &[String], rows: bool| {
        out.push_str(if rows { "\n[[" } else { "\n[" });
        for (n, k) in keys.iter().enumerate() {
            if n > 0 {
                out.push('.');
            }
            toml_key(k, out);
        }
        out.push_str(if rows { "]]\n" } else { "]\n" });
    };
    for (name, path, item) in later {
        let mut keys = keys.to_vec();
        keys.push(name);
        if let Ok(table) = item.cast::<PyDict>() {
            // A table of tables alone takes no header of its own: its
            // sections define it, and glint's parser reads a table named
            // both ways (`[materials]`, then `[materials.m]`) 10 times
            // slower.
            let plain = table
                .iter()
                .any(|(_, v)| v.cast::<PyDict>().is_err() && !is_rows(&v));
            if plain || table.is_empty() {
                header(out, &keys, false);
            }
            section(table, &keys, &path, depth + 1, out, files)?;
        } else {
            for (i, row) in item.try_iter()?.enumerate() {
                let row = row?;
                header(out, &keys, true);
                let row = row.cast::<PyDict>().map_err(|_| named("a row"))?;
                // A mesh given as arrays: an OBJ file of its own, named in
                // place of the arrays.
                let arrays = keys.len() == 1
                    && keys[0] == "meshes"
                    && (row.contains("vertices")? || row.contains("faces")?);
                if arrays {
                    let file = files.mesh(row, &format!("{path}[{i}]"))?;
                    out.push_str("file = ");
                    quoted(&file, out);
                    out.push('\n');
                }
                // A row's own dicts go inline: a section under a row of an
                // array would need its header after every row.
                for (k, v) in row.iter() {
                    if arrays
                        && k.extract::<String>()
                            .is_ok_and(|k| MESH_ARRAYS.contains(&k.as_str()))
                    {
                        continue;
                    }
                    let (k, p) = key_of(&k, &format!("{path}[{i}]"), &named)?;
                    toml_key(&k, out);
                    out.push_str(" = ");
                    to_toml(&v, &p, depth + 2, out)?;
                    out.push('\n');
                }
            }
        }
    }
    Ok(())
}

/// `k` as a TOML key: bare where TOML allows one (a quoted key costs the
/// parser more: each keeps its own text), else quoted.
fn toml_key(k: &str, out: &mut String) {
    if !k.is_empty()
        && k.chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    {
        out.push_str(k);
    } else {
        quoted(k, out);
    }
}

/// `s` as a TOML basic string on one line (inside an inline table a
/// multi-line string may not stand).
fn quoted(s: &str, out: &mut String) {
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if c.is_control() => out.push_str(&format!("\\u{:04X}", u32::from(c))),
            c => out.push(c),
        }
    }
    out.push('"');
}
