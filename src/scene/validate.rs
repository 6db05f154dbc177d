//! Checks a parsed [`SceneFile`] against docs/scene-format.md and resolves it into a
//! [`Scene`]. Every error carries the key path, which [`Located`] turns into
//! a line and column of the file.

use std::path::{Path, PathBuf};

use glam::DVec3;

use super::contrast::ContrastKeys;
use super::file::SceneFile;
use super::images::Images;
use super::texture::Texture;
use super::{Sampling, Scene, SceneError, MAX_DEPTH, MAX_SAMPLES, MAX_SIZE};
use crate::input::field::MAX_COORDINATE;
use crate::input::field::{root, At, Validator};
use crate::input::locate::Locate;
use crate::prim::mesh::Cache as MeshCache;
use crate::prim::Prims;

/// Command-line values that replace the scene's own.
#[derive(Debug, Clone, Copy, Default)]
pub struct Overrides {
    /// The image's width (`--width`).
    pub width: Option<u32>,
    /// The image's height (`--height`).
    pub height: Option<u32>,
    /// Samples a side of each pixel (`--samples`).
    pub samples: Option<u32>,
    /// The ray tree's depth (`--max-depth`).
    pub max_depth: Option<u32>,
}

/// Validates a scene file read from any format: `located` names where
/// each key path was written.
pub(super) fn resolve(
    raw: SceneFile,
    file: &Path,
    located: &dyn Locate,
    overrides: &Overrides,
    meshes: Option<&MeshCache>,
) -> Result<Scene> {
    let check = Validator { file, located };
    let mut scene = check.scene(raw, overrides, meshes)?;
    apply_overrides(&mut scene, overrides)?;
    check.brightness(&scene)?;
    check.scale(&scene)?;
    check.counts(&scene)?;
    Ok(scene)
}

/// The first bounded kind of which `scene` has more than `max`, and its count.
fn over_count(scene: &Scene, max: usize) -> Option<(&'static crate::prim::KindInfo, usize)> {
    crate::prim::KINDS
        .iter()
        .zip(scene.prims.counts())
        .find(|(kind, n)| kind.bounded && *n > max)
}

/// The brightest pixel value a scene may be able to make: a pixel sums up
/// to 256 samples before it divides, and every sum stays inside f32.
pub const MAX_BRIGHTNESS: f64 = 1e36;

type Result<T> = std::result::Result<T, SceneError>;

/// The least distance from the eye that some object of a scene must reach:
/// 1/`MAX_COORDINATE`, so that its square (1e-36) is a normal f32.
pub const MIN_REACH: f64 = 1.0 / MAX_COORDINATE;

