//! Imperfection parameters (Becket & Badler 1990): scratches, splotches,
//! stains, mould and rust, each with a coverage (the adverb table's number)
//! and a placement rule in image space. Sizes are metres, through the
//! scene's scale.

use serde::{Deserialize, Serialize};

use super::params::{ParamSpec, p};

/// Where on the wall an imperfection goes (Becket & Badler's placement
/// rules, in image space).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Placement {
    /// Anywhere on the wall.
    Everywhere,
    /// Within `band` of the region's edges.
    Edges,
    /// The top `band` of the wall, per column.
    Top,
    /// The bottom `band` of the wall, per column.
    Bottom,
    /// Within `band` above the ground line (the wall's foot where the
    /// ground is not seen).
    Ground,
    /// The `band` below each window sill.
    Sills,
    /// Within `band` of the railings (balcony ledges; with none, the sills'
    /// metal flashings; with none, every ledge).
    Railings,
    /// Within `band` of the point `around`.
    Point,
    /// Inside the polygon `area` (a painted area, photo pixels).
    Area,
}

/// A placement rule as an effect reads it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Place<'a> {
    /// Which rule.
    pub placement: Placement,
    /// Width of the band, metres (radius for `point`).
    pub band: f32,
    /// The point for `point`, photo pixels.
    pub around: [f32; 2],
    /// The polygon for `area`, photo pixels.
    pub area: &'a [[f32; 2]],
}

/// The placement fields every imperfection has, and the fields the
/// sentence sets ([`crate::say`]).
pub trait Imperfection {
    /// Its placement rule.
    fn place(&self) -> Place<'_>;
    /// Turns it on with a coverage and, if given, a placement.
    fn set(&mut self, coverage: f32, placement: Option<Placement>);
    /// Scales its point and area (photo pixels) with the photo.
    fn scale_place(&mut self, sx: f32, sy: f32);
}

macro_rules! imperfection {
    ($t:ty) => {
        impl Imperfection for $t {
            fn place(&self) -> Place<'_> {
                Place {
                    placement: self.placement,
                    band: self.band,
                    around: self.around,
                    area: &self.area,
                }
            }
            fn set(&mut self, coverage: f32, placement: Option<Placement>) {
                self.enabled = true;
                self.coverage = coverage;
                if let Some(p) = placement {
                    self.placement = p;
                }
            }
            fn scale_place(&mut self, sx: f32, sy: f32) {
                for p in std::iter::once(&mut self.around).chain(&mut self.area) {
                    *p = [p[0] * sx, p[1] * sy];
                }
            }
        }
    };
}
imperfection!(ScratchParams);
imperfection!(BlotchParams);
imperfection!(MouldParams);
imperfection!(RustParams);
pub(super) use imperfection;

/// Scratches: straight lines, Gaussian in length, orientation and intensity.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ScratchParams {
    /// Whether to scratch.
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
    /// Mean length, metres.
    pub length: f32,
    /// Standard deviation of the length, metres.
    pub length_spread: f32,
    /// Width of a scratch, metres.
    pub width: f32,
    /// Dominant direction, degrees from horizontal.
    pub angle: f32,
    /// Standard deviation of the direction, degrees.
    pub angle_spread: f32,
    /// Mean intensity (alpha) of a scratch.
    pub intensity: f32,
    /// Standard deviation of the intensity.
    pub intensity_spread: f32,
    /// Colour of the scratched material, sRGB.
    pub color: [u8; 3],
    /// Layer opacity.
    pub opacity: f32,
}

impl Default for ScratchParams {
    fn default() -> Self {
        ScratchParams {
            enabled: false,
            coverage: 0.25,
            placement: Placement::Everywhere,
            band: 1.0,
            around: [0.0, 0.0],
            area: Vec::new(),
            length: 0.08,
            length_spread: 0.03,
            width: 0.005,
            angle: 20.0,
            angle_spread: 12.0,
            intensity: 0.6,
            intensity_spread: 0.15,
            color: [225, 220, 210],
            opacity: 0.85,
        }
    }
}

/// Splotches (mud, tar) and stains: fBm by midpoint subdivision, thresholded.
/// The two sections differ in their defaults ([`super::sections`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BlotchParams {
    /// Whether to draw them.
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
    /// Roughness of the fractal: amplitude ratio per halving (H = -log2).
    pub roughness: f32,
    /// Splotches: share of each splotch that is still wet (darker); stains:
    /// how much darker the edge is than the inside.
    pub wet: f32,
    /// Stains only: a ring (coffee stain) with a light inside.
    pub ring: bool,
    /// Colour, sRGB.
    pub color: [u8; 3],
    /// Layer opacity.
    pub opacity: f32,
}

