//! One scene on one driver, as `glint drivers` runs it: the probe's run
//! under its deadline and its verdict, and for a failure the reproducer,
//! its explanation and the shader it compiled.

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use glint::drivers::repro::{self, Size};
use glint::drivers::verdict::{self, Verdict};
use glint::drivers::{shrink, Identity};
use glint::raster::Image;
use glint::scene::Scene;

use super::folder::folder;
use super::identify::Driver;
use super::probe::{self, Job};
use super::rows::reference;
use super::Run;
use crate::cli::scene_name;

impl Run<'_> {
    /// Whether the run's --budget has run out: no driver's run starts.
    pub(super) fn past_budget(&self) -> bool {
        self.ends.is_some_and(|e| Instant::now() >= e)
    }

    /// `scene` (from `path`) on driver `d`, waited for at most `deadline`:
    /// the verdict, the image where it made one, and the child's stderr
    /// file.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn scene(
        &self,
        d: &Driver,
        path: &Path,
        scene: &Scene,
        reference: &Image,
        tag: &str,
        size: Size,
        deadline: Duration,
    ) -> anyhow::Result<(Verdict, Option<Image>, PathBuf)> {
        let out = self.work.join(format!(
            "{}-{}-{tag}",
            folder(&d.name, &d.icd),
            folder(&scene_name(path), path)
        ));
        let mut args: Vec<OsString> = vec!["--scene".into(), path.as_os_str().to_owned()];
        for w in size.args() {
            args.push(w.into());
        }
        args.extend(self.device_args.iter().cloned());
        let job = Job {
            icd: &d.icd,
            args,
            out: out.clone(),
            deadline,
        };
        let ended = job.run()?;
        let (v, image) = verdict::judge(ended, &out, scene, reference, self.args.device.accel);
        Ok((v, image, out.join("stderr.txt")))
    }

    /// Shrinks the failure `first` of `scene` on `d` while it stays the
    /// same kind of failure, then writes its reproducer into `dir`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn reproducer(
        &self,
        d: &Driver,
        identity: &Identity,
        path: &Path,
        scene: &Scene,
        first: &Verdict,
        image: Option<Image>,
        reference: &Image,
        stderr: PathBuf,
        dir: &Path,
    ) -> anyhow::Result<Option<(u32, u32)>> {
        let first_size = Size::of(scene);
        let mut best = (
            scene.clone(),
            first.clone(),
            image,
            reference.clone(),
            stderr,
        );
        let mut size = first_size;
        // The shrink's own time (a hang was shrunk at the full deadline
        // for each of up to 15 tries). A try gets what is left of it; one
        // cut short by it is no evidence either way.
        let until = Instant::now() + self.shrink_budget;
        let until = self.ends.map_or(until, |e| e.min(until));
        let try_deadline = || {
            let left = until.saturating_duration_since(Instant::now());
            (!left.is_zero()).then(|| left.min(self.deadline))
        };
        let conclusive = |v: &Verdict, deadline: Duration| {
            deadline == self.deadline || !matches!(v, Verdict::Hung { .. })
        };
        while let Some(smaller) = size.smaller(scene).filter(|_| !self.args.no_shrink) {
            let Some(deadline) = try_deadline() else {
                break;
            };
            let small = Scene::load(path, &smaller.overrides())?;
            let small_ref = self::reference(&small, self.args.device.accel)?;
            let tag = format!(
                "{}x{}x{}",
                smaller.width,
                smaller.height,
                smaller.samples.unwrap_or(0)
            );
            let (v, img, err) = self.scene(d, path, &small, &small_ref, &tag, smaller, deadline)?;
            if !v.same_kind(first) || !conclusive(&v, deadline) {
                break;
            }
            best = (small, v, img, small_ref, err);
            size = smaller;
        }
        // Then the objects, in the reproducer's own copy of the scene.
        let copy = repro::copy_scene(path, &best.0, dir)?;
        let objects = if self.args.no_shrink {
            None
        } else {
            let mut run = 0;
            shrink::objects::<anyhow::Error>(&copy, &mut |candidate| {
                run += 1;
                let Some(deadline) = try_deadline() else {
                    return Ok(false);
                };
                let Ok(small) = Scene::load(candidate, &size.overrides()) else {
                    return Ok(false);
                };
                let small_ref = self::reference(&small, self.args.device.accel)?;
                let tag = format!("objects-{run}");
                let (v, img, err) =
                    self.scene(d, candidate, &small, &small_ref, &tag, size, deadline)?;
                let same = v.same_kind(first) && conclusive(&v, deadline);
                if same {
                    best = (small, v, img, small_ref, err);
                }
                Ok(same)
            })?
        };
        let (_, verdict, image, reference, stderr) = best;
        let failure = repro::Failure {
            scene_path: path,
            icd: &d.icd,
            identity,
            verdict: &verdict,
            size,
            device_args: &self.device_args,
            gpu: image.as_ref(),
            reference: &reference,
            // A crash's or a hang's last words; a wrong image has none.
            stderr: matches!(verdict, Verdict::Crashed { .. } | Verdict::Hung { .. })
                .then_some(stderr.as_path()),
            first_size,
            objects,
        };
        let dump = |scene_copy: &Path, shader_dir: &Path| {
            self.shader_dump(d, scene_copy, size, shader_dir)
        };
        repro::write(&failure, dir, &copy, &dump)?;
        // A wrong image: its worst pixel explained on this driver.
        let worst = match (&verdict, &image) {
            (Verdict::Fail { .. }, Some(img)) => glint::explain::worst_pixels(img, &reference, 1)
                .first()
                .copied(),
            _ => None,
        };
        if let Some(pixel) = worst {
            self.explain(d, &copy, size, pixel, dir);
        }
        Ok(worst)
    }

    /// `glint explain` of `pixel` of the reproducer's scene on driver `d`,
    /// in a child, into `explain.txt` in `dir` (what went wrong, where it
    /// could not run).
    pub(super) fn explain(
        &self,
        d: &Driver,
        scene: &Path,
        size: Size,
        (x, y): (u32, u32),
        dir: &Path,
    ) {
        let out = dir.join("explain.txt");
        let ran = (|| -> anyhow::Result<Option<std::process::ExitStatus>> {
            let mut c = probe::on_driver(&d.icd)?;
            c.arg("explain")
                .arg(scene)
                .args(size.args())
                .args(["--pixel", &format!("{x},{y}")])
                .args(&self.device_args)
                .stdout(std::fs::File::create(&out)?);
            probe::bounded(c, &dir.join("explain.stderr.txt"), self.deadline)
        })();
        let said = std::fs::read_to_string(dir.join("explain.stderr.txt")).unwrap_or_default();
        let _ = std::fs::remove_file(dir.join("explain.stderr.txt"));
        let problem = match ran {
            Ok(Some(s)) if s.code() == Some(0) || s.code() == Some(1) => return,
            Ok(Some(_)) => said.trim().to_owned(),
            Ok(None) => format!(
                "`glint explain` on this driver was still running after {:.0} s: killed",
                self.deadline.as_secs_f64()
            ),
            Err(e) => format!("{e:#}"),
        };
        let _ = std::fs::write(
            &out,
            format!("glint explain --pixel {x},{y} could not run here: {problem}\n"),
        );
    }

    /// `glint shader dump` of the scene's variant on driver `d`, in a child.
    pub(super) fn shader_dump(
        &self,
        d: &Driver,
        scene: &Path,
        size: Size,
        dir: &Path,
    ) -> Result<(), String> {
        let mut c = probe::on_driver(&d.icd).map_err(|e| e.to_string())?;
        c.arg("shader")
            .arg("dump")
            .arg(scene)
            .args(size.args())
            .arg("-o")
            .arg(dir)
            .args(&self.device_args);
        // Bounded like every child: a driver that hangs in its compile
        // must not hang the run.
        let stderr = dir.with_extension("stderr.txt");
        let status = probe::bounded(c, &stderr, self.deadline).map_err(|e| e.to_string())?;
        let said = std::fs::read_to_string(&stderr).unwrap_or_default();
        let _ = std::fs::remove_file(&stderr);
        match status {
            Some(s) if s.success() => Ok(()),
            Some(_) => Err(said.trim().to_owned()),
            None => Err(format!(
                "`glint shader dump` on this driver was still running after {:.0} s: killed",
                self.deadline.as_secs_f64()
            )),
        }
    }
}
