//! Sun, humidity and the weathering generators driven by them (Riihiaho
//! 2020, ch. 3): Spotty, Roughy, Fade Towardy and Desaturaty.

use serde::{Deserialize, Serialize};

use super::params::{ParamSpec, p};

/// The sun and the air: direct and indirect light, humidity (Riihiaho
/// eqs. 3.5-3.8). Read by the weathering generators; other effects can
/// read the maps through `effects::climate`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ClimateParams {
    /// Sun azimuth, degrees: 0 = straight in front of the wall, -90 = from
    /// the left, 90 = from the right.
    pub sun_azimuth: f32,
    /// Sun elevation above the horizon, degrees.
    pub sun_elevation: f32,
    /// k1: power of the two side suns, share of the main one.
    pub k1: f32,
    /// k2: elevation of the side suns, share of the main one's.
    pub k2: f32,
    /// k3: azimuth spread of the side suns, degrees.
    pub k3: f32,
    /// s: scale of direct light (eq. 3.5).
    pub light_scale: f32,
    /// How strongly the photo's shading is read as relief when no normal
    /// map is given.
    pub relief: f32,
    /// Indirect light sigmoid offset and steepness (eq. 3.6).
    pub indirect_offset: f32,
    /// Steepness s_s of the indirect light's sigmoid.
    pub indirect_steepness: f32,
    /// h_b: base humidity.
    pub base_humidity: f32,
    /// Offset s_o of the ground sigmoid S(1 - z): how high the ground's
    /// wetness reaches (z = 0 at the ground, 1 at the wall's top).
    pub ground_offset: f32,
    /// Steepness s_s of the ground sigmoid.
    pub ground_steepness: f32,
    /// c1: drying by air (accessibility).
    pub c1: f32,
    /// c2: drying by direct light.
    pub c2: f32,
    /// c3: drying by indirect light.
    pub c3: f32,
    /// s: scale of humidity (eq. 3.8).
    pub humidity_scale: f32,
}

impl Default for ClimateParams {
    fn default() -> Self {
        ClimateParams {
            sun_azimuth: -30.0,
            sun_elevation: 40.0,
            k1: 0.3,
            k2: 0.6,
            k3: 60.0,
            light_scale: 0.8,
            relief: 4.0,
            indirect_offset: 0.4,
            indirect_steepness: 20.0,
            base_humidity: 0.35,
            ground_offset: 0.8,
            ground_steepness: 60.0,
            c1: 0.2,
            c2: 0.5,
            c3: 0.05,
            humidity_scale: 1.0,
        }
    }
}

/// What one generator shares with the others: time, durability and the
/// environment `e = encourage - discourage` (Riihiaho eqs. 3.9-3.10).
/// Each generator's section has its own defaults ([`super::sections`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GeneratorParams {
    /// Whether it runs.
    pub enabled: bool,
    /// t: years of exposure.
    pub years: f32,
    /// d: durability, years (t_d = t / d).
    pub durability: f32,
    /// Environment without light or humidity.
    pub base: f32,
    /// Encouragement by humidity (negative: discouragement).
    pub by_humidity: f32,
    /// Encouragement by direct light (negative: discouragement).
    pub by_light: f32,
    /// s_o of the generator's sigmoid (Roughy, Fade, Desaturaty).
    pub offset: f32,
    /// s_s of the generator's sigmoid.
    pub steepness: f32,
    /// Lower limit l_min (Roughy, Desaturaty: the least saturation kept).
    pub l_min: f32,
    /// Upper limit l_max (Roughy).
    pub l_max: f32,
    /// Feature size, metres (Spotty's islands, Roughy's contrast radius).
    pub size: f32,
    /// Colour: Spotty's spots, Fade Towardy's c2.
    pub color: [u8; 3],
    /// Layer opacity.
    pub opacity: f32,
}

impl GeneratorParams {
    fn new(by_humidity: f32, by_light: f32, color: [u8; 3]) -> GeneratorParams {
        GeneratorParams {
            enabled: false,
            years: 10.0,
            durability: 10.0,
            base: 0.0,
            by_humidity,
            by_light,
            offset: 0.9,
            steepness: 10.0,
            l_min: 0.0,
            l_max: 1.0,
            size: 0.3,
            color,
            opacity: 1.0,
        }
    }

    /// Spotty: lichen-like spots where it is damp and shaded.
    pub fn spotty() -> GeneratorParams {
        GeneratorParams {
            base: 0.3,
            size: 0.15,
            opacity: 0.85,
            ..GeneratorParams::new(0.8, -0.3, [120, 118, 70])
        }
    }

    /// Roughy: a matte, weathered surface where the sun and rain reach.
    pub fn roughy() -> GeneratorParams {
        GeneratorParams {
            base: 0.2,
            l_max: 0.7,
            size: 0.05,
            ..GeneratorParams::new(0.3, 0.5, [0, 0, 0])
        }
    }

    /// Fade Towardy: yellowing where the light is.
    pub fn fade() -> GeneratorParams {
        GeneratorParams {
            opacity: 0.6,
            ..GeneratorParams::new(0.0, 0.8, [214, 196, 150])
        }
    }

    /// Desaturaty: sun-faded paint.
    pub fn desaturate() -> GeneratorParams {
        GeneratorParams {
            l_min: 0.2,
            ..GeneratorParams::new(0.0, 1.0, [0, 0, 0])
        }
    }
}

