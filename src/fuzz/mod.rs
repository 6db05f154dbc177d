//! The oracle over the whole scene space (docs/guarantees.md, Generated
//! scenes): each generated scene ([`crate::generate`]) is held to
//! properties that could fail, differential (the GPU's f32 and the CPU's
//! f32 against the f64 reference, the scene managements against each
//! other) and metamorphic (a dark light, the order of the file, depth
//! where nothing reflects, a moved scene). A failure shrinks to a
//! smallest scene that still fails the same way ([`shrink`]).

#[cfg(feature = "gpu")]
mod gpu;
mod shrink;

use std::path::Path;

use crate::accel::Accel;
use crate::condition::{judge, judge_rendered, Judgement};
use crate::cpu;
use crate::generate::{LightSpec, Spec};
use crate::output::interrupt::TempFolder;
use crate::raster::diff::Tolerance;
use crate::raster::Image;
use crate::sampling::Sampled;
use crate::scene::Scene;

#[cfg(feature = "gpu")]
pub use gpu::GpuOracle;
pub use shrink::shrink;

/// A property of a generated scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
pub enum Property {
    /// The scene the generator wrote is one glint reads.
    Loads,
    /// The CPU's f32 image passes `compare` against the f64 reference.
    CpuF32,
    /// The CPU reference renders the same bits with every scene management.
    CpuAccel,
    /// A light of zero intensity added changes no bit.
    DarkLight,
    /// The objects and lights in the file's reverse order change no pixel
    /// past the conditioning (ties of t go to the earlier primitive).
    Reorder,
    /// Depth 1 and depth 5 agree bit for bit where nothing reflects or
    /// transmits.
    Depth,
    /// The whole scene moved, camera and all, moves no pixel past the
    /// conditioning.
    Translate,
    /// The GPU's f32 image passes `compare` against the f64 reference.
    GpuCompare,
    /// The GPU renders the same bits with every scene management.
    GpuAccel,
    /// The GPU renders the same bits on the megakernel and the wavefront.
    GpuSchedule,
    /// A region of the GPU's render is the crop of the whole, and a
    /// prepared scene renders the same bits twice.
    GpuRegion,
    /// The GPU's ray counts are the CPU f32's.
    GpuCounts,
    /// `explain` of the middle pixel holds its recorded trees to the pixel
    /// the render wrote.
    GpuExplain,
}

impl Property {
    /// Every property, in the order they are checked.
    pub const ALL: &'static [Property] = &[
        Property::Loads,
        Property::CpuF32,
        Property::CpuAccel,
        Property::DarkLight,
        Property::Reorder,
        Property::Depth,
        Property::Translate,
        Property::GpuCompare,
        Property::GpuAccel,
        Property::GpuSchedule,
        Property::GpuRegion,
        Property::GpuCounts,
        Property::GpuExplain,
    ];

    /// Whether it needs the GPU renderer.
    pub fn on_gpu(self) -> bool {
        self >= Property::GpuCompare
    }

    /// Whether it compiles more shader variants than the scene's own
    /// (seconds a case on lavapipe): the CI set checks these on its
    /// covering array's rows alone.
    pub fn costly(self) -> bool {
        matches!(
            self,
            Property::GpuAccel | Property::GpuSchedule | Property::GpuCounts | Property::GpuExplain
        )
    }

    /// Its name, as the reports print it.
    pub fn name(self) -> &'static str {
        match self {
            Property::Loads => "loads",
            Property::CpuF32 => "cpu-f32",
            Property::CpuAccel => "cpu-accel",
            Property::DarkLight => "dark-light",
            Property::Reorder => "reorder",
            Property::Depth => "depth",
            Property::Translate => "translate",
            Property::GpuCompare => "gpu-compare",
            Property::GpuAccel => "gpu-accel",
            Property::GpuSchedule => "gpu-schedule",
            Property::GpuRegion => "gpu-region",
            Property::GpuCounts => "gpu-counts",
            Property::GpuExplain => "gpu-explain",
        }
    }
}

