//! Every relative link and image in the repository's Markdown files names
//! a file or folder that is there (the README's SPD pictures pointed at
//! files that were never committed).

use std::path::{Path, PathBuf};

mod common;

/// The Markdown files of the repository, outside target/ and hidden
/// folders.
fn markdown_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if name.starts_with('.') || name == "target" {
            continue;
        }
        if path.is_dir() {
            markdown_files(&path, out);
        } else if name.ends_with(".md") {
            out.push(path);
        }
    }
}

/// The lines of `text` outside fenced code blocks, numbered from 1.
fn unfenced_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    let mut fenced = false;
    text.lines().enumerate().filter_map(move |(n, line)| {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            return None;
        }
        (!fenced).then_some((n + 1, line))
    })
}

/// The targets of `[text](target)` and `![alt](target)` in `text`, with
/// their lines; code spans and fenced blocks are skipped.
fn link_targets(text: &str) -> Vec<(usize, String)> {
    let mut targets = Vec::new();
    for (n, line) in unfenced_lines(text) {
        // Code spans hold examples, not links.
        let prose: String = line.split('`').step_by(2).collect::<Vec<_>>().join(" ");
        let mut rest = prose.as_str();
        while let Some(at) = rest.find("](") {
            let after = &rest[at + 2..];
            let Some(end) = after.find(')') else { break };
            targets.push((n, after[..end].to_owned()));
            rest = &after[end..];
        }
    }
    targets
}

#[test]
fn every_relative_link_and_image_in_the_markdown_is_there() {
    let root = common::repo();
    let mut files = Vec::new();
    markdown_files(&root, &mut files);
    assert!(files.len() > 5, "found {} Markdown files", files.len());
    let mut broken = Vec::new();
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        for (line, target) in link_targets(&text) {
            let target = target.split_whitespace().next().unwrap_or_default();
            let path = target.split('#').next().unwrap_or_default();
            if path.is_empty() || path.contains("://") || path.starts_with("mailto:") {
                continue;
            }
            if !file.parent().unwrap().join(path).exists() {
                broken.push(format!(
                    "{}:{line}: {target}",
                    file.strip_prefix(&root).unwrap().display()
                ));
            }
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

/// The check sees a broken link, and passes over examples in code.
#[test]
fn the_check_sees_a_broken_link() {
    let text = "see ![a](img/a.png) and [b](b.md#part), not `[c](c.md)`\n```\n[d](d.md)\n```\n";
    let targets: Vec<String> = link_targets(text).into_iter().map(|(_, t)| t).collect();
    assert_eq!(targets, ["img/a.png", "b.md#part"]);
}

/// The file names in `text`'s code spans (outside fenced blocks), with
/// their lines: a span without spaces or placeholders (`<name>`, `*`) that
/// has a folder and a file's extension, or ends in `/`.
fn named_files(text: &str) -> Vec<(usize, String)> {
    const EXTENSIONS: &[&str] = &[
        ".rs", ".glsl", ".comp", ".md", ".py", ".toml", ".json", ".svg", ".nff", ".obj",
    ];
    let mut names = Vec::new();
    for (n, line) in unfenced_lines(text) {
        for span in line.split('`').skip(1).step_by(2) {
            let plain = !span.contains(|c: char| c.is_whitespace() || "<>*{}()".contains(c));
            let file = EXTENSIONS.iter().any(|e| span.ends_with(e)) || span.ends_with('/');
            if plain && file && span.contains('/') {
                names.push((n, span.to_owned()));
            }
        }
    }
    names
}

/// The names of `named_files(text)` that are no file or folder, read from
/// the repository's root, or from src/ or shaders/ (where the page names
/// a file by its place in one of them).
fn missing_files(text: &str) -> Vec<String> {
    let root = common::repo();
    named_files(text)
        .into_iter()
        .filter(|(_, name)| {
            !["", "src", "shaders"]
                .iter()
                .any(|base| root.join(base).join(name).exists())
        })
        .map(|(line, name)| format!("{line}: {name}"))
        .collect()
}

/// docs/architecture.md is the map: every file and folder it names is
/// there. The check fails on a name that is not, and passes over
/// placeholders and code in fenced blocks.
#[test]
fn every_file_the_architecture_names_is_there() {
    let text = std::fs::read_to_string(common::repo().join("docs/architecture.md")).unwrap();
    assert!(named_files(&text).len() > 40, "{:?}", named_files(&text));
    let missing = missing_files(&text);
    assert!(
        missing.is_empty(),
        "docs/architecture.md names:\n{}",
        missing.join("\n")
    );
    let made_up = "`src/gpu/nowhere.rs`, `accel/bvh.rs`, `prim/sphere.glsl`, \
                   `src/prim/<name>.rs`, `cli/`\n```\nsrc/fenced.rs\n```\n`gpu/gone/`";
    assert_eq!(
        missing_files(made_up),
        ["1: src/gpu/nowhere.rs", "5: gpu/gone/"]
    );
}
