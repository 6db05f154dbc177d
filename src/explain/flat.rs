//! A tree laid flat: every quantity of it under a label, in the order it
//! was computed, so that two renderers' trees line up entry by entry; and
//! each quantity's f32 bound, from the conditioning trials.

use std::borrow::Cow;

use super::tree::{Tree, TreeRay};

/// f32's unit roundoff.
const U32: f64 = 1.0 / 16_777_216.0;

/// The least bound on a quantity, in roundings of its scale: a few
/// operations' worth of f32 error, below which no difference is a
/// divergence whatever the trials say.
const FLOOR_ULPS: f64 = 64.0;

/// How far past the widest spread of the trials a value may be: a trial
/// samples the roundings, it does not find the worst of them.
const SPREAD_FACTOR: f64 = 4.0;

/// Which stage of the model computes a quantity, as docs/shaders.md names
/// the files: a divergence points at one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    Ray,
    Intersect,
    Shade,
    Trace,
}

impl Stage {
    pub fn name(self) -> &'static str {
        match self {
            Stage::Ray => "ray (ray.glsl, src/cpu/ray.rs)",
            Stage::Intersect => "intersect (intersect.glsl, src/cpu/intersect.rs)",
            Stage::Shade => "shade (shade.glsl, src/cpu/shade.rs)",
            Stage::Trace => "trace (trace.glsl, src/cpu/trace.rs)",
        }
    }
}

/// Up to three numbers, kept in the entry: a tree of 2,000 rays under 16
/// lights is some 350,000 entries, and a `Vec` and a `String` each (the
/// label's) made `explain` of one pixel peak at 350 MB.
#[derive(Debug, Clone, Copy)]
pub struct Numbers {
    v: [f64; 3],
    /// Never 0: the value's enum keeps its tag there.
    len: std::num::NonZeroU8,
}

impl std::ops::Deref for Numbers {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        &self.v[..usize::from(self.len.get())]
    }
}

impl PartialEq for Numbers {
    fn eq(&self, other: &Self) -> bool {
        **self == **other
    }
}

/// A quantity's value.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// Numbers, compared by their largest difference against a bound of
    /// `scale`'s roundings.
    Num { v: Numbers, scale: f64 },
    /// A primitive, a verdict or a type: equal or not.
    Exact(Cow<'static, str>),
}

impl Value {
    fn num(v: &[f64], scale: f64) -> Self {
        let len = v.len().clamp(1, 3);
        let mut n = Numbers {
            v: [0.0; 3],
            len: std::num::NonZeroU8::new(len as u8).expect("1 to 3"),
        };
        n.v[..v.len().min(3)].copy_from_slice(&v[..v.len().min(3)]);
        Value::Num { v: n, scale }
    }

    fn exact(s: impl Into<Cow<'static, str>>) -> Self {
        Value::Exact(s.into())
    }

    /// The largest difference between two numeric values of one length;
    /// None where they are not that.
    pub fn difference(&self, other: &Value) -> Option<f64> {
        match (self, other) {
            (Value::Num { v: a, .. }, Value::Num { v: b, .. }) if a.len() == b.len() => Some(
                a.iter()
                    .zip(b.iter())
                    .map(|(x, y)| if x == y { 0.0 } else { (x - y).abs() })
                    .fold(0.0, f64::max),
            ),
            _ => None,
        }
    }
}

/// Which quantity an entry is: its ray (by its place in the tree) or the
/// sample, the light where it is one light's, and the field. Written as
/// the table labels it: `ray 2, light 0: diffuse`, `sample: color`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Label {
    ray: u32,
    light: u32,
    /// The field: `hit`, `shadow ray origin`, ...
    pub what: &'static str,
}

/// No ray or no light, in a [`Label`].
const NONE: u32 = u32::MAX;

impl Label {
    /// The ray it belongs to, by its place in the tree (None: the sample).
    pub fn ray(&self) -> Option<usize> {
        (self.ray != NONE).then_some(self.ray as usize)
    }

    /// The light it is of, where it is one light's.
    pub fn light(&self) -> Option<u32> {
        (self.light != NONE).then_some(self.light)
    }

    /// The label without its ray: `light 0: diffuse`, `hit`.
    pub fn field(&self) -> String {
        match self.light() {
            Some(l) => format!("light {l}: {}", self.what),
            None => self.what.to_owned(),
        }
    }
}

