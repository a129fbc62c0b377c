//! The command language of Becket & Badler: a sentence such as
//! `very rusty near the railings, slightly scratched, moderately mossy`
//! sets which effects run, how much of the wall they cover and where.
//!
//! Each clause is `[adverb] effect [place]`. The adverb is a coverage, by
//! the paper's table ([`ADVERBS`]); the imperfections take it as their
//! `coverage` (they calibrate their output to it), the other effects as a
//! proportional change of their own strength field ([`Target`]). The
//! sentence becomes preset assignments ([`assignments`]), so the CLI, a
//! preset's `say` and the GUI's text box all set the same sliders.

use crate::error::{Error, Result};
use crate::preset::Preset;

/// Adverbs and their coverage (Becket & Badler's table). "heavily" and
/// "lightly" are grime's synonyms of "very" and "slightly" [choice: for
/// rain, "heavily streaked" reads better than "very streaked"].
pub const ADVERBS: &[(&str, f32)] = &[
    ("slightly", 0.05),
    ("lightly", 0.05),
    ("partially", 0.10),
    ("somewhat", 0.20),
    ("moderately", 0.35),
    ("very", 0.55),
    ("heavily", 0.55),
    ("extremely", 0.75),
    ("completely", 1.00),
];

/// The coverage of a clause without an adverb.
pub const NO_ADVERB: f32 = 0.25;

/// What an effect word sets.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Target {
    /// An imperfection section: `enabled`, `coverage`, `placement`.
    Imperfection(&'static str),
    /// A weathering generator: `enabled` and `years = 40 c` (0.25 = its
    /// default 10 years).
    Generator(&'static str),
    /// An integer field scaled so that no adverb (0.25) gives its default:
    /// `field = round(c * per_coverage)`.
    Scaled(&'static str, &'static str, f32),
}

/// Effect words (adjectives) and what they set.
const EFFECTS: &[(&str, Target)] = &[
    ("scratched", Target::Imperfection("scratches")),
    ("splotched", Target::Imperfection("splotches")),
    ("muddy", Target::Imperfection("splotches")),
    ("stained", Target::Imperfection("stains")),
    ("mouldy", Target::Imperfection("mould")),
    ("moldy", Target::Imperfection("mould")),
    ("rusty", Target::Imperfection("rust")),
    ("smudged", Target::Imperfection("smudges")),
    ("smudgy", Target::Imperfection("smudges")),
    ("greasy", Target::Imperfection("smudges")),
    ("corroded", Target::Imperfection("corrosion")),
    ("pitted", Target::Imperfection("corrosion")),
    ("decayed", Target::Imperfection("corrosion")),
    ("spotted", Target::Generator("spotty")),
    ("spotty", Target::Generator("spotty")),
    ("weathered", Target::Generator("roughy")),
    ("yellowed", Target::Generator("fade")),
    ("faded", Target::Generator("desaturate")),
    // Rain: 12 rainfalls at 0.25 (the default), 48 completely.
    ("streaked", Target::Scaled("rain", "layers", 48.0)),
    ("rainy", Target::Scaled("rain", "layers", 48.0)),
    // Moss: candidate sites per year, 0.3 at 0.25 (the default).
    ("mossy", Target::Scaled("moss", "seed_rate", 1.2)),
    // Dust: 15 years at 0.25 (the default), sixty completely.
    ("dusty", Target::Scaled("dust", "days", 21900.0)),
];

/// Place phrases (after "near", "at", "below", ... and "the") and the
/// placement they name.
const PLACES: &[(&str, &str)] = &[
    ("edges", "edges"),
    ("edge", "edges"),
    ("top", "top"),
    ("bottom", "bottom"),
    ("ground", "ground"),
    ("foot", "ground"),
    ("sills", "sills"),
    ("sill", "sills"),
    ("windows", "sills"),
    ("railings", "railings"),
    ("railing", "railings"),
    ("balconies", "railings"),
    ("metal", "railings"),
    ("everywhere", "everywhere"),
    ("area", "area"),
];

/// Words that introduce a place, and words the sentence may use freely.
const PREPOSITIONS: &[&str] = &[
    "near", "at", "along", "below", "under", "around", "on", "in", "by", "over", "all",
];
const FILLERS: &[&str] = &[
    "and", "the", "a", "is", "it", "make", "wall", "facade", "painted",
];

/// What a sentence says: preset assignments (`path`, `value`, as `--set`
/// takes them) in order, and notes on words that set nothing.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Said {
    /// The assignments.
    pub set: Vec<(String, String)>,
    /// What the user should know (a place an effect cannot take yet).
    pub notes: Vec<String>,
}

