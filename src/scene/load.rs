//! Reading a scene file, TOML or NFF by its extension, into a [`Scene`].

use std::path::Path;

use super::{is_nff, nff, parse, Overrides, Scene, SceneError};

impl Scene {
    /// Reads and validates a scene file, then applies command-line overrides.
    pub fn load(path: &Path, overrides: &Overrides) -> Result<Scene, SceneError> {
        Self::load_with_text(path, overrides).map(|(scene, _)| scene)
    }

    /// As [`Scene::load`], with the file's text (TOML, or NFF by the
    /// extension), which the Python module's `Scene.to_dict` gives back.
    pub fn load_with_text(
        path: &Path,
        overrides: &Overrides,
    ) -> Result<(Scene, String), SceneError> {
        let text = crate::input::read_text(path, crate::input::ReadAs::Scene).map_err(|cause| {
            SceneError::Read {
                path: path.to_owned(),
                cause,
            }
        })?;
        let scene = if is_nff(path) {
            nff::parse_nff(&text, path, overrides)
        } else {
            parse(&text, path, overrides)
        }?;
        Ok((scene, text))
    }
}
