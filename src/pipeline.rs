//! The one pipeline every front end calls: scene + preset in, layer stack
//! and report out.

use std::sync::Arc;
use std::time::Instant;

use image::GrayImage;
use serde::Serialize;

use crate::effects::rain::{self, LayerStats, RainInput, RainOutput};
use crate::error::{Error, Result};
use crate::grid::Grid;
use crate::photo::Photo;
use crate::preset::Preset;
use crate::progress::Progress;
use crate::stack::{BlendMode, Layer, LayerPixels, Stack};

/// What is being aged: the photo and the wall region.
#[derive(Debug, Clone)]
pub struct Scene {
    /// The photo.
    pub photo: Arc<Photo>,
    /// Wall region, photo-sized, 255 = wall; `None` = the whole photo.
    pub region: Option<Arc<GrayImage>>,
}

impl Scene {
    /// A scene; the region must have the photo's size.
    ///
    /// # Errors
    /// [`Error::MaskSize`] for a mask of another size.
    pub fn new(photo: Photo, region: Option<GrayImage>) -> Result<Scene> {
        if let Some(m) = &region
            && m.dimensions() != (photo.width(), photo.height())
        {
            return Err(Error::MaskSize {
                mask_w: m.width(),
                mask_h: m.height(),
                img_w: photo.width(),
                img_h: photo.height(),
            });
        }
        Ok(Scene {
            photo: Arc::new(photo),
            region: region.map(Arc::new),
        })
    }
}

/// The pipeline's result.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// Photo plus effect layers.
    pub stack: Stack,
    /// What happened, in numbers.
    pub report: Report,
    /// The rain's grid-level result (wall water and dirt), for effects and
    /// tools that build on it.
    pub rain: RainOutput,
    /// The simulation grid.
    pub grid: Grid,
}

/// Size of an image.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Size {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
}

/// One layer as reported.
#[derive(Debug, Clone, Serialize)]
pub struct LayerReport {
    /// Layer name.
    pub name: String,
    /// Blend mode.
    pub blend: BlendMode,
    /// Opacity.
    pub opacity: f32,
    /// Mean coverage over the photo, 0..1.
    pub coverage: f64,
    /// Rain numbers, for rain layers.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rain: Option<LayerStats>,
}

/// Time spent in one stage.
#[derive(Debug, Clone, Serialize)]
pub struct Timing {
    /// Stage name.
    pub stage: String,
    /// Milliseconds.
    pub ms: f64,
}

/// What a run did, in numbers (`--report`).
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    /// Photo size.
    pub image: Size,
    /// Simulation grid size and photo pixels per grid pixel.
    pub grid: GridReport,
    /// Master seed.
    pub seed: u64,
    /// Droplets per rainfall.
    pub droplets_per_layer: u32,
    /// D_max the stains are measured against.
    pub d_max: f32,
    /// Every layer, bottom to top.
    pub layers: Vec<LayerReport>,
    /// Time per stage.
    pub timings: Vec<Timing>,
}

/// The grid as reported.
#[derive(Debug, Clone, Serialize)]
pub struct GridReport {
    /// Grid width.
    pub width: usize,
    /// Grid height.
    pub height: usize,
    /// Photo pixels per grid pixel.
    pub scale: f32,
}

struct Clock {
    last: Instant,
    timings: Vec<Timing>,
}

impl Clock {
    fn lap(&mut self, stage: &str) {
        let now = Instant::now();
        self.timings.push(Timing {
            stage: stage.to_string(),
            ms: (now - self.last).as_secs_f64() * 1000.0,
        });
        self.last = now;
    }
}

/// Runs every enabled effect on the scene.
///
/// # Errors
/// [`Error::EmptyRegion`] for an empty mask, [`Error::Cancelled`] when the
/// progress's cancel flag is set, or an invalid preset's error.
pub fn run(scene: &Scene, preset: &Preset, progress: &Progress) -> Result<Outcome> {
    preset.validate()?;
    let mut clock = Clock {
        last: Instant::now(),
        timings: Vec::new(),
    };
    let photo = &scene.photo;
    let (w, h) = (photo.width(), photo.height());
    let mask = scene.region.as_deref();
    let grid = Grid::new(w, h, mask, preset.sim.max_side)?;
    let luma = grid.luma(photo);
    let region = grid.region(mask);
    clock.lap("grid");
    progress.update("prepare", 0.05);

    let source_lines = preset
        .rain
        .source_lines
        .iter()
        .map(|line| line.iter().map(|p| grid.to_grid(p[0], p[1])).collect())
        .collect();
    let input = RainInput {
        width: grid.width,
        height: grid.height,
        luma: &luma,
        region: &region,
        source_lines,
    };
    let rain = rain::simulate(&input, &preset.rain, preset.seed, &progress.span(0.05, 0.8))?;
    clock.lap("rain");

    let d_max = rain::stain::d_max(&rain.layers, preset.stain.percentile);
    let mut layers = Vec::with_capacity(rain.layers.len());
    let mut reports = Vec::with_capacity(rain.layers.len());
    for (i, rl) in rain.layers.iter().enumerate() {
        progress.check()?;
        progress.update("stain", 0.8 + 0.2 * i as f32 / rain.layers.len().max(1) as f32);
        let cov = rain::stain::coverage(&rl.deposit, grid.width, grid.height, d_max, &preset.stain);
        let alpha = grid.upsample(&cov, mask, w, h);
        let layer = Layer {
            name: format!("rain {:02}", i + 1),
            blend: BlendMode::Multiply,
            opacity: preset.stain.opacity,
            visible: true,
            pixels: LayerPixels::Tint {
                color: preset.stain.color,
                alpha,
            },
        };
        reports.push(LayerReport {
            name: layer.name.clone(),
            blend: layer.blend,
            opacity: layer.opacity,
            coverage: layer.coverage(),
            rain: Some(rl.stats.clone()),
        });
        layers.push(layer);
    }
    clock.lap("stain");
    progress.update("done", 1.0);

    let report = Report {
        image: Size { width: w, height: h },
        grid: GridReport {
            width: grid.width,
            height: grid.height,
            scale: grid.scale,
        },
        seed: preset.seed,
        droplets_per_layer: rain::droplet_count(&preset.rain, grid.width),
        d_max,
        layers: reports,
        timings: clock.timings,
    };
    Ok(Outcome {
        stack: Stack {
            base: Arc::clone(&scene.photo),
            layers,
            region: scene.region.clone(),
        },
        report,
        rain,
        grid,
    })
}