impl Validator<'_> {
    /// Refuses a scene whose objects all lie within `MIN_REACH` of the eye:
    /// camera-relative, its squared lengths would underflow f32, and the
    /// GPU's f32 render would be flat ambient without a word (a valid scene
    /// scaled by 1e-25). Refuses more primitives of one kind than the scene
    /// management can address (`accel::bvh::MAX_PRIMS`, 2^24), before any
    /// is built.
    fn counts(&self, scene: &Scene) -> Result<()> {
        let max = crate::accel::bvh::MAX_PRIMS;
        match over_count(scene, max) {
            Some((kind, n)) => self.err(
                &root().key(kind.key),
                format!(
                    "{n} {}s, past the {max} (2^24) of one kind that glint addresses: \
                     split the scene",
                    kind.name
                ),
            ),
            None => Ok(()),
        }
    }

    fn scale(&self, scene: &Scene) -> Result<()> {
        let reach = scene.prims.reach_from(scene.camera.eye);
        if reach > 0.0 && reach < MIN_REACH {
            return self.err(
                &root().key("camera").key("eye"),
                format!(
                    "every object lies within {reach:.1e} of the eye, under the {MIN_REACH:e} that \
                     f32 carries (squared lengths would underflow): scale the scene up"
                ),
            );
        }
        Ok(())
    }

    /// Refuses a scene whose brightest possible pixel
    /// ([`Scene::brightest_pixel`]) passes `MAX_BRIGHTNESS`.
    fn brightness(&self, scene: &Scene) -> Result<()> {
        let max = |v: DVec3| v.max_element();
        let per_light = scene.light_peaks();
        let bound = scene.brightest_pixel();
        if bound.is_finite() && bound <= MAX_BRIGHTNESS {
            return Ok(());
        }
        let (worst, _) = per_light
            .iter()
            .enumerate()
            .fold(
                (None, 0.0f64),
                |(w, m), (i, b)| if *b > m { (Some(i), *b) } else { (w, m) },
            );
        // A texture far brighter than every material colour (a texel of
        // 1e38) is named itself, through the material that takes it, rather
        // than the light that lights it.
        let textured = scene
            .materials
            .iter()
            .filter_map(|m| {
                let peak = [m.texture, m.ambient_texture]
                    .into_iter()
                    .flatten()
                    .map(|t| max(scene.textures[t as usize].brightest()))
                    .fold(0.0f64, f64::max);
                (peak > 1.0 && peak > max(m.diffuse).max(max(m.ambient))).then_some((m, peak))
            })
            .max_by(|a, b| a.1.total_cmp(&b.1));
        let path = match (textured, worst) {
            (Some((m, peak)), _) if bound / peak <= MAX_BRIGHTNESS => {
                return self.err(
                    &root().key("materials").key(&m.name),
                    format!(
                        "its texture's brightest value, {peak:.3e}, makes the brightest pixel this \
                         scene can make up to {bound:.3e}, past {MAX_BRIGHTNESS:e}: it could \
                         overflow f32; scale the texture's colours down"
                    ),
                );
            }
            (_, Some(i)) => root().key("lights").index(i),
            (_, None) => root().key("render").key("background"),
        };
        self.err(
            &path,
            format!(
                "the brightest pixel this scene can make, up to {bound:e}, passes {MAX_BRIGHTNESS:e} \
                 and could overflow f32: lower the light and material colours, or raise the \
                 attenuation's constant term"
            ),
        )
    }

    fn scene(
        &self,
        mut raw: SceneFile,
        overrides: &Overrides,
        meshes: Option<&MeshCache>,
    ) -> Result<Scene> {
        let image = root().key("image");
        let render = root().key("render");
        let width = self.int_in(&image.key("width"), raw.image.width, 1, MAX_SIZE)?;
        let height = self.int_in(&image.key("height"), raw.image.height, 1, MAX_SIZE)?;
        let samples = self.int_in(&image.key("samples"), raw.image.samples, 1, MAX_SAMPLES)?;
        let sampling = raw.image.sampling;
        if sampling == Sampling::Corners && samples != 1 {
            return self.err(
                &image.key("sampling"),
                format!("\"corners\" traces one ray per pixel corner: it takes samples = 1, got {samples}"),
            );
        }
        let keys = (raw.image.sampling, raw.image.threshold, raw.image.max_level);
        let adaptive = self.adaptive(&image, keys, samples)?;
        let im = &raw.image;
        let keys = ContrastKeys {
            thresholds: im.thresholds,
            range: im.range,
            max_samples: im.max_samples,
            compare_trees: im.compare_trees,
        };
        let contrast = self.contrast(&image, sampling == Sampling::Contrast, keys, samples)?;
        let max_depth =
            self.int_in(&render.key("max_depth"), raw.render.max_depth, 1, MAX_DEPTH)?;
        let background = self.colour(&render.key("background"), raw.render.background)?;

        let prim_files = raw.take_prims();
        let dir = self.file.parent().unwrap_or(Path::new("."));
        let mut images = Images::default();
        let names: Vec<&String> = raw.materials.keys().collect();
        let texture_names: Vec<&String> = raw.textures.keys().collect();
        let mut textures = raw
            .textures
            .iter()
            .map(|(name, t)| self.texture(&root().key("textures").key(name), t, dir, &mut images))
            .collect::<Result<Vec<_>>>()?;
        let mut texture_names: Vec<String> = texture_names.into_iter().cloned().collect();
        let mut materials = raw
            .materials
            .iter()
            .map(|(name, m)| {
                self.material(&root().key("materials").key(name), name, m, &texture_names)
            })
            .collect::<Result<Vec<_>>>()?;
        let mut prims = Prims::check(&prim_files, |key, i| At {
            check: self,
            names: &names,
            path: root().key(key).index(i),
        })?;
        // A mesh's triangles follow the file's [[triangles]], mesh by mesh.
        let mut input_files: Vec<_> = raw.meshes.iter().map(|m| dir.join(&m.file)).collect();
        let mut mesh_starts = Vec::new();
        for (i, mesh) in raw.meshes.iter().enumerate() {
            let at = At {
                check: self,
                names: &names,
                path: root().key("meshes").index(i),
            };
            mesh_starts.push(prims.triangles.len());
            // Straight into the scene's list: a list of the mesh's own, then
            // copied, would hold every triangle twice.
            let first = materials.len() as u32;
            let loaded =
                crate::prim::mesh::load(mesh, dir, &at, first, &mut prims.triangles, meshes)?;
            for m in &loaded.materials {
                let mut material = super::material::from_mtl(m);
                // An MTL map's texels are multiplied by its colour (Kd, Ka).
                let mut map = |file: &Option<PathBuf>, tint: DVec3, what: &str| {
                    let Some(file) = file else {
                        return Ok(None);
                    };
                    let texels = images
                        .texels(file)
                        .or_else(|e| at.invalid("file", format!("{}: {what}: {e}", m.name)))?;
                    textures.push(Texture {
                        colors: [tint; 2],
                        ..Texture::image(texels)
                    });
                    texture_names.push(format!("{what} of {}", m.name));
                    Ok::<_, SceneError>(Some(textures.len() as u32 - 1))
                };
                material.texture = map(&m.map_kd, material.diffuse, "map_Kd")?;
                material.ambient_texture = map(&m.map_ka, material.ambient, "map_Ka")?;
                materials.push(material);
            }
            input_files.extend(loaded.files);
        }
        input_files.extend(images.files);

        self.textures_fit(&prims, &materials, &textures, &texture_names, &mesh_starts)?;

        let lights = raw
            .lights
            .iter()
            .enumerate()
            .map(|(i, l)| self.light(&root().key("lights").index(i), l))
            .collect::<Result<Vec<_>>>()?;

        let final_width = overrides.width.unwrap_or(width);
        let final_height = overrides.height.unwrap_or(height);
        let aspect = f64::from(final_width) / f64::from(final_height);
        let camera = self.camera(&root().key("camera"), &raw.camera, aspect)?;

        Ok(Scene {
            width,
            height,
            samples,
            sampling,
            adaptive,
            contrast,
            srgb: raw.image.srgb,
            max_depth,
            shadows: raw.render.shadows,
            spd_rays: raw.render.spd_rays,
            background,
            camera,
            materials,
            textures,
            prims,
            lights,
            input_files,
            texels: std::sync::Arc::new(images.texels),
            replay: None,
        })
    }
}

fn apply_overrides(scene: &mut Scene, o: &Overrides) -> Result<()> {
    let check = |flag: &'static str, v: Option<u32>, lo: u32, hi: u32| -> Result<Option<u32>> {
        match v {
            Some(v) if v < lo || v > hi => Err(SceneError::Override {
                flag,
                message: format!("must be in {lo}..={hi}, got {v}"),
            }),
            v => Ok(v),
        }
    };
    if let Some(w) = check("--width", o.width, 1, MAX_SIZE)? {
        scene.width = w;
    }
    if let Some(h) = check("--height", o.height, 1, MAX_SIZE)? {
        scene.height = h;
    }
    if let Some(s) = check("--samples", o.samples, 1, MAX_SAMPLES)? {
        scene.samples = s;
        // A grid of samples is the centres sampling's (docs/scene-format.md, Rays).
        scene.sampling = Sampling::Centers;
        scene.adaptive = None;
        scene.contrast = None;
    }
    if let Some(d) = check("--max-depth", o.max_depth, 1, MAX_DEPTH)? {
        scene.max_depth = d;
    }
    Ok(())
}

#[cfg(test)]
#[path = "validate_tests.rs"]
mod tests;
