//! Presets: every tunable number of every effect, as one TOML document.
//!
//! A [`Preset`] is what the user writes (TOML, `--set key=value`, GUI
//! sliders). [`Preset::validate`] checks every numeric field against the
//! [`PARAMS`] table, so the error names the field and its allowed range. The
//! same table documents each field (`grime preset default`) and gives the GUI
//! its slider ranges and tooltips, so the three cannot drift apart.

mod age;
mod builtin;
mod diff;
mod dust;
mod foot;
mod gammaton;
mod imperfections;
mod moss;
mod params;
mod params_dust;
mod rain;
mod scaled;
mod sections;
mod smudges;
mod table;
mod toml_text;
mod weathering;

pub use age::AgeParams;
pub use builtin::{BUILTIN, builtin};
pub use diff::diff_paths;
pub use dust::{DustEnvironment, DustParams, Segment};
pub use foot::FootParams;
pub use gammaton::{
    GammaSource, GammatonParams, MAX_SUBSTANCES, Rule, RuleKind, SourceKind, Stop, Substance,
};
pub use imperfections::{
    BlotchParams, Imperfection, MouldParams, Place, Placement, RustParams, ScratchParams,
};
pub use moss::{MossColor, MossParams};
pub use params::{ParamSpec, param};
pub use rain::{RainParams, SourceLine, StainParams};
pub use smudges::{CorrosionParams, SmudgeParams};
pub use table::PARAMS;
pub use weathering::{ClimateParams, GeneratorParams};

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use toml_text::{
    insert_missing, is_integer_text, leaves, lookup_mut, one_line, push_field, push_unset,
    toml_literal,
};

/// A complete, serialisable set of parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Preset {
    /// Master seed; every random stream is derived from it.
    pub seed: u64,
    /// The one clock: age in years and each effect's rate per year.
    pub age: AgeParams,
    /// Simulation grid.
    pub sim: SimParams,
    /// Rain streaks (Chang et al. eqs. 1-17).
    pub rain: RainParams,
    /// How rain dirt is drawn onto the photo.
    pub stain: StainParams,
    /// Moss colonies where the wall stays wet and dirty (Chang eq. 18).
    pub moss: MossParams,
    /// Dust settling over days (Santos & Baranoski eqs. 1-11).
    pub dust: DustParams,
    /// γ-tons: substances carried over the wall (Chen et al., Stadler).
    pub gammaton: GammatonParams,
    /// The sentence that set this preset's starting point (`--say`): it is
    /// applied to the defaults, then the fields written here win.
    pub say: String,
    /// Scratches (Becket & Badler).
    pub scratches: ScratchParams,
    /// Splotches of mud or tar (Becket & Badler).
    #[serde(deserialize_with = "sections::splotches")]
    pub splotches: BlotchParams,
    /// Water stains (Becket & Badler).
    #[serde(deserialize_with = "sections::stains")]
    pub stains: BlotchParams,
    /// Mould (Becket & Badler).
    pub mould: MouldParams,
    /// Rust (Becket & Badler).
    pub rust: RustParams,
    /// Smudges (Becket & Badler: fBm as a weight).
    pub smudges: SmudgeParams,
    /// Corrosion (Becket & Badler: fBm as a weight).
    pub corrosion: CorrosionParams,
    /// Sun and humidity (Riihiaho eqs. 3.5-3.8).
    pub climate: ClimateParams,
    /// Soil splashed up the wall's foot, and the rising-damp tide mark.
    pub foot: FootParams,
    /// Spotty (Riihiaho eq. 3.12).
    #[serde(deserialize_with = "sections::spotty")]
    pub spotty: GeneratorParams,
    /// Roughy (Riihiaho eq. 3.13).
    #[serde(deserialize_with = "sections::roughy")]
    pub roughy: GeneratorParams,
    /// Fade Towardy (Riihiaho eqs. 3.14-3.15).
    #[serde(deserialize_with = "sections::fade")]
    pub fade: GeneratorParams,
    /// Desaturaty (Riihiaho sec. 3.3.4).
    #[serde(deserialize_with = "sections::desaturate")]
    pub desaturate: GeneratorParams,
}

impl Default for Preset {
    fn default() -> Self {
        Preset {
            seed: 1,
            age: AgeParams::default(),
            sim: SimParams::default(),
            rain: RainParams::default(),
            stain: StainParams::default(),
            moss: MossParams::default(),
            dust: DustParams::default(),
            gammaton: GammatonParams::default(),
            say: String::new(),
            scratches: ScratchParams::default(),
            splotches: BlotchParams::splotches(),
            stains: BlotchParams::stains(),
            mould: MouldParams::default(),
            rust: RustParams::default(),
            smudges: SmudgeParams::default(),
            corrosion: CorrosionParams::default(),
            climate: ClimateParams::default(),
            foot: FootParams::default(),
            spotty: GeneratorParams::spotty(),
            roughy: GeneratorParams::roughy(),
            fade: GeneratorParams::fade(),
            desaturate: GeneratorParams::desaturate(),
        }
    }
}

