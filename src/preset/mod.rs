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
mod foot;
mod gammaton;
mod imperfections;
mod params;
mod params_dust;
mod scaled;
mod sections;
mod smudges;
mod table;
mod toml_text;
mod weathering;

pub use age::AgeParams;
pub use builtin::{BUILTIN, builtin};
pub use diff::diff_paths;
pub use foot::FootParams;
pub use gammaton::{
    GammaSource, GammatonParams, MAX_SUBSTANCES, Rule, RuleKind, SourceKind, Stop, Substance,
};
pub use imperfections::{
    BlotchParams, Imperfection, MouldParams, Place, Placement, RustParams, ScratchParams,
};
pub use params::{ParamSpec, param};
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
    /// [choice] Chang's Table 1 draws I_D0 in 0..5; here it is fresh grime
    /// added before every rainfall (eq. 12), and at 5 the droplets dissolve
    /// and re-deposit so much of it that blotches drown the streaks, so the
    /// default is 2 (`chang-table1` keeps 5).
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
    /// Diffusion rounds per layer, spread evenly over its droplets
    /// [choice: one, after the rainfall's droplets; Chang diffuses every
    /// time step and leaves the iteration count open].
    pub diffusion_rounds: u32,
    /// Relaxation iterations per round.
    pub diffusion_iterations: u32,
    /// How strongly dirt follows diffusing water, 0..1.
    pub dirt_coupling: f32,
    /// Whether the top edge of the region is a water source.
    pub top_edge: bool,
    /// Extra water sources: polylines in photo pixels (sills, cornices).
    pub source_lines: Vec<SourceLine>,
    /// Mean spacing of the drip points along a ledge, metres; 0 = water
    /// leaves anywhere along it (Chang's uniform start).
    pub drip_spacing_m: f32,
    /// Share of a ledge's water released at its two ends, 0..1.
    pub end_share: f32,
    /// Width of a release point (a streak's width at its top), metres.
    pub release_width_m: f32,
    /// Fall over which a streak's darkness fades (to a tenth), metres;
    /// 0 = no fading. Under drip points it follows each point's water,
    /// from a third to 4/3 of this (`effects::rain::fall`).
    pub fall_m: f32,
    /// A found ledge's confidence at which its streaks show in full; less
    /// sure ledges show theirs in proportion (`effects::rain::fall`); 0 = all.
    pub sure_at: f32,
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
            initial_dirt: 2.0,
            initial_dirt_scale: 48.0,
            ledge_dirt: 3.0,
            delta: 0.01,
            eps: 0.3,
            tau: 0.1,
            diffusion_rounds: 1,
            diffusion_iterations: 3,
            dirt_coupling: 0.5,
            top_edge: true,
            source_lines: Vec::new(),
            drip_spacing_m: 0.9,
            end_share: 0.5,
            release_width_m: 0.06,
            fall_m: 1.5,
            sure_at: crate::effects::rain::fall::SURE_AT,
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
    /// Blur radius of the stain edge, metres (added to `softness`).
    pub blur_m: f32,
    /// Colour the washed runs lighten toward, sRGB (screen blend).
    pub washed_color: [u8; 3],
    /// Opacity of the washed-runs layer; 0 = no such layer.
    pub washed_opacity: f32,
    /// Share of a full soot film laid under eaves, cornices and balconies
    /// between two rainfalls (the rain shelter); 0 = none.
    pub soot: f32,
    /// The rain's dirt as a deposit painted over the wall (hiding its grain
    /// where thick), with this share of the local wall's own chroma (the
    /// rest `color`'s); 0 = `color` multiplied onto the wall (Chang's).
    pub wall_hue: f32,
    /// The stain's grain (`effects/rain/texture.rs`): the deviation of a
    /// gain on each rainfall's alpha; 0 = smooth, the default (at 0.3 blind
    /// check p25 found its stripes under cornices a comb of drips).
    pub texture: f32,
    /// How far above the region's lower edges the stains run out, metres
    /// (a log-normal length about it, differing from streak to streak);
    /// 0 = they stop at the edge.
    pub run_out_m: f32,
}

impl Default for StainParams {
    fn default() -> Self {
        StainParams {
            color: [86, 76, 62],
            opacity: 0.25,
            strength: 0.6,
            percentile: 0.99,
            softness: 0.0,
            blur_m: 0.03,
            washed_color: [200, 196, 186],
            washed_opacity: 0.35,
            soot: crate::effects::rain::soot::PER_RAINFALL,
            wall_hue: 0.6,
            texture: 0.0,
            run_out_m: 0.3,
        }
    }
}

