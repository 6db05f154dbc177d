//! The GPU renderer: the model of docs/scene-format.md (Rays, Shading) as a
//! Vulkan compute shader, one invocation per pixel, large images in tiles.
//!
//! Two stages: a [`Renderer`] owns the device and the compiled shaders;
//! [`Renderer::prepare`] turns a scene into a [`Prepared`] one (its
//! variant's pipeline, its buffers on the device), and
//! [`Prepared::render`] renders any region of it, as often as asked.
//! [`Renderer::render`] does both for a whole image.
//!
//! The files, in the order a render passes through them: options.rs (how a
//! renderer is made and a scene prepared), renderer.rs (the device and the
//! pipelines), layout.rs, features.rs and variant.rs (the scene laid out
//! for the shader, what it needs of it, and what it compiles with),
//! compile.rs (glslang and the caches),
//! resident.rs (the buffers), prepared.rs (the stages and the tiles),
//! work.rs (tile sizes and waits), passes.rs and schedule.rs (recording,
//! submitting and waiting), refine.rs (adaptive sampling's levels on the
//! device), times.rs.

mod access;
mod blocks;
pub mod compile;
mod entities;
mod error;
mod features;
pub(crate) mod generated;
pub(crate) mod layout;
mod macros;
mod options;
mod passes;
mod prepared;
mod refine;
mod renderer;
mod resident;
pub mod schedule;
pub mod sealed;
mod shared;
mod times;
pub mod variant;
pub(crate) mod vk;
mod work;
pub mod workarounds;

pub use crate::base::{Precision, WORKGROUP};
pub use crate::settings::Intersect;
pub use error::{GpuError, VkCode};
pub use features::EXPERIMENTS;
pub use options::{check_define, check_include_dir, GpuOptions, RenderSettings};
pub use prepared::{Prepared, Rendered, Update};
pub use renderer::Renderer;
pub use schedule::Schedule;
pub use times::{RenderTimes, SetupTimes};
pub use vk::bounded::{open_unfinished, OPEN_LIMIT};
pub use vk::device::DeviceInfo;
pub use vk::instance::validation_layer_installed;
pub use work::{tile_timeout, COMPILE_TIMEOUT};

/// Every Vulkan device, best first, for `glint info`.
pub fn list_devices() -> Result<Vec<DeviceInfo>, GpuError> {
    vk::bounded::bounded(vk::bounded::OPEN_LIMIT, || {
        let instance = vk::instance::Instance::new(false)?;
        Ok(vk::device::candidates(&instance)?
            .into_iter()
            .map(|c| c.info)
            .collect())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Overrides, Scene};

    /// An edited shader file makes a new pipeline for the variant, which
    /// replaces the old one (as `glint watch` edits it), rather than
    /// piling up one pipeline an edit.
    #[test]
    fn an_edit_replaces_the_variants_pipeline() {
        let dir = tempfile::tempdir().unwrap();
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let specular = std::fs::read_to_string(root.join("shaders/specular.glsl")).unwrap();
        let file = dir.path().join("specular.glsl");
        std::fs::write(&file, &specular).unwrap();
        let small = Overrides {
            width: Some(16),
            height: Some(12),
            ..Overrides::default()
        };
        let scene = Scene::load(&root.join("scenes/seed-fig4.toml"), &small).unwrap();
        let mut renderer = Renderer::new(&GpuOptions {
            include_dirs: vec![dir.path().to_owned()],
            ..GpuOptions::from_env(None)
        })
        .unwrap();
        let (before, _) = renderer.render(&scene, &|_| {}).unwrap();
        std::fs::write(&file, specular.replace("spec_pow(", "0.0 * spec_pow(")).unwrap();
        let (after, _) = renderer.render(&scene, &|_| {}).unwrap();
        assert!(before != after, "the edit changes the image");
        assert_eq!(renderer.pipelines(), 1);
        // The edit undone: the first image again, still one pipeline.
        std::fs::write(&file, &specular).unwrap();
        let (again, _) = renderer.render(&scene, &|_| {}).unwrap();
        assert!(again == before);
        assert_eq!(renderer.pipelines(), 1);
    }

    /// A renderer keeps at most `KEPT_PIPELINES` pipelines that no
    /// prepared scene holds: one that rendered 40 variants (depths 1 to
    /// 40) keeps the last ones, while a prepared scene's pipeline stays
    /// alive and renders the same bits after the others went.
    #[test]
    fn a_renderer_keeps_a_bounded_number_of_pipelines() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let at_depth = |d: u32| {
            let o = Overrides {
                width: Some(8),
                height: Some(6),
                max_depth: Some(d),
                ..Overrides::default()
            };
            Scene::load(&root.join("scenes/seed-fig5.toml"), &o).unwrap()
        };
        let mut renderer = Renderer::new(&GpuOptions::from_env(None)).unwrap();
        let settings = renderer.settings();
        let first = at_depth(1);
        let mut held = renderer.prepare(&first, &settings).unwrap();
        let before = held.render(None, &|_| {}).unwrap().image;
        for d in 2..=40 {
            renderer.render(&at_depth(d), &|_| {}).unwrap();
            assert!(
                renderer.pipelines() <= shared::KEPT_PIPELINES + 1,
                "depth {d}"
            );
        }
        assert_eq!(held.render(None, &|_| {}).unwrap().image, before);
    }

    /// A set stop flag fails the render before its first tile, and the
    /// prepared scene renders whole again once it is cleared (the Python
    /// module's Ctrl-C).
    #[test]
    fn a_stop_ends_a_render_and_the_scene_renders_again() {
        use std::sync::atomic::{AtomicBool, Ordering};
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let small = Overrides {
            width: Some(16),
            height: Some(12),
            ..Overrides::default()
        };
        let scene = Scene::load(&root.join("scenes/seed-fig4.toml"), &small).unwrap();
        let mut renderer = Renderer::new(&GpuOptions::from_env(None)).unwrap();
        let mut prepared = renderer.prepare(&scene, &renderer.settings()).unwrap();
        let whole = prepared.render(None, &|_| {}).unwrap().image;
        let stop = std::sync::Arc::new(AtomicBool::new(true));
        prepared.stop_when(stop.clone());
        let tiles = std::cell::Cell::new(0);
        let stopped = prepared.render(None, &|_| tiles.set(tiles.get() + 1));
        assert!(matches!(stopped, Err(GpuError::Interrupted)));
        assert_eq!(tiles.get(), 0, "no tile ran");
        stop.store(false, Ordering::Relaxed);
        assert!(prepared.render(None, &|_| {}).unwrap().image == whole);
    }
}
