//! One sample's ray tree, recorded event by event (`glint explain`), and
//! single rays against single primitives: what an explanation asks of the
//! reference beside its image.

use super::{ray, trace, World};
use crate::accel::Accel;
use crate::base::ray::Ray;
use crate::base::real::{Real, Vec3};
use crate::base::record::{Event, Prim};
use crate::prim::PrimId;
use crate::scene::Scene;
use crate::stats::{Counter, RayType, Tally};

/// A scene laid out as a render in precision `R` lays it out, to trace
/// one sample at a time.
pub struct Probe<R: Real>(World<R>);

/// A tally that keeps the events of the tree and counts nothing.
#[derive(Default)]
struct Recorder(Vec<Event>);

impl Tally for Recorder {
    fn count(&mut self, _: Counter) {}
    fn ray_type(&mut self, _: RayType) {}
    fn merge(mut self, other: Self) -> Self {
        self.0.extend(other.0);
        self
    }
    fn record(&mut self, event: impl FnOnce() -> Event) {
        self.0.push(event());
    }
}

impl<R: Real> Probe<R> {
    /// `scene` as a render lays it out with `accel`.
    pub fn new(scene: &Scene, accel: Accel) -> Self {
        Self(World::new(scene, accel))
    }

    /// As [`Probe::new`], with every hit point and leaving direction moved
    /// as a conditioning trial moves them (`crate::condition`).
    pub(crate) fn moved(scene: &Scene, accel: Accel, moves: (u64, f64)) -> Self {
        let mut world = World::new(scene, accel);
        world.hit_move = Some(moves);
        Self(world)
    }

    /// The events of the tree of sample (i, j) of pixel (x, y), in the order
    /// the shader records them (shaders/record.glsl).
    pub fn record(&self, [x, y, i, j]: [u32; 4]) -> Vec<Event> {
        let mut recorder = Recorder::default();
        let eye = ray::primary_ray(&self.0, x, y, i, j);
        trace::trace(&self.0, eye, &mut recorder);
        recorder.0
    }

    /// The distance along the ray from `origin` in the unit direction `dir`
    /// (camera-relative, as the events give them) to the primitive `prim`,
    /// leaving `from`; None where the ray misses it.
    pub fn distance(
        &self,
        prim: Prim,
        origin: glam::DVec3,
        dir: glam::DVec3,
        from: Option<Prim>,
    ) -> Option<f64> {
        let id = PrimId {
            kind: prim.0,
            index: prim.1,
        };
        let from = from.map_or(PrimId::NONE, |(kind, index)| PrimId { kind, index });
        let ray = Ray {
            origin: Vec3::of(origin),
            dir: Vec3::of(dir),
        };
        self.0.prims.intersect(id, &ray, from).map(Real::to_f64)
    }
}
