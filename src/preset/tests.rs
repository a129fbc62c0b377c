//! Tests of presets: parsing, validation, `--set`, the documented TOML.

use super::*;

/// Dotted paths of every numeric leaf below `v`; array elements share
/// their array's path, so a list of segments gives `….alpha` once per item.
fn numeric_leaves(v: &toml::Value, path: &str, out: &mut Vec<String>) {
    match v {
        toml::Value::Integer(_) | toml::Value::Float(_) => out.push(path.to_string()),
        toml::Value::Array(items) => items.iter().for_each(|i| numeric_leaves(i, path, out)),
        toml::Value::Table(t) => {
            for (k, child) in t {
                let p = if path.is_empty() {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                };
                numeric_leaves(child, &p, out);
            }
        }
        _ => {}
    }
}

#[test]
fn set_seed_past_i64_says_out_of_range() {
    let mut p = Preset::default();
    let err = p.set("seed=18446744073709551615").unwrap_err().to_string();
    assert_eq!(
        err,
        "preset: seed = 18446744073709551615 is out of range; allowed: 0 ..= 9223372036854775807"
    );
    let err = p
        .set("rain.layers=99999999999999999999")
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("rain.layers = 99999999999999999999 is out of range"),
        "{err}"
    );
    assert!(
        p.set("nope=99999999999999999999")
            .unwrap_err()
            .to_string()
            .contains("unknown field")
    );
    p.set("seed=9223372036854775807").unwrap();
    assert_eq!(p.seed, i64::MAX as u64);
}

#[test]
fn every_parameter_has_a_spec() {
    // The default preset, plus the custom dust lists filled in so their
    // leaves are seen too.
    let mut p = Preset::default();
    p.dust.environment = DustEnvironment::Custom;
    p.dust.film_segments = vec![Segment::new(5, 11.1, 5.1), Segment::new(0, 2.8, 0.0)];
    p.dust.mask_segments = vec![Segment::new(0, 1.3, 0.3)];
    p.validate().unwrap();
    let mut paths = Vec::new();
    numeric_leaves(&toml::Value::try_from(&p).unwrap(), "", &mut paths);
    assert!(
        paths.iter().any(|p| p == "dust.film_segments.alpha"),
        "{paths:?}"
    );
    let missing: Vec<_> = paths.iter().filter(|p| param(p).is_none()).collect();
    assert!(
        missing.is_empty(),
        "parameters without a PARAMS entry: {missing:?}"
    );
    for spec in PARAMS {
        assert!(
            !spec.doc.is_empty() && spec.min <= spec.max,
            "{}",
            spec.path
        );
    }
}

#[test]
fn moss_and_dust_sections_round_trip_and_validate() {
    let mut p = Preset::default();
    p.set("moss.color=orange").unwrap();
    p.set("dust.environment=steep-start").unwrap();
    p.set("dust.days=200").unwrap();
    assert_eq!(p.moss.color, MossColor::Orange);
    let back = Preset::from_toml(&p.to_toml()).unwrap();
    assert_eq!(back, p);
    assert!(
        p.to_commented_toml()
            .contains("# Days of dust accumulation")
    );
    let (film, mask) = p.dust.segments();
    assert_eq!((film.len(), mask.len()), (2, 1));
}

#[test]
fn array_elements_and_custom_segments_are_checked() {
    let mut p = Preset::default();
    p.dust.film_weights = [1.0, -0.5, 1.0];
    let e = p.validate().unwrap_err().to_string();
    assert!(e.contains("dust.film_weights"), "{e}");

    let mut p = Preset::default();
    p.dust.environment = DustEnvironment::Custom;
    assert!(
        p.validate()
            .unwrap_err()
            .to_string()
            .contains("dust.film_segments")
    );
    p.dust.film_segments = vec![Segment::new(0, -1.0, 0.0)];
    p.dust.mask_segments = vec![Segment::new(0, 1.0, 0.0)];
    assert!(
        p.validate()
            .unwrap_err()
            .to_string()
            .contains("dust.film_segments.alpha")
    );

    let mut p = Preset::default();
    p.dust.mask_segments = vec![Segment::new(0, 1.0, 0.0)];
    assert!(
        p.validate().unwrap_err().to_string().contains("custom"),
        "ignored lists are an error"
    );
    assert!(Preset::default().set("moss.color=purple").is_err());
}

#[test]
fn a_dumped_preset_leaves_the_clock_free_and_reads_back_the_same() {
    let text = Preset::default().to_commented_toml();
    assert!(text.contains("\n# layers = 12\n"), "{text}");
    assert!(text.contains("\nr = 100.0\n"), "other fields stay: {text}");
    assert_eq!(Preset::from_toml(&text).unwrap(), Preset::default());
    assert_eq!(
        crate::clock::Pins::in_toml(&text),
        crate::clock::Pins::none()
    );
    // At 30 years, the clock's own counts are left free; a count set over
    // it is written, so it stays pinned.
    let mut p = crate::clock::at(&Preset::default(), 30, crate::clock::Pins::none()).unwrap();
    p.dust.days = 5;
    let text = p.to_commented_toml();
    assert!(
        text.contains("\n# layers = 24\n") && text.contains("\ndays = 5\n"),
        "{text}"
    );
    let pins = crate::clock::Pins::in_toml(&text);
    assert!(pins.pins("dust.days") && !pins.pins("rain.layers"));
    assert_eq!(crate::clock::load(&text).unwrap(), p);
}

#[test]
fn every_word_field_lists_its_choices_and_each_one_sets() {
    let value = toml::Value::try_from(Preset::default()).unwrap();
    let Some(root) = value.as_table() else {
        panic!("a preset is a table")
    };
    for (section, table) in root.iter().filter_map(|(k, v)| Some((k, v.as_table()?))) {
        for (key, v) in table {
            let path = format!("{section}.{key}");
            let Some(word) = v.as_str() else { continue };
            let spec = param(&path).unwrap_or_else(|| panic!("no row for {path}"));
            assert!(
                spec.choices.contains(&word),
                "{path}: the default {word:?} is not among {:?}",
                spec.choices
            );
            // Each word parses (one may still need other fields: "custom").
            let known = |c: &str| match Preset::default().set(&format!("{path}=\"{c}\"")) {
                Ok(()) => true,
                Err(e) => !e.to_string().contains("unknown variant"),
            };
            for c in spec.choices {
                assert!(known(c), "{path} = {c}");
            }
            assert!(!known("no-such-word"));
        }
    }
    assert!(param("smudges.placement").unwrap().choices.len() >= 9);
}