impl BlotchParams {
    /// Dry mud splotches.
    pub fn splotches() -> BlotchParams {
        BlotchParams {
            enabled: false,
            coverage: 0.25,
            placement: Placement::Ground,
            band: 1.0,
            around: [0.0, 0.0],
            area: Vec::new(),
            size: 0.6,
            roughness: 0.55,
            wet: 0.3,
            ring: false,
            color: [92, 74, 52],
            opacity: 0.8,
        }
    }

    /// Water stains, darker at the edge.
    pub fn stains() -> BlotchParams {
        BlotchParams {
            enabled: false,
            coverage: 0.25,
            placement: Placement::Sills,
            band: 0.8,
            around: [0.0, 0.0],
            area: Vec::new(),
            size: 0.4,
            roughness: 0.5,
            wet: 0.6,
            ring: false,
            color: [78, 70, 60],
            opacity: 0.7,
        }
    }
}

/// Mould: Gaussian clusters of dots.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MouldParams {
    /// Whether it grows.
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
    /// Cluster centres per square metre of placement area.
    pub clusters: f32,
    /// Standard deviation of a cluster, metres.
    pub cluster_size: f32,
    /// Dot size, metres.
    pub dot_size: f32,
    /// Colour, sRGB.
    pub color: [u8; 3],
    /// Layer opacity.
    pub opacity: f32,
}

impl Default for MouldParams {
    fn default() -> Self {
        MouldParams {
            enabled: false,
            coverage: 0.25,
            placement: Placement::Ground,
            band: 1.2,
            around: [0.0, 0.0],
            area: Vec::new(),
            clusters: 1.5,
            cluster_size: 0.25,
            dot_size: 0.006,
            color: [46, 52, 38],
            opacity: 0.85,
        }
    }
}

/// Rust: rule-guided aggregation from the edges and seeds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RustParams {
    /// Whether it rusts.
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
    /// Aggregation iterations: the severity.
    pub iterations: u32,
    /// Chance per iteration that a cell at the placement's metal (its
    /// edge cells) starts to rust.
    pub p_edge: f32,
    /// Chance per iteration that any other cell starts to rust.
    pub p_interior: f32,
    /// Chance per iteration per rusted neighbour that a cell rusts.
    pub p_neighbour: f32,
    /// Fixings (bolts, brackets): seed points drawn in the placement area.
    pub fixings: u32,
    /// Length of the run-down smear below the rust, metres (0 = none).
    pub run: f32,
    /// Opacity of the run-down smear.
    pub run_opacity: f32,
    /// Colour of fresh rust, sRGB (old rust is darker).
    pub color: [u8; 3],
    /// Layer opacity.
    pub opacity: f32,
}

impl Default for RustParams {
    fn default() -> Self {
        RustParams {
            enabled: false,
            coverage: 0.25,
            placement: Placement::Railings,
            band: 0.25,
            around: [0.0, 0.0],
            area: Vec::new(),
            iterations: 40,
            p_edge: 0.02,
            p_interior: 0.0005,
            p_neighbour: 0.25,
            fixings: 12,
            run: 0.5,
            run_opacity: 0.35,
            color: [150, 72, 28],
            opacity: 0.9,
        }
    }
}

/// The rows every imperfection section shares.
macro_rules! common_rows {
    ($s:literal, $what:literal) => {
        [
            p(
                concat!($s, ".enabled"),
                "",
                concat!("Draw ", $what, " (Becket & Badler); off by default"),
                0.0,
                0.0,
            ),
            p(
                concat!($s, ".coverage"),
                "",
                "Fraction of the placement area covered (--say's adverbs: slightly 0.05, partially 0.1, somewhat 0.2, none 0.25, moderately 0.35, very 0.55, extremely 0.75, completely 1)",
                0.0,
                1.0,
            ),
            p(
                concat!($s, ".placement"),
                "",
                "Where: \"everywhere\", \"edges\", \"top\", \"bottom\", \"ground\", \"sills\" (below them), \"railings\" (balconies, else sills), \"point\" (around), \"area\" (polygon)",
                0.0,
                0.0,
            )
            .choices(PLACEMENTS),
            p(
                concat!($s, ".band"),
                "",
                "Width of the placement band in metres (radius for \"point\"); coverage is measured over it",
                0.01,
                100.0,
            ),
            p(
                concat!($s, ".around"),
                "",
                "The point for placement = \"point\", photo pixels [x, y]",
                -1e6,
                1e6,
            ),
            p(
                concat!($s, ".area"),
                "",
                "The polygon for placement = \"area\", photo pixels [[x, y], ...]",
                -1e6,
                1e6,
            ),
            p(concat!($s, ".color"), "", "Colour, sRGB [r, g, b]", 0.0, 255.0),
            p(concat!($s, ".opacity"), "", "Layer opacity", 0.0, 1.0),
        ]
    };
}

