//! The house's rules on files (docs/architecture.md, The house):
//! a source file under src/ says one thing, in at most 600 lines; a test
//! file is named by what it tests, never by the review round that found
//! its defects.

use std::path::{Path, PathBuf};

/// The most lines a file under src/ may have.
const MOST_LINES: usize = 600;

/// Every file under `dir` whose name ends in one of `extensions`, as a
/// path relative to the repository.
fn files(dir: &str, extensions: &[&str]) -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut out = Vec::new();
    let mut dirs = vec![root.join(dir)];
    while let Some(d) = dirs.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                dirs.push(path);
            } else if path
                .extension()
                .is_some_and(|e| extensions.iter().any(|x| e == *x))
            {
                out.push(path.strip_prefix(root).unwrap().to_owned());
            }
        }
    }
    out.sort();
    out
}

/// The files of `texts` (a name and its text) over `most` lines.
fn too_long(texts: &[(String, String)], most: usize) -> Vec<String> {
    texts
        .iter()
        .filter(|(_, text)| text.lines().count() > most)
        .map(|(name, text)| format!("{name}: {} lines", text.lines().count()))
        .collect()
}

/// The names among `names` that name a review round (`round_four`,
/// `test_round_five`, `round6`) rather than a subject.
fn named_after_a_round(names: &[String]) -> Vec<String> {
    names
        .iter()
        .filter(|n| {
            let stem = Path::new(n.as_str())
                .file_stem()
                .map_or(String::new(), |s| s.to_string_lossy().to_lowercase());
            stem.split(['_', '-']).any(|w| w.starts_with("round"))
        })
        .cloned()
        .collect()
}

#[test]
fn no_source_file_is_over_600_lines() {
    let texts: Vec<(String, String)> = files("src", &["rs"])
        .into_iter()
        .map(|p| {
            let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(&p));
            (p.display().to_string(), text.unwrap())
        })
        .collect();
    assert!(texts.len() > 100, "src/ read: {} files", texts.len());
    let long = too_long(&texts, MOST_LINES);
    assert!(
        long.is_empty(),
        "over {MOST_LINES} lines:\n{}",
        long.join("\n")
    );
}

#[test]
fn no_test_file_is_named_after_a_round() {
    let mut names: Vec<String> = files("tests", &["rs"])
        .into_iter()
        .chain(files("python/tests", &["py"]))
        .map(|p| p.display().to_string())
        .collect();
    names.retain(|n| !n.starts_with("tests/data/"));
    assert!(names.len() > 50, "tests read: {}", names.len());
    let rounds = named_after_a_round(&names);
    assert!(rounds.is_empty(), "named after a round: {rounds:?}");
}

/// The two checks fail on the files they exist for: the names this
/// house's tests once had, and a file one line past the bound.
#[test]
fn the_checks_see_a_round_and_a_long_file() {
    let names = [
        "tests/hostile_round_four.rs",
        "python/tests/test_round_five.py",
        "tests/round6.rs",
        "tests/surroundings.rs",
        "tests/hostile_input.rs",
    ]
    .map(String::from);
    assert_eq!(named_after_a_round(&names), names[..3].to_vec());
    let long = ("src/a.rs".to_owned(), "x\n".repeat(MOST_LINES + 1));
    let fits = ("src/b.rs".to_owned(), "x\n".repeat(MOST_LINES));
    assert_eq!(
        too_long(&[long, fits], MOST_LINES),
        vec![format!("src/a.rs: {} lines", MOST_LINES + 1)]
    );
}

/// What in a test file's text says it reaches a GPU: a gpu-gated item, the
/// GPU renderer, or the glint binary (a GPU build's binary renders there).
const GPU_MARKS: &[&str] = &[
    "feature = \"gpu\"",
    "glint::gpu",
    "render_gpu",
    "gpu_from",
    "gpu_with",
    "CARGO_BIN_EXE_glint",
    "common::cmd",
    "common::glint",
    "use common::glint",
];

/// The marks of `GPU_MARKS` in `text`.
fn gpu_marks(text: &str) -> Vec<&'static str> {
    GPU_MARKS
        .iter()
        .copied()
        .filter(|m| text.contains(m))
        .collect()
}

/// ci/test runs the files it lists in CPU_ONLY_TEST_FILES in the CPU-only
/// lane alone: each must exist and reach no GPU, else a GPU test would
/// never run on a GPU.
#[test]
fn the_tests_ci_runs_once_need_no_gpu() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let ci = std::fs::read_to_string(root.join("ci/test")).unwrap();
    let list = ci
        .lines()
        .find_map(|l| l.strip_prefix("CPU_ONLY_TEST_FILES=\""))
        .and_then(|l| l.strip_suffix('"'))
        .expect("ci/test sets CPU_ONLY_TEST_FILES");
    let names: Vec<&str> = list.split_whitespace().collect();
    assert!(names.len() >= 4, "{names:?}");
    for name in names {
        let path = root.join("tests").join(format!("{name}.rs"));
        let text =
            std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        // This file names the marks it looks for.
        let text = if name == "house" {
            text.split("const GPU_MARKS").next().unwrap().to_owned()
        } else {
            text
        };
        assert!(
            gpu_marks(&text).is_empty(),
            "tests/{name}.rs reaches a GPU: {:?}",
            gpu_marks(&text)
        );
    }
    assert_eq!(
        gpu_marks("#[cfg(feature = \"gpu\")]\nlet r = common::gpu_with(s);"),
        ["feature = \"gpu\"", "gpu_with"]
    );
}
