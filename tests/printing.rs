//! What a command does when its stdout or stderr will not take its words
//! (docs/guarantees.md, Printing): a full stdout is one line and exit 2, a
//! closed pipe ends quietly with 141, a full stderr exits 2; never a panic.
//! And the rule that keeps it so: every line goes through one writer.

mod common;

use std::fs::File;
use std::path::Path;
use std::process::{Command, Output, Stdio};

use common::repo;

/// glint run with `args`, stdout and stderr as given.
fn run(args: &[&str], stdout: Stdio, stderr: Stdio) -> Output {
    Command::new(env!("CARGO_BIN_EXE_glint"))
        .args(args)
        .env("GLINT_VALIDATION", "1")
        .stdout(stdout)
        .stderr(stderr)
        .output()
        .expect("run glint")
}

fn full() -> Stdio {
    File::options()
        .write(true)
        .open("/dev/full")
        .expect("/dev/full")
        .into()
}

/// A pipe whose reader is gone before glint starts: its first write fails
/// with EPIPE, every time.
fn closed_pipe() -> Stdio {
    use std::os::fd::{FromRawFd, OwnedFd};
    let mut fds = [0i32; 2];
    // SAFETY: pipe() fills both descriptors, each owned once below.
    assert_eq!(unsafe { libc::pipe(fds.as_mut_ptr()) }, 0, "pipe");
    // SAFETY: fds[0] and fds[1] are open and owned by nothing else.
    let (reader, writer) = unsafe { (OwnedFd::from_raw_fd(fds[0]), OwnedFd::from_raw_fd(fds[1])) };
    drop(reader);
    writer.into()
}

/// Commands that print their answer on stdout, with arguments that make
/// them do it quickly.
fn printers() -> Vec<Vec<String>> {
    let scene = repo().join("scenes/seed-fig3.toml").display().to_string();
    let image = repo().join("docs/img/seed-fig5.png").display().to_string();
    let mut v: Vec<Vec<&str>> = vec![
        vec!["--version"],
        vec!["--help"],
        vec!["render", "--help"],
        vec!["man"],
        vec!["completions", "bash"],
        vec!["diff", &image, &image],
    ];
    if cfg!(feature = "gpu") {
        v.push(vec!["info"]);
        v.push(vec!["shader", "check", "shaders/main.comp"]);
        v.push(vec![
            "compare", &scene, "--width", "16", "--height", "12", "--json",
        ]);
    }
    v.into_iter()
        .map(|a| a.into_iter().map(str::to_owned).collect())
        .collect()
}

fn words(args: &[String]) -> Vec<&str> {
    args.iter().map(String::as_str).collect()
}

#[test]
fn a_full_stdout_is_one_line_and_exit_2() {
    for args in printers() {
        let out = run(&words(&args), full(), Stdio::piped());
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {out:?}");
        let lines: Vec<&str> = err.lines().collect();
        assert_eq!(lines.len(), 1, "{args:?}: {err}");
        assert!(
            lines[0].starts_with("error: cannot write to stdout"),
            "{args:?}: {err}"
        );
    }
}

#[test]
fn a_closed_pipe_ends_quietly() {
    for args in printers() {
        let out = run(&words(&args), closed_pipe(), Stdio::piped());
        assert_eq!(
            out.status.code(),
            Some(141),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(out.stderr.is_empty(), "{args:?}: {out:?}");
    }
}

#[test]
fn a_full_stderr_exits_2_without_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let image = dir.path().join("x.png");
    let scene = repo().join("scenes/seed-fig3.toml");
    let out = run(
        &[
            "render",
            &scene.display().to_string(),
            "--backend",
            "cpu",
            "--width",
            "16",
            "--height",
            "12",
            "-o",
            &image.display().to_string(),
        ],
        Stdio::null(),
        full(),
    );
    assert_eq!(out.status.code(), Some(2), "{out:?}");
    // The image was committed before its line could not be printed.
    assert!(image.is_file());
    let missing = run(&["render", "no-such.toml"], Stdio::null(), full());
    assert_eq!(missing.status.code(), Some(2), "{missing:?}");
}

/// The print macros and the standard streams appear in `src/` only in the
/// one writer, `src/cli/console.rs` (and in doc comments and unit tests),
/// so no new command can print past its error handling.
#[test]
fn every_line_goes_through_the_one_writer() {
    let mut offenders = Vec::new();
    scan(&repo().join("src"), &mut offenders);
    assert!(
        offenders.is_empty(),
        "print through src/cli/console.rs:\n{}",
        offenders.join("\n")
    );
}

#[test]
fn the_scan_finds_a_print() {
    let text = "fn f() {\n    println!(\"x\");\n}\n";
    assert_eq!(prints_in(text).len(), 1);
    assert!(prints_in("/// println!(\"doc\")\nfn f() {}\n").is_empty());
}

fn scan(dir: &Path, offenders: &mut Vec<String>) {
    for entry in std::fs::read_dir(dir).unwrap().flatten() {
        let path = entry.path();
        if path.is_dir() {
            scan(&path, offenders);
            continue;
        }
        let name = path.file_name().unwrap().to_string_lossy();
        let test_file = name == "tests.rs" || name.ends_with("_tests.rs");
        if path.extension().is_none_or(|e| e != "rs") || test_file || name == "console.rs" {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        for line in prints_in(&text) {
            offenders.push(format!("{}:{line}", path.display()));
        }
    }
}

/// The numbers of the lines of `text` that print or take a standard
/// stream, doc comments left out.
fn prints_in(text: &str) -> Vec<usize> {
    const NEEDLES: [&str; 6] = [
        "println!",
        "print!(",
        "eprint!(",
        "io::stdout()",
        "io::stderr()",
        "dbg!(",
    ];
    text.lines()
        .enumerate()
        .filter(|(_, l)| !l.trim_start().starts_with("//"))
        .filter(|(_, l)| NEEDLES.iter().any(|n| l.contains(n)))
        .map(|(i, _)| i + 1)
        .collect()
}
