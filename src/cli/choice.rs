//! Command-line parsers for the library's settings ([`Choice`]): the
//! library names its values, the command line alone knows clap.

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use glint::settings::Choice;

/// Parses one of `T`'s names into its value; `--help` lists them with
/// their lines.
pub fn of<T: Choice + Send + Sync>() -> impl TypedValueParser<Value = T> {
    PossibleValuesParser::new(
        T::ALL
            .iter()
            .map(|(_, name, help)| PossibleValue::new(*name).help(*help)),
    )
    .map(|name| T::named(&name).expect("clap took one of the possible values"))
}
