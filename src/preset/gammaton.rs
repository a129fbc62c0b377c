//! γ-ton parameters (Chen et al. 2005 as Stadler implements them in
//! `aitios`, thesis ch. 3), on the image plane: sources, substances,
//! motion, transport and ageing rules.

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// Most substances one simulation carries.
pub const MAX_SUBSTANCES: usize = 4;

/// γ-tons: particles that carry substances from sources over the wall.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GammatonParams {
    /// Run the γ-tons.
    pub enabled: bool,
    /// γ-tons emitted per iteration, over all sources.
    pub particles: u32,
    /// Iterations: emit and trace, then apply the ageing rules.
    pub iterations: u32,
    /// Most contacts one γ-ton makes before it settles (the tracing cap).
    pub max_depth: u32,
    /// Interaction radius r, in grid pixels (thesis eq. 3.19).
    pub radius: f32,
    /// Initial probability of straight motion p_s.
    pub p_straight: f32,
    /// Initial probability of parabolic motion p_p.
    pub p_parabolic: f32,
    /// Initial probability of flow p_f (settling takes the rest, eq. 3.9).
    pub p_flow: f32,
    /// Deterioration of p_s per contact, Δ_s (eq. 3.21).
    pub d_straight: f32,
    /// Deterioration of p_p per contact, Δ_p.
    pub d_parabolic: f32,
    /// Deterioration of p_f per contact, Δ_f.
    pub d_flow: f32,
    /// Length of a straight or parabolic hop, grid pixels.
    pub hop: f32,
    /// Length of one flow segment between contacts, grid pixels.
    pub flow_step: f32,
    /// Sideways wander of flowing γ-tons, 0 = straight down the slope.
    pub wander: f32,
    /// Consistent transport (exchange at every contact, eqs. 3.26-3.27)
    /// instead of classic (absorb at stops, deposit on settling, 3.23-3.25).
    pub consistent: bool,
    /// Where γ-tons come from.
    pub sources: Vec<GammaSource>,
    /// What they carry; at most [`MAX_SUBSTANCES`].
    pub substances: Vec<Substance>,
    /// Ageing rules applied after each iteration, in order.
    pub rules: Vec<Rule>,
}

impl Default for GammatonParams {
    fn default() -> Self {
        GammatonParams {
            enabled: false,
            particles: 200_000,
            iterations: 1,
            max_depth: 48,
            radius: 1.0,
            p_straight: 0.1,
            p_parabolic: 0.1,
            p_flow: 0.75,
            d_straight: 0.1,
            d_parabolic: 0.05,
            d_flow: 0.02,
            hop: 6.0,
            flow_step: 2.0,
            wander: 0.3,
            consistent: true,
            sources: vec![GammaSource::new(SourceKind::Sky, vec![1.0])],
            substances: vec![Substance {
                name: "dirt".into(),
                filter: 0,
                absorb: 0.05,
                deposit: 0.2,
                initial: 0.0,
                scale: 4.0,
                stops: vec![
                    Stop::new(0.0, [60, 52, 44], 0.0),
                    Stop::new(1.0, [60, 52, 44], 0.6),
                ],
            }],
            rules: Vec::new(),
        }
    }
}

/// Where a source emits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SourceKind {
    /// Rain from the sky: first contact anywhere on the wall the ledges do
    /// not shelter from its direction, then down.
    Sky,
    /// Splash from the ground: thrown up the foot of the wall.
    Ground,
    /// A point or polyline (a rusty fixing, a railing), photo pixels.
    Line,
    /// A painted mask: a greyscale image the photo's size, white = emit
    /// (grey: proportionally fewer); first contact where it is painted.
    Mask,
}

