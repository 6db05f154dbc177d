//! The output rules, on private device nodes and FIFOs made in a temporary
//! folder (`mknod` needs root: those tests say so and pass vacuously where
//! it fails, as they cannot make the node).

use std::io::{Read, Write};
use std::path::{Path, PathBuf};

use super::*;

fn text(outputs: &mut Outputs, path: &Path, s: &str) -> Result<(), OutputError> {
    outputs.stage(path, |w: &mut dyn Write| {
        w.write_all(s.as_bytes()).map_err(io_err(path))
    })
}

/// A node made by mknod(1) (`kind` c, b or p); None where that is refused.
fn mknod(dir: &Path, name: &str, args: &[&str]) -> Option<PathBuf> {
    let path = dir.join(name);
    let ok = std::process::Command::new("mknod")
        .arg(&path)
        .args(args)
        .status()
        .is_ok_and(|s| s.success());
    if !ok {
        eprintln!("skipped: mknod {name} {args:?} is refused here (not root?)");
    }
    ok.then_some(path)
}

fn is_char_device(p: &Path) -> bool {
    use std::os::unix::fs::FileTypeExt;
    std::fs::symlink_metadata(p).is_ok_and(|m| m.file_type().is_char_device())
}

fn only_entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn a_character_device_is_written_into_not_replaced() {
    let dir = tempfile::tempdir().unwrap();
    // A private /dev/null: major 1, minor 3.
    let Some(null) = mknod(dir.path(), "null", &["c", "1", "3"]) else {
        return;
    };
    let link = dir.path().join("link.json");
    std::os::unix::fs::symlink(&null, &link).unwrap();
    for path in [&null, &link] {
        let mut outputs = Outputs::new::<&Path>([], false);
        assert_eq!(outputs.check(path).unwrap(), TargetKind::Stream);
        text(&mut outputs, path, "{}").unwrap();
        outputs.commit().unwrap();
        assert!(is_char_device(&null), "the device node was replaced");
    }
    assert!(std::fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    assert_eq!(only_entries(dir.path()), ["link.json", "null"]);
}

#[test]
fn a_fifo_gets_the_bytes_and_stays_a_fifo() {
    use std::os::unix::fs::FileTypeExt;
    let dir = tempfile::tempdir().unwrap();
    let Some(fifo) = mknod(dir.path(), "pipe", &["p"]) else {
        return;
    };
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || {
            let mut s = String::new();
            std::fs::File::open(&fifo)
                .unwrap()
                .read_to_string(&mut s)
                .unwrap();
            s
        })
    };
    let mut outputs = Outputs::new::<&Path>([], false);
    text(&mut outputs, &fifo, "through the pipe").unwrap();
    outputs.commit().unwrap();
    assert_eq!(reader.join().unwrap(), "through the pipe");
    let t = std::fs::symlink_metadata(&fifo).unwrap().file_type();
    assert!(t.is_fifo());
}

#[test]
fn a_block_device_a_directory_and_a_socket_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let sub = dir.path().join("sub");
    std::fs::create_dir(&sub).unwrap();
    let socket = dir.path().join("sock");
    let _listener = std::os::unix::net::UnixListener::bind(&socket).unwrap();
    let mut refused = vec![(sub.clone(), "a directory"), (socket, "a socket")];
    // A private loop device node: major 7, minor 0.
    if let Some(block) = mknod(dir.path(), "loop", &["b", "7", "0"]) {
        refused.push((block, "a block device"));
    }
    for (path, what) in refused {
        let mut outputs = Outputs::new::<&Path>([], false);
        let e = text(&mut outputs, &path, "x").unwrap_err();
        assert!(e.to_string().contains(what), "{e}");
        // Through a link too.
        let link = dir.path().join("to-it");
        let _ = std::fs::remove_file(&link);
        std::os::unix::fs::symlink(&path, &link).unwrap();
        let e = Outputs::new::<&Path>([], false).check(&link).unwrap_err();
        assert!(e.to_string().contains(what), "{e}");
    }
    assert!(sub.is_dir());
}

#[test]
fn nothing_is_replaced_until_the_commit_and_then_all_are() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a.json"), dir.path().join("b.png"));
    std::fs::write(&a, "old a").unwrap();
    std::fs::write(&b, "old b").unwrap();
    let mut outputs = Outputs::new::<&Path>([], false);
    text(&mut outputs, &a, "new a").unwrap();
    text(&mut outputs, &b, "new b").unwrap();
    assert_eq!(std::fs::read_to_string(&a).unwrap(), "old a");
    outputs.commit().unwrap();
    assert_eq!(std::fs::read_to_string(&a).unwrap(), "new a");
    assert_eq!(std::fs::read_to_string(&b).unwrap(), "new b");
    assert_eq!(only_entries(dir.path()), ["a.json", "b.png"]);
}

#[test]
fn a_failed_second_output_leaves_the_first_unreplaced_and_no_temp_file() {
    let dir = tempfile::tempdir().unwrap();
    let image = dir.path().join("out.png");
    std::fs::write(&image, "old image").unwrap();
    let mut outputs = Outputs::new::<&Path>([], false);
    text(&mut outputs, &image, "new image").unwrap();
    let missing = dir.path().join("no-such-folder").join("stats.json");
    assert!(matches!(
        text(&mut outputs, &missing, "{}"),
        Err(OutputError::Io { .. })
    ));
    drop(outputs);
    assert_eq!(std::fs::read_to_string(&image).unwrap(), "old image");
    assert_eq!(only_entries(dir.path()), ["out.png"]);
}

#[test]
fn an_input_is_refused_by_inode_through_links() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("s.toml");
    std::fs::write(&scene, "scene").unwrap();
    let hard = dir.path().join("hard.png");
    std::fs::hard_link(&scene, &hard).unwrap();
    let soft = dir.path().join("soft.png");
    std::os::unix::fs::symlink(&scene, &soft).unwrap();
    let mut outputs = Outputs::new([&scene], false);
    for p in [&scene, &hard, &soft] {
        assert!(matches!(
            outputs.check(p),
            Err(OutputError::OverwritesInput { .. })
        ));
    }
    assert_eq!(std::fs::read_to_string(&scene).unwrap(), "scene");
}

#[test]
fn a_read_only_file_is_replaced_only_with_force() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("ro.png");
    std::fs::write(&path, "old").unwrap();
    let mut perms = std::fs::metadata(&path).unwrap().permissions();
    perms.set_readonly(true);
    std::fs::set_permissions(&path, perms).unwrap();
    assert!(matches!(
        Outputs::new::<&Path>([], false).check(&path),
        Err(OutputError::ReadOnly(_))
    ));
    let mut outputs = Outputs::new::<&Path>([], true);
    text(&mut outputs, &path, "new").unwrap();
    outputs.commit().unwrap();
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
    assert!(std::fs::metadata(&path).unwrap().permissions().readonly());
}

#[test]
fn two_outputs_that_are_one_file_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let image = dir.path().join("out.png");
    let link = dir.path().join("stats.json");
    std::os::unix::fs::symlink(&image, &link).unwrap();
    let mut outputs = Outputs::new::<&Path>([], false);
    text(&mut outputs, &link, "{}").unwrap();
    assert!(matches!(
        text(&mut outputs, &image, "image"),
        Err(OutputError::Twice(_))
    ));
}
