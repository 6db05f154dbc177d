//! Sampling decisions in the oracle's model (docs/guarantees.md, Sampling
//! decisions): a render replays the reference's decisions and traces its
//! samples, on either renderer; a near-tie that made f32 sample otherwise
//! is judged on the reference's samples, and passes; the decision check
//! fails where the replayed image, a decision or the plain image is wrong.

mod common;

use glint::accel::Accel;
use glint::condition::{judge, judge_rendered, Judgement};
use glint::cpu;
use glint::raster::diff::Tolerance;
use glint::raster::Image;
use glint::sampling::Sampled;
use glint::scene::decisions::Decisions;
use glint::scene::{Overrides, Scene};

type Rendered = (Image, Option<Sampled>);

fn f64_of(scene: &Scene) -> Rendered {
    cpu::render_sampled::<f64>(scene, Accel::Auto, &|_| {})
}

fn f32_of(scene: &Scene) -> Rendered {
    cpu::render_sampled::<f32>(scene, Accel::Auto, &|_| {})
}

/// The scenes whose sampling decides: adaptive (the Whitted scene), by
/// Mitchell's contrast and by the range test (the showcase), small.
fn deciding() -> Vec<Scene> {
    vec![
        common::resampled(
            "scenes/whitted-1980.toml",
            48,
            36,
            "sampling = \"adaptive\"\nthreshold = 0.05\nmax_level = 3\n",
        ),
        common::resampled(
            "scenes/showcase.toml",
            48,
            36,
            "sampling = \"contrast\"\nthresholds = [0.05, 0.05, 0.05]\nmax_samples = 17\n",
        ),
        common::resampled(
            "scenes/showcase.toml",
            48,
            36,
            "sampling = \"contrast\"\nrange = 0.02\nmax_samples = 33\ncompare_trees = false\n",
        ),
    ]
}

/// A generated scene whose f32 decisions differ from the reference's
/// (`glint fuzz --backend cpu --seed 99`, case 3671: one of 9 such among
/// 20,000).
fn near_tie() -> Scene {
    let path = common::repo().join("tests/data/adaptive-near-tie.toml");
    Scene::load(&path, &Overrides::default()).unwrap()
}

fn judged(scene: &Scene, plain: &Rendered, reference: &Rendered, replay: Rendered) -> Judgement {
    let replay = |_: &Scene| Ok::<_, ()>(replay);
    judge_rendered(
        scene,
        (&plain.0, plain.1.as_ref()),
        (&reference.0, reference.1.as_ref()),
        replay,
        &Tolerance::default(),
        Accel::Auto,
        &|_| {},
    )
    .unwrap()
}

/// A render replaying the reference's decisions takes each of them, and
/// notes none it would take otherwise where it is the reference again;
/// a render of the scene that decides nothing notes no decisions.
#[test]
fn a_replay_takes_the_references_decisions() {
    for scene in deciding() {
        let (reference, sampled) = f64_of(&scene);
        let sampled = sampled.expect("the scene decides");
        assert!(sampled.count > 0 && !sampled.taken.is_empty());
        let replaying = scene.replaying(&sampled.taken);
        let (again, own) = f64_of(&replaying);
        let own = own.unwrap();
        assert_eq!((again, &own.taken), (reference, &sampled.taken));
        assert!(own.otherwise.is_empty());
        let (_, f32s) = f32_of(&replaying);
        assert_eq!(f32s.unwrap().taken, sampled.taken, "f32 replays them too");
    }
    let centres = common::scene_sized(common::SMALL, 16, 12);
    assert!(f64_of(&centres).1.is_none());
}

