//! Riihiaho's effect generators (2020, sec. 3.3), driven by the sun and
//! humidity of [`super::climate`]: each takes time t, durability d
//! (`t_d = t / d`, eq. 3.9) and the environment `e = e_e - e_d` (eq. 3.10),
//! here `base + by_humidity h + by_light l_d` per cell.
//!
//! - Spotty (eq. 3.12): fBm islands whose sea level `c_0 = e t_d` drops
//!   with time, so spots grow in place.
//! - Roughy (eq. 3.13): `[S(e t_d)]` clamped to `[l_min, l_max]`, a change of
//!   roughness; a photo shows it as lower local contrast (a matte surface).
//! - Fade Towardy (eqs. 3.14-3.15): `c = c_1 (1 - g) + c_2 g`, `g = S(e t_d)`.
//! - Desaturaty: saturation scaled by `[1 - S(e t_d)]` clamped to `[l_min, 1]`.
//!
//! Each is one layer whose normal blend over the photo is the generator's
//! formula.

use image::RgbaImage;
use rayon::prelude::*;
use serde::Serialize;

use super::climate::{self, Climate, sigmoid};
use super::{Context, Effect, Produced, Products, Stats};
use crate::error::Result;
use crate::field::RowMajor;
use crate::preset::{GeneratorParams, Preset};
use crate::progress::Progress;
use crate::random::{Noise, key};
use crate::stack::{BlendMode, Layer, LayerPixels};

/// The numbers for the report.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WeatheringStats {
    /// Mean direct light over the wall.
    pub light: f32,
    /// Mean humidity over the wall.
    pub humidity: f32,
    /// Per generator that ran: its name and mean strength over the wall.
    pub generators: Vec<(String, f32)>,
}

/// The environment e per cell (eq. 3.10).
pub fn environment(c: &Climate, p: &GeneratorParams) -> RowMajor<f32> {
    let (w, h) = (c.light.width(), c.light.height());
    RowMajor::from_fn(w, h, |x, y| {
        p.base + p.by_humidity * c.humidity.get(x, y) + p.by_light * c.light.get(x, y)
    })
}

/// Spotty (eq. 3.12) from fBm `m` in 0..1: a cell is spot where
/// `m + c_0 > 1`, `c_0 = e t_d`; the alpha rises over a shore of 0.06.
pub fn spotty(m: &RowMajor<f32>, e: &RowMajor<f32>, t_d: f32) -> RowMajor<f32> {
    RowMajor::from_fn(m.width(), m.height(), |x, y| {
        ((m.get(x, y) + e.get(x, y) * t_d - 1.0) / 0.06).clamp(0.0, 1.0)
    })
}

/// `S(e t_d)` per cell, clamped to `[lo, hi]` (Roughy eq. 3.13, Fade
/// Towardy eq. 3.14 with the full range).
pub fn strength(e: &RowMajor<f32>, p: &GeneratorParams, lo: f32, hi: f32) -> RowMajor<f32> {
    let t_d = p.years / p.durability.max(1e-3);
    RowMajor::from_fn(e.width(), e.height(), |x, y| {
        sigmoid(e.get(x, y) * t_d, p.offset, p.steepness).clamp(lo, hi.max(lo))
    })
}

/// The generators as a pipeline stage: a layer each.
pub(super) fn stage(
    ctx: &Context,
    products: &mut Products,
    preset: &Preset,
    progress: &Progress,
) -> Result<Produced> {
    progress.update("sun and humidity", 0.0);
    let climate = products.climate(ctx, &preset.climate);
    let (w, h) = ctx.size();
    let mean = |m: &RowMajor<f32>| {
        let (s, n) = m
            .data()
            .iter()
            .zip(ctx.region.data())
            .filter(|(_, r)| **r)
            .fold((0.0f64, 0usize), |(s, n), (v, _)| (s + *v as f64, n + 1));
        (s / n.max(1) as f64) as f32
    };
    let photo = ctx.photo.image().to_rgb8();
    let mut layers = Vec::new();
    let mut generators = Vec::new();
    let mut add = |name: &str, opacity: f32, g: &RowMajor<f32>, pixels: LayerPixels| {
        generators.push((name.to_string(), mean(g)));
        layers.push(Layer {
            name: name.into(),
            kind: Some(Effect::Weathering),
            blend: BlendMode::Normal,
            opacity,
            visible: true,
            pixels,
        });
    };
    let up = |g: &RowMajor<f32>| ctx.grid.upsample(g, ctx.mask, w, h);
    let p = &preset.desaturate;
    if p.enabled {
        progress.check()?;
        progress.update("desaturaty", 0.2);
        // Saturation scaled by f = [1 - S]: a grey layer of alpha 1 - f.
        let s = strength(&environment(&climate, p), p, 0.0, 1.0 - p.l_min);
        let alpha = up(&s);
        let img = RgbaImage::from_fn(w, h, |x, y| {
            let [r, g, b] = photo.get_pixel(x, y).0;
            let grey = (0.299 * r as f32 + 0.587 * g as f32 + 0.114 * b as f32).round() as u8;
            image::Rgba([grey, grey, grey, alpha.get_pixel(x, y)[0]])
        });
        add("desaturaty", p.opacity, &s, LayerPixels::Rgba(img));
    }
    let p = &preset.fade;
    if p.enabled {
        progress.check()?;
        progress.update("fade towardy", 0.4);
        let g = strength(&environment(&climate, p), p, 0.0, 1.0);
        let pixels = LayerPixels::Tint {
            color: p.color,
            alpha: up(&g),
        };
        add("fade towardy", p.opacity, &g, pixels);
    }
    let p = &preset.roughy;
    if p.enabled {
        progress.check()?;
        progress.update("roughy", 0.6);
        let g = strength(&environment(&climate, p), p, p.l_min, p.l_max);
        let alpha = up(&g);
        let radius = ctx.photo_px(p.size).round().max(1.0) as usize;
        let smooth = smoothed(&photo, radius);
        let img = RgbaImage::from_fn(w, h, |x, y| {
            let c = smooth.get_pixel(x, y).0;
            image::Rgba([c[0], c[1], c[2], alpha.get_pixel(x, y)[0]])
        });
        add("roughy", p.opacity, &g, LayerPixels::Rgba(img));
    }
    let p = &preset.spotty;
    if p.enabled {
        progress.check()?;
        progress.update("spotty", 0.8);
        let m = musgrave(ctx, p, preset.seed);
        let g = spotty(
            &m,
            &environment(&climate, p),
            p.years / p.durability.max(1e-3),
        );
        let pixels = LayerPixels::Rgba(crust(
            &photo,
            &up(&g),
            p,
            (preset.seed, ctx.photo_px(p.size / 15.0).max(1.5)),
        ));
        add("spotty", p.opacity, &g, pixels);
    }
    Ok(Produced {
        layer_stats: vec![None; layers.len()],
        layers,
        stats: Stats::Weathering(WeatheringStats {
            light: mean(&climate.light),
            humidity: mean(&climate.humidity),
            generators,
        }),
    })
}

