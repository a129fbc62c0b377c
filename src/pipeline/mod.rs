//! The one door into the core: scene + preset in, layer stack and report
//! out. `grime run`, `grime batch` (through [`crate::age`]) and the GUI's
//! preview and export all call [`run`] or [`run_cached`].
//!
//! A run prepares the simulation grid once ([`Context`]), then runs every
//! enabled [`Effect`] in order, each on its share of the progress bar. With
//! a wall plane ([`Scene::quad`]) it runs in that plane and warps the layers
//! back onto the photo. A [`Cache`] keeps each effect's output with the
//! preset it was made with, so a later run re-simulates only the effects
//! whose fields changed ([`crate::effects::stale`]).

mod frames;
mod previews;
mod report;
mod scene;
mod site;

use std::collections::{BTreeMap, BTreeSet};
use std::sync::Arc;

use crate::effects::rain::RainOutput;
use crate::effects::region::Region;
use crate::effects::{Context, Effect, Produced, Products};
use crate::error::{Error, Result};
use crate::grid::Grid;
use crate::perspective::{Quad, Rectifier};
use crate::preset::Preset;
use crate::progress::Progress;
use crate::stack::Stack;

pub use frames::{Frame, run_frames, run_sharing_rain};
pub use previews::{KEY_EVERY, key_frames, run_previews};
pub use report::{GridReport, LayerReport, Report, Size, Timing};
pub use scene::Scene;
pub use site::{ASSUMED_WALL_WIDTH_M, Site};

use report::Clock;

/// The pipeline's result.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// Photo plus effect layers.
    pub stack: Stack,
    /// What happened, in numbers.
    pub report: Report,
    /// The rain's grid-level result (wall water and dirt), for effects and
    /// tools that build on it. With a wall plane, it is the plane's.
    pub rain: Arc<RainOutput>,
    /// The simulation grid (the wall plane's, with a quad).
    pub grid: Grid,
}

/// Each effect's last output and the preset it was made with, for
/// [`run_cached`]. Made for one scene: a run on another scene (other photo,
/// region, normals or quad buffers) starts it afresh.
#[derive(Debug)]
pub struct Cache {
    /// Whether to keep outputs at all: a plain [`run`] keeps none (a copy
    /// of every layer costs time and memory at full size).
    keep: bool,
    scene: Option<Scene>,
    made: BTreeMap<Effect, (Preset, Produced)>,
    /// Per effect in `made`: the stamp of the files it read
    /// ([`files_stamp`]; none = 0).
    stamps: BTreeMap<Effect, u64>,
    products: Products,
}

impl Default for Cache {
    /// An empty cache that keeps what runs make.
    fn default() -> Self {
        Cache {
            keep: true,
            scene: None,
            made: BTreeMap::new(),
            stamps: BTreeMap::new(),
            products: Products::default(),
        }
    }
}

impl Cache {
    /// A cache that keeps nothing.
    fn none() -> Cache {
        Cache {
            keep: false,
            ..Cache::default()
        }
    }

    /// The effects whose kept output is still valid for `preset` on `scene`
    /// (before the effects that read re-run ones are counted out).
    pub fn valid(&self, scene: &Scene, preset: &Preset) -> BTreeSet<Effect> {
        if !self.scene.as_ref().is_some_and(|s| s.same_as(scene)) {
            return BTreeSet::new();
        }
        self.made
            .iter()
            .filter(|(e, (old, _))| !crate::effects::stale(old, preset).contains(e))
            .filter(|(e, _)| self.stamps.get(e).copied().unwrap_or(0) == files_stamp(**e, preset))
            .map(|(e, _)| *e)
            .collect()
    }
}

/// Runs every enabled effect on the scene.
///
/// # Errors
/// [`Error::EmptyRegion`] for an empty mask, [`Error::Cancelled`] when the
/// progress's cancel flag is set, a bad quad's or an invalid preset's error.
pub fn run(scene: &Scene, preset: &Preset, progress: &Progress) -> Result<Outcome> {
    run_cached(scene, preset, progress, &mut Cache::none())
}

