//! The kinds of primitive, as units. Each kind is one Rust module here (its
//! scene-file table, its checks, its GPU struct, its bounds, and the CPU
//! reference's intersect and normal) and one GLSL include under
//! shaders/prim/ (the shader's intersect and normal), listed in the table
//! below. Everything that treats every kind alike is generated from that
//! table: the scene file's arrays, the scene's lists, the uploads and their
//! bindings, the shader's scans and dispatch, and the CPU reference's.
//!
//! Adding a kind: its module, its include, and one line of the table.

pub mod cylinder;
pub mod mesh;
mod mtl;
pub mod plane;
pub mod sphere;
pub mod triangle;

use glam::DVec3;
use serde::de::DeserializeOwned;

use crate::base::aabb::Aabb;
use crate::base::count::Counter;
use crate::base::interface::{self, Array, GpuStruct};
use crate::base::ray::Ray;
use crate::base::real::{Real, Vec3};
use crate::base::tally::Tally;
use crate::base::Precision;
use crate::input::error::SceneError;
use crate::input::field::At;
use crate::rng::Place;

/// The table of kinds: the scene file's key of each kind's array, and the
/// kind. Kinds with bounds come before the unbounded ones (tested): a tie in
/// t goes to the earlier kind, then to the earlier primitive in the file,
/// and the BVH's bounded kinds are searched before the unbounded kinds' scans.
macro_rules! with_kinds {
    ($then:path) => {
        $then! {
            spheres: $crate::prim::sphere::Sphere,
            triangles: $crate::prim::triangle::Triangle,
            cylinders: $crate::prim::cylinder::Cylinder,
            planes: $crate::prim::plane::Plane,
        }
    };
}
pub(crate) use with_kinds;

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
    const fn of<K: Kind>(key: &'static str) -> Self {
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

/// A kind's GPU struct, as the shader's array holds it.
fn gpu_array<K: Kind + Sync>(
    items: &[K],
    order: Option<Vec<u32>>,
    precision: Precision,
    origin: Option<DVec3>,
) -> Array<'_> {
    let gpu = move |i: u32| match origin {
        Some(origin) => items[i as usize].relative_to(origin).gpu(i),
        None => items[i as usize].gpu(i),
    };
    // Written into the buffer when it is made, in the BVH's leaf order
    // where the kind is in the BVH, else the file's.
    let len = order.as_ref().map_or(items.len(), Vec::len);
    let each = move |f: &mut dyn FnMut(K::Gpu)| match &order {
        Some(order) => order.iter().for_each(|&i| f(gpu(i))),
        None => (0..items.len() as u32).for_each(|i| f(gpu(i))),
    };
    interface::written(len, each, precision)
}

