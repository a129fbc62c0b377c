//! What the workers run: the preview on a ~1 MP proxy ([`super::proxy`]),
//! and the export at full resolution. Both go through the core's one door:
//! the preview through [`pipeline::run_cached`], the export through
//! [`age::age_adjusted`], whose guard is the only overwrite check.
//!
//! A preview keeps its layer stack, so changes the core says need no new
//! simulation ([`effects::stale`] is empty: stain colour and opacity, fewer
//! rainfalls when nothing reads the last one) and layer visibility and
//! opacity only re-composite ([`Preview::restyle`], with
//! [`Effect::restyle`]).
//!
//! A simulation runs in two passes ([`Previewer::run`]): a quick one on a
//! coarse grid ([`QUICK_MAX_SIDE`]) that the canvas shows at once, then the
//! full one with the preset as it is. Each pass keeps a [`pipeline::Cache`],
//! so a change re-runs only the effects it makes stale (a dust change
//! re-runs the dust alone, a rain change keeps the dust), and the quick
//! pass is skipped when no effect to re-run depends on the grid.

use eframe::egui;

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use egui::ColorImage;
use image::DynamicImage;

use crate::age;
use crate::effects::{self, Effect};
use crate::error::Result;
use crate::pipeline::{self, Cache, Scene, Timing};
use crate::preset::Preset;
use crate::progress::Progress;
use crate::stack::Stack;

use super::state::{LayerSetting, apply_layer_settings};

pub use super::proxy::{PROXY_PIXELS, Proxy};

/// Longest side of the simulation grid in the quick pass. The droplet count
/// follows the grid's width and the streak geometry is resolution
/// independent, so the quick pass looks like the full one, only blurrier.
pub const QUICK_MAX_SIDE: u32 = 192;

/// One preview computation.
#[derive(Debug, Clone)]
pub struct PreviewJob {
    /// Proxy photo, mask and quad (proxy pixels).
    pub scene: Scene,
    /// The preset, source lines in proxy pixels.
    pub preset: Preset,
    /// Layer visibility and opacity.
    pub layers: BTreeMap<String, LayerSetting>,
}

/// A computed preview: the layer stack and its composite.
#[derive(Debug, Clone)]
pub struct Preview {
    /// The simulated stack, styled by the current settings.
    pub stack: Stack,
    /// The preset the stack was simulated with (for a quick pass: with the
    /// coarse grid).
    pub sim_preset: Preset,
    /// Opacity and visibility of each layer as the pipeline made it.
    original: Vec<(f32, bool)>,
    /// The composite, ready for a texture (shared with it, not copied).
    pub image: Arc<ColorImage>,
    /// True for a quick pass on a coarse grid; the full pass follows.
    pub quick: bool,
    /// Where the time went: the pipeline's stages (a kept effect as
    /// "NAME (kept)"), then "composite" and "image" (conversion for the
    /// texture), ms.
    pub timings: Vec<Timing>,
    /// With the clock on, the composite at each year up to the preset's
    /// age ([`super::ages`]); empty otherwise and for a quick pass.
    pub ages: Vec<super::ages::Frame>,
}

/// The quick pass's preset for a proxy of `width` x `height`: the same
/// preset on a grid of at most [`QUICK_MAX_SIDE`]. `None` when the full
/// pass's grid is not much finer than that (or there is nothing the grid
/// changes), so one pass is enough.
pub fn quick_preset(preset: &Preset, width: u32, height: u32) -> Option<Preset> {
    let longest = width.max(height);
    let full = match preset.sim.max_side {
        0 => longest,
        m => m.min(longest),
    };
    let grid_matters = preset.rain.layers > 0 || preset.moss.enabled;
    (grid_matters && full * 2 > QUICK_MAX_SIDE * 3).then(|| {
        let mut p = preset.clone();
        p.sim.max_side = QUICK_MAX_SIDE;
        p
    })
}

/// Runs preview jobs (the preview worker owns one): a quick pass on a
/// coarse grid, then the full pass, each keeping its effects' outputs for
/// the next run.
#[derive(Debug, Default)]
pub struct Previewer {
    quick: Cache,
    full: Cache,
}

