//! A render's AOVs (arbitrary output values): per pixel, what its first
//! eye ray met first (its distance, normal, albedo and primitive), and how
//! many rays its samples traced. Both renderers give them: the shader
//! through shaders/aov.glsl, whose capture and write are generated from
//! [`AOVS`] (src/gpu/generated.rs, `aovs.glsl`), the CPU through its
//! tally (`Tally::eye_hit`); a render that asks for none compiles none.
//!
//! An AOV is a row of [`AOVS`]: its name, its channels and what they hold,
//! what the shader captures of it and how either renderer's record of a
//! pixel ([`Aov`]) reads as its channels. The Python module's arrays,
//! `glint render --aov` and the docs' lists come from the table.

use super::record::{Prim, KIND_SHIFT};

/// What a pixel's first eye ray (sample i = 0, j = 0) met first.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EyeHit {
    /// The distance along the eye ray's unit direction.
    pub depth: f64,
    /// The shading normal, turned to face the ray, as shading takes it.
    pub normal: [f64; 3],
    /// The material's diffuse colour there, its textures applied.
    pub albedo: [f64; 3],
    /// The primitive: its kind (`prim::KINDS`) and index in the scene.
    pub prim: Prim,
}

/// A pixel's record of its AOVs, from either renderer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aov {
    /// The first eye ray's hit; None where it met nothing.
    pub hit: Option<EyeHit>,
    /// The rays the pixel's samples traced: eye, reflection, refraction
    /// and shadow rays, as `--stats` counts them.
    pub rays: u32,
}

/// What an AOV's channels hold.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Values {
    /// Floats (numpy float32).
    Float,
    /// Whole numbers that may be -1 (numpy int32).
    Int,
    /// Counts (numpy uint32).
    Count,
}

/// When the shader captures an AOV's words.
#[derive(Debug, Clone, Copy)]
pub enum Capture {
    /// At the first eye hit of the pixel's first sample: a GLSL `uint`
    /// expression a word, over `hit` (the `Hit`), `n` (the shading normal
    /// facing the ray) and `m` (the material, its textures applied).
    Hit(&'static [&'static str]),
    /// When the pixel is written: a GLSL `uint` expression a word, over
    /// `counted` (count.glsl's counters of this invocation).
    Pixel(&'static [&'static str]),
}

impl Capture {
    /// The GLSL expressions, one a word.
    pub const fn words(&self) -> &'static [&'static str] {
        match *self {
            Capture::Hit(w) | Capture::Pixel(w) => w,
        }
    }
}

/// One AOV: a row of [`AOVS`].
#[derive(Debug, Clone, Copy)]
pub struct AovType {
    /// Its name, as `aovs=[...]` and `--aov` take it.
    pub name: &'static str,
    /// What its channels hold, and what they are where the eye ray met
    /// nothing (the docs' lists).
    pub doc: &'static str,
    /// Channels a pixel: 1, 2 or 3.
    pub channels: usize,
    /// Their values.
    pub values: Values,
    /// What the shader captures: its words in the `Aovs` block.
    pub capture: Capture,
    /// The word each of its words starts as: what the shader leaves where
    /// the eye ray met nothing.
    pub missed_word: u32,
    /// Its channels in a pixel's record, from either renderer (the unused
    /// ones 0).
    pub read: fn(&Aov) -> [f64; 3],
    /// How far the GPU's channels may be from the CPU's, both in f32
    /// (0: the same): what the contract test holds each row to.
    pub agreement: f64,
}

/// The word of no primitive (the shader's NONE).
const NONE: u32 = u32::MAX;

/// Every AOV, in the order of their words in the `Aovs` block.
pub const AOVS: &[AovType] = &[
    AovType {
        name: "depth",
        doc: "the distance along the eye ray's unit direction; infinity where it met nothing",
        channels: 1,
        values: Values::Float,
        capture: Capture::Hit(&["floatBitsToUint(float((hit).t))"]),
        missed_word: 0,
        read: |a| [a.hit.map_or(f64::INFINITY, |h| h.depth), 0.0, 0.0],
        // f32's rounding of a distance, relative to it.
        agreement: 1e-5,
    },
    AovType {
        name: "normal",
        doc: "the shading normal, turned to face the ray; 0 where it met nothing",
        channels: 3,
        values: Values::Float,
        capture: Capture::Hit(&[
            "floatBitsToUint(float((n).x))",
            "floatBitsToUint(float((n).y))",
            "floatBitsToUint(float((n).z))",
        ]),
        missed_word: 0,
        read: |a| a.hit.map_or([0.0; 3], |h| h.normal),
        // A smooth triangle's normal is interpolated with weights from the
        // hit, which the shader and the CPU round differently (up to
        // 1.3e-5 measured on cylinders.toml's triangles).
        agreement: 1e-4,
    },
    AovType {
        name: "albedo",
        doc: "the material's diffuse colour, its textures applied; 0 where it met nothing",
        channels: 3,
        values: Values::Float,
        capture: Capture::Hit(&[
            "floatBitsToUint(float((m).diffuse.r))",
            "floatBitsToUint(float((m).diffuse.g))",
            "floatBitsToUint(float((m).diffuse.b))",
        ]),
        missed_word: 0,
        read: |a| a.hit.map_or([0.0; 3], |h| h.albedo),
        // An image texture's texel moves with a sphere's uv, which comes
        // through acos and atan2, a few f32 ulps off libm on llvmpipe (up
        // to 1.4e-3 measured on textures.toml); plain colours agree to
        // f32's rounding (tests/aovs.rs holds them to 1e-5).
        agreement: 2e-3,
    },
    AovType {
        name: "prim_id",
        doc: "the primitive's kind (spheres 0, triangles 1, cylinders 2, planes 3) and its index among that kind in the scene; -1, -1 where it met nothing",
        channels: 2,
        values: Values::Int,
        capture: Capture::Hit(&["prim_in_file((hit).prim)"]),
        missed_word: NONE,
        read: |a| {
            a.hit.map_or([-1.0, -1.0, 0.0], |h| {
                [f64::from(h.prim.0), f64::from(h.prim.1), 0.0]
            })
        },
        agreement: 0.0,
    },
    AovType {
        name: "rays",
        doc: "the rays the pixel's samples traced (eye, reflection, refraction and shadow rays): 1 a sample where they met nothing",
        channels: 1,
        values: Values::Count,
        capture: Capture::Pixel(&[
            "counted[COUNT_EYE] + counted[COUNT_REFLECT] + counted[COUNT_REFRACT] + counted[COUNT_SHADOW]",
        ]),
        missed_word: 0,
        read: |a| [f64::from(a.rays), 0.0, 0.0],
        agreement: 0.0,
    },
];

