//! Eric Haines' Neutral File Format (NFF.TXT; the Standard Procedural
//! Databases' format), read into the scene file's own tables
//! (`SceneFile`), so that an NFF scene is validated, rendered and written
//! out as TOML (`glint convert`) through the same structs as a TOML one.
//! docs/scene-format.md (NFF) gives the mapping; every error names the
//! file and line.

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use glam::DVec3;

use super::camera::CameraFile;
use super::file::{ImageFile, RenderFile, SceneFile};
use super::light::point::{Point, PointFile};
use super::light::LightFile;
use super::light::LightType;
use super::material::MaterialFile;
use super::sampling::Sampling;
use super::SceneError;
use crate::input::field::Triple;
use crate::input::locate::{KeyPath, LineCol, Locate, Seg};
use crate::input::triangles;
use crate::prim::cylinder::CylinderFile;
use crate::prim::sphere::SphereFile;
use crate::prim::triangle::{Triangle, TriangleFile};

/// The SPD's ray-tree depth: the eye ray is depth 1.
pub const SPD_DEPTH: i64 = 5;

/// An NFF scene as the scene file's tables, and where each came from.
pub struct Nff {
    /// The scene, as a scene file's tables (`glint convert` writes them).
    pub scene: SceneFile,
    /// The NFF line each table came from, for messages.
    pub lines: Lines,
}

impl Nff {
    /// Checks and resolves the scene, as for a TOML file; errors name the
    /// NFF line of the entity at fault.
    pub fn check(
        self,
        file: &Path,
        overrides: &super::Overrides,
    ) -> Result<super::Scene, SceneError> {
        super::validate::resolve(self.scene, file, &self.lines, overrides, None)
    }
}

/// Reads and validates NFF text (docs/scene-format.md, NFF); `file` is only
/// used in messages.
pub fn parse_nff(
    text: &str,
    file: &Path,
    overrides: &super::Overrides,
) -> Result<super::Scene, SceneError> {
    read(text, file)?.check(file, overrides)
}

/// The NFF line of each table: of each row of an array (`spheres[3]`), in
/// a list per array rather than a name per row (300,000 spheres took 60
/// bytes each as names), and of each single table (`materials.f2`,
/// `camera`).
#[derive(Default)]
pub struct Lines {
    rows: HashMap<&'static str, Vec<usize>>,
    tables: HashMap<String, usize>,
}

impl Lines {
    /// The next row of `array` comes from `line`.
    fn note_row(&mut self, array: &'static str, line: usize) {
        self.rows.entry(array).or_default().push(line);
    }

    fn note(&mut self, key: String, line: usize) {
        self.tables.entry(key).or_insert(line);
    }
}

impl Locate for Lines {
    /// The line of the table the path starts in: its first two steps
    /// (`spheres[3]`, `materials.f2`), else its first (`camera`).
    fn find(&self, path: &KeyPath) -> Option<LineCol> {
        let row = match path.0.as_slice() {
            [Seg::Key(k), Seg::Index(i), ..] => self.rows.get(k.as_str()).and_then(|r| r.get(*i)),
            _ => None,
        };
        let head = |n: usize| KeyPath(path.0.iter().take(n).cloned().collect()).to_string();
        let line = row
            .or_else(|| self.tables.get(&head(2)))
            .or_else(|| self.tables.get(&head(1)))?;
        Some(LineCol {
            line: *line,
            column: 1,
        })
    }
}

/// Reads NFF text; `file` names it in errors.
pub fn read(text: &str, file: &Path) -> Result<Nff, SceneError> {
    let mut r = Reader {
        file,
        lines: text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.split('#').next().unwrap_or("")))
            .filter(|(_, l)| !l.trim().is_empty())
            .collect(),
        next: 0,
        last_line: text.lines().count().max(1),
        bytes: text.len() as u64,
    };
    r.scene()
}

struct Reader<'a> {
    file: &'a Path,
    /// The lines that hold something, 1-based, comments cut.
    lines: Vec<(usize, &'a str)>,
    next: usize,
    last_line: usize,
    /// The text's size, which bounds the triangles it may make.
    bytes: u64,
}

/// The view (`v`), as NFF gives it.
struct View {
    from: DVec3,
    at: DVec3,
    up: DVec3,
    angle: f64,
    width: i64,
    height: i64,
    line: usize,
}

