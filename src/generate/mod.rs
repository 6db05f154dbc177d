//! Scenes made from a specification, for the oracle over the whole scene
//! space (docs/guarantees.md, Generated scenes). A [`Spec`] names what a
//! scene holds: objects of the primitive kinds, lights of the light types,
//! one material's features (reflection, transmission, a texture of any
//! pattern), shadows, sampling, depth, scale and offset. [`Spec::scene`]
//! writes it as a scene file whose objects, lights and textures each come
//! from their unit's own `sample` (`Kind::sample`, `LightType::sample`,
//! `PatternType::sample`), so that a new entry of a table is generated
//! with no code here. [`space`] lists the specs: every small one, a
//! covering array, random ones.

pub mod space;

use std::path::{Path, PathBuf};

use glam::DVec3;

use crate::output::OutputError;
use crate::prim::KINDS;
use crate::rng::Place;
use crate::rng::Xorshift;
use crate::scene::texture::PATTERNS;
use crate::scene::{Overrides, Sampling, Scene, SceneError, LIGHT_TYPES};

/// One object: its kind (a place in the kinds' table) and the key its
/// placement is drawn from, so that leaving another object out moves
/// nothing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct Object {
    /// Its kind's place in the kinds' table.
    pub kind: usize,
    /// What its place, size and shape are drawn from.
    pub key: u64,
}

/// One light: its type (a place in the light types' table), its key, and
/// whether it is dark (every intensity 0: a metamorphic check's light).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct LightSpec {
    /// Its type's place in the light types' table.
    pub kind: usize,
    /// What its place and colours are drawn from.
    pub key: u64,
    /// Every intensity 0.
    pub dark: bool,
}

/// How a generated scene samples its pixels: a mode of `[image] sampling`,
/// with contrast sampling's two tests apart, since each is its own choice
/// of which pixels go on (docs/scene-format.md, Rays).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum Sampler {
    /// `centers`, at the spec's `samples`.
    Centers,
    /// `corners`.
    Corners,
    /// `adaptive`: threshold 0.05, to level 2.
    Adaptive,
    /// `contrast` with Mitchell's test (thresholds 0.1), to 9 samples,
    /// the trees compared.
    Contrast,
    /// `contrast` with the range test (0.03), to 9 samples, the trees not
    /// compared.
    Range,
}

impl Sampler {
    /// The mode it sets.
    pub fn mode(self) -> Sampling {
        match self {
            Sampler::Centers => Sampling::Centers,
            Sampler::Corners => Sampling::Corners,
            Sampler::Adaptive => Sampling::Adaptive,
            Sampler::Contrast | Sampler::Range => Sampling::Contrast,
        }
    }

    /// Its keys under `[image]`, beside `samples`.
    fn keys(self, image: &mut toml::Table) {
        image.insert("sampling".into(), value(self.mode()));
        let keys = match self {
            Sampler::Centers | Sampler::Corners => vec![],
            Sampler::Adaptive => vec![("threshold", value(0.05)), ("max_level", value(2))],
            Sampler::Contrast => vec![
                ("thresholds", toml::Value::Array(vec![value(0.1); 3])),
                ("max_samples", value(9)),
            ],
            Sampler::Range => vec![
                ("range", value(0.03)),
                ("max_samples", value(9)),
                ("compare_trees", value(false)),
            ],
        };
        for (k, v) in keys {
            image.insert(k.into(), v);
        }
    }
}

/// What a generated scene holds.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Spec {
    /// The objects, in the file's order within each kind.
    pub objects: Vec<Object>,
    /// The lights, in the file's order.
    pub lights: Vec<LightSpec>,
    /// The material reflects (reflectivity > 0).
    pub reflect: bool,
    /// The material transmits (transmittance > 0, an index of refraction).
    pub transmit: bool,
    /// The material's texture: a pattern's place in the patterns' table.
    pub texture: Option<usize>,
    /// `[render] shadows`.
    pub shadows: bool,
    /// `[image] sampling` and its keys.
    pub sampling: Sampler,
    /// `[image] samples` (for `centers`).
    pub samples: u32,
    /// `[render] max_depth`.
    pub depth: u32,
    /// The image's size.
    pub width: u32,
    /// The image's size.
    pub height: u32,
    /// The size of the scene's objects and distances.
    pub scale: f64,
    /// Where the scene is centred, camera and all.
    pub offset: [f64; 3],
    /// The eye near an object's centre (inside a sphere, say): the one of
    /// the least key, so that the file's order does not move it.
    pub eye_inside: bool,
    /// Lights placed at a grazing angle to the scene's centre.
    pub grazing: bool,
    /// What the camera, the material and the background are drawn from.
    pub seed: u64,
}

