//! Nearest hit and any hit over every primitive; mirrors shaders/intersect.glsl
//! and the scans that src/gpu/generated.rs writes for the shader. Each
//! kind's own intersect and normal are in its module of `crate::prim`.

use crate::accel::bvh::{Bvh, Child, EMPTY, MAX_DEPTH, WIDTH};
use crate::accel::tables::{Entry, Lookup, KEY_SLACK};
use crate::prim::{PrimId, KINDS};
use crate::stats::{Counter, Tally};

use super::world::World;
use crate::base::ray::Ray;
use crate::base::real::{Real, Vec3};

#[derive(Debug, Clone, Copy)]
pub struct Hit<R> {
    pub t: R,
    pub prim: PrimId,
}

/// The nearest hit with t in (0, t_max), skipping the surface the ray
/// leaves (`from`). Ties in t go to the lower id: the earlier kind, then the
/// earlier primitive in the file. `tally` counts the tests and nodes.
pub fn intersect_scene<R: Real, T: Tally>(
    w: &World<R>,
    ray: &Ray<R>,
    from: PrimId,
    t_max: R,
    tally: &mut T,
) -> Option<Hit<R>> {
    nearest(w, ray, from, t_max, Lookup::Walk, tally)
}

/// The nearest hit of an eye ray: through its tile's list where the scene
/// has the eye's tiles (`accel::tables`), else as `intersect_scene`. Mirrors
/// intersect_eye() in shaders/intersect.glsl.
pub fn intersect_eye<R: Real, T: Tally>(
    w: &World<R>,
    ray: &Ray<R>,
    tally: &mut T,
) -> Option<Hit<R>> {
    let lookup = match (&w.tables, &w.bvh) {
        (Some(t), Some(_)) => t.eye(ray.dir),
        _ => None,
    };
    if lookup.is_some() {
        tally.count(Counter::Cell);
    }
    let lookup = lookup.unwrap_or(Lookup::Walk);
    nearest(w, ray, PrimId::NONE, R::infinity(), lookup, tally)
}

fn nearest<R: Real, T: Tally>(
    w: &World<R>,
    ray: &Ray<R>,
    from: PrimId,
    t_max: R,
    lookup: Lookup<R>,
    tally: &mut T,
) -> Option<Hit<R>> {
    let mut best: Option<Hit<R>> = None;
    let mut limit = t_max;
    if let Some(tree) = &w.bvh {
        let visit = |id: PrimId, limit: &mut R, tally: &mut T| {
            tally.count(Counter::Test(id.kind));
            if let Some(t) = w.prims.intersect(id, ray, from) {
                let tie = t == *limit && best.is_some_and(|b| id < b.prim);
                if t < *limit || tie {
                    *limit = t;
                    best = Some(Hit { t, prim: id });
                }
            }
            true
        };
        limit = match (lookup, &w.tables) {
            // Nearest first: a primitive that starts beyond the hit (with
            // slack for rounding) cannot be nearer, nor a tie.
            (Lookup::List(range, bound), Some(tables)) => {
                let bound = |limit: R| bound.min(limit * R::of(KEY_SLACK));
                scan_list(tree, &tables.entries[range], limit, bound, tally, visit)
            }
            _ => walk(tree, ray, limit, tally, visit),
        };
    }
    // The kinds the tree does not hold, in the table's order: a strict `<`
    // leaves a tie to the earlier.
    w.prims.scan(w.bvh.is_some(), ray, from, tally, |id, t| {
        if t < limit {
            limit = t;
            best = Some(Hit { t, prim: id });
        }
        true
    });
    best
}

/// Scans a cell's list (`accel::tables`) in the walk's place: calls
/// `visit(id, &mut limit)` for each primitive listed, nearest first, until it
/// returns false or the next entry's key is over `bound(limit)`. Returns the
/// limit. Mirrors list_next() in shaders/tables.glsl, which feeds the walk's
/// own loop.
fn scan_list<R: Real, T: Tally>(
    tree: &Bvh,
    entries: &[Entry],
    mut limit: R,
    bound: impl Fn(R) -> R,
    tally: &mut T,
    mut visit: impl FnMut(PrimId, &mut R, &mut T) -> bool,
) -> R {
    for e in entries {
        if R::of(e.key.into()) > bound(limit) {
            break;
        }
        for id in leaf_prims(tree, e.leaf) {
            if !visit(id, &mut limit, tally) {
                return limit;
            }
        }
    }
    limit
}

