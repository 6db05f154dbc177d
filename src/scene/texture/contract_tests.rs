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

use super::*;
use crate::input::error::SceneError;
use crate::input::field::{root, Validator};
use crate::input::locate::Located;
use crate::scene::images::Images;

/// A table of `P` with each of its keys (and, read from a file, none).
fn table<P: PatternType>() -> TextureFile {
    let has = |k: &str| P::KEYS.contains(&k);
    TextureFile {
        pattern: (!P::FILE).then(|| P::NAME.to_owned()),
        image: None,
        size: has("size").then_some(0.5),
        colors: has("colors").then_some([Triple([1.0, 0.0, 0.0]), Triple([0.0, 0.0, 1.0])]),
        angle: has("angle").then_some(30.0),
        origin: has("origin").then_some(Triple([0.1, 0.2, 0.3])),
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

impl TextureFile {
    /// The keys a pattern may take, each with whether this table has it.
    fn typed_keys(&self) -> [(&'static str, bool); 4] {
        [
            ("size", self.size.is_some()),
            ("colors", self.colors.is_some()),
            ("angle", self.angle.is_some()),
            ("origin", self.origin.is_some()),
        ]
    }
}

/// What pattern `P` (the table's `pattern`) breaks of the contract.
pub(super) fn problems<P: PatternType>(pattern: Pattern) -> Vec<String> {
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
    let keys: Vec<&str> = table::<P>().typed_keys().iter().map(|(k, _)| *k).collect();
    for key in P::KEYS {
        if !keys.contains(key) {
            out.push(format!(
                "{name}: its key `{key}` is none of the texture table's {keys:?}"
            ));
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
    for (key, _) in table::<P>().typed_keys() {
        if P::KEYS.contains(&key) {
            continue;
        }
        let mut t = table::<P>();
        match key {
            "size" => t.size = Some(1.0),
            "colors" => t.colors = Some([Triple([1.0; 3]); 2]),
            "angle" => t.angle = Some(1.0),
            "origin" => t.origin = Some(Triple([0.0; 3])),
            other => {
                out.push(format!("{name}: the contract cannot set `{other}`"));
                continue;
            }
        }
        if checked(&t).is_ok() {
            out.push(format!("{name}: `{key}` is not refused"));
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
    impl PatternType for Broken {
        const NAME: &'static str = "broken";
        const WHAT: &'static str = "a \"broken\"";
        const GLSL: &'static str = "vec3r broken_color(Texture tx);\n";
        const INCLUDE: &'static str = "broken";
        const KEYS: &'static [&'static str] = &["size", "colors", "tint"];
        const NEEDS: Needs = Needs::Nothing;
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
        "broken: its key `tint`",
    ] {
        assert!(
            found.iter().any(|p| p.starts_with(wanted)),
            "{wanted}: {found:?}"
        );
    }
}