/// A generated scene: its file's text and the files beside it.
#[derive(Debug, Clone)]
pub struct Generated {
    /// The scene file, TOML.
    pub text: String,
    /// Files it names (image textures), by name relative to it, and their
    /// bytes.
    pub files: Vec<(String, Vec<u8>)>,
}

impl Generated {
    /// Writes the scene (as `name`) and its files into `dir`; the scene's
    /// path. Each file is written as every output is (`output::write_one`):
    /// whole or not at all, an earlier one at its name kept until the new
    /// one is complete, none left half-written by a signal.
    pub fn write(&self, dir: &Path, name: &str) -> Result<PathBuf, OutputError> {
        let whole = |path: &Path, bytes: &[u8]| {
            crate::output::write_one::<OutputError>(path, &[], false, |w| {
                w.write_all(bytes).map_err(crate::output::io_err(path))
            })
        };
        for (file, bytes) in &self.files {
            whole(&dir.join(file), bytes)?;
        }
        let path = dir.join(name);
        whole(&path, self.text.as_bytes())?;
        Ok(path)
    }

    /// The scene, read as `glint render` reads it, its files written into
    /// `dir` first.
    pub fn load(&self, dir: &Path) -> Result<Scene, SceneError> {
        let path = self
            .write(dir, "generated.toml")
            .map_err(|e| SceneError::Read {
                path: dir.join("generated.toml"),
                cause: match e {
                    OutputError::Io { cause, .. } => cause,
                    other => std::io::Error::other(other.to_string()),
                },
            })?;
        crate::scene::parse(&self.text, &path, &Overrides::default())
    }
}

/// A key drawn from `seed` and a stream number: distinct streams give
/// unrelated draws.
pub(crate) fn mix(seed: u64, stream: u64) -> u64 {
    let mut z = seed ^ stream.wrapping_mul(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    (z ^ (z >> 31)) | 1
}

/// The kinds' keys (`spheres`, ...), in the table's order: what
/// [`Object::kind`] indexes.
pub fn kind_keys() -> Vec<&'static str> {
    KINDS.iter().map(|k| k.key).collect()
}

/// Every value [`Spec::texture`] takes: none, or each pattern.
pub fn pattern_count_options() -> Vec<Option<usize>> {
    std::iter::once(None)
        .chain((0..PATTERNS.len()).map(Some))
        .collect()
}

/// The seed of the `i`-th random case of a run seeded `seed`.
pub fn case_seed(seed: u64, i: u64) -> u64 {
    mix(seed, 1 << 32 | i)
}

/// Three numbers in [lo, hi).
fn colour(rng: &mut Xorshift, lo: f64, hi: f64) -> [f64; 3] {
    [0; 3].map(|_| lo + (hi - lo) * rng.next())
}

fn value<T: serde::Serialize>(v: T) -> toml::Value {
    toml::Value::try_from(v).expect("plain data serializes")
}

impl Spec {
    /// The scene's centre.
    fn center(&self) -> DVec3 {
        DVec3::from_array(self.offset)
    }

    /// Where object `o` goes: a point within 1.6 scales of the centre, and
    /// a size of 0.3 to 0.8 scales.
    fn placed(&self, o: &Object) -> (DVec3, f64, Xorshift) {
        let mut rng = Xorshift(mix(o.key, 1));
        let at = self.center() + rng.unit() * (1.6 * self.scale * rng.next().cbrt());
        let size = self.scale * (0.3 + 0.5 * rng.next());
        (at, size, rng)
    }

    /// Whether material "m" fits kind `kind`'s primitives: its texture's
    /// pattern reads what they have (else they take "bare", the same
    /// material without the texture).
    fn fits(&self, kind: usize) -> bool {
        self.texture
            .is_none_or(|t| PATTERNS[t].needs.met_by(&KINDS[kind]))
    }