/// The primitives of the leaf `word` names, by their ids in the scene.
fn leaf_prims(tree: &Bvh, word: u32) -> impl Iterator<Item = PrimId> + '_ {
    let (kind, range) = match Child::of(word) {
        Child::Leaf(kind, range) => (kind, range),
        _ => (0, 0..0),
    };
    tree.orders[kind][range].iter().map(move |&index| PrimId {
        kind: kind as u32,
        index,
    })
}

/// Whether anything lies on the shadow ray to light `light` strictly
/// between 0 and `dist`: the light's cell where it has a light buffer
/// (`accel::tables`), else the any-hit walk of the BVH; then the scan of
/// what the tree does not hold.
pub fn occluded<R: Real, T: Tally>(
    w: &World<R>,
    ray: &Ray<R>,
    from: PrimId,
    dist: R,
    light: usize,
    tally: &mut T,
) -> bool {
    let mut blocked = false;
    if let Some(tree) = &w.bvh {
        let lookup = w
            .tables
            .as_ref()
            .and_then(|t| t.shadow(light, ray.origin, ray.dir, dist));
        if lookup.is_some() {
            tally.count(Counter::Cell);
        }
        let test = |id: PrimId, _: &mut R, tally: &mut T| {
            tally.count(Counter::Test(id.kind));
            blocked = w.prims.intersect(id, ray, from).is_some_and(|t| t < dist);
            !blocked
        };
        match (lookup, &w.tables) {
            (Some(Lookup::List(range, bound)), Some(tables)) => {
                scan_list(tree, &tables.entries[range], dist, |_| bound, tally, test);
            }
            _ => {
                walk(tree, ray, dist, tally, test);
            }
        }
    }
    if !blocked {
        w.prims.scan(w.bvh.is_some(), ray, from, tally, |_, t| {
            blocked = t < dist;
            !blocked
        });
    }
    blocked
}

/// Walks the tree in `ray`'s order: for each primitive of every leaf whose
/// box the ray meets within `limit`, calls `visit(id, &mut limit)`, which
/// may lower the limit, and returns false to end the walk. Returns the limit.
/// Mirrors walk() in shaders/bvh.glsl: at an inner node, the children whose
/// boxes the ray enters are taken nearest entry first (ties to the earlier
/// slot), the first at once and the others from a stack, where one that
/// starts beyond the limit by then is dropped.
fn walk<R: Real, T: Tally>(
    tree: &Bvh,
    ray: &Ray<R>,
    limit: R,
    tally: &mut T,
    mut visit: impl FnMut(PrimId, &mut R, &mut T) -> bool,
) -> R {
    STACK.with_borrow_mut(|stack| {
        stack.clear();
        walk_with(tree, ray, limit, tally, &mut visit, stack)
    })
}

thread_local! {
    /// Each thread's walk stack: child words and entry distances (an f32
    /// entry is exact in f64), kept between rays so that no walk clears or
    /// allocates one.
    static STACK: std::cell::RefCell<Vec<(u32, f64)>> = std::cell::RefCell::new(Vec::with_capacity(STACK_MAX));
}

fn walk_with<R: Real, T: Tally>(
    tree: &Bvh,
    ray: &Ray<R>,
    mut limit: R,
    tally: &mut T,
    visit: &mut impl FnMut(PrimId, &mut R, &mut T) -> bool,
    stack: &mut Vec<(u32, f64)>,
) -> R {
    let boxes = BoxWalk::new(ray);
    let mut current = ROOT;
    loop {
        match Child::of(current) {
            Child::Leaf(kind, range) => {
                for &index in &tree.orders[kind][range] {
                    let id = PrimId {
                        kind: kind as u32,
                        index,
                    };
                    if !visit(id, &mut limit, tally) {
                        return limit;
                    }
                }
            }
            Child::Inner(i) => {
                tally.count(Counter::Node);
                let node = &tree.nodes[i];
                let mut entered = [(R::zero(), 0usize); WIDTH];
                let mut n = 0;
                for k in 0..WIDTH {
                    if node.child[k] == EMPTY {
                        continue;
                    }
                    if let Some(t) = boxes.entry(node.child_box(k), limit) {
                        entered[n] = (t, k);
                        n += 1;
                    }
                }
                // Nearest first; a tie to the earlier slot (the order the
                // shader's sorting network gives).
                entered[..n].sort_unstable_by(|a, b| {
                    a.0.partial_cmp(&b.0)
                        .unwrap_or(std::cmp::Ordering::Equal)
                        .then(a.1.cmp(&b.1))
                });
                if n > 0 {
                    for &(t, k) in entered[1..n].iter().rev() {
                        stack.push((node.child[k], t.to_f64()));
                    }
                    current = node.child[entered[0].1];
                    continue;
                }
            }
            Child::Empty => unreachable!("an empty slot is never entered"),
        }
        // The next child waiting that starts within the limit.
        loop {
            let Some((word, t)) = stack.pop() else {
                return limit;
            };
            if R::of(t) <= limit * R::of(BOX_SLACK) {
                current = word;
                break;
            }
        }
    }
}

