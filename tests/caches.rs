//! The caches glint keeps on disk ($XDG_CACHE_HOME/glint): the SPIR-V of
//! each shader variant and the Vulkan pipeline cache. An entry damaged on
//! disk (a flipped bit, a torn copy) is found by its checksum, made again
//! and replaced, and said once at INFO; it never reaches the driver. A
//! flipped bit in a cached constant rendered a wrong image with exit 0,
//! and an entry cut in half failed every render of its variant with the
//! driver's "unknown error".

#![cfg(feature = "gpu")]

mod common;

use std::path::{Path, PathBuf};

/// Renders seed-fig3 small on the GPU with its caches in `cache`: the
/// image's bytes and stderr.
fn render(cache: &Path, out: &Path) -> (Vec<u8>, String) {
    let o = common::cmd()
        .args(["render", "--width", "32", "--height", "24"])
        .arg(common::repo().join("scenes/seed-fig3.toml"))
        .arg("-o")
        .arg(out)
        .env("XDG_CACHE_HOME", cache)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "{err}");
    (std::fs::read(out).unwrap(), err)
}

fn files_ending(dir: &Path, end: &str) -> Vec<PathBuf> {
    std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.to_string_lossy().ends_with(end))
        .collect()
}

/// One way an entry's bytes are damaged.
type Harm = Box<dyn Fn(&mut Vec<u8>)>;

#[test]
fn a_damaged_cache_entry_is_made_again_and_said() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let out = dir.path().join("a.pfm");
    let (want, err) = render(&cache, &out);
    assert!(!err.contains("info:"), "{err}");
    let spirv = files_ending(&cache.join("glint/spirv"), ".spv.sealed");
    assert_eq!(spirv.len(), 1, "{spirv:?}");
    let spirv = &spirv[0];
    let pipelines = files_ending(&cache.join("glint"), ".sealed");
    assert_eq!(pipelines.len(), 1, "{pipelines:?}");
    let whole = std::fs::read(spirv).unwrap();
    let damage: [(&str, Harm); 3] = [
        // A bit of a word past the header (a constant, an opcode).
        (
            "a flipped bit",
            Box::new(|b| {
                let middle = b.len() / 2;
                b[middle] ^= 0x10;
            }),
        ),
        (
            "cut in half",
            Box::new(|b| {
                let half = b.len() / 2;
                b.truncate(half);
            }),
        ),
        // Raw SPIR-V where a sealed entry belongs (a hand-made copy).
        ("no header", Box::new(|b| b.drain(..24).for_each(drop))),
    ];
    for (what, harm) in damage {
        let mut bytes = whole.clone();
        harm(&mut bytes);
        std::fs::write(spirv, &bytes).unwrap();
        let (image, err) = render(&cache, &out);
        assert_eq!(image, want, "{what}: another image");
        assert!(
            err.contains("info: the cached SPIR-V") && err.contains("damaged"),
            "{what}: {err}"
        );
        assert_eq!(std::fs::read(spirv).unwrap(), whole, "{what}: not replaced");
        let (_, err) = render(&cache, &out);
        assert!(!err.contains("info:"), "{what}: said twice: {err}");
    }
    // The pipeline cache's file, flipped past the driver's header.
    let mut bytes = std::fs::read(&pipelines[0]).unwrap();
    let last = bytes.len() - 1;
    bytes[last] ^= 1;
    std::fs::write(&pipelines[0], &bytes).unwrap();
    let (image, err) = render(&cache, &out);
    assert_eq!(image, want);
    assert!(
        err.contains("info: the Vulkan pipeline cache") && err.contains("damaged"),
        "{err}"
    );
}
