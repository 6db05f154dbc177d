//! The table a person reads: one block per ray, one column per renderer,
//! a `*` after each value that leaves the reference's by more than its
//! f32 bound, and the bound in the last column.

use std::collections::HashMap;
use std::fmt::Write;

use super::diverge::show;
use super::flat::{self, Bound, Entry, Value};
use super::number;
use super::tree::Tree;

/// Which of the reference's quantities `entries` (a tree's) leaves past
/// its bound, or lacks.
pub fn marks(entries: &[Entry], reference: &[Entry], bounds: &[Bound]) -> Vec<bool> {
    let by_label: HashMap<&str, &Entry> = entries.iter().map(|e| (e.label.as_str(), e)).collect();
    reference
        .iter()
        .zip(bounds)
        .map(|(r, b)| match by_label.get(r.label.as_str()) {
            None => r.judged,
            Some(e) => r.judged && super::diverge::beyond(e, r, b),
        })
        .collect()
}

/// The table of `trees` (the reference last, its entries `reference`).
pub fn render(
    trees: &[Tree],
    reference: &[Entry],
    bounds: &[Bound],
    marks: &[Vec<bool>],
) -> String {
    let flats: Vec<HashMap<String, Entry>> = trees
        .iter()
        .map(|t| {
            flat::entries(t)
                .into_iter()
                .map(|e| (e.label.clone(), e))
                .collect()
        })
        .collect();
    let mut rows: Vec<(Option<usize>, String, Vec<String>, String)> = Vec::new();
    for (k, r) in reference.iter().enumerate() {
        let cells = flats
            .iter()
            .zip(marks)
            .map(|(f, m)| {
                let mark = if m[k] { " *" } else { "" };
                format!("{}{mark}", show(f.get(&r.label)))
            })
            .collect();
        let bound = match (&r.value, &bounds[k]) {
            _ if !r.judged => "(shown, not judged)".to_owned(),
            (Value::Num { .. }, b) => format!(
                "{}{}",
                number::show(b.bound),
                if b.unstable { " (ill)" } else { "" }
            ),
            (Value::Exact(_), b) if b.unstable => "ill-conditioned".to_owned(),
            _ => String::new(),
        };
        rows.push((r.ray, r.label.clone(), cells, bound));
    }
    let head: Vec<String> = trees.iter().map(|t| t.renderer.clone()).collect();
    let name_w = rows
        .iter()
        .map(|r| field(&r.1).len())
        .max()
        .unwrap_or(0)
        .max(8);
    let widths: Vec<usize> = (0..trees.len())
        .map(|c| {
            rows.iter()
                .map(|r| r.2[c].len())
                .chain([head[c].len()])
                .max()
                .unwrap_or(0)
        })
        .collect();
    let mut s = String::new();
    let line = |s: &mut String, name: &str, cells: &[String], bound: &str| {
        let mut row = format!("  {name:name_w$}");
        for (c, w) in cells.iter().zip(&widths) {
            let _ = write!(row, "  {c:w$}");
        }
        let _ = write!(row, "  {bound}");
        s.push_str(row.trim_end());
        s.push('\n');
    };
    let mut current = None;
    for (ray, label, cells, bound) in &rows {
        if *ray != current || s.is_empty() {
            current = *ray;
            let title = match ray {
                Some(n) => {
                    let t = &trees[trees.len() - 1].rays[*n];
                    format!("ray {} ({} ray, depth {})", n + 1, t.kind, t.depth)
                }
                None => "the sample".to_owned(),
            };
            if !s.is_empty() {
                s.push('\n');
            }
            let _ = writeln!(s, "{title}");
            line(&mut s, "", &head, "f32 bound");
        }
        line(&mut s, field(label), cells, bound);
    }
    s
}

/// A label without its ray: `ray 2, light 0: diffuse` is `light 0: diffuse`.
fn field(label: &str) -> &str {
    match label.split_once(", ") {
        Some((_, rest)) if label.starts_with("ray ") => rest,
        _ => label.split_once(": ").map_or(label, |(_, f)| f),
    }
}