/// Moss colour, one of the two Chang chooses for Caloplaca lichen.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MossColor {
    /// RGB(180, 130, 0).
    Orange,
    /// RGB(140, 130, 80).
    YellowGreen,
}

impl MossColor {
    /// The sRGB colour (Chang sec. 4).
    pub fn rgb(self) -> [u8; 3] {
        match self {
            MossColor::Orange => [180, 130, 0],
            MossColor::YellowGreen => [140, 130, 80],
        }
    }
}

/// Moss parameters (Chang, Yoshida & Mukai sec. 4, eq. 18, plus clustering
/// and growth over the years).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MossParams {
    /// Whether moss grows.
    pub enabled: bool,
    /// Years of growth (the GUI's time slider).
    pub years: u32,
    /// Probability factor gamma of eq. 18 (Chang Table 1: 1.5).
    pub gamma: f32,
    /// Wetness used instead of the rain's water and dirt when there is no rain.
    pub humidity: f32,
    /// Colony colour.
    pub color: MossColor,
    /// Random change of each dot's R, G and B, up to this many levels.
    pub color_jitter: f32,
    /// Layer opacity.
    pub opacity: f32,
    /// Fractal baseline as a fraction of the region's width (Chang: 1/40);
    /// 0 = `colony_m` through the scene's scale.
    pub baseline: f32,
    /// A colony's typical radius, metres (lichen patches are centimetres).
    pub colony_m: f32,
    /// Height of the splash zone above the ground, metres.
    pub splash_m: f32,
    /// Depth of the wet band on a ledge's top, metres.
    pub ledge_top_m: f32,
    /// How much moss the open wall takes, 0..1, against 1 in the splash
    /// zone, on ledge tops, in joints and in shelter.
    pub open_wall: f32,
    /// How much the climate's humidity (`climate.*`, Riihiaho eq. 3.8)
    /// moves moss toward the wet, shaded wall and off the dry, sunlit one;
    /// 0 = not at all.
    pub by_humidity: f32,
    /// Mix species: grey-green lichen, dark moss and orange Caloplaca
    /// besides `color`.
    pub mixed_species: bool,
    /// Generator iterations (vertices per arm = 4^iterations + 1).
    pub iterations: u32,
    /// Height of the generator's peak, fraction of its base.
    pub peak: f32,
    /// Dot radius, fraction of the baseline.
    pub dot_size: f32,
    /// Candidate sites tested with eq. 18 per baseline^2 of wall per year.
    pub seed_rate: f32,
    /// Chance per colony per year of seeding a neighbour.
    pub spread: f32,
    /// Typical distance of a neighbour, in baselines.
    pub spread_distance: f32,
    /// Spread of colony sizes (log-normal sigma).
    pub size_spread: f32,
    /// Years a colony takes to reach full size.
    pub maturity: f32,
}

impl Default for MossParams {
    fn default() -> Self {
        MossParams {
            enabled: true,
            years: 15,
            gamma: 1.5,
            humidity: 0.5,
            color: MossColor::YellowGreen,
            color_jitter: 14.0,
            opacity: 0.7,
            baseline: 0.0,
            colony_m: 0.05,
            splash_m: 0.4,
            ledge_top_m: 0.15,
            open_wall: 0.0,
            by_humidity: 0.3,
            mixed_species: true,
            iterations: 3,
            peak: 0.45,
            dot_size: 0.03,
            seed_rate: 0.3,
            spread: 0.5,
            spread_distance: 0.8,
            size_spread: 0.5,
            maturity: 4.0,
        }
    }
}

/// Dust accumulation environments: Santos & Baranoski's measured rates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DustEnvironment {
    /// Low human activity: film (2.4, 0.8), mask (0.1, 0).
    LowActivity,
    /// High human activity: film (2.8, 25.7), mask (1.3, 0.3).
    HighActivity,
    /// A steeper first five days: film (11.1, 5.1) then (2.8, 0); mask (1.3, 0.3).
    SteepStart,
    /// The paper's desktop scene: film (10, 25.7), mask (0.1, 0).
    Desktop,
    /// The rates in `film_segments` and `mask_segments`.
    Custom,
}

/// One piece of a piecewise accumulation rate (Santos eq. 1 per piece).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Segment {
    /// Days this rate lasts; 0 = until the end.
    pub days: u32,
    /// Elements per in^2 per day.
    pub alpha: f64,
    /// Extra elements per in^2 on the segment's first day.
    pub beta: f64,
}