impl<'a> Reader<'a> {
    fn error<T>(&self, line: usize, message: impl Into<String>) -> Result<T, SceneError> {
        Err(SceneError::Syntax {
            file: self.file.to_owned(),
            line,
            column: 1,
            message: message.into(),
        })
    }

    /// The next line that holds something: its number and its words.
    fn line(&mut self, what: &str) -> Result<(usize, Vec<&'a str>), SceneError> {
        match self.lines.get(self.next) {
            Some(&(n, l)) => {
                self.next += 1;
                Ok((n, l.split_whitespace().collect()))
            }
            None => self.error(
                self.last_line,
                format!("the file ends where {what} should be"),
            ),
        }
    }

    /// `words` as exactly `n` numbers (or, with `optional`, that many more).
    fn numbers(
        &self,
        line: usize,
        words: &[&str],
        n: usize,
        optional: usize,
        what: &str,
    ) -> Result<Vec<f64>, SceneError> {
        if words.len() != n && words.len() != n + optional {
            let want = if optional > 0 {
                format!("{n} or {}", n + optional)
            } else {
                n.to_string()
            };
            return self.error(
                line,
                format!("{what}: expected {want} numbers, got {}", words.len()),
            );
        }
        words
            .iter()
            .map(|w| match w.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(v),
                _ => self.error(
                    line,
                    format!(
                        "{what}: \"{}\" is not a finite number",
                        crate::printable::text(w)
                    ),
                ),
            })
            .collect()
    }

    fn triple(v: &[f64]) -> Triple {
        Triple([v[0], v[1], v[2]])
    }

    /// The `v` entity's six lines, after its `v`.
    fn view(&mut self, line: usize) -> Result<View, SceneError> {
        let mut field = |name: &str, n: usize| -> Result<Vec<f64>, SceneError> {
            let (at, words) = self.line(&format!("the view's \"{name}\""))?;
            if words.first() != Some(&name) {
                return self.error(
                    at,
                    format!(
                        "v: expected \"{name}\" here, got \"{}\"",
                        crate::printable::text(words.first().unwrap_or(&""))
                    ),
                );
            }
            self.numbers(at, &words[1..], n, 0, &format!("v {name}"))
        };
        let from = field("from", 3)?;
        let at = field("at", 3)?;
        let up = field("up", 3)?;
        let angle = field("angle", 1)?[0];
        let _hither = field("hither", 1)?;
        let resolution = field("resolution", 2)?;
        let whole = |v: f64| v.fract() == 0.0 && v.abs() < 1e9;
        if !resolution.iter().all(|&v| whole(v)) {
            return self.error(
                self.lines[self.next - 1].0,
                "v resolution: expected two integers",
            );
        }
        Ok(View {
            from: DVec3::from_slice(&from),
            at: DVec3::from_slice(&at),
            up: DVec3::from_slice(&up),
            angle,
            width: resolution[0] as i64,
            height: resolution[1] as i64,
            line,
        })
    }

    /// `count` vertex lines of a polygon (`p`) or a patch (`pp`, with normals).
    fn vertices(
        &mut self,
        count: usize,
        normals: bool,
        what: &str,
    ) -> Result<Vec<(DVec3, DVec3)>, SceneError> {
        let n = if normals { 6 } else { 3 };
        (0..count)
            .map(|i| {
                let (at, words) = self.line(&format!("{what}'s vertex {}", i + 1))?;
                let v = self.numbers(at, &words, n, 0, &format!("{what} vertex {}", i + 1))?;
                let normal = if normals {
                    DVec3::from_slice(&v[3..])
                } else {
                    DVec3::ZERO
                };
                Ok((DVec3::from_slice(&v[..3]), normal))
            })
            .collect()
    }

    fn scene(&mut self) -> Result<Nff, SceneError> {
        let mut lines = Lines::default();
        let mut view: Option<View> = None;
        let mut background = Triple::default();
        let mut lights: Vec<(usize, Vec<f64>)> = Vec::new();
        let mut materials: BTreeMap<String, MaterialFile> = BTreeMap::new();
        // Each distinct `f` once: its values' bits, and its name.
        let mut names: HashMap<[u64; 8], String> = HashMap::new();
        let mut material: Option<String> = None;
        let mut spheres = Vec::new();
        let mut triangles = Vec::new();
        let mut cylinders = Vec::new();
        // Triangles made so far, and how many the file may make.
        let mut made = 0u64;
        let allowed = triangles::allowed(self.bytes);

        while self.next < self.lines.len() {
            let (line, words) = self.line("an entity")?;
            let (keyword, rest) = (words[0], &words[1..]);
            let needs_material = |m: &Option<String>| -> Result<String, SceneError> {
                m.clone().map_or_else(
                    || {
                        self.error(
                            line,
                            format!("{keyword}: an object before any \"f\" gives it a material"),
                        )
                    },
                    Ok,
                )
            };
            match keyword {
                "v" => {
                    self.numbers(line, rest, 0, 0, "v")?;
                    if view.is_some() {
                        return self.error(line, "v: a second view");
                    }
                    view = Some(self.view(line)?);
                }
                "b" => background = Self::triple(&self.numbers(line, rest, 3, 0, "b")?),
                "l" => {
                    lines.note_row("lights", line);
                    lights.push((line, self.numbers(line, rest, 3, 3, "l")?));
                }
                "f" => {
                    let v = self.numbers(line, rest, 8, 0, "f")?;
                    let key: [u64; 8] = std::array::from_fn(|i| v[i].to_bits());
                    let next = format!("f{}", names.len() + 1);
                    let name = names.entry(key).or_insert(next).clone();
                    lines.note(format!("materials.{name}"), line);
                    materials
                        .entry(name.clone())
                        .or_insert_with(|| nff_material(&v));
                    material = Some(name);
                }
                "s" => {
                    let m = needs_material(&material)?;
                    let v = self.numbers(line, rest, 4, 0, "s")?;
                    lines.note_row("spheres", line);
                    // A negative radius shows the inside only: glint's
                    // surfaces show both sides (docs/scene-format.md, NFF).
                    spheres.push(SphereFile {
                        center: Self::triple(&v),
                        radius: v[3].abs(),
                        material: m,
                    });
                }
                "c" => {
                    let m = needs_material(&material)?;
                    // NFF.TXT puts the base and the apex on lines of their
                    // own; the SPD's programs write all eight on the `c` line.
                    let (base, apex) = if rest.is_empty() {
                        let (at, words) = self.line("the cone's base")?;
                        let base = self.numbers(at, &words, 4, 0, "c base")?;
                        let (at, words) = self.line("the cone's apex")?;
                        (base, self.numbers(at, &words, 4, 0, "c apex")?)
                    } else {
                        let v = self.numbers(line, rest, 8, 0, "c")?;
                        (v[..4].to_vec(), v[4..].to_vec())
                    };
                    lines.note_row("cylinders", line);
                    cylinders.push(CylinderFile {
                        base: Self::triple(&base),
                        base_radius: base[3].abs(),
                        apex: Self::triple(&apex),
                        apex_radius: apex[3].abs(),
                        material: m,
                    });
                }
                "p" | "pp" => {
                    let m = needs_material(&material)?;
                    let count = self.numbers(line, rest, 1, 0, keyword)?[0];
                    if count.fract() != 0.0 || !(3.0..=1e6).contains(&count) {
                        return self.error(
                            line,
                            format!("{keyword}: the vertex count must be an integer of at least 3, got {count}"),
                        );
                    }
                    made += count as u64 - 2;
                    if made > allowed {
                        let past = triangles::Past {
                            line,
                            triangles: made,
                        };
                        return self.error(line, triangles::message(past, self.bytes));
                    }
                    let smooth = keyword == "pp";
                    let corners = self.vertices(count as usize, smooth, keyword)?;
                    for tri in fan(&corners) {
                        lines.note_row("triangles", line);
                        triangles.push(TriangleFile {
                            vertices: tri.map(|(p, _)| Triple(p.to_array())),
                            normals: smooth.then(|| tri.map(|(_, n)| Triple(n.to_array()))),
                            uvs: None,
                            material: m.clone(),
                        });
                    }
                }
                _ => {
                    return self.error(
                        line,
                        format!(
                            "unknown entity \"{}\" (NFF has v, b, l, f, c, s, p, pp and #)",
                            crate::printable::text(keyword)
                        ),
                    )
                }
            }
        }

        let Some(view) = view else {
            return self.error(1, "no view: NFF needs a \"v\" entity");
        };
        lines.note("camera".into(), view.line);
        lines.note("image".into(), view.line);
        let intensity = 1.0 / (lights.len().max(1) as f64).sqrt();
        let lights = lights
            .iter()
            .map(|(_, l)| {
                let colour = if l.len() == 6 {
                    Self::triple(&l[3..])
                } else {
                    Triple([intensity; 3])
                };
                LightFile {
                    ambient: Triple::default(),
                    diffuse: colour,
                    specular: colour,
                    ..LightFile::new(
                        Point::NAME,
                        &PointFile {
                            position: Some(Self::triple(l)),
                            attenuation: None,
                        },
                    )
                }
            })
            .collect();
        if !(view.angle > 0.0 && view.angle < 180.0) || view.width < 2 || view.height < 2 {
            return self.error(
                view.line,
                format!(
                    "v: the angle must be in (0, 180) degrees and the resolution at least 2×2, got {} and {}×{}",
                    crate::printable::number(view.angle),
                    view.width,
                    view.height
                ),
            );
        }
        let camera = camera(&view);
        let scene = SceneFile {
            image: ImageFile {
                width: view.width,
                height: view.height,
                samples: 1,
                srgb: true,
                sampling: Sampling::Corners,
                threshold: None,
                max_level: None,
                thresholds: None,
                range: None,
                max_samples: None,
                compare_trees: None,
            },
            render: RenderFile {
                max_depth: SPD_DEPTH,
                shadows: true,
                background,
                spd_rays: true,
            },
            camera,
            materials,
            textures: Default::default(),
            spheres,
            triangles,
            cylinders,
            planes: Vec::new(),
            meshes: Vec::new(),
            lights,
        };
        Ok(Nff { scene, lines })
    }
}

