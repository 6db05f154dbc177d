//! `glint explain`: one pixel's ray tree on the GPU, the CPU's f32 and the
//! f64 reference, side by side, down to the first number that differs
//! (docs/guide.md, Why does this pixel differ?). `compare --explain N` and
//! `drivers`' reproducers explain their worst pixels through it.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use clap::Args;
use serde_json::json;

use glint::explain::{
    explain_on_gpu, in_frame, record_words, samples, tree_of_words, Explanation, Sample, Tree,
};
use glint::gpu::{self, Renderer};
use glint::scene::Scene;

use super::console::outln;
use super::{DeviceArgs, Precision, SceneArgs};

#[derive(Args)]
pub struct ExplainArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// The pixel, X,Y from the top-left (0,0).
    #[arg(long, value_name = "X,Y", value_parser = parse_pixel)]
    pixel: (u32, u32),
    /// One sample of the pixel: j·samples + i of its grid, or the corner (0..4: top-left, top-right, bottom-left, bottom-right) where the scene samples corners [default: each in turn].
    #[arg(long, value_name = "I")]
    sample: Option<u32>,
    /// Print one JSON object on stdout: every renderer's tree, each ray with its origin, direction and the rest under their plain names.
    #[arg(long)]
    json: bool,
    /// Add the tree of the driver whose ICD file is FILE, run in a child process as `glint drivers` runs it; repeatable.
    #[arg(long, value_name = "FILE")]
    icd: Vec<PathBuf>,
    /// Print the GPU's record alone, for a parent `glint explain --icd` (internal).
    #[arg(long, hide = true)]
    record_only: bool,
    #[command(flatten)]
    device: DeviceArgs,
}

/// X,Y as two pixel coordinates.
fn parse_pixel(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("{s:?}: a pixel is X,Y, two whole numbers from 0 (the top-left)");
    let (x, y) = s.split_once(',').ok_or_else(bad)?;
    Ok((
        x.trim().parse().map_err(|_| bad())?,
        y.trim().parse().map_err(|_| bad())?,
    ))
}