impl std::fmt::Display for Label {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match (self.ray(), self.light()) {
            (None, _) => write!(f, "sample: {}", self.what),
            (Some(n), None) => write!(f, "ray {}: {}", n + 1, self.what),
            (Some(n), Some(l)) => write!(f, "ray {}, light {l}: {}", n + 1, self.what),
        }
    }
}

/// One quantity of a tree.
#[derive(Debug, Clone)]
pub struct Entry {
    pub label: Label,
    /// Whether a difference here is a divergence: which of several
    /// blockers is nearest is shown, not judged (the render asks only
    /// whether any is there).
    pub judged: bool,
    pub stage: Stage,
    pub value: Value,
}

impl Entry {
    /// The ray it belongs to, by its place in the tree (None: the sample).
    pub fn ray(&self) -> Option<usize> {
        self.label.ray()
    }
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x.abs()).fold(0.0, f64::max)
}

/// Every quantity of `tree`, in the order the renderers compute them.
pub fn entries(tree: &Tree) -> Vec<Entry> {
    entries_of(tree, |_| true)
}

/// The quantities of the rays of `tree` that `keep` takes (by their place
/// in the tree), and the sample's.
pub fn entries_of(tree: &Tree, keep: impl Fn(usize) -> bool) -> Vec<Entry> {
    // Counted first: a vector grown by doubling holds up to twice them.
    let mut out = Vec::with_capacity(
        tree.rays
            .iter()
            .enumerate()
            .filter(|(n, _)| keep(*n))
            .map(|(_, r)| ray_len(r))
            .sum::<usize>()
            + 1,
    );
    for (n, ray) in tree.rays.iter().enumerate() {
        if keep(n) {
            ray_entries(n, ray, &mut out);
        }
    }
    out.push(sample_entry(tree));
    out
}

/// The entries of `tree` one at a time, in `entries`' order: a ray's laid
/// flat when the walk comes to it, so that a tree is compared with the
/// reference's without all its entries held at once.
pub fn walk(tree: &Tree) -> impl Iterator<Item = Entry> + '_ {
    tree.rays
        .iter()
        .enumerate()
        .flat_map(|(n, ray)| {
            let mut out = Vec::with_capacity(ray_len(ray));
            ray_entries(n, ray, &mut out);
            out
        })
        .chain(std::iter::once_with(|| sample_entry(tree)))
}

/// How many entries `entries(tree)` has.
pub fn count(tree: &Tree) -> usize {
    tree.rays.iter().map(ray_len).sum::<usize>() + 1
}

/// Entry `k` of `entries(tree)`, laid flat alone: only its ray's.
pub fn entry(tree: &Tree, mut k: usize) -> Option<Entry> {
    for (n, ray) in tree.rays.iter().enumerate() {
        let len = ray_len(ray);
        if k < len {
            let mut out = Vec::with_capacity(len);
            ray_entries(n, ray, &mut out);
            return out.into_iter().nth(k);
        }
        k -= len;
    }
    (k == 0).then(|| sample_entry(tree))
}

/// The sample's own quantity: its colour.
fn sample_entry(tree: &Tree) -> Entry {
    Entry {
        label: Label {
            ray: NONE,
            light: NONE,
            what: "color",
        },
        judged: true,
        stage: Stage::Trace,
        value: Value::num(&tree.color, norm(&tree.color).max(1.0)),
    }
}

/// How many entries `ray_entries` makes of `ray`.
fn ray_len(ray: &TreeRay) -> usize {
    let lights: usize = ray
        .lights
        .iter()
        .map(|l| {
            7 + l
                .shadow_ray
                .as_ref()
                .map_or(0, |s| 3 + 2 * usize::from(s.blocker.is_some()))
        })
        .sum();
    let hit = ray
        .hit
        .as_ref()
        .map_or(0, |h| 4 + usize::from(h.uv.is_some()) + lights);
    let kr = usize::from(ray.reflectivity.is_some() && ray.transmittance.is_some());
    7 + hit + 2 * kr
}

