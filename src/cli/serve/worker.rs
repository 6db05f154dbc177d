//! The two threads behind the page. The render thread owns the device: it
//! looks at the inputs' stamps (as `watch` does), renders the scene again
//! when one changed and shows the image at once, and answers the page's
//! pixel explanations and the reference thread's replays. The reference
//! thread makes the CPU f64 reference of the newest render and judges the
//! render against it as `glint compare` does, in the background.

use std::path::PathBuf;
use std::sync::mpsc::{self, Receiver, RecvTimeoutError, Sender};
use std::sync::{Arc, Condvar, Mutex};
use std::time::{Duration, Instant};

use glint::condition;
use glint::files::Stamp;
use glint::gpu::{GpuError, GpuOptions, Renderer};
use glint::raster::diff::{self, Tolerance};
use glint::raster::Image;
use glint::sampling::Sampled;
use glint::scene::{Sampling, Scene};

use super::state::{Frame, GpuStatus, ReferenceStatus, State, Verdict};
use crate::cli::{DeviceArgs, SceneArgs};

/// What the other threads ask of the render thread.
pub enum Job {
    /// Pixel (x, y) of the newest good scene explained: the JSON the page
    /// reads, or the error in words.
    Explain {
        x: u32,
        y: u32,
        reply: Sender<Result<String, String>>,
    },
    /// A render of `scene` (the reference's sampling decisions replayed),
    /// for the judgement of the render it replays.
    Replay {
        scene: Box<Scene>,
        reply: Sender<Result<(Image, Option<Sampled>), String>>,
    },
}

/// How often the inputs' stamps are looked at: a saved edit is seen
/// within this.
const LOOK: Duration = Duration::from_millis(25);

/// The inputs of a render, each with what says it changed: the scene
/// file, the files it names and the user's shader files.
fn stamps(files: &[PathBuf]) -> Vec<(PathBuf, Option<Stamp>)> {
    files
        .iter()
        .map(|f| (f.clone(), Stamp::of_file(f)))
        .collect()
}

/// A GPU render waiting for its reference.
struct Pending {
    generation: u64,
    scene: Arc<Scene>,
    image: Image,
    sampled: Option<Sampled>,
}

/// The newest render without a reference: a later one replaces it.
#[derive(Default)]
pub struct Queue {
    next: Mutex<Option<Pending>>,
    ready: Condvar,
}

/// The render thread: runs until the process ends.
pub fn render_thread(
    scene_args: SceneArgs,
    device: DeviceArgs,
    options: GpuOptions,
    mut renderer: Renderer,
    state: Arc<State>,
    jobs: Receiver<Job>,
    queue: Arc<Queue>,
) {
    let name = renderer.device_info().name.clone();
    let mut generation = 0;
    let mut good: Option<Arc<Scene>> = None;
    let mut files = {
        let mut f = vec![scene_args.scene.clone()];
        f.extend(device.inputs());
        f
    };
    let mut last = None;
    loop {
        match jobs.recv_timeout(LOOK) {
            Ok(job) => answer(job, &mut renderer, good.as_deref()),
            Err(RecvTimeoutError::Timeout) => {}
            Err(RecvTimeoutError::Disconnected) => return,
        }
        let now = stamps(&files);
        if last.as_ref() == Some(&now) {
            continue;
        }
        last = Some(now.clone());
        state.change(|s| s.status.rendering = true);
        let started = Instant::now();
        let rendered = scene_args.load().and_then(|scene| {
            glint::cpu::bound::check(&scene)?;
            let settings = renderer.settings();
            let r = renderer.prepare(&scene, &settings)?.render(None, &|_| {})?;
            Ok((scene, r))
        });
        match rendered {
            Ok((scene, r)) => {
                generation += 1;
                let scene = Arc::new(scene);
                // The files it names now (a new mesh, a texture), each
                // with its stamp from before the load: a change made while
                // it rendered is seen at the next look, not lost.
                files = crate::cli::inputs(&scene_args.scene, &scene, &device);
                last = Some(
                    files
                        .iter()
                        .map(|f| match now.iter().find(|(g, _)| g == f) {
                            Some((_, stamp)) => (f.clone(), stamp.clone()),
                            None => (f.clone(), Stamp::of_file(f)),
                        })
                        .collect(),
                );
                let frame = Frame::of(generation, &r.image, scene.srgb);
                let render_s = started.elapsed().as_secs_f64();
                state.change(|s| {
                    s.status.rendering = false;
                    s.status.error = None;
                    s.status.width = scene.width;
                    s.status.height = scene.height;
                    s.status.gpu = Some(GpuStatus {
                        generation,
                        device: name.clone(),
                        render_s,
                        trace_s: r.times.dispatch_s,
                    });
                    s.gpu = Some(frame);
                });
                *queue.next.lock().unwrap_or_else(|p| p.into_inner()) = Some(Pending {
                    generation,
                    scene: scene.clone(),
                    image: r.image,
                    sampled: r.sampled,
                });
                queue.ready.notify_one();
                good = Some(scene);
            }
            Err(e) => {
                let lost = e
                    .downcast_ref::<GpuError>()
                    .is_some_and(GpuError::device_lost);
                state.change(|s| {
                    s.status.rendering = false;
                    s.status.error = Some(format!("error: {e:#}"));
                });
                // A lost device takes no more work: the next change
                // renders on a new one.
                if lost {
                    match Renderer::new(&options) {
                        Ok(r) => renderer = r,
                        Err(e) => state.change(|s| {
                            s.status.error = Some(format!("error: {e:#}"));
                        }),
                    }
                }
            }
        }
    }
}

