//! A light's table in the scene file, as read: its `type` and the colours
//! every light has, and the rest of its keys kept aside for its type, which
//! reads them into its own struct (`LightType::File`) when it is checked
//! (check.rs).

use serde::{Deserialize, Serialize};

use crate::input::field::Triple;

/// A `[[lights]]` table: what every type shares, and the type's own keys.
/// (serde's `flatten`, which takes the own keys, cannot sit beside
/// `deny_unknown_fields`; the type's struct denies unknown keys instead.)
#[derive(Debug, Clone, Deserialize, Serialize)]
pub struct LightFile {
    /// `type`: a name of the table of light types.
    #[serde(rename = "type")]
    pub kind: String,
    /// Its ambient intensity (default 0).
    #[serde(default)]
    pub ambient: Triple,
    /// Its diffuse intensity (default 0).
    #[serde(default)]
    pub diffuse: Triple,
    /// Its specular intensity (default 0).
    #[serde(default)]
    pub specular: Triple,
    /// The keys of its type, as TOML.
    #[serde(flatten)]
    pub own: toml::Table,
}

impl LightFile {
    /// A light of the type named `kind` with its own keys `own` (its
    /// type's `LightType::File`), white, with a little ambient.
    pub(crate) fn new(kind: &str, own: &impl Serialize) -> Self {
        LightFile {
            kind: kind.to_owned(),
            ambient: Triple([0.1; 3]),
            diffuse: Triple([1.0; 3]),
            specular: Triple([0.5; 3]),
            own: toml::Table::try_from(own).expect("a light type's table is a TOML table"),
        }
    }

    /// Its own key `key`, where it is three numbers.
    pub fn triple(&self, key: &str) -> Option<Triple> {
        self.own.get(key).cloned()?.try_into().ok()
    }

    /// Sets its own key `key` to three numbers.
    pub fn set_triple(&mut self, key: &str, t: Triple) {
        let value = toml::Value::try_from(t).expect("three numbers are TOML");
        self.own.insert(key.to_owned(), value);
    }
}
