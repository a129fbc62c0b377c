//! Dust settling over days (Santos & Baranoski 2022): the measured
//! accumulation environments and the dust's parameters.

use serde::{Deserialize, Serialize};

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
    /// on a vertical wall that rain never washes (rain shelter keeps 0.75,
    /// ledge tops, facing up, up to 2).
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
