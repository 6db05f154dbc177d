//! `Scene.params`' keys: paths into the scene file's tables
//! (`"spheres[0].center"`, `"materials.red.diffuse"`, `"camera.eye"`), the
//! values they name, and setting one in a table.

use pyo3::exceptions::PyKeyError;
use pyo3::prelude::*;

/// One step of a key: a table's key, or an array's index.
#[derive(Debug, Clone, PartialEq)]
enum Step {
    Key(String),
    Index(usize),
}

/// The steps of `key`: names split at dots, each maybe followed by
/// `[i]`s; a name with a dot, a bracket or a space is written in double
/// quotes (`materials."red glass".diffuse`), as TOML writes it.
fn steps(key: &str) -> PyResult<Vec<Step>> {
    let bad = |why: &str| PyKeyError::new_err(format!("{key:?}: {why}"));
    let mut out = Vec::new();
    let mut rest = key;
    loop {
        let name;
        if let Some(q) = rest.strip_prefix('"') {
            let (unquoted, after) = quoted(q).ok_or_else(|| bad("a quote is not closed"))?;
            name = unquoted;
            rest = after;
        } else {
            let end = rest.find(['.', '[']).unwrap_or(rest.len());
            name = rest[..end].to_owned();
            rest = &rest[end..];
        }
        if name.is_empty() {
            return Err(bad("an empty name"));
        }
        out.push(Step::Key(name));
        while let Some(r) = rest.strip_prefix('[') {
            let end = r.find(']').ok_or_else(|| bad("a bracket is not closed"))?;
            let i = r[..end]
                .parse()
                .map_err(|_| bad("an index is a whole number >= 0"))?;
            out.push(Step::Index(i));
            rest = &r[end + 1..];
        }
        match rest.strip_prefix('.') {
            Some(r) => rest = r,
            None if rest.is_empty() => return Ok(out),
            None => return Err(bad("a name is followed by a dot or an index")),
        }
    }
}

/// The name in a quoted step (`q` is the text after its opening quote),
/// its escapes read as TOML's basic strings have them (`\"`, `\\`,
/// `\uXXXX`), and the text after its closing quote; None where it is not
/// closed.
fn quoted(q: &str) -> Option<(String, &str)> {
    let mut name = String::new();
    let mut chars = q.char_indices();
    while let Some((i, c)) = chars.next() {
        match c {
            '"' => return Some((name, &q[i + 1..])),
            '\\' => match chars.next()?.1 {
                'u' => {
                    let hex: String = (0..4)
                        .filter_map(|_| chars.next().map(|(_, c)| c))
                        .collect();
                    name.push(char::from_u32(u32::from_str_radix(&hex, 16).ok()?)?);
                }
                e => name.push(e),
            },
            c => name.push(c),
        }
    }
    None
}

/// A table key as a step of a key: quoted where it is not bare, with `"`,
/// `\` and control characters escaped, so that every key `params` lists
/// reads back (a material named `say "hi"` was listed as a key no read
/// could parse).
fn name(k: &str) -> String {
    let bare = !k.is_empty()
        && k.chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
    if bare {
        return k.to_owned();
    }
    let mut out = String::from("\"");
    for c in k.chars() {
        match c {
            '"' | '\\' => {
                out.push('\\');
                out.push(c);
            }
            c if c.is_control() => out.push_str(&format!("\\u{:04x}", u32::from(c))),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// Whether a value is one `params` lists: a number, or a list of numbers.
fn is_value(v: &toml::Value) -> bool {
    let number = |v: &toml::Value| matches!(v, toml::Value::Integer(_) | toml::Value::Float(_));
    match v {
        toml::Value::Array(a) => !a.is_empty() && a.iter().all(number),
        v => number(v),
    }
}

/// Keys `params` does not list, though they may be set: the image's size
/// and sampling and the ray tree's depth, which are the render's settings
/// rather than the scene's values (a new depth compiles a new shader).
fn is_setting(key: &str) -> bool {
    key.starts_with("image.") || key == "render.max_depth"
}

/// A key of `params`, read into its steps.
pub struct Key<'k> {
    text: &'k str,
    steps: Vec<Step>,
}

impl<'k> Key<'k> {
    pub fn parse(text: &'k str) -> PyResult<Self> {
        Ok(Key {
            text,
            steps: steps(text)?,
        })
    }

    /// Whether its first name is the spheres' array.
    pub fn of_spheres(&self) -> bool {
        self.steps.first() == Some(&Step::Key(SPHERES.to_owned()))
    }

    /// The sphere whose value it names (`spheres[3].radius`: 3); None for
    /// any other key, and for a sphere's whole table.
    pub fn in_sphere(&self) -> Option<usize> {
        match self.steps.as_slice() {
            [Step::Key(k), Step::Index(i), _, ..] if k == SPHERES => Some(*i),
            _ => None,
        }
    }

    /// The KeyError of a sphere the scene does not have.
    pub fn no_sphere(&self) -> PyErr {
        missing(self, 1)
    }
}

/// The spheres' array: the one a large scene is made of, whose entries a
/// scene's text keeps apart (`Document`).
pub const SPHERES: &str = "spheres";

/// The key of sphere `i`'s table, as `params` lists it.
pub fn sphere_key(i: usize) -> String {
    format!("{SPHERES}[{i}]")
}

/// A root key as `params` lists it.
pub fn root_key(k: &str) -> String {
    name(k)
}

/// Calls `out` with each key under `at` that `params` lists and its value,
/// in the file's order (`v` is the value at `at`).
pub fn list(
    v: &toml::Value,
    at: String,
    out: &mut dyn FnMut(String, &toml::Value) -> PyResult<()>,
) -> PyResult<()> {
    match v {
        v if is_value(v) && !is_setting(&at) => out(at, v),
        v if is_value(v) => Ok(()),
        toml::Value::Table(t) => {
            for (k, x) in t {
                let key = if at.is_empty() {
                    name(k)
                } else {
                    format!("{at}.{}", name(k))
                };
                list(x, key, out)?;
            }
            Ok(())
        }
        toml::Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                list(x, format!("{at}[{i}]"), out)?;
            }
            Ok(())
        }
        _ => Ok(()),
    }
}