/// The root's word: inner node 0.
const ROOT: u32 = 0;

/// The deepest stack a walk can need (`Bvh::stack_size` of the deepest tree).
const STACK_MAX: usize = (WIDTH - 1) * MAX_DEPTH as usize;

/// A ray's slab test against node boxes; mirrors shaders/bvh.glsl.
struct BoxWalk<R> {
    origin: Vec3<R>,
    inv: Vec3<R>,
}

/// Widens a box's far distance against the rounding of the slab test
/// (1 + 2γ₃ of Ize, "Robust BVH Ray Traversal", JCGT 2013, for f32 with
/// room to spare; the boxes are padded besides).
const BOX_SLACK: f64 = 1.000_002;

impl<R: Real> BoxWalk<R> {
    fn new(ray: &Ray<R>) -> Self {
        // ±1e30 for a zero component: (lo - o) * inv is then never 0 * inf.
        let inv = |d: R| {
            if d.abs() > R::of(1e-30) {
                d.recip()
            } else if d >= R::zero() {
                R::of(1e30)
            } else {
                R::of(-1e30)
            }
        };
        let d = ray.dir;
        Self {
            origin: ray.origin,
            inv: Vec3::new(inv(d.x), inv(d.y), inv(d.z)),
        }
    }

    /// Where the ray enters the box (lo, hi), where it meets it somewhere
    /// in [0, t_max]; else None.
    fn entry(&self, (lo, hi): ([f32; 3], [f32; 3]), t_max: R) -> Option<R> {
        let v = |c: [f32; 3]| Vec3::new(R::of(c[0].into()), R::of(c[1].into()), R::of(c[2].into()));
        let t0 = (v(lo) - self.origin) * self.inv;
        let t1 = (v(hi) - self.origin) * self.inv;
        let near = t0.x.min(t1.x).max(t0.y.min(t1.y)).max(t0.z.min(t1.z));
        let far = t0.x.max(t1.x).min(t0.y.max(t1.y)).min(t0.z.max(t1.z)) * R::of(BOX_SLACK);
        (near <= far && far >= R::zero() && near <= t_max * R::of(BOX_SLACK)).then_some(near)
    }
}

/// What shading needs of the primitive hit at `p`.
pub struct Surface<R> {
    /// The outward (geometric) normal: which side the ray is on.
    pub outward: Vec3<R>,
    /// The normal shading uses, on the side of `outward`.
    pub shading: Vec3<R>,
    pub material: usize,
    /// Whether rays leaving it start lifted off it ([`lift`]).
    pub lifted: bool,
}

pub fn surface<R: Real>(w: &World<R>, prim: PrimId, p: Vec3<R>) -> Surface<R> {
    let shape = w.prims.get(prim);
    let outward = shape.normal(p);
    Surface {
        outward,
        shading: shape.shading(p, outward),
        material: shape.material(),
        lifted: KINDS[prim.kind as usize].lift,
    }
}

/// How far rays leaving a triangle start off it, relative to the size of
/// their coordinates ([`lift`]): 512 ulps in f32.
pub const LIFT: f64 = 1.0 / 16384.0;

/// `p` moved off the surface along the unit `side`, by [`LIFT`] of the
/// largest coordinate of `p` and of the ray's origin `o`: more than the
/// rounding of p = o + t·d and of t can put it behind a neighbouring
/// triangle's plane. The same distance in f64, so that both precisions
/// trace the same model. Mirrors lift() in shaders/intersect.glsl.
pub fn lift<R: Real>(p: Vec3<R>, o: Vec3<R>, side: Vec3<R>) -> Vec3<R> {
    let largest = |v: Vec3<R>| v.x.abs().max(v.y.abs()).max(v.z.abs());
    p + side * (largest(p).max(largest(o)) * R::of(LIFT))
}
