//! Maps between key paths (`spheres[2].radius`) and places in the scene text,
//! so that every error names the file, the line and the key.

use std::fmt;
use std::ops::Range;

use toml_edit::{ImDocument, Item, Value};

/// One step of a key path.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Seg {
    Key(String),
    Index(usize),
}

/// A key path such as `lights[1].cutoff`.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct KeyPath(pub Vec<Seg>);

impl KeyPath {
    pub fn key(&self, k: &str) -> Self {
        let mut p = self.clone();
        p.0.push(Seg::Key(k.to_owned()));
        p
    }
    pub fn index(&self, i: usize) -> Self {
        let mut p = self.clone();
        p.0.push(Seg::Index(i));
        p
    }
}

impl fmt::Display for KeyPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (n, seg) in self.0.iter().enumerate() {
            match seg {
                Seg::Key(k) if n == 0 => write!(f, "{k}")?,
                Seg::Key(k) => write!(f, ".{k}")?,
                Seg::Index(i) => write!(f, "[{i}]")?,
            }
        }
        Ok(())
    }
}

/// A 1-based line and column.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LineCol {
    pub line: usize,
    pub column: usize,
}

pub fn line_col(text: &str, offset: usize) -> LineCol {
    let offset = offset.min(text.len());
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    LineCol {
        line,
        column: before[line_start..].chars().count() + 1,
    }
}

/// Where in its file a key path was written: the line and column of a TOML
/// value, or the line of the NFF entity a table came from.
pub trait Locate {
    fn find(&self, path: &KeyPath) -> Option<LineCol>;
}

impl Locate for Located {
    fn find(&self, path: &KeyPath) -> Option<LineCol> {
        Located::find(self, path)
    }
}

/// The text of a scene, kept to locate errors. Its document (with the span
/// of every key) is parsed only when an error asks where: it takes about
/// 20 times the text's size, which a scene that loads never needs.
pub struct Located {
    doc: std::cell::OnceCell<Option<ImDocument<String>>>,
    text: String,
}

impl Located {
    pub fn new(text: &str) -> Self {
        Self {
            doc: std::cell::OnceCell::new(),
            text: text.to_owned(),
        }
    }

    fn doc(&self) -> Option<&ImDocument<String>> {
        self.doc
            .get_or_init(|| ImDocument::parse(self.text.clone()).ok())
            .as_ref()
    }

    /// Where the value at `path` starts; where the path runs out (a missing
    /// key), the deepest table that exists.
    pub fn find(&self, path: &KeyPath) -> Option<LineCol> {
        let doc = self.doc()?;
        let mut best = None;
        let mut walk = Walk::Table(doc.as_table());
        for seg in &path.0 {
            match walk.child(seg) {
                Some(next) => {
                    if let Some(span) = next.span() {
                        best = Some(span.start);
                    }
                    walk = next;
                }
                None => break,
            }
        }
        best.map(|o| line_col(&self.text, o))
    }

    /// The key path of the smallest value whose text holds the byte range
    /// `span` (table spans cover only their headers, so the whole tree is
    /// searched rather than descended).
    pub fn path_at(&self, span: &Range<usize>) -> Option<KeyPath> {
        fn search(
            walk: Walk,
            path: &mut KeyPath,
            span: &Range<usize>,
            best: &mut Option<(usize, KeyPath)>,
        ) {
            for (seg, child) in walk.children() {
                path.0.push(seg);
                if let Some(s) = child.span() {
                    let holds = s.start <= span.start && span.end <= s.end.max(s.start + 1);
                    if holds && best.as_ref().is_none_or(|(len, _)| s.len() <= *len) {
                        *best = Some((s.len(), path.clone()));
                    }
                }
                search(child, path, span, best);
                path.0.pop();
            }
        }
        let doc = self.doc()?;
        let mut best = None;
        search(
            Walk::Table(doc.as_table()),
            &mut KeyPath::default(),
            span,
            &mut best,
        );
        best.map(|(_, p)| p)
    }

    pub fn line_col(&self, offset: usize) -> LineCol {
        line_col(&self.text, offset)
    }

    /// Whether a TOML date-time starts at `offset` (four digits and a dash).
    pub fn is_datetime_at(&self, offset: usize) -> bool {
        let t = self.text.as_bytes().get(offset..).unwrap_or_default();
        t.len() >= 5 && t[..4].iter().all(u8::is_ascii_digit) && t[4] == b'-'
    }

