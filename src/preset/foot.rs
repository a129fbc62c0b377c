//! The wall's foot: soil and grime splashed up by rain where the wall
//! stands on the ground, and a rising-damp tide mark above it
//! (`how-facades-age.md`, "Near the ground"). Sizes are metres, through the
//! scene's scale; the effect is `effects/foot.rs`.

use serde::{Deserialize, Serialize};

use super::params::{ParamSpec, p};

/// The splash zone's soiling and the tide mark.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FootParams {
    /// Whether the foot of the wall is soiled (a "splash zone soiling"
    /// layer under the rain's).
    pub enabled: bool,
    /// Mean height the spatter reaches above the ground, metres (the
    /// spec's splash zone is the bottom 0.3 to 0.5 m).
    pub height_m: f32,
    /// How much that height varies along the wall, as a share of it: 0 = a
    /// level top.
    pub top_spread: f32,
    /// Size along the wall of the top's rises and dips, metres.
    pub top_size_m: f32,
    /// Coverage at the foot of a full-grown soiling, 0..1.
    pub strength: f32,
    /// Rainfalls (`rain.layers`, set by `age.years`) after which the
    /// soiling has reached 1 - 1/e of its full strength: it grows with
    /// every rain that throws soil up the wall.
    pub rainfalls: f32,
    /// Share of the soiling that is separate specks of spatter; the rest
    /// is a mottled tone.
    pub spatter: f32,
    /// Size of a speck, metres.
    pub speck_m: f32,
    /// Colour multiplied into the wall, sRGB (a warm brown-grey soil).
    pub color: [u8; 3],
    /// Coverage of the rising-damp tide mark at full strength (a darker
    /// rim along a damp, slightly darker band); 0 = none.
    pub tide: f32,
    /// Mean height of the tide mark, metres (the spec's "up to about 1 m").
    pub tide_m: f32,
    /// Layer opacity.
    pub opacity: f32,
}

impl Default for FootParams {
    fn default() -> Self {
        FootParams {
            enabled: false,
            height_m: 0.4,
            top_spread: 0.35,
            top_size_m: 0.6,
            strength: 0.85,
            rainfalls: 24.0,
            spatter: 0.45,
            speck_m: 0.012,
            color: [112, 94, 76],
            tide: 0.0,
            tide_m: 0.9,
            opacity: 1.0,
        }
    }
}

/// The rows of the PARAMS table for `[foot]`.
pub(super) const ROWS: &[ParamSpec] = &[
    p(
        "foot.enabled",
        "",
        "Soil the foot of the wall where it stands on the ground (a \"splash zone soiling\" layer)",
        0.0,
        0.0,
    ),
    p(
        "foot.height_m",
        "",
        "Mean height the rain's splashed soil reaches above the ground, metres",
        0.0,
        5.0,
    ),
    p(
        "foot.top_spread",
        "",
        "How much that height varies along the wall, as a share of it (0 = a level top)",
        0.0,
        0.9,
    ),
    p(
        "foot.top_size_m",
        "",
        "Size along the wall of the splash top's rises and dips, metres",
        0.01,
        20.0,
    ),
    p(
        "foot.strength",
        "",
        "Coverage at the foot of a full-grown soiling, 0..1",
        0.0,
        1.0,
    ),
    p(
        "foot.rainfalls",
        "",
        "Rainfalls (rain.layers, set by age.years) after which the soiling reaches 1 - 1/e of its full strength",
        0.1,
        1000.0,
    ),
    p(
        "foot.spatter",
        "",
        "Share of the soiling that is separate specks of spatter (the rest a mottled tone)",
        0.0,
        1.0,
    ),
    p(
        "foot.speck_m",
        "",
        "Size of a speck of spatter, metres",
        0.001,
        0.5,
    ),
    p(
        "foot.color",
        "",
        "Colour of the soil multiplied into the wall, sRGB",
        0.0,
        255.0,
    ),
    p(
        "foot.tide",
        "",
        "Coverage of the rising-damp tide mark (a darker rim over a damp band); 0 = none",
        0.0,
        1.0,
    ),
    p(
        "foot.tide_m",
        "",
        "Mean height of the rising-damp tide mark, metres",
        0.05,
        5.0,
    ),
    p(
        "foot.opacity",
        "",
        "Opacity of the foot soiling layer",
        0.0,
        1.0,
    ),
];
