//! Every textured primitive has what its textures' patterns read of a
//! surface (`Needs`): its own coordinates, or uv coordinates.

use super::{Needs, Texture, PATTERNS};
use crate::input::error::SceneError;
use crate::input::field::{root, Validator};
use crate::prim::{KindInfo, Prims, KINDS};
use crate::scene::Material;

/// What `needs` asks of a surface, the kinds that can have it, and what a
/// kind of the table says of it.
fn wanted(needs: Needs) -> (&'static str, fn(&KindInfo) -> bool) {
    match needs {
        Needs::Frame => ("a surface's own coordinates", |k| k.frame),
        Needs::Uv => ("uv coordinates", |k| k.uv),
        Needs::Nothing => ("nothing", |_| true),
    }
}

impl Validator<'_> {
    /// Refuses a texture on a primitive without what its pattern reads (a
    /// frame: spheres and cylinders lack one; uvs: cylinders, triangles
    /// without uvs and meshes without vt), naming the primitive, or the mesh
    /// (`mesh_starts`: where each mesh's triangles start), its material and
    /// its texture (of `names`).
    pub(crate) fn textures_fit(
        &self,
        prims: &Prims,
        materials: &[Material],
        textures: &[Texture],
        names: &[String],
        mesh_starts: &[usize],
    ) -> Result<(), SceneError> {
        let needs = |m: &Material| {
            let of = |n: Needs| {
                [m.texture, m.ambient_texture]
                    .into_iter()
                    .flatten()
                    .find(|t| textures[*t as usize].pattern.needs() == n)
            };
            [of(Needs::Frame), of(Needs::Uv)]
        };
        let lacking = prims.first_lacking(|m| needs(&materials[m as usize]).map(|t| t.is_some()));
        let Some((key, i, m)) = lacking else {
            return Ok(());
        };
        let m = &materials[m as usize];
        let kind = KINDS
            .iter()
            .find(|k| k.key == key)
            .expect("a kind of the table");
        // The frame where the kind has none, else the uvs this primitive lacks.
        let t = match needs(m) {
            [Some(frame), _] if !kind.frame => frame,
            [_, Some(uv)] => uv,
            _ => unreachable!("first_lacking found what the primitive lacks"),
        };
        let pattern = textures[t as usize].pattern.info();
        let (material, texture) = (
            crate::printable::text(&m.name),
            crate::printable::text(&names[t as usize]),
        );
        let (needed, has) = wanted(pattern.needs);
        let anywhere = PATTERNS
            .iter()
            .find(|p| p.needs == Needs::Nothing)
            .expect("a pattern for any surface");
        let what = format!(
            "material \"{material}\" has the {} texture \"{texture}\", which needs {needed}",
            pattern.name
        );
        if !has(kind) {
            let having: Vec<&str> = KINDS.iter().filter(|k| has(k)).map(|k| k.key).collect();
            return self.err(
                &root().key(key).index(i).key("material"),
                format!(
                    "{what} ({} can have them, {key} do not): use a pattern = \"{}\" texture",
                    having.join(", "),
                    anywhere.name
                ),
            );
        }
        // A triangle without uvs: of the file's [[triangles]] or of a mesh.
        match mesh_starts.iter().rposition(|start| *start <= i) {
            Some(mesh) => self.err(
                &root().key("meshes").index(mesh).key("file"),
                format!(
                    "{what}, and face {} of this OBJ has none: give every corner of its faces \
                     a texture coordinate (vt)",
                    i - mesh_starts[mesh]
                ),
            ),
            None => self.err(
                &root().key(key).index(i).key("material"),
                format!("{what}: give this triangle uvs = [[u, v], [u, v], [u, v]]"),
            ),
        }
    }
}