macro_rules! generator_rows {
    ($s:literal, $what:literal) => {
        [
            p(
                concat!($s, ".enabled"),
                "",
                concat!("Run ", $what, " (Riihiaho); off by default"),
                0.0,
                0.0,
            ),
            p(concat!($s, ".years"), "t", "Years of exposure", 0.0, 1000.0),
            p(
                concat!($s, ".durability"),
                "d",
                "Durability in years; the generator sees t_d = t / d (eq. 3.9)",
                0.01,
                1000.0,
            ),
            p(
                concat!($s, ".base"),
                "",
                "Environment e without light or humidity (eq. 3.10)",
                -2.0,
                2.0,
            ),
            p(
                concat!($s, ".by_humidity"),
                "e_e",
                "How much humidity encourages it (negative: discourages)",
                -2.0,
                2.0,
            ),
            p(
                concat!($s, ".by_light"),
                "e_d",
                "How much direct sunlight encourages it (negative: discourages)",
                -2.0,
                2.0,
            ),
            p(
                concat!($s, ".offset"),
                "s_o",
                "Offset of the generator's sigmoid S(e t_d) (eq. 3.7)",
                -2.0,
                2.0,
            ),
            p(
                concat!($s, ".steepness"),
                "s_s",
                "Steepness of the generator's sigmoid (eq. 3.7)",
                0.01,
                10000.0,
            ),
            p(
                concat!($s, ".l_min"),
                "l_min",
                "Lower limit of the sigmoid (Desaturaty: the least saturation kept)",
                0.0,
                1.0,
            ),
            p(
                concat!($s, ".l_max"),
                "l_max",
                "Upper limit of the sigmoid (Roughy)",
                0.0,
                1.0,
            ),
            p(
                concat!($s, ".size"),
                "",
                "Feature size, metres (Spotty's islands; Roughy's contrast radius)",
                0.005,
                50.0,
            ),
            p(
                concat!($s, ".color"),
                "c_2",
                "Colour: Spotty's spots, Fade Towardy's target",
                0.0,
                255.0,
            ),
            p(concat!($s, ".opacity"), "", "Layer opacity", 0.0, 1.0),
        ]
    };
}

const CLIMATE: &[ParamSpec] = &[
    p(
        "climate.sun_azimuth",
        "phi",
        "Sun azimuth in degrees: 0 = in front of the wall, -90 = from the left, 90 = from the right (eq. 3.5)",
        -180.0,
        180.0,
    ),
    p(
        "climate.sun_elevation",
        "theta",
        "Sun elevation above the horizon, degrees",
        -90.0,
        90.0,
    ),
    p(
        "climate.k1",
        "k_1",
        "Power of the two side suns, share of the main sun's",
        0.0,
        1.0,
    ),
    p(
        "climate.k2",
        "k_2",
        "Elevation of the side suns, share of the main sun's",
        0.0,
        1.0,
    ),
    p(
        "climate.k3",
        "k_3",
        "Azimuth spread of the side suns, degrees",
        0.0,
        180.0,
    ),
    p(
        "climate.light_scale",
        "s",
        "Scale of direct light (eq. 3.5)",
        0.0,
        1.0,
    ),
    p(
        "climate.relief",
        "",
        "How strongly the photo's shading is read as relief for the normals (no --normal-map)",
        0.0,
        100.0,
    ),
    p(
        "climate.indirect_offset",
        "s_o",
        "Offset of the indirect light's sigmoid of accessibility (eq. 3.6)",
        -2.0,
        2.0,
    ),
    p(
        "climate.indirect_steepness",
        "s_s",
        "Steepness of the indirect light's sigmoid",
        0.01,
        10000.0,
    ),
    p(
        "climate.base_humidity",
        "h_b",
        "Base humidity (eq. 3.8's alpha)",
        0.0,
        1.0,
    ),
    p(
        "climate.ground_offset",
        "s_o",
        "Offset of S(1 - z): 1 - z above it is wet (z = 0 at the ground, 1 at the wall's top)",
        -2.0,
        2.0,
    ),
    p(
        "climate.ground_steepness",
        "s_s",
        "Steepness of S(1 - z)",
        0.01,
        10000.0,
    ),
    p(
        "climate.c1",
        "c_1",
        "Drying by air: weight of S(a_g) in beta",
        0.0,
        2.0,
    ),
    p(
        "climate.c2",
        "c_2",
        "Drying by direct light: weight of l_d in beta",
        0.0,
        2.0,
    ),
    p(
        "climate.c3",
        "c_3",
        "Drying by indirect light: weight of l_i in beta",
        0.0,
        2.0,
    ),
    p(
        "climate.humidity_scale",
        "s",
        "Scale of humidity h = [s (alpha - beta)] (eq. 3.8)",
        0.0,
        10.0,
    ),
];

const SPOTTY: [ParamSpec; 13] = generator_rows!(
    "spotty",
    "Spotty: islands whose sea level drops with time (eq. 3.12)"
);
const ROUGHY: [ParamSpec; 13] = generator_rows!(
    "roughy",
    "Roughy: a change of roughness, seen as local contrast (eq. 3.13)"
);
const FADE: [ParamSpec; 13] = generator_rows!(
    "fade",
    "Fade Towardy: a colour shift toward `color` (eqs. 3.14-3.15)"
);
const DESATURATE: [ParamSpec; 13] = generator_rows!("desaturate", "Desaturaty: sun-faded colour");

/// Every row of this module, for the PARAMS table.
pub(super) const ROWS: [&[ParamSpec]; 5] = [CLIMATE, &SPOTTY, &ROUGHY, &FADE, &DESATURATE];
