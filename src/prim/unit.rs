//! What a primitive kind provides (`Kind`), what its CPU form answers
//! (`Shape`), and what the generated code and the other layers know of it:
//! `KindInfo`, its bounding `Hull`, a surface's `Frame` and a primitive's
//! `PrimId`.

use glam::DVec3;
use serde::de::DeserializeOwned;

use crate::base::aabb::Aabb;
use crate::base::interface::{self, GpuStruct};
use crate::base::ray::Ray;
use crate::base::real::{Real, Vec3};
use crate::input::error::SceneError;
use crate::input::field::At;
use crate::rng::Place;

/// What one kind provides.
pub trait Kind: Clone + PartialEq + std::fmt::Debug + Send + Sync + 'static {
    /// Its table in the scene file.
    type File: DeserializeOwned + serde::Serialize + std::fmt::Debug;
    /// Its struct in the shader's buffers.
    type Gpu: GpuStruct;
    /// Its form in the CPU reference's arithmetic.
    type Cpu<R: Real>: Shape<R>;
    /// The stem of its GLSL names: `sphere_intersect`, `sphere_shape` and
    /// `sphere_normal` in shaders/prim/sphere.glsl.
    const NAME: &'static str;
    /// Its GLSL include.
    const GLSL: &'static str;
    /// Whether it has bounds (and so goes into the BVH).
    const BOUNDED: bool;
    /// Whether its shading normal can differ from its geometric one: its
    /// include then gives `<name>_shading` too (see [`Shape::shading`]).
    const SHADING: bool = false;
    /// The members of its GPU struct that a ray test (`<name>_intersect`,
    /// `<name>_shape`) never reads: the scans fetch the others alone
    /// (`<name>_test_at`), and these are read for shading.
    const SHADING_ONLY: &'static [&'static str] = &[];
    /// Whether it has its own surface coordinates, for the 2D textures
    /// (`Shape::frame`): its include then gives `<name>_frame` too.
    const FRAME: bool = false;
    /// Whether its primitives can have uv coordinates, for the image
    /// textures (`Shape::uv`): its include then gives `<name>_uv` too.
    const UV: bool = false;
    /// Whether rays leaving it start lifted off its surface: a triangle's
    /// neighbours share its edges, and the rounding of a hit point near an
    /// edge can put it behind a neighbour's plane (`crate::cpu::intersect::lift`).
    const LIFT: bool = false;

    /// Checks the file's table (`at` names where it is) and resolves it.
    fn check(file: &Self::File, at: &At) -> Result<Self, SceneError>;
    /// The index of its material in the scene's list.
    fn material(&self) -> u32;
    /// Whether this primitive has uv coordinates (`Shape::uv`): every one
    /// of a kind with them, unless the kind says otherwise.
    fn has_uv(&self) -> bool {
        Self::UV
    }
    /// The same primitive with `origin` moved to 0 (camera-relative
    /// coordinates, `Scene::camera_relative`).
    fn relative_to(&self, origin: DVec3) -> Self;
    /// Its box; None where it is unbounded.
    fn bounds(&self) -> Option<Aabb>;
    /// Balls whose convex hull holds it, where that is tighter than its
    /// box from some side (the light buffers' and the eye's tiles' spans,
    /// `accel::tables`); none by default, and the box alone serves.
    fn hull(&self) -> Hull {
        Hull::default()
    }
    /// Its struct in the shader's buffers, with a member `uvec4 meta`: x
    /// the material, y `file_index`, its place among its kind in the scene
    /// file (ties in t go to the lower); z and w are the kind's.
    fn gpu(&self, file_index: u32) -> Self::Gpu;
    /// Its form in the CPU reference's arithmetic.
    fn cpu<R: Real>(&self) -> Self::Cpu<R>;
    /// One primitive of this kind, of material `material`, for the tests
    /// that every kind must pass (src/prim/contract_tests.rs).
    #[cfg(test)]
    fn example(material: u32) -> Self;
    /// One primitive of this kind about `p.center`, of about `p.size`, as a
    /// scene file's table: what `crate::generate` puts in a scene.
    fn sample(p: &mut Place) -> Self::File;
}

/// Up to three balls (centre, radius) whose convex hull holds a primitive:
/// a sphere's own, a cone's two end circles' balls, a triangle's corners.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Hull {
    balls: [(DVec3, f64); 3],
    len: usize,
}