/// Spotty's spots as a crust: the colour shaded by the wall's own light
/// (so its texture shows through) and an alpha broken by a fine noise
/// `grain` pixels across (a spot is a crust of small bodies, not a coat of
/// paint).
fn crust(
    photo: &image::RgbImage,
    alpha: &image::GrayImage,
    p: &GeneratorParams,
    (seed, grain): (u64, f32),
) -> RgbaImage {
    let (w, h) = photo.dimensions();
    let luma = |c: [u8; 3]| 0.299 * c[0] as f32 + 0.587 * c[1] as f32 + 0.114 * c[2] as f32;
    let mean = photo.pixels().map(|c| luma(c.0)).sum::<f32>() / (w * h).max(1) as f32;
    let fine = Noise::new(key(seed, (Effect::Weathering, 1), 0, 0), w, h, grain, 2);
    RgbaImage::from_fn(w, h, |x, y| {
        let a = alpha.get_pixel(x, y)[0];
        if a == 0 {
            return image::Rgba([0; 4]);
        }
        let shade = (luma(photo.get_pixel(x, y).0) / mean.max(1.0))
            .clamp(0.4, 1.4)
            .powf(0.7);
        let c = p
            .color
            .map(|v| (v as f32 * shade).round().clamp(0.0, 255.0) as u8);
        let n = fine.at(x as f32, y as f32);
        let a = (a as f32 * (0.45 + 0.55 * n)).round().max(1.0) as u8;
        image::Rgba([c[0], c[1], c[2], a])
    })
}

/// Spotty's fBm on the grid (5 octaves, coarsest `size` metres), spread
/// to 0..1 over the wall.
pub fn musgrave(ctx: &Context, p: &GeneratorParams, seed: u64) -> RowMajor<f32> {
    let (gw, gh) = (ctx.grid.width, ctx.grid.height);
    let noise = Noise::new(
        key(seed, (Effect::Weathering, 0), 0, 0),
        gw as u32,
        gh as u32,
        ctx.grid_px(p.size).max(2.0),
        5,
    );
    let m = RowMajor::from_fn(gw, gh, |x, y| noise.at(x as f32, y as f32));
    let (lo, hi) = m
        .data()
        .iter()
        .fold((f32::MAX, f32::MIN), |(a, b), &v| (a.min(v), b.max(v)));
    RowMajor::from_fn(gw, gh, |x, y| (m.get(x, y) - lo) / (hi - lo).max(1e-6))
}

/// The photo box-blurred with radius `r` (the local mean Roughy fades to).
pub(crate) fn smoothed(photo: &image::RgbImage, r: usize) -> image::RgbImage {
    let (w, h) = (photo.width() as usize, photo.height() as usize);
    let channels: Vec<RowMajor<f32>> = (0..3)
        .into_par_iter()
        .map(|c| {
            let v = RowMajor::from_fn(w, h, |x, y| photo.get_pixel(x as u32, y as u32)[c] as f32);
            climate::blur(&v, r)
        })
        .collect();
    image::RgbImage::from_fn(w as u32, h as u32, |x, y| {
        image::Rgb(std::array::from_fn(|c| {
            channels[c].get(x as usize, y as usize).round() as u8
        }))
    })
}

/// Whether any generator is on.
pub fn enabled(preset: &Preset) -> bool {
    preset.spotty.enabled
        || preset.roughy.enabled
        || preset.fade.enabled
        || preset.desaturate.enabled
}

#[cfg(test)]
mod tests;
