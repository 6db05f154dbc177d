//! What `render -o FILE` does to a FILE that exists, as
//! docs/guarantees.md states it: a read-only file is refused unless
//! `--force`; a symbolic link keeps pointing where it did and its target
//! gets the new image, atomically; a hard link's other names keep the old
//! image, since the write renames a new file over the name.

#![cfg(feature = "gpu")]

mod common;

use std::os::unix::fs::PermissionsExt;

use assert_cmd::assert::OutputAssertExt;
use common::small_cpu_render;

#[test]
fn a_read_only_output_is_refused_unless_forced() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("ro.pfm");
    std::fs::write(&out, b"old").unwrap();
    std::fs::set_permissions(&out, std::fs::Permissions::from_mode(0o444)).unwrap();
    small_cpu_render(&out, &[])
        .assert()
        .code(2)
        .stderr(predicates::str::contains("is read-only"));
    assert_eq!(std::fs::read(&out).unwrap(), b"old");

    small_cpu_render(&out, &["--force"]).assert().success();
    assert_ne!(std::fs::read(&out).unwrap(), b"old");
    let mode = std::fs::metadata(&out).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode, 0o444, "the new file keeps the old one's permissions");
}

#[test]
fn a_symbolic_link_keeps_pointing_at_its_target_which_gets_the_image() {
    let dir = tempfile::tempdir().unwrap();
    let target = dir.path().join("real.pfm");
    std::fs::write(&target, b"old").unwrap();
    let link = dir.path().join("link.pfm");
    std::os::unix::fs::symlink("real.pfm", &link).unwrap();
    small_cpu_render(&link, &[]).assert().success();
    assert!(std::fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    assert_ne!(std::fs::read(&target).unwrap(), b"old");
    assert!(glint::raster::io::read(&target).is_ok());

    // A dangling link: its target is created.
    let dangling = dir.path().join("dangling.pfm");
    std::os::unix::fs::symlink("made.pfm", &dangling).unwrap();
    small_cpu_render(&dangling, &[]).assert().success();
    assert!(std::fs::symlink_metadata(&dangling)
        .unwrap()
        .file_type()
        .is_symlink());
    assert!(dir.path().join("made.pfm").is_file());
}

#[test]
fn a_hard_links_other_name_keeps_the_old_image() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.pfm");
    std::fs::write(&out, b"old").unwrap();
    let other = dir.path().join("other.pfm");
    std::fs::hard_link(&out, &other).unwrap();
    small_cpu_render(&out, &[]).assert().success();
    assert_eq!(std::fs::read(&other).unwrap(), b"old");
    assert!(glint::raster::io::read(&out).is_ok());
}
