//! The library's modules stand in layers, and a module uses only those
//! below it (docs/architecture.md, Layers): read from every `crate::`,
//! `super::` and `self::` path in src/, so that no loop of imports can
//! come back. The command line (src/main.rs, src/cli/) is the binary's and
//! uses the library only through `glint::`.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Bottom up. A module may use its own layer's files and any module of a
/// lower layer; modules that share a layer do not use each other.
const LAYERS: &[&[&str]] = &[
    // The ground floor and the helpers that import nothing of glint.
    &["base", "printable", "fnv", "rng", "files", "spec_worst"],
    // What users give glint and what it writes.
    &["input", "output"],
    // Images; the primitive kinds.
    &["raster", "prim"],
    // Scene management over the kinds; the counters' slots, sized by them.
    &["accel", "stats"],
    &["scene", "settings"],
    // How a pixel's samples are placed and refined, which both renderers
    // share (the scene holds only the keys).
    &["sampling"],
    // The two renderers.
    &["cpu", "gpu", "generate"],
    // What is built on both renderers.
    &["stability", "tiles", "bench"],
    &["condition", "report"],
    // One pixel's trees on every renderer, bounded by the conditioning;
    // the drivers' verdicts, held to the conditioning too.
    &["explain", "drivers"],
    // The oracle over generated scenes, held by every layer below.
    &["fuzz"],
];

/// The modules the binary's files are in: not part of the library.
const BINARY: &[&str] = &["main", "cli"];

/// One use of another module: the file and line, and the module used.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Edge {
    file: String,
    line: usize,
    from: String,
    to: String,
    path: String,
}

#[test]
fn every_module_uses_only_the_layers_below_it() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let sources = read_tree(&src);
    let tops = top_modules(&src);
    let mut problems = check(&sources, &tops);
    for m in LAYERS.iter().flat_map(|l| l.iter()) {
        if !tops.iter().any(|t| t == m) {
            problems.push(format!(
                "tests/layers.rs: {m} is in a layer but lib.rs has no such module"
            ));
        }
    }
    assert!(
        problems.is_empty(),
        "{} problem(s) with the layers:\n{}",
        problems.len(),
        problems.join("\n")
    );
}

#[test]
fn a_use_of_a_higher_layer_fails() {
    let sources = vec![
        (
            "prim/sphere.rs".to_owned(),
            "use crate::base::ray::Ray;\nfn f() { crate::cpu::render(); }\n".to_owned(),
        ),
        (
            "cpu/mod.rs".to_owned(),
            "//! crate::gpu in a comment is no use\nuse crate::{prim::Prims, stats};\nconst S: &str = \"crate::gpu\";\n"
                .to_owned(),
        ),
    ];
    let tops = ["base", "prim", "cpu", "stats", "gpu"]
        .map(String::from)
        .to_vec();
    let problems = check(&sources, &tops);
    assert_eq!(
        problems,
        vec![
            "src/prim/sphere.rs:2: prim uses cpu (crate::cpu::render), a layer above it".to_owned()
        ]
    );
}

#[test]
fn a_use_within_one_layer_fails_and_super_resolves_through_inline_modules() {
    let sources = vec![
        (
            "cpu/trace.rs".to_owned(),
            "mod tests {\n    use super::*;\n    use super::super::shade;\n}\nuse super::super::gpu::Renderer;\n".to_owned(),
        ),
        ("printable.rs".to_owned(), "#[cfg(test)]\nmod tests { use super::*; }\n".to_owned()),
    ];
    let tops = ["cpu", "gpu", "printable"].map(String::from).to_vec();
    let problems = check(&sources, &tops);
    assert_eq!(
        problems,
        vec![
            "src/cpu/trace.rs:5: cpu uses gpu (crate::gpu::Renderer), in its own layer".to_owned()
        ]
    );
}

#[test]
fn a_module_in_no_layer_fails() {
    let problems = check(&[], &["cpu".to_owned(), "shiny".to_owned()]);
    assert_eq!(
        problems,
        vec!["src/shiny: a module in no layer of tests/layers.rs".to_owned()]
    );
}