/// A property a scene broke, and how.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Failure {
    /// The property.
    pub property: Property,
    /// What was seen.
    pub detail: String,
}

/// Which properties to check.
pub type Wanted<'a> = &'a dyn Fn(Property) -> bool;

/// The first pixel where two images' bits differ, as text; None where they
/// are the same.
pub fn first_difference(a: &Image, b: &Image) -> Option<String> {
    if (a.width, a.height) != (b.width, b.height) {
        return Some(format!(
            "{}x{} against {}x{}",
            a.width, a.height, b.width, b.height
        ));
    }
    let at = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .position(|(p, q)| p.map(f32::to_bits) != q.map(f32::to_bits))?;
    let (x, y) = (at as u32 % a.width, at as u32 / a.width);
    Some(format!(
        "pixel ({x}, {y}) is {:?} against {:?}",
        a.pixels[at], b.pixels[at]
    ))
}

/// Holds `img` to the f64 reference as `glint compare` does; the verdict
/// as text where it fails.
pub fn compare_failure(scene: &Scene, img: &Image, reference: &Image) -> Option<String> {
    let j = judge(
        scene,
        img,
        reference,
        &Tolerance::default(),
        Accel::Auto,
        &|_| {},
    );
    verdict(&j)
}

/// The f64 reference of a scene, and what its sampling decided.
pub struct Reference {
    /// Its image.
    pub image: Image,
    /// Its adaptive or contrast sampling's decisions.
    pub sampled: Option<Sampled>,
}

/// [`compare_failure`] for a renderer whose own render (and decisions)
/// is `plain`, on the reference's samples where the scene's sampling
/// decides: `replay` renders the scene it is given as `plain` was
/// (`condition::judge_rendered`).
pub fn compare_rendered<E: std::fmt::Display>(
    scene: &Scene,
    plain: (&Image, Option<&Sampled>),
    reference: &Reference,
    replay: impl FnOnce(&Scene) -> Result<(Image, Option<Sampled>), E>,
) -> Option<String> {
    let j = judge_rendered(
        scene,
        plain,
        (&reference.image, reference.sampled.as_ref()),
        replay,
        &Tolerance::default(),
        Accel::Auto,
        &|_| {},
    );
    match j {
        Ok(j) => verdict(&j),
        Err(e) => Some(format!("the render of the reference's samples failed: {e}")),
    }
}

/// A judgement's verdict as text, where it fails.
fn verdict(j: &Judgement) -> Option<String> {
    (!j.pass()).then(|| {
        format!(
            "max_abs {:.3e}, rmse {:.3e}, {:.2} % over 1/255, {} non-finite: {}",
            j.error.max_abs,
            j.error.rmse,
            100.0 * j.error.frac_over_1_255,
            j.error.nonfinite,
            j.violations.join("; ")
        )
    })
}

/// A generated scene, loaded: its files go into a folder of their own,
/// which an interrupted run removes.
pub fn load(spec: &Spec) -> Result<(Scene, TempFolder), String> {
    let dir = TempFolder::new("fuzz").map_err(|e| format!("cannot make a folder: {e}"))?;
    let scene = spec.scene().load(dir.path()).map_err(|e| e.to_string())?;
    Ok((scene, dir))
}

/// A renderer held to the reference: the GPU's (`GpuOracle`, in the default build), or a
/// test's own.
pub trait Device {
    /// The failures of `scene` among the properties `wanted`, its f64
    /// render being `reference`.
    fn check(&mut self, scene: &Scene, reference: &Reference, wanted: Wanted) -> Vec<Failure>;
}

