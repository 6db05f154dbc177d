//! A prepared scene taking its scene's new values in place (`Scene.params`
//! in the Python module): its arrays laid out again and copied over the
//! ones on the device, its BVH refitted, nothing compiled.

use std::sync::Arc;
use std::time::Instant;

use super::{Block, Gather, Prepared};
use crate::gpu::layout::Uploads;
use crate::gpu::resident::rewrite_scene_blocks;
use crate::gpu::times::{RenderTimes, SetupTimes};
use crate::gpu::work::PixelWork;
use crate::gpu::GpuError;
use crate::scene::Scene;

/// What [`Prepared::update`] did.
#[derive(Debug, Clone, PartialEq)]
pub enum Update {
    /// The scene's arrays were written in place, its BVH refitted: the
    /// next render shows the scene as it is now, compiling nothing.
    InPlace,
    /// The scene needs what it was not prepared with, named here: another
    /// shader variant, more primitives, another size or sampling. Nothing
    /// was changed; prepare it again ([`Renderer::prepare`](crate::gpu::Renderer::prepare)).
    Prepare(String),
}

impl Prepared {
    /// Takes `scene`'s values in place of those the scene was prepared
    /// with: `scene` is that scene with values changed (colours,
    /// positions, radii, lights, the camera). Its arrays are laid out
    /// again and written over the ones on the device, its BVH refitted
    /// rather than built (`accel::refit`); nothing is compiled. Where it
    /// needs another variant or more room, says what and changes nothing.
    /// The next render's times report the update's work.
    pub fn update(&mut self, scene: &Scene) -> Result<Update, GpuError> {
        if self.shared.device.hung() {
            return Err(GpuError::Lost);
        }
        if (scene.width, scene.height) != self.size {
            return Ok(Update::Prepare(format!(
                "the image is {}x{}, where it was {}x{}",
                scene.width, scene.height, self.size.0, self.size.1
            )));
        }
        let grid = scene.corner_grid();
        let traced = grid.as_ref().unwrap_or(scene);
        if Gather::of(scene, grid.is_some()) != self.gather {
            return Ok(Update::Prepare("the image's sampling changed".to_owned()));
        }
        let t0 = Instant::now();
        let s = self.settings;
        let up = Uploads::fitted(
            traced,
            s.intersect,
            s.precision,
            s.accel,
            self.shape.as_ref(),
        );
        let variant = self
            .gather
            .stage(self.shared.variant(traced, &s, &up, s.count).0);
        if variant != self.main.variant {
            return Ok(Update::Prepare(format!(
                "it needs another shader variant: {}",
                variant.difference(&self.main.variant)
            )));
        }
        let same_texels =
            Arc::ptr_eq(&self.texels, &traced.texels) || *self.texels == *traced.texels;
        let unchanged: &[Block] = if same_texels { &[Block::Texels] } else { &[] };
        let written = rewrite_scene_blocks(
            &self.shared.device,
            &mut self.executor.commands,
            &self.scene,
            &variant,
            &up,
            unchanged,
        )?;
        if let Err(why) = written {
            return Ok(Update::Prepare(why));
        }
        self.work = PixelWork::of(traced).through(up.ray_cost);
        self.texels = traced.texels.clone();
        self.pending = Some(RenderTimes {
            setup: SetupTimes {
                device_s: self.shared.device_s(),
                ..SetupTimes::default()
            },
            bvh_s: up.bvh_s,
            tables_s: up.tables_s,
            upload_s: t0.elapsed().as_secs_f64() - up.bvh_s - up.tables_s,
            ..RenderTimes::default()
        });
        self.shape = up.shape;
        Ok(Update::InPlace)
    }
}
