//! The weathering effects. Each is pure: buffers, parameters and a seed in,
//! maps or layers out; no file I/O, no clock, no threads beyond rayon.
//!
//! # The effect contract
//!
//! Every effect has the same shape, [`Effect::run`]: the shared read-only
//! inputs ([`Context`]: grid, luminance, region, normals), what earlier
//! effects produced ([`Products`]), the preset (its params and seed) in;
//! layers and stats ([`Produced`]) out. The pipeline runs
//! [`Effect::ALL`] in order, each over a share of the progress bar
//! ([`Effect::weight`]), and knows from [`Effect::params`] and
//! [`Effect::inputs`] which preset fields make which effect's output stale,
//! so a preview cache can keep what is still valid ([`stale`]).
//!
//! [choice: a closed enum dispatched by `match`, as tiny-skia's shaders,
//! rather than trait objects. The set of effects is known when grime is
//! built; `match` makes the compiler list every place a new effect must
//! answer (name, params, run), the effects stay plain functions on plain
//! data, and nothing is boxed or registered at run time.]
//!
//! Adding an effect touches three files plus its tests: its own module (the
//! simulation and a `stage` function of the shape of [`Effect::run`]), this
//! file (a variant and its arms), and `preset/` (its params struct and
//! PARAMS rows). README "How to add an effect" walks through it.

pub mod box_mean;
pub mod carry;
pub mod climate;
pub mod dust;
pub mod foot;
pub mod gammaton;
pub mod habitat;
pub mod imperfections;
pub mod moss;
pub mod patches;
pub mod percentile;
pub mod rain;
pub mod region;
pub mod roughness;
mod stages;
pub use stages::{WASHED, washed_layer};
pub mod surface;
#[cfg(test)]
pub(crate) mod testing;
pub mod weathering;

use std::collections::BTreeSet;
use std::sync::Arc;

use image::{GrayImage, RgbImage};
use serde::Serialize;

use crate::error::Result;
use crate::field::RowMajor;
use crate::grid::Grid;
use crate::preset::Preset;
use crate::progress::Progress;
use crate::stack::Layer;

pub use stages::RainStats;

/// One weathering effect. [`Effect::ALL`] is the pipeline order (an effect
/// may read what the ones before it produced); new variants go last, since
/// a variant's number keys its random streams.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Effect {
    /// Rain streaks (Chang et al.): one layer per rainfall.
    Rain,
    /// Moss (Chang eq. 18), grown from the rain's wetness and dirt.
    Moss,
    /// Dust film and granules (Santos & Baranoski).
    Dust,
    /// γ-tons (Chen et al., Stadler): substances carried over the wall,
    /// one layer per substance.
    Gammaton,
    /// Scratches, splotches, stains, mould and rust (Becket & Badler).
    Imperfections,
    /// Spotty, Roughy, Fade Towardy and Desaturaty driven by sun and
    /// humidity (Riihiaho); first in the pipeline, under the grime.
    Weathering,
    /// Soil splashed up the wall's foot, and rising damp's tide mark.
    Foot,
}

impl Effect {
    /// Every effect, in the order the pipeline runs them.
    pub const ALL: [Effect; 7] = [
        Effect::Weathering,
        Effect::Foot,
        Effect::Rain,
        Effect::Moss,
        Effect::Dust,
        Effect::Gammaton,
        Effect::Imperfections,
    ];

