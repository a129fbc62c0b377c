//! `--say` end to end: the sentence sets the effects, the imperfections
//! cover what the adverbs say, a preset's `say` does the same, and an
//! unknown word is one clear error.

mod common;

use common::{assert_clear_error, grime, s, stderr};

fn report(path: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn coverage(r: &serde_json::Value, name: &str) -> (f64, f64) {
    let g = r["imperfections"]["generators"]
        .as_array()
        .unwrap()
        .iter()
        .find(|g| g["name"] == name)
        .unwrap_or_else(|| panic!("no {name} in {r}"));
    (
        g["target"].as_f64().unwrap(),
        g["coverage"].as_f64().unwrap(),
    )
}

#[test]
fn say_sets_the_effects_and_their_coverage() {
    let dir = tempfile::tempdir().unwrap();
    let (out, rep) = (dir.path().join("aged.png"), dir.path().join("r.json"));
    let plain = dir.path().join("plain.png");
    let sentence =
        "very rusty near the railings, slightly scratched, moderately mossy near the ground";
    let o = grime(&[
        "run",
        "--demo",
        "-o",
        s(&out),
        "--layers",
        "2",
        "--say",
        sentence,
        "--report",
        s(&rep),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("note"),
        "moss's place is reported: {}",
        stderr(&o)
    );
    let r = report(&rep);
    for (name, want) in [("rust", 0.55), ("scratches", 0.05)] {
        let (target, got) = coverage(&r, name);
        assert_eq!(target as f32, want as f32);
        assert!((got - want).abs() <= 0.02, "{name}: {got}");
    }
    let names: Vec<&str> = r["layers"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|l| l["name"].as_str())
        .collect();
    assert!(
        names.contains(&"rust") && names.contains(&"scratches"),
        "{names:?}"
    );
    let o = grime(&["run", "--demo", "-o", s(&plain), "--layers", "2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_ne!(
        image::open(&out).unwrap().to_rgb8().into_raw(),
        image::open(&plain).unwrap().to_rgb8().into_raw()
    );
}

#[test]
fn a_preset_says_it_too_and_its_own_fields_win() {
    let dir = tempfile::tempdir().unwrap();
    let preset = dir.path().join("p.toml");
    std::fs::write(
        &preset,
        "say = \"extremely mouldy at the bottom, stained\"\n[stains]\nenabled = false\n",
    )
    .unwrap();
    let (out, rep) = (dir.path().join("a.png"), dir.path().join("r.json"));
    let o = grime(&[
        "run",
        "--demo",
        "-o",
        s(&out),
        "--layers",
        "1",
        "--preset",
        s(&preset),
        "--report",
        s(&rep),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let r = report(&rep);
    let (target, got) = coverage(&r, "mould");
    assert_eq!(target as f32, 0.75);
    assert!((got - 0.75).abs() <= 0.02, "mould {got}");
    let gens = r["imperfections"]["generators"].as_array().unwrap();
    assert!(
        gens.iter().all(|g| g["name"] != "stains"),
        "the file's enabled = false wins"
    );
}

#[test]
fn an_unknown_word_is_one_line_listing_the_known_words() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("a.png");
    let o = grime(&[
        "run",
        "--demo",
        "-o",
        s(&out),
        "--say",
        "very crusty near the ground",
    ]);
    assert_clear_error(&o, "crusty");
    let err = stderr(&o);
    for known in [
        "slightly",
        "completely",
        "rusty",
        "scratched",
        "mossy",
        "streaked",
        "ground",
    ] {
        assert!(err.contains(known), "{known} missing: {err}");
    }
    assert!(!out.exists());
}

#[test]
fn preset_default_documents_the_new_sections() {
    let o = grime(&["preset", "default"]);
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout);
    for section in [
        "[scratches]",
        "[splotches]",
        "[stains]",
        "[mould]",
        "[rust]",
        "[smudges]",
        "[corrosion]",
        "[climate]",
        "[spotty]",
        "[roughy]",
        "[fade]",
        "[desaturate]",
    ] {
        assert!(text.contains(section), "{section} missing");
    }
    for doc in [
        "Fraction of the placement area covered",
        "Sun azimuth",
        "eq. 3.12",
        "Share of a full-weight pixel that is pitted",
        "greasy blur",
    ] {
        assert!(text.contains(doc), "{doc} missing");
    }
}

#[test]
fn smudged_and_corroded_cover_what_they_say_where_they_say() {
    let dir = tempfile::tempdir().unwrap();
    let (out, rep) = (dir.path().join("a.png"), dir.path().join("r.json"));
    let o = grime(&[
        "run",
        "--demo",
        "-o",
        s(&out),
        "--layers",
        "1",
        "--say",
        "somewhat smudged near the ground, very corroded at the edges",
        "--report",
        s(&rep),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let r = report(&rep);
    for (name, want, place) in [("smudges", 0.2, "ground"), ("corrosion", 0.55, "edges")] {
        let (target, got) = coverage(&r, name);
        assert_eq!(target as f32, want as f32);
        assert!((got - want).abs() <= 0.02, "{name}: {got}");
        let g = r["imperfections"]["generators"]
            .as_array()
            .unwrap()
            .iter()
            .find(|g| g["name"] == name)
            .unwrap();
        assert_eq!(g["placement"], place);
    }
}