fn ray_entries(n: usize, ray: &TreeRay, out: &mut Vec<Entry>) {
    let n32 = n as u32;
    let mut push = |light: u32, what: &'static str, stage: Stage, value: Value| {
        out.push(Entry {
            judged: !what.starts_with("shadow ray blocker"),
            label: Label {
                ray: n32,
                light,
                what,
            },
            stage,
            value,
        })
    };
    let place = norm(&ray.origin);
    push(
        NONE,
        "type",
        Stage::Trace,
        Value::exact(format!("{} depth {}", ray.kind, ray.depth)),
    );
    push(NONE, "origin", Stage::Ray, Value::num(&ray.origin, place));
    push(
        NONE,
        "direction",
        Stage::Ray,
        Value::num(&ray.direction, 1.0),
    );
    push(NONE, "weight", Stage::Trace, Value::num(&[ray.weight], 1.0));
    let met = ray.hit.as_ref().map_or(Value::exact("nothing"), |h| {
        Value::exact(h.primitive.to_string())
    });
    push(NONE, "hit", Stage::Intersect, met);
    if let Some(h) = &ray.hit {
        let scale = place.max(h.distance);
        push(
            NONE,
            "distance",
            Stage::Intersect,
            Value::num(&[h.distance], scale),
        );
        push(
            NONE,
            "point",
            Stage::Intersect,
            Value::num(&h.point, scale.max(norm(&h.point))),
        );
        push(NONE, "normal", Stage::Intersect, Value::num(&h.normal, 1.0));
        push(
            NONE,
            "shading_normal",
            Stage::Intersect,
            Value::num(&h.shading_normal, 1.0),
        );
        if let Some(uv) = h.uv {
            push(
                NONE,
                "uv",
                Stage::Intersect,
                Value::num(&uv, norm(&uv).max(1.0)),
            );
        }
        for l in &ray.lights {
            let at = l.light;
            push(at, "n_dot_l", Stage::Shade, Value::num(&[l.n_dot_l], 1.0));
            push(at, "cone", Stage::Shade, Value::num(&[l.cone], 1.0));
            let cast = if l.shadow_ray.is_some() {
                "cast"
            } else {
                "not cast"
            };
            push(at, "shadow ray cast", Stage::Shade, Value::exact(cast));
            if let Some(s) = &l.shadow_ray {
                let scale = norm(&s.origin).max(1e-300);
                push(
                    at,
                    "shadow ray origin",
                    Stage::Shade,
                    Value::num(&s.origin, scale),
                );
                push(
                    at,
                    "shadow ray direction",
                    Stage::Shade,
                    Value::num(&s.direction, 1.0),
                );
                let blocked = if s.blocked { "blocked" } else { "clear" };
                push(at, "shadow ray", Stage::Intersect, Value::exact(blocked));
                if let Some(b) = s.blocker {
                    push(
                        at,
                        "shadow ray blocker",
                        Stage::Intersect,
                        Value::exact(b.primitive.to_string()),
                    );
                    push(
                        at,
                        "shadow ray blocker distance",
                        Stage::Intersect,
                        Value::num(&[b.distance], scale.max(b.distance)),
                    );
                }
            }
            let lit = if l.lit { "true" } else { "false" };
            push(at, "lit", Stage::Shade, Value::exact(lit));
            for (name, term) in [
                ("ambient", l.ambient),
                ("diffuse", l.diffuse),
                ("specular", l.specular),
            ] {
                push(
                    at,
                    name,
                    Stage::Shade,
                    Value::num(&term, norm(&term).max(1.0)),
                );
            }
        }
    }
    push(
        NONE,
        "local",
        Stage::Shade,
        Value::num(&ray.local, norm(&ray.local).max(1.0)),
    );
    if let (Some(kr), Some(kt)) = (ray.reflectivity, ray.transmittance) {
        push(NONE, "reflectivity", Stage::Trace, Value::num(&[kr], 1.0));
        push(NONE, "transmittance", Stage::Trace, Value::num(&[kt], 1.0));
    }
    push(
        NONE,
        "color",
        Stage::Trace,
        Value::num(&ray.color, norm(&ray.color).max(1.0)),
    );
}

/// Each quantity of the reference's tree: its f32 bound and whether a
/// trial changed it past any bound (a different primitive, verdict or
/// shape: ill-conditioned).
#[derive(Debug, Clone)]
pub struct Bound {
    pub bound: f64,
    pub unstable: bool,
}

/// The bounds of `reference`'s entries before any trial: [`FLOOR_ULPS`]
/// roundings of each one's scale. [`widen`] adds each trial's tree: the
/// widest a trial moved a quantity, [`SPREAD_FACTOR`] times.
pub fn floor_bounds(reference: &[Entry]) -> Vec<Bound> {
    reference
        .iter()
        .map(|e| Bound {
            bound: match &e.value {
                Value::Num { scale, .. } => FLOOR_ULPS * U32 * scale,
                Value::Exact(_) => 0.0,
            },
            unstable: false,
        })
        .collect()
}

