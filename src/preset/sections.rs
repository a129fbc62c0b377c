//! Sections that share a type but not their defaults (splotches and stains;
//! the four weathering generators): a missing field takes its section's
//! default, not the type's.

use serde::Serialize;
use serde::de::{Deserialize, DeserializeOwned, Deserializer, Error as _};

use super::{BlotchParams, GeneratorParams};

/// The section's fields over its defaults.
fn over<'de, D: Deserializer<'de>, T: Serialize + DeserializeOwned>(
    d: D,
    default: fn() -> T,
) -> Result<T, D::Error> {
    let given = toml::Table::deserialize(d)?;
    let mut value = toml::Table::try_from(default()).map_err(D::Error::custom)?;
    for (k, v) in given {
        value.insert(k, v);
    }
    value.try_into().map_err(D::Error::custom)
}

macro_rules! section {
    ($name:ident, $t:ty, $default:path) => {
        pub(super) fn $name<'de, D: Deserializer<'de>>(d: D) -> Result<$t, D::Error> {
            over(d, $default)
        }
    };
}

section!(splotches, BlotchParams, BlotchParams::splotches);
section!(stains, BlotchParams, BlotchParams::stains);
section!(spotty, GeneratorParams, GeneratorParams::spotty);
section!(roughy, GeneratorParams, GeneratorParams::roughy);
section!(fade, GeneratorParams, GeneratorParams::fade);
section!(desaturate, GeneratorParams, GeneratorParams::desaturate);

/// A preset from its TOML table with a `say` sentence: the sentence
/// applied to the defaults first, then the table's own fields over that
/// (a field written in the file wins over the sentence).
pub(super) fn with_say(table: toml::Table) -> crate::Result<super::Preset> {
    use crate::error::Error;
    let sentence = table.get("say").and_then(toml::Value::as_str).unwrap_or("");
    let mut base = super::Preset::default();
    crate::say::apply(&mut base, sentence)?;
    let mut value = toml::Value::try_from(&base).map_err(|e| Error::Preset(e.to_string()))?;
    merge(&mut value, toml::Value::Table(table));
    value
        .try_into()
        .map_err(|e: toml::de::Error| Error::Preset(super::toml_text::one_line(&e)))
}

/// `over` into `base`: tables field by field, anything else replaced.
fn merge(base: &mut toml::Value, over: toml::Value) {
    match (base, over) {
        (toml::Value::Table(b), toml::Value::Table(o)) => {
            for (k, v) in o {
                match b.get_mut(&k) {
                    Some(slot) => merge(slot, v),
                    None => {
                        b.insert(k, v);
                    }
                }
            }
        }
        (b, o) => *b = o,
    }
}
