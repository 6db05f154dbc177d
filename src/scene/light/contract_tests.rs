//! The contract every light type keeps, checked for each type of the table
//! and failing with its name (docs/shaders.md, Adding a light type):
//!
//! - its include defines `<name>_toward` and, where `LightType::CONE`,
//!   `<name>_cone`, with the signatures lights.glsl calls;
//! - its example table checks, as its own type, and each key of
//!   `LightType::KEYS` is one of the light table's; a key it does not take
//!   is refused naming the type;
//! - a positioned type's light reaches a point at the distance to its
//!   position, unit way towards it; any other's at an infinite distance;
//! - its cone's share lies in 0..=1 (1 without a cone).

use std::path::Path;

use glam::DVec3;

use super::*;
use crate::input::field::{Check, Triple};
use crate::input::locate::Located;

/// A light table of type `kind`, lit, at `position`, pointing `direction`.
pub(super) fn file(
    kind: &str,
    position: Option<[f64; 3]>,
    direction: Option<[f64; 3]>,
) -> LightFile {
    LightFile::placed(kind, position, direction)
}

fn checked(f: &LightFile) -> Result<Light, SceneError> {
    let located = Located::new("");
    let check = Check {
        file: Path::new("t.toml"),
        located: &located,
    };
    check.light(&crate::input::field::root().key("lights").index(0), f)
}

/// What type `T` (the table's `kind`) breaks of the contract.
pub(super) fn problems<T: LightType>(kind: LightKind) -> Vec<String> {
    let name = T::NAME;
    let mut out = Vec::new();
    let signature = format!(
        "void {name}_toward(Light light, vec3r p, out vec3r l, out real dist, out real att)"
    );
    if !T::GLSL.contains(&signature) {
        out.push(format!("{name}: its include lacks `{signature}`"));
    }
    let cone = format!("real {name}_cone(Light light, vec3r l)");
    if T::CONE != T::GLSL.contains(&cone) {
        out.push(format!(
            "{name}: CONE is {} but its include {} `{cone}`",
            T::CONE,
            if T::CONE { "lacks" } else { "has" }
        ));
    }
    let example = T::example();
    let all_keys: Vec<&str> = example.typed_keys().iter().map(|(k, _)| *k).collect();
    for key in T::KEYS {
        if !all_keys.contains(key) {
            out.push(format!(
                "{name}: its key `{key}` is none of the light table's {all_keys:?}"
            ));
        }
    }
    let light = match checked(&example) {
        Ok(l) => l,
        Err(e) => {
            out.push(format!("{name}: its example does not check: {e}"));
            return out;
        }
    };
    if light.kind != kind || kind.info().name != name {
        out.push(format!("{name}: its example checks as {:?}", light.kind));
    }
    // A key of another type, added to its example, is refused by name.
    for (key, _) in example.typed_keys() {
        if T::KEYS.contains(&key) {
            continue;
        }
        let mut f = T::example();
        match key {
            "position" => f.position = Some(Triple([0.0; 3])),
            "direction" => f.direction = Some(Triple([0.0, 0.0, 1.0])),
            "attenuation" => f.attenuation = Some(Triple([1.0, 0.0, 0.0])),
            "cutoff" => f.cutoff = Some(10.0),
            "exponent" => f.exponent = Some(1.0),
            other => {
                out.push(format!("{name}: the contract cannot set `{other}`"));
                continue;
            }
        }
        match checked(&f) {
            Err(e)
                if e.to_string()
                    .contains(&format!("does not apply to a {name} light")) => {}
            other => out.push(format!("{name}: `{key}` is not refused: {other:?}")),
        }
    }
    let l: LightR<f64> = light.cpu(DVec3::ZERO);
    let p = Vec3::new(4.0, -2.0, 7.0);
    let (to, dist, att) = T::toward(&l, p);
    if (to.length() - 1.0).abs() > 1e-12 || !(att > 0.0 && att <= 1.0) {
        out.push(format!(
            "{name}: toward gives a way of length {} and attenuation {att}",
            to.length()
        ));
    }
    let want = if T::POSITIONED {
        (l.position - p).length()
    } else {
        f64::INFINITY
    };
    if dist != want || T::POSITIONED != light.position().is_some() {
        out.push(format!(
            "{name}: POSITIONED is {} but the distance is {dist}",
            T::POSITIONED
        ));
    }
    for d in [to, -to, Vec3::new(0.0, 1.0, 0.0)] {
        let share = T::cone(&l, d);
        if !(0.0..=1.0).contains(&share) || !T::CONE && share != 1.0 {
            out.push(format!("{name}: its cone's share towards {d:?} is {share}"));
        }
    }
    out
}

#[test]
fn every_light_type_keeps_the_contract() {
    let problems = every_type_problems();
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// The contract test fails, naming the type, for a type that breaks it.
#[test]
fn a_type_without_its_function_is_named() {
    struct Broken;
    impl LightType for Broken {
        const NAME: &'static str = "broken";
        const GLSL: &'static str = "void broken_towards(Light light);\n";
        const KEYS: &'static [&'static str] = &["position"];
        const POSITIONED: bool = true;
        fn check(at: &LightAt) -> Result<Placement, SceneError> {
            Ok(Placement {
                position: at.position()?,
                ..Placement::default()
            })
        }
        fn toward<R: Real>(l: &LightR<R>, _p: Vec3<R>) -> Toward<R> {
            (-l.direction, R::infinity(), R::one())
        }
        fn example() -> LightFile {
            file("point", Some([1.0, 2.0, 3.0]), None)
        }
        fn sample(_: &mut crate::rng::Place) -> LightFile {
            Self::example()
        }
    }
    let found = problems::<Broken>(LightKind::Point);
    assert!(
        found
            .iter()
            .any(|p| p.starts_with("broken: its include lacks")),
        "{found:?}"
    );
    assert!(
        found.iter().any(|p| p.starts_with("broken: POSITIONED")),
        "{found:?}"
    );
}
