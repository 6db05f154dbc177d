//! The oracle over the scene space (docs/guarantees.md, Generated scenes):
//! the CI set of generated scenes (every mix of kinds, lights, reflection
//! and transmission, the other factors by a covering array) and fixed
//! random ones, each held to the CPU f64 reference and to the metamorphic
//! properties, on the GPU (with the validation layer) and on the CPU; the
//! set's coverage; shrinking; and the corpus of scenes that failed once,
//! tests/data/found/.

mod common;

use std::collections::BTreeSet;

use glint::accel::Accel;
use glint::cpu;
use glint::fuzz::{self, Device, Failure, Property};
use glint::generate::{space, Spec};
use glint::raster::Image;
use glint::scene::{Overrides, Scene, LIGHT_TYPES};

/// The CI set's scenes are 16×12, from this seed.
const SEED: u64 = 56;
/// Random scenes a lane checks, of up to 40 objects.
const RANDOM: u64 = 12;

fn ci_specs() -> Vec<Spec> {
    space::ci().iter().map(|p| p.spec(SEED, 16, 12)).collect()
}

fn random_specs() -> Vec<Spec> {
    (0..RANDOM)
        .map(|i| space::random(glint::generate::case_seed(SEED, i), 40, 16, 12))
        .collect()
}

fn report(failed: &[(usize, Vec<Failure>)], specs: &[Spec]) -> String {
    failed
        .iter()
        .map(|(i, f)| format!("case {i}: {f:?}\n{}", specs[*i].scene().text))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The CPU's properties (f32 against f64, every scene management, a dark
/// light, the file's order, depth, a moved scene) over the CI set and the
/// random scenes: every lane, the CPU-only one included.
#[test]
fn the_generated_scenes_keep_the_cpu_properties() {
    let specs: Vec<Spec> = ci_specs().into_iter().chain(random_specs()).collect();
    let cpu_only = |p: Property| !p.on_gpu();
    let failed: Vec<(usize, Vec<Failure>)> = specs
        .iter()
        .enumerate()
        .map(|(i, s)| (i, fuzz::check(s, None, &cpu_only)))
        .filter(|(_, f)| !f.is_empty())
        .collect();
    assert!(failed.is_empty(), "{}", report(&failed, &specs));
}

/// The GPU's properties over the CI set (the costly ones, which compile
/// more variants, on the covering array's rows and the random scenes
/// alone), with the validation layer on. The scenes are checked in chunks,
/// each in a child process of this test, so that a driver that crashes
/// names its chunk rather than ending the test binary: Mesa 22.3's
/// lavapipe corrupted its heap and crashed on uniform-buffer variants here
/// (SIGSEGV in the validation layer's vkDestroyPipeline, glibc's
/// "corrupted size vs. prev_size"), until glint stopped giving it any
/// (`DeviceInfo::reads_uniform_arrays`).
#[cfg(feature = "gpu")]
#[test]
fn the_generated_scenes_agree_with_the_reference_on_the_gpu() {
    let specs: Vec<Spec> = ci_specs().into_iter().chain(random_specs()).collect();
    if let Some(chunk) = std::env::var("GLINT_GENERATED_CHUNK")
        .ok()
        .and_then(|c| c.parse::<usize>().ok())
    {
        return check_chunk(&specs, chunk);
    }
    let mut failed = Vec::new();
    for chunk in 0..specs.len().div_ceil(CHUNK) {
        let o = std::process::Command::new(std::env::current_exe().unwrap())
            .args([
                "the_generated_scenes_agree_with_the_reference_on_the_gpu",
                "--exact",
                "--test-threads",
                "1",
                "--nocapture",
            ])
            .env("GLINT_GENERATED_CHUNK", chunk.to_string())
            .output()
            .unwrap();
        if !o.status.success() {
            let text = String::from_utf8_lossy(&o.stderr).into_owned();
            failed.push(format!(
                "scenes {} to {}: {:?}\n{}",
                chunk * CHUNK,
                ((chunk + 1) * CHUNK).min(specs.len()) - 1,
                o.status,
                &text[text.len().saturating_sub(20_000)..]
            ));
        }
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}

/// Scenes one child process checks.
#[cfg(feature = "gpu")]
const CHUNK: usize = 64;

/// Checks `specs`' chunk `chunk` on one renderer, as the child of
/// `the_generated_scenes_agree_with_the_reference_on_the_gpu`.
#[cfg(feature = "gpu")]
fn check_chunk(specs: &[Spec], chunk: usize) {
    let opts = glint::gpu::GpuOptions {
        validate: true,
        ..glint::gpu::GpuOptions::default()
    };
    let mut gpu = fuzz::GpuOracle::new(&opts).expect("the Vulkan device");
    let core = ci_specs().len() - space::pairwise_rows();
    let mut failed = Vec::new();
    let end = ((chunk + 1) * CHUNK).min(specs.len());
    for (i, s) in specs.iter().enumerate().take(end).skip(chunk * CHUNK) {
        let all = i >= core;
        let wanted = move |p: Property| p.on_gpu() && (all || !p.costly());
        let f = fuzz::check(s, Some(&mut gpu), &wanted);
        if !f.is_empty() {
            failed.push((i, f));
        }
    }
    assert!(failed.is_empty(), "{}", report(&failed, specs));
}

/// The CI set holds every kind, light type, pattern, material feature and
/// sampling mode, every pair of a kind and a light type, and the scene of
/// the first defect the generated scenes found (spheres alone, no light, a material that
/// neither reflects nor transmits); the random scenes add scale, offset,
/// the eye inside and grazing lights, and the BVH's threshold.
#[test]
fn the_ci_set_covers_the_tables() {
    let specs = ci_specs();
    let kinds = glint::generate::kind_keys();
    let mut seen = BTreeSet::new();
    for s in &specs {
        let present: BTreeSet<usize> = s.objects.iter().map(|o| o.kind).collect();
        for &k in &present {
            seen.insert(format!("kind {}", kinds[k]));
            if s.lights.is_empty() {
                seen.insert(format!("kind {} with no light", kinds[k]));
            }
            for l in &s.lights {
                seen.insert(format!(
                    "kind {} with {}",
                    kinds[k], LIGHT_TYPES[l.kind].name
                ));
            }
        }
        for l in &s.lights {
            seen.insert(format!("light {}", LIGHT_TYPES[l.kind].name));
        }
        seen.insert(format!("{} lights", s.lights.len()));
        seen.insert(format!("no objects: {}", s.objects.is_empty()));
        seen.insert(format!("reflect {}", s.reflect));
        seen.insert(format!("transmit {}", s.transmit));
        seen.insert(format!("texture {:?}", s.texture));
        seen.insert(format!("shadows {}", s.shadows));
        seen.insert(format!("sampling {:?}", s.sampling));
        seen.insert(format!("depth {}", s.depth));
        if present == BTreeSet::from([0]) && s.lights.is_empty() && !s.reflect && !s.transmit {
            seen.insert("spheres alone, no light, nothing reflected".into());
        }
    }
    let mut wanted: Vec<String> = Vec::new();
    for k in &kinds {
        wanted.push(format!("kind {k}"));
        wanted.push(format!("kind {k} with no light"));
        for t in LIGHT_TYPES {
            wanted.push(format!("kind {k} with {}", t.name));
        }
    }
    for t in LIGHT_TYPES {
        wanted.push(format!("light {}", t.name));
    }
    for p in glint::generate::pattern_count_options() {
        wanted.push(format!("texture {p:?}"));
    }
    for s in space::SAMPLINGS {
        wanted.push(format!("sampling {s:?}"));
    }
    for b in [false, true] {
        wanted.extend([
            format!("reflect {b}"),
            format!("transmit {b}"),
            format!("shadows {b}"),
            format!("no objects: {b}"),
        ]);
    }
    wanted.extend(["0 lights", "1 lights", "2 lights", "depth 1", "depth 3"].map(String::from));
    wanted.push("spheres alone, no light, nothing reflected".into());
    let missing: Vec<&String> = wanted.iter().filter(|w| !seen.contains(*w)).collect();
    assert!(missing.is_empty(), "the CI set lacks {missing:?}");

    let random = random_specs();
    assert!(random.iter().any(|s| s.scale != 1.0));
    assert!(random.iter().any(|s| s.offset != [0.0; 3]));
    assert!(random.iter().any(|s| s.eye_inside));
    assert!(random.iter().any(|s| s.grazing));
    assert!(random
        .iter()
        .any(|s| s.objects.len() > glint::accel::AUTO_MIN_BOUNDED));
}

/// The CI set's covering array holds every pair of values of every two
/// factors.
#[test]
fn the_covering_array_holds_every_pair() {
    let sizes = [3, 3, 5, 2, 4, 3];
    let rows = space::pairwise(&sizes, 1);
    for a in 0..sizes.len() {
        for b in a + 1..sizes.len() {
            for x in 0..sizes[a] {
                for y in 0..sizes[b] {
                    assert!(
                        rows.iter().any(|r| r[a] == x && r[b] == y),
                        "factors {a}={x} and {b}={y}"
                    );
                }
            }
        }
    }
    // Far fewer rows than the product (3·3·5·2·4·3 = 1080).
    assert!(rows.len() <= 30, "{} rows", rows.len());
}

/// A renderer with a defect planted: the CPU's f32 image, with `defect`
/// applied where the scene has `when`.
struct Planted {
    when: fn(&Scene) -> bool,
    defect: fn(&mut Image),
}

impl Device for Planted {
    fn check(
        &mut self,
        scene: &Scene,
        reference: &fuzz::Reference,
        wanted: fuzz::Wanted,
    ) -> Vec<Failure> {
        let mut img = cpu::render::<f32>(scene);
        if (self.when)(scene) {
            (self.defect)(&mut img);
        }
        if !wanted(Property::GpuCompare) {
            return vec![];
        }
        fuzz::compare_failure(scene, &img, &reference.image)
            .map(|detail| Failure {
                property: Property::GpuCompare,
                detail,
            })
            .into_iter()
            .collect()
    }
}

/// The generated scenes' first defect, planted: garbage where a scene has spheres and no
/// light. The CI set finds it, and a random scene of many objects that
/// has it shrinks to one sphere, no light, a plain material; a renderer
/// without the defect passes the same scenes.
#[test]
fn a_planted_defect_is_found_and_shrunk() {
    let garbage = |img: &mut Image| {
        for p in img.pixels.iter_mut().step_by(4) {
            *p = [4.3e4; 3];
        }
    };
    let no_light_spheres = |s: &Scene| s.lights.is_empty() && !s.prims.spheres.is_empty();
    let mut planted = Planted {
        when: no_light_spheres,
        defect: garbage,
    };
    let gpu_only = |p: Property| p == Property::GpuCompare;
    let specs = ci_specs();
    let found: Vec<&Spec> = specs
        .iter()
        .filter(|s| !fuzz::check(s, Some(&mut planted), &gpu_only).is_empty())
        .collect();
    assert!(!found.is_empty(), "the CI set missed the planted defect");
    assert!(found
        .iter()
        .all(|s| s.lights.is_empty() && s.objects.iter().any(|o| o.kind == 0)));

    // A large random scene with it: shrunk to its smallest form.
    let big = (0..200)
        .map(|i| space::random(glint::generate::case_seed(7, i), 30, 16, 12))
        .find(|s| {
            s.lights.is_empty()
                && s.objects.len() > 10
                && s.objects.iter().any(|o| o.kind == 0)
                && (s.reflect || s.transmit || s.texture.is_some())
        })
        .expect("a random scene with spheres and no light");
    let (small, failures, checks) =
        fuzz::shrink(&big, Property::GpuCompare, Some(&mut planted), 200);
    assert!(!failures.is_empty());
    assert_eq!(small.objects.len(), 1, "{small:?}");
    assert_eq!(small.objects[0].kind, 0, "{small:?}");
    assert!(small.lights.is_empty() && !small.reflect && !small.transmit);
    assert!(small.texture.is_none() && small.depth == 1, "{small:?}");
    assert!(checks <= 200);

    // The same device without the defect passes every scene it failed.
    let mut clean = Planted {
        when: |_| false,
        defect: garbage,
    };
    for s in found {
        assert!(fuzz::check(s, Some(&mut clean), &gpu_only).is_empty());
    }
}

/// Each metamorphic property can fail: a scene changed where the property
/// says it must not change is caught.
#[test]
fn a_changed_image_fails_the_exact_properties() {
    let spec = ci_specs()
        .into_iter()
        .find(|s| s.objects.len() > 1 && !s.lights.is_empty())
        .expect("a scene with objects and lights");
    let (scene, _dir) = fuzz::load(&spec).unwrap();
    let a = cpu::render::<f64>(&scene);
    let mut b = a.clone();
    b.pixels[5][1] = f32::from_bits(b.pixels[5][1].to_bits() ^ 1);
    assert!(fuzz::first_difference(&a, &a).is_none());
    let d = fuzz::first_difference(&b, &a).expect("one bit apart");
    assert!(d.starts_with("pixel (5, 0)"), "{d}");
    // Past the tolerance: the comparison fails.
    let mut c = a.clone();
    for p in c.pixels.iter_mut().take(20) {
        p[0] += 0.5;
    }
    assert!(fuzz::compare_failure(&scene, &c, &a).is_some());
}

/// Scenes the oracle found failing once, kept so that they never come
/// back: each renders on the GPU within the reference's tolerance, and the
/// CPU's f32 too (every lane; the CPU-only one checks the CPU alone).
#[test]
fn the_found_scenes_stay_fixed() {
    let files = common::scene_files("tests/data/found");
    assert!(!files.is_empty(), "tests/data/found holds the corpus");
    #[cfg(feature = "gpu")]
    let mut gpu = common::gpu();
    for path in files {
        let scene = Scene::load(&path, &Overrides::default())
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let f32_of = |s: &Scene| cpu::render_sampled::<f32>(s, Accel::Auto, &|_| {});
        let (image, sampled) = cpu::render_sampled::<f64>(&scene, Accel::Auto, &|_| {});
        let reference = fuzz::Reference { image, sampled };
        let (f32, sampled) = f32_of(&scene);
        let replay = |s: &Scene| Ok::<_, std::convert::Infallible>(f32_of(s));
        let verdict = fuzz::compare_rendered(&scene, (&f32, sampled.as_ref()), &reference, replay);
        assert!(verdict.is_none(), "{} CPU f32: {verdict:?}", path.display());
        #[cfg(feature = "gpu")]
        {
            let settings = gpu.settings();
            let rendered = gpu
                .prepare(&scene, &settings)
                .unwrap()
                .render(None, &|_| {});
            let rendered = rendered.unwrap();
            let replay = |s: &Scene| {
                let r = gpu.prepare(s, &settings)?.render(None, &|_| {})?;
                Ok::<_, glint::gpu::GpuError>((r.image, r.sampled))
            };
            let own = (&rendered.image, rendered.sampled.as_ref());
            let verdict = fuzz::compare_rendered(&scene, own, &reference, replay);
            assert!(verdict.is_none(), "{}: {verdict:?}", path.display());
        }
    }
}

/// `glint drivers --generated N` holds every driver to the reference on N
/// generated scenes, written under -o, as on the scenes named.
#[cfg(feature = "gpu")]
#[test]
fn drivers_runs_generated_scenes() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let icd = std::fs::read_dir("/usr/share/vulkan/icd.d")
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .find(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("lvp_icd"))
        })
        .expect("lavapipe's ICD file");
    let o = common::glint(&[
        "drivers",
        "--generated",
        "3",
        "--quick",
        "--icd",
        icd.to_str().unwrap(),
        "--only",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("drivers.json")).unwrap()).unwrap();
    let rows: Vec<&str> = json["rows"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["scene"].as_str().unwrap())
        .collect();
    assert_eq!(rows, ["case-56-0", "case-56-1", "case-56-2"]);
    assert!(out.join("generated/case-56-2.toml").is_file());
}
