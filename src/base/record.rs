//! The events of one sample's ray tree as a renderer records them for
//! `glint explain` (docs/guide.md, Why does this pixel differ?): the CPU
//! reference through its tally (`Tally::record`), the shader through the
//! hooks of shaders/record.glsl into a buffer of words that [`decode`]
//! reads. Both record the same events in the same order, so that two
//! renderers' trees line up event by event.

use glam::{DVec2, DVec3};

use super::count::RayType;

/// A primitive: its kind (its place in `crate::prim::KINDS`) and its index
/// among its kind in the scene file.
pub type Prim = (u32, u32);

/// One event of a sample's ray tree, in f64 whatever the renderer computed
/// it in (an f32 value is exact in f64).
#[derive(Debug, Clone, PartialEq)]
pub enum Event {
    /// A ray is traced: its type, its depth (1: the eye ray), the surface it
    /// leaves, and its path weight.
    Ray {
        kind: RayType,
        depth: u32,
        from: Option<Prim>,
        origin: DVec3,
        dir: DVec3,
        weight: f64,
    },
    /// It met nothing: the background it adds, times its weight.
    Miss { color: DVec3 },
    /// It met `prim` at distance `t`: the point, the outward geometric
    /// normal, the shading normal (both before they are turned to face the
    /// ray) and the uv coordinates where the scene's image textures read them.
    Hit {
        prim: Prim,
        material: u32,
        t: f64,
        point: DVec3,
        normal: DVec3,
        shading: DVec3,
        uv: Option<DVec2>,
    },
    /// A shadow ray to light `light`, `dist` long: whether it is blocked,
    /// and then the nearest blocker and its distance.
    Shadow {
        light: u32,
        origin: DVec3,
        dir: DVec3,
        dist: f64,
        blocked: bool,
        blocker: Option<(Prim, f64)>,
    },
    /// Light `light`'s terms at the hit, each with its attenuation and
    /// cone: N·L, the cone's factor, whether the direct terms count (in
    /// front, inside the cone, not shadowed), and the ambient, diffuse and
    /// specular terms.
    Light {
        light: u32,
        n_dot_l: f64,
        cone: f64,
        lit: bool,
        ambient: DVec3,
        diffuse: DVec3,
        specular: DVec3,
    },
    /// The hit's local colour: the sum over the lights.
    Local { color: DVec3 },
    /// The weights of the rays the hit spawns (reflectivity with any total
    /// internal reflection added, transmittance) and whether the path
    /// goes on with the reflection ray.
    Branch { kr: f64, kt: f64, follow: bool },
    /// The sample's colour: what the whole tree brings back.
    End { color: DVec3 },
}

/// Words of one recorded entry in the shader's buffer (shaders/record.glsl).
pub const ENTRY_WORDS: usize = 32;
/// Entries the shader's buffer holds; a tree of more is cut short there
/// (and [`decode`] says so).
pub const CAPACITY: usize = 1 << 16;
/// Words before the first entry: the sample recorded (x, y, i, j), the
/// count of entries written (past [`CAPACITY`] where cut short), padding.
pub const HEADER_WORDS: usize = 8;
/// The header's word that counts the entries written (the shader's
/// `record_count`, after the uvec4 `record_at`).
pub const COUNT_WORD: usize = 4;

/// The tags of the entries, as the shader writes them.
const RAY: u32 = 1;
const MISS: u32 = 2;
const HIT: u32 = 3;
const SHADOW: u32 = 4;
const LIGHT: u32 = 5;
const LOCAL: u32 = 6;
const BRANCH: u32 = 7;
const END: u32 = 8;

/// The tags and entry size as GLSL defines, for the recording variant.
pub fn glsl_defines() -> Vec<(String, Option<String>)> {
    [
        ("RECORD_WORDS", ENTRY_WORDS),
        ("RECORD_CAPACITY", CAPACITY),
        ("REC_RAY", RAY as usize),
        ("REC_MISS", MISS as usize),
        ("REC_HIT", HIT as usize),
        ("REC_SHADOW", SHADOW as usize),
        ("REC_LIGHT", LIGHT as usize),
        ("REC_LOCAL", LOCAL as usize),
        ("REC_BRANCH", BRANCH as usize),
        ("REC_END", END as usize),
    ]
    .into_iter()
    .map(|(n, v)| (n.to_owned(), Some(format!("{v}u"))))
    .collect()
}