    /// Its name in reports and timings.
    pub fn name(self) -> &'static str {
        match self {
            Effect::Rain => "rain",
            Effect::Moss => "moss",
            Effect::Dust => "dust",
            Effect::Gammaton => "gammaton",
            Effect::Imperfections => "imperfections",
            Effect::Weathering => "weathering",
            Effect::Foot => "foot",
        }
    }

    /// Whether the preset asks for it. The rain always runs: with
    /// `rain.layers = 0` it makes no layer but still gives moss its dry wall.
    pub fn enabled(self, preset: &Preset) -> bool {
        match self {
            Effect::Rain => true,
            Effect::Moss => preset.moss.enabled,
            Effect::Dust => preset.dust.enabled,
            Effect::Gammaton => preset.gammaton.enabled,
            Effect::Imperfections => imperfections::enabled(preset),
            Effect::Weathering => weathering::enabled(preset),
            Effect::Foot => preset.foot.enabled,
        }
    }

    /// Its share of a run's progress bar (about its share of the time on
    /// the default preset; the enabled effects' weights are normalised).
    pub fn weight(self) -> f32 {
        match self {
            Effect::Rain => 0.79,
            Effect::Moss => 0.105,
            Effect::Dust => 0.105,
            Effect::Gammaton => 0.3,
            Effect::Imperfections | Effect::Weathering => 0.1,
            Effect::Foot => 0.02,
        }
    }

    /// The effects whose products it reads.
    pub fn inputs(self) -> &'static [Effect] {
        match self {
            Effect::Rain
            | Effect::Dust
            | Effect::Gammaton
            | Effect::Imperfections
            | Effect::Weathering
            | Effect::Foot => &[],
            Effect::Moss => &[Effect::Rain],
        }
    }

    /// Preset fields (dotted paths or their prefixes) its output depends
    /// on. A changed field outside every effect's list makes all stale.
    pub fn params(self) -> &'static [&'static str] {
        match self {
            Effect::Rain => &["seed", "sim", "rain", "stain"],
            Effect::Moss => &["seed", "sim", "moss", "stain.percentile"],
            Effect::Dust => &["seed", "dust"],
            // Line sources default to the rain's ledges.
            Effect::Gammaton => &["seed", "sim", "gammaton", "rain.source_lines"],
            Effect::Imperfections => &[
                "seed",
                "sim",
                "scratches",
                "splotches",
                "stains",
                "mould",
                "rust",
                "smudges",
                "corrosion",
            ],
            Effect::Weathering => &[
                "seed",
                "sim",
                "climate",
                "spotty",
                "roughy",
                "fade",
                "desaturate",
            ],
            // The soiling grows with the rainfalls.
            Effect::Foot => &["seed", "foot", "rain.layers"],
        }
    }

    /// Fields of [`Effect::params`] that finished layers follow without a
    /// new simulation ([`Effect::restyle`]). `rain.layers` is one only when
    /// it goes down and no enabled effect reads the rain's final state: each
    /// rainfall depends only on those before it, so the first N of M are the
    /// N-rainfall run, but the wall after N is not the wall after M.
    fn restyles(self, path: &str, old: &Preset, new: &Preset) -> bool {
        let read_by_enabled = |e: Effect| {
            Effect::ALL
                .iter()
                .any(|d| d.inputs().contains(&e) && d.enabled(new))
        };
        match self {
            Effect::Rain => match path {
                "stain.opacity" | "stain.washed_color" => true,
                // A deposit's colour map is made from the dirt's colour.
                "stain.color" => old.stain.wall_hue == 0.0 && new.stain.wall_hue == 0.0,
                // The washed layer exists on both sides.
                "stain.washed_opacity" => {
                    old.stain.washed_opacity > 0.0 && new.stain.washed_opacity > 0.0
                }
                // The washed runs sum every rainfall: fewer need a new run.
                "rain.layers" => {
                    new.rain.layers <= old.rain.layers
                        && !read_by_enabled(self)
                        && new.stain.washed_opacity == 0.0
                }
                _ => false,
            },
            // Off on both sides it made no layer to follow the rainfalls
            // (so it does not stop the rain's time slider from restyling).
            Effect::Foot => path == "rain.layers" && !old.foot.enabled && !new.foot.enabled,
            Effect::Moss
            | Effect::Dust
            | Effect::Gammaton
            | Effect::Imperfections
            | Effect::Weathering => false,
        }
    }

    /// Brings a finished layer of this effect in line with `preset` where
    /// [`Effect::restyles`] allows it; `index` counts this effect's layers
    /// from 0. On the preset a layer was made with, this changes nothing.
    pub fn restyle(self, layer: &mut Layer, index: usize, preset: &Preset) {
        match self {
            Effect::Rain => stages::restyle_rain(layer, index, preset),
            Effect::Moss
            | Effect::Dust
            | Effect::Gammaton
            | Effect::Imperfections
            | Effect::Weathering
            | Effect::Foot => {}
        }
    }

    /// Runs the effect.
    ///
    /// # Errors
    /// The effect's own errors, and [`crate::Error::Cancelled`].
    pub fn run(
        self,
        ctx: &Context,
        products: &mut Products,
        preset: &Preset,
        progress: &Progress,
    ) -> Result<Produced> {
        match self {
            Effect::Rain => stages::rain(ctx, products, preset, progress),
            Effect::Moss => stages::moss(ctx, products, preset, progress),
            Effect::Dust => stages::dust(ctx, products, preset, progress),
            Effect::Gammaton => gammaton::stage(ctx, products, preset, progress),
            Effect::Imperfections => imperfections::stage(ctx, products, preset, progress),
            Effect::Weathering => weathering::stage(ctx, products, preset, progress),
            Effect::Foot => foot::stage(ctx, products, preset, progress),
        }
    }
}

