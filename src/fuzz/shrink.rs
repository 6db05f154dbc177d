//! Shrinking a failing generated scene (the simplest delta debugging, as
//! Hypothesis and proptest shrink): each step tries a smaller spec (an
//! object or a light left out, a feature off, fewer samples, depth 1,
//! scale 1 at the origin) and keeps it where the same
//! property still fails; until no step helps, or the budget of checks is
//! spent.

use super::{check, Device, Failure, Property};
use crate::generate::{Sampler, Spec};

/// The specs one step smaller than `s`, the largest cuts first.
fn smaller(s: &Spec) -> Vec<Spec> {
    let mut out = Vec::new();
    let with = |f: &dyn Fn(&mut Spec)| {
        let mut t = s.clone();
        f(&mut t);
        t
    };
    if s.objects.len() > 1 {
        let half = s.objects.len() / 2;
        out.push(with(&|t| t.objects.truncate(half)));
        out.push(with(&|t| {
            t.objects.drain(..half);
        }));
    }
    for i in 0..s.objects.len() {
        out.push(with(&|t| {
            t.objects.remove(i);
        }));
    }
    for i in 0..s.lights.len() {
        out.push(with(&|t| {
            t.lights.remove(i);
        }));
    }
    type Cut<'a> = (bool, &'a dyn Fn(&mut Spec));
    let flags: [Cut; 9] = [
        (s.texture.is_some(), &|t| t.texture = None),
        (s.transmit, &|t| t.transmit = false),
        (s.reflect, &|t| t.reflect = false),
        (s.eye_inside, &|t| t.eye_inside = false),
        (s.grazing, &|t| t.grazing = false),
        (s.sampling != Sampler::Centers, &|t| {
            t.sampling = Sampler::Centers
        }),
        (s.samples > 1, &|t| t.samples = 1),
        (s.depth > 1, &|t| t.depth = 1),
        (s.offset != [0.0; 3] || s.scale != 1.0, &|t| {
            t.offset = [0.0; 3];
            t.scale = 1.0;
        }),
    ];
    out.extend(flags.iter().filter(|(on, _)| *on).map(|(_, f)| with(f)));
    if !s.shadows {
        out.push(with(&|t| t.shadows = true));
    }
    // Not the image's size: `compare` judges shares of pixels (at most
    // 10 % ill-conditioned), and a smaller image fails it for another
    // reason than the scene's.
    out
}

/// The device again, for one more check.
fn reborrow<'a>(d: &'a mut Option<&mut dyn Device>) -> Option<&'a mut dyn Device> {
    match d {
        Some(d) => Some(&mut **d),
        None => None,
    }
}

/// The smallest spec found that still fails `property`, with its
/// failures, and the checks it took; at most `budget` checks.
pub fn shrink(
    spec: &Spec,
    property: Property,
    mut device: Option<&mut dyn Device>,
    budget: usize,
) -> (Spec, Vec<Failure>, usize) {
    let only = move |p: Property| p == property;
    let mut best = spec.clone();
    let mut failures = check(&best, reborrow(&mut device), &only);
    let mut runs = 1;
    'steps: loop {
        for candidate in smaller(&best) {
            if runs >= budget {
                break 'steps;
            }
            runs += 1;
            let f = check(&candidate, reborrow(&mut device), &only);
            if f.iter().any(|f| f.property == property) {
                best = candidate;
                failures = f;
                continue 'steps;
            }
        }
        break;
    }
    (best, failures, runs)
}
