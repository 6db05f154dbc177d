//! A sample's ray tree as one renderer traced it: its events
//! (`crate::base::record`) gathered ray by ray, under the names `--json`
//! gives them.

use glam::DVec3;
use serde::Serialize;

use crate::base::count::RayType;
use crate::base::record::{Event, Prim};
use crate::prim::KINDS;

/// A primitive as an explanation names it: its kind and its index among
/// its kind in the scene file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Primitive {
    /// Its kind: `sphere`, `triangle`, ...
    pub kind: &'static str,
    /// Its index among its kind, in the scene file's order.
    pub index: u32,
    /// Its kind's place in the table of kinds, and its index.
    #[serde(skip)]
    pub(crate) id: Prim,
}

impl Primitive {
    pub(crate) fn of(p: Prim) -> Self {
        Self {
            kind: KINDS.get(p.0 as usize).map_or("primitive", |k| k.name),
            index: p.1,
            id: p,
        }
    }
}

impl std::fmt::Display for Primitive {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} {}", self.kind, self.index)
    }
}

/// Where a ray met its primitive.
#[derive(Debug, Clone, Serialize)]
pub struct Hit {
    /// The primitive met.
    pub primitive: Primitive,
    /// How far along the ray.
    pub distance: f64,
    /// The hit point.
    pub point: [f64; 3],
    /// The outward geometric normal.
    pub normal: [f64; 3],
    /// The normal shading uses, on the outward side.
    pub shading_normal: [f64; 3],
    /// Where the scene's image textures read uv coordinates.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub uv: Option<[f64; 2]>,
    /// The index of its material.
    pub material: u32,
}

/// What blocked a shadow ray: the nearest blocker.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Blocker {
    /// The primitive in the way.
    pub primitive: Primitive,
    /// How far along the shadow ray.
    pub distance: f64,
}

/// A shadow ray towards a light.
#[derive(Debug, Clone, Serialize)]
pub struct Shadow {
    /// Where it starts: the hit point.
    pub origin: [f64; 3],
    /// Towards the light, unit.
    pub direction: [f64; 3],
    /// How far the light is along it.
    pub light_distance: f64,
    /// Whether anything lies between.
    pub blocked: bool,
    /// The nearest thing that does.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub blocker: Option<Blocker>,
}

/// One light at a hit.
#[derive(Debug, Clone, Serialize)]
pub struct Light {
    /// Its index in the scene's lights.
    pub light: u32,
    /// N·L: the light is in front of the surface where it is above 0.
    pub n_dot_l: f64,
    /// The cone's factor (1 but for a spot light).
    pub cone: f64,
    /// The shadow ray, where one was cast.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shadow_ray: Option<Shadow>,
    /// Whether the diffuse and specular terms count.
    pub lit: bool,
    /// Its ambient term, times attenuation and cone.
    pub ambient: [f64; 3],
    /// Its diffuse term (0 where not lit), times attenuation and cone.
    pub diffuse: [f64; 3],
    /// Its specular term (0 where not lit), times attenuation and cone.
    pub specular: [f64; 3],
}

/// One ray of the tree and what it met.
#[derive(Debug, Clone, Serialize)]
pub struct TreeRay {
    /// eye, reflect or refract.
    #[serde(rename = "type")]
    pub kind: &'static str,
    /// 1 for the eye ray, one more a bounce.
    pub depth: u32,
    /// Where it starts.
    pub origin: [f64; 3],
    /// Its unit direction.
    pub direction: [f64; 3],
    /// The product of the reflectivities and transmittances on its path.
    pub weight: f64,
    /// The surface it leaves.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub leaves: Option<Primitive>,
    /// None where it met nothing.
    pub hit: Option<Hit>,
    /// Each light at the hit, in the scene's order.
    pub lights: Vec<Light>,
    /// The sum of the lights' terms at the hit (the background where it
    /// met nothing).
    pub local: [f64; 3],
    /// The reflection ray's weight at the hit (with any total internal
    /// reflection) and the refraction ray's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reflectivity: Option<f64>,
    /// The refraction ray's weight at the hit.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub transmittance: Option<f64>,
    /// What this ray adds to the sample: its local colour times its weight.
    pub color: [f64; 3],
}