/// The near-tie: f32 decides otherwise than f64 on a few squares, so its
/// own image samples otherwise there and is off by more than 1/255 in
/// some pixel. On the reference's samples it is within the tolerance over
/// every pixel, each decision it would take otherwise is one a trial
/// takes otherwise too, and its own image is the replay's wherever its
/// decisions are the reference's.
#[test]
fn a_near_tie_is_judged_on_the_references_samples() {
    let scene = near_tie();
    let reference = f64_of(&scene);
    let plain = f32_of(&scene);
    let (ours, theirs) = (plain.1.as_ref().unwrap(), reference.1.as_ref().unwrap());
    assert_ne!(ours.taken, theirs.taken, "f32 decides otherwise somewhere");
    let tolerance = Tolerance::default();
    let old = judge(
        &scene,
        &plain.0,
        &reference.0,
        &tolerance,
        Accel::Auto,
        &|_| {},
    );
    assert!(old.error.frac_over_1_255 > 0.0, "{:?}", old.error);
    let replayed = f32_of(&scene.replaying(&theirs.taken));
    let j = judged(&scene, &plain, &reference, replayed);
    assert!(j.pass(), "{:?}", j.violations);
    assert!(
        j.conditioned.is_none(),
        "the same samples pass over every pixel"
    );
    let d = j.decisions.expect("the scene decides");
    assert!(d.otherwise > 0 && d.unexplained == 0, "{d:?}");
    assert!(d.sampled_otherwise > 0.0 && d.plain.is_some());
}

/// The check can fail: a replayed image off the reference, a decision
/// taken otherwise that no trial explains, a plain image off its replay
/// where its decisions are the reference's, and decisions that differ
/// but do not on the same samples.
#[test]
fn the_decision_check_can_fail() {
    let scene = near_tie();
    let reference = f64_of(&scene);
    let plain = f32_of(&scene);
    let theirs = reference.1.clone().unwrap();
    let replayed = f32_of(&scene.replaying(&theirs.taken));
    assert!(judged(&scene, &plain, &reference, replayed.clone()).pass());

    let mut off = replayed.clone();
    let tenth = off.0.pixels.len() / 10;
    for p in &mut off.0.pixels[..tenth] {
        p[1] += 0.05;
    }
    let j = judged(&scene, &plain, &reference, off);
    assert!(!j.pass(), "a replayed image off the reference");

    // Every decision the reference took, said to go otherwise: far more
    // than the trials take otherwise.
    let mut wrong = replayed.clone();
    let sampled = wrong.1.as_mut().unwrap();
    sampled.otherwise = sampled.otherwise.union(&theirs.taken);
    let j = judged(&scene, &plain, &reference, wrong);
    let d = j.decisions.unwrap();
    assert!(d.unexplained > 0, "{d:?}");
    assert!(
        j.violations.iter().any(|v| v.contains("no trial")),
        "{:?}",
        j.violations
    );

    // A pixel whose decisions are the reference's, off in the plain image.
    let ours = plain.1.as_ref().unwrap();
    let differing = ours.taken.pixels_differing(&theirs.taken, scene.width);
    let kept = (0..plain.0.pixels.len())
        .find(|i| differing.binary_search(i).is_err())
        .unwrap();
    let mut moved = plain.clone();
    moved.0.pixels[kept][0] += 1e-3;
    let j = judged(&scene, &moved, &reference, replayed.clone());
    assert!(
        j.violations
            .iter()
            .any(|v| v.contains("differs from its replay")),
        "{:?}",
        j.violations
    );

    // Decisions that differ, yet none taken otherwise on the same samples.
    let mut none = replayed;
    none.1.as_mut().unwrap().otherwise = Decisions::default();
    let j = judged(&scene, &plain, &reference, none);
    assert!(
        j.violations.iter().any(|v| v.contains("does not repeat")),
        "{:?}",
        j.violations
    );
}

/// The GPU replays the reference's decisions as the CPU does, and passes
/// on the near-tie's samples; `compare` says what it judged.
#[cfg(feature = "gpu")]
#[test]
fn the_gpu_replays_the_references_decisions() {
    let mut gpu = common::gpu();
    let settings = gpu.settings();
    for scene in deciding().into_iter().chain([near_tie()]) {
        let (_, sampled) = f64_of(&scene);
        let taken = sampled.unwrap().taken;
        let replaying = scene.replaying(&taken);
        let r = gpu.prepare(&replaying, &settings).unwrap();
        let rendered = { r }.render(None, &|_| {}).unwrap();
        assert_eq!(rendered.sampled.unwrap().taken, taken);
    }
    let path = common::repo().join("tests/data/adaptive-near-tie.toml");
    let run = common::cmd()
        .args(["compare", "--json"])
        .arg(&path)
        .assert()
        .success();
    let out = common::json_of(&run);
    assert!(out["decisions"]["decisions"].as_u64().unwrap() > 0, "{out}");
    assert_eq!(out["decisions"]["unexplained"], 0);
}