/// [`run`], re-using from `cache` each effect whose output is still valid,
/// and leaving this run's outputs in it. The result is the same as [`run`]'s.
///
/// # Errors
/// As [`run`].
pub fn run_cached(
    scene: &Scene,
    preset: &Preset,
    progress: &Progress,
    cache: &mut Cache,
) -> Result<Outcome> {
    preset.validate()?;
    let valid = cache.valid(scene, preset);
    if !cache.scene.as_ref().is_some_and(|s| s.same_as(scene)) {
        *cache = Cache {
            keep: cache.keep,
            scene: Some(scene.clone()),
            ..Cache::default()
        };
    }
    match &scene.quad {
        None => run_effects(scene, preset, progress, cache, &valid, preset),
        Some(quad) => in_plane(scene, quad, preset, progress, cache, &valid),
    }
}

/// What every effect of a scene reads besides the photo: the simulation
/// grid and the luminance and region on it.
struct Prepared {
    grid: Grid,
    luma: crate::field::RowMajor<f32>,
    region: crate::field::RowMajor<bool>,
}

impl Prepared {
    fn new(scene: &Scene, preset: &Preset) -> Result<Prepared> {
        let (w, h) = scene.size();
        let mask = scene.region.as_deref();
        let grid = Grid::new(w, h, mask, preset.sim.max_side)?;
        let luma = grid.luma(&scene.photo);
        let region = grid.region(mask);
        Ok(Prepared { grid, luma, region })
    }

    /// The effects' shared inputs; `wall` is the scene's region.
    fn context<'a>(&'a self, scene: &'a Scene, wall: &'a Region<'a>) -> Context<'a> {
        Context {
            photo: &scene.photo,
            grid: &self.grid,
            luma: &self.luma,
            region: &self.region,
            mask: scene.region.as_deref(),
            wall,
            normals: scene.normals.as_deref(),
            site: &scene.site,
        }
    }
}

/// The effects on the scene's own pixels; their outputs go into `cache`
/// under `made_with`, the preset as the caller gave it.
fn run_effects(
    scene: &Scene,
    preset: &Preset,
    progress: &Progress,
    cache: &mut Cache,
    valid: &BTreeSet<Effect>,
    made_with: &Preset,
) -> Result<Outcome> {
    let mut clock = Clock::start();
    let (w, h) = scene.size();
    let prepared = Prepared::new(scene, preset)?;
    let wall = Region::new(w, h, scene.region.as_deref())?;
    let ctx = prepared.context(scene, &wall);
    clock.lap("grid");
    progress.update("prepare", 0.05);

    let enabled: Vec<Effect> = Effect::ALL
        .into_iter()
        .filter(|e| e.enabled(preset))
        .collect();
    let total: f32 = enabled.iter().map(|e| e.weight()).sum();
    let mut at = 0.05;
    let mut rerun = BTreeSet::new();
    let mut stack = Stack {
        base: Arc::clone(&scene.photo),
        layers: Vec::new(),
        region: scene.region.clone(),
    };
    let mut layer_reports = Vec::new();
    let mut effects = BTreeMap::new();
    for effect in enabled {
        progress.check()?;
        let end = at + 0.95 * effect.weight() / total;
        let keep = valid.contains(&effect) && !effect.inputs().iter().any(|i| rerun.contains(i));
        let produced = match (keep, cache.made.get(&effect)) {
            (true, Some((_, kept))) => {
                let kept = kept.clone();
                clock.lap(&format!("{} (kept)", effect.name()));
                kept
            }
            _ => {
                rerun.insert(effect);
                let stamp = files_stamp(effect, made_with);
                let made =
                    effect.run(&ctx, &mut cache.products, preset, &progress.span(at, end))?;
                if cache.keep {
                    cache.made.insert(effect, (made_with.clone(), made.clone()));
                    cache.stamps.insert(effect, stamp);
                }
                clock.lap(effect.name());
                made
            }
        };
        at = end;
        for (i, (mut layer, stats)) in produced
            .layers
            .into_iter()
            .zip(produced.layer_stats)
            .enumerate()
        {
            effect.restyle(&mut layer, i, preset);
            layer_reports.push(LayerReport::of(&layer, stats));
            stack.layers.push(layer);
        }
        effects.insert(effect, produced.stats);
    }
    progress.update("done", 1.0);
    let rain = cache
        .products
        .rain
        .clone()
        .ok_or_else(|| Error::Preset("the rain did not run".into()))?;
    let grid = prepared.grid;
    let report = Report {
        image: Size {
            width: w,
            height: h,
        },
        grid: GridReport {
            width: grid.width,
            height: grid.height,
            scale: grid.scale,
        },
        seed: preset.seed,
        layers: layer_reports,
        effects,
        timings: clock.timings,
    };
    Ok(Outcome {
        stack,
        report,
        rain,
        grid,
    })
}