impl Previewer {
    /// Both passes: hands the quick one to `emit` as soon as it is ready,
    /// then returns the full one. Stops at the pipeline's next check once
    /// `progress` is cancelled, also between and during the passes.
    ///
    /// # Errors
    /// As [`pipeline::run`].
    pub fn run(
        &mut self,
        job: PreviewJob,
        progress: &Progress,
        emit: &dyn Fn(Preview),
    ) -> Result<Preview> {
        if let Some(quick) = self.quick(&job, progress) {
            emit(quick?);
            progress.check()?;
        }
        self.full(&job, progress)
    }

    /// The quick pass alone; `None` when the job needs none: the grid is
    /// coarse already ([`quick_preset`]), or the full pass re-runs no effect
    /// the grid changes (e.g. a dust change: the full pass is quick).
    ///
    /// # Errors
    /// As [`pipeline::run`].
    pub fn quick(&mut self, job: &PreviewJob, progress: &Progress) -> Option<Result<Preview>> {
        let (w, h) = job.scene.size();
        let preset = quick_preset(&job.preset, w, h)?;
        let coarse = effects::stale(&job.preset, &preset);
        let kept = self.full.valid(&job.scene, &job.preset);
        let rerun = Effect::ALL
            .into_iter()
            .any(|e| e.enabled(&job.preset) && !kept.contains(&e) && coarse.contains(&e));
        rerun.then(|| pass(&mut self.quick, job, &preset, true, progress))
    }

    /// The full pass alone: the job's preset as it is.
    ///
    /// # Errors
    /// As [`pipeline::run`].
    pub fn full(&mut self, job: &PreviewJob, progress: &Progress) -> Result<Preview> {
        pass(&mut self.full, job, &job.preset, false, progress)
    }
}

/// One pass with `preset`, re-using what `cache` still holds, styled with
/// the job's preset and layer settings.
fn pass(
    cache: &mut Cache,
    job: &PreviewJob,
    preset: &Preset,
    quick: bool,
    progress: &Progress,
) -> Result<Preview> {
    // With the clock on, the full pass also makes every year's frame (a
    // run of its own: the cache's rain would not have kept their walls).
    let (out, ages) = match (quick, preset.age.years) {
        (false, Some(_)) => {
            *cache = Cache::default();
            super::ages::run(&job.scene, preset, &job.layers, progress)?
        }
        _ => (
            pipeline::run_cached(&job.scene, preset, progress, cache)?,
            Vec::new(),
        ),
    };
    let original = out
        .stack
        .layers
        .iter()
        .map(|l| (l.opacity, l.visible))
        .collect();
    let mut preview = Preview {
        stack: out.stack,
        sim_preset: preset.clone(),
        original,
        image: Arc::default(),
        quick,
        timings: out.report.timings,
        ages,
    };
    progress.update("composite", 1.0);
    let [composite, image] = preview.restyle_timed(&job.preset, &job.layers);
    preview.timings.extend([composite, image]);
    Ok(preview)
}

fn lap(stage: &str, since: Instant) -> Timing {
    Timing {
        stage: stage.into(),
        ms: since.elapsed().as_secs_f64() * 1000.0,
    }
}

/// Runs the pipeline for a preview and composites it: the full pass alone,
/// with nothing kept from earlier runs.
///
/// # Errors
/// As [`pipeline::run`].
pub fn simulate(job: PreviewJob, progress: &Progress) -> Result<Preview> {
    Previewer::default().full(&job, progress)
}

/// Whether a preview simulated with `sim` can follow `next` by a restyle
/// alone: the core makes no effect stale ([`effects::stale`]).
pub fn restyles(sim: &Preset, next: &Preset) -> bool {
    effects::stale(sim, next).is_empty()
}

impl Preview {
    /// Applies the preset's restyle-only fields ([`Effect::restyle`]) and
    /// the layer settings, then re-composites. Call only when
    /// [`restyles`] holds for the preset it was simulated with.
    pub fn restyle(&mut self, preset: &Preset, layers: &BTreeMap<String, LayerSetting>) {
        self.restyle_timed(preset, layers);
    }