/// Every problem: a module in no layer, or a use of a module that is not
/// below.
fn check(sources: &[(String, String)], tops: &[String]) -> Vec<String> {
    let layer_of: BTreeMap<&str, usize> = LAYERS
        .iter()
        .enumerate()
        .flat_map(|(i, l)| l.iter().map(move |m| (*m, i)))
        .collect();
    let mut problems: Vec<String> = tops
        .iter()
        .filter(|t| !layer_of.contains_key(t.as_str()))
        .map(|t| format!("src/{t}: a module in no layer of tests/layers.rs"))
        .collect();
    for (file, text) in sources {
        for e in edges(file, text) {
            let (Some(&from), Some(&to)) =
                (layer_of.get(e.from.as_str()), layer_of.get(e.to.as_str()))
            else {
                continue;
            };
            let why = if to > from {
                "a layer above it"
            } else if to == from {
                "in its own layer"
            } else {
                continue;
            };
            problems.push(format!(
                "src/{}:{}: {} uses {} ({}), {why}",
                e.file, e.line, e.from, e.to, e.path
            ));
        }
    }
    problems
}

/// The library's .rs files under `src`, relative to it, with their text.
fn read_tree(src: &Path) -> Vec<(String, String)> {
    let mut files = read_all(src);
    files.retain(|(rel, _)| !BINARY.contains(&module_of(rel).first().map_or("", |m| m.as_str())));
    files
}

/// The modules lib.rs declares.
fn top_modules(src: &Path) -> Vec<String> {
    let lib = strip(&std::fs::read_to_string(src.join("lib.rs")).unwrap());
    lib.lines()
        .filter_map(|l| {
            let l = l.trim();
            let rest = l
                .strip_prefix("pub ")
                .or_else(|| l.strip_prefix("pub(crate) "))
                .unwrap_or(l);
            rest.strip_prefix("mod ")?
                .strip_suffix(';')
                .map(str::to_owned)
        })
        .collect()
}

/// The module path of a file: `gpu/vk/device.rs` is gpu::vk::device,
/// `gpu/mod.rs` is gpu, lib.rs is the root.
fn module_of(rel: &str) -> Vec<String> {
    let p = PathBuf::from(rel.strip_suffix(".rs").unwrap_or(rel));
    let mut parts: Vec<String> = p.iter().map(|c| c.to_string_lossy().into_owned()).collect();
    if parts.last().is_some_and(|l| l == "mod" || l == "lib") {
        parts.pop();
    }
    parts
}

/// Every use, in `use` items and in paths written inline, of a top-level
/// module other than the file's own.
fn edges(file: &str, text: &str) -> Vec<Edge> {
    let code = strip(text);
    let base = module_of(file);
    let Some(from) = base.first().cloned() else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for (pos, path, module) in paths(&code, &base) {
        let Some(to) = resolve(&path, &module) else {
            continue;
        };
        if to.first().is_some_and(|t| *t != from) {
            out.push(Edge {
                file: file.to_owned(),
                line: code[..pos].matches('\n').count() + 1,
                from: from.clone(),
                to: to[0].clone(),
                path: format!("crate::{}", to.join("::")),
            });
        }
    }
    out
}

/// `path` (`crate::a::b`, `super::c`, `self::d`) from inside `module`, as
/// a path from the crate's root; None for a path of another crate.
fn resolve(path: &[String], module: &[String]) -> Option<Vec<String>> {
    let mut at: Vec<String> = match path.first()?.as_str() {
        "crate" | "$crate" => Vec::new(),
        "super" | "self" => module.to_vec(),
        _ => return None,
    };
    let mut rest = path;
    if matches!(path[0].as_str(), "crate" | "$crate") {
        rest = &path[1..];
    }
    while let Some(first) = rest.first() {
        match first.as_str() {
            "super" => {
                at.pop();
            }
            "self" => {}
            _ => break,
        }
        rest = &rest[1..];
    }
    at.extend(rest.iter().filter(|s| *s != "*").cloned());
    Some(at)
}

