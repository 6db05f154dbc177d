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
mod unit;

pub use unit::{Frame, Hull, Kind, KindInfo, PrimId, Shape};

use glam::DVec3;

use crate::base::aabb::Aabb;
use crate::base::count::Counter;
use crate::base::interface::{self, Array};
use crate::base::ray::Ray;
use crate::base::real::Real;
use crate::base::tally::Tally;
use crate::base::Precision;
use crate::input::error::SceneError;
use crate::input::field::At;

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