/// The AOVs' names, in the table's order.
pub fn names() -> impl Iterator<Item = &'static str> {
    AOVS.iter().map(|t| t.name)
}

/// The row named `name`.
pub fn named(name: &str) -> Option<&'static AovType> {
    AOVS.iter().find(|t| t.name == name)
}

/// Whether `a` and `b` are the same name (a `const fn`'s `==`).
const fn same(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// The first word of `name`'s words in a pixel's words; with no such
/// AOV, the words the table takes. Computed where it is compiled where
/// `name` is a constant (`Aov::decode`, once a pixel).
pub const fn word_of(name: &str) -> usize {
    let mut n = 0;
    let mut i = 0;
    while i < AOVS.len() && !same(AOVS[i].name, name) {
        n += AOVS[i].capture.words().len();
        i += 1;
    }
    n
}

/// Words the table's AOVs take.
const fn words_used() -> usize {
    word_of("")
}

/// Words of a pixel's AOVs in the shader's Aovs block: the table's, in
/// its order, padded to whole uvec4s.
pub const WORDS: usize = words_used().div_ceil(4) * 4;

impl Aov {
    /// A pixel's AOVs from the shader's words (laid out as [`AOVS`] says).
    pub fn decode(w: &[u32]) -> Self {
        const DEPTH: usize = word_of("depth");
        const NORMAL: usize = word_of("normal");
        const ALBEDO: usize = word_of("albedo");
        const PRIM: usize = word_of("prim_id");
        const RAYS: usize = word_of("rays");
        let f = |i: usize| f64::from(f32::from_bits(w[i]));
        let (depth, normal, albedo) = (DEPTH, NORMAL, ALBEDO);
        let prim = w[PRIM];
        let hit = (prim != NONE).then(|| EyeHit {
            depth: f(depth),
            normal: [f(normal), f(normal + 1), f(normal + 2)],
            albedo: [f(albedo), f(albedo + 1), f(albedo + 2)],
            prim: (prim >> KIND_SHIFT, prim & ((1 << KIND_SHIFT) - 1)),
        });
        Aov { hit, rays: w[RAYS] }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The words decode to the record the table's rows read back: every
    /// row's channels from words written as the shader writes them.
    #[test]
    fn each_rows_words_decode_to_its_channels() {
        let mut words = vec![0u32; WORDS];
        let put = |words: &mut Vec<u32>, name: &str, values: &[u32]| {
            let at = word_of(name);
            words[at..at + values.len()].copy_from_slice(values);
        };
        put(&mut words, "depth", &[2.5f32.to_bits()]);
        put(&mut words, "normal", &[0f32, 1.0, 0.0].map(f32::to_bits));
        put(
            &mut words,
            "albedo",
            &[0.25f32, 0.5, 0.75].map(f32::to_bits),
        );
        put(&mut words, "prim_id", &[2 << KIND_SHIFT | 7]);
        put(&mut words, "rays", &[9]);
        let a = Aov::decode(&words);
        let read = |name: &str| (named(name).unwrap().read)(&a);
        assert_eq!(read("depth"), [2.5, 0.0, 0.0]);
        assert_eq!(read("normal"), [0.0, 1.0, 0.0]);
        assert_eq!(read("albedo"), [0.25, 0.5, 0.75]);
        assert_eq!(read("prim_id"), [2.0, 7.0, 0.0]);
        assert_eq!(read("rays"), [9.0, 0.0, 0.0]);
        // The words the shader starts with: nothing met.
        let missed: Vec<u32> = AOVS
            .iter()
            .flat_map(|t| vec![t.missed_word; t.capture.words().len()])
            .chain(std::iter::repeat(0))
            .take(WORDS)
            .collect();
        let a = Aov::decode(&missed);
        assert_eq!(a.hit, None);
        assert_eq!((named("depth").unwrap().read)(&a)[0], f64::INFINITY);
        assert_eq!((named("prim_id").unwrap().read)(&a), [-1.0, -1.0, 0.0]);
    }

    /// Each row's channels fit its reader, names are unique, and the words
    /// fit the three uvec4s the block gives a pixel.
    #[test]
    fn the_rows_are_whole() {
        let mut seen = Vec::new();
        for t in AOVS {
            assert!((1..=3).contains(&t.channels), "{}", t.name);
            assert!(!t.capture.words().is_empty(), "{}", t.name);
            assert!(!seen.contains(&t.name), "{} twice", t.name);
            seen.push(t.name);
        }
        assert_eq!(WORDS, 12);
        assert_eq!(names().collect::<Vec<_>>(), seen);
    }
}
