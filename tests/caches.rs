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

/// One way an entry is damaged, as a bad sector, a torn copy or a sync
/// tool leaves it.
#[derive(Debug, Clone)]
enum Damage {
    /// Bytes at these fractions of the length XORed with these (non-zero)
    /// masks.
    Flips(Vec<(f64, u8)>),
    /// Cut to this fraction of its length.
    Cut(f64),
    /// These bytes added at the end.
    Grown(Vec<u8>),
    /// Its bytes all replaced by these.
    Replaced(Vec<u8>),
    /// An empty file.
    Emptied,
    /// No file: a folder of its name.
    Folder,
}

impl Damage {
    fn apply(&self, path: &Path, whole: &[u8]) {
        let mut b = whole.to_vec();
        match self {
            Damage::Flips(flips) => {
                for &(at, mask) in flips {
                    let i = ((at * b.len() as f64) as usize).min(b.len() - 1);
                    b[i] ^= mask;
                }
            }
            Damage::Cut(keep) => b.truncate(((keep * b.len() as f64) as usize).min(b.len() - 1)),
            Damage::Grown(more) => b.extend_from_slice(more),
            Damage::Replaced(bytes) => b = bytes.clone(),
            Damage::Emptied => b.clear(),
            Damage::Folder => {
                std::fs::remove_file(path).unwrap();
                std::fs::create_dir(path).unwrap();
                return;
            }
        }
        std::fs::write(path, b).unwrap();
    }
}

fn damage() -> impl proptest::strategy::Strategy<Value = Damage> {
    use proptest::prelude::*;
    prop_oneof![
        proptest::collection::vec((0.0..1.0f64, 1..=255u8), 1..4).prop_map(Damage::Flips),
        (0.0..1.0f64).prop_map(Damage::Cut),
        proptest::collection::vec(any::<u8>(), 1..64).prop_map(Damage::Grown),
        proptest::collection::vec(any::<u8>(), 0..256).prop_map(Damage::Replaced),
        Just(Damage::Emptied),
        Just(Damage::Folder),
    ]
}

/// The cache folder fuzzed: each case damages the SPIR-V entry, the
/// pipeline cache's entry or both, at random (a fixed seed, so CI runs the
/// same cases; `GLINT_FUZZ_SEED` explores others). Every render after it
/// writes the image of a clean cache and exits 0, and the next render
/// finds the cache whole again.
#[test]
fn a_damaged_cache_folder_never_changes_an_image() {
    use proptest::test_runner::{Config, RngSeed, TestRunner};
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let out = dir.path().join("a.pfm");
    let (want, _) = render(&cache, &out);
    let spirv = files_ending(&cache.join("glint/spirv"), ".spv.sealed").remove(0);
    let pipelines = files_ending(&cache.join("glint"), ".sealed").remove(0);
    let whole_spirv = std::fs::read(&spirv).unwrap();
    let whole_pipelines = std::fs::read(&pipelines).unwrap();
    let seed = match std::env::var("GLINT_FUZZ_SEED").ok().as_deref() {
        Some("random") => RngSeed::Random,
        Some(n) => RngSeed::Fixed(n.parse().expect("GLINT_FUZZ_SEED: a u64 or `random`")),
        None => RngSeed::Fixed(0x6361_6368),
    };
    let mut runner = TestRunner::new(Config {
        cases: 16,
        rng_seed: seed,
        failure_persistence: None,
        ..Config::default()
    });
    let which = || proptest::option::of(damage());
    runner
        .run(&(which(), which()), |(on_spirv, on_pipelines)| {
            for (path, whole) in [(&spirv, &whole_spirv), (&pipelines, &whole_pipelines)] {
                if path.is_dir() {
                    std::fs::remove_dir(path).unwrap();
                }
                std::fs::write(path, whole).unwrap();
            }
            if let Some(d) = &on_spirv {
                d.apply(&spirv, &whole_spirv);
            }
            if let Some(d) = &on_pipelines {
                d.apply(&pipelines, &whole_pipelines);
            }
            let (image, err) = render(&cache, &out);
            proptest::prop_assert!(image == want, "another image: {err}");
            // The render's own line, and an INFO line where it mended an entry.
            proptest::prop_assert!(
                err.lines()
                    .all(|l| l.starts_with("rendered ") || l.starts_with("info: ")),
                "{}",
                err
            );
            let (image, err) = render(&cache, &out);
            proptest::prop_assert!(image == want, "another image the second time: {err}");
            proptest::prop_assert!(!err.contains("damaged"), "still damaged: {}", err);
            Ok(())
        })
        .unwrap();
}
