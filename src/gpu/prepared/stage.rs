//! A stage of a prepared scene: one pipeline and the buffers bound to it
//! through a descriptor set of its own (the main stage, and adaptive
//! sampling's refinement).

use std::sync::Arc;

use glam::UVec4;

use crate::base::interface::Array;
use crate::gpu::blocks::Block;
use crate::gpu::passes::Target;
use crate::gpu::resident::{list_buffer, stage_blocks, Blocks, Bound, StageInput};
use crate::gpu::shared::{Pipeline, Shared};
use crate::gpu::variant::Variant;
use crate::gpu::vk::buffer::Buffer;
use crate::gpu::vk::descriptor::{DescriptorSet, Resource};
use crate::gpu::GpuError;

/// One pipeline and the buffers bound to it through a set of its own.
/// Field order is drop order: the set before the buffers it names.
pub(super) struct BoundStage {
    pub(super) set: DescriptorSet,
    pub(super) own: Blocks,
    pub(super) pipeline: Arc<Pipeline>,
    pub(super) variant: Variant,
    /// Its output tile, in pixels.
    pub(super) tile: (u32, u32),
}

/// The main stage, or the refinement's where `refine` (a free function,
/// so that the executor stays free to borrow).
pub(super) fn pick<'a>(
    main: &'a BoundStage,
    refinement: &'a Option<BoundStage>,
    refine: bool,
) -> &'a BoundStage {
    if refine {
        refinement
            .as_ref()
            .expect("the refinement's stage is made first")
    } else {
        main
    }
}

impl BoundStage {
    /// `pipeline` (of `variant`) with a set of its own, bound to the scene's
    /// buffers (`scene`) and to its own, made here: an output tile of
    /// `tile` pixels and what else the variant declares.
    pub(super) fn new(
        shared: &Shared,
        pipeline: Arc<Pipeline>,
        variant: Variant,
        scene: &Blocks,
        tile: (u32, u32),
        own: StageInput<'_>,
    ) -> Result<Self, GpuError> {
        let device = &shared.device;
        let own = stage_blocks(device, &variant, tile, own)?;
        let set = DescriptorSet::new(device, &pipeline.raw)?;
        let stage = Self {
            set,
            own,
            pipeline,
            variant,
            tile,
        };
        let resources = stage.resources(scene);
        // SAFETY: the set is new, so no submission uses it; the buffers it
        // names live in this stage (its own) or in the prepared scene,
        // which drops its stages first, and are leaked where a wait timed
        // out.
        unsafe { stage.set.write(&resources) };
        Ok(stage)
    }

    /// Whether its output holds a tile of `tile` invocations' words.
    pub(super) fn holds(&self, tile: (u32, u32)) -> bool {
        tile.0 <= self.tile.0 && tile.1 <= self.tile.1
    }

    /// `list` bound in place of the stage's list (a refining stage's),
    /// which no submission uses once the last has been waited on.
    pub(super) fn bind_list(
        &mut self,
        shared: &Shared,
        scene: &Blocks,
        list: &Array<'_>,
    ) -> Result<(), GpuError> {
        let buffer = list_buffer(&shared.device, list)?;
        let last = self.own.replace(Block::Refine, Bound::Buffer(buffer));
        assert!(last.is_some(), "a stage with a list binds another");
        let resources = self.resources(scene);
        // SAFETY: every submission of this set has been waited on (each
        // tile's dispatch waits on its fence), and the buffers it names live
        // in this stage or in the prepared scene, as in `new`; the list it
        // named is dropped only after the set no longer names it.
        unsafe { self.set.write(&resources) };
        drop(last);
        Ok(())
    }

    /// The resources of its bindings, its own buffers first, then the
    /// scene's.
    pub(super) fn resources(&self, scene: &Blocks) -> Vec<Resource> {
        self.variant
            .bindings()
            .into_iter()
            .map(|(block, _, _)| {
                self.own
                    .get(block)
                    .or_else(|| scene.get(block))
                    .expect("every binding has its buffer")
                    .resource()
            })
            .collect()
    }

    /// The stage's buffer at `block`, where it has one of its own.
    pub(super) fn buffer(&self, block: Block) -> Option<&Buffer> {
        self.own.get(block).map(|b| b.buffer())
    }

    /// A dispatch of this stage over no pixels, counters untouched.
    pub(super) fn target(&self) -> Target<'_> {
        Target {
            pipeline: &self.pipeline.raw,
            set: self.set.set,
            out: self
                .buffer(Block::Pixels)
                .expect("a stage has its output")
                .raw,
            out_bytes: ash::vk::WHOLE_SIZE,
            zero: None,
            rect: UVec4::ZERO,
        }
    }
}
