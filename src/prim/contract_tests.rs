//! The contract every kind keeps, checked for each kind of the table and
//! failing with its name (docs/shaders.md, Adding a kind). What the
//! generated code assumes of a kind, and nothing else says:
//!
//! - its GPU struct has a member `uvec4 meta`, x the material and y the
//!   primitive's place among its kind in the scene file (the scans read
//!   `p.meta.x` and `p.meta.y`); the members it names as shading-only
//!   (`Kind::SHADING_ONLY`, which a ray test does not fetch) are members
//!   of it, and meta is none of them;
//! - its include defines `<name>_intersect`, `<name>_shape` (a hit keeps
//!   one `vec4r` of shape), `<name>_normal` and, where `Kind::SHADING`,
//!   `<name>_shading`, where `Kind::FRAME` `<name>_frame`, where `Kind::UV`
//!   `<name>_uv`, with the signatures the scans call;
//! - its CPU form has uv coordinates exactly where `Kind::has_uv` says, and
//!   they move with it;
//! - where `Kind::FRAME`, its frame's axes are unit and at right angles to
//!   each other and to its normal;
//! - a bounded kind has a box, which holds it and moves with it; an
//!   unbounded kind has none;
//! - its hull (`Kind::hull`), where it has one, holds every hit of rays
//!   from all around it;
//! - its CPU form has the same material.

use glam::DVec3;

use super::*;
use crate::base::interface::GpuStruct;
use crate::base::real::Vec3;

/// What `K` breaks of the contract, each naming the kind.
fn problems<K: Kind>() -> Vec<String> {
    let name = K::NAME;
    let mut out = Vec::new();
    let material = 5;
    let file_index = 7;
    let p = K::example(material);

    let fields = <K::Gpu as GpuStruct>::FIELDS;
    let at = fields
        .iter()
        .position(|f| *f == ("meta", interface::Member::Uvec4));
    if let Some(at) = at {
        // Its byte offset in the f32 layout: 16 a word.
        let offset = 16 * interface::span(&fields[..at], Precision::F32);
        let bytes = bytemuck::bytes_of(&p.gpu(file_index).f32()).to_vec();
        let meta: [u32; 4] = bytemuck::pod_read_unaligned(&bytes[offset..offset + 16]);
        if meta[0] != material || meta[1] != file_index {
            out.push(format!(
                "{name}: meta is {meta:?}: x must be the material ({material}), y the file index ({file_index})"
            ));
        }
    } else {
        out.push(format!(
            "{name}: its GPU struct has no `uvec4 meta`: {fields:?}"
        ));
    }
    for skipped in K::SHADING_ONLY {
        if *skipped == "meta" || !fields.iter().any(|(f, _)| f == skipped) {
            out.push(format!(
                "{name}: `{skipped}` is shading-only but no member a test may skip"
            ));
        }
    }

    let s = <K::Gpu as GpuStruct>::NAME;
    let mut wanted = vec![
        format!("real {name}_intersect(Ray r, {s} "),
        format!("vec4r {name}_shape({s} "),
        format!("vec3r {name}_normal(uint i, vec4r shape, vec3r p)"),
    ];
    if K::SHADING {
        wanted.push(format!(
            "vec3r {name}_shading(uint i, vec3r p, vec3r geometric)"
        ));
    }
    if K::FRAME {
        wanted.push(format!(
            "void {name}_frame(uint i, out vec3r origin, out vec3r u, out vec3r v)"
        ));
    }
    if K::UV {
        wanted.push(format!("vec2r {name}_uv(uint i, vec4r shape, vec3r p)"));
    }
    for w in wanted {
        if !K::GLSL.lines().any(|l| l.starts_with(&w)) {
            out.push(format!(
                "{name}: its include (shaders/prim/{name}.glsl) does not define `{w}…`"
            ));
        }
    }

    let cpu = p.cpu::<f64>();
    let by = DVec3::new(3.0, -2.0, 0.5);
    match (K::FRAME, cpu.frame()) {
        (false, None) => {}
        (true, Some(f)) => {
            // u and v unit, at right angles to each other and to the normal.
            let n = cpu.normal(f.origin);
            let off = [
                f.u.dot(f.u) - 1.0,
                f.v.dot(f.v) - 1.0,
                f.u.dot(f.v),
                f.u.dot(n),
                f.v.dot(n),
            ];
            if off.iter().any(|e| e.abs() > 1e-12) {
                out.push(format!(
                    "{name}: its frame {f:?} is not unit and at right angles to its normal {n:?}"
                ));
            }
        }
        (frame, f) => out.push(format!(
            "{name}: FRAME is {frame} but its CPU form's frame is {f:?}"
        )),
    }
    // uv at a point of the surface: where a ray through the box's centre
    // meets it, or the frame's origin for an unbounded kind.
    let on_surface = match (p.bounds(), cpu.frame()) {
        (Some(b), _) => {
            let origin = b.center() - DVec3::new(0.0, 0.0, 10.0 + (b.hi.z - b.lo.z));
            let ray = Ray {
                origin: Vec3::of(origin),
                dir: Vec3::of(DVec3::Z),
            };
            cpu.intersect(&ray, false).map(|t| origin + DVec3::Z * t)
        }
        (None, Some(f)) => {
            Some(DVec3::new(f.origin.x, f.origin.y, f.origin.z) + DVec3::new(0.3, 0.2, 0.1))
        }
        (None, None) => None,
    };
    if let Some(q) = on_surface {
        let uv = cpu.uv(Vec3::of(q));
        if uv.is_some() != p.has_uv() || p.has_uv() && !K::UV {
            out.push(format!(
                "{name}: has_uv is {} (UV {}) but its CPU form's uv is {uv:?}",
                p.has_uv(),
                K::UV
            ));
        }
        let moved = p.relative_to(by).cpu::<f64>().uv(Vec3::of(q - by));
        if let (Some(a), Some(b)) = (uv, moved) {
            if (a[0] - b[0]).abs() + (a[1] - b[1]).abs() > 1e-9 {
                out.push(format!("{name}: its uv {a:?} does not move with it: {b:?}"));
            }
        }
    }
    if cpu.material() != material as usize || p.material() != material {
        out.push(format!(
            "{name}: the CPU form's material is {}, not {material}",
            cpu.material()
        ));
    }

    match (K::BOUNDED, p.bounds(), p.relative_to(by).bounds()) {
        (true, Some(b), Some(moved)) => {
            let shifted = (moved.lo - (b.lo - by)).abs().max_element()
                + (moved.hi - (b.hi - by)).abs().max_element();
            if shifted > 1e-12 {
                out.push(format!(
                    "{name}: its box {b:?} does not move with it: {moved:?}"
                ));
            }
            // A ray from outside the box through its centre meets the
            // primitive inside the box.
            let origin = b.center() - DVec3::new(0.0, 0.0, 10.0 + (b.hi.z - b.lo.z));
            let ray = Ray {
                origin: Vec3::of(origin),
                dir: Vec3::of(DVec3::Z),
            };
            match cpu.intersect(&ray, false) {
                Some(t) => {
                    let hit = origin + DVec3::Z * t;
                    let slack = 1e-9 * (1.0 + hit.abs().max_element());
                    if (hit - b.lo).min_element() < -slack || (b.hi - hit).min_element() < -slack {
                        out.push(format!("{name}: a hit at {hit} lies outside its box {b:?}"));
                    }
                }
                None => out.push(format!(
                    "{name}: its example is not hit along +z through its box's centre, so the box goes unchecked"
                )),
            }
        }
        (false, None, None) => {}
        (bounded, b, _) => out.push(format!(
            "{name}: BOUNDED is {bounded} but its example's box is {b:?}"
        )),
    }
    // A hull holds every hit: the tables' spans take it for the primitive
    // (`Kind::hull`), and a hull too small would lose hits from their lists.
    if let (false, Some(b)) = (p.hull().balls().is_empty(), p.bounds()) {
        for hit in hits_around(&cpu, b) {
            if let Some(by) = outside_hull(&p.hull(), hit) {
                out.push(format!(
                    "{name}: a hit at {hit} lies {by:.3e} outside its hull {:?}",
                    p.hull()
                ));
                break;
            }
        }
    }
    out
}