/// One source of γ-tons.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GammaSource {
    /// Where it emits.
    pub kind: SourceKind,
    /// Its share of the particles (shares are normalised).
    #[serde(default = "one")]
    pub share: f32,
    /// For `line`: the points, `[x, y]` in photo pixels (one point is a
    /// point source).
    #[serde(default)]
    pub points: Vec<[f32; 2]>,
    /// For `line`: emit from this many fixed spots along it (a fixing, a
    /// bracket), drawn from the seed; 0 = anywhere along it.
    #[serde(default)]
    pub spots: u32,
    /// For `mask`: the path of the mask image (relative to the working
    /// folder), the photo's size.
    #[serde(default)]
    pub mask: String,
    /// For `sky`: the rain's angle from vertical on the image plane,
    /// degrees; positive falls to the right (wind from the left).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub direction: f32,
    /// For `sky`: the spread of the rain's angles around `direction`,
    /// degrees (uniform within ± spread).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub spread: f32,
    /// For `sky`: how far below a cornice its shelter reaches, metres
    /// (1/e; sills reach less); 0 = ledges shelter nothing.
    #[serde(default = "sky_shelter", skip_serializing_if = "is_sky_shelter")]
    pub shelter: f32,
    /// What each γ-ton starts with, per substance in `substances` order.
    #[serde(default)]
    pub carries: Vec<f32>,
}

fn one() -> f32 {
    1.0
}

/// The default reach of a cornice's rain shelter, metres [choice: driving
/// rain reaches about 0.5 m under a cornice projecting 0.3 m].
pub const SKY_SHELTER_M: f32 = 0.5;

fn sky_shelter() -> f32 {
    SKY_SHELTER_M
}

// Fields at their defaults stay out of saved presets and recipes (so those
// of presets made before them are unchanged).
fn is_zero(v: &f32) -> bool {
    *v == 0.0
}

fn is_sky_shelter(v: &f32) -> bool {
    *v == SKY_SHELTER_M
}

impl GammaSource {
    /// A source of `kind` with share 1 carrying `carries`, the other
    /// fields at their defaults.
    pub fn new(kind: SourceKind, carries: Vec<f32>) -> GammaSource {
        GammaSource {
            kind,
            share: 1.0,
            points: Vec::new(),
            spots: 0,
            mask: String::new(),
            direction: 0.0,
            spread: 0.0,
            shelter: SKY_SHELTER_M,
            carries,
        }
    }
}

/// One substance: a map on the grid, and a layer.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Substance {
    /// Its name, which is also the layer's.
    pub name: String,
    /// Absorption rate a of the γ-tons (eqs. 3.23, 3.26).
    #[serde(default)]
    pub absorb: f32,
    /// Deposition rate k of the wall (eqs. 3.25, 3.26).
    #[serde(default = "one")]
    pub deposit: f32,
    /// Concentration on the wall before the first iteration.
    #[serde(default)]
    pub initial: f32,
    /// The concentration above `initial` the last blend stop stands for
    /// (the layer shows what the γ-tons gathered, not the wall's own).
    #[serde(default = "one")]
    pub scale: f32,
    /// Blend stops: concentration (0..1 of `scale`) to colour and opacity,
    /// interpolated linearly.
    pub stops: Vec<Stop>,
    /// Texture synthesis: each pixel's concentration is the mean over the
    /// wall pixels within this many grid pixels (thesis §3.8, texels
    /// average their near surfels); 0 = the pixel's own.
    #[serde(default, skip_serializing_if = "is_zero_u32")]
    pub filter: u32,
}

fn is_zero_u32(v: &u32) -> bool {
    *v == 0
}

/// A blend stop.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Stop {
    /// Concentration, 0..1 of the substance's `scale`.
    pub value: f32,
    /// Colour, sRGB.
    pub color: [u8; 3],
    /// Opacity, 0..1.
    pub opacity: f32,
}

impl Stop {
    /// A stop at `value` of `color` and `opacity`.
    pub fn new(value: f32, color: [u8; 3], opacity: f32) -> Stop {
        Stop {
            value,
            color,
            opacity,
        }
    }
}

/// An ageing rule (thesis eqs. 3.28-3.29).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Rule {
    /// Transfer or deteriorate.
    pub kind: RuleKind,
    /// The substance it takes from.
    pub from: String,
    /// For `transfer`: the substance it gives to.
    #[serde(default)]
    pub to: String,
    /// Rate k: transfer moves `k c_i`; deteriorate scales by `1 + k`.
    pub rate: f32,
    /// Apply only where this substance is present (> 0): a material mask
    /// made by the simulation (e.g. iron where a fixing sits); "" = everywhere.
    #[serde(default)]
    pub only_where: String,
}

