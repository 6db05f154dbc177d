//! The first quantity where a renderer's tree leaves the reference's by
//! more than its f32 bound, and its cause in words: a near-tie between two
//! primitives, a self-intersection, a ray that grazes an edge, or a wrong
//! value at one stage.

use serde::Serialize;

use super::flat::{self, Bound, Entry, Value};
use super::tree::{Primitive, Tree};
use super::{number, Geometry};

/// A shadow ray blocked this close to where it starts, relative to the
/// size of its origin's coordinates (2^-12: thousands of f32 roundings),
/// is blocked by the surface it leaves or its neighbour: a self-intersection.
const SELF_HIT: f64 = 1.0 / 4096.0;

/// Where and why a tree leaves the reference's.
#[derive(Debug, Clone, Serialize)]
pub struct Divergence {
    /// The quantity, as the table labels it: `ray 2: hit`.
    pub quantity: String,
    /// The stage that computes it.
    pub stage: &'static str,
    /// Its value in the tree and in the reference's, as printed.
    pub value: String,
    /// The reference's value.
    pub reference: String,
    /// The difference and its f32 bound, for numbers.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub difference: Option<f64>,
    /// The quantity's f32 bound.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bound: Option<f64>,
    /// Whether a conditioning trial changes it too: f32 rounding alone can.
    pub ill_conditioned: bool,
    /// The cause, in words.
    pub cause: String,
}

/// The entry index of `tree`'s first divergence from the reference (`reference`,
/// bounded by `bounds`); None where every quantity is within its bound.
/// The tree is walked an entry at a time ([`flat::walk`]).
pub fn first(tree: &Tree, reference: &[Entry], bounds: &[Bound]) -> Option<usize> {
    let k = flat::walk(tree)
        .zip(reference)
        .zip(bounds)
        .position(|((a, b), bound)| a.label != b.label || b.judged && beyond(&a, b, bound));
    let len = flat::count(tree);
    k.or_else(|| (len != reference.len()).then(|| len.min(reference.len())))
}

/// Whether `a` leaves the reference's `b` past `bound`.
pub fn beyond(a: &Entry, b: &Entry, bound: &Bound) -> bool {
    match a.value.difference(&b.value) {
        Some(d) => d > bound.bound,
        None => a.value != b.value,
    }
}

/// Names a renderer in a sentence: "the GPU" for glint's own.
fn who(renderer: &str) -> String {
    if renderer.starts_with("gpu") {
        "the GPU".to_owned()
    } else {
        renderer.to_owned()
    }
}