    /// The scene file.
    pub fn scene(&self) -> Generated {
        let mut rng = Xorshift(mix(self.seed, 0));
        let mut files = Vec::new();
        let mut doc = toml::Table::new();
        let center = self.center();
        let s = self.scale;

        let mut image = toml::Table::new();
        image.insert("width".into(), value(self.width));
        image.insert("height".into(), value(self.height));
        image.insert("samples".into(), value(self.samples));
        self.sampling.keys(&mut image);
        doc.insert("image".into(), toml::Value::Table(image));

        let mut render = toml::Table::new();
        render.insert("max_depth".into(), value(self.depth));
        render.insert("shadows".into(), value(self.shadows));
        render.insert("background".into(), value(colour(&mut rng, 0.0, 0.4)));
        doc.insert("render".into(), toml::Value::Table(render));

        // Near the centre of the object of the least key, whatever the
        // file's order: a quarter of its size off it, since the centre of
        // a flat primitive is on its surface, where every eye ray starts
        // on the triangle and no f32 renderer can be held to the image
        // (`glint fuzz` found 8 such scenes, 100 % ill-conditioned).
        let eye = match self.objects.iter().min_by_key(|o| o.key) {
            Some(o) if self.eye_inside => {
                let (at, size, _) = self.placed(o);
                at + Xorshift(mix(o.key, 3)).unit() * (0.25 * size)
            }
            _ => center + (DVec3::new(0.0, 1.2, 5.5) + rng.unit() * 0.5) * s,
        };
        let look = if eye.distance(center) < 0.1 * s {
            center + DVec3::new(0.3, 0.1, -1.0) * s
        } else {
            center
        };
        let mut camera = toml::Table::new();
        camera.insert("eye".into(), value(eye.to_array()));
        camera.insert("look_at".into(), value(look.to_array()));
        camera.insert("vfov".into(), value(40.0 + 30.0 * rng.next()));
        doc.insert("camera".into(), toml::Value::Table(camera));

        let mut material = toml::Table::new();
        material.insert("ambient".into(), value(colour(&mut rng, 0.0, 0.3)));
        material.insert("diffuse".into(), value(colour(&mut rng, 0.2, 0.9)));
        material.insert("specular".into(), value(colour(&mut rng, 0.0, 0.8)));
        let shininess = [0.0, 1.0, 20.0, 200.0][(rng.next() * 4.0) as usize % 4];
        material.insert("shininess".into(), value(shininess));
        if self.reflect {
            material.insert("reflectivity".into(), value(0.2 + 0.6 * rng.next()));
        }
        if self.transmit {
            material.insert("transmittance".into(), value(0.3 + 0.6 * rng.next()));
            material.insert("ior".into(), value(1.0 + rng.next()));
        }
        let bare = material.clone();
        let mut materials = toml::Table::new();
        if let Some(t) = self.texture {
            material.insert("texture".into(), value("t"));
            let mut p = Place::new(center, s, "m", &mut files, &mut rng);
            let table = value((PATTERNS[t].sample)(&mut p));
            doc.insert(
                "textures".into(),
                value(
                    [("t".to_owned(), table)]
                        .into_iter()
                        .collect::<toml::Table>(),
                ),
            );
        }
        materials.insert("m".into(), toml::Value::Table(material));
        materials.insert("bare".into(), toml::Value::Table(bare));
        doc.insert("materials".into(), toml::Value::Table(materials));

        for (k, kind) in KINDS.iter().enumerate() {
            let name = if self.fits(k) { "m" } else { "bare" };
            let rows: Vec<toml::Value> = self
                .objects
                .iter()
                .filter(|o| o.kind == k)
                .map(|o| {
                    let (at, size, mut orng) = self.placed(o);
                    let mut p = Place::new(at, size, name, &mut files, &mut orng);
                    toml::Value::Table((kind.sample)(&mut p))
                })
                .collect();
            if !rows.is_empty() {
                doc.insert(kind.key.into(), toml::Value::Array(rows));
            }
        }

        let lights: Vec<toml::Value> = self
            .lights
            .iter()
            .map(|l| {
                let mut lrng = Xorshift(mix(l.key, 2));
                let mut p = Place::new(center, s, "", &mut files, &mut lrng);
                let mut f = (LIGHT_TYPES[l.kind].sample)(&mut p);
                if self.grazing {
                    // Nearly in the plane through the centre that faces the eye's way up.
                    let tilt = |t: &mut crate::scene::Triple| {
                        let d = DVec3::from_array(t.0) - center;
                        let flat = DVec3::new(d.x, 0.02 * d.length(), d.z);
                        t.0 = (center + flat).to_array();
                    };
                    if let Some(mut pos) = f.triple("position") {
                        tilt(&mut pos);
                        f.set_triple("position", pos);
                    } else if let Some(mut dir) = f.triple("direction") {
                        let d = DVec3::from_array(dir.0);
                        dir.0 = DVec3::new(d.x, -0.02, d.z).normalize().to_array();
                        f.set_triple("direction", dir);
                    }
                }
                let intensity = if l.dark { 0.0 } else { 1.0 };
                let mut c = |lo: f64, hi: f64| {
                    crate::scene::Triple(colour(&mut lrng, lo, hi).map(|x| x * intensity))
                };
                f.ambient = c(0.0, 0.3);
                f.diffuse = c(0.3, 1.0);
                f.specular = c(0.0, 1.0);
                value(f)
            })
            .collect();
        if !lights.is_empty() {
            doc.insert("lights".into(), toml::Value::Array(lights));
        }
        let text = format!(
            "# glint's scene generator: {}\n{}",
            serde_json::to_string(self).expect("a spec serializes"),
            toml::to_string(&doc).expect("a generated scene serializes")
        );
        Generated { text, files }
    }
}