/// What an ageing rule does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RuleKind {
    /// `c_i -= k c_i; c_j += k c_i` (water plus iron to rust).
    Transfer,
    /// `c_i *= 1 + k` (evaporation with k < 0).
    Deteriorate,
}

impl GammatonParams {
    /// The index of substance `name`.
    pub fn substance(&self, name: &str) -> Option<usize> {
        self.substances.iter().position(|s| s.name == name)
    }

    /// Checks what the PARAMS table cannot: counts, names, stops, sources.
    ///
    /// # Errors
    /// [`Error::OutOfRange`] naming the field.
    pub fn validate(&self) -> Result<()> {
        let bad = |field: String, value: String, range: &str| Error::OutOfRange {
            field,
            value,
            range: range.into(),
        };
        let n = self.substances.len();
        if n == 0 || n > MAX_SUBSTANCES {
            return Err(bad(
                "gammaton.substances".into(),
                n.to_string(),
                "1 ..= 4 substances",
            ));
        }
        if self.p_straight + self.p_parabolic + self.p_flow > 1.0 {
            return Err(bad(
                "gammaton.p_flow".into(),
                self.p_flow.to_string(),
                "p_straight + p_parabolic + p_flow <= 1 (eq. 3.8)",
            ));
        }
        for (i, s) in self.substances.iter().enumerate() {
            let field = |f: &str| format!("gammaton.substances[{i}].{f}");
            if s.name.is_empty() || self.substance(&s.name) != Some(i) {
                return Err(bad(
                    field("name"),
                    format!("{:?}", s.name),
                    "a unique, non-empty name",
                ));
            }
            let sorted = s.stops.windows(2).all(|w| w[0].value <= w[1].value);
            if s.stops.is_empty()
                || !sorted
                || s.stops.iter().any(|t| !(0.0..=1.0).contains(&t.opacity))
            {
                return Err(bad(
                    field("stops"),
                    format!("{:?}", s.stops),
                    "at least one stop, values ascending, opacity 0 ..= 1",
                ));
            }
        }
        if self.sources.is_empty() {
            return Err(bad(
                "gammaton.sources".into(),
                "[]".into(),
                "at least one source",
            ));
        }
        for (i, s) in self.sources.iter().enumerate() {
            let field = |f: &str| format!("gammaton.sources[{i}].{f}");
            if s.carries.len() > n || s.carries.iter().any(|c| !(c.is_finite() && *c >= 0.0)) {
                return Err(bad(
                    field("carries"),
                    format!("{:?}", s.carries),
                    "one amount >= 0 per substance, at most one per substance",
                ));
            }
            if (s.kind == SourceKind::Mask) == s.mask.is_empty() {
                return Err(bad(
                    field("mask"),
                    format!("{:?}", s.mask),
                    "the path of a greyscale image for kind = \"mask\" (white = emit), \"\" for other kinds",
                ));
            }
            let sky = s.kind == SourceKind::Sky;
            if !sky && (s.direction != 0.0 || s.spread != 0.0 || s.shelter != SKY_SHELTER_M) {
                return Err(bad(
                    field("direction"),
                    format!(
                        "direction {}, spread {}, shelter {}",
                        s.direction, s.spread, s.shelter
                    ),
                    "direction, spread and shelter only on kind = \"sky\" (leave them out for other kinds)",
                ));
            }
            if s.points.iter().flatten().any(|c| !c.is_finite()) {
                return Err(bad(
                    field("points"),
                    format!("{:?}", s.points),
                    "finite [x, y] points (none: a line source uses rain.source_lines)",
                ));
            }
        }
        for (i, r) in self.rules.iter().enumerate() {
            let field = |f: &str| format!("gammaton.rules[{i}].{f}");
            let known = |name: &str| self.substance(name).is_some();
            if !known(&r.from) {
                return Err(bad(
                    field("from"),
                    format!("{:?}", r.from),
                    "the name of a substance",
                ));
            }
            if r.kind == RuleKind::Transfer && !known(&r.to) {
                return Err(bad(
                    field("to"),
                    format!("{:?}", r.to),
                    "the name of a substance",
                ));
            }
            if !r.only_where.is_empty() && !known(&r.only_where) {
                return Err(bad(
                    field("only_where"),
                    format!("{:?}", r.only_where),
                    "the name of a substance, or \"\"",
                ));
            }
        }
        Ok(())
    }
}