/// `tree`'s first divergence from the reference's tree (`ref_tree`, its
/// entries `reference` and their `bounds`), with its cause; `geometry`
/// answers where the reference's rays meet other primitives.
pub fn divergence(
    tree: &Tree,
    ref_tree: &Tree,
    reference: &[Entry],
    bounds: &[Bound],
    geometry: &dyn Geometry,
    cpu_f32: &Tree,
) -> Option<Divergence> {
    let k = first(tree, reference, bounds)?;
    let gpu = who(&tree.renderer);
    let at = flat::entry(tree, k);
    let (Some(a), Some(b)) = (at.as_ref(), reference.get(k)) else {
        let (longer, extra) = match &at {
            Some(e) => (gpu.clone(), e),
            None => ("the CPU".to_owned(), &reference[k]),
        };
        return Some(Divergence {
            quantity: extra.label.to_string(),
            stage: extra.stage.name(),
            value: show(at.as_ref()),
            reference: show(reference.get(k)),
            difference: None,
            bound: None,
            ill_conditioned: bounds.get(k).is_some_and(|b| b.unstable),
            cause: format!(
                "{longer} traces more of the tree: {} is there alone",
                extra.label
            ),
        });
    };
    let unstable = bounds[k].unstable;
    let mut d = Divergence {
        quantity: b.label.to_string(),
        stage: b.stage.name(),
        value: show(Some(a)),
        reference: show(Some(b)),
        difference: a.value.difference(&b.value),
        bound: matches!(b.value, Value::Num { .. }).then_some(bounds[k].bound),
        ill_conditioned: unstable,
        cause: String::new(),
    };
    if a.label != b.label {
        d.cause = format!(
            "the trees part here: {gpu} computes {} where the CPU computes {}",
            a.label, b.label
        );
        return Some(d);
    }
    let ray = b.ray().map(|n| (&tree.rays[n], &ref_tree.rays[n]));
    let ill = if unstable {
        "; a conditioning trial (f32-sized moves of the scene) changes it too: the pixel is ill-conditioned"
    } else {
        ""
    };
    d.cause = match (ray, b.label.what) {
        (Some((g, c)), "hit") => {
            let kind = ray_name(c.kind);
            match (&g.hit, &c.hit) {
                (Some(gh), Some(ch)) => {
                    let other = geometry.distance(gh.primitive, c);
                    // The bound of the distance, the entry after a hit
                    // (`flat::entries`).
                    let tie_bound = bounds[k + 1].bound;
                    debug_assert_eq!(reference[k + 1].label.what, "distance");
                    let (cpu_t, gpu_t) = number::show_apart(ch.distance, gh.distance);
                    match other {
                        Some(t) if (t - ch.distance).abs() <= tie_bound => format!(
                            "the {kind} hits {} on the CPU and {} on {gpu}: distances {cpu_t} and {gpu_t}; the two are within f32 rounding of each other (a near-tie)",
                            ch.primitive,
                            gh.primitive,
                        ),
                        Some(t) => format!(
                            "the {kind} hits {} on the CPU at {} and {} on {gpu} at {}; along the CPU's ray {} is at {}, past f32 rounding: not a near-tie, a wrong ray or intersection on {gpu}{ill}",
                            ch.primitive,
                            number::show(ch.distance),
                            gh.primitive,
                            number::show(gh.distance),
                            gh.primitive,
                            number::show(t)
                        ),
                        None => format!(
                            "the {kind} hits {} on the CPU and {} on {gpu} at {}, which the CPU's ray misses: a wrong ray or intersection on {gpu}{ill}",
                            ch.primitive,
                            gh.primitive,
                            number::show(gh.distance)
                        ),
                    }
                }
                (None, Some(ch)) => format!(
                    "the {kind} hits {} at {} on the CPU and nothing on {gpu}{}",
                    ch.primitive,
                    number::show(ch.distance),
                    graze(unstable, &ch.primitive)
                ),
                (Some(gh), None) => format!(
                    "the {kind} meets nothing on the CPU and {} at {} on {gpu}{}",
                    gh.primitive,
                    number::show(gh.distance),
                    graze(unstable, &gh.primitive)
                ),
                (None, None) => unreachable!("both met nothing: the same value"),
            }
        }
        (Some((g, c)), "shadow ray") => {
            let light = b.label.light().unwrap_or(0);
            let (gs, cs) = (shadow_of(g, light), shadow_of(c, light));
            match (gs.and_then(|s| s.blocker), cs.and_then(|s| s.blocker)) {
                (Some(gb), cb) => {
                    let origin = gs.map_or(0.0, |s| number::largest(&s.origin));
                    let own = g.hit.as_ref().is_some_and(|h| h.primitive == gb.primitive);
                    if own || gb.distance <= SELF_HIT * origin {
                        format!(
                            "the shadow ray to light {light} is blocked on {gpu} by {} at t = {} (self-intersection){}",
                            gb.primitive,
                            number::show(gb.distance),
                            match cb {
                                Some(cb) => format!("; on the CPU by {} at {}", cb.primitive, number::show(cb.distance)),
                                None => "; on the CPU it is clear".to_owned(),
                            }
                        )
                    } else {
                        format!(
                            "the shadow ray to light {light} is blocked on {gpu} by {} at t = {}, and {} on the CPU{}",
                            gb.primitive,
                            number::show(gb.distance),
                            cb.map_or("clear".to_owned(), |cb| format!("by {} at {}", cb.primitive, number::show(cb.distance))),
                            graze(unstable, &gb.primitive)
                        )
                    }
                }
                (None, Some(cb)) => format!(
                    "the shadow ray to light {light} is blocked on the CPU by {} at t = {} and clear on {gpu}{}",
                    cb.primitive,
                    number::show(cb.distance),
                    graze(unstable, &cb.primitive)
                ),
                (None, None) if d.value == "blocked" => format!(
                    "the shadow ray to light {light} is blocked on {gpu} and clear on the CPU, yet {gpu}'s own nearest-hit query finds nothing before the light: its any-hit test (occluded) is wrong{ill}"
                ),
                (None, None) => format!(
                    "the shadow ray to light {light} is {} on {gpu} and {} on the CPU{ill}",
                    d.value, d.reference
                ),
            }
        }
        _ => match (d.difference, d.bound) {
            (Some(diff), Some(bound)) => {
                let f32_within = flat::entry(cpu_f32, k)
                    .is_some_and(|e| e.label == b.label && !beyond(&e, b, &bounds[k]));
                format!(
                    "{} is {} on {gpu} and {} on the CPU: {} apart, past its f32 bound of {}; the first value beyond f32 rounding, computed by {}{}{ill}",
                    b.label,
                    d.value,
                    d.reference,
                    number::show(diff),
                    number::show(bound),
                    b.stage.name(),
                    if f32_within {
                        format!(
                            " (the CPU's f32 is within the bound: {gpu} computes this stage less accurately{})",
                            if tree.renderer.ends_with(super::worst::SUFFIX) {
                                super::worst::clause(b.label.what)
                            } else {
                                String::new()
                            }
                        )
                    } else {
                        String::new()
                    }
                )
            }
            _ => format!(
                "{} is {} on {gpu} and {} on the CPU, computed by {}{ill}",
                b.label,
                d.value,
                d.reference,
                b.stage.name()
            ),
        },
    };
    Some(d)
}

/// Where a conditioning trial moves the answer too (`unstable`), the
/// clause that says the ray grazes `p`; else nothing.
fn graze(unstable: bool, p: &Primitive) -> String {
    if !unstable {
        return String::new();
    }
    format!(
        "; a conditioning trial (f32-sized moves of the scene) changes it too: the ray grazes {p}, and the pixel is ill-conditioned"
    )
}

/// "the eye ray", "the reflection ray", "the refraction ray".
fn ray_name(kind: &str) -> &'static str {
    match kind {
        "eye" => "eye ray",
        "reflect" => "reflection ray",
        _ => "refraction ray",
    }
}

fn shadow_of(ray: &super::tree::TreeRay, light: u32) -> Option<&super::tree::Shadow> {
    ray.lights
        .iter()
        .find(|l| l.light == light)
        .and_then(|l| l.shadow_ray.as_ref())
}

/// An entry's value as the table prints it.
pub fn show(e: Option<&Entry>) -> String {
    match e.map(|e| &e.value) {
        None => "-".to_owned(),
        Some(Value::Exact(s)) => s.to_string(),
        Some(Value::Num { v, .. }) => number::show_all(v),
    }
}
