//! The contract every pattern keeps, checked for each pattern of the table
//! and failing with its name (docs/shaders.md, Adding a pattern):
//!
//! - its include defines `<name>_colour(Texture tx, Hit hit, vec3r p)`, and
//!   is named by a pattern of its own name (the builtin files list it once);
//! - its keys are the texture table's, and a table with each of its keys
//!   and none other checks as this pattern; a key it does not take is
//!   refused;
//! - its colour on a surface with a frame and uvs is finite, and one of its
//!   two colours where it reads no image;
//! - exactly one pattern reads nothing of the surface (the messages offer
//!   it), and at most one is read from a file.

use std::path::Path;

use glam::DVec3;

use super::*;
use crate::input::error::SceneError;
use crate::input::field::{root, Validator};
use crate::input::keys::keys_of;
use crate::input::locate::Located;
use crate::scene::images::Images;

/// A table of `P` with every key of its sample (and, read from a file,
/// no file).
fn table<P: PatternType>() -> TextureFile {
    let mut files = Vec::new();
    let mut rng = crate::rng::Xorshift(7);
    let mut place = crate::rng::Place::new(DVec3::ZERO, 1.0, "", &mut files, &mut rng);
    TextureFile {
        image: None,
        ..P::sample(&mut place)
    }
}

fn checked(t: &TextureFile) -> Result<Texture, SceneError> {
    let located = Located::new("");
    let check = Validator {
        file: Path::new("t.toml"),
        located: &located,
    };
    check.texture(
        &root().key("textures").key("t"),
        t,
        Path::new("."),
        &mut Images::default(),
    )
}

/// A key no pattern takes.
const NO_PATTERNS_KEY: &str = "no_pattern_takes_this";

/// What pattern `P` (the table's `pattern`) breaks of the contract.
pub(super) fn problems<P: PatternType>(pattern: PatternId) -> Vec<String> {
    let name = P::NAME;
    let mut out = Vec::new();
    let signature = format!("vec3r {name}_colour(Texture tx, Hit hit, vec3r p)");
    if !P::GLSL.contains(&signature) {
        out.push(format!("{name}: its include lacks `{signature}`"));
    }
    if !PATTERNS
        .iter()
        .any(|p| p.name == P::INCLUDE && p.glsl == P::GLSL)
    {
        out.push(format!(
            "{name}: no pattern of the include's name `{}` has its include",
            P::INCLUDE
        ));
    }
    let own = keys_of::<P::File>();
    let sample = table::<P>();
    for key in own {
        if !sample.own.contains_key(*key) {
            out.push(format!("{name}: its sample lacks its key `{key}`"));
        }
    }
    if P::FILE {
        // A file pattern is checked with its file in tests/image_textures.rs.
        return out;
    }
    let texture = match checked(&table::<P>()) {
        Ok(t) => t,
        Err(e) => {
            out.push(format!("{name}: its table does not check: {e}"));
            return out;
        }
    };
    if texture.pattern != pattern || pattern.info().name != name {
        out.push(format!("{name}: its table checks as {:?}", texture.pattern));
    }
    // A key of another pattern, added to its table, is refused naming the
    // patterns that take it; a key of no pattern, as unknown.
    let others = PATTERNS
        .iter()
        .flat_map(|p| (p.keys)())
        .filter(|k| !own.contains(k));
    for (key, refusal) in others
        .map(|k| (*k, format!("{} takes no `{k}` (only ", P::WHAT)))
        .chain([(
            NO_PATTERNS_KEY,
            format!("unknown field `{NO_PATTERNS_KEY}`"),
        )])
    {
        let mut t = table::<P>();
        t.own.insert(key.to_owned(), toml::Value::Float(1.0));
        match checked(&t) {
            Err(e)
                if e.to_string()
                    .contains(&format!("textures.t.{key}: {refusal}")) => {}
            other => out.push(format!("{name}: `{key}` is not refused: {other:?}")),
        }
    }
    // On a plane through (0, 0, 1): a frame and uvs.
    let plane: crate::prim::plane::Plane = crate::prim::Kind::example(0);
    let surface = crate::prim::Kind::cpu::<f64>(&plane);
    let t = texture.cpu::<f64>(DVec3::ZERO);
    for p in [Vec3::new(0.3, -2.0, 0.0), Vec3::new(-7.25, 1.5, 0.0)] {
        let c = P::colour(&t, &[], &surface, p);
        if !t.colors.iter().any(|k| [k.x, k.y, k.z] == [c.x, c.y, c.z]) {
            out.push(format!(
                "{name}: its colour at {p:?} is {c:?}, neither of its two"
            ));
        }
    }
    out
}

#[test]
fn every_pattern_keeps_the_contract() {
    let mut problems = every_pattern_problems();
    let anywhere = PATTERNS
        .iter()
        .filter(|p| p.needs == Needs::Nothing)
        .count();
    if anywhere != 1 {
        problems.push(format!(
            "{anywhere} patterns read nothing of a surface, not 1"
        ));
    }
    if PATTERNS.iter().filter(|p| p.file).count() > 1 {
        problems.push("more than one pattern is read from a file".to_owned());
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// The contract test fails, naming the pattern, for one that breaks it.
#[test]
fn a_pattern_without_its_function_is_named() {
    struct Broken;
    #[derive(serde::Serialize, serde::Deserialize)]
    struct BrokenFile {
        tint: Option<f64>,
    }
    impl PatternType for Broken {
        const NAME: &'static str = "broken";
        const WHAT: &'static str = "a \"broken\"";
        const GLSL: &'static str = "vec3r broken_color(Texture tx);\n";
        const INCLUDE: &'static str = "broken";
        type File = BrokenFile;
        const NEEDS: Needs = Needs::Nothing;
        fn check(_: BrokenFile, _: &PatternAt) -> Result<Look, SceneError> {
            Ok(Look::default())
        }
        fn colour<R: Real>(
            t: &TextureR<R>,
            _: &[[f32; 3]],
            _: &dyn Shape<R>,
            _: Vec3<R>,
        ) -> Vec3<R> {
            t.colors[0] * R::of(0.5)
        }
        fn sample(_: &mut crate::rng::Place) -> TextureFile {
            TextureFile::default()
        }
    }
    let found = problems::<Broken>(PATTERNS[0].pattern);
    for wanted in [
        "broken: its include lacks",
        "broken: no pattern of the include",
        "broken: its sample lacks its key `tint`",
    ] {
        assert!(
            found.iter().any(|p| p.starts_with(wanted)),
            "{wanted}: {found:?}"
        );
    }
}
