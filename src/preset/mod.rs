//! Presets: every tunable number of every effect, as one TOML document.
//!
//! A [`Preset`] is what the user writes (TOML, `--set key=value`, GUI
//! sliders). [`Preset::validate`] checks every numeric field against the
//! [`PARAMS`] table, so the error names the field and its allowed range. The
//! same table documents each field (`grime preset default`) and gives the GUI
//! its slider ranges and tooltips, so the three cannot drift apart.

mod params;

pub use params::{PARAMS, ParamSpec, param};

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// A complete, serialisable set of parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Preset {
    /// Master seed; every random stream is derived from it.
    pub seed: u64,
    /// Simulation grid.
    pub sim: SimParams,
    /// Rain streaks (Chang et al. eqs. 1-17).
    pub rain: RainParams,
    /// How rain dirt is drawn onto the photo.
    pub stain: StainParams,
}

impl Default for Preset {
    fn default() -> Self {
        Preset {
            seed: 1,
            sim: SimParams::default(),
            rain: RainParams::default(),
            stain: StainParams::default(),
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

/// A polyline in photo pixel coordinates that water drips from.
pub type SourceLine = Vec<[f32; 2]>;

/// Rain parameters. Symbols follow Chang, Yoshida & Mukai.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RainParams {
    /// Number of rainfalls (layers).
    pub layers: u32,
    /// Droplets per layer on a wall `reference_width` grid pixels wide.
    pub droplets: u32,
    /// Wall width the droplet count refers to; 0 = use `droplets` as is.
    pub reference_width: u32,
    /// Upper bound of the first layer's droplet mass, m ~ U(0, mass_max).
    pub mass_max: f32,
    /// Droplets lighter than this are removed.
    pub mass_min: f32,
    /// Spread of droplet mass and start position between layers (eqs. 16-17).
    pub sigma: f32,
    /// Wall absorption rate k_a (eqs. 5-6).
    pub k_a: f32,
    /// Deposition rate k_S; dissolution k_D = 1 - k_S (eqs. 7-8).
    pub k_s: f32,
    /// Saturation a: water one grid pixel can hold.
    pub saturation: f32,
    /// Evaporation I_sun per diffusion round, per pixel.
    pub i_sun: f32,
    /// User roughness r (eqs. 3-4).
    pub r: f32,
    /// Largest roughness r_max.
    pub r_max: f32,
    /// Sideways scatter constant b (eq. 2).
    pub b: f32,
    /// Gravity g, grid px per step squared.
    pub g: f32,
    /// Wall resistance rho (eq. 4).
    pub rho: f32,
    /// Speed limit, grid px per step (keeps streaks gap-free).
    pub v_max: f32,
    /// Exchange time per step for eqs. 5-8.
    pub dt: f32,
    /// Safety cap on steps per droplet.
    pub max_steps: u32,
    /// Amplitude of the initial dirt I_D0 (noise in 0..initial_dirt).
    pub initial_dirt: f32,
    /// Feature size of the initial-dirt noise, in grid pixels.
    pub initial_dirt_scale: f32,
    /// Dirt a droplet carries when it leaves its source (washed off the ledge).
    pub ledge_dirt: f32,
    /// Carry-over rate delta between layers (eqs. 13-14).
    pub delta: f32,
    /// Surface raise eps from deposited dirt, fraction of full scale (eq. 15).
    pub eps: f32,
    /// Diffusion rate tau per neighbour (eqs. 9-10); at most 1/8.
    pub tau: f32,
    /// Diffusion rounds per layer (spread over the rainfall).
    pub diffusion_rounds: u32,
    /// Relaxation iterations per round.
    pub diffusion_iterations: u32,
    /// How strongly dirt follows diffusing water, 0..1.
    pub dirt_coupling: f32,
    /// Whether the top edge of the region is a water source.
    pub top_edge: bool,
    /// Extra water sources: polylines in photo pixels (sills, cornices).
    pub source_lines: Vec<SourceLine>,
}

impl Default for RainParams {
    fn default() -> Self {
        RainParams {
            layers: 12,
            droplets: 600,
            reference_width: 1000,
            mass_max: 120.0,
            mass_min: 0.5,
            sigma: 10.0,
            k_a: 0.5,
            k_s: 0.7,
            saturation: 0.3,
            i_sun: 0.01,
            r: 100.0,
            r_max: 100.0,
            b: 0.02,
            g: 0.15,
            rho: 3.0,
            v_max: 1.0,
            dt: 0.01,
            max_steps: 20_000,
            initial_dirt: 5.0,
            initial_dirt_scale: 48.0,
            ledge_dirt: 3.0,
            delta: 0.01,
            eps: 0.3,
            tau: 0.1,
            diffusion_rounds: 2,
            diffusion_iterations: 3,
            dirt_coupling: 0.5,
            top_edge: true,
            source_lines: Vec::new(),
        }
    }
}

/// How each rainfall's dirt is drawn onto the photo.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StainParams {
    /// Colour of the dirt, sRGB.
    pub color: [u8; 3],
    /// Opacity of each rain layer.
    pub opacity: f32,
    /// Stain strength: alpha = strength * D / D_max.
    pub strength: f32,
    /// Percentile of the first rainfall's deposits that defines D_max.
    pub percentile: f32,
    /// Blur radius of the stain edge, grid pixels.
    pub softness: f32,
}

impl Default for StainParams {
    fn default() -> Self {
        StainParams {
            color: [62, 54, 44],
            opacity: 0.8,
            strength: 0.6,
            percentile: 0.99,
            softness: 0.8,
        }
    }
}

impl Preset {
    /// Parses a TOML preset and validates it.
    ///
    /// # Errors
    /// [`Error::Preset`] for bad TOML or unknown fields,
    /// [`Error::OutOfRange`] for a value outside its documented range.
    pub fn from_toml(text: &str) -> Result<Preset> {
        let preset: Preset = toml::from_str(text).map_err(|e| Error::Preset(one_line(&e)))?;
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
        let value = toml::Value::try_from(self).map_err(|e| Error::Preset(e.to_string()))?;
        for spec in PARAMS {
            let Some(v) = lookup(&value, spec.path) else {
                continue;
            };
            let x = match v {
                toml::Value::Integer(i) => *i as f64,
                toml::Value::Float(f) => *f,
                _ => continue,
            };
            if !(x.is_finite() && x >= spec.min && x <= spec.max) {
                return Err(Error::OutOfRange {
                    field: spec.path.to_string(),
                    value: v.to_string(),
                    range: format!("{} ..= {}", spec.min, spec.max),
                });
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
        let slot = lookup_mut(&mut value, key)
            .ok_or_else(|| Error::Preset(format!("--set: unknown field {key:?}; see `grime preset default`")))?;
        // Keep floats floats: `--set rain.k_a=1` means 1.0.
        *slot = match (&*slot, parsed) {
            (toml::Value::Float(_), toml::Value::Integer(i)) => toml::Value::Float(i as f64),
            (_, p) => p,
        };
        let next: Preset = value
            .try_into()
            .map_err(|e: toml::de::Error| Error::Preset(format!("--set {key}: {}", one_line(&e))))?;
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
        // Top-level scalars first, then one [section] per table.
        for (k, v) in root.iter().filter(|(_, v)| !v.is_table()) {
            push_field(&mut out, k, k, v);
        }
        for (section, v) in root.iter().filter(|(_, v)| v.is_table()) {
            out.push_str(&format!("\n[{section}]\n"));
            if let toml::Value::Table(t) = v {
                for (k, v) in t {
                    push_field(&mut out, &format!("{section}.{k}"), k, v);
                }
            }
        }
        out
    }
}

fn push_field(out: &mut String, path: &str, key: &str, v: &toml::Value) {
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
    out.push_str(&format!("{key} = {v}\n"));
}

fn lookup<'a>(v: &'a toml::Value, path: &str) -> Option<&'a toml::Value> {
    path.split('.').try_fold(v, |v, k| v.get(k))
}

fn lookup_mut<'a>(v: &'a mut toml::Value, path: &str) -> Option<&'a mut toml::Value> {
    path.split('.').try_fold(v, |v, k| v.get_mut(k))
}