/// The properties of `spec` among those `wanted`: the CPU's, then the
/// device's where there is one.
pub fn check(spec: &Spec, device: Option<&mut dyn Device>, wanted: Wanted) -> Vec<Failure> {
    let mut out = Vec::new();
    let fail =
        |out: &mut Vec<Failure>, property, detail: String| out.push(Failure { property, detail });
    let (scene, _dir) = match load(spec) {
        Ok(s) => s,
        Err(e) => {
            fail(&mut out, Property::Loads, e);
            return out;
        }
    };
    let f32_of = |s: &Scene| cpu::render_sampled::<f32>(s, Accel::Auto, &|_| {});
    let f64_of = |s: &Scene| cpu::render_sampled::<f64>(s, Accel::Auto, &|_| {});
    let (image, sampled) = f64_of(&scene);
    let reference = Reference { image, sampled };
    let ok = |r| Ok::<_, std::convert::Infallible>(r);
    if wanted(Property::CpuF32) {
        let (img, sampled) = f32_of(&scene);
        let plain = (&img, sampled.as_ref());
        if let Some(d) = compare_rendered(&scene, plain, &reference, |s| ok(f32_of(s))) {
            fail(&mut out, Property::CpuF32, d);
        }
    }
    if wanted(Property::CpuAccel) {
        for accel in [Accel::None, Accel::Bvh, Accel::Tables] {
            let img = cpu::render_rows::<f64>(&scene, accel, &|_| {});
            if let Some(d) = first_difference(&img, &reference.image) {
                fail(
                    &mut out,
                    Property::CpuAccel,
                    format!("--accel {accel:?}: {d}"),
                );
                break;
            }
        }
    }
    let varied = |out: &mut Vec<Failure>, property, changed: Spec, exact: bool| {
        let Ok((other, _dir)) = load(&changed) else {
            fail(out, property, "the changed scene does not load".into());
            return;
        };
        let (img, sampled) = f64_of(&other);
        let verdict = if exact {
            first_difference(&img, &reference.image)
        } else {
            // The changed scene replays the reference's decisions: the
            // replayed scene's own with the other's objects.
            let replay = |s: &Scene| {
                let replaying = Scene {
                    replay: s.replay.clone(),
                    ..other.clone()
                };
                ok(f64_of(&replaying))
            };
            compare_rendered(&scene, (&img, sampled.as_ref()), &reference, replay)
        };
        if let Some(d) = verdict {
            fail(out, property, d);
        }
    };
    if wanted(Property::DarkLight) {
        let mut s = spec.clone();
        s.lights.push(LightSpec {
            kind: spec.lights.first().map_or(0, |l| l.kind),
            key: crate::generate::mix(spec.seed, 77),
            dark: true,
        });
        varied(&mut out, Property::DarkLight, s, true);
    }
    if wanted(Property::Reorder) && spec.objects.len() + spec.lights.len() > 1 {
        let mut s = spec.clone();
        s.objects.reverse();
        s.lights.reverse();
        varied(&mut out, Property::Reorder, s, false);
    }
    if wanted(Property::Depth) && !spec.reflect && !spec.transmit {
        for depth in [1, 5] {
            if depth != spec.depth {
                let s = Spec {
                    depth,
                    ..spec.clone()
                };
                varied(&mut out, Property::Depth, s, true);
            }
        }
    }
    if wanted(Property::Translate) {
        let by = 37.0 * spec.scale;
        let s = Spec {
            offset: spec.offset.map(|x| x + by),
            ..spec.clone()
        };
        varied(&mut out, Property::Translate, s, false);
    }
    if let Some(d) = device {
        if Property::ALL.iter().any(|p| p.on_gpu() && wanted(*p)) {
            out.extend(d.check(&scene, &reference, wanted));
        }
    }
    out
}

/// What one check of a scene found.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Case {
    /// The scene.
    pub spec: Spec,
    /// What it broke.
    pub failures: Vec<Failure>,
}

/// Writes a failing case's scene (shrunk, where it was) and its files into
/// `dir` as `name`, with the failures as comments at its head; the path.
pub fn write_case(
    case: &Case,
    dir: &Path,
    name: &str,
) -> Result<std::path::PathBuf, crate::output::OutputError> {
    let mut g = case.spec.scene();
    let mut head = String::new();
    for f in &case.failures {
        head.push_str(&format!(
            "# fails {}: {}\n",
            f.property.name(),
            crate::printable::text(&f.detail)
        ));
    }
    g.text = head + &g.text;
    g.write(dir, name)
}
