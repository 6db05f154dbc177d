//! How a pixel is sampled, which both renderers share (docs/scene-format.md,
//! Rays): the scene holds each mode's keys and checks (`scene::Sampling`,
//! `scene::Adaptive`, `scene::Contrast`); this layer holds what the modes
//! do, between the scene and the two renderers, so that both trace the same
//! samples and sum them in the same order.
//!
//! A mode is a unit: a module here, a GLSL include where its passes need
//! one, and a row of [`MODES`]. Each renderer brings its own tracer of a
//! list of points or entries (src/cpu/adaptive.rs and src/cpu/contrast.rs;
//! src/gpu/prepared/refinement.rs and src/gpu/prepared/contrast.rs).

pub mod adaptive;
pub mod contrast;
mod corners;
pub mod decisions;

pub use decisions::{Decider, Log, Sampled};

use crate::scene::Sampling;

/// A sampling mode: the scene's value, whether its first pass traces the
/// pixels' corners, and the shader include its refinement passes read
/// (None where the megakernel alone traces it).
#[derive(Debug, Clone, Copy)]
pub struct Mode {
    /// The scene's `sampling` value.
    pub sampling: Sampling,
    /// Its name in the scene file.
    pub name: &'static str,
    /// Whether its first pass traces the corner grid (`Scene::corner_grid`).
    pub corners: bool,
    /// The GLSL file under shaders/ that its refinement passes include.
    pub shader: Option<&'static str>,
    /// Why AOVs are not taken of it, which are of a pixel's first samples
    /// on its own grid (`base::aov`); None where they are.
    pub no_aovs: Option<&'static str>,
}

/// Every sampling mode, in the scene format's order.
pub const MODES: &[Mode] = &[
    Mode {
        sampling: Sampling::Centers,
        name: "centers",
        corners: false,
        shader: None,
        no_aovs: None,
    },
    Mode {
        sampling: Sampling::Corners,
        name: "corners",
        corners: true,
        shader: None,
        no_aovs: Some(CORNERS_NO_AOVS),
    },
    Mode {
        sampling: Sampling::Adaptive,
        name: "adaptive",
        corners: true,
        shader: Some("adaptive.glsl"),
        no_aovs: Some(CORNERS_NO_AOVS),
    },
    Mode {
        sampling: Sampling::Contrast,
        name: "contrast",
        corners: false,
        shader: Some("contrast.glsl"),
        no_aovs: Some(
            "AOVs are of the first samples of a pixel's grid, and this scene samples by \
             contrast, level by level",
        ),
    },
];

/// Why a mode that traces the corner grid takes no AOVs.
const CORNERS_NO_AOVS: &str =
    "AOVs are of a pixel's own samples, and this scene samples its pixels' corners";

/// Where `scene`'s sampling takes no AOVs, why, in one sentence that ends
/// with what to do.
pub fn aovs_refused(scene: &crate::scene::Scene) -> Option<String> {
    let m = mode(scene.sampling);
    m.no_aovs.map(|why| {
        format!(
            "{why} (sampling = \"{}\"): render it with sampling = \"centers\"",
            m.name
        )
    })
}

/// The row of `sampling`.
pub fn mode(sampling: Sampling) -> &'static Mode {
    MODES
        .iter()
        .find(|m| m.sampling == sampling)
        .expect("every sampling has a row of MODES")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each mode has one row, named as the scene file names it, and its
    /// shader include is one of shaders/.
    #[test]
    fn every_mode_has_one_row_named_as_the_file_names_it() {
        for m in MODES {
            let named: Sampling =
                serde_json::from_value(serde_json::Value::String(m.name.to_owned())).unwrap();
            assert_eq!(named, m.sampling, "{}", m.name);
            assert_eq!(mode(m.sampling).name, m.name);
            if let Some(file) = m.shader {
                let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                    .join("shaders")
                    .join(file);
                assert!(path.is_file(), "{}", path.display());
            }
        }
        // A new Sampling fails to compile here until it is listed, and
        // then fails `mode` until it has its row.
        let listed = |s: Sampling| match s {
            Sampling::Centers | Sampling::Corners | Sampling::Adaptive | Sampling::Contrast => s,
        };
        for s in [
            Sampling::Centers,
            Sampling::Corners,
            Sampling::Adaptive,
            Sampling::Contrast,
        ] {
            assert_eq!(mode(listed(s)).sampling, s);
        }
        assert_eq!(MODES.len(), 4);
    }
}
