//! The one pipeline every front end calls: scene + preset in, layer stack
//! and report out.

use std::sync::Arc;
use std::time::Instant;

use image::{GrayImage, RgbImage};
use serde::Serialize;

use crate::effects::dust::{self, DustStats};
use crate::effects::moss::{self, MossInput, MossStats, Wet};
use crate::effects::rain::{self, LayerStats, RainInput, RainOutput};
use crate::effects::region::Region;
use crate::error::{Error, Result};
use crate::field::RowMajor;
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
    /// Tangent-space normal map of the wall, photo-sized, for the dust's
    /// per-pixel view and light angles (see [`crate::effects::dust::shade`]).
    pub normals: Option<Arc<RgbImage>>,
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
            normals: None,
        })
    }

    /// The scene with a normal map for the dust.
    ///
    /// # Errors
    /// [`Error::NormalMapSize`] for a map of another size than the photo.
    pub fn with_normals(mut self, normals: RgbImage) -> Result<Scene> {
        let (w, h) = (self.photo.width(), self.photo.height());
        if normals.dimensions() != (w, h) {
            return Err(Error::NormalMapSize {
                map_w: normals.width(),
                map_h: normals.height(),
                img_w: w,
                img_h: h,
            });
        }
        self.normals = Some(Arc::new(normals));
        Ok(self)
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
    /// Moss numbers (colonies, dots, coverage), when moss is enabled.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub moss: Option<MossStats>,
    /// Dust numbers (particles per component, coverage), when dust is enabled.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dust: Option<DustStats>,
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
        luma: &luma,
        region: &region,
        source_lines,
    };
    let rain = rain::simulate(&input, &preset.rain, preset.seed, &progress.span(0.05, 0.7))?;
    clock.lap("rain");

    let d_max = rain::stain::d_max(&rain.layers, preset.stain.percentile);
    let mut layers = Vec::with_capacity(rain.layers.len());
    let mut reports = Vec::with_capacity(rain.layers.len());
    let mut coverage = rain::stain::Coverage::new(grid.width, grid.height);
    for (i, rl) in rain.layers.iter().enumerate() {
        progress.check()?;
        progress.update(
            "stain",
            0.7 + 0.1 * i as f32 / rain.layers.len().max(1) as f32,
        );
        let alpha = grid.upsample(coverage.of(&rl.deposit, d_max, &preset.stain), mask, w, h);
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
        reports.push(LayerReport::of(&layer, Some(rl.stats.clone())));
        layers.push(layer);
    }
    clock.lap("stain");

    let wall = Region::new(w, h, mask)?;
    let moss = match preset.moss.enabled {
        false => None,
        true => {
            let input = moss_input(&luma, &region, &rain, preset);
            let (layer, stats) =
                moss_layer(&input, &grid, &wall, preset, &progress.span(0.8, 0.9))?;
            reports.push(LayerReport::of(&layer, None));
            layers.push(layer);
            clock.lap("moss");
            Some(stats)
        }
    };
    let dust = match preset.dust.enabled {
        false => None,
        true => {
            let (new, stats) = dust_layers(
                &wall,
                scene.normals.as_deref(),
                preset,
                &progress.span(0.9, 1.0),
            )?;
            for layer in new {
                reports.push(LayerReport::of(&layer, None));
                layers.push(layer);
            }
            clock.lap("dust");
            Some(stats)
        }
    };
    progress.update("done", 1.0);

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
        droplets_per_layer: rain::droplet_count(&preset.rain, grid.width),
        d_max,
        layers: reports,
        moss,
        dust,
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

impl LayerReport {
    fn of(layer: &Layer, rain: Option<LayerStats>) -> LayerReport {
        LayerReport {
            name: layer.name.clone(),
            blend: layer.blend,
            opacity: layer.opacity,
            coverage: layer.coverage(),
            rain,
        }
    }
}

/// What moss grows from: the rain's final water and dirt, or (with no
/// rainfall) the preset's humidity.
fn moss_input<'a>(
    luma: &'a RowMajor<f32>,
    region: &'a RowMajor<bool>,
    rain: &'a RainOutput,
    preset: &Preset,
) -> MossInput<'a> {
    let wet = (!rain.layers.is_empty()).then(|| Wet {
        water: &rain.water,
        saturation: preset.rain.saturation,
        dirt: &rain.dirt,
        d_max: moss::d_max(&rain.dirt, region, preset.stain.percentile),
    });
    MossInput { luma, region, wet }
}

/// The "moss" layer.
fn moss_layer(
    input: &MossInput,
    grid: &Grid,
    wall: &Region,
    preset: &Preset,
    progress: &Progress,
) -> Result<(Layer, MossStats)> {
    let grown = moss::grow(input, grid, wall, &preset.moss, preset.seed, progress)?;
    let layer = Layer {
        name: "moss".into(),
        blend: BlendMode::Normal,
        opacity: preset.moss.opacity,
        visible: true,
        pixels: LayerPixels::Rgba(grown.layer),
    };
    Ok((layer, grown.stats))
}

/// The "dust film" and "dust granules" layers.
fn dust_layers(
    wall: &Region,
    normals: Option<&RgbImage>,
    preset: &Preset,
    progress: &Progress,
) -> Result<([Layer; 2], DustStats)> {
    let p = &preset.dust;
    let (film, granules, stats) = dust::accumulate(wall, normals, p, preset.seed, progress)?;
    let layer = |name: &str, opacity: f32, pixels: LayerPixels| Layer {
        name: name.into(),
        blend: BlendMode::Normal,
        opacity,
        visible: true,
        pixels,
    };
    let film = layer("dust film", p.film_opacity, LayerPixels::Rgba(film));
    let granules = layer(
        "dust granules",
        p.granule_opacity,
        LayerPixels::Tint {
            color: p.granule_color,
            alpha: granules,
        },
    );
    Ok(([film, granules], stats))
}