fn one_line(e: &impl std::fmt::Display) -> String {
    e.to_string().split_whitespace().collect::<Vec<_>>().join(" ")
}

/// Built-in presets, by name: what `grime preset NAME` prints and
/// `--preset NAME` loads.
pub const BUILTIN: &[(&str, &str)] = &[
    ("default", "the defaults: 12 rainfalls"),
    ("chang-table1", "the paper's Table 1 values (k_S 0.7, k_a 0.5, 600 droplets, r 100)"),
    ("light-rain", "4 rainfalls, a recently weathered wall"),
    ("heavy-rain", "20 rainfalls, wetter and dirtier"),
];

/// Returns a built-in preset by name.
///
/// # Errors
/// [`Error::Preset`] listing the known names.
pub fn builtin(name: &str) -> Result<Preset> {
    let mut p = Preset::default();
    match name {
        "default" => {}
        "chang-table1" => {
            p.rain.reference_width = 0;
            p.rain.droplets = 600;
            p.rain.k_s = 0.7;
            p.rain.k_a = 0.5;
            p.rain.r = 100.0;
        }
        "light-rain" => p.rain.layers = 4,
        "heavy-rain" => {
            p.rain.layers = 20;
            p.rain.droplets = 900;
            p.rain.ledge_dirt = 4.0;
            p.rain.mass_max = 160.0;
        }
        _ => {
            let names: Vec<_> = BUILTIN.iter().map(|(n, _)| *n).collect();
            return Err(Error::Preset(format!(
                "unknown preset {name:?}; built-in presets: {}; or pass a .toml file",
                names.join(", ")
            )));
        }
    }
    Ok(p)
}