/// Where the simulation runs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SimParams {
    /// Longest side of the simulation grid in pixels; 0 = photo resolution.
    pub max_side: u32,
}

impl Default for SimParams {
    fn default() -> Self {
        SimParams { max_side: 1024 }
    }
}

impl Preset {
    /// Parses a TOML preset and validates it.
    ///
    /// # Errors
    /// [`Error::Preset`] for bad TOML or unknown fields,
    /// [`Error::OutOfRange`] for a value outside its documented range,
    /// [`Error::Say`] for a `say` sentence grime cannot read.
    pub fn from_toml(text: &str) -> Result<Preset> {
        let table: toml::Table = toml::from_str(text).map_err(|e| Error::Preset(one_line(&e)))?;
        let preset: Preset = match table.get("say").and_then(toml::Value::as_str) {
            Some(s) if !s.trim().is_empty() => sections::with_say(table)?,
            _ => toml::from_str(text).map_err(|e| Error::Preset(one_line(&e)))?,
        };
        preset.validate()?;
        Ok(preset)
    }

    /// Serialises to TOML (no comments; see [`Preset::to_commented_toml`]).
    pub fn to_toml(&self) -> String {
        toml::to_string(self).unwrap_or_default()
    }

    /// Checks every numeric field against [`PARAMS`] and the structural rules.
    ///
    /// # Errors
    /// [`Error::OutOfRange`] naming the first offending field and its range.
    pub fn validate(&self) -> Result<()> {
        // TOML integers are i64: a larger seed could not be saved as a preset.
        if self.seed > i64::MAX as u64 {
            return Err(Error::OutOfRange {
                field: "seed".into(),
                value: self.seed.to_string(),
                range: format!("0 ..= {}", i64::MAX),
            });
        }
        let value = toml::Value::try_from(self).map_err(|e| Error::Preset(e.to_string()))?;
        for spec in PARAMS {
            let keys: Vec<&str> = spec.path.split('.').collect();
            let mut found = Vec::new();
            leaves(&value, &keys, &mut found);
            for v in found {
                let x = match v {
                    toml::Value::Integer(i) => *i as f64,
                    toml::Value::Float(f) => *f,
                    _ => continue,
                };
                if !(x.is_finite() && x >= spec.min && x <= spec.max) {
                    let value = match v {
                        toml::Value::Float(f) => (*f as f32).to_string(),
                        other => other.to_string(),
                    };
                    return Err(Error::OutOfRange {
                        field: spec.path.to_string(),
                        value,
                        range: format!("{} ..= {}", spec.min, spec.max),
                    });
                }
            }
        }
        for (i, line) in self.rain.source_lines.iter().enumerate() {
            if line.len() < 2 || line.iter().flatten().any(|c| !c.is_finite()) {
                return Err(Error::OutOfRange {
                    field: format!("rain.source_lines[{i}]"),
                    value: format!("{line:?}"),
                    range: "a polyline of at least 2 finite [x, y] points".into(),
                });
            }
        }
        if self.rain.r > self.rain.r_max {
            return Err(Error::OutOfRange {
                field: "rain.r".into(),
                value: self.rain.r.to_string(),
                range: format!("0 ..= rain.r_max ({})", self.rain.r_max),
            });
        }
        if self.rain.mass_min >= self.rain.mass_max {
            return Err(Error::OutOfRange {
                field: "rain.mass_min".into(),
                value: self.rain.mass_min.to_string(),
                range: format!("below rain.mass_max ({})", self.rain.mass_max),
            });
        }
        self.validate_dust()?;
        self.gammaton.validate()
    }

    fn validate_dust(&self) -> Result<()> {
        let d = &self.dust;
        let custom = d.environment == DustEnvironment::Custom;
        for (name, segments) in [
            ("film_segments", &d.film_segments),
            ("mask_segments", &d.mask_segments),
        ] {
            if custom && segments.is_empty() {
                return Err(Error::OutOfRange {
                    field: format!("dust.{name}"),
                    value: "[]".into(),
                    range: "at least one { days, alpha, beta } segment when dust.environment = \"custom\"".into(),
                });
            }
            if !custom && !segments.is_empty() {
                return Err(Error::OutOfRange {
                    field: format!("dust.{name}"),
                    value: format!("{} segment(s)", segments.len()),
                    range:
                        "empty unless dust.environment = \"custom\" (set it to use your own rates)"
                            .into(),
                });
            }
        }
        if d.arc_share + d.clump_share + d.hair_share <= 0.0 {
            return Err(Error::OutOfRange {
                field: "dust.arc_share".into(),
                value: d.arc_share.to_string(),
                range: "arc_share + clump_share + hair_share above 0".into(),
            });
        }
        Ok(())
    }

