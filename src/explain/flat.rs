//! A tree laid flat: every quantity of it under a label, in the order it
//! was computed, so that two renderers' trees line up entry by entry; and
//! each quantity's f32 bound, from the conditioning trials.

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

/// A quantity's value.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// Numbers, compared by their largest difference against a bound of
    /// `scale`'s roundings.
    Num { v: Vec<f64>, scale: f64 },
    /// A primitive, a verdict or a type: equal or not.
    Exact(String),
}

impl Value {
    fn num(v: &[f64], scale: f64) -> Self {
        Value::Num {
            v: v.to_vec(),
            scale,
        }
    }

    /// The largest difference between two numeric values of one length;
    /// None where they are not that.
    pub fn difference(&self, other: &Value) -> Option<f64> {
        match (self, other) {
            (Value::Num { v: a, .. }, Value::Num { v: b, .. }) if a.len() == b.len() => Some(
                a.iter()
                    .zip(b)
                    .map(|(x, y)| if x == y { 0.0 } else { (x - y).abs() })
                    .fold(0.0, f64::max),
            ),
            _ => None,
        }
    }
}

/// One quantity of a tree.
#[derive(Debug, Clone)]
pub struct Entry {
    pub label: String,
    /// Whether a difference here is a divergence: which of several
    /// blockers is nearest is shown, not judged (the render asks only
    /// whether any is there).
    pub judged: bool,
    /// The ray it belongs to, by its place in the tree (None: the sample).
    pub ray: Option<usize>,
    pub stage: Stage,
    pub value: Value,
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x.abs()).fold(0.0, f64::max)
}

/// Every quantity of `tree`, in the order the renderers compute them.
pub fn entries(tree: &Tree) -> Vec<Entry> {
    let mut out = Vec::new();
    for (n, ray) in tree.rays.iter().enumerate() {
        ray_entries(n, ray, &mut out);
    }
    out.push(Entry {
        label: "sample: color".to_owned(),
        judged: true,
        ray: None,
        stage: Stage::Trace,
        value: Value::num(&tree.color, norm(&tree.color).max(1.0)),
    });
    out
}

fn ray_entries(n: usize, ray: &TreeRay, out: &mut Vec<Entry>) {
    let at = format!("ray {}", n + 1);
    let mut push = |at: &str, what: &str, stage: Stage, value: Value| {
        let label = format!("{at}: {what}");
        out.push(Entry {
            judged: !label.contains("shadow ray blocker"),
            label,
            ray: Some(n),
            stage,
            value,
        })
    };
    let place = norm(&ray.origin);
    push(
        &at,
        "type",
        Stage::Trace,
        Value::Exact(format!("{} depth {}", ray.kind, ray.depth)),
    );
    push(&at, "origin", Stage::Ray, Value::num(&ray.origin, place));
    push(
        &at,
        "direction",
        Stage::Ray,
        Value::num(&ray.direction, 1.0),
    );
    push(&at, "weight", Stage::Trace, Value::num(&[ray.weight], 1.0));
    let met = ray
        .hit
        .as_ref()
        .map_or("nothing".to_owned(), |h| h.primitive.to_string());
    push(&at, "hit", Stage::Intersect, Value::Exact(met));
    if let Some(h) = &ray.hit {
        let scale = place.max(h.distance);
        push(
            &at,
            "distance",
            Stage::Intersect,
            Value::num(&[h.distance], scale),
        );
        push(
            &at,
            "point",
            Stage::Intersect,
            Value::num(&h.point, scale.max(norm(&h.point))),
        );
        push(&at, "normal", Stage::Intersect, Value::num(&h.normal, 1.0));
        push(
            &at,
            "shading_normal",
            Stage::Intersect,
            Value::num(&h.shading_normal, 1.0),
        );
        if let Some(uv) = h.uv {
            push(
                &at,
                "uv",
                Stage::Intersect,
                Value::num(&uv, norm(&uv).max(1.0)),
            );
        }
        for l in &ray.lights {
            let at = format!("{at}, light {}", l.light);
            push(&at, "n_dot_l", Stage::Shade, Value::num(&[l.n_dot_l], 1.0));
            push(&at, "cone", Stage::Shade, Value::num(&[l.cone], 1.0));
            let cast = if l.shadow_ray.is_some() {
                "cast"
            } else {
                "not cast"
            };
            push(
                &at,
                "shadow ray cast",
                Stage::Shade,
                Value::Exact(cast.to_owned()),
            );
            if let Some(s) = &l.shadow_ray {
                let scale = norm(&s.origin).max(1e-300);
                push(
                    &at,
                    "shadow ray origin",
                    Stage::Shade,
                    Value::num(&s.origin, scale),
                );
                push(
                    &at,
                    "shadow ray direction",
                    Stage::Shade,
                    Value::num(&s.direction, 1.0),
                );
                let blocked = if s.blocked { "blocked" } else { "clear" };
                push(
                    &at,
                    "shadow ray",
                    Stage::Intersect,
                    Value::Exact(blocked.to_owned()),
                );
                if let Some(b) = s.blocker {
                    push(
                        &at,
                        "shadow ray blocker",
                        Stage::Intersect,
                        Value::Exact(b.primitive.to_string()),
                    );
                }
                if let Some(b) = s.blocker {
                    push(
                        &at,
                        "shadow ray blocker distance",
                        Stage::Intersect,
                        Value::num(&[b.distance], scale.max(b.distance)),
                    );
                }
            }
            push(&at, "lit", Stage::Shade, Value::Exact(l.lit.to_string()));
            for (name, term) in [
                ("ambient", l.ambient),
                ("diffuse", l.diffuse),
                ("specular", l.specular),
            ] {
                push(
                    &at,
                    name,
                    Stage::Shade,
                    Value::num(&term, norm(&term).max(1.0)),
                );
            }
        }
    }
    push(
        &at,
        "local",
        Stage::Shade,
        Value::num(&ray.local, norm(&ray.local).max(1.0)),
    );
    if let (Some(kr), Some(kt)) = (ray.reflectivity, ray.transmittance) {
        push(&at, "reflectivity", Stage::Trace, Value::num(&[kr], 1.0));
        push(&at, "transmittance", Stage::Trace, Value::num(&[kt], 1.0));
    }
    push(
        &at,
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
/// no more than one trial's entries are held (issue 57, defect 6: a tree
/// of 1,953 rays held nine, and `explain` peaked at 0.7-1 GB).
pub fn widen(bounds: &mut [Bound], reference: &[Entry], t: &[Entry]) {
    let changed = first_change(reference, t);
    for (k, (e, b)) in reference.iter().zip(bounds).enumerate().take(changed + 1) {
        if k == changed {
            b.unstable = true;
        } else if let Some(d) = e.value.difference(&t[k].value) {
            b.bound = b.bound.max(SPREAD_FACTOR * d);
        }
    }
}

/// The first entry where `t` differs from `reference` in shape: another
/// label or another exact value; the length of the shorter where none does.
pub fn first_change(reference: &[Entry], t: &[Entry]) -> usize {
    reference
        .iter()
        .zip(t)
        .position(|(a, b)| {
            a.label != b.label
                || a.judged
                    && matches!((&a.value, &b.value), (Value::Exact(x), Value::Exact(y)) if x != y)
        })
        .unwrap_or(reference.len().min(t.len()))
}
