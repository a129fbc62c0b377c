//! Small helpers for the preset's TOML text: literals, leaves, and the
//! lines `grime preset` writes.

use super::{PARAMS, param};

/// True for `123`, `-4`, `+5_000`: digits with an optional sign.
pub(super) fn is_integer_text(raw: &str) -> bool {
    let digits = raw.strip_prefix(['-', '+']).unwrap_or(raw);
    !digits.is_empty() && digits.chars().all(|c| c.is_ascii_digit() || c == '_')
}

pub(super) fn push_field(out: &mut String, path: &str, key: &str, v: &toml::Value) {
    if let Some(spec) = param(path) {
        let sym = if spec.symbol.is_empty() {
            String::new()
        } else {
            format!(" [{}]", spec.symbol)
        };
        let range = if spec.min.is_finite() && spec.max.is_finite() && spec.max > spec.min {
            format!(" Range {} ..= {}.", spec.min, spec.max)
        } else {
            String::new()
        };
        out.push_str(&format!("# {}{sym}.{range}\n", spec.doc));
    }
    out.push_str(&format!("{key} = {}\n", toml_literal(v)));
}

/// Documents the fields of `section` that are unset (optional fields, such
/// as `age.years`), as commented-out lines.
pub(super) fn push_unset(out: &mut String, section: &str, table: &toml::Table) {
    let prefix = format!("{section}.");
    for spec in PARAMS {
        let Some(key) = spec.path.strip_prefix(&prefix) else {
            continue;
        };
        if !key.contains('.') && !table.contains_key(key) {
            let range = format!(" Range {} ..= {}.", spec.min, spec.max);
            out.push_str(&format!(
                "# {}.{range} Unset by default.\n# {key} = (a number)\n",
                spec.doc
            ));
        }
    }
}

/// Every value at `keys` below `v`; arrays fan out (each element is looked
/// up with the same remaining keys), so `stain.color` yields three numbers
/// and `dust.film_segments.alpha` one per segment.
pub(super) fn leaves<'a>(v: &'a toml::Value, keys: &[&str], out: &mut Vec<&'a toml::Value>) {
    match (v, keys.split_first()) {
        (toml::Value::Array(items), _) => items.iter().for_each(|item| leaves(item, keys, out)),
        (_, None) => out.push(v),
        (_, Some((k, rest))) => {
            if let Some(child) = v.get(*k) {
                leaves(child, rest, out);
            }
        }
    }
}

/// A TOML literal with floats printed at f32 precision (`0.025`, not
/// `0.02500000037252903`), as the preset stores them.
pub(super) fn toml_literal(v: &toml::Value) -> String {
    match v {
        toml::Value::Float(f) => {
            let s = (*f as f32).to_string();
            if s.contains(['.', 'e', 'i', 'N']) {
                s
            } else {
                format!("{s}.0")
            }
        }
        toml::Value::Array(items) => {
            let items: Vec<String> = items.iter().map(toml_literal).collect();
            format!("[{}]", items.join(", "))
        }
        other => other.to_string(),
    }
}

/// Makes room for an optional field that is unset (so absent from the
/// serialised preset), e.g. `age.years`, so `--set` can give it a value.
pub(super) fn insert_missing(v: &mut toml::Value, path: &str) {
    let Some((parent, key)) = path.rsplit_once('.') else {
        return;
    };
    if let Some(toml::Value::Table(t)) = lookup_mut(v, parent) {
        t.entry(key)
            .or_insert_with(|| toml::Value::String(String::new()));
    }
}

pub(super) fn lookup_mut<'a>(v: &'a mut toml::Value, path: &str) -> Option<&'a mut toml::Value> {
    path.split('.').try_fold(v, |v, k| v.get_mut(k))
}

pub(super) fn one_line(e: &impl std::fmt::Display) -> String {
    e.to_string()
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
}
