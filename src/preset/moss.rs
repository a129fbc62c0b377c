//! Moss and lichen colonies (Chang, Yoshida & Mukai sec. 4, eq. 18).

use serde::{Deserialize, Serialize};

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
