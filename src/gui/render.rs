//! What the workers run: the preview on a ~1 MP proxy, and the export at
//! full resolution. Both call the same pipeline as the CLI
//! ([`perspective::pipeline_with_quad`], which is [`crate::pipeline::run`]
//! without a quad).
//!
//! A preview keeps its layer stack, so changes that need no new simulation
//! (stain colour and opacity, layer visibility and opacity, fewer rainfalls)
//! only re-composite: see [`needs_simulation`] and [`Preview::restyle`].
//!
//! A simulation runs in two passes ([`Previewer::run`]): a quick one on a
//! coarse grid ([`QUICK_MAX_SIDE`]) that the canvas shows at once, then the
//! full one with the preset as it is. The [`Previewer`] also keeps the dust
//! layers between runs: they depend only on the region, the quad, the dust
//! parameters and the seed, so a rain or moss change reuses them.

use eframe::egui;

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use egui::ColorImage;
use image::{DynamicImage, GrayImage};

use crate::age;
use crate::error::Result;
use crate::perspective::Quad;
use crate::photo::Photo;
use crate::pipeline::{Scene, Timing};
use crate::preset::{DustParams, Preset};
use crate::progress::Progress;
use crate::stack::{Layer, LayerPixels, Stack};

use super::state::{LayerSetting, apply_layer_settings};
use super::tools::PixelRect;

/// Pixels of the preview proxy (about 1 MP).
pub const PROXY_PIXELS: u64 = 1_000_000;

/// Longest side of the simulation grid in the quick pass. The droplet count
/// follows the grid's width and the streak geometry is resolution
/// independent, so the quick pass looks like the full one, only blurrier.
pub const QUICK_MAX_SIDE: u32 = 192;

/// The photo and mask scaled down for previews, and the mapping to them.
#[derive(Debug, Clone)]
pub struct Proxy {
    /// Proxy pixels per photo pixel, horizontally.
    pub sx: f32,
    /// Proxy pixels per photo pixel, vertically.
    pub sy: f32,
    /// The scaled photo (the photo itself when it is small enough).
    pub photo: Arc<Photo>,
    /// The scaled mask, area-averaged.
    pub mask: GrayImage,
}

impl Proxy {
    /// The proxy of `photo` with at most `max_pixels` pixels.
    pub fn new(photo: &Arc<Photo>, mask: &GrayImage, max_pixels: u64) -> Proxy {
        let (w, h) = (photo.width(), photo.height());
        let s = (max_pixels as f64 / (w as f64 * h as f64)).sqrt().min(1.0);
        if s >= 1.0 {
            return Proxy {
                sx: 1.0,
                sy: 1.0,
                photo: Arc::clone(photo),
                mask: mask.clone(),
            };
        }
        let (pw, ph) = (
            ((w as f64 * s).round() as u32).max(1),
            ((h as f64 * s).round() as u32).max(1),
        );
        let img = photo
            .image()
            .resize_exact(pw, ph, image::imageops::FilterType::Triangle);
        let mut small = Photo::new(img);
        small.icc = photo.icc.clone();
        let mut proxy = Proxy {
            sx: pw as f32 / w as f32,
            sy: ph as f32 / h as f32,
            photo: Arc::new(small),
            mask: GrayImage::new(pw, ph),
        };
        proxy.update_mask(mask, PixelRect::full(w, h));
        proxy
    }

    /// True when the proxy is the photo itself.
    pub fn is_full_size(&self) -> bool {
        self.sx == 1.0 && self.sy == 1.0
    }

