//! One clock for every effect: `age.years` (or `--years`) sets the number
//! of rainfalls, the years of moss and the days of dust from the rates in
//! the preset's `[age]` section.
//!
//! Which value wins, from strongest to weakest:
//! 1. a field pinned by the user: given on the command line (`--layers`,
//!    `--set rain.layers=…`, `--set moss.years=…`, `--set dust.days=…`) or
//!    written in the preset file itself;
//! 2. the clock, when `age.years` is set: `round(years × rate)`;
//! 3. the field's value in the preset (a built-in preset's, or the default).
//!
//! With `age.years` unset nothing changes. A resolved preset keeps
//! `age.years`, so a recipe records the age it was made at; its fields are
//! all written out, so re-running it gives the same numbers.

use crate::error::{Error, Result};
use crate::preset::{AgeParams, PARAMS, Preset};

/// The preset fields the clock sets, by dotted path.
pub const FIELDS: [&str; 3] = ["rain.layers", "moss.years", "dust.days"];

/// Which of [`FIELDS`] the user gave explicitly (they win over the clock).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Pins([bool; 3]);

impl Pins {
    /// Nothing pinned: the clock sets all three.
    pub fn none() -> Pins {
        Pins::default()
    }

    /// The fields among `keys` (dotted paths, e.g. `--set` keys).
    pub fn of_keys<'a>(keys: impl IntoIterator<Item = &'a str>) -> Pins {
        let mut pins = Pins::none();
        for key in keys {
            if let Some(i) = FIELDS.iter().position(|f| *f == key.trim()) {
                pins.0[i] = true;
            }
        }
        pins
    }

    /// The fields a preset file writes (its TOML text).
    pub fn in_toml(text: &str) -> Pins {
        let Ok(table) = text.parse::<toml::Table>() else {
            return Pins::none();
        };
        Pins::of_keys(FIELDS.into_iter().filter(|path| {
            let (section, key) = path.split_once('.').unwrap_or(("", path));
            table.get(section).and_then(|s| s.get(key)).is_some()
        }))
    }

    /// Both pins' fields.
    pub fn union(self, other: Pins) -> Pins {
        Pins(std::array::from_fn(|i| self.0[i] || other.0[i]))
    }

    /// Whether `path` (one of [`FIELDS`]) is pinned.
    pub fn pins(self, path: &str) -> bool {
        FIELDS
            .iter()
            .position(|f| *f == path)
            .is_some_and(|i| self.0[i])
    }
}

/// `round(years × rate)` for each of [`FIELDS`], in that order.
pub fn counts(age: &AgeParams, years: u32) -> [f64; 3] {
    [
        age.rainfalls_per_year,
        age.moss_years_per_year,
        age.dust_days_per_year,
    ]
    .map(|rate| (years as f64 * rate as f64).round())
}

/// `preset` with the clock applied: when `age.years` is set, each field of
/// [`FIELDS`] that `pins` leaves free is set from its rate.
///
/// # Errors
/// [`Error::OutOfRange`] naming `age.years` when a count would leave its
/// field's range (say, too many rainfalls).
pub fn resolve(preset: &Preset, pins: Pins) -> Result<Preset> {
    let mut out = preset.clone();
    let Some(years) = preset.age.years else {
        return Ok(out);
    };
    for (path, n) in FIELDS.into_iter().zip(counts(&preset.age, years)) {
        if pins.pins(path) {
            continue;
        }
        let max = PARAMS
            .iter()
            .find(|s| s.path == path)
            .map_or(f64::MAX, |s| s.max);
        if !(0.0..=max).contains(&n) {
            return Err(Error::OutOfRange {
                field: "age.years".into(),
                value: years.to_string(),
                range: format!(
                    "one giving {path} = {n} within 0 ..= {max}; lower the year or its rate in [age]"
                ),
            });
        }
        let n = n as u32;
        match path {
            "rain.layers" => out.rain.layers = n,
            "moss.years" => out.moss.years = n,
            _ => out.dust.days = n,
        }
    }
    Ok(out)
}

/// The fields of `preset` that differ from what its clock gives (so were
/// set over it); none when `age.years` is unset.
pub fn pins_of(preset: &Preset) -> Pins {
    let Some(years) = preset.age.years else {
        return Pins::none();
    };
    let have = [preset.rain.layers, preset.moss.years, preset.dust.days];
    let clock = counts(&preset.age, years);
    Pins(std::array::from_fn(|i| have[i] as f64 != clock[i]))
}

/// Parses a preset file and applies its clock, the counts it writes pinned.
///
/// # Errors
/// As [`Preset::from_toml`] and [`resolve`].
pub fn load(text: &str) -> Result<Preset> {
    resolve(&Preset::from_toml(text)?, Pins::in_toml(text))
}

/// The value the clock gives `path` (one of [`FIELDS`]) at `preset`'s
/// age; `None` for another field or with the clock off.
pub fn free_value(preset: &Preset, path: &str) -> Option<i64> {
    let i = FIELDS.iter().position(|f| *f == path)?;
    Some(counts(&preset.age, preset.age.years?)[i] as i64)
}

/// `preset` at `years` of age: [`resolve`] with `age.years = years`.
///
/// # Errors
/// As [`resolve`].
pub fn at(preset: &Preset, years: u32, pins: Pins) -> Result<Preset> {
    let mut p = preset.clone();
    p.age.years = Some(years);
    resolve(&p, pins)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_rates_give_the_default_preset_at_15_years() {
        let p = at(&Preset::default(), 15, Pins::none()).unwrap();
        let d = Preset::default();
        assert_eq!(
            (p.rain.layers, p.moss.years, p.dust.days),
            (d.rain.layers, d.moss.years, d.dust.days)
        );
        let p = at(&d, 30, Pins::none()).unwrap();
        assert_eq!((p.rain.layers, p.moss.years, p.dust.days), (24, 30, 10950));
        let p = at(&d, 0, Pins::none()).unwrap();
        assert_eq!((p.rain.layers, p.moss.years, p.dust.days), (0, 0, 0));
    }

    #[test]
    fn unset_years_change_nothing_and_pins_win_over_the_clock() {
        let mut p = Preset::default();
        p.rain.layers = 5;
        assert_eq!(resolve(&p, Pins::none()).unwrap(), p);
        p.age.years = Some(30);
        let pins = Pins::of_keys(["rain.layers"]);
        let r = resolve(&p, pins).unwrap();
        assert_eq!((r.rain.layers, r.moss.years, r.dust.days), (5, 30, 10950));
        // Resolving again changes nothing: a recipe re-runs the same.
        assert_eq!(resolve(&r, pins).unwrap(), r);
        assert_eq!(pins_of(&r), pins);
    }

    #[test]
    fn a_preset_file_pins_what_it_writes() {
        let pins = Pins::in_toml("[rain]\nlayers = 3\n[dust]\nenvironment = \"desktop\"\n");
        assert!(pins.pins("rain.layers"));
        assert!(!pins.pins("dust.days") && !pins.pins("moss.years"));
        assert_eq!(Pins::in_toml("[age]\nyears = 3\n"), Pins::none());
    }

    #[test]
    fn too_many_years_name_the_clock() {
        let mut p = Preset::default();
        p.age.rainfalls_per_year = 1.0;
        let err = at(&p, 250, Pins::none()).unwrap_err();
        assert!(err.to_string().contains("age.years"), "{err}");
    }
}