impl Segment {
    /// A segment.
    pub const fn new(days: u32, alpha: f64, beta: f64) -> Segment {
        Segment { days, alpha, beta }
    }
}

impl DustEnvironment {
    /// (film, mask) segments of this environment; `None` for `Custom`.
    pub fn segments(self) -> Option<(Vec<Segment>, Vec<Segment>)> {
        let s = Segment::new;
        Some(match self {
            DustEnvironment::LowActivity => (vec![s(0, 2.4, 0.8)], vec![s(0, 0.1, 0.0)]),
            DustEnvironment::HighActivity => (vec![s(0, 2.8, 25.7)], vec![s(0, 1.3, 0.3)]),
            DustEnvironment::SteepStart => {
                (vec![s(5, 11.1, 5.1), s(0, 2.8, 0.0)], vec![s(0, 1.3, 0.3)])
            }
            DustEnvironment::Desktop => (vec![s(0, 10.0, 25.7)], vec![s(0, 0.1, 0.0)]),
            DustEnvironment::Custom => return None,
        })
    }
}

/// Dust parameters (Santos & Baranoski 2022).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DustParams {
    /// Whether dust settles.
    pub enabled: bool,
    /// Days of accumulation (the GUI's time slider).
    pub days: u32,
    /// Accumulation rates: a measured environment, or `custom`.
    pub environment: DustEnvironment,
    /// Custom film rates, used when `environment = "custom"`.
    pub film_segments: Vec<Segment>,
    /// Custom granule rates, used when `environment = "custom"`.
    pub mask_segments: Vec<Segment>,
    /// Pixels per inch of the wall; sets the area A of eq. 1. 0 = from the
    /// scene's scale (Santos' texture is 150 ppi).
    pub ppi: f64,
    /// The three grey levels of fine particles [choice: darker than
    /// Santos' desk dust (100, 150, 200): on a facade it is urban soot].
    pub film_greys: [u8; 3],
    /// Opacity weight of each grey (eq. 3).
    pub film_weights: [f32; 3],
    /// Weighted count at which the film is opaque (eq. 4).
    pub anp_max: f32,
    /// Colour of coarse elements (eq. 7).
    pub granule_color: [u8; 3],
    /// Largest width of a coarse element, pixels (Santos Table 1: 12..36).
    pub granule_size: f32,
    /// Share of arcs among coarse elements.
    pub arc_share: f32,
    /// Share of clumps among coarse elements.
    pub clump_share: f32,
    /// Share of hairs among coarse elements.
    pub hair_share: f32,
    /// Viewing angle from the wall's normal, degrees (eq. 8).
    pub theta_v: f32,
    /// Light incidence angle from the wall's normal, degrees (eq. 9).
    pub theta_i: f32,
    /// Opacity of the film layer.
    pub film_opacity: f32,
    /// Opacity of the granules layer.
    pub granule_opacity: f32,
    /// How much dust stays on the open, rain-washed wall, 0..1, against 1
    /// on ledge tops and in rain shelter.
    pub open_wall: f32,
    /// Depth of the dusty band on top of each ledge, metres.
    pub ledge_top_m: f32,
    /// How much the climate's direct light (`climate.*`, Riihiaho eq. 3.5)
    /// moves dust: negative keeps it in the shade and recesses, off the
    /// sunlit open wall; 0 = not at all.
    pub by_light: f32,
}

impl Default for DustParams {
    fn default() -> Self {
        DustParams {
            enabled: true,
            days: 5475,
            environment: DustEnvironment::LowActivity,
            film_segments: Vec::new(),
            mask_segments: Vec::new(),
            ppi: 0.0,
            film_greys: [70, 90, 110],
            film_weights: [1.0, 0.8, 0.6],
            anp_max: 1.2,
            granule_color: [220, 220, 220],
            granule_size: 12.0,
            arc_share: 0.3,
            clump_share: 0.4,
            hair_share: 0.3,
            theta_v: 60.0,
            theta_i: 45.0,
            film_opacity: 1.0,
            granule_opacity: 0.5,
            open_wall: 0.02,
            ledge_top_m: 0.06,
            by_light: -0.5,
        }
    }
}

impl DustParams {
    /// (film, mask) rate segments: the environment's, or the custom lists.
    pub fn segments(&self) -> (Vec<Segment>, Vec<Segment>) {
        self.environment
            .segments()
            .unwrap_or_else(|| (self.film_segments.clone(), self.mask_segments.clone()))
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
