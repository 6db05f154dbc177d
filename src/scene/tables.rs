//! A scene's light buffers and the eye's tiles (`accel::tables`): what the
//! tables see of its lights and camera. The light buffers belong to the
//! scene, the tiles to its view; both renderers build them here, so that
//! they read the same lists.

use glam::DVec3;

use super::Scene;
use crate::accel::bvh::Bvh;
use crate::accel::tables::{self, CameraSpec, LightSpec, Tables};
use crate::accel::{prim_boxes, tables_budget};

impl Scene {
    /// The tables over `tree` (built from the primitives translated by
    /// `-origin`), in the same coordinates: a light buffer for each light
    /// that casts shadow rays (none where the scene has no shadows), and the
    /// eye's tiles over `width`×`height`
    /// pixels; None where none fits the budget (`accel::tables_budget`).
    pub(crate) fn tables(
        &self,
        tree: &Bvh,
        origin: DVec3,
        (width, height): (u32, u32),
    ) -> Option<Tables> {
        let lights: Vec<LightSpec> = self
            .lights
            .iter()
            .map(|l| LightSpec {
                position: l.position().map(|p| p - origin),
                direction: l.direction,
                casts: self.shadows && l.has_direct_term(),
            })
            .collect();
        let cam = &self.camera;
        let camera = CameraSpec {
            eye: cam.eye - origin,
            to_screen: cam.screen_center - cam.eye,
            right: cam.screen_right,
            up: cam.screen_up,
            width,
            height,
        };
        tables::build(
            tree,
            &prim_boxes(&self.prims, origin),
            &self.prims.relative_hulls(origin),
            &lights,
            Some(&camera),
            tables_budget(&self.prims, tree),
        )
    }
}

#[cfg(test)]
#[path = "tables_tests.rs"]
mod tests;