/// Widens `bounds` by one trial's entries `t`. A trial's tree says nothing
/// of the quantities after its first change of shape (another primitive,
/// verdict or ray), and calls that one unstable. A trial at a time, so that
/// no more than one trial's entries are held (a tree of 1,953 rays held
/// nine, and `explain` peaked at 0.7-1 GB).
pub fn widen(bounds: &mut [Bound], reference: &[Entry], t: &Tree) {
    let mut walked = 0;
    for ((e, b), te) in reference.iter().zip(bounds.iter_mut()).zip(walk(t)) {
        if changes_shape(e, &te) {
            b.unstable = true;
            return;
        }
        if let Some(d) = e.value.difference(&te.value) {
            b.bound = b.bound.max(SPREAD_FACTOR * d);
        }
        walked += 1;
    }
    // A tree that ends early changes shape where it ends.
    if let Some(b) = bounds.get_mut(walked) {
        b.unstable = true;
    }
}

/// Whether `t`'s entry is another quantity than the reference's `e`, or
/// another exact value of a judged one: a change of the tree's shape.
fn changes_shape(e: &Entry, t: &Entry) -> bool {
    e.label != t.label
        || e.judged && matches!((&e.value, &t.value), (Value::Exact(x), Value::Exact(y)) if x != y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::Accel;
    use crate::cpu::Probe;

    /// A pixel whose tree reflects, refracts and casts shadow rays, some
    /// of them blocked: every kind of entry.
    fn tree() -> Tree {
        let text = "[image]\nwidth = 1\nheight = 1\n[render]\nmax_depth = 5\nshadows = true\n\
            [camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\nvfov = 10\n\
            [materials.g]\ndiffuse = [0.2, 0.2, 0.2]\nspecular = [0.5, 0.5, 0.5]\nshininess = 50\n\
            reflectivity = 0.3\ntransmittance = 0.6\nior = 1.5\n\
            [[spheres]]\ncenter = [0, 0, 0]\nradius = 2\nmaterial = \"g\"\n\
            [[spheres]]\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"g\"\n\
            [materials.o]\ndiffuse = [0.5, 0.5, 0.5]\n\
            [[spheres]]\ncenter = [1.5, 1.5, 4]\nradius = 0.5\nmaterial = \"o\"\n\
            [[lights]]\ntype = \"point\"\nposition = [3, 3, 6]\ndiffuse = [1, 1, 1]\n\
            [[lights]]\ntype = \"point\"\nposition = [0, 0, -6]\ndiffuse = [1, 1, 1]\n";
        let scene = crate::scene::parse(
            text,
            std::path::Path::new("t.toml"),
            &crate::scene::Overrides::default(),
        )
        .unwrap();
        let events = Probe::<f64>::new(&scene, Accel::Bvh).record([0, 0, 0, 0]);
        Tree::of("cpu f64", &events).unwrap()
    }

    /// An entry laid flat alone is the one laid flat with the rest, and
    /// each ray's count is its entries' (the vector is sized by it).
    #[test]
    fn an_entry_alone_is_the_same_entry_of_the_whole_tree() {
        let tree = tree();
        let all = entries(&tree);
        assert!(tree.rays.len() > 4, "{} rays", tree.rays.len());
        assert!(all.iter().any(|e| e.label.what == "shadow ray blocker"));
        assert_eq!(all.len(), tree.rays.iter().map(ray_len).sum::<usize>() + 1);
        for (k, e) in all.iter().enumerate() {
            let alone = entry(&tree, k).unwrap();
            assert_eq!((alone.label, &alone.value), (e.label, &e.value));
        }
        assert!(entry(&tree, all.len()).is_none());
        assert_eq!(count(&tree), all.len());
        let walked: Vec<Entry> = walk(&tree).collect();
        assert!(walked
            .iter()
            .zip(&all)
            .all(|(a, b)| a.label == b.label && a.value == b.value));
        assert_eq!(walked.len(), all.len());
        assert!(std::mem::size_of::<Entry>() <= 72);
        let some = entries_of(&tree, |n| n == 1);
        assert!(some.iter().all(|e| e.ray().is_none_or(|n| n == 1)));
        assert_eq!(all[0].label.to_string(), "ray 1: type");
        assert!(all
            .iter()
            .any(|e| e.label.to_string().starts_with("ray 1, light 1: ")));
    }
}