/// A stamp of the files `effect` reads besides the scene and the preset
/// (the γ-tons' painted masks), so a kept output goes stale when one of
/// them changes under the same preset; 0 for effects that read none.
fn files_stamp(effect: Effect, preset: &Preset) -> u64 {
    match effect {
        Effect::Gammaton => crate::effects::gammaton::files_stamp(&preset.gammaton),
        _ => 0,
    }
}

/// The effects in the wall plane of `quad` (Endo et al.), with layers
/// warped back to the photo. Source lines in `preset` are photo pixels and
/// are mapped into the plane; a normal map is resampled into it.
fn in_plane(
    scene: &Scene,
    quad: &Quad,
    preset: &Preset,
    progress: &Progress,
    cache: &mut Cache,
    valid: &BTreeSet<Effect>,
) -> Result<Outcome> {
    let (w, h) = scene.size();
    let region = scene.region.as_deref();
    let (rect, plane) = plane_of(scene, quad)?;
    let plane_preset = plane_preset(&rect, preset);
    progress.update("rectify", 0.02);
    let out = run_effects(
        &plane,
        &plane_preset,
        &progress.span(0.02, 0.9),
        cache,
        valid,
        preset,
    )?;
    let mut layers = Vec::with_capacity(out.stack.layers.len());
    for (i, layer) in out.stack.layers.iter().enumerate() {
        progress.check()?;
        progress.update(
            "warp back",
            0.9 + 0.1 * i as f32 / out.stack.layers.len() as f32,
        );
        layers.push(rect.unrectify_layer(layer, w, h, region));
    }
    let mut report = out.report;
    report.image = Size {
        width: w,
        height: h,
    };
    for (r, l) in report.layers.iter_mut().zip(&layers) {
        r.coverage = l.coverage();
    }
    progress.update("done", 1.0);
    Ok(Outcome {
        stack: Stack {
            base: Arc::clone(&scene.photo),
            layers,
            region: scene.region.clone(),
        },
        report,
        rain: out.rain,
        grid: out.grid,
    })
}

/// The rectifier of `quad` on `scene` and the scene in the wall's plane:
/// the photo, mask and normal map rectified.
fn plane_of(scene: &Scene, quad: &Quad) -> Result<(Rectifier, Scene)> {
    let (w, h) = scene.size();
    let rect = Rectifier::new(quad, (w as u64 * h as u64).saturating_mul(2))?;
    let mut plane = Scene::new(
        rect.rectify_photo(&scene.photo),
        Some(rect.rectify_mask(scene.region.as_deref(), w, h)),
    )?;
    if let Some(normals) = &scene.normals {
        plane = plane.with_normals(rect.rectify_rgb(normals))?;
    }
    // The plane keeps the wall's scale; ground, ledges and shelter are the
    // photo's and are not carried into it (source lines are, by
    // `plane_preset`).
    let (pw, ph) = plane.size();
    let stretch = (quad_area(quad) / (pw as f32 * ph as f32)).sqrt();
    plane.site.metres_per_pixel = scene.site.metres_per_pixel * stretch.max(1e-3);
    Ok((rect, plane))
}

/// `preset` in the wall plane of `rect`: its source lines (photo pixels)
/// mapped into it.
fn plane_preset(rect: &Rectifier, preset: &Preset) -> Preset {
    let mut plane = preset.clone();
    for line in &mut plane.rain.source_lines {
        for p in line.iter_mut() {
            let (u, v) = rect.photo_to_rect_unbounded(p[0], p[1]);
            *p = [u, v];
        }
    }
    plane
}

