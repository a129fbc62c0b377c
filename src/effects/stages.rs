//! The rain, moss and dust as pipeline stages: each turns its simulation's
//! result into layers and stats (see [`super::Effect::run`]).

use std::sync::Arc;

use serde::Serialize;

use super::moss::{self, MossInput, Wet};
use super::rain::{self, RainInput};
use super::{Context, Effect, Produced, Products, Stats, dust};
use crate::error::Result;
use crate::preset::Preset;
use crate::progress::Progress;
use crate::stack::{BlendMode, Layer, LayerPixels};

/// The rain's numbers for the whole run (per rainfall: the layers' own).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RainStats {
    /// Droplets per rainfall.
    pub droplets_per_layer: u32,
    /// D_max the stains are measured against.
    pub d_max: f32,
}

/// A layer of `effect` at full opacity setting `opacity`, visible.
fn layer(
    effect: Effect,
    name: String,
    opacity: f32,
    blend: BlendMode,
    pixels: LayerPixels,
) -> Layer {
    Layer {
        name,
        kind: Some(effect),
        blend,
        opacity,
        visible: true,
        pixels,
    }
}

/// The rainfalls (Chang eqs. 2-17) and one stain layer per rainfall.
pub(super) fn rain(
    ctx: &Context,
    products: &mut Products,
    preset: &Preset,
    progress: &Progress,
) -> Result<Produced> {
    let grid = ctx.grid;
    let (w, h) = ctx.size();
    let source_lines = preset
        .rain
        .source_lines
        .iter()
        .map(|line| line.iter().map(|p| grid.to_grid(p[0], p[1])).collect())
        .collect();
    let input = RainInput {
        luma: ctx.luma,
        region: ctx.region,
        source_lines,
    };
    let (out, kept) = rain::simulate_keeping(
        &input,
        &preset.rain,
        preset.seed,
        &progress.span(0.0, 0.87),
        &products.keep_rain_at,
    )?;
    products.rain_kept = kept.into_iter().map(Arc::new).collect();

    let d_max = rain::stain::d_max(&out.layers, preset.stain.percentile);
    let mut layers = Vec::with_capacity(out.layers.len());
    let mut layer_stats = Vec::with_capacity(out.layers.len());
    let mut coverage = rain::stain::Coverage::new(grid.width, grid.height);
    for (i, rl) in out.layers.iter().enumerate() {
        progress.check()?;
        progress.update("stain", 0.87 + 0.13 * i as f32 / out.layers.len() as f32);
        let alpha = grid.upsample(
            coverage.of(&rl.deposit, d_max, &preset.stain),
            ctx.mask,
            w,
            h,
        );
        let pixels = LayerPixels::Tint {
            color: preset.stain.color,
            alpha,
        };
        let name = format!("rain {:02}", i + 1);
        layers.push(layer(
            Effect::Rain,
            name,
            preset.stain.opacity,
            BlendMode::Multiply,
            pixels,
        ));
        layer_stats.push(Some(rl.stats.clone()));
    }
    products.rain = Some(Arc::new(out));
    Ok(Produced {
        layers,
        layer_stats,
        stats: Stats::Rain(RainStats {
            droplets_per_layer: rain::droplet_count(&preset.rain, grid.width),
            d_max,
        }),
    })
}

/// A rain layer follows the preset's stain colour and opacity, and shows
/// only the first `rain.layers` rainfalls.
pub(super) fn restyle_rain(layer: &mut Layer, index: usize, preset: &Preset) {
    layer.opacity = preset.stain.opacity;
    if let LayerPixels::Tint { color, .. } = &mut layer.pixels {
        *color = preset.stain.color;
    }
    layer.visible = index < preset.rain.layers as usize;
}

/// The "moss" layer (Chang eq. 18), grown from the rain's final water and
/// dirt, or (with no rainfall) from the preset's humidity.
pub(super) fn moss(
    ctx: &Context,
    products: &mut Products,
    preset: &Preset,
    progress: &Progress,
) -> Result<Produced> {
    let rain = products.rain.as_deref();
    let wet = rain.filter(|r| !r.layers.is_empty()).map(|r| Wet {
        water: &r.water,
        saturation: preset.rain.saturation,
        dirt: &r.dirt,
        d_max: moss::d_max(&r.dirt, ctx.region, preset.stain.percentile),
    });
    let input = MossInput {
        luma: ctx.luma,
        region: ctx.region,
        wet,
    };
    let grown = moss::grow(
        &input,
        ctx.grid,
        ctx.wall,
        &preset.moss,
        preset.seed,
        progress,
    )?;
    let pixels = LayerPixels::Rgba(grown.layer);
    let layer = layer(
        Effect::Moss,
        "moss".into(),
        preset.moss.opacity,
        BlendMode::Normal,
        pixels,
    );
    Ok(Produced {
        layers: vec![layer],
        layer_stats: vec![None],
        stats: Stats::Moss(grown.stats),
    })
}

/// The "dust film" and "dust granules" layers (Santos & Baranoski).
pub(super) fn dust(ctx: &Context, preset: &Preset, progress: &Progress) -> Result<Produced> {
    let p = &preset.dust;
    let (film, granules, stats) =
        dust::accumulate(ctx.wall, ctx.normals, p, preset.seed, progress)?;
    let film = LayerPixels::Rgba(film);
    let granules = LayerPixels::Tint {
        color: p.granule_color,
        alpha: granules,
    };
    let normal = BlendMode::Normal;
    Ok(Produced {
        layers: vec![
            layer(
                Effect::Dust,
                "dust film".into(),
                p.film_opacity,
                normal,
                film,
            ),
            layer(
                Effect::Dust,
                "dust granules".into(),
                p.granule_opacity,
                normal,
                granules,
            ),
        ],
        layer_stats: vec![None, None],
        stats: Stats::Dust(stats),
    })
}