pub fn run(a: &ExplainArgs) -> anyhow::Result<ExitCode> {
    let scene = a.scene.load()?;
    glint::cpu::bound::check(&scene)?;
    let chosen = samples(&scene, a.pixel, a.sample)?;
    let options = a.device.options()?;
    options.check()?;
    super::drivers::icd::check_given(&a.icd)?;
    let mut renderer = super::render_gpu::open(&options)?;
    if a.record_only {
        return record_only(&mut renderer, &scene, &options.settings, &chosen);
    }
    let others = Others {
        icds: a.icd.clone(),
        forward: forward(a),
    };
    let explained = explain(&mut renderer, &scene, &options.settings, &chosen, &others)?;
    let info = renderer.device_info();
    let agree = explained.iter().all(|e| e.agree);
    if a.json {
        // Written from the trees as they are: a `serde_json::Value` of a
        // tree of 2,000 rays under 16 lights took some 200 MB.
        let out = Printed {
            agree,
            device: info,
            height: scene.height,
            pixel: [a.pixel.0, a.pixel.1],
            samples: &explained,
            scene: &a.scene.scene,
            width: scene.width,
        };
        outln!(
            "{}",
            serde_json::to_string(&out).context("writing the trees as JSON")?
        );
    } else {
        outln!("{}", super::scene_line(&a.scene.scene, &scene));
        outln!("gpu f32    {} ({}, {})", info.name, info.kind, info.driver);
        outln!("{}", header());
        for e in &explained {
            outln!("\n{}", text(e, &scene));
        }
    }
    Ok(if agree {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

/// `explain --json`'s object (its keys in order, as before).
#[derive(serde::Serialize)]
struct Printed<'a> {
    agree: bool,
    device: &'a glint::gpu::DeviceInfo,
    height: u32,
    pixel: [u32; 2],
    samples: &'a [glint::explain::Explanation],
    scene: &'a std::path::Path,
    width: u32,
}

/// What the table's numbers are.
pub fn header() -> String {
    format!(
        "Coordinates are relative to the eye, as every renderer traces them. A quantity's f32 bound is the most that {} conditioning trials \
         (the scene, each hit point and each leaving direction moved by f32's roundings) and the CPU's own f32 move it, 4 times, and at \
         least 64 roundings of its size; `*` marks a value past it. The CPU f64 column is the reference.",
        glint::condition::TRIALS
    )
}

/// One sample's explanation as a person reads it: the sample, its table,
/// the verdict.
pub fn text(e: &Explanation, scene: &Scene) -> String {
    let [x, y] = e.sample.pixel;
    let which = match e.sample.traced {
        [tx, ty, ..] if scene.sampling == glint::scene::Sampling::Corners => format!(
            "corner {} of 4 (traced as pixel {tx},{ty} of the corner grid)",
            e.sample.index
        ),
        [_, _, i, j] => format!(
            "sample {} of {} (i {i}, j {j})",
            e.sample.index,
            scene.samples * scene.samples
        ),
    };
    format!("pixel {x},{y}, {which}\n\n{}\n{}", e.table, e.verdict())
}

/// The device options as words for a child `glint explain`.
fn forward(a: &ExplainArgs) -> Vec<std::ffi::OsString> {
    let mut v = a.scene.forward();
    v.extend(a.device.forward());
    v
}

/// Other drivers to run the samples on, in children, and the words that
/// give them the scene and the options.
pub struct Others {
    pub icds: Vec<PathBuf>,
    /// The scene file and its overrides, and the device options.
    pub forward: Vec<std::ffi::OsString>,
}

/// Each of `chosen` explained: its tree on `renderer`'s device and on
/// each of `others`' drivers, against the reference's.
pub fn explain(
    renderer: &mut Renderer,
    scene: &Scene,
    settings: &gpu::RenderSettings,
    chosen: &[Sample],
    others: &Others,
) -> anyhow::Result<Vec<Explanation>> {
    let mut out = Vec::new();
    for sample in chosen {
        let mut trees = Vec::new();
        for icd in &others.icds {
            let tree = child_tree(icd, &others.forward, *sample)?;
            trees.push(in_frame(tree, scene, settings.intersect));
        }
        out.push(explain_on_gpu(renderer, scene, settings, *sample, trees)?);
    }
    glint::explain::check_renders(renderer, scene, settings, &mut out)?;
    Ok(out)
}

/// The record of each sample on this process's device, as one JSON line
/// each: its device and its words.
fn record_only(
    renderer: &mut Renderer,
    scene: &Scene,
    settings: &gpu::RenderSettings,
    chosen: &[Sample],
) -> anyhow::Result<ExitCode> {
    let settings = gpu::RenderSettings {
        precision: Precision::F32,
        ..*settings
    };
    let device = renderer.device_info().name.clone();
    for sample in chosen {
        let words = record_words(renderer, scene, &settings, *sample)?;
        outln!("{}", json!({ "device": device, "words": words }));
    }
    Ok(ExitCode::SUCCESS)
}

/// The longest a child `glint explain --record-only` may take: opening
/// the device, the driver's compile of the recording variant (bounded by
/// `COMPILE_TIMEOUT` within it) and one pixel.
const CHILD_LIMIT: std::time::Duration = std::time::Duration::from_secs(600);

/// The tree of `sample` on the driver of `icd`, from a child glint bounded
/// as `drivers` bounds its children.
fn child_tree(
    icd: &std::path::Path,
    forward: &[std::ffi::OsString],
    sample: Sample,
) -> anyhow::Result<Tree> {
    use super::drivers::probe;
    let [x, y] = sample.pixel;
    let scratch = std::env::temp_dir().join(format!(
        "glint-explain-{}-{x}-{y}-{}",
        std::process::id(),
        sample.index
    ));
    let (out, err) = (
        scratch.with_extension("json"),
        scratch.with_extension("txt"),
    );
    let mut c = probe::on_driver(icd)?;
    c.arg("explain")
        .args(forward)
        .args([
            "--pixel",
            &format!("{x},{y}"),
            "--sample",
            &sample.index.to_string(),
            "--record-only",
        ])
        .stdout(
            std::fs::File::create(&out)
                .with_context(|| format!("cannot create {}", out.display()))?,
        );
    let status = probe::bounded(c, &err, CHILD_LIMIT);
    let said = std::fs::read_to_string(&err).unwrap_or_default();
    let printed = std::fs::read(&out).unwrap_or_default();
    let _ = (std::fs::remove_file(&out), std::fs::remove_file(&err));
    match status? {
        Some(s) if s.success() => {}
        Some(_) => anyhow::bail!(
            "--icd {}: the driver's glint failed: {}",
            icd.display(),
            glint::printable::one_line(said.trim())
        ),
        None => anyhow::bail!(
            "--icd {}: the driver's glint was still running after {} s: killed",
            icd.display(),
            CHILD_LIMIT.as_secs()
        ),
    }
    let record: serde_json::Value = serde_json::from_slice(&printed).with_context(|| {
        format!(
            "--icd {}: the driver's record could not be read",
            icd.display()
        )
    })?;
    let words: Vec<u32> = serde_json::from_value(record["words"].clone()).with_context(|| {
        format!(
            "--icd {}: the driver's record holds no words",
            icd.display()
        )
    })?;
    let device = record["device"].as_str().unwrap_or("a device");
    Ok(tree_of_words(
        &words,
        Precision::F32,
        &format!("gpu f32 on {device}"),
    )?)
}