/// Each path that starts with `crate`, `$crate`, `super` or `self`, with
/// `use` groups (`a::{b, c::d}`) expanded: its offset in `code`, its
/// segments, and the module it is written in (the file's, with the inline
/// `mod name { .. }` blocks around it).
fn paths(code: &str, file_module: &[String]) -> Vec<(usize, Vec<String>, Vec<String>)> {
    let bytes = code.as_bytes();
    let mut out = Vec::new();
    // Inline modules open at a brace depth; they close with it.
    let mut inline: Vec<(String, usize)> = Vec::new();
    let mut depth = 0usize;
    let mut i = 0;
    let module = |inline: &[(String, usize)]| {
        let mut m = file_module.to_vec();
        m.extend(inline.iter().map(|(n, _)| n.clone()));
        m
    };
    while i < bytes.len() {
        let c = bytes[i];
        if c == b'{' {
            depth += 1;
            i += 1;
            continue;
        }
        if c == b'}' {
            depth = depth.saturating_sub(1);
            if inline.last().is_some_and(|(_, d)| *d == depth) {
                inline.pop();
            }
            i += 1;
            continue;
        }
        if !(c == b'$' || c.is_ascii_alphabetic() || c == b'_') {
            i += 1;
            continue;
        }
        let word_start = i;
        while i < bytes.len()
            && (bytes[i] == b'$' || bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_')
        {
            i += 1;
        }
        let word = &code[word_start..i];
        let preceded_by_path = code[..word_start].trim_end().ends_with("::");
        if preceded_by_path {
            continue;
        }
        match word {
            "mod" => {
                let rest = &code[i..];
                let name: String = rest
                    .trim_start()
                    .chars()
                    .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                    .collect();
                let after = rest.trim_start()[name.len()..].trim_start();
                if !name.is_empty() && after.starts_with('{') {
                    inline.push((name, depth));
                }
            }
            "use" => {
                let end = code[i..].find(';').map_or(code.len(), |e| i + e);
                for p in use_tree(&code[i..end]) {
                    out.push((word_start, p, module(&inline)));
                }
                i = end;
            }
            "crate" | "$crate" | "super" | "self" => {
                let mut end = i;
                let mut segs = vec![word.to_owned()];
                loop {
                    let rest = &code[end..];
                    let Some(after) = rest.strip_prefix("::") else {
                        break;
                    };
                    let seg: String = after
                        .chars()
                        .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                        .collect();
                    if seg.is_empty() {
                        break;
                    }
                    end += 2 + seg.len();
                    segs.push(seg);
                }
                if segs.len() > 1 {
                    out.push((word_start, segs, module(&inline)));
                }
                i = end;
            }
            _ => {}
        }
    }
    out
}

/// The paths a `use` tree names: `crate::{a::b, c}` is crate::a::b and
/// crate::c; `x as y` is x.
fn use_tree(tree: &str) -> Vec<Vec<String>> {
    fn expand(tree: &str, prefix: &[String], out: &mut Vec<Vec<String>>) {
        let tree = tree.trim();
        if tree.is_empty() {
            return;
        }
        if let Some(open) = tree.find('{') {
            let head: Vec<String> = split_path(&tree[..open]);
            let mut base = prefix.to_vec();
            base.extend(head);
            let inner = &tree[open + 1..tree.rfind('}').unwrap_or(tree.len())];
            let mut level = 0;
            let mut start = 0;
            for (k, ch) in inner.char_indices() {
                match ch {
                    '{' => level += 1,
                    '}' => level -= 1,
                    ',' if level == 0 => {
                        expand(&inner[start..k], &base, out);
                        start = k + 1;
                    }
                    _ => {}
                }
            }
            expand(&inner[start..], &base, out);
            return;
        }
        let without_alias = tree.split(" as ").next().unwrap_or(tree);
        let mut p = prefix.to_vec();
        p.extend(split_path(without_alias));
        out.push(p);
    }
    let mut out = Vec::new();
    let tree = tree.trim_start().trim_start_matches("::");
    expand(tree, &[], &mut out);
    out
}

fn split_path(p: &str) -> Vec<String> {
    p.split("::")
        .map(str::trim)
        .filter(|s| !s.is_empty() && *s != "self")
        .map(str::to_owned)
        .collect()
}

/// The text with comments, strings and char literals blanked (newlines
/// kept, so that offsets still give lines).
fn strip(text: &str) -> String {
    let b = text.as_bytes();
    let mut out = String::with_capacity(text.len());
    let blank = |s: &str, out: &mut String| {
        out.extend(s.chars().map(|c| if c == '\n' { '\n' } else { ' ' }));
    };
    let mut i = 0;
    while i < b.len() {
        let rest = &text[i..];
        if rest.starts_with("//") {
            let end = rest.find('\n').map_or(b.len(), |e| i + e);
            blank(&text[i..end], &mut out);
            i = end;
        } else if rest.starts_with("/*") {
            let mut level = 0;
            let mut j = i;
            while j < b.len() {
                if text[j..].starts_with("/*") {
                    level += 1;
                    j += 2;
                } else if text[j..].starts_with("*/") {
                    level -= 1;
                    j += 2;
                    if level == 0 {
                        break;
                    }
                } else {
                    j += 1;
                }
            }
            blank(&text[i..j], &mut out);
            i = j;
        } else if rest.starts_with("r#") || rest.starts_with("r\"") {
            let hashes = rest[1..].chars().take_while(|c| *c == '#').count();
            if rest[1 + hashes..].starts_with('"') {
                let close = format!("\"{}", "#".repeat(hashes));
                let body = i + 2 + hashes;
                let end = text[body..]
                    .find(&close)
                    .map_or(b.len(), |e| body + e + close.len());
                blank(&text[i..end], &mut out);
                i = end;
            } else {
                out.push('r');
                i += 1;
            }
        } else if b[i] == b'"' {
            let mut j = i + 1;
            while j < b.len() && b[j] != b'"' {
                j += if b[j] == b'\\' { 2 } else { 1 };
            }
            let end = (j + 1).min(b.len());
            blank(&text[i..end], &mut out);
            i = end;
        } else if b[i] == b'\'' && is_char_literal(&text[i..]) {
            let end = text[i + 1..].find('\'').map_or(b.len(), |e| i + 2 + e);
            let end = if text[i + 1..].starts_with("\\'") {
                i + 4
            } else {
                end
            };
            blank(&text[i..end], &mut out);
            i = end;
        } else {
            let ch = rest.chars().next().unwrap();
            out.push(ch);
            i += ch.len_utf8();
        }
    }
    out
}

/// Whether a quote starts a char literal (`'a'`, `'\n'`, `'{'`), not a
/// lifetime (`'a`).
fn is_char_literal(s: &str) -> bool {
    let mut chars = s.chars().skip(1);
    match chars.next() {
        Some('\\') => true,
        Some(_) => chars.next() == Some('\''),
        None => false,
    }
}

/// The binary's files and the library's, each with its crate's root: no
/// two files of one folder may import each other, directly or around a
/// loop, in either crate.
#[test]
fn no_files_of_one_folder_import_each_other() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut all = read_all(&src);
    all.retain(|(rel, _)| rel != "main.rs" && rel != "lib.rs");
    let (binary, library): (Vec<_>, Vec<_>) = all
        .into_iter()
        .partition(|(rel, _)| BINARY.contains(&module_of(rel)[0].as_str()));
    let mut problems = circles(&library);
    problems.extend(circles(&binary));
    assert!(
        problems.is_empty(),
        "{} circle(s) of imports:\n{}",
        problems.len(),
        problems.join("\n")
    );
}