/// The γ-ton part of the built-in presets `rust-runs`, `salt-bloom` and
/// `splash` (anything else: the defaults).
pub fn builtin(name: &str) -> GammatonParams {
    let source = GammaSource::new;
    let fade = |color: [u8; 3], opacity: f32| {
        vec![Stop::new(0.0, color, 0.0), Stop::new(1.0, color, opacity)]
    };
    let d = GammatonParams::default();
    match name {
        // Dissolved iron from the ledges' fixings and railings (line
        // sources default to the rain's ledges), running down and leaving
        // a little at every contact (consistent transport). A contact every
        // pixel (a flow step of 2 left every other row narrower: a comb
        // along the runs' edges), softened by a 3 x 3 filter.
        "rust-runs" => GammatonParams {
            enabled: true,
            particles: 60_000,
            max_depth: 320,
            p_straight: 0.0,
            p_parabolic: 0.02,
            p_flow: 0.97,
            d_straight: 0.0,
            d_parabolic: 0.01,
            d_flow: 0.002,
            flow_step: 1.0,
            wander: 0.25,
            sources: vec![GammaSource {
                spots: 14,
                ..source(SourceKind::Line, vec![1.0])
            }],
            substances: vec![Substance {
                name: "rust".into(),
                filter: 1,
                absorb: 0.0,
                deposit: 0.02,
                initial: 0.0,
                scale: 1.0,
                stops: vec![
                    Stop::new(0.0, [150, 80, 35], 0.0),
                    Stop::new(0.4, [150, 80, 35], 0.3),
                    Stop::new(1.0, [110, 55, 28], 0.6),
                ],
            }],
            ..d
        },
        // Rising damp: ground water climbs the foot of the wall, dissolving
        // the salts in it, and leaves them where it stops and dries: a
        // white tide line (classic transport: absorb on the way, deposit
        // all on settling).
        "salt-bloom" => GammatonParams {
            enabled: true,
            particles: 400_000,
            max_depth: 10,
            p_straight: 0.75,
            p_parabolic: 0.0,
            p_flow: 0.05,
            d_straight: 0.12,
            d_flow: 0.0,
            hop: 14.0,
            consistent: false,
            radius: 2.0,
            sources: vec![source(SourceKind::Ground, vec![1.0, 0.0])],
            substances: vec![
                Substance {
                    name: "water".into(),
                    filter: 0,
                    absorb: 0.0,
                    deposit: 1.0,
                    initial: 0.0,
                    scale: 20.0,
                    stops: fade([90, 90, 95], 0.0),
                },
                Substance {
                    name: "salt".into(),
                    // Single deposits sparkled like glitter: a crust shows
                    // the mean over 7 x 7 pixels.
                    filter: 3,
                    absorb: 0.3,
                    deposit: 1.0,
                    initial: 0.5,
                    scale: 0.2,
                    stops: vec![
                        Stop::new(0.0, [236, 234, 226], 0.0),
                        Stop::new(0.3, [236, 234, 226], 0.25),
                        Stop::new(1.0, [244, 243, 238], 0.85),
                    ],
                },
            ],
            rules: vec![Rule {
                kind: RuleKind::Deteriorate,
                from: "water".into(),
                to: String::new(),
                rate: -0.8,
                only_where: String::new(),
            }],
            ..d
        },
        // Rain splashing off the ground throws dirt up the foot of the wall.
        "splash" => GammatonParams {
            enabled: true,
            particles: 120_000,
            max_depth: 12,
            p_straight: 0.3,
            p_parabolic: 0.5,
            p_flow: 0.1,
            hop: 18.0,
            sources: vec![source(SourceKind::Ground, vec![1.0])],
            substances: vec![Substance {
                name: "splash dirt".into(),
                filter: 0,
                absorb: 0.0,
                deposit: 0.3,
                initial: 0.0,
                scale: 2.0,
                stops: fade([72, 58, 44], 0.65),
            }],
            ..d
        },
        _ => d,
    }
}
