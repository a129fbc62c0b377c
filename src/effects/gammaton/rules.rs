//! Between iterations: the ageing rules (thesis eqs. 3.28-3.29). After the
//! last: each substance's colour through its blend stops.

use image::{GrayImage, RgbaImage};
use rayon::prelude::*;

use crate::preset::{GammatonParams, RuleKind, Stop};

/// Applies `p.rules` in order to the substance maps (all the same size).
///
/// - transfer (eq. 3.28): `c_i -= k c_i; c_j += k c_i`;
/// - deteriorate (eq. 3.29): `c_i *= 1 + k`.
///
/// A rule with `only_where` acts only on pixels where that substance is
/// above zero (the material mask). Results are clamped at zero.
pub fn apply(maps: &mut [Vec<f32>], p: &GammatonParams) {
    for rule in &p.rules {
        let (Some(from), to) = (p.substance(&rule.from), p.substance(&rule.to)) else {
            continue;
        };
        let mask: Option<Vec<bool>> = p
            .substance(&rule.only_where)
            .map(|m| maps[m].iter().map(|&v| v > 0.0).collect());
        let here = |i: usize| mask.as_ref().is_none_or(|m| m[i]);
        let k = rule.rate;
        match (rule.kind, to) {
            (RuleKind::Transfer, Some(to)) if to != from => {
                let moved: Vec<f32> = maps[from]
                    .iter_mut()
                    .enumerate()
                    .map(|(i, c)| {
                        let m = if here(i) {
                            (k * *c).clamp(-*c, *c)
                        } else {
                            0.0
                        };
                        *c -= m;
                        m
                    })
                    .collect();
                for (c, m) in maps[to].iter_mut().zip(moved) {
                    *c = (*c + m).max(0.0);
                }
            }
            (RuleKind::Deteriorate, _) => {
                for (i, c) in maps[from].iter_mut().enumerate() {
                    if here(i) {
                        *c = (*c * (1.0 + k)).max(0.0);
                    }
                }
            }
            _ => {}
        }
    }
}

/// Colour and opacity of `value` (0..1) by linear interpolation between the
/// stops, clamped to the first and last.
pub fn sample(stops: &[Stop], value: f32) -> ([f32; 3], f32) {
    let rgb = |s: &Stop| s.color.map(|c| c as f32);
    let Some(first) = stops.first() else {
        return ([0.0; 3], 0.0);
    };
    if value <= first.value {
        return (rgb(first), first.opacity);
    }
    for w in stops.windows(2) {
        if value <= w[1].value {
            let t = (value - w[0].value) / (w[1].value - w[0].value).max(1e-9);
            let (a, b) = (rgb(&w[0]), rgb(&w[1]));
            let c = [0, 1, 2].map(|i| a[i] + (b[i] - a[i]) * t);
            return (c, w[0].opacity + (w[1].opacity - w[0].opacity) * t);
        }
    }
    let last = &stops[stops.len() - 1];
    (rgb(last), last.opacity)
}

/// The layer of a substance: photo-sized `value` (0..255 for 0..1 of its
/// scale) through its blend stops; transparent outside `mask`.
pub fn colour(value: &GrayImage, stops: &[Stop], mask: Option<&GrayImage>) -> RgbaImage {
    let lut: Vec<[u8; 4]> = (0..256)
        .map(|v| {
            let (c, a) = sample(stops, v as f32 / 255.0);
            let [r, g, b] = c.map(|x| x.round().clamp(0.0, 255.0) as u8);
            [r, g, b, (a * 255.0).round().clamp(0.0, 255.0) as u8]
        })
        .collect();
    let (w, h) = value.dimensions();
    let mut out = RgbaImage::new(w, h);
    out.par_chunks_mut(w as usize * 4)
        .enumerate()
        .for_each(|(y, row)| {
            let y = y as u32;
            for (x, px) in row.chunks_exact_mut(4).enumerate() {
                let x = x as u32;
                if mask.is_none_or(|m| m.get_pixel(x, y)[0] > 0) {
                    px.copy_from_slice(&lut[value.get_pixel(x, y)[0] as usize]);
                }
            }
        });
    out
}