#[test]
fn a_circle_of_three_files_fails() {
    let sources = [
        ("gpu/a.rs", "use super::b::B;\n"),
        ("gpu/b.rs", "fn f() { crate::gpu::c::g(); }\n"),
        ("gpu/c.rs", "use super::{a::A, d};\n"),
        ("gpu/d.rs", "pub struct D;\n"),
        ("gpu/mod.rs", "pub use a::A;\nmod tests { use super::b; }\n"),
    ]
    .map(|(f, t)| (f.to_owned(), t.to_owned()));
    assert_eq!(
        circles(&sources),
        vec!["src/gpu: a.rs -> b.rs -> c.rs -> a.rs".to_owned()]
    );
}

/// Every .rs file under `src`, relative to it, with its text.
fn read_all(src: &Path) -> Vec<(String, String)> {
    let mut files = Vec::new();
    let mut dirs = vec![src.to_path_buf()];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                dirs.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let rel = path
                    .strip_prefix(src)
                    .unwrap()
                    .to_string_lossy()
                    .into_owned();
                files.push((rel.clone(), std::fs::read_to_string(&path).unwrap()));
            }
        }
    }
    files.sort();
    files
}

/// The loops of imports among the files of each folder, its mod.rs among
/// them: each as `src/<folder>: a.rs -> b.rs -> a.rs`, once. A name a
/// mod.rs re-exports from one of its files (`pub use unit::Kind;`) is
/// that file's, so a loop that runs through a re-export is seen; a
/// mod.rs's declarations and re-exports are not uses of its files.
fn circles(sources: &[(String, String)]) -> Vec<String> {
    let modules: BTreeMap<Vec<String>, &str> = sources
        .iter()
        .map(|(rel, _)| (module_of(rel), rel.as_str()))
        .collect();
    let reexported = reexports(sources, &modules);
    // The file a path lands in, through the re-exports: the longest prefix
    // that is a file's module.
    let file_of = |path: &[String]| {
        let path = through(&reexported, path);
        (1..=path.len())
            .rev()
            .find_map(|n| modules.get(&path[..n]).copied())
    };
    let mut graph: BTreeMap<&str, std::collections::BTreeSet<&str>> = BTreeMap::new();
    for (rel, text) in sources {
        let base = module_of(rel);
        for (_, path, module) in paths(&strip(text), &base) {
            let Some(to) = resolve(&path, &module).and_then(|p| file_of(&p)) else {
                continue;
            };
            let same_folder = Path::new(to).parent() == Path::new(rel.as_str()).parent();
            if to != rel && same_folder {
                graph.entry(rel.as_str()).or_default().insert(to);
            }
        }
    }
    // Each loop once, from its smallest file, found by a walk from each.
    let mut found = Vec::new();
    for &start in graph.keys() {
        let mut stack = vec![(start, vec![start])];
        while let Some((at, trail)) = stack.pop() {
            for &next in graph.get(at).into_iter().flatten() {
                if next == start {
                    let names: Vec<&str> = trail
                        .iter()
                        .chain([&start])
                        .map(|f| f.rsplit('/').next().unwrap_or(f))
                        .collect();
                    let folder = Path::new(start).parent().unwrap().display().to_string();
                    found.push(format!("src/{folder}: {}", names.join(" -> ")));
                } else if next > start && !trail.contains(&next) {
                    let mut t = trail.clone();
                    t.push(next);
                    stack.push((next, t));
                }
            }
        }
    }
    found.sort();
    found
}