    /// [`Preview::restyle`], returning the time of the composite and of the
    /// conversion to a texture image.
    fn restyle_timed(
        &mut self,
        preset: &Preset,
        layers: &BTreeMap<String, LayerSetting>,
    ) -> [Timing; 2] {
        let start = Instant::now();
        style_stack(&mut self.stack, &self.original, preset);
        apply_layer_settings(layers, &mut self.stack);
        let composite = self.stack.composite();
        let t_composite = lap("composite", start);
        let start = Instant::now();
        self.image = Arc::new(to_color_image(&composite));
        [t_composite, lap("image", start)]
    }

    /// Names of the layers, bottom to top.
    pub fn layer_names(&self) -> Vec<String> {
        self.stack.layers.iter().map(|l| l.name.clone()).collect()
    }
}

/// Puts each layer back as the pipeline made it, then lets its effect
/// restyle it for `preset` (by kind, counting each effect's layers).
fn style_stack(stack: &mut Stack, original: &[(f32, bool)], preset: &Preset) {
    let mut index: BTreeMap<Effect, usize> = BTreeMap::new();
    for (layer, &(opacity, visible)) in stack.layers.iter_mut().zip(original) {
        layer.opacity = opacity;
        layer.visible = visible;
        if let Some(kind) = layer.kind {
            let i = index.entry(kind).or_default();
            kind.restyle(layer, *i, preset);
            *i += 1;
        }
    }
}

/// An image as an egui texture source.
pub fn to_color_image(img: &DynamicImage) -> ColorImage {
    let size = [img.width() as usize, img.height() as usize];
    match img {
        DynamicImage::ImageRgb8(rgb) => ColorImage::from_rgb(size, rgb.as_raw()),
        DynamicImage::ImageRgba8(rgba) => ColorImage::from_rgba_unmultiplied(size, rgba.as_raw()),
        other if other.color().has_alpha() => {
            ColorImage::from_rgba_unmultiplied(size, other.to_rgba8().as_raw())
        }
        other => ColorImage::from_rgb(size, other.to_rgb8().as_raw()),
    }
}

/// One full-resolution export.
#[derive(Debug, Clone)]
pub struct ExportJob {
    /// Full-size photo, mask and quad.
    pub scene: Scene,
    /// The files the document was loaded from (photo, mask, project), which
    /// the export must not overwrite ([`age::guard`]).
    pub from: Vec<PathBuf>,
    /// The preset with the document's source lines.
    pub preset: Preset,
    /// Layer visibility and opacity.
    pub layers: BTreeMap<String, LayerSetting>,
    /// Output file; its extension picks the format.
    pub path: PathBuf,
    /// Write the time-lapse (year 0 to the preset's age) to `path` instead.
    pub timelapse: bool,
}

/// What an export wrote.
#[derive(Debug, Clone)]
pub struct Exported {
    /// The file.
    pub path: PathBuf,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Number of layers.
    pub layers: usize,
}

