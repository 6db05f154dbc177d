//! The table a person reads: one block per ray, one column per renderer,
//! a `*` after each value that leaves the reference's by more than its
//! f32 bound, and the bound in the last column.

use std::collections::HashMap;
use std::fmt::Write;

use super::diverge::show;
use super::flat::{self, Bound, Entry, Label, Value};
use super::number;
use super::tree::Tree;

/// Which of the reference's quantities `tree` leaves past its bound, or
/// lacks: walked beside the reference while the two agree in shape, by
/// label past where they part.
pub fn marks(tree: &Tree, reference: &[Entry], bounds: &[Bound]) -> Vec<bool> {
    let mark = |e: Option<&Entry>, r: &Entry, b: &Bound| match e {
        None => r.judged,
        Some(e) => r.judged && super::diverge::beyond(e, r, b),
    };
    let mut out = Vec::with_capacity(reference.len());
    let mut walk = flat::walk(tree);
    for (r, b) in reference.iter().zip(bounds) {
        match walk.next() {
            Some(e) if e.label == r.label => out.push(mark(Some(&e), r, b)),
            _ => break,
        }
    }
    let parted = out.len();
    if parted < reference.len() {
        let all = flat::entries(tree);
        let by_label: HashMap<Label, &Entry> = all.iter().map(|e| (e.label, e)).collect();
        for (r, b) in reference[parted..].iter().zip(&bounds[parted..]) {
            out.push(mark(by_label.get(&r.label).copied(), r, b));
        }
    }
    out
}

/// A tree of more rays than this is shown in part: the first ray, the
/// rays on the path to each first divergence, and a line for the rest
/// (1,953 rays printed 55 MB).
pub const FULL_RAYS: usize = 64;

/// The rays of `reference` (the f64 tree) to show in full, where it has
/// more than `FULL_RAYS`: the first, and each of `focus` (the rays of the
/// first divergences) with the rays that led to it; None: every ray.
pub fn shown_rays(reference: &Tree, focus: &[usize]) -> Option<Vec<bool>> {
    let rays = &reference.rays;
    if rays.len() <= FULL_RAYS {
        return None;
    }
    let mut shown = vec![false; rays.len()];
    shown[0] = true;
    for &f in focus {
        let mut n = f.min(rays.len() - 1);
        loop {
            shown[n] = true;
            match parent(rays, n) {
                Some(p) => n = p,
                None => break,
            }
        }
    }
    Some(shown)
}

/// The ray that spawned ray `n`: of the earlier rays one shallower, the
/// latest whose hit point is nearest `n`'s origin (a refraction ray waits
/// on a stack, so the latest alone is not always its parent).
fn parent(rays: &[super::tree::TreeRay], n: usize) -> Option<usize> {
    let r = &rays[n];
    let dist = |p: &[f64; 3]| {
        p.iter()
            .zip(&r.origin)
            .map(|(a, b)| (a - b) * (a - b))
            .sum::<f64>()
    };
    (0..n)
        .rev()
        .filter(|&m| rays[m].depth + 1 == r.depth)
        .filter_map(|m| rays[m].hit.as_ref().map(|h| (m, dist(&h.point))))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(m, _)| m)
}

/// One quantity as the table shows it: a row of every renderer's value.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Row {
    /// Its ray, by its place in the tree (None: the sample).
    pub ray: Option<usize>,
    /// Its whole label (`ray 2, light 0: diffuse`), as a divergence names it.
    pub label: String,
    /// Its label without the ray (`light 0: diffuse`).
    pub field: String,
    /// Each tree's value as printed, in the trees' order (the reference last).
    pub values: Vec<String>,
    /// Whether each value leaves the reference's past the bound.
    pub past: Vec<bool>,
    /// The f32 bound, or why there is none.
    pub bound: String,
}

/// The rows of `trees` (the reference last), each laid flat in `columns`,
/// for the rays `shown` (None: all).
pub fn rows(
    columns: &[&[Entry]],
    bounds: &[Bound],
    marks: &[Vec<bool>],
    shown: Option<&[bool]>,
) -> Vec<Row> {
    let reference = *columns.last().expect("the reference's entries");
    let full = |ray: Option<usize>| ray.is_none_or(|n| shown.is_none_or(|s| s[n]));
    // Only the rows shown are looked up.
    let flats: Vec<HashMap<Label, &Entry>> = columns
        .iter()
        .map(|c| {
            c.iter()
                .filter(|e| full(e.ray()))
                .map(|e| (e.label, e))
                .collect()
        })
        .collect();
    let mut rows = Vec::new();
    for (k, r) in reference.iter().enumerate() {
        if !full(r.ray()) {
            continue;
        }
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
        rows.push(Row {
            ray: r.ray(),
            label: r.label.to_string(),
            field: r.label.field(),
            values: flats
                .iter()
                .map(|f| show(f.get(&r.label).copied()))
                .collect(),
            past: marks.iter().map(|m| m[k]).collect(),
            bound,
        });
    }
    rows
}

/// The table of `trees` (the reference last) from their `rows`, the rays
/// `shown` in full (None: all) and a line for the others (`reference`,
/// the reference's entries, and `marks` count them).
pub fn render(
    trees: &[Tree],
    rows: &[Row],
    reference: &[Entry],
    marks: &[Vec<bool>],
    shown: Option<&[bool]>,
) -> String {
    let rows: Vec<(Option<usize>, String, Vec<String>, String)> = rows
        .iter()
        .map(|r| {
            let cells = r
                .values
                .iter()
                .zip(&r.past)
                .map(|(v, &past)| format!("{v}{}", if past { " *" } else { "" }))
                .collect();
            (r.ray, r.field.clone(), cells, r.bound.clone())
        })
        .collect();
    let head: Vec<String> = trees.iter().map(|t| t.renderer.clone()).collect();
    let name_w = rows.iter().map(|r| r.1.len()).max().unwrap_or(0).max(8);
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
    let mut note = hidden_note(trees, reference, marks, shown);
    let mut current = None;
    for (ray, label, cells, bound) in &rows {
        if ray.is_none() {
            if let Some(n) = note.take() {
                let _ = write!(s, "\n{n}\n");
            }
        }
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
        line(&mut s, label, cells, bound);
    }
    s
}

/// A line for the rays not shown: how many, how deep, and how many hold a
/// value past its bound in a judged column.
fn hidden_note(
    trees: &[Tree],
    reference: &[Entry],
    marks: &[Vec<bool>],
    shown: Option<&[bool]>,
) -> Option<String> {
    let shown = shown?;
    let rays = &trees.last()?.rays;
    let hidden: Vec<usize> = (0..rays.len()).filter(|&n| !shown[n]).collect();
    if hidden.is_empty() {
        return None;
    }
    let deepest = hidden.iter().map(|&n| rays[n].depth).max().unwrap_or(0);
    let shallowest = hidden.iter().map(|&n| rays[n].depth).min().unwrap_or(0);
    let mut past = vec![false; rays.len()];
    for (k, e) in reference.iter().enumerate() {
        if let Some(n) = e.ray() {
            past[n] |= marks.iter().any(|m| m[k]);
        }
    }
    let marked = hidden.iter().filter(|&&n| past[n]).count();
    Some(format!(
        "{} more rays, {shallowest} to {deepest} deep, are not shown ({}): the first ray and the path to each first divergence are; `glint explain --json` holds every ray",
        hidden.len(),
        match marked {
            0 => "every quantity of theirs is within its bound".to_owned(),
            m => format!("{m} of them hold a value past its bound"),
        }
    ))
}