    /// Sets one field from a `section.key=value` assignment (the CLI's `--set`).
    /// The value is read as a TOML literal; bare words are taken as strings.
    ///
    /// # Errors
    /// [`Error::Preset`] for a malformed assignment or unknown field,
    /// [`Error::OutOfRange`] if the result does not validate.
    pub fn set(&mut self, assignment: &str) -> Result<()> {
        let (key, raw) = assignment.split_once('=').ok_or_else(|| {
            Error::Preset(format!("--set {assignment:?}: expected section.key=value"))
        })?;
        let key = key.trim();
        let raw = raw.trim();
        let parsed: toml::Value = toml::from_str::<toml::Table>(&format!("v = {raw}"))
            .ok()
            .and_then(|mut t| t.remove("v"))
            .unwrap_or_else(|| toml::Value::String(raw.to_string()));
        let mut value = toml::Value::try_from(&*self).map_err(|e| Error::Preset(e.to_string()))?;
        if param(key).is_some() {
            insert_missing(&mut value, key);
        }
        let slot = lookup_mut(&mut value, key).ok_or_else(|| {
            Error::Preset(format!(
                "--set: unknown field {key:?}; see `grime preset default`"
            ))
        })?;
        // A whole number TOML cannot hold (past i64) is out of range, not a
        // string of the wrong type.
        if matches!(parsed, toml::Value::String(_)) && is_integer_text(raw) {
            return Err(Error::OutOfRange {
                field: key.to_string(),
                value: raw.to_string(),
                range: match param(key) {
                    Some(spec) if key != "seed" => format!("{} ..= {}", spec.min, spec.max),
                    _ => format!("0 ..= {}", i64::MAX),
                },
            });
        }
        // Keep floats floats: `--set rain.k_a=1` means 1.0.
        *slot = match (&*slot, parsed) {
            (toml::Value::Float(_), toml::Value::Integer(i)) => toml::Value::Float(i as f64),
            (_, p) => p,
        };
        let next: Preset = value.try_into().map_err(|e: toml::de::Error| {
            Error::Preset(format!("--set {key}: {}", one_line(&e)))
        })?;
        next.validate()?;
        *self = next;
        Ok(())
    }

    /// The preset as TOML with every field documented: meaning, paper symbol
    /// and allowed range. This is what `grime preset default` prints.
    pub fn to_commented_toml(&self) -> String {
        let value = toml::Value::try_from(self).unwrap_or(toml::Value::Table(Default::default()));
        let mut out = String::from(
            "# grime preset. Every field is optional: a missing one takes its default.\n\
             # Ranges are checked on load; an out-of-range value is an error naming the field.\n\
             # Symbols refer to Chang, Yoshida & Mukai, \"Weathering simulation based on a single image\".\n\n",
        );
        let toml::Value::Table(root) = &value else {
            return out;
        };
        let defaults = toml::Value::try_from(Preset::default())
            .unwrap_or(toml::Value::Table(Default::default()));
        // Top-level scalars first, then one [section] per table.
        for (k, v) in root.iter().filter(|(_, v)| !v.is_table()) {
            push_field(&mut out, k, k, v);
        }
        for (section, v) in root.iter().filter(|(_, v)| v.is_table()) {
            out.push_str(&format!("\n[{section}]\n"));
            if let toml::Value::Table(t) = v {
                for (k, v) in t {
                    let path = format!("{section}.{k}");
                    push_field(&mut out, &path, k, v);
                    // A count the clock sets, at the value it would have
                    // anyway (the clock's at this age, or the default), is
                    // written commented out: written, it would pin the
                    // count against `age.years` (crate::clock).
                    let default = defaults.get(section).and_then(|d| d.get(k));
                    let free = crate::clock::FIELDS
                        .contains(&path.as_str())
                        .then(|| {
                            crate::clock::free_value(self, &path)
                                .or(default.and_then(toml::Value::as_integer))
                        })
                        .flatten();
                    if free.is_some() && free == v.as_integer() {
                        let line = format!("{k} = {}\n", toml_literal(v));
                        out.truncate(out.len() - line.len());
                        out.push_str(&format!(
                            "# (left to age.years when that is set; uncomment to keep it)\n# {line}"
                        ));
                    }
                }
                push_unset(&mut out, section, t);
            }
        }
        out
    }
}

#[cfg(test)]
mod tests;