    /// For text that toml_edit cannot parse: the key of the `key = value`
    /// line holding `offset`, under the last `[table]` header above it.
    pub fn key_on_line(&self, offset: usize) -> Option<KeyPath> {
        let before = self.text.get(..offset.min(self.text.len()))?;
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let line = self.text[line_start..].lines().next()?;
        let (key, _) = line.split_once('=')?;
        let key = key.trim();
        if key.is_empty() || key.starts_with('[') {
            return None;
        }
        let table = before[..line_start].lines().rev().find_map(|l| {
            let l = l.trim();
            (l.starts_with('[') && !l.starts_with("[["))
                .then(|| l.trim_matches(['[', ']']).trim().to_owned())
                .or_else(|| {
                    l.starts_with("[[")
                        .then(|| l.trim_matches(['[', ']']).trim().to_owned())
                })
        });
        let mut path = KeyPath::default();
        if let Some(t) = table {
            for seg in t.split('.') {
                path = path.key(seg.trim());
            }
        }
        Some(path.key(key))
    }
}

/// A position in the document: toml_edit keeps tables, arrays of tables and
/// values in different types, so the walk names which one it stands on.
#[derive(Clone, Copy)]
enum Walk<'a> {
    Table(&'a toml_edit::Table),
    Tables(&'a toml_edit::ArrayOfTables),
    Value(&'a Value),
    Nothing,
}

impl<'a> Walk<'a> {
    fn from_item(item: &'a Item) -> Self {
        match item {
            Item::Table(t) => Walk::Table(t),
            Item::ArrayOfTables(a) => Walk::Tables(a),
            Item::Value(v) => Walk::Value(v),
            Item::None => Walk::Nothing,
        }
    }

    fn span(self) -> Option<Range<usize>> {
        match self {
            Walk::Table(t) => t.span(),
            Walk::Tables(a) => a.span(),
            Walk::Value(v) => v.span(),
            Walk::Nothing => None,
        }
    }

    fn child(self, seg: &Seg) -> Option<Walk<'a>> {
        match (self, seg) {
            (Walk::Table(t), Seg::Key(k)) => t.get(k).map(Walk::from_item),
            (Walk::Tables(a), Seg::Index(i)) => a.get(*i).map(Walk::Table),
            (Walk::Value(Value::InlineTable(t)), Seg::Key(k)) => t.get(k).map(Walk::Value),
            (Walk::Value(Value::Array(a)), Seg::Index(i)) => a.get(*i).map(Walk::Value),
            _ => None,
        }
    }

    fn children(self) -> Vec<(Seg, Walk<'a>)> {
        match self {
            Walk::Table(t) => t
                .iter()
                .map(|(k, item)| (Seg::Key(k.to_owned()), Walk::from_item(item)))
                .collect(),
            Walk::Tables(a) => a
                .iter()
                .enumerate()
                .map(|(i, t)| (Seg::Index(i), Walk::Table(t)))
                .collect(),
            Walk::Value(Value::InlineTable(t)) => t
                .iter()
                .map(|(k, v)| (Seg::Key(k.to_owned()), Walk::Value(v)))
                .collect(),
            Walk::Value(Value::Array(a)) => a
                .iter()
                .enumerate()
                .map(|(i, v)| (Seg::Index(i), Walk::Value(v)))
                .collect(),
            _ => Vec::new(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = "[image]\nwidth = 8\n\n[[spheres]]\ncenter = [1.0, 2.0, 3.0]\n\n[[spheres]]\ncenter = [4.0, nan, 6.0]\n";

    fn path(segs: &[Seg]) -> KeyPath {
        KeyPath(segs.to_vec())
    }

    #[test]
    fn key_paths_print_like_toml() {
        let p = KeyPath::default()
            .key("spheres")
            .index(2)
            .key("center")
            .index(1);
        assert_eq!(p.to_string(), "spheres[2].center[1]");
    }

    #[test]
    fn paths_locate_values_in_arrays_of_tables() {
        let l = Located::new(TEXT);
        let p = path(&[
            Seg::Key("spheres".into()),
            Seg::Index(1),
            Seg::Key("center".into()),
            Seg::Index(1),
        ]);
        assert_eq!(
            l.find(&p),
            Some(LineCol {
                line: 8,
                column: 16
            })
        );
        let missing = path(&[
            Seg::Key("spheres".into()),
            Seg::Index(0),
            Seg::Key("radius".into()),
        ]);
        assert_eq!(l.find(&missing).map(|a| a.line), Some(4));
    }

    #[test]
    fn spans_map_back_to_the_deepest_key() {
        let l = Located::new(TEXT);
        let offset = TEXT.find("nan").unwrap();
        let p = l.path_at(&(offset..offset + 3)).unwrap();
        assert_eq!(p.to_string(), "spheres[1].center[1]");
    }
}
