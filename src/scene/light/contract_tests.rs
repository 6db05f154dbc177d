//! The contract every light type keeps, checked for each type of the table
//! and failing with its name (docs/shaders.md, Adding a light type):
//!
//! - its include defines `<name>_toward` and, where `LightType::CONE`,
//!   `<name>_cone`, with the signatures lights.glsl calls;
//! - its example checks, as its own type; a key of another type is refused
//!   naming the type, and a key no type takes as unknown;
//! - a positioned type's light reaches a point at the distance to its
//!   position, unit way towards it; any other's at an infinite distance;
//! - its cone's share lies in 0..=1 (1 without a cone).

use std::path::Path;

use glam::DVec3;

use super::*;
use crate::input::field::Validator;
use crate::input::locate::Located;

fn checked(f: &LightFile) -> Result<Light, SceneError> {
    let located = Located::new("");
    let check = Validator {
        file: Path::new("t.toml"),
        located: &located,
    };
    check.light(&crate::input::field::root().key("lights").index(0), f)
}

/// A key no light type takes.
const NO_TYPES_KEY: &str = "no_light_type_takes_this";

/// What type `T` (the table's `kind`) breaks of the contract.
pub(super) fn problems<T: LightType>(kind: LightTypeId) -> Vec<String> {
    let name = T::NAME;
    let mut out = Vec::new();
    let signature = format!(
        "void {name}_toward(Light light, vec3r p, vec3r n, out vec3r l, out real dist, out real att)"
    );
    if !T::GLSL.contains(&signature) {
        out.push(format!("{name}: its include lacks `{signature}`"));
    }
    let cone = format!("real {name}_cone(Light light, vec3r p, vec3r n, vec3r l)");
    if T::CONE != T::GLSL.contains(&cone) {
        out.push(format!(
            "{name}: CONE is {} but its include {} `{cone}`",
            T::CONE,
            if T::CONE { "lacks" } else { "has" }
        ));
    }
    // Named as the table names `kind`, so that a type whose NAME is not
    // its table's is found below.
    let example = LightFile {
        kind: kind.info().name.to_owned(),
        ..LightFile::new(T::NAME, &T::example())
    };
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
    // A key of another type, added to its example, is refused by name; a
    // key of no type, as unknown.
    let own = crate::input::keys::keys_of::<T::File>();
    let others = LIGHT_TYPES
        .iter()
        .flat_map(|t| (t.keys)())
        .filter(|k| !own.contains(k));
    for (key, refusal) in others
        .map(|k| (*k, format!("does not apply to a {name} light")))
        .chain([(NO_TYPES_KEY, format!("unknown field `{NO_TYPES_KEY}`"))])
    {
        let mut f = example.clone();
        f.own.insert(key.to_owned(), toml::Value::Float(1.0));
        match checked(&f) {
            Err(e)
                if e.to_string()
                    .contains(&format!("lights[0].{key}: {refusal}")) => {}
            other => out.push(format!("{name}: `{key}` is not refused: {other:?}")),
        }
    }
    let l: LightR<f64> = light.cpu(DVec3::ZERO);
    let p = Vec3::new(4.0, -2.0, 7.0);
    let n = Vec3::new(0.0, 1.0, 0.0);
    let (to, dist, att) = T::toward(&l, p, n);
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
        let share = T::cone(&l, p, n, d);
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
        type File = point::PointFile;
        const NAME: &'static str = "broken";
        const GLSL: &'static str = "void broken_towards(Light light);\n";
        const POSITIONED: bool = true;
        fn check(file: Self::File, at: &LightAt) -> Result<Placement, SceneError> {
            Ok(Placement {
                position: at.position(file.position)?,
                ..Placement::default()
            })
        }
        fn toward<R: Real>(l: &LightR<R>, _p: Vec3<R>, _n: Vec3<R>) -> Toward<R> {
            (-l.direction, R::infinity(), R::one())
        }
        fn example() -> Self::File {
            <point::Point as LightType>::example()
        }
        fn sample(_: &mut crate::rng::Place) -> Self::File {
            Self::example()
        }
    }
    let found = problems::<Broken>(LightTypeId::Point);
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
