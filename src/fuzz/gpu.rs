//! The GPU's properties of a generated scene: against the f64 reference,
//! and against its own other forms (scene managements, schedules, a
//! region, a second render, the counting variant).

use super::{compare_rendered, first_difference, Device, Failure, Property, Reference, Wanted};
use crate::accel::Accel;
use crate::cpu;
use crate::gpu::{GpuError, GpuOptions, RenderSettings, Renderer};
use crate::raster::region::Region;
use crate::raster::Image;
use crate::scene::Scene;
use crate::settings::Schedule;
use crate::stats::Counts;

/// The GPU renderer the properties run on.
pub struct GpuOracle {
    renderer: Renderer,
}

impl GpuOracle {
    /// A renderer on the device `opts` names.
    pub fn new(opts: &GpuOptions) -> Result<Self, GpuError> {
        Ok(Self {
            renderer: Renderer::new(opts)?,
        })
    }

    fn render(
        &mut self,
        scene: &Scene,
        settings: &RenderSettings,
        region: Option<Region>,
    ) -> Result<(Image, Option<Counts>), GpuError> {
        let r = self
            .renderer
            .prepare(scene, settings)?
            .render(region, &|_| {})?;
        Ok((r.image, r.counts))
    }

    /// Where `explain` of the middle pixel finds its recorded trees off the
    /// pixel the render wrote, what it says; None where they agree or the
    /// scene has nothing `explain` takes (no primitive, adaptive sampling).
    fn explained(&mut self, scene: &Scene) -> Option<String> {
        use crate::explain::{check_renders, explain_on_gpu, samples};
        let pixel = (scene.width / 2, scene.height / 2);
        let chosen = samples(scene, pixel, None).ok()?;
        let settings = self.renderer.settings();
        let mut explained = Vec::new();
        for s in chosen {
            match explain_on_gpu(&mut self.renderer, scene, &settings, s, Vec::new()) {
                Ok(e) => explained.push(e),
                Err(e) => return Some(format!("explain failed: {e}")),
            }
        }
        if let Err(e) = check_renders(&mut self.renderer, scene, &settings, &mut explained) {
            return Some(format!("explain failed: {e}"));
        }
        explained.iter().find_map(|e| e.render.clone())
    }
}

/// `img`'s pixels within `r`.
fn crop(img: &Image, r: Region) -> Image {
    let pixels = (r.y..r.y + r.height)
        .flat_map(|y| (r.x..r.x + r.width).map(move |x| (x, y)))
        .map(|(x, y)| img.get(x, y))
        .collect();
    Image::new(r.width, r.height, pixels)
}

/// The counters where the GPU's counts and the CPU f32's differ by more
/// than 0.1 % and 4 (a ray whose hit the two decide differently spawns a
/// few more; docs/guarantees.md), as text.
fn count_differences(gpu: &Counts, cpu: &Counts) -> Vec<String> {
    gpu.named()
        .into_iter()
        .zip(cpu.named())
        .filter(|((_, a), (_, b))| a.abs_diff(*b) as f64 > (1e-3 * (*a).max(*b) as f64).max(4.0))
        .map(|((name, a), (_, b))| format!("{name} {a} on the GPU against {b}"))
        .collect()
}

impl Device for GpuOracle {
    fn check(&mut self, scene: &Scene, reference: &Reference, wanted: Wanted) -> Vec<Failure> {
        let mut out = Vec::new();
        let mut fail = |property, detail: String| out.push(Failure { property, detail });
        let plain = RenderSettings::default();
        // One prepared scene for the plain image, its second render and its
        // region (`gpu-region`).
        let prepared = self.renderer.prepare(scene, &plain);
        let (mut prepared, (image, sampled)) = match prepared.and_then(|mut p| {
            let r = p.render(None, &|_| {})?;
            Ok((p, (r.image, r.sampled)))
        }) {
            Ok(done) => done,
            Err(e) => {
                fail(Property::GpuCompare, format!("the render failed: {e}"));
                return out;
            }
        };
        if wanted(Property::GpuCompare) {
            let replay = |s: &Scene| {
                let r = self.renderer.prepare(s, &plain)?.render(None, &|_| {})?;
                Ok::<_, GpuError>((r.image, r.sampled))
            };
            let own = (&image, sampled.as_ref());
            if let Some(d) = compare_rendered(scene, own, reference, replay) {
                fail(Property::GpuCompare, d);
            }
        }
        // Another render of a different settings' variant, bit for bit the
        // plain one; an unsupported combination is no failure.
        let same = |this: &mut Self, property, what: String, settings: RenderSettings| match this
            .render(scene, &settings, None)
        {
            Ok((img, _)) => {
                first_difference(&img, &image).map(|d| (property, format!("{what}: {d}")))
            }
            Err(GpuError::Unsupported(_)) => None,
            Err(e) => Some((property, format!("{what}: the render failed: {e}"))),
        };
        let mut found = Vec::new();
        let accels = [Accel::None, Accel::Bvh, Accel::Tables].map(|accel| {
            (
                format!("--accel {accel:?}"),
                RenderSettings { accel, ..plain },
            )
        });
        let schedules = [Schedule::Megakernel, Schedule::Wavefront].map(|schedule| {
            (
                format!("--schedule {schedule:?}"),
                RenderSettings { schedule, ..plain },
            )
        });
        let runs: [(Property, &[(String, RenderSettings)]); 2] = [
            (Property::GpuAccel, &accels),
            (Property::GpuSchedule, &schedules),
        ];
        for (property, settings) in runs.into_iter().filter(|(p, _)| wanted(*p)) {
            for (what, s) in settings {
                found.extend(same(self, property, what.clone(), *s));
            }
        }
        if wanted(Property::GpuRegion) {
            match prepared.render(None, &|_| {}) {
                Ok(again) => found.extend(
                    first_difference(&again.image, &image)
                        .map(|d| (Property::GpuRegion, format!("a second render: {d}"))),
                ),
                Err(e) => found.push((Property::GpuRegion, format!("a second render failed: {e}"))),
            }
            let (w, h) = (scene.width, scene.height);
            let r = Region {
                x: w / 4,
                y: h / 3,
                width: (w / 2).max(1),
                height: (h / 2).max(1),
            };
            match prepared.render(Some(r), &|_| {}) {
                Ok(part) => {
                    if let Some(d) = first_difference(&part.image, &crop(&image, r)) {
                        found.push((Property::GpuRegion, format!("the region {r:?}: {d}")));
                    }
                }
                Err(e) => found.push((Property::GpuRegion, format!("the region failed: {e}"))),
            }
        }
        drop(prepared);
        if wanted(Property::GpuCounts) {
            let s = RenderSettings {
                count: true,
                ..plain
            };
            match self.render(scene, &s, None) {
                Ok((img, Some(counts))) => {
                    if let Some(d) = first_difference(&img, &image) {
                        found.push((
                            Property::GpuCounts,
                            format!("counting changed the image: {d}"),
                        ));
                    }
                    let cpu = cpu::render_counted::<f32>(scene, Accel::Auto, &|_| {}).1;
                    let off = count_differences(&counts, &cpu);
                    if !off.is_empty() {
                        found.push((Property::GpuCounts, off.join(", ")));
                    }
                }
                Ok((_, None)) => found.push((Property::GpuCounts, "no counts came back".into())),
                Err(e) => found.push((Property::GpuCounts, format!("the render failed: {e}"))),
            }
        }
        if wanted(Property::GpuExplain) {
            found.extend(self.explained(scene).map(|d| (Property::GpuExplain, d)));
        }
        for (property, detail) in found {
            fail(property, detail);
        }
        out
    }
}