/// The value at `key` in the file's `table`, None where there is none.
pub fn get<'t>(table: &'t toml::Table, key: &Key) -> Option<&'t toml::Value> {
    get_from(table, key, 0)
}

/// The value at `key` (`key.in_sphere()`) in its sphere's own table.
pub fn get_in_sphere<'t>(sphere: &'t toml::Table, key: &Key) -> Option<&'t toml::Value> {
    get_from(sphere, key, 2)
}

/// The value at `key`'s steps from `from` on, in `table`.
fn get_from<'t>(table: &'t toml::Table, key: &Key, from: usize) -> Option<&'t toml::Value> {
    let mut at: Option<&toml::Value> = None;
    for (n, step) in key.steps[from..].iter().enumerate() {
        at = match (n, at, step) {
            (0, _, Step::Key(k)) => table.get(k),
            (_, Some(toml::Value::Table(t)), Step::Key(k)) => t.get(k),
            (_, Some(toml::Value::Array(a)), Step::Index(i)) => a.get(*i),
            _ => None,
        };
        at?;
    }
    at
}

/// Sets `key` in `table` to `value` (None: removes it). A key gives or
/// replaces a value of a table or of an array's entry. A missing section
/// of the file on its way (`render` for `"render.max_depth"`) is made (the
/// scene's check refuses one it does not know); a missing entry further in
/// (`materials.rde`, a misspelt material) is a KeyError naming it, unless
/// `create` (`params.add`); a missing array entry is always one.
pub fn set(
    table: &mut toml::Table,
    key: &Key,
    value: Option<toml::Value>,
    create: bool,
) -> PyResult<()> {
    set_from(table, key, 0, value, create)
}

/// As [`set`], in the sphere's own table that `key.in_sphere()` names.
pub fn set_in_sphere(
    sphere: &mut toml::Table,
    key: &Key,
    value: Option<toml::Value>,
    create: bool,
) -> PyResult<()> {
    set_from(sphere, key, 2, value, create)
}

fn set_from(
    table: &mut toml::Table,
    key: &Key,
    from: usize,
    value: Option<toml::Value>,
    create: bool,
) -> PyResult<()> {
    let mut root = toml::Value::Table(std::mem::take(table));
    let result = set_in(&mut root, key, from, value, create);
    if let toml::Value::Table(t) = root {
        *table = t;
    }
    result
}

/// The KeyError of a key whose steps up to `at` name nothing.
fn missing(key: &Key, at: usize) -> PyErr {
    PyKeyError::new_err(format!(
        "{:?}: the scene has no {} (a key gives a value to an entry that the \
         scene has; add entries with params.add, or to_dict and from_dict)",
        key.text,
        shown(&key.steps[..=at])
    ))
}

fn set_in(
    v: &mut toml::Value,
    key: &Key,
    at: usize,
    value: Option<toml::Value>,
    create: bool,
) -> PyResult<()> {
    let steps = &key.steps;
    let step = &steps[at];
    if at + 1 == steps.len() {
        return match (v, step, value) {
            (toml::Value::Table(t), Step::Key(k), Some(x)) => {
                t.insert(k.clone(), x);
                Ok(())
            }
            (toml::Value::Table(t), Step::Key(k), None) => match t.remove(k) {
                Some(_) => Ok(()),
                None => Err(missing(key, at)),
            },
            (toml::Value::Array(a), Step::Index(i), Some(x)) if *i < a.len() => {
                a[*i] = x;
                Ok(())
            }
            (toml::Value::Array(_), Step::Index(_), None) => Err(PyKeyError::new_err(format!(
                "{:?}: an array's entry cannot be removed (to_dict and from_dict can)",
                key.text
            ))),
            _ => Err(missing(key, at)),
        };
    }
    let next = match (v, step, &steps[at + 1]) {
        // A section of the file is made where it is missing (`render` for
        // "render.max_depth"), an entry in one only where asked; an
        // array's entry never is.
        (toml::Value::Table(t), Step::Key(k), Step::Key(_)) if at == 0 || create => Some(
            t.entry(k.clone())
                .or_insert_with(|| toml::Value::Table(toml::Table::new())),
        ),
        (toml::Value::Table(t), Step::Key(k), Step::Key(_)) => t.get_mut(k),
        (toml::Value::Table(t), Step::Key(k), Step::Index(_)) => t.get_mut(k),
        (toml::Value::Array(a), Step::Index(i), _) => a.get_mut(*i),
        _ => None,
    };
    match next {
        Some(next) => set_in(next, key, at + 1, value, create),
        None => Err(missing(key, at)),
    }
}

/// Steps written back as a key.
fn shown(steps: &[Step]) -> String {
    let mut out = String::new();
    for s in steps {
        match s {
            Step::Key(k) => {
                if !out.is_empty() {
                    out.push('.');
                }
                out.push_str(&name(k));
            }
            Step::Index(i) => out.push_str(&format!("[{i}]")),
        }
    }
    out
}
