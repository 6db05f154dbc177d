//! A render's AOVs (arbitrary output values, issue 60): per pixel, what its
//! first eye ray met first (its distance, normal, albedo and primitive),
//! and how many rays its samples traced. Both renderers give them, the
//! shader through shaders/aov.glsl in the words below, the CPU through its
//! tally (`Tally::eye_hit`); a render that asks for none compiles none.

use super::record::{Prim, KIND_SHIFT};

/// The AOVs a render can give, by the names the Python module takes.
pub const NAMES: [&str; 5] = ["depth", "normal", "albedo", "prim_id", "rays"];

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

/// A pixel's AOVs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aov {
    /// The first eye ray's hit; None where it met nothing.
    pub hit: Option<EyeHit>,
    /// The rays the pixel's samples traced: eye, reflection, refraction
    /// and shadow rays, as `--stats` counts them.
    pub rays: u32,
}

/// Words of a pixel's AOVs in the shader's Aovs block: three uvec4s
/// (depth as f32 bits, the primitive's id, the rays, 0), (the normal's
/// three f32s, 0), (the albedo's, 0).
pub const WORDS: usize = 12;

/// The word of no primitive (the shader's NONE).
const NONE: u32 = u32::MAX;

impl Aov {
    /// A pixel's AOVs from the shader's words.
    pub fn decode(w: &[u32]) -> Self {
        let f = |i: usize| f64::from(f32::from_bits(w[i]));
        let hit = (w[1] != NONE).then(|| EyeHit {
            depth: f(0),
            normal: [f(4), f(5), f(6)],
            albedo: [f(8), f(9), f(10)],
            prim: (w[1] >> KIND_SHIFT, w[1] & ((1 << KIND_SHIFT) - 1)),
        });
        Aov { hit, rays: w[2] }
    }

    /// The depth as an image holds it: infinity where nothing was met.
    pub fn depth(&self) -> f32 {
        self.hit.map_or(f32::INFINITY, |h| h.depth as f32)
    }

    /// The normal as an image holds it: zero where nothing was met.
    pub fn normal(&self) -> [f32; 3] {
        self.hit.map_or([0.0; 3], |h| h.normal.map(|x| x as f32))
    }

    /// The albedo as an image holds it: zero where nothing was met.
    pub fn albedo(&self) -> [f32; 3] {
        self.hit.map_or([0.0; 3], |h| h.albedo.map(|x| x as f32))
    }

    /// The primitive's kind and index; -1, -1 where nothing was met.
    pub fn prim_id(&self) -> [i32; 2] {
        self.hit
            .map_or([-1, -1], |h| [h.prim.0 as i32, h.prim.1 as i32])
    }
}