/// NFF's `f r g b Kd Ks Shine T ior` as a material: diffuse Kd·colour, a
/// white highlight of Ks with exponent Shine, reflectivity Ks, transmittance
/// T, and no ambient term (NFF has none). The index of refraction of a
/// surface that transmits nothing is never used, and the SPD writes 0 there:
/// it becomes 1.
fn nff_material(v: &[f64]) -> MaterialFile {
    let (kd, ks) = (v[3], v[4]);
    let ior = if v[6] == 0.0 { 1.0 } else { v[7] };
    MaterialFile {
        ambient: None,
        diffuse: Triple([v[0] * kd, v[1] * kd, v[2] * kd]),
        specular: Triple([ks; 3]),
        shininess: v[5],
        reflectivity: ks,
        transmittance: v[6],
        ior,
        texture: None,
        ambient_texture: None,
    }
}

/// The convex polygon `corners` as a fan from its first corner, leaving out
/// the triangles without area (collinear corners).
fn fan(corners: &[(DVec3, DVec3)]) -> Vec<[(DVec3, DVec3); 3]> {
    (1..corners.len() - 1)
        .map(|i| [corners[0], corners[i], corners[i + 1]])
        .filter(|[a, b, c]| Triangle::new([a.0, b.0, c.0], None, 0).is_some())
        .collect()
}

/// NFF's view as glint's look-at camera (form (b), which the checks turn
/// into a screen as for any TOML scene). NFF's `angle` spans the centres of
/// the top and bottom rows of pixels; a pixel centre's screen coordinate is
/// 2 (y + 0.5) / h − 1, so those centres sit at ±(1 − 1/h) of the
/// half-height, and `vfov` (edge to edge) is wider by that factor.
fn camera(v: &View) -> CameraFile {
    let half = (v.angle.to_radians() / 2.0).tan() / (1.0 - 1.0 / v.height as f64);
    let triple = |p: DVec3| Some(Triple(p.to_array()));
    CameraFile {
        eye: Triple(v.from.to_array()),
        screen_center: None,
        screen_right: None,
        screen_up: None,
        look_at: triple(v.at),
        up: triple(v.up),
        vfov: Some(2.0 * half.atan().to_degrees()),
    }
}

#[cfg(test)]
mod tests;