/// Where rays from 26 directions around `b` (its corners, edges' and
/// faces' middles), aimed at points about its centre, meet `shape`.
fn hits_around<S: Shape<f64>>(shape: &S, b: Aabb) -> Vec<DVec3> {
    let size = (b.hi - b.lo).max_element().max(1e-9);
    let mut hits = Vec::new();
    for i in 0..27 {
        let way = DVec3::new(
            f64::from(i % 3) - 1.0,
            f64::from(i / 3 % 3) - 1.0,
            f64::from(i / 9) - 1.0,
        );
        if way == DVec3::ZERO {
            continue;
        }
        for aim in [
            DVec3::ZERO,
            DVec3::new(0.2, -0.1, 0.15),
            DVec3::new(-0.3, 0.25, -0.2),
        ] {
            let target = b.center() + aim * (b.hi - b.lo);
            let origin = target + way.normalize() * (4.0 * size);
            let ray = Ray {
                origin: Vec3::of(origin),
                dir: Vec3::of(-way.normalize()),
            };
            if let Some(t) = shape.intersect(&ray, false) {
                hits.push(origin - way.normalize() * t);
            }
        }
    }
    hits
}

/// How far `p` lies outside the convex hull of `hull`'s balls, where it
/// does by more than rounding. The hull is the union of the balls
/// `B(sum w c, sum w r)` over weights w >= 0 that sum to 1, so the least of
/// `|p - sum w c| - sum w r` over w (convex in w: found by ternary search,
/// nested for three balls) is <= 0 exactly where p is in it.
fn outside_hull(hull: &Hull, p: DVec3) -> Option<f64> {
    let balls = hull.balls();
    let gap = |w: [f64; 3]| {
        let (c, r) = balls
            .iter()
            .zip(w)
            .fold((DVec3::ZERO, 0.0), |(c, r), (&(bc, br), w)| {
                (c + bc * w, r + br * w)
            });
        (p - c).length() - r
    };
    let least = |f: &dyn Fn(f64) -> f64, hi: f64| {
        let (mut lo, mut hi) = (0.0, hi);
        for _ in 0..100 {
            let (a, b) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
            if f(a) <= f(b) {
                hi = b;
            } else {
                lo = a;
            }
        }
        f(0.5 * (lo + hi))
    };
    let by = match balls.len() {
        1 => gap([1.0, 0.0, 0.0]),
        2 => least(&|t| gap([1.0 - t, t, 0.0]), 1.0),
        _ => least(&|a| least(&|b| gap([1.0 - a - b, a, b]), 1.0 - a), 1.0),
    };
    let scale = balls.iter().fold(p.abs().max_element(), |m, (c, r)| {
        m.max(c.abs().max_element() + r)
    });
    (by > 1e-9 * (1.0 + scale)).then_some(by)
}