pub(super) use common_rows;

/// The placement rules, as the preset spells them (the GUI's choices).
pub(super) const PLACEMENTS: &[&str] = &[
    "everywhere",
    "edges",
    "top",
    "bottom",
    "ground",
    "sills",
    "railings",
    "point",
    "area",
];

const SCRATCH: [ParamSpec; 8] = common_rows!("scratches", "scratches");
const SPLOTCH: [ParamSpec; 8] = common_rows!("splotches", "splotches of mud or tar");
const STAIN: [ParamSpec; 8] = common_rows!("stains", "water stains");
const MOULD: [ParamSpec; 8] = common_rows!("mould", "mould");
const RUST: [ParamSpec; 8] = common_rows!("rust", "rust");

/// What is particular to each imperfection.
const OWN: &[ParamSpec] = &[
    p(
        "say",
        "",
        "A sentence that sets the starting point, applied to the defaults before this file's fields, e.g. \"very rusty near the railings, slightly scratched\" (see --say)",
        0.0,
        0.0,
    ),
    p(
        "scratches.length",
        "",
        "Mean scratch length, metres (Gaussian)",
        0.001,
        10.0,
    ),
    p(
        "scratches.length_spread",
        "",
        "Standard deviation of the length, metres",
        0.0,
        10.0,
    ),
    p("scratches.width", "", "Scratch width, metres", 0.0005, 0.5),
    p(
        "scratches.angle",
        "",
        "Dominant direction, degrees from horizontal",
        -180.0,
        180.0,
    ),
    p(
        "scratches.angle_spread",
        "",
        "Standard deviation of the direction, degrees (Gaussian around the dominant axis)",
        0.0,
        180.0,
    ),
    p(
        "scratches.intensity",
        "",
        "Mean intensity of a scratch (Gaussian)",
        0.0,
        1.0,
    ),
    p(
        "scratches.intensity_spread",
        "",
        "Standard deviation of the intensity",
        0.0,
        1.0,
    ),
    p(
        "splotches.size",
        "",
        "Size of the fractal's coarsest feature, metres (midpoint subdivision)",
        0.01,
        100.0,
    ),
    p(
        "splotches.roughness",
        "",
        "Amplitude ratio per subdivision level: higher = more ragged",
        0.1,
        0.95,
    ),
    p(
        "splotches.wet",
        "",
        "Share of each splotch still wet (fractal wet and dry regions, darker)",
        0.0,
        1.0,
    ),
    p(
        "splotches.ring",
        "",
        "Splotches ignore this (stains only)",
        0.0,
        0.0,
    ),
    p(
        "stains.size",
        "",
        "Size of the fractal's coarsest feature, metres",
        0.01,
        100.0,
    ),
    p(
        "stains.roughness",
        "",
        "Amplitude ratio per subdivision level: higher = more ragged edges",
        0.1,
        0.95,
    ),
    p(
        "stains.wet",
        "",
        "How much darker the stain's edge is than its inside",
        0.0,
        1.0,
    ),
    p(
        "stains.ring",
        "",
        "A ring of fractal edge with a light inside (coffee stain)",
        0.0,
        0.0,
    ),
    p(
        "mould.clusters",
        "",
        "Cluster centres per square metre of placement area",
        0.01,
        1000.0,
    ),
    p(
        "mould.cluster_size",
        "",
        "Standard deviation of a cluster, metres (Gaussian)",
        0.005,
        10.0,
    ),
    p("mould.dot_size", "", "Dot size, metres", 0.0005, 0.5),
    p(
        "rust.iterations",
        "",
        "Aggregation iterations: the severity (Becket & Badler's rule-guided aggregation)",
        1.0,
        2000.0,
    ),
    p(
        "rust.p_edge",
        "",
        "Chance per iteration that a cell at the metal (the placement's source) starts to rust",
        0.0,
        1.0,
    ),
    p(
        "rust.p_interior",
        "",
        "Chance per iteration that any other cell starts to rust",
        0.0,
        1.0,
    ),
    p(
        "rust.p_neighbour",
        "",
        "Chance per iteration per rusted neighbour that a cell rusts",
        0.0,
        1.0,
    ),
    p(
        "rust.fixings",
        "",
        "Fixings (bolts, brackets): seed points in the placement area",
        0.0,
        10000.0,
    ),
    p(
        "rust.run",
        "",
        "Length of the run-down smear below the rust, metres; 0 = none",
        0.0,
        20.0,
    ),
    p(
        "rust.run_opacity",
        "",
        "Opacity of the run-down smear",
        0.0,
        1.0,
    ),
];

/// Every row of this module, for the PARAMS table.
pub(super) const ROWS: [&[ParamSpec]; 6] = [&SCRATCH, &SPLOTCH, &STAIN, &MOULD, &RUST, OWN];