/// Does what another thread asked of the device.
fn answer(job: Job, renderer: &mut Renderer, scene: Option<&Scene>) {
    match job {
        Job::Explain { x, y, reply } => {
            let answer = match scene {
                None => Err("no image has rendered yet".to_owned()),
                Some(scene) => super::explained::json(renderer, scene, (x, y))
                    .map_err(|e| format!("error: {e:#}")),
            };
            let _ = reply.send(answer);
        }
        Job::Replay { scene, reply } => {
            let settings = renderer.settings();
            let r = renderer
                .prepare(&scene, &settings)
                .and_then(|mut p| p.render(None, &|_| {}))
                .map(|r| (r.image, r.sampled))
                .map_err(|e| format!("{e:#}"));
            let _ = reply.send(r);
        }
    }
}

/// The reference thread: runs until the process ends.
pub fn reference_thread(
    state: Arc<State>,
    queue: Arc<Queue>,
    jobs: Sender<Job>,
    accel: glint::accel::Accel,
) {
    loop {
        let pending = {
            let next = queue.next.lock().unwrap_or_else(|p| p.into_inner());
            let mut next = queue
                .ready
                .wait_while(next, |n| n.is_none())
                .unwrap_or_else(|p| p.into_inner());
            next.take().expect("woken with a render")
        };
        state.change(|s| s.status.referencing = true);
        let started = Instant::now();
        let scene = &pending.scene;
        let prepared = glint::cpu::Prepared::<f64>::new(scene, accel);
        // Adaptive and contrast sampling's decisions are judged on the
        // reference's samples; their render does not count rays.
        let sampled_by_decisions = scene.sampling == Sampling::Adaptive || scene.contrast.is_some();
        let (reference, reference_sampled, rays) = if sampled_by_decisions {
            let (image, sampled) = prepared.render_sampled(&|_| {});
            (image, sampled, None)
        } else {
            let (image, counts) = prepared.render_counted(&|_| {});
            (image, None, Some(counts.rays()))
        };
        let seconds = started.elapsed().as_secs_f64();
        let replay = |replaying: &Scene| {
            let (reply, answer) = mpsc::channel();
            jobs.send(Job::Replay {
                scene: Box::new(replaying.clone()),
                reply,
            })
            .map_err(|_| "the render thread has stopped".to_owned())?;
            answer
                .recv()
                .map_err(|_| "the render thread has stopped".to_owned())?
        };
        let judged = condition::judge_rendered(
            scene,
            (&pending.image, pending.sampled.as_ref()),
            (&reference, reference_sampled.as_ref()),
            replay,
            &Tolerance::default(),
            accel,
            &|_| {},
        );
        let frame = Frame::of(pending.generation, &reference, scene.srgb);
        let map = diff::heat_map(&pending.image, &reference)
            .ok()
            .map(|m| Frame::of(pending.generation, &m, false));
        let generation = pending.generation;
        state.change(|s| {
            s.status.referencing = false;
            s.status.reference = Some(ReferenceStatus {
                generation,
                seconds,
            });
            s.reference = Some(frame);
            s.error_map = map;
            s.status.verdict = Some(match judged {
                Ok(j) => verdict(generation, &j, rays),
                Err(e) => Verdict {
                    generation,
                    pass: false,
                    lines: vec![format!("the check could not run: {e}")],
                    max_abs: f64::NAN,
                    rmse: f64::NAN,
                    frac_over_1_255: f64::NAN,
                    ill: None,
                    violations: vec![e],
                    rays,
                },
            });
        });
    }
}

/// compare's verdict of a judgement, in its words.
fn verdict(
    generation: u64,
    j: &condition::Judgement,
    rays: Option<glint::stats::RayCounts>,
) -> Verdict {
    let tolerance = Tolerance::default();
    let mut lines = vec![format!(
        "gpu error  {}",
        crate::cli::diff::format_figures(&j.error)
    )];
    if let Some(d) = &j.decisions {
        lines.push(crate::cli::diff::format_decisions(d));
    }
    if let Some(c) = &j.conditioned {
        lines.extend(crate::cli::diff::condition_lines(c));
    }
    lines.push(crate::cli::diff::tolerance_line(
        &tolerance,
        j.conditioned.is_some(),
        j.pass(),
    ));
    Verdict {
        generation,
        pass: j.pass(),
        lines,
        max_abs: j.error.max_abs,
        rmse: j.error.rmse,
        frac_over_1_255: j.error.frac_over_1_255,
        ill: j.conditioned.as_ref().map(|c| c.ill),
        violations: j.violations.clone(),
        rays,
    }
}