/// One renderer's tree of one sample.
#[derive(Debug, Clone, Serialize)]
pub struct Tree {
    /// "gpu f32", "cpu f32", "cpu f64", or a driver's name.
    pub renderer: String,
    /// The rays in the order they were traced.
    pub rays: Vec<TreeRay>,
    /// The sample's colour.
    pub color: [f64; 3],
}

fn arr(v: DVec3) -> [f64; 3] {
    v.to_array()
}

impl Tree {
    /// The tree with every position moved by `-eye`: camera-relative, as
    /// the other trees are, where the renderer traced the scene as written
    /// (the GPU's `--intersect naive`).
    pub fn relative_to(mut self, eye: DVec3) -> Self {
        let shift = |p: &mut [f64; 3]| *p = (DVec3::from_array(*p) - eye).to_array();
        for ray in &mut self.rays {
            shift(&mut ray.origin);
            if let Some(h) = &mut ray.hit {
                shift(&mut h.point);
            }
            for l in &mut ray.lights {
                if let Some(s) = &mut l.shadow_ray {
                    shift(&mut s.origin);
                }
            }
        }
        self
    }

    /// The tree of `events`, one sample's, from its first ray to its end.
    pub fn of(renderer: &str, events: &[Event]) -> Result<Self, String> {
        let mut rays: Vec<TreeRay> = Vec::new();
        let mut shadow: Option<Shadow> = None;
        let mut color = None;
        for e in events {
            if let Event::Ray {
                kind,
                depth,
                from,
                origin,
                dir,
                weight,
            } = e
            {
                rays.push(TreeRay {
                    kind: match kind {
                        RayType::Eye => "eye",
                        RayType::Reflect => "reflect",
                        _ => "refract",
                    },
                    depth: *depth,
                    origin: arr(*origin),
                    direction: arr(*dir),
                    weight: *weight,
                    leaves: from.map(Primitive::of),
                    hit: None,
                    lights: Vec::new(),
                    local: [0.0; 3],
                    reflectivity: None,
                    transmittance: None,
                    color: [0.0; 3],
                });
                continue;
            }
            if let Event::End { color: c } = e {
                color = Some(arr(*c));
                continue;
            }
            let Some(ray) = rays.last_mut() else {
                return Err("the record has an event before its first ray".to_owned());
            };
            match e {
                Event::Miss { color: c } => {
                    // The background: what the ray adds, over its weight.
                    if ray.weight != 0.0 {
                        ray.local = arr(*c / ray.weight);
                    }
                    ray.color = arr(*c);
                }
                Event::Hit {
                    prim,
                    material,
                    t,
                    point,
                    normal,
                    shading,
                    uv,
                } => {
                    ray.hit = Some(Hit {
                        primitive: Primitive::of(*prim),
                        distance: *t,
                        point: arr(*point),
                        normal: arr(*normal),
                        shading_normal: arr(*shading),
                        uv: uv.map(|u| u.to_array()),
                        material: *material,
                    })
                }
                Event::Shadow {
                    origin,
                    dir,
                    dist,
                    blocked,
                    blocker,
                    ..
                } => {
                    shadow = Some(Shadow {
                        origin: arr(*origin),
                        direction: arr(*dir),
                        light_distance: *dist,
                        blocked: *blocked,
                        blocker: blocker.map(|(p, t)| Blocker {
                            primitive: Primitive::of(p),
                            distance: t,
                        }),
                    })
                }
                Event::Light {
                    light,
                    n_dot_l,
                    cone,
                    lit,
                    ambient,
                    diffuse,
                    specular,
                } => ray.lights.push(Light {
                    light: *light,
                    n_dot_l: *n_dot_l,
                    cone: *cone,
                    shadow_ray: shadow.take(),
                    lit: *lit,
                    ambient: arr(*ambient),
                    diffuse: arr(*diffuse),
                    specular: arr(*specular),
                }),
                Event::Local { color: c } => {
                    ray.local = arr(*c);
                    ray.color = arr(*c * ray.weight);
                }
                Event::Branch { kr, kt, .. } => {
                    ray.reflectivity = Some(*kr);
                    ray.transmittance = Some(*kt);
                }
                Event::Ray { .. } | Event::End { .. } => unreachable!("taken above"),
            }
        }
        let color = color.ok_or("the record ends before its sample does")?;
        if rays.is_empty() {
            return Err("the record has no ray".to_owned());
        }
        Ok(Self {
            renderer: renderer.to_owned(),
            rays,
            color,
        })
    }
}
