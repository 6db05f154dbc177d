//! docs/shaders.md's table of shader files and their CPU twins names files
//! that exist, and every built-in shader file is in it (the table was kept
//! by hand and named a file the check had left).

use std::path::Path;

/// The rows of the table under `| file | job | CPU twin |`: each row's
/// shader files (first column, under shaders/) and the source files its
/// twin column names (`src/...`), in backticks.
fn twin_rows(doc: &str) -> Vec<(Vec<String>, Vec<String>)> {
    let ticked = |cell: &str| -> Vec<String> {
        cell.split('`')
            .skip(1)
            .step_by(2)
            .map(str::to_owned)
            .collect()
    };
    doc.lines()
        .skip_while(|l| !l.starts_with("| file | job | CPU twin |"))
        .skip(2)
        .take_while(|l| l.starts_with('|'))
        .map(|row| {
            let cells: Vec<&str> = row.split('|').collect();
            let files = ticked(cells[1]);
            let twins = ticked(cells[3])
                .into_iter()
                .filter(|t| t.starts_with("src/"))
                .collect();
            (files, twins)
        })
        .collect()
}

/// What the table names that `root` lacks, and the shader files under
/// `root`/shaders (outside experiments/) that it does not name.
fn problems(doc: &str, root: &Path) -> Vec<String> {
    let rows = twin_rows(doc);
    let mut out = Vec::new();
    if rows.is_empty() {
        out.push("no table under `| file | job | CPU twin |`".to_owned());
    }
    let mut listed = Vec::new();
    for (files, twins) in &rows {
        for f in files {
            if !root.join("shaders").join(f).is_file() {
                out.push(format!("shaders/{f} is in the table but not in the tree"));
            }
            listed.push(f.clone());
        }
        if twins.is_empty() {
            out.push(format!("{files:?} has no twin under src/"));
        }
        for t in twins {
            if !root.join(t).is_file() {
                out.push(format!("{t}, the twin of {files:?}, is not in the tree"));
            }
        }
    }
    let shaders = root.join("shaders");
    let mut stack = vec![shaders.clone()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                if path.file_name().unwrap() != "experiments" {
                    stack.push(path);
                }
                continue;
            }
            let name = path
                .strip_prefix(&shaders)
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/");
            if !listed.contains(&name) {
                out.push(format!("shaders/{name} is not in the table"));
            }
        }
    }
    out
}

#[test]
fn the_twin_table_names_the_files_there_are() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let doc = std::fs::read_to_string(root.join("docs/shaders.md")).unwrap();
    let found = problems(&doc, root);
    assert!(found.is_empty(), "docs/shaders.md:\n{}", found.join("\n"));
}

/// The check fails on a twin that is not there, a shader file that is not
/// there, and a shader file left out.
#[test]
fn a_table_naming_a_missing_file_fails() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let doc = std::fs::read_to_string(root.join("docs/shaders.md")).unwrap();
    let moved = doc.replacen("`src/cpu/shade.rs` |", "`src/gpu/no_such_file.rs` |", 1);
    assert!(problems(&moved, root)
        .iter()
        .any(|p| p.starts_with("src/gpu/no_such_file.rs")));
    let renamed = doc.replacen("| `ray.glsl` |", "| `rays.glsl` |", 1);
    let found = problems(&renamed, root);
    assert!(
        found
            .iter()
            .any(|p| p == "shaders/rays.glsl is in the table but not in the tree"),
        "{found:?}"
    );
    assert!(
        found
            .iter()
            .any(|p| p == "shaders/ray.glsl is not in the table"),
        "{found:?}"
    );
}