/// Ages the document at full resolution and saves it, through
/// [`age::age_adjusted`] (which applies the layer settings).
///
/// # Errors
/// [`age::guard`]'s errors (an output that is an input, a missing folder,
/// an unknown extension) before any work, then as [`age::age`].
pub fn export(job: ExportJob, progress: &Progress) -> Result<Exported> {
    let inputs = age::Inputs {
        source: age::Source::Loaded {
            scene: job.scene,
            from: job.from,
        },
        mask: None,
        normal_map: None,
        quad: None,
        // The document's own region and source lines, never re-detected.
        region: age::RegionMode::Full,
        sources: age::SourcesMode::Auto,
        wall_width_m: None,
    };
    let outputs = match job.timelapse {
        false => age::Outputs {
            images: vec![job.path.clone()],
            ..age::Outputs::default()
        },
        true => {
            let mut t = crate::timelapse::Timelapse::new(&job.path);
            t.pins = crate::clock::pins_of(&job.preset);
            t.caption = true;
            age::Outputs {
                timelapse: Some(t),
                ..age::Outputs::default()
            }
        }
    };
    let adjust = |stack: &mut Stack| apply_layer_settings(&job.layers, stack);
    let out = age::age_adjusted(&inputs, &job.preset, &outputs, progress, &adjust)?;
    Ok(Exported {
        path: job.path,
        width: out.stack.base.width(),
        height: out.stack.base.height(),
        layers: out.stack.layers.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rain_only(p: &mut Preset) {
        for effect in ["moss", "dust"] {
            let _ = p.set(&format!("{effect}.enabled=false"));
        }
    }

    #[test]
    fn first_rainfalls_of_a_longer_run_are_the_shorter_run() {
        // What lets the time slider scrub down without re-simulating.
        let d = crate::demo::facade(96, 72);
        let scene = Scene::new(d.photo, d.region).unwrap();
        let mut p = Preset::default();
        p.rain.source_lines = d.source_lines;
        p.rain.droplets = 200;
        p.rain.layers = 4;
        rain_only(&mut p);
        let long = crate::pipeline::run(&scene, &p, &Progress::none())
            .unwrap()
            .stack;
        p.rain.layers = 2;
        let short = crate::pipeline::run(&scene, &p, &Progress::none())
            .unwrap()
            .stack;
        // The rainfalls' own layers (the washed runs sum them all).
        let rainfalls = |s: &crate::stack::Stack| {
            let washed = crate::effects::WASHED;
            s.layers
                .iter()
                .filter(|l| l.name != washed)
                .cloned()
                .collect::<Vec<_>>()
        };
        let (short, long) = (rainfalls(&short), rainfalls(&long));
        assert_eq!(short.len(), 2);
        for (a, b) in short.iter().zip(&long) {
            assert_eq!(a.to_rgba(), b.to_rgba(), "{}", a.name);
        }
    }

    fn facade_job(w: u32, h: u32, edit: impl Fn(&mut Preset)) -> PreviewJob {
        let d = crate::demo::facade(w, h);
        let mut p = Preset::default();
        p.rain.source_lines = d.source_lines.clone();
        p.rain.droplets = 300;
        p.rain.layers = 3;
        edit(&mut p);
        PreviewJob {
            scene: Scene::new(d.photo, d.region).unwrap(),
            preset: p,
            layers: BTreeMap::new(),
        }
    }

    #[test]
    fn the_quick_pass_only_coarsens_the_grid() {
        let p = Preset::default();
        let q = quick_preset(&p, 1155, 866).expect("1 MP proxy, 1024 grid: two passes");
        assert_eq!(q.sim.max_side, QUICK_MAX_SIDE);
        let mut back = q.clone();
        back.sim.max_side = p.sim.max_side;
        assert_eq!(back, p, "every other parameter is the same");
        let mut photo_res = p.clone();
        photo_res.sim.max_side = 0;
        assert!(quick_preset(&photo_res, 1155, 866).is_some());
        assert!(
            quick_preset(&p, 240, 180).is_none(),
            "a small photo's grid is coarse already"
        );
        let mut coarse = p.clone();
        coarse.sim.max_side = QUICK_MAX_SIDE;
        assert!(quick_preset(&coarse, 1155, 866).is_none());
    }

    #[test]
    fn run_shows_the_quick_pass_then_the_full_one() {
        let job = facade_job(480, 360, |_| {});
        let shown = std::sync::Mutex::new(Vec::new());
        let full = Previewer::default()
            .run(job.clone(), &Progress::none(), &|p| {
                shown.lock().unwrap().push(p)
            })
            .unwrap();
        let shown = shown.into_inner().unwrap();
        assert_eq!(shown.len(), 1, "one quick pass before the full one");
        let quick = &shown[0];
        assert!(quick.quick && !full.quick);
        assert_eq!(quick.sim_preset.sim.max_side, QUICK_MAX_SIDE);
        assert_eq!(full.sim_preset, job.preset);
        assert_eq!(quick.image.size, full.image.size);
        assert_eq!(quick.layer_names(), full.layer_names());
        assert_ne!(quick.image, full.image, "the full pass adds detail");
        let fresh = simulate(job, &Progress::none()).unwrap();
        assert_eq!(full.image, fresh.image, "the full pass is the plain run");
    }

    #[test]
    fn the_full_pass_stops_when_cancelled_after_the_quick_one() {
        let job = facade_job(480, 360, |p| p.rain.layers = 200);
        let cancel = std::sync::atomic::AtomicBool::new(false);
        let progress = Progress::new(None, Some(&cancel));
        let shown = std::sync::Mutex::new(None);
        let r = Previewer::default().run(job, &progress, &|_| {
            // A newer change arrives as soon as the quick pass shows.
            *shown.lock().unwrap() = Some(std::time::Instant::now());
            cancel.store(true, std::sync::atomic::Ordering::Relaxed);
        });
        assert!(
            matches!(r, Err(crate::Error::Cancelled)),
            "{:?}",
            r.map(|_| ())
        );
        let at = shown.into_inner().unwrap().expect("the quick pass showed");
        assert!(
            at.elapsed() < std::time::Duration::from_secs(2),
            "stopped {:?} after the quick pass",
            at.elapsed()
        );
    }

    /// Whether the pass kept `effect`'s output from the run before.
    fn kept(p: &Preview, effect: &str) -> bool {
        p.timings
            .iter()
            .any(|t| t.stage == format!("{effect} (kept)"))
    }

    #[test]
    fn kept_effects_match_a_fresh_run() {
        let mut previewer = Previewer::default();
        let a = facade_job(240, 180, |p| p.rain.k_a = 0.5);
        let first = previewer.full(&a, &Progress::none()).unwrap();
        assert!(
            first
                .stack
                .layers
                .iter()
                .any(|l| l.kind == Some(Effect::Dust))
        );
        assert!(!kept(&first, "dust"));
        // A rain change: the dust is kept, the picture is the fresh run's.
        let mut b = facade_job(240, 180, |p| p.rain.k_a = 0.6);
        b.scene = a.scene.clone(); // the same buffers, as the GUI's proxy
        let same_dust = previewer.full(&b, &Progress::none()).unwrap();
        assert!(kept(&same_dust, "dust") && !kept(&same_dust, "rain"));
        let fresh = simulate(b.clone(), &Progress::none()).unwrap();
        assert_eq!(same_dust.layer_names(), fresh.layer_names());
        assert_eq!(same_dust.image, fresh.image);
        // A dust change: only the dust is made again.
        b.preset.dust.days += 30;
        let redone = previewer.full(&b, &Progress::none()).unwrap();
        assert!(!kept(&redone, "dust"));
        assert!(kept(&redone, "rain") && kept(&redone, "moss"));
        assert_eq!(
            redone.image,
            simulate(b.clone(), &Progress::none()).unwrap().image
        );
        // Another region: everything is made again.
        let mut region = (*b.scene.region.clone().unwrap()).clone();
        for px in region.pixels_mut().take(20_000) {
            px[0] = 0;
        }
        b.scene = Scene::shared(Arc::clone(&b.scene.photo), Some(Arc::new(region))).unwrap();
        let other = previewer.full(&b, &Progress::none()).unwrap();
        assert!(!kept(&other, "dust") && !kept(&other, "rain"));
        assert_eq!(other.image, simulate(b, &Progress::none()).unwrap().image);
    }

    #[test]
    fn a_dust_change_skips_the_quick_pass() {
        let mut previewer = Previewer::default();
        let mut job = facade_job(480, 360, |_| {});
        assert!(previewer.quick(&job, &Progress::none()).is_some());
        previewer.full(&job, &Progress::none()).unwrap();
        job.preset.dust.days += 30;
        assert!(
            previewer.quick(&job, &Progress::none()).is_none(),
            "only the dust re-runs: the full pass is quick"
        );
        job.preset.rain.k_a *= 0.5;
        assert!(previewer.quick(&job, &Progress::none()).is_some());
    }

    #[test]
    fn restyle_matches_a_fresh_simulation() {
        let d = crate::demo::facade(96, 72);
        let job = |layers: u32, opacity: f32| {
            let mut p = Preset::default();
            p.rain.source_lines = d.source_lines.clone();
            p.rain.droplets = 200;
            p.rain.layers = layers;
            p.stain.opacity = opacity;
            // Fewer rainfalls restyle only without the washed runs.
            p.stain.washed_opacity = 0.0;
            rain_only(&mut p);
            PreviewJob {
                scene: Scene::new(d.photo.clone(), d.region.clone()).unwrap(),
                preset: p,
                layers: BTreeMap::new(),
            }
        };
        let mut a = simulate(job(4, 0.8), &Progress::none()).unwrap();
        let fresh = simulate(job(2, 0.5), &Progress::none()).unwrap();
        let target = job(2, 0.5).preset;
        assert!(restyles(&a.sim_preset, &target));
        a.restyle(&target, &BTreeMap::new());
        assert_eq!(a.image, fresh.image);
    }
}