/// Area of a quad in photo pixels (shoelace formula).
fn quad_area(q: &Quad) -> f32 {
    let twice: f32 = (0..4)
        .map(|i| {
            let (a, b) = (q[i], q[(i + 1) % 4]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum();
    twice.abs() / 2.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::demo;
    use crate::stack::LayerPixels;

    fn small() -> (Scene, Preset) {
        let d = demo::facade(120, 90);
        let mut p = Preset::default();
        p.rain.layers = 2;
        p.rain.droplets = 120;
        p.rain.source_lines = d.source_lines;
        (Scene::new(d.photo, d.region).unwrap(), p)
    }

    fn pixels(out: &Outcome) -> Vec<Vec<u8>> {
        let raw = |l: &crate::stack::Layer| match &l.pixels {
            LayerPixels::Tint { alpha, .. } => alpha.as_raw().clone(),
            LayerPixels::Rgba(img) => img.as_raw().clone(),
            LayerPixels::Painted { color, alpha } => {
                [color.as_raw().clone(), alpha.as_raw().clone()].concat()
            }
        };
        out.stack.layers.iter().map(raw).collect()
    }

    #[test]
    fn a_cached_run_equals_a_fresh_one_and_keeps_what_is_valid() {
        let (scene, mut p) = small();
        let mut cache = Cache::default();
        run_cached(&scene, &p, &Progress::none(), &mut cache).unwrap();
        p.dust.days += 30;
        let cached = run_cached(&scene, &p, &Progress::none(), &mut cache).unwrap();
        let fresh = run(&scene, &p, &Progress::none()).unwrap();
        assert_eq!(pixels(&cached), pixels(&fresh));
        let stages: Vec<&str> = cached
            .report
            .timings
            .iter()
            .map(|t| t.stage.as_str())
            .collect();
        assert!(
            stages.contains(&"rain (kept)") && stages.contains(&"moss (kept)"),
            "{stages:?}"
        );
        assert!(stages.contains(&"dust"), "dust re-ran: {stages:?}");
        // Another scene (new buffers) starts the cache afresh.
        let other = Scene::shared(Arc::clone(&scene.photo), None).unwrap();
        let out = run_cached(&other, &p, &Progress::none(), &mut cache).unwrap();
        assert!(
            out.report
                .timings
                .iter()
                .all(|t| !t.stage.ends_with("(kept)"))
        );
    }

    #[test]
    fn fewer_rainfalls_hide_layers_without_a_new_simulation() {
        let (scene, mut p) = small();
        p.moss.enabled = false;
        p.dust.enabled = false;
        p.stain.washed_opacity = 0.0;
        let mut cache = Cache::default();
        run_cached(&scene, &p, &Progress::none(), &mut cache).unwrap();
        p.rain.layers = 1;
        let out = run_cached(&scene, &p, &Progress::none(), &mut cache).unwrap();
        let visible: Vec<bool> = out.stack.layers.iter().map(|l| l.visible).collect();
        assert_eq!(visible, [true, false]);
        assert!(out.report.timings.iter().any(|t| t.stage == "rain (kept)"));
    }

    #[test]
    fn a_quad_keeps_the_normal_map() {
        let (scene, mut p) = small();
        p.rain.layers = 0;
        p.moss.enabled = false;
        // Dust at Santos' own resolution, on the whole wall.
        p.dust.ppi = 150.0;
        p.dust.open_wall = 1.0;
        let (w, h) = scene.size();
        // Every normal facing down: the dust collects less (shade.rs).
        let down = image::RgbImage::from_pixel(w, h, image::Rgb([128, 0, 128]));
        let quad = [
            [0.0, 0.0],
            [w as f32, 0.0],
            [w as f32, h as f32],
            [0.0, h as f32],
        ];
        let plain = scene.clone().with_quad(Some(quad)).unwrap();
        let with_normals = plain.clone().with_normals(down).unwrap();
        let a = run(&plain, &p, &Progress::none()).unwrap();
        let b = run(&with_normals, &p, &Progress::none()).unwrap();
        assert_ne!(pixels(&a), pixels(&b), "the normal map changed the dust");
    }
}