/// The shader's "no primitive".
const NONE: u32 = u32::MAX;
/// Where a primitive's kind starts in its id, above its index (the
/// shader's `prim_id`).
pub const KIND_SHIFT: u32 = 28;

/// A recording shader's entry being read: its words in order.
struct Words<'a> {
    words: &'a [u32],
    at: usize,
    doubles: bool,
}

impl Words<'_> {
    fn word(&mut self) -> u32 {
        let w = self.words[self.at];
        self.at += 1;
        w
    }
    fn real(&mut self) -> f64 {
        if self.doubles {
            let lo = u64::from(self.word());
            let hi = u64::from(self.word());
            f64::from_bits(hi << 32 | lo)
        } else {
            f64::from(f32::from_bits(self.word()))
        }
    }
    fn vec(&mut self) -> DVec3 {
        DVec3::new(self.real(), self.real(), self.real())
    }
    fn prim(&mut self) -> Option<Prim> {
        let w = self.word();
        (w != NONE).then_some((w >> KIND_SHIFT, w & ((1 << KIND_SHIFT) - 1)))
    }
}

/// The events in a recording shader's buffer, whose reals are doubles
/// where `doubles` (the f64 variant); Err where the shader recorded more
/// than the buffer holds, or wrote a tag this does not know.
pub fn decode(buffer: &[u32], doubles: bool) -> Result<Vec<Event>, String> {
    let count = buffer[COUNT_WORD] as usize;
    if count > CAPACITY {
        return Err(format!(
            "the ray tree has {count} events, more than the {CAPACITY} the shader's record holds"
        ));
    }
    if buffer.len() < HEADER_WORDS + count * ENTRY_WORDS {
        return Err(format!(
            "the record holds fewer words than its {count} events"
        ));
    }
    let mut events = Vec::with_capacity(count);
    for k in 0..count {
        let start = HEADER_WORDS + k * ENTRY_WORDS;
        let mut w = Words {
            words: &buffer[start..start + ENTRY_WORDS],
            at: 1,
            doubles,
        };
        let event = match w.words[0] {
            RAY => Event::Ray {
                // RAY_EYE and the others are the types' places in `ALL`.
                kind: RayType::ALL[(w.word() as usize).min(RayType::ALL.len() - 1)],
                depth: w.word(),
                from: w.prim(),
                origin: w.vec(),
                dir: w.vec(),
                weight: w.real(),
            },
            MISS => Event::Miss { color: w.vec() },
            HIT => {
                let prim = w.prim().unwrap_or((NONE, NONE));
                let material = w.word();
                let has_uv = w.word() != 0;
                let (t, point, normal, shading) = (w.real(), w.vec(), w.vec(), w.vec());
                let uv = DVec2::new(w.real(), w.real());
                Event::Hit {
                    prim,
                    material,
                    t,
                    point,
                    normal,
                    shading,
                    uv: has_uv.then_some(uv),
                }
            }
            SHADOW => {
                let light = w.word();
                let blocked = w.word() != 0;
                let blocker = w.prim();
                let (origin, dir, dist, blocker_t) = (w.vec(), w.vec(), w.real(), w.real());
                Event::Shadow {
                    light,
                    origin,
                    dir,
                    dist,
                    blocked,
                    blocker: blocker.map(|b| (b, blocker_t)),
                }
            }
            LIGHT => Event::Light {
                light: w.word(),
                lit: w.word() != 0,
                n_dot_l: w.real(),
                cone: w.real(),
                ambient: w.vec(),
                diffuse: w.vec(),
                specular: w.vec(),
            },
            LOCAL => Event::Local { color: w.vec() },
            BRANCH => {
                let follow = w.word() != 0;
                Event::Branch {
                    kr: w.real(),
                    kt: w.real(),
                    follow,
                }
            }
            END => Event::End { color: w.vec() },
            tag => return Err(format!("entry {k} of the shader's record has tag {tag}")),
        };
        events.push(event);
    }
    Ok(events)
}