/// Generates from the table: `KINDS`, the scene's `Prims` and the CPU
/// reference's `CpuPrims`.
macro_rules! generate {
    ($($key:ident : $kind:ty),* $(,)?) => {
        /// Every kind, in the table's order.
        pub const KINDS: &[KindInfo] = &[$(KindInfo::of::<$kind>(stringify!($key)),)*];

        /// The scene's primitives, a list for each kind.
        #[derive(Debug, Clone, PartialEq, Default)]
        pub struct Prims {
            $(
                #[doc = concat!("The ", stringify!($key), ", in the file's order.")]
                pub $key: Vec<$kind>,
            )*
        }

        /// The scene file's arrays, a list of tables for each kind.
        #[derive(Debug, Default)]
        pub struct PrimFiles {
            $(pub $key: Vec<<$kind as Kind>::File>,)*
        }

        impl Prims {
            /// Checks every table of `files`; `at(key, i)` names the i-th
            /// table of the array `key`.
            pub(crate) fn check<'a>(
                files: &PrimFiles,
                at: impl Fn(&'static str, usize) -> At<'a>,
            ) -> Result<Self, SceneError> {
                Ok(Self {
                    $($key: files
                        .$key
                        .iter()
                        .enumerate()
                        .map(|(i, f)| <$kind>::check(f, &at(stringify!($key), i)))
                        .collect::<Result<_, _>>()?,)*
                })
            }

            /// Primitives of each kind, in the table's order.
            pub fn counts(&self) -> Vec<usize> {
                vec![$(self.$key.len(),)*]
            }

            /// Primitives of every kind.
            pub fn len(&self) -> usize {
                0 $(+ self.$key.len())*
            }

            /// Primitives of the kinds with bounds: what a BVH would hold.
            pub fn bounded_count(&self) -> usize {
                0 $(+ if <$kind as Kind>::BOUNDED { self.$key.len() } else { 0 })*
            }

            /// Whether there are none.
            pub fn is_empty(&self) -> bool {
                self.len() == 0
            }

            /// Every primitive translated by `-origin`, in f64.
            pub fn relative_to(&self, origin: DVec3) -> Self {
                Self {
                    $($key: self.$key.iter().map(|p| p.relative_to(origin)).collect(),)*
                }
            }

            /// Each primitive moved by `by(its box)` (None: unbounded).
            pub(crate) fn each_moved(&self, mut by: impl FnMut(Option<Aabb>) -> DVec3) -> Self {
                Self {
                    $($key: self.$key.iter().map(|p| p.relative_to(-by(p.bounds()))).collect(),)*
                }
            }

            /// The materials the primitives use, each once or more.
            pub fn materials(&self) -> impl Iterator<Item = u32> + '_ {
                std::iter::empty()
                    $(.chain(self.$key.iter().map(|p| p.material())))*
            }

            /// The first primitive that lacks what its material needs:
            /// `needs(material)` says whether it needs its own coordinates
            /// (`Kind::FRAME`) and uv coordinates (`Kind::has_uv`). Its
            /// array's key, its index and its material.
            pub(crate) fn first_lacking(
                &self,
                needs: impl Fn(u32) -> [bool; 2],
            ) -> Option<(&'static str, usize, u32)> {
                $(
                    for (i, p) in self.$key.iter().enumerate() {
                        let [frame, uv] = needs(p.material());
                        if frame && !<$kind as Kind>::FRAME || uv && !p.has_uv() {
                            return Some((stringify!($key), i, p.material()));
                        }
                    }
                )*
                None
            }

            /// The bounded primitives' boxes (and, in `relative_bounds`,
            /// their ids).
            pub(crate) fn bounds(&self) -> Vec<Aabb> {
                self.relative_bounds(DVec3::ZERO).0
            }

            /// The farthest any bounded primitive's box reaches from
            /// `origin` along an axis (0 without one), without a copy.
            pub(crate) fn reach_from(&self, origin: DVec3) -> f64 {
                let mut reach = 0.0f64;
                $(
                    for p in &self.$key {
                        if let Some(b) = p.bounds() {
                            let far = (b.lo - origin).abs().max((b.hi - origin).abs());
                            reach = reach.max(far.max_element());
                        }
                    }
                )*
                reach
            }

            /// Each primitive's hull (`Kind::hull`) translated by `-origin`,
            /// by kind and index in the scene.
            pub(crate) fn relative_hulls(&self, origin: DVec3) -> Vec<Vec<Hull>> {
                vec![$(self.$key.iter().map(|p| p.relative_to(origin).hull()).collect(),)*]
            }

            /// The boxes of the primitives translated by `-origin` (those
            /// of `relative_to(origin)`, without holding that copy).
            pub(crate) fn relative_bounds(&self, origin: DVec3) -> (Vec<Aabb>, Vec<PrimId>) {
                // Reserved for every primitive (the bounded ones are most):
                // grown by doubling, a million boxes would take up to twice
                // their 48 MB, and half as much again while moved.
                let all = 0 $(+ self.$key.len())*;
                let (mut boxes, mut ids) = (Vec::with_capacity(all), Vec::with_capacity(all));
                let mut _kind = 0u32;
                $(
                    for (i, p) in self.$key.iter().enumerate() {
                        if let Some(b) = p.relative_to(origin).bounds() {
                            boxes.push(b);
                            ids.push(PrimId { kind: _kind, index: i as u32 });
                        }
                    }
                    _kind += 1;
                )*
                (boxes, ids)
            }

            /// Each kind's array as the shader reads it, translated by
            /// `-origin` item by item (None: as written); `orders[kind]`: the
            /// kind in the BVH's leaf order, where it is in one.
            pub(crate) fn gpu_arrays(
                &self,
                orders: Vec<Option<Vec<u32>>>,
                precision: Precision,
                origin: Option<DVec3>,
            ) -> Vec<Array<'_>> {
                let mut orders = orders.into_iter();
                vec![$(gpu_array(
                    &self.$key,
                    orders.next().flatten(),
                    precision,
                    origin,
                ),)*]
            }

            /// The CPU reference's forms of the primitives translated by
            /// `-origin`, in `R` (those of `relative_to(origin)`, without
            /// holding that copy: a million triangles are 152 MB).
            pub(crate) fn relative_cpu<R: Real>(&self, origin: DVec3) -> CpuPrims<R> {
                CpuPrims {
                    $($key: self.$key.iter().map(|p| p.relative_to(origin).cpu()).collect(),)*
                }
            }
        }

        /// The primitives in the CPU reference's arithmetic; its scans
        /// mirror those generated for the shader (`crate::gpu::kinds`).
        pub struct CpuPrims<R: Real> {
            $(pub $key: Vec<<$kind as Kind>::Cpu<R>>,)*
        }

        impl<R: Real> CpuPrims<R> {
            /// Tests each primitive the scan covers, in the table's order and
            /// then the file's: every one, or (`bvh`) only the unbounded
            /// kinds; calls `f(id, t)` for each hit, which returns false to
            /// end the scan. `from`: the primitive the ray leaves; `tally`
            /// counts the tests.
            pub fn scan<T: Tally>(
                &self,
                bvh: bool,
                ray: &Ray<R>,
                from: PrimId,
                tally: &mut T,
                mut f: impl FnMut(PrimId, R) -> bool,
            ) {
                let mut _kind = 0u32;
                $(
                    if !(bvh && <$kind as Kind>::BOUNDED) {
                        for (i, p) in self.$key.iter().enumerate() {
                            let id = PrimId { kind: _kind, index: i as u32 };
                            tally.count(Counter::Test(_kind));
                            if let Some(t) = p.intersect(ray, from == id) {
                                if !f(id, t) {
                                    return;
                                }
                            }
                        }
                    }
                    _kind += 1;
                )*
            }

            /// The distance along `ray` to the primitive `id`, or None.
            pub fn intersect(&self, id: PrimId, ray: &Ray<R>, from: PrimId) -> Option<R> {
                let mut _kind = 0u32;
                $(
                    if id.kind == _kind {
                        return self.$key[id.index as usize].intersect(ray, from == id);
                    }
                    _kind += 1;
                )*
                unreachable!("no kind {}", id.kind)
            }

            /// The primitive `id`.
            pub fn get(&self, id: PrimId) -> &dyn Shape<R> {
                let mut _kind = 0u32;
                $(
                    if id.kind == _kind {
                        return &self.$key[id.index as usize];
                    }
                    _kind += 1;
                )*
                unreachable!("no kind {}", id.kind)
            }
        }
    };
}

with_kinds!(generate);

#[cfg(test)]
mod contract_tests;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounded_kinds_come_first() {
        let first_unbounded = KINDS.iter().position(|k| !k.bounded).unwrap_or(KINDS.len());
        assert!(
            KINDS[first_unbounded..].iter().all(|k| !k.bounded),
            "{KINDS:?}"
        );
    }

    #[test]
    fn the_kinds_fit_the_id_and_count_words() {
        // A GPU primitive id keeps the kind in 4 bits, the uniform block
        // the counts of 8 kinds.
        assert!(KINDS.len() <= 8);
    }
}
