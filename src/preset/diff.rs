//! Which fields differ between two presets, as dotted paths.

/// Dotted paths of the leaves that differ between two TOML values
/// (`rain.k_a`, `stain.color`, ...), keys missing on one side included.
pub fn diff_paths(a: &toml::Value, b: &toml::Value, prefix: String, out: &mut Vec<String>) {
    let join = |k: &str| match prefix.is_empty() {
        true => k.to_string(),
        false => format!("{prefix}.{k}"),
    };
    match (a, b) {
        (toml::Value::Table(ta), toml::Value::Table(tb)) => {
            for (k, va) in ta {
                match tb.get(k) {
                    Some(vb) => diff_paths(va, vb, join(k), out),
                    None => out.push(join(k)),
                }
            }
            out.extend(tb.keys().filter(|k| !ta.contains_key(*k)).map(|k| join(k)));
        }
        _ if a != b => out.push(prefix),
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::preset::Preset;

    #[test]
    fn lists_changed_leaves_only() {
        let a = Preset::default();
        let mut b = a.clone();
        b.rain.k_a += 0.1;
        b.stain.color = [0, 0, 0];
        let mut out = Vec::new();
        diff_paths(
            &toml::Value::try_from(&a).unwrap(),
            &toml::Value::try_from(&b).unwrap(),
            String::new(),
            &mut out,
        );
        out.sort();
        assert_eq!(out, ["rain.k_a", "stain.color"]);
    }
}