/// The hull's check fails a hull that is too small, and passes the true
/// one: a sphere's hits against its own ball and half of it, a segment's
/// and a triangle's points against the balls at their ends and corners.
#[test]
fn a_hull_too_small_is_found() {
    let s = sphere::Sphere::example(0);
    let b = s.bounds().unwrap();
    let hits = hits_around(&s.cpu::<f64>(), b);
    assert!(hits.len() > 50, "{}", hits.len());
    let (c, r) = s.hull().balls()[0];
    assert!(hits.iter().all(|&h| outside_hull(&s.hull(), h).is_none()));
    let half = Hull::of(&[(c, 0.5 * r)]);
    assert!(hits.iter().all(|&h| outside_hull(&half, h).is_some()));
    let ends = Hull::of(&[(DVec3::ZERO, 1.0), (DVec3::X * 4.0, 0.5)]);
    assert!(outside_hull(&ends, DVec3::new(2.0, 0.74, 0.0)).is_none());
    assert!(outside_hull(&ends, DVec3::new(2.0, 0.8, 0.0)).is_some());
    let corners = Hull::of(&[(DVec3::ZERO, 0.0), (DVec3::X, 0.0), (DVec3::Y, 0.0)]);
    assert!(outside_hull(&corners, DVec3::new(0.25, 0.25, 0.0)).is_none());
    assert!(outside_hull(&corners, DVec3::new(0.25, 0.25, 1e-3)).is_some());
    assert!(outside_hull(&corners, DVec3::new(0.6, 0.6, 0.0)).is_some());
}

macro_rules! every_kind {
    ($($key:ident : $kind:ty),* $(,)?) => {
        /// Every kind's problems, in the table's order.
        fn every_kind_problems() -> Vec<String> {
            let mut out = Vec::new();
            $(out.extend(problems::<$kind>());)*
            out
        }
    };
}
with_kinds!(every_kind);

#[test]
fn every_kind_keeps_the_contract() {
    let problems = every_kind_problems();
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// A kind that breaks the contract is named: the sphere with its meta's
/// x and y swapped, as a kind that wrote them the other way would be.
#[derive(Debug, Clone, PartialEq)]
struct SwappedMeta(sphere::Sphere);

impl Kind for SwappedMeta {
    type File = sphere::SphereFile;
    type Gpu = sphere::gpu::Values;
    type Cpu<R: Real> = sphere::SphereR<R>;
    const NAME: &'static str = "swapped";
    const GLSL: &'static str = "real swapped_intersect(Ray r, Sphere s, bool from_self);\n";
    const BOUNDED: bool = true;

    fn check(file: &Self::File, at: &At) -> Result<Self, SceneError> {
        sphere::Sphere::check(file, at).map(SwappedMeta)
    }
    fn material(&self) -> u32 {
        self.0.material()
    }
    fn relative_to(&self, origin: DVec3) -> Self {
        SwappedMeta(self.0.relative_to(origin))
    }
    fn bounds(&self) -> Option<Aabb> {
        self.0.bounds()
    }
    fn gpu(&self, file_index: u32) -> Self::Gpu {
        let mut g = self.0.gpu(file_index);
        g.meta.swap(0, 1);
        g
    }
    fn cpu<R: Real>(&self) -> Self::Cpu<R> {
        self.0.cpu()
    }
    fn example(material: u32) -> Self {
        SwappedMeta(sphere::Sphere::example(material))
    }
    fn sample(p: &mut crate::rng::Place) -> Self::File {
        sphere::Sphere::sample(p)
    }
}

#[test]
fn a_kind_that_breaks_the_contract_is_named() {
    let problems = problems::<SwappedMeta>();
    assert_eq!(problems.len(), 4, "{problems:#?}");
    assert!(
        problems[0].starts_with("swapped: meta is [7, 5, 0, 0]"),
        "{}",
        problems[0]
    );
    assert!(problems[1].contains("swapped_shape"), "{}", problems[1]);
    assert!(problems[2].contains("swapped_normal"), "{}", problems[2]);
    // A sphere's uv under a kind that says it has none.
    assert!(problems[3].contains("has_uv is false"), "{}", problems[3]);
}