/// The read-only inputs every effect shares.
pub struct Context<'a> {
    /// The photo (in the wall's plane with a quad), for effects that
    /// change or follow its own colours.
    pub photo: &'a crate::photo::Photo,
    /// The simulation grid.
    pub grid: &'a Grid,
    /// Luminance on the grid, 0..255.
    pub luma: &'a RowMajor<f32>,
    /// The region on the grid: true = wall.
    pub region: &'a RowMajor<bool>,
    /// The region at the photo's size (255 = wall), `None` = whole photo.
    pub mask: Option<&'a GrayImage>,
    /// The region as a pixel sampler at the photo's size.
    pub wall: &'a region::Region<'a>,
    /// Tangent-space normal map at the photo's size, if given.
    pub normals: Option<&'a RgbImage>,
    /// The building around the wall: scale in metres, ground, ledges,
    /// shelter (photo pixels).
    pub site: &'a crate::pipeline::Site,
}

impl Context<'_> {
    /// Photo width and height.
    pub fn size(&self) -> (u32, u32) {
        (self.wall.width(), self.wall.height())
    }

    /// Photo pixels for a length in metres, through the scene's scale.
    pub fn photo_px(&self, metres: f32) -> f32 {
        self.site.px(metres)
    }

    /// Grid pixels for a length in metres.
    pub fn grid_px(&self, metres: f32) -> f32 {
        self.site.px(metres) / self.grid.scale
    }
}

/// What effects produced for later effects to read (grid-level maps).
#[derive(Debug, Clone, Default)]
pub struct Products {
    /// The rain's wall state after the last rainfall.
    pub rain: Option<Arc<rain::RainOutput>>,
    /// Rainfall counts after which the rain should also keep the wall (a
    /// time-lapse's frames; [`rain::simulate_keeping`]).
    pub keep_rain_at: Vec<u32>,
    /// The walls it kept, in rainfall order.
    pub rain_kept: Vec<Arc<rain::Kept>>,
    /// What a time-lapse's frames carry from one to the next (the dust so
    /// far, maps that do not age); `None` in a plain run.
    pub carry: Option<Box<carry::Carry>>,
    /// The sun and humidity maps, with the params they were made from.
    pub(crate) climate: Option<(crate::preset::ClimateParams, Arc<climate::Climate>)>,
}

impl Products {
    /// The climate maps for `p` ([`climate::maps`]), made once per run and
    /// shared by the effects that read them.
    pub fn climate(
        &mut self,
        ctx: &Context,
        p: &crate::preset::ClimateParams,
    ) -> Arc<climate::Climate> {
        match &self.climate {
            Some((made, maps)) if made == p => maps.clone(),
            _ => {
                let maps = Arc::new(climate::maps(ctx, p));
                self.climate = Some((p.clone(), maps.clone()));
                maps
            }
        }
    }
}

/// What one effect made.
#[derive(Debug, Clone)]
pub struct Produced {
    /// Its layers, bottom to top.
    pub layers: Vec<Layer>,
    /// Per-layer numbers (the rain's per-rainfall stats), by layer.
    pub layer_stats: Vec<Option<rain::LayerStats>>,
    /// Its numbers for the report.
    pub stats: Stats,
}

/// An effect's numbers in the report (`--report`), under its name.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Stats {
    /// Droplets per rainfall and the stains' D_max.
    Rain(RainStats),
    /// Colonies, dots, coverage.
    Moss(moss::MossStats),
    /// Particles per component, coverage.
    Dust(dust::DustStats),
    /// γ-tons emitted, settled, left; each substance's balance.
    Gammaton(gammaton::GammaStats),
    /// Each imperfection's coverage of its placement area.
    Imperfections(imperfections::ImperfectionStats),
    /// Light, humidity and each generator's mean strength.
    Weathering(weathering::WeatheringStats),
    /// How grown the foot's soiling is, and what it covers.
    Foot(foot::FootStats),
}