    /// Re-samples the proxy mask where the photo mask changed (`rect`, photo
    /// pixels). Returns the proxy pixels that were updated.
    pub fn update_mask(&mut self, full: &GrayImage, rect: PixelRect) -> Option<PixelRect> {
        let (pw, ph) = self.mask.dimensions();
        let (w, h) = full.dimensions();
        let r = PixelRect::around(
            rect.x0 as f32 * self.sx,
            rect.y0 as f32 * self.sy,
            rect.x1 as f32 * self.sx,
            rect.y1 as f32 * self.sy,
            pw,
            ph,
        )?;
        if self.is_full_size() {
            for y in r.y0..r.y1 {
                let s = (y * w + r.x0) as usize;
                let e = s + r.width() as usize;
                self.mask.as_mut()[s..e].copy_from_slice(&full.as_raw()[s..e]);
            }
            return Some(r);
        }
        let span = |p: u32, s: f32, max: u32| {
            let a = ((p as f32 / s) as u32).min(max - 1);
            let b = (((p + 1) as f32 / s).ceil() as u32).clamp(a + 1, max);
            (a, b)
        };
        let raw = full.as_raw();
        for py in r.y0..r.y1 {
            let (ya, yb) = span(py, self.sy, h);
            for px in r.x0..r.x1 {
                let (xa, xb) = span(px, self.sx, w);
                let mut sum = 0u64;
                for y in ya..yb {
                    let row = &raw[(y * w + xa) as usize..(y * w + xb) as usize];
                    sum += row.iter().map(|&v| v as u64).sum::<u64>();
                }
                let n = ((yb - ya) * (xb - xa)) as u64;
                self.mask
                    .put_pixel(px, py, image::Luma([((sum + n / 2) / n) as u8]));
            }
        }
        Some(r)
    }

    /// A photo point on the proxy.
    pub fn to_proxy(&self, p: [f32; 2]) -> [f32; 2] {
        [p[0] * self.sx, p[1] * self.sy]
    }

    /// The preview job for a document's state.
    pub fn job(
        &self,
        preset: &Preset,
        quad: Option<&Quad>,
        layers: &BTreeMap<String, LayerSetting>,
    ) -> Result<PreviewJob> {
        let mut preset = preset.clone();
        for line in &mut preset.rain.source_lines {
            for p in line.iter_mut() {
                *p = self.to_proxy(*p);
            }
        }
        // The proxy photo is shared, not copied (it never changes).
        Ok(PreviewJob {
            scene: Scene {
                photo: Arc::clone(&self.photo),
                region: Some(Arc::new(self.mask.clone())),
                normals: None,
                quad: None,
            },
            quad: quad.map(|q| q.map(|p| self.to_proxy(p))),
            preset,
            layers: layers.clone(),
        })
    }
}

/// One preview computation.
#[derive(Debug, Clone)]
pub struct PreviewJob {
    /// Proxy photo and mask.
    pub scene: Scene,
    /// Perspective quad in proxy pixels.
    pub quad: Option<Quad>,
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
    /// Where the time went: the pipeline's stages, then "composite" and
    /// "image" (conversion for the texture), ms.
    pub timings: Vec<Timing>,
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

/// True for the layers the dust makes ("dust film", "dust granules").
fn is_dust_layer(name: &str) -> bool {
    name.starts_with("dust ")
}

/// The dust layers of the last run and what they were made from.
#[derive(Debug)]
struct DustCache {
    size: (u32, u32),
    region: Option<Arc<GrayImage>>,
    quad: Option<Quad>,
    params: DustParams,
    seed: u64,
    layers: Vec<Layer>,
}

impl DustCache {
    fn matches(&self, job: &PreviewJob, preset: &Preset) -> bool {
        let photo = &job.scene.photo;
        self.size == (photo.width(), photo.height())
            && self.quad == job.quad
            && self.params == preset.dust
            && self.seed == preset.seed
            && job.scene.normals.is_none()
            && match (&self.region, &job.scene.region) {
                (None, None) => true,
                (Some(a), Some(b)) => Arc::ptr_eq(a, b) || a.as_raw() == b.as_raw(),
                _ => false,
            }
    }
}

/// Runs preview jobs (the preview worker owns one): a quick pass on a
/// coarse grid, then the full pass. Keeps the last dust layers for the next
/// run.
#[derive(Debug, Default)]
pub struct Previewer {
    dust: Option<DustCache>,
}

impl Previewer {
    /// Both passes: hands the quick one to `emit` as soon as it is ready,
    /// then returns the full one. Stops at the pipeline's next check once
    /// `progress` is cancelled, also between and during the passes.
    ///
    /// # Errors
    /// As [`perspective::pipeline_with_quad`].
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