/// The preset assignments a sentence makes, in order ([`parse`]'s).
///
/// # Errors
/// As [`parse`].
pub fn assignments(sentence: &str) -> Result<Vec<(String, String)>> {
    Ok(parse(sentence)?.set)
}

/// Reads a sentence.
///
/// ```
/// let set = grime::say::assignments("very rusty near the railings, slightly scratched").unwrap();
/// assert!(set.contains(&("rust.coverage".into(), "0.55".into())));
/// assert!(set.contains(&("rust.placement".into(), "\"railings\"".into())));
/// assert!(set.contains(&("scratches.coverage".into(), "0.05".into())));
/// ```
///
/// # Errors
/// [`Error::Say`] for a word grime does not know (listing the words it
/// knows), a clause without an effect word, or a point without two numbers.
pub fn parse(sentence: &str) -> Result<Said> {
    let mut out = Said::default();
    for clause in sentence.split([',', ';', '.']) {
        let words: Vec<String> = clause
            .split_whitespace()
            .map(|w| w.to_lowercase())
            .collect();
        // "and" joins clauses too: "rusty and scratched".
        for part in words.split(|w| w == "and") {
            if !part.is_empty() {
                clause_assignments(part, &mut out)?;
            }
        }
    }
    Ok(out)
}

fn clause_assignments(words: &[String], out: &mut Said) -> Result<()> {
    let mut coverage = None;
    let mut target = None;
    let mut place = None;
    let mut around: Vec<f32> = Vec::new();
    for w in words {
        let w = w.as_str();
        if let Some((_, c)) = ADVERBS.iter().find(|(a, _)| *a == w) {
            coverage = Some(*c);
        } else if let Some((_, t)) = EFFECTS.iter().find(|(e, _)| *e == w) {
            target = Some((w, *t));
        } else if let Some((_, p)) = PLACES.iter().find(|(p, _)| *p == w) {
            place = Some(*p);
        } else if let Ok(v) = w.parse::<f32>() {
            // "around 120 340": a point in photo pixels.
            around.push(v);
            place = Some("point");
        } else if !PREPOSITIONS.contains(&w) && !FILLERS.contains(&w) {
            return Err(Error::Say(format!(
                "unknown word {w:?}; grime knows the adverbs {}, the effects {}, and the places {} (after near, at, below, around, ...; \"around X Y\" for a point in pixels)",
                list(ADVERBS.iter().map(|a| a.0)),
                list(EFFECTS.iter().map(|e| e.0)),
                list(PLACES.iter().map(|p| p.0)),
            )));
        }
    }
    let Some((word, target)) = target else {
        return Err(Error::Say(format!(
            "{:?} names no effect; say one of {}",
            words.join(" "),
            list(EFFECTS.iter().map(|e| e.0)),
        )));
    };
    let c = coverage.unwrap_or(NO_ADVERB);
    let mut set = |path: String, value: String| out.set.push((path, value));
    match target {
        Target::Imperfection(s) => {
            set(format!("{s}.enabled"), "true".into());
            set(format!("{s}.coverage"), fmt(c));
            if let Some(p) = place {
                set(format!("{s}.placement"), format!("\"{p}\""));
            }
            if let [x, y] = around[..] {
                set(format!("{s}.around"), format!("[{}, {}]", fmt(x), fmt(y)));
            } else if !around.is_empty() {
                return Err(Error::Say(format!(
                    "\"{word}\": around takes two numbers, x and y in pixels"
                )));
            }
        }
        Target::Generator(s) => {
            set(format!("{s}.enabled"), "true".into());
            set(format!("{s}.years"), fmt(40.0 * c));
        }
        Target::Scaled(s, field, per) => {
            if s != "rain" {
                set(format!("{s}.enabled"), "true".into());
            }
            let v = c * per;
            let v = if field == "seed_rate" {
                fmt(v)
            } else {
                (v.round() as i64).to_string()
            };
            set(format!("{s}.{field}"), v);
        }
    }
    if let (Some(p), Target::Generator(_) | Target::Scaled(..)) = (place, target) {
        out.notes.push(format!(
            "\"{word}\": the place ({p}) sets nothing; this effect places itself (by the rain's water, light or humidity)"
        ));
    }
    Ok(())
}

