//! A TOML scene file (docs/scene-format.md) read into a [`SceneFile`], its
//! errors translated to the line, column and key they are at.

use std::path::Path;

use super::file::SceneFile;
use super::validate::{resolve, Overrides};
use super::{Scene, SceneError};
use crate::input::locate::Located;
use crate::prim::mesh::Cache as MeshCache;

/// Parses and validates scene text; `file` is only used in messages.
pub fn parse(text: &str, file: &Path, overrides: &Overrides) -> Result<Scene, SceneError> {
    parse_cached(text, file, overrides, None)
}

/// As [`parse`], the meshes' OBJ files taken from `meshes` where read
/// before and unchanged since (`prim::mesh::load`): a scene read again
/// with values changed (the Python module's `Scene.params`).
pub fn parse_cached(
    text: &str,
    file: &Path,
    overrides: &Overrides,
    meshes: Option<&MeshCache>,
) -> Result<Scene, SceneError> {
    let located = Located::new(text);
    let raw: SceneFile =
        super::split::parse(text).map_err(|b| toml_error(&b.error, b.offset, file, &located))?;
    resolve(raw, file, &located, overrides, meshes)
}

/// `offset`: where the text that `e` came from starts in the file.
fn toml_error(e: &toml::de::Error, offset: usize, file: &Path, located: &Located) -> SceneError {
    let span = e.span().map_or(0..0, |s| s.start + offset..s.end + offset);
    let at = located.line_col(span.start);
    let mut message = e.message().trim().to_owned();
    // toml hands a date-time to serde as a map.
    if message.contains("invalid type: map") && located.is_datetime_at(span.start) {
        message = message.replace("invalid type: map", "invalid type: date-time");
    }
    // A missing top-level table: toml gives it no span at all.
    if let Some(field) = message.strip_prefix("missing field ") {
        if e.span().is_none_or(|s| s == (0..0)) {
            return SceneError::Invalid {
                file: file.to_owned(),
                line: 1,
                column: 1,
                key: field.trim_matches('`').to_owned(),
                message: "missing table (required)".to_owned(),
            };
        }
    }
    let key = located
        .path_at(&span)
        .or_else(|| located.key_on_line(span.start));
    match key {
        Some(key) => SceneError::Invalid {
            file: file.to_owned(),
            line: at.line,
            column: at.column,
            key: key.to_string(),
            message,
        },
        None => SceneError::Syntax {
            file: file.to_owned(),
            line: at.line,
            column: at.column,
            message,
        },
    }
}