    /// The quick pass alone; `None` when the job needs none (see
    /// [`quick_preset`]).
    ///
    /// # Errors
    /// As [`perspective::pipeline_with_quad`].
    pub fn quick(&mut self, job: &PreviewJob, progress: &Progress) -> Option<Result<Preview>> {
        let photo = &job.scene.photo;
        let preset = quick_preset(&job.preset, photo.width(), photo.height())?;
        Some(self.pass(job, &preset, true, progress))
    }

    /// The full pass alone: the job's preset as it is.
    ///
    /// # Errors
    /// As [`perspective::pipeline_with_quad`].
    pub fn full(&mut self, job: &PreviewJob, progress: &Progress) -> Result<Preview> {
        self.pass(job, &job.preset, false, progress)
    }

    fn pass(
        &mut self,
        job: &PreviewJob,
        preset: &Preset,
        quick: bool,
        progress: &Progress,
    ) -> Result<Preview> {
        let reuse =
            preset.dust.enabled && self.dust.as_ref().is_some_and(|c| c.matches(job, preset));
        let without_dust;
        let run = if reuse {
            let mut p = preset.clone();
            p.dust.enabled = false;
            without_dust = p;
            &without_dust
        } else {
            preset
        };
        let scene = job.scene.clone().with_quad(job.quad)?;
        let out = crate::pipeline::run(&scene, run, progress)?;
        let mut timings = out.report.timings;
        let mut stack = out.stack;
        let start = Instant::now();
        if let (true, Some(cache)) = (reuse, &self.dust) {
            stack.layers.extend(cache.layers.iter().cloned());
            timings.push(lap("dust (kept)", start));
        } else if preset.dust.enabled && job.scene.normals.is_none() {
            let photo = &job.scene.photo;
            self.dust = Some(DustCache {
                size: (photo.width(), photo.height()),
                region: job.scene.region.clone(),
                quad: job.quad,
                params: preset.dust.clone(),
                seed: preset.seed,
                layers: stack
                    .layers
                    .iter()
                    .filter(|l| is_dust_layer(&l.name))
                    .cloned()
                    .collect(),
            });
        }
        let original = stack
            .layers
            .iter()
            .map(|l| (l.opacity, l.visible))
            .collect();
        let mut preview = Preview {
            stack,
            sim_preset: preset.clone(),
            original,
            image: Arc::default(),
            quick,
            timings,
        };
        progress.update("composite", 1.0);
        let [composite, image] = preview.restyle_timed(&job.preset, &job.layers);
        preview.timings.extend([composite, image]);
        Ok(preview)
    }
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
/// As [`perspective::pipeline_with_quad`].
pub fn simulate(job: PreviewJob, progress: &Progress) -> Result<Preview> {
    Previewer::default().full(&job, progress)
}

impl Preview {
    /// Applies stain colour and opacity, the number of rainfalls shown and
    /// the layer settings, then re-composites. Call only when
    /// [`needs_simulation`] is false.
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

/// True for the layers the rain makes ("rain 01", ...).
pub fn is_rain_layer(name: &str) -> bool {
    name.starts_with("rain ")
}

fn style_stack(stack: &mut Stack, original: &[(f32, bool)], preset: &Preset) {
    let mut rain_index = 0;
    for (layer, &(opacity, visible)) in stack.layers.iter_mut().zip(original) {
        layer.opacity = opacity;
        layer.visible = visible;
        if is_rain_layer(&layer.name) {
            layer.opacity = preset.stain.opacity;
            if let LayerPixels::Tint { color, .. } = &mut layer.pixels {
                *color = preset.stain.color;
            }
            layer.visible = rain_index < preset.rain.layers;
            rain_index += 1;
        }
    }
}

/// Preset fields a finished stack can follow without a new simulation.
pub const RESTYLE_ONLY: &[&str] = &["stain.color", "stain.opacity"];

/// Whether going from the preset a stack was simulated with to `next` needs
/// a new simulation. Stain colour and opacity never do; fewer rainfalls do
/// not either when the stack holds only rain layers (`only_rain`): each
/// rainfall depends only on the ones before it, so the first N of M are the
/// N-rainfall run. (Moss grows from the wall's state after the last one.)
pub fn needs_simulation(sim: &Preset, next: &Preset, only_rain: bool) -> bool {
    let (Ok(a), Ok(b)) = (toml::Value::try_from(sim), toml::Value::try_from(next)) else {
        return true;
    };
    let mut changed = Vec::new();
    diff_paths(&a, &b, String::new(), &mut changed);
    changed.iter().any(|path| match path.as_str() {
        p if RESTYLE_ONLY.contains(&p) => false,
        "rain.layers" => next.rain.layers > sim.rain.layers || !only_rain,
        _ => true,
    })
}

/// Dotted paths of the leaves that differ between two TOML values.
pub fn diff_paths(a: &toml::Value, b: &toml::Value, prefix: String, out: &mut Vec<String>) {
    match (a, b) {
        (toml::Value::Table(ta), toml::Value::Table(tb)) => {
            for (k, va) in ta {
                let path = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                match tb.get(k) {
                    Some(vb) => diff_paths(va, vb, path, out),
                    None => out.push(path),
                }
            }
            for k in tb.keys().filter(|k| !ta.contains_key(*k)) {
                out.push(if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                });
            }
        }
        _ if a != b => out.push(prefix),
        _ => {}
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
    /// Full-size photo and mask.
    pub scene: Scene,
    /// Perspective quad, photo pixels.
    pub quad: Option<Quad>,
    /// The preset with the document's source lines.
    pub preset: Preset,
    /// Layer visibility and opacity.
    pub layers: BTreeMap<String, LayerSetting>,
    /// Output file; its extension picks the format.
    pub path: PathBuf,
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

/// Runs the pipeline at full resolution and saves the result.
///
/// # Errors
/// As [`perspective::pipeline_with_quad`] and [`export::save`].
pub fn export(job: ExportJob, progress: &Progress) -> Result<Exported> {
    let inputs = age::Inputs {
        source: age::Source::Loaded {
            scene: job.scene,
            from: Vec::new(),
        },
        mask: None,
        normal_map: None,
        quad: job.quad,
    };
    let outputs = age::Outputs {
        images: vec![job.path.clone()],
        ..age::Outputs::default()
    };
    let adjust = |stack: &mut Stack| {
        let original: Vec<_> = stack
            .layers
            .iter()
            .map(|l| (l.opacity, l.visible))
            .collect();
        style_stack(stack, &original, &job.preset);
        apply_layer_settings(&job.layers, stack);
    };
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

    /// Rain only: other effects (moss grows from the final wetness) depend on
    /// the number of rainfalls. Effects a build lacks are skipped.
    fn only_rain(stack: &Stack) -> bool {
        stack.layers.iter().all(|l| is_rain_layer(&l.name))
    }

    fn rain_only(p: &mut Preset) {
        for effect in ["moss", "dust"] {
            let _ = p.set(&format!("{effect}.enabled=false"));
        }
    }

    #[test]
    fn proxy_is_about_one_megapixel_and_averages_the_mask() {
        let photo = Arc::new(Photo::new(DynamicImage::ImageRgb8(image::RgbImage::new(
            3000, 2000,
        ))));
        let mut mask = GrayImage::new(3000, 2000);
        for y in 0..2000 {
            for x in 0..1500 {
                mask.put_pixel(x, y, image::Luma([255]));
            }
        }
        let p = Proxy::new(&photo, &mask, PROXY_PIXELS);
        let (w, h) = (p.photo.width(), p.photo.height());
        assert!(
            (w * h) as f64 / 1e6 > 0.95 && (w * h) as f64 / 1e6 < 1.05,
            "{w}x{h}"
        );
        assert_eq!(p.mask.dimensions(), (w, h));
        assert_eq!(p.mask.get_pixel(10, 10)[0], 255);
        assert_eq!(p.mask.get_pixel(w - 10, 10)[0], 0);
        let mid = p.mask.get_pixel(w / 2, 10)[0];
        assert!(mid > 0, "edge is averaged: {mid}");
        assert_eq!(p.to_proxy([3000.0, 2000.0]), [w as f32, h as f32]);
        let small = Proxy::new(
            &Arc::new(Photo::new(DynamicImage::ImageRgb8(image::RgbImage::new(
                100, 80,
            )))),
            &GrayImage::new(100, 80),
            PROXY_PIXELS,
        );
        assert!(small.is_full_size());
    }

    #[test]
    fn what_needs_a_new_simulation() {
        let d = crate::demo::facade(64, 48);
        let scene = Scene::new(d.photo, d.region).unwrap();
        let mut sim = Preset::default();
        sim.rain.layers = 3;
        sim.rain.droplets = 50;
        rain_only(&mut sim);
        let stack = crate::pipeline::run(&scene, &sim, &Progress::none())
            .unwrap()
            .stack;
        let mut next = sim.clone();
        next.stain.opacity = 0.3;
        next.stain.color = [10, 20, 30];
        assert!(!needs_simulation(&sim, &next, only_rain(&stack)));
        next.rain.layers = 2;
        assert!(
            !needs_simulation(&sim, &next, only_rain(&stack)),
            "fewer rainfalls: hide the last ones"
        );
        assert!(
            needs_simulation(&sim, &next, false),
            "unless other layers depend on them"
        );
        next.rain.layers = 4;
        assert!(needs_simulation(&sim, &next, only_rain(&stack)));
        let mut k = sim.clone();
        k.rain.k_a = 0.9;
        assert!(needs_simulation(&sim, &k, only_rain(&stack)));
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
        for (a, b) in short.layers.iter().zip(&long.layers) {
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
            quad: None,
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

    #[test]
    fn kept_dust_matches_a_fresh_run() {
        let mut previewer = Previewer::default();
        let a = facade_job(240, 180, |p| p.rain.k_a = 0.5);
        let first = previewer.full(&a, &Progress::none()).unwrap();
        assert!(first.layer_names().iter().any(|n| is_dust_layer(n)));
        // A rain change: the dust is kept, the picture is the fresh run's.
        let mut b = facade_job(240, 180, |p| p.rain.k_a = 0.6);
        let kept = previewer.full(&b, &Progress::none()).unwrap();
        assert!(kept.timings.iter().any(|t| t.stage == "dust (kept)"));
        let fresh = simulate(b.clone(), &Progress::none()).unwrap();
        assert_eq!(kept.layer_names(), fresh.layer_names());
        assert_eq!(kept.image, fresh.image);
        // A dust change or another region: the dust is made again.
        b.preset.dust.days += 30;
        let redone = previewer.full(&b, &Progress::none()).unwrap();
        assert!(!redone.timings.iter().any(|t| t.stage == "dust (kept)"));
        assert_eq!(
            redone.image,
            simulate(b.clone(), &Progress::none()).unwrap().image
        );
        let mut region = (*b.scene.region.clone().unwrap()).clone();
        for px in region.pixels_mut().take(20_000) {
            px[0] = 0;
        }
        b.scene.region = Some(Arc::new(region));
        let other = previewer.full(&b, &Progress::none()).unwrap();
        assert!(!other.timings.iter().any(|t| t.stage == "dust (kept)"));
        assert_eq!(other.image, simulate(b, &Progress::none()).unwrap().image);
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
            rain_only(&mut p);
            PreviewJob {
                scene: Scene::new(d.photo.clone(), d.region.clone()).unwrap(),
                quad: None,
                preset: p,
                layers: BTreeMap::new(),
            }
        };
        let mut a = simulate(job(4, 0.8), &Progress::none()).unwrap();
        let fresh = simulate(job(2, 0.5), &Progress::none()).unwrap();
        let target = job(2, 0.5).preset;
        assert!(!needs_simulation(
            &a.sim_preset,
            &target,
            only_rain(&a.stack)
        ));
        a.restyle(&target, &BTreeMap::new());
        assert_eq!(a.image, fresh.image);
    }
}
