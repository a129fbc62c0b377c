//! Imperfections after Becket & Badler (1990): scratches, splotches,
//! stains, mould, rust, smudges and corrosion, each a weight map that blends the wall toward
//! an imperfect look, placed by a rule in image space ([`placement`]) and
//! calibrated so that it covers `coverage` of the placement area: the
//! adverb table of the command language ([`crate::say`]) holds by
//! construction.
//!
//! Each generator makes a field over the photo; the field times the
//! placement weight is thresholded at the quantile that leaves exactly
//! `coverage` x area pixels above it ([`threshold`]), and only those get
//! a non-zero alpha. Scratches are lines, so they are drawn one by one
//! until they cover enough instead.

pub mod blots;
pub mod fractal;
pub mod mould;
pub mod placement;
pub mod rust;
pub mod scratches;
pub mod smudges;

use image::GrayImage;
use serde::Serialize;

use self::placement::Placed;
use super::percentile::{Rank, percentile};
use super::{Context, Effect, Produced, Products, Stats};
use crate::error::Result;
use crate::preset::{Imperfection, Preset};
use crate::progress::Progress;
use crate::stack::{BlendMode, Layer, LayerPixels};

/// Random stream numbers of the generators, under [`Effect::Imperfections`].
#[derive(Debug, Clone, Copy)]
#[repr(u16)]
pub enum Gen {
    /// Scratches.
    Scratches = 0,
    /// Splotches.
    Splotches = 1,
    /// Stains.
    Stains = 2,
    /// Mould.
    Mould = 3,
    /// Rust.
    Rust = 4,
    /// Smudges.
    Smudges = 5,
    /// Corrosion.
    Corrosion = 6,
}

impl Gen {
    /// Its random stream: `(Effect::Imperfections, 16 * which + sub)`.
    pub fn stream(self, sub: u16) -> (Effect, u16) {
        (Effect::Imperfections, self as u16 * 16 + sub)
    }
}

/// How much of its placement area one generator covers.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Coverage {
    /// The layer.
    pub name: String,
    /// The placement rule used.
    pub placement: String,
    /// Pixels in the placement area.
    pub area: u64,
    /// The coverage asked for.
    pub target: f32,
    /// Pixels with non-zero alpha over the area's pixels.
    pub coverage: f32,
}

/// The imperfections' numbers for the report.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ImperfectionStats {
    /// One entry per generator that ran.
    pub generators: Vec<Coverage>,
}

/// The value of `g` (one per pixel) above which exactly
/// `round(coverage x area)` of the pixels with placement weight above 0
/// lie (fewer on ties). `+inf` for none; just below the least for all.
pub fn threshold(g: &[f32], placed: &Placed, coverage: f32) -> f32 {
    let candidates: Vec<f32> = g
        .iter()
        .zip(&placed.weight)
        .filter(|(_, w)| **w > 0.0)
        .map(|(v, _)| *v)
        .collect();
    let n = (coverage.clamp(0.0, 1.0) as f64 * placed.area as f64).round() as usize;
    let total = candidates.len();
    if n == 0 || total == 0 {
        return f32::INFINITY;
    }
    if n >= total {
        let (lo, hi) = candidates
            .iter()
            .fold((f32::MAX, f32::MIN), |(a, b), &v| (a.min(v), b.max(v)));
        return lo - (hi - lo) * 1e-3 - 1e-6;
    }
    let q = (total - n - 1) as f32 / (total - 1).max(1) as f32;
    percentile(candidates, q, Rank::Nearest).unwrap_or(f32::INFINITY)
}

/// Fraction of the placement area's size that `alpha` covers.
pub fn measured(alpha: &GrayImage, placed: &Placed) -> f32 {
    let covered = alpha.as_raw().iter().filter(|&&a| a > 0).count();
    covered as f32 / placed.area.max(1) as f32
}

/// An alpha byte that is never 0 for a covered pixel.
pub fn alpha_byte(a: f32) -> u8 {
    (a * 255.0).round().clamp(1.0, 255.0) as u8
}

/// What one generator made: layers and its coverage.
pub struct Made {
    /// Layers, bottom to top.
    pub layers: Vec<Layer>,
    /// The first layer's coverage of its placement area.
    pub coverage: Coverage,
}

fn coverage(name: &str, placed: &Placed, target: f32, alpha: &GrayImage) -> Coverage {
    Coverage {
        name: name.into(),
        placement: placed.used.clone(),
        area: placed.area,
        target,
        coverage: measured(alpha, placed),
    }
}

/// A layer of this effect.
pub fn layer(name: &str, blend: BlendMode, opacity: f32, pixels: LayerPixels) -> Layer {
    Layer {
        name: name.into(),
        kind: Some(Effect::Imperfections),
        blend,
        opacity,
        visible: true,
        pixels,
    }
}

