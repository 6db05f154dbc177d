//! A table read in two steps: keys that the scene's own structs do not name
//! are kept aside as TOML (serde's `flatten`), and a unit (a light type)
//! later reads them into its own struct. This file gives that second step:
//! the keys a struct takes, read from its serde derive rather than listed
//! again, and the struct read from the kept table with the key path of
//! whatever is wrong in it.

use serde::de::{self, DeserializeOwned, Visitor};

use super::error::SceneError;
use super::field::Validator;
use super::locate::KeyPath;

/// The keys of struct `T` as its derive declares them (renames applied).
pub fn keys_of<T: DeserializeOwned>() -> &'static [&'static str] {
    let mut keys = KeysOf(&[]);
    // The deserializer below refuses everything: its one job is to be told
    // the struct's fields.
    let _ = T::deserialize(&mut keys);
    keys.0
}

struct KeysOf(&'static [&'static str]);

impl<'de> de::Deserializer<'de> for &mut KeysOf {
    type Error = de::value::Error;

    fn deserialize_any<V: Visitor<'de>>(self, _: V) -> Result<V::Value, Self::Error> {
        Err(de::Error::custom("not a struct"))
    }

    fn deserialize_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        fields: &'static [&'static str],
        _visitor: V,
    ) -> Result<V::Value, Self::Error> {
        self.0 = fields;
        Err(de::Error::custom("keys read"))
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string
        bytes byte_buf option unit unit_struct newtype_struct seq tuple
        tuple_struct map enum identifier ignored_any
    }
}

impl Validator<'_> {
    /// `table`, the kept keys of the table at `path`, read as a unit's own
    /// struct `F`. A key `F` lacks is refused, the first in the file's
    /// order (a kept table holds its keys sorted): with `elsewhere`'s
    /// message where another unit takes it, else as an unknown field that
    /// lists `shared` (the keys every unit's table has) and `F`'s. A wrong
    /// value is named by its key path.
    pub(crate) fn read_own<F: DeserializeOwned>(
        &self,
        path: &KeyPath,
        table: &toml::Table,
        shared: &[&str],
        elsewhere: impl FnOnce(&str) -> Option<String>,
    ) -> Result<F, SceneError> {
        let keys = keys_of::<F>();
        let place = |key: &str| {
            self.located
                .find(&path.key(key))
                .map(|a| (a.line, a.column))
        };
        let stray = table
            .keys()
            .map(String::as_str)
            .filter(|k| !keys.contains(k))
            .min_by_key(|k| place(k));
        if let Some(key) = stray {
            let message = elsewhere(key).unwrap_or_else(|| {
                let known: Vec<String> = shared
                    .iter()
                    .chain(keys)
                    .map(|k| format!("`{k}`"))
                    .collect();
                format!(
                    "unknown field `{key}`, expected one of {}",
                    known.join(", ")
                )
            });
            return self.err(&path.key(key), message);
        }
        read_table(table, path).or_else(|(at, message)| self.err(&at, message))
    }
}

/// `table` read as a `T`; an error gives the path below `at` of the value
/// that is wrong (`at` itself where none is named) and serde's message.
fn read_table<T: DeserializeOwned>(
    table: &toml::Table,
    at: &KeyPath,
) -> Result<T, (KeyPath, String)> {
    serde_path_to_error::deserialize(toml::Value::Table(table.clone())).map_err(|e| {
        let mut path = at.clone();
        for segment in e.path().iter() {
            path = match segment {
                serde_path_to_error::Segment::Seq { index } => path.index(*index),
                serde_path_to_error::Segment::Map { key } => path.key(key),
                _ => path,
            };
        }
        (path, e.into_inner().message().to_owned())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::field::root;

    #[derive(Debug, serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Beam {
        radius: Option<f64>,
        #[serde(rename = "way")]
        direction: Option<[f64; 3]>,
    }

    #[test]
    fn a_structs_keys_are_its_derives() {
        assert_eq!(keys_of::<Beam>(), ["radius", "way"]);
    }

    #[test]
    fn a_wrong_value_is_named_by_its_path() {
        let path = root().key("lights").index(2);
        let table: toml::Table = toml::from_str("radius = 1.0\nway = [1.0, 2.0, \"x\"]").unwrap();
        let (at, message) = read_table::<Beam>(&table, &path).unwrap_err();
        assert_eq!(at.to_string(), "lights[2].way[2]");
        assert!(message.contains("invalid type"), "{message}");
        let ok: Beam = read_table(&toml::from_str("radius = 2.0").unwrap(), &path).unwrap();
        assert_eq!(ok.radius, Some(2.0));
    }
}
