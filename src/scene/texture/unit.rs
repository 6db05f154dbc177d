//! What a pattern provides (`PatternType`), and what the generated code
//! and the checks know of it (`PatternInfo`).

use serde::de::DeserializeOwned;
use serde::Serialize;

use super::{Look, Needs, PatternAt, PatternId, TextureFile, TextureR};
use crate::base::real::{Real, Vec3};
use crate::input::error::SceneError;
use crate::input::field::Triple;
use crate::input::keys::keys_of;
use crate::prim::Shape;
use crate::rng::Place;

/// What one pattern provides.
pub trait PatternType {
    /// Its name: `pattern = "<name>"` in the scene file (but for a pattern
    /// read from a file), and the stem of `<name>_colour` in
    /// `shaders/texture/<include>.glsl`.
    const NAME: &'static str;
    /// How messages name one: `a "checker"`, `an image`.
    const WHAT: &'static str;
    /// Its GLSL include (shared by patterns of one module).
    const GLSL: &'static str;
    /// The include's name under shaders/texture/.
    const INCLUDE: &'static str;
    /// Whether it is read from an image file (`image = "..."`) rather than
    /// named by `pattern`.
    const FILE: bool = false;
    /// Its keys besides `pattern` and `image`, with serde's
    /// `deny_unknown_fields`: a key of another pattern is refused naming
    /// the patterns that take it, any other as unknown. (TOML leaves a key
    /// that is `None` out when it writes one.)
    type File: DeserializeOwned + Serialize;
    /// What of the surface it reads: its include reads it where the variant
    /// has it (`HAS_TEXTURES` a frame, `HAS_IMAGES` uvs).
    const NEEDS: Needs;

    /// Checks its keys (read from `at`'s table) into its look.
    fn check(file: Self::File, at: &PatternAt) -> Result<Look, SceneError>;
    /// Its colour at `p` on `surface` (whose uv or frame it has, where it
    /// needs them); mirrors `<name>_colour`.
    fn colour<R: Real>(
        t: &TextureR<R>,
        texels: &[[f32; 3]],
        surface: &dyn Shape<R>,
        p: Vec3<R>,
    ) -> Vec3<R>;
    /// One texture of this pattern, of squares about `p.size`, as a scene
    /// file's table (an image's file added to `p.files`): what
    /// `crate::generate` gives a textured material.
    fn sample(p: &mut Place) -> TextureFile;
}

/// Two colours apart from each other, for a generated pattern.
pub(crate) fn sample_colors(p: &mut Place) -> [Triple; 2] {
    let a = [
        p.uniform(0.5, 1.0),
        p.uniform(0.0, 1.0),
        p.uniform(0.0, 0.5),
    ];
    let b = [
        p.uniform(0.0, 0.3),
        p.uniform(0.0, 0.3),
        p.uniform(0.3, 1.0),
    ];
    [Triple(a), Triple(b)]
}

impl Needs {
    /// Whether primitives of `kind` have what this asks of a surface.
    pub(crate) fn met_by(self, kind: &crate::prim::KindInfo) -> bool {
        match self {
            Needs::Frame => kind.frame,
            Needs::Uv => kind.uv,
            Needs::Nothing => true,
        }
    }
}

/// What the generated code knows of a pattern.
#[derive(Debug, Clone, Copy)]
pub struct PatternInfo {
    /// Its variant.
    pub pattern: PatternId,
    /// `PatternType::NAME`.
    pub name: &'static str,
    /// `PatternType::WHAT`.
    pub what: &'static str,
    /// `PatternType::GLSL`.
    pub glsl: &'static str,
    /// `PatternType::INCLUDE`.
    pub include: &'static str,
    /// `PatternType::FILE`.
    pub file: bool,
    /// The keys of `PatternType::File`.
    pub keys: fn() -> &'static [&'static str],
    /// `PatternType::NEEDS`.
    pub needs: Needs,
    /// `PatternType::sample`.
    pub(crate) sample: fn(&mut Place) -> TextureFile,
}

impl PatternInfo {
    pub(super) const fn of<P: PatternType>(pattern: PatternId) -> Self {
        Self {
            pattern,
            name: P::NAME,
            what: P::WHAT,
            glsl: P::GLSL,
            include: P::INCLUDE,
            file: P::FILE,
            keys: keys_of::<P::File>,
            needs: P::NEEDS,
            sample: P::sample,
        }
    }

    /// Its include's name: `texture/checker.glsl`.
    pub fn include(&self) -> String {
        format!("texture/{}.glsl", self.include)
    }

    /// The uppercase stem of its code's name: `CHECKER` in
    /// `PATTERN_CHECKER`.
    pub fn upper(&self) -> String {
        self.name.to_uppercase()
    }
}
