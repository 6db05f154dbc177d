//! What glint holds itself to in memory, shown under a cap of address
//! space (`ulimit -v`): the tables' build for thousands of lights stays
//! within a bound whatever their number, and a render too large for memory
//! is refused in one line before its images are allocated.

mod common;

use std::path::Path;
use std::process::{Command, Output};

/// Runs glint with `args` under a cap of `mib` MiB of address space (as
/// `ulimit -v` sets it), so that a run that needs more fails.
fn capped(mib: u64, args: &[&str]) -> Output {
    let mut line = format!("ulimit -v {} && exec \"$0\"", mib * 1024);
    for (i, _) in args.iter().enumerate() {
        line.push_str(&format!(" \"${{{}}}\"", i + 1));
    }
    Command::new("bash")
        .arg("-c")
        .arg(line)
        .arg(env!("CARGO_BIN_EXE_glint"))
        .args(args)
        .output()
        .unwrap()
}

/// `n` spheres and `n` point lights scattered over a box, as a scene.
fn crowd(n: usize) -> String {
    let mut s = String::from(
        "[image]\nwidth = 16\nheight = 12\n[camera]\neye = [0, 0, 60]\nlook_at = [0, 0, 0]\n\
         vfov = 60\n[materials.m]\ndiffuse = [0.5, 0.5, 0.5]\n",
    );
    // A fixed scatter (a Weyl sequence): no generator needed.
    let at = |i: usize, k: f64, span: f64| ((i as f64 * k).fract() - 0.5) * span;
    for i in 0..n {
        s += &format!(
            "[[spheres]]\ncenter = [{}, {}, {}]\nradius = 0.3\nmaterial = \"m\"\n",
            at(i, 0.618_034, 40.0),
            at(i, 0.414_214, 40.0),
            at(i, 0.732_051, 40.0)
        );
    }
    for i in 0..n {
        s += &format!(
            "[[lights]]\ntype = \"point\"\nposition = [{}, {}, {}]\ndiffuse = [0.001, 0.001, 0.001]\n",
            at(i, 0.236_068, 60.0),
            at(i, 0.162_278, 60.0),
            at(i, 0.605_551, 60.0)
        );
    }
    s
}

/// `--accel tables` built a light buffer for each of 3,000
/// lights over 3,000 spheres and grew past 2.3 GB (the walk takes 19 MB).
/// The build's working memory is bounded by a few budgets now, whatever
/// the number of lights: the scene renders under a 384 MiB cap of address
/// space (676c44f aborted under it), to the walk's bits.
#[test]
fn tables_for_thousands_of_lights_stay_within_a_bound() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("crowd.toml");
    std::fs::write(&scene, crowd(3000)).unwrap();
    let out = |name: &str| dir.path().join(name).display().to_string();
    let s = scene.display().to_string();
    let mut outputs = Vec::new();
    for (accel, name) in [("tables", "t.pfm"), ("bvh", "b.pfm")] {
        let o = capped(
            384,
            &[
                "render",
                &s,
                "--backend",
                "cpu",
                "--accel",
                accel,
                "-o",
                &out(name),
            ],
        );
        assert!(
            o.status.success(),
            "--accel {accel}: {:?} {}",
            o.status,
            String::from_utf8_lossy(&o.stderr)
        );
        outputs.push(glint::raster::io::read(Path::new(&out(name))).unwrap());
    }
    assert!(common::same_bits(&outputs[0], &outputs[1]));
}

/// Found in the Python module, and the binary had it too):
/// `render` at 16384x16384 under a 3 GiB cap aborted on an allocation, on
/// the CPU and the GPU. It is refused before the images are allocated, in
/// one line, with exit status 2 and no output file.
#[test]
fn a_render_that_does_not_fit_in_memory_is_refused_first() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("big.pfm");
    let scene = common::repo().join("scenes/seed-fig4.toml");
    let backends: &[&str] = if cfg!(feature = "gpu") {
        &["cpu", "gpu"]
    } else {
        &["cpu"]
    };
    for backend in backends {
        let o = capped(
            3072,
            &[
                "render",
                scene.to_str().unwrap(),
                "--width",
                "16384",
                "--height",
                "16384",
                "--backend",
                backend,
                "-o",
                out.to_str().unwrap(),
            ],
        );
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{backend}: {:?} {err}", o.status);
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.contains("a 16384x16384 render needs"), "{err}");
        assert!(!out.exists());
    }
}