/// The imperfections as a pipeline stage: a layer per enabled generator
/// (rust also its run-down).
pub(super) fn stage(
    ctx: &Context,
    _: &mut Products,
    preset: &Preset,
    progress: &Progress,
) -> Result<Produced> {
    let seed = preset.seed;
    let mut layers = Vec::new();
    let mut generators = Vec::new();
    let steps = 7.0;
    // [choice] A generator's own colour is the material's in the wall's
    // light: normal-blended colour layers take the photo's luminance over
    // the wall's mean, as moss does, so rust and splotches are shaded and
    // textured with the wall rather than flat cut-outs (blind review 7).
    let l_wall = super::surface::wall_luma(ctx.luma, ctx.region);
    let mut push = |mut made: Made| {
        for l in &mut made.layers {
            if let (BlendMode::Normal, LayerPixels::Rgba(img)) = (l.blend, &mut l.pixels) {
                super::surface::modulate(img, ctx.photo, l_wall);
            }
        }
        layers.extend(made.layers);
        generators.push(made.coverage);
    };
    if preset.scratches.enabled {
        progress.update("scratches", 0.0);
        let p = &preset.scratches;
        let placed = placement::place(ctx, p.place());
        let drawn = scratches::draw(ctx, p, &placed, seed);
        let cov = coverage("scratches", &placed, p.coverage, &drawn.alpha);
        let pixels = LayerPixels::Tint {
            color: p.color,
            alpha: drawn.alpha,
        };
        push(Made {
            layers: vec![layer("scratches", BlendMode::Normal, p.opacity, pixels)],
            coverage: cov,
        });
    }
    progress.check()?;
    for (i, (name, p, which)) in [
        ("splotches", &preset.splotches, Gen::Splotches),
        ("stains", &preset.stains, Gen::Stains),
    ]
    .into_iter()
    .enumerate()
    {
        if p.enabled {
            progress.update(name, (1 + i) as f32 / steps);
            let placed = placement::place(ctx, p.place());
            let (pixels, blend, alpha) = blots::draw(ctx, p, &placed, seed, which);
            let cov = coverage(name, &placed, p.coverage, &alpha);
            push(Made {
                layers: vec![layer(name, blend, p.opacity, pixels)],
                coverage: cov,
            });
        }
        progress.check()?;
    }
    if preset.mould.enabled {
        progress.update("mould", 3.0 / steps);
        let p = &preset.mould;
        let placed = placement::place(ctx, p.place());
        let alpha = mould::draw(ctx, p, &placed, seed);
        let cov = coverage("mould", &placed, p.coverage, &alpha);
        let pixels = LayerPixels::Tint {
            color: p.color,
            alpha,
        };
        push(Made {
            layers: vec![layer("mould", BlendMode::Normal, p.opacity, pixels)],
            coverage: cov,
        });
    }
    progress.check()?;
    if preset.rust.enabled {
        progress.update("rust", 4.0 / steps);
        let p = &preset.rust;
        let placed = placement::place(ctx, p.place());
        push(rust::stage(ctx, p, &placed, seed, progress)?);
    }
    progress.check()?;
    if preset.smudges.enabled {
        progress.update("smudges", 5.0 / steps);
        let p = &preset.smudges;
        let placed = placement::place(ctx, p.place());
        let (img, alpha) = smudges::smudges(ctx, p, &placed, seed);
        push(Made {
            layers: vec![layer(
                "smudges",
                BlendMode::Normal,
                p.opacity,
                LayerPixels::Rgba(img),
            )],
            coverage: coverage("smudges", &placed, p.coverage, &alpha),
        });
    }
    progress.check()?;
    if preset.corrosion.enabled {
        progress.update("corrosion", 6.0 / steps);
        let p = &preset.corrosion;
        let placed = placement::place(ctx, p.place());
        let (img, alpha) = smudges::corrosion(ctx, p, &placed, seed);
        push(Made {
            layers: vec![layer(
                "corrosion",
                BlendMode::Multiply,
                p.opacity,
                LayerPixels::Rgba(img),
            )],
            coverage: coverage("corrosion", &placed, p.coverage, &alpha),
        });
    }
    Ok(Produced {
        layer_stats: vec![None; layers.len()],
        layers,
        stats: Stats::Imperfections(ImperfectionStats { generators }),
    })
}

/// Whether any imperfection is on.
pub fn enabled(preset: &Preset) -> bool {
    preset.scratches.enabled
        || preset.splotches.enabled
        || preset.stains.enabled
        || preset.mould.enabled
        || preset.rust.enabled
        || preset.smudges.enabled
        || preset.corrosion.enabled
}

#[cfg(test)]
mod tests;