/// The effects whose output made with `old` is stale for `new`: those with
/// a changed field among their [`Effect::params`] that they cannot restyle,
/// and those that read a stale one's products. A changed field that no
/// effect lists makes every effect stale; the clock's `age` fields make
/// none (they act through the fields [`crate::clock`] sets).
pub fn stale(old: &Preset, new: &Preset) -> BTreeSet<Effect> {
    let (Ok(a), Ok(b)) = (toml::Value::try_from(old), toml::Value::try_from(new)) else {
        return Effect::ALL.into_iter().collect();
    };
    let mut changed = Vec::new();
    crate::preset::diff_paths(&a, &b, String::new(), &mut changed);
    let mut out = BTreeSet::new();
    for path in changed.iter().filter(|p| !covers("age", p)) {
        // The clock's fields act through the fields it sets (crate::clock),
        // and the sentence's through the fields it set.
        if path == "say" {
            continue;
        }
        let owners: Vec<Effect> = Effect::ALL
            .into_iter()
            .filter(|e| e.params().iter().any(|p| covers(p, path)))
            .collect();
        if owners.is_empty() {
            return Effect::ALL.into_iter().collect();
        }
        out.extend(owners.into_iter().filter(|e| !e.restyles(path, old, new)));
    }
    for e in Effect::ALL {
        if e.inputs().iter().any(|i| out.contains(i)) {
            out.insert(e);
        }
    }
    out
}

/// Whether params entry `prefix` covers the dotted `path`.
fn covers(prefix: &str, path: &str) -> bool {
    path == prefix
        || path
            .strip_prefix(prefix)
            .is_some_and(|rest| rest.starts_with('.'))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stain_colour_restyles_and_dust_alone_stays_dust() {
        let mut old = Preset::default();
        let mut new = old.clone();
        new.stain.color = [1, 2, 3];
        new.stain.opacity = 0.3;
        // A deposit's colour map is made from the dirt's colour.
        assert!(stale(&old, &new).contains(&Effect::Rain));
        old.stain.wall_hue = 0.0;
        new.stain.wall_hue = 0.0;
        assert!(stale(&old, &new).is_empty());
        new.dust.days += 1;
        assert_eq!(stale(&old, &new), BTreeSet::from([Effect::Dust]));
    }

    #[test]
    fn fewer_rainfalls_restyle_only_when_nothing_reads_the_final_wall() {
        let mut old = Preset::default();
        old.moss.enabled = false;
        old.foot.enabled = true;
        let mut new = old.clone();
        new.rain.layers -= 1;
        // The washed runs sum every rainfall: they need the new count.
        assert!(stale(&old, &new).contains(&Effect::Rain));
        old.stain.washed_opacity = 0.0;
        new.stain.washed_opacity = 0.0;
        // The foot's soiling grows with every rainfall: it is made anew,
        // unless it is off.
        assert_eq!(stale(&old, &new), BTreeSet::from([Effect::Foot]));
        let (mut off, mut off_new) = (old.clone(), new.clone());
        off.foot.enabled = false;
        off_new.foot.enabled = false;
        assert!(stale(&off, &off_new).is_empty());
        new.rain.layers += 2;
        assert_eq!(
            stale(&old, &new),
            BTreeSet::from([Effect::Rain, Effect::Moss, Effect::Foot])
        );
        // Moss grows from the wall after the last rainfall: a new rain run.
        new.rain.layers -= 2;
        new.moss.enabled = true;
        assert!(stale(&old, &new).contains(&Effect::Rain));
    }

    #[test]
    fn a_rain_change_reaches_moss_through_its_inputs_and_seed_reaches_all() {
        let old = Preset::default();
        let mut new = old.clone();
        new.rain.k_a *= 0.5;
        assert_eq!(
            stale(&old, &new),
            BTreeSet::from([Effect::Rain, Effect::Moss])
        );
        let mut new = old.clone();
        new.seed += 1;
        assert_eq!(stale(&old, &new).len(), Effect::ALL.len());
    }

    #[test]
    fn prefixes_cover_whole_segments_only() {
        assert!(covers("rain", "rain.k_a"));
        assert!(covers("stain.percentile", "stain.percentile"));
        assert!(!covers("rain", "rainbow"));
        assert!(!covers("stain.percentile", "stain.opacity"));
    }
}
