//! Meshes: a scene's `[[meshes]]` read from Wavefront OBJ files (with the
//! tobj crate) into triangles. Not a kind of its own: once loaded, a mesh's
//! faces are triangles like any other (docs/scene-format.md, Meshes).

use std::io::BufReader;
use std::path::Path;

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::triangle::Triangle;
use crate::input::error::SceneError;
use crate::input::field::{unit_vector, At, Triple};

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MeshFile {
    /// The OBJ file, relative to the scene file.
    pub file: String,
    pub material: String,
    /// Uniform scale, applied before `translate`: p·scale + translate.
    #[serde(default = "one")]
    pub scale: f64,
    #[serde(default)]
    pub translate: Option<Triple>,
}

fn one() -> f64 {
    1.0
}

/// Reads the mesh's OBJ file (relative to `dir`, the scene file's folder)
/// and appends its faces to `out` as triangles: fan-triangulated polygons, with the
/// file's vertex normals where every corner of a face has one, else flat.
/// Faces without area are left out, as a mesh's slivers often are.
pub fn load(f: &MeshFile, dir: &Path, at: &At, out: &mut Vec<Triangle>) -> Result<(), SceneError> {
    let material = at.material("material", &f.material)?;
    let scale = at.length("scale", f.scale)?;
    let translate = match f.translate {
        Some(t) => at.position("translate", t)?,
        None => DVec3::ZERO,
    };
    let path = dir.join(&f.file);
    let shown = crate::printable::path(&path);
    let file = crate::input::open(&path, crate::input::Kind::Mesh)
        .or_else(|e| at.invalid("file", format!("cannot read {shown}: {e}")))?;
    let options = tobj::LoadOptions {
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    // Materials are the scene's: the OBJ's own (mtllib) are not read.
    let (models, _) = tobj::load_obj_buf(&mut BufReader::new(file), &options, |_| {
        Ok(Default::default())
    })
    .or_else(|e| at.invalid("file", format!("{shown}: not a valid OBJ file: {e}")))?;

    // Exactly as many as there are faces (at most): a Vec grown by doubling
    // would hold up to twice the triangles' 208 bytes each.
    let faces: usize = models.iter().map(|m| m.mesh.indices.len() / 3).sum();
    out.reserve_exact(faces);
    if models.iter().all(|m| m.mesh.indices.is_empty()) {
        return at.invalid(
            "file",
            format!("{shown}: has no faces (not an OBJ model, or an empty one)"),
        );
    }
    for model in &models {
        let m = &model.mesh;
        let point = |i: u32| {
            let i = 3 * i as usize;
            DVec3::new(m.positions[i], m.positions[i + 1], m.positions[i + 2]) * scale + translate
        };
        let normal = |i: u32| {
            let i = 3 * i as usize;
            DVec3::new(m.normals[i], m.normals[i + 1], m.normals[i + 2])
        };
        let smooth = m.normal_indices.len() == m.indices.len();
        for (face, corners) in m.indices.chunks_exact(3).enumerate() {
            let vertices = [point(corners[0]), point(corners[1]), point(corners[2])];
            if let Some(bad) = vertices.iter().find(|v| {
                !v.is_finite() || v.abs().max_element() > crate::input::field::MAX_COORDINATE
            }) {
                return at.invalid(
                    "file",
                    format!(
                        "{shown}: object \"{}\", face {face}: vertex {bad} is not finite \
                         or beyond ±{:e} once scaled and translated",
                        crate::printable::text(&model.name),
                        crate::input::field::MAX_COORDINATE
                    ),
                );
            }
            let normals = if smooth {
                let n = &m.normal_indices[3 * face..3 * face + 3];
                // A zero or non-finite vertex normal cannot be interpolated:
                // that face is shaded flat.
                match [n[0], n[1], n[2]].map(|i| unit_vector(normal(i))) {
                    [Some(a), Some(b), Some(c)] => Some([a, b, c]),
                    _ => None,
                }
            } else {
                None
            };
            out.extend(Triangle::new(vertices, normals, material));
        }
    }
    Ok(())
}