/// What each mod.rs re-exports from its own files: the name it gives
/// (`gpu::Form`) and the path it stands for (`gpu::blocks::Form`).
fn reexports(
    sources: &[(String, String)],
    modules: &BTreeMap<Vec<String>, &str>,
) -> BTreeMap<Vec<String>, Vec<String>> {
    let mut out = BTreeMap::new();
    for (rel, text) in sources.iter().filter(|(r, _)| r.ends_with("mod.rs")) {
        let base = module_of(rel);
        let code = strip(text);
        for statement in code.split(';') {
            let statement = statement.trim();
            let Some(tree) = ["pub use ", "pub(crate) use ", "pub(super) use "]
                .iter()
                .find_map(|p| statement.strip_prefix(p))
            else {
                continue;
            };
            for path in use_tree(tree) {
                let mut target = base.clone();
                target.extend(path.iter().cloned());
                let child = base.iter().chain(path.first()).cloned().collect::<Vec<_>>();
                if path.len() > 1 && modules.contains_key(&child) {
                    let mut name = base.clone();
                    name.push(path.last().unwrap().clone());
                    out.insert(name, target);
                }
            }
        }
    }
    out
}

/// `path` with its longest re-exported prefix replaced by what it stands
/// for.
fn through(reexported: &BTreeMap<Vec<String>, Vec<String>>, path: &[String]) -> Vec<String> {
    for n in (1..=path.len()).rev() {
        if let Some(target) = reexported.get(&path[..n]) {
            let mut p = target.clone();
            p.extend(path[n..].iter().cloned());
            return p;
        }
    }
    path.to_vec()
}

#[test]
fn a_circle_through_a_reexport_or_a_mod_rs_fails() {
    let sources = [
        (
            "prim/mod.rs",
            "mod sphere;\nmod unit;\npub use unit::Kind;\nfn t() { crate::prim::sphere::f(); }\n",
        ),
        ("prim/sphere.rs", "use super::Kind;\npub fn f() {}\n"),
        (
            "prim/unit.rs",
            "pub trait Kind {}\nfn g() { super::sphere::f(); }\n",
        ),
        (
            "gpu/mod.rs",
            "mod a;\npub struct S;\nfn t() { crate::gpu::a::f(); }\n",
        ),
        ("gpu/a.rs", "use super::S;\npub fn f() {}\n"),
    ]
    .map(|(f, t)| (f.to_owned(), t.to_owned()));
    assert_eq!(
        circles(&sources),
        vec![
            "src/gpu: a.rs -> mod.rs -> a.rs".to_owned(),
            "src/prim: sphere.rs -> unit.rs -> sphere.rs".to_owned(),
        ]
    );
}