fn fmt(x: f32) -> String {
    format!("{x}")
}

fn list<'a>(words: impl Iterator<Item = &'a str>) -> String {
    words.collect::<Vec<_>>().join(", ")
}

/// Applies a sentence to `preset`: its assignments through
/// [`Preset::set`] (so each is validated), and the sentence kept in
/// `preset.say`. Returns what it said, for showing.
///
/// # Errors
/// As [`assignments`], and [`Preset::set`]'s errors.
pub fn apply(preset: &mut Preset, sentence: &str) -> Result<Said> {
    let said = parse(sentence)?;
    let mut next = preset.clone();
    for (path, value) in &said.set {
        next.set(&format!("{path}={value}"))?;
    }
    next.say = sentence.to_string();
    *preset = next;
    Ok(said)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_issue_sentence_sets_rust_scratches_and_moss() {
        let mut p = Preset::default();
        apply(
            &mut p,
            "very rusty near the railings, slightly scratched, moderately mossy near the ground",
        )
        .unwrap();
        assert!(p.rust.enabled && p.scratches.enabled && p.moss.enabled);
        assert_eq!(p.rust.coverage, 0.55);
        assert_eq!(p.rust.placement, crate::preset::Placement::Railings);
        assert_eq!(p.scratches.coverage, 0.05);
        assert_eq!(p.moss.seed_rate, 0.35 * 1.2);
    }

    #[test]
    fn no_adverb_is_a_quarter_and_gives_the_defaults_of_scaled_effects() {
        let mut p = Preset::default();
        apply(&mut p, "streaked and dusty, stained below the sills").unwrap();
        assert_eq!(p.rain.layers, Preset::default().rain.layers);
        assert_eq!(p.dust.days, Preset::default().dust.days);
        assert_eq!(p.stains.coverage, NO_ADVERB);
        let p2 = {
            let mut p = Preset::default();
            apply(&mut p, "heavily streaked").unwrap();
            p
        };
        assert!(p2.rain.layers > p.rain.layers);
    }

    #[test]
    fn an_unknown_word_lists_the_known_ones() {
        let e = assignments("very crusty").unwrap_err().to_string();
        assert!(e.contains("\"crusty\""), "{e}");
        for known in [
            "slightly",
            "completely",
            "rusty",
            "mossy",
            "streaked",
            "railings",
        ] {
            assert!(e.contains(known), "{known} missing from: {e}");
        }
        assert!(assignments("very near the ground").is_err());
        let said = parse("moderately mossy near the ground").unwrap();
        assert_eq!(said.notes.len(), 1, "{said:?}");
    }

    #[test]
    fn smudged_and_corroded_set_their_generators() {
        let mut p = Preset::default();
        apply(
            &mut p,
            "slightly smudged near the ground and extremely corroded at the edges",
        )
        .unwrap();
        assert!(p.smudges.enabled && p.corrosion.enabled);
        assert_eq!((p.smudges.coverage, p.corrosion.coverage), (0.05, 0.75));
        assert_eq!(p.corrosion.placement, crate::preset::Placement::Edges);
        let e = assignments("very crusty").unwrap_err().to_string();
        assert!(e.contains("smudged") && e.contains("corroded"), "{e}");
    }

    #[test]
    fn a_point_takes_two_numbers() {
        let set = assignments("mouldy around 120 340").unwrap();
        assert!(set.contains(&("mould.around".into(), "[120, 340]".into())));
        assert!(set.contains(&("mould.placement".into(), "\"point\"".into())));
        assert!(assignments("mouldy around 120").is_err());
    }
}
