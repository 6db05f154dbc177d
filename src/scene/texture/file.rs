//! A texture's table in the scene file, as read: `pattern` or `image`, and
//! the rest of its keys kept aside for its pattern (check.rs reads them).

use serde::{Deserialize, Serialize};

/// `[textures.NAME]` as written: a `pattern` or an `image`, and the rest
/// of its keys kept aside for its pattern, which reads them into its own
/// struct (`PatternType::File`) when it is checked (check.rs). (serde's
/// `flatten`, which takes them, cannot sit beside `deny_unknown_fields`;
/// the pattern's struct denies unknown keys instead.)
#[derive(Debug, Default, Deserialize, Serialize)]
pub struct TextureFile {
    /// A pattern's name (the table's patterns not read from a file).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pattern: Option<String>,
    /// A PNG, EXR or PFM file, relative to the scene file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub image: Option<String>,
    /// The keys of its pattern, as TOML.
    #[serde(flatten)]
    pub own: toml::Table,
}

impl TextureFile {
    /// A texture of the pattern named `pattern`, or read from `image`,
    /// with its own keys `own` (its pattern's `PatternType::File`).
    pub(crate) fn new(pattern: Option<&str>, image: Option<String>, own: &impl Serialize) -> Self {
        TextureFile {
            pattern: pattern.map(str::to_owned),
            image,
            own: toml::Table::try_from(own).expect("a pattern's keys are a TOML table"),
        }
    }
}