impl Hull {
    /// The hull of `balls` (at most three).
    pub fn of(balls: &[(DVec3, f64)]) -> Self {
        let mut h = Hull::default();
        h.balls[..balls.len()].copy_from_slice(balls);
        h.len = balls.len();
        h
    }

    pub fn balls(&self) -> &[(DVec3, f64)] {
        &self.balls[..self.len]
    }
}

/// A primitive as the CPU reference traces it; mirrors its GLSL include.
pub trait Shape<R: Real>: Send + Sync {
    /// The distance along a unit-direction ray to the primitive, or None.
    /// `from_self`: the ray leaves this primitive's surface.
    fn intersect(&self, ray: &Ray<R>, from_self: bool) -> Option<R>;
    /// The outward unit (geometric) normal at `p` on the surface: which
    /// side of it a ray is on.
    fn normal(&self, p: Vec3<R>) -> Vec3<R>;
    /// The unit normal that shading uses at `p`, on the side of
    /// `geometric` (the outward normal at `p`); the same by default.
    fn shading(&self, _p: Vec3<R>, geometric: Vec3<R>) -> Vec3<R> {
        geometric
    }
    /// Its own surface coordinates, where it has them (`Kind::FRAME`): an
    /// origin on the surface and two unit axes u and v at right angles in
    /// it. A point's coordinates are its offset from the origin along each.
    fn frame(&self) -> Option<Frame<R>> {
        None
    }
    /// Its uv coordinates at `p` on the surface, where it has them
    /// (`Kind::UV`, `Kind::has_uv`), as an image texture reads them.
    fn uv(&self, _p: Vec3<R>) -> Option<[R; 2]> {
        None
    }
    fn material(&self) -> usize;
}

/// A surface's own coordinates: `origin` on it, `u` and `v` unit and at
/// right angles in it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame<R> {
    /// Where u = v = 0.
    pub origin: Vec3<R>,
    /// The first axis.
    pub u: Vec3<R>,
    /// The second axis, `normal × u`.
    pub v: Vec3<R>,
}

/// What the generated code knows of a kind.
#[derive(Debug, Clone, Copy)]
pub struct KindInfo {
    /// The scene file's key of its array, also its array's name in GLSL.
    pub key: &'static str,
    pub name: &'static str,
    pub struct_name: &'static str,
    pub struct_members: &'static str,
    pub struct_fields: &'static [(&'static str, interface::Member)],
    pub shading_only: &'static [&'static str],
    pub glsl: &'static str,
    pub bounded: bool,
    pub shading: bool,
    pub lift: bool,
    pub frame: bool,
    pub uv: bool,
    /// `Kind::sample`, as a scene file's table.
    pub(crate) sample: fn(&mut Place) -> toml::Table,
}

/// `K::sample` as a TOML table (a file struct always serializes to one).
fn sample_table<K: Kind>(p: &mut Place) -> toml::Table {
    toml::Table::try_from(K::sample(p)).expect("a kind's file table serializes")
}

impl KindInfo {
    pub(super) const fn of<K: Kind>(key: &'static str) -> Self {
        Self {
            key,
            name: K::NAME,
            struct_name: <K::Gpu as GpuStruct>::NAME,
            struct_members: <K::Gpu as GpuStruct>::MEMBERS,
            struct_fields: <K::Gpu as GpuStruct>::FIELDS,
            shading_only: K::SHADING_ONLY,
            glsl: K::GLSL,
            bounded: K::BOUNDED,
            shading: K::SHADING,
            lift: K::LIFT,
            frame: K::FRAME,
            uv: K::UV,
            sample: sample_table::<K>,
        }
    }

    /// Its include's name: `prim/sphere.glsl`.
    pub fn include(&self) -> String {
        format!("prim/{}.glsl", self.name)
    }

    /// The uppercase stem of its defines: `SPHERES` in `HAS_SPHERES`,
    /// `SPHERES_COUNT` and `SPHERES_BINDING`.
    pub fn upper(&self) -> String {
        self.key.to_uppercase()
    }
}

/// A primitive: its kind (its place in the table) and its index among its kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct PrimId {
    pub kind: u32,
    pub index: u32,
}

impl PrimId {
    /// No primitive: what an eye ray leaves.
    pub const NONE: PrimId = PrimId {
        kind: u32::MAX,
        index: u32::MAX,
    };

    /// As a recorded tree names it (`crate::base::record`); None for [`PrimId::NONE`].
    pub fn recorded(self) -> Option<crate::base::record::Prim> {
        (self != Self::NONE).then_some((self.kind, self.index))
    }
}
