//! Smudge and corrosion parameters (Becket & Badler 1990: "fBm intensity
//! used as an interpolation weight"), placed and calibrated like the other
//! imperfections ([`super::imperfections`]). Sizes are metres.

use serde::{Deserialize, Serialize};

use super::imperfections::{Imperfection, PLACEMENTS, Place, Placement, common_rows, imperfection};
use super::params::{ParamSpec, p};

/// Smudges: hands and splash-back, a greasy darkening and blur of the wall
/// weighted by fBm.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SmudgeParams {
    /// Whether to smudge.
    pub enabled: bool,
    /// Fraction of the placement area covered (the adverb table).
    pub coverage: f32,
    /// Where: everywhere, edges, top, bottom, ground, sills, railings,
    /// point or area.
    pub placement: Placement,
    /// Width of the placement band, metres (radius for `point`).
    pub band: f32,
    /// The point for `placement = "point"`, photo pixels.
    pub around: [f32; 2],
    /// The polygon for `placement = "area"`, photo pixels.
    pub area: Vec<[f32; 2]>,
    /// Feature size of the fractal's coarsest level, metres.
    pub size: f32,
    /// Roughness of the fractal: amplitude ratio per halving.
    pub roughness: f32,
    /// How much wider than tall a smudge is (1 = round; splash-back and
    /// hands smear sideways).
    pub stretch: f32,
    /// Radius of the greasy blur, metres.
    pub blur: f32,
    /// How far a full-weight smudge pulls the blurred wall toward `color`.
    pub darken: f32,
    /// Colour of the grease and grime, sRGB.
    pub color: [u8; 3],
    /// Layer opacity.
    pub opacity: f32,
}

impl Default for SmudgeParams {
    fn default() -> Self {
        SmudgeParams {
            enabled: false,
            coverage: 0.25,
            placement: Placement::Ground,
            band: 1.0,
            around: [0.0, 0.0],
            area: Vec::new(),
            size: 0.5,
            roughness: 0.5,
            stretch: 2.0,
            blur: 0.01,
            darken: 0.5,
            color: [58, 46, 34],
            opacity: 0.85,
        }
    }
}

/// Corrosion: discolouration and pitting (stone decay, corroded metal)
/// weighted by fBm.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CorrosionParams {
    /// Whether it corrodes.
    pub enabled: bool,
    /// Fraction of the placement area covered (the adverb table).
    pub coverage: f32,
    /// Where: everywhere, edges, top, bottom, ground, sills, railings,
    /// point or area.
    pub placement: Placement,
    /// Width of the placement band, metres (radius for `point`).
    pub band: f32,
    /// The point for `placement = "point"`, photo pixels.
    pub around: [f32; 2],
    /// The polygon for `placement = "area"`, photo pixels.
    pub area: Vec<[f32; 2]>,
    /// Feature size of the fractal's coarsest level, metres.
    pub size: f32,
    /// Roughness of the fractal: amplitude ratio per halving.
    pub roughness: f32,
    /// Share of a full-weight pixel that is pitted.
    pub pits: f32,
    /// Size of a pit, metres.
    pub pit_size: f32,
    /// Alpha of the discolouration at full weight.
    pub discolour: f32,
    /// Colour multiplied into the decayed surface, sRGB (pits are darker).
    pub color: [u8; 3],
    /// Layer opacity.
    pub opacity: f32,
}

impl Default for CorrosionParams {
    fn default() -> Self {
        CorrosionParams {
            enabled: false,
            coverage: 0.25,
            placement: Placement::Bottom,
            band: 1.5,
            around: [0.0, 0.0],
            area: Vec::new(),
            size: 0.8,
            roughness: 0.6,
            pits: 0.35,
            pit_size: 0.02,
            discolour: 0.8,
            color: [172, 160, 142],
            opacity: 0.9,
        }
    }
}

imperfection!(SmudgeParams);
imperfection!(CorrosionParams);

const SMUDGE: [ParamSpec; 8] = common_rows!("smudges", "smudges (hands, splash-back)");
const CORROSION: [ParamSpec; 8] = common_rows!("corrosion", "corrosion (stone decay, metal)");

/// What is particular to smudges and corrosion.
const OWN: &[ParamSpec] = &[
    p(
        "smudges.size",
        "",
        "Size of the fractal's coarsest feature, metres (its value is the smudge's weight)",
        0.01,
        100.0,
    ),
    p(
        "smudges.roughness",
        "",
        "Amplitude ratio per subdivision level: higher = more broken smudges",
        0.1,
        0.95,
    ),
    p(
        "smudges.stretch",
        "",
        "How much wider than tall a smudge is (1 = round)",
        0.2,
        10.0,
    ),
    p(
        "smudges.blur",
        "",
        "Radius of the greasy blur under a smudge, metres",
        0.0,
        1.0,
    ),
    p(
        "smudges.darken",
        "",
        "How far a full-weight smudge pulls the blurred wall toward its colour",
        0.0,
        1.0,
    ),
    p(
        "corrosion.size",
        "",
        "Size of the fractal's coarsest feature, metres (its value weighs the pitting and discolouration)",
        0.01,
        100.0,
    ),
    p(
        "corrosion.roughness",
        "",
        "Amplitude ratio per subdivision level: higher = more ragged patches",
        0.1,
        0.95,
    ),
    p(
        "corrosion.pits",
        "",
        "Share of a full-weight pixel that is pitted (fewer where the fBm is weaker)",
        0.0,
        1.0,
    ),
    p(
        "corrosion.pit_size",
        "",
        "Size of a pit, metres",
        0.0005,
        0.5,
    ),
    p(
        "corrosion.discolour",
        "",
        "Alpha of the discolouration at full weight",
        0.0,
        1.0,
    ),
];

/// Every row of this module, for the PARAMS table.
pub(super) const ROWS: [&[ParamSpec]; 3] = [&SMUDGE, &CORROSION, OWN];
