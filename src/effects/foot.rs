//! The foot of the wall (`how-facades-age.md`, "Near the ground"): rain
//! hitting the ground throws soil and grime up the bottom 0.3 to 0.5 m of a
//! wall that stands on it, a darker spatter that thins out upward with a
//! ragged top; rising damp leaves a tide mark up to about 1 m. One
//! "splash zone soiling" layer, multiplied into the wall so its
//! texture shows through, only where the scene's ground is right below
//! the wall (not over a shop window's glass, not where a car, a tree or
//! the frame cuts the wall), growing with the rainfalls.
//!
//! Blind review p28 (`docs/blind-review.md`): critics preferred stronger
//! ageing where dirt collects and called its absence at the foot "freshly
//! washed"; the open wall stays as it was.

use image::GrayImage;
use rayon::prelude::*;
use serde::Serialize;

use super::{Context, Effect, Produced, Products, Stats};
use crate::error::Result;
use crate::preset::{FootParams, Preset};
use crate::progress::Progress;
use crate::random::{Noise, key, smoothstep};
use crate::stack::{BlendMode, Layer, LayerPixels};

/// The layer's name in the stack and in PSD, ORA and layer folders.
pub const LAYER: &str = "splash zone soiling";

/// The ground line is smoothed over this width, metres: the analysis
/// finds it on its own, coarser grid, in steps.
const SMOOTH_M: f32 = 0.2;

/// Gaps in the ground line narrower than this, metres, are bridged (a
/// bollard in front of the foot).
const GAP_M: f32 = 0.2;

/// A wall's foot runs on, straight or gently bending, for metres: the
/// ground line is compared with its running median over this width,
/// metres, ...
const TREND_M: f32 = 1.2;

/// ... and a column further than this from it, metres, is something else
/// standing on the ground (a walker's legs, a bollard, a wheel taken for
/// wall) [choice: 0.12 m also cut the ragged edge of the analysis's ground
/// under IMG_8813's shop fronts, 662 columns to 33 (with 1 m runs)].
const OFF_TREND_M: f32 = 0.25;

/// Stretches of ground line shorter than this, metres, are left alone:
/// the foot of a wall is wider than a person or a post [choice: at 0.5 m
/// IMG_8813's short stretches became rows of small tents (277 columns,
/// 115 at 1 m)].
const MIN_RUN_M: f32 = 1.0;

/// Toward the end of a stretch of ground (a car, a shop window, a tree
/// beside it) the soiling fades out over this, metres, so its end is soft
/// instead of cut square.
const TAPER_M: f32 = 0.15;

/// ... and its height falls to this share of its reach there.
const TAPER_HEIGHT: f32 = 0.5;

// Only where the scene is at least `SURE` sure the ground row is the
// wall's foot (`Site::ground_sure_at`) is it soiled, and there its soiling
// is weighed by how sure [choice: the analysis's sure foot].
use crate::analysis::foot_line::SURE;

/// Size of the tone's mottling, metres (soil splashes in patches).
const MOTTLE_M: f32 = 0.15;

/// How the tone thins out from the ground to the splash's top: `(1 -
/// t)^TONE_FALL` at a share `t` of the height [choice: 1.5 left the
/// darkening a thin line at the foot on street photos 4-10 cm a pixel].
const TONE_FALL: f32 = 1.0;

/// Specks fly this much higher than the tone reaches.
const SPECK_REACH: f32 = 1.3;

/// How much of the splash height the soiling has when it starts; it rises
/// to the full height as it grows.
const YOUNG_HEIGHT: f32 = 0.6;

/// Width of the tide mark's darker rim, metres.
const RIM_M: f32 = 0.04;

/// The damp band under the tide mark is this share of the rim's coverage.
const DAMP: f32 = 0.3;

/// How much the tide mark's height varies along the wall, as a share of
/// it, and over what length, metres.
const TIDE_SPREAD: f32 = 0.2;
const TIDE_SIZE_M: f32 = 1.5;

/// The foot's own random streams, under [`Effect::Foot`].
const TOP: u16 = 0;
const MOTTLE: u16 = 1;
const SPECKS: u16 = 2;
const TIDE: u16 = 3;

/// The foot soiling's numbers in the report.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FootStats {
    /// How grown the soiling is, 0..1 ([`grown`]).
    pub grown: f32,
    /// Photo columns where the wall stands on the ground.
    pub columns: u32,
    /// Pixels the layer covers.
    pub pixels: u64,
    /// Their mean coverage, 0..1.
    pub mean: f32,
}

/// How grown the soiling is after `rainfalls`: `1 - exp(-n / p.rainfalls)`
/// [choice: each rain throws up a little more soil, and the next rain
/// washes some of it down; saturating, 0.86 at 50 years' 40 rainfalls].
pub fn grown(p: &FootParams, rainfalls: u32) -> f32 {
    1.0 - (-(rainfalls as f32) / p.rainfalls.max(0.1)).exp()
}

/// The "splash zone soiling" layer.
pub(super) fn stage(
    ctx: &Context,
    _products: &mut Products,
    preset: &Preset,
    progress: &Progress,
) -> Result<Produced> {
    progress.check()?;
    let p = &preset.foot;
    let (alpha, stats) = alpha(ctx, p, preset.rain.layers, preset.seed);
    progress.update("foot", 1.0);
    // [choice] No layer where nothing is soiled (no ground under the wall,
    // no rainfall yet): an empty layer in every stack says nothing.
    if stats.pixels == 0 {
        return Ok(Produced {
            layers: Vec::new(),
            layer_stats: Vec::new(),
            stats: Stats::Foot(stats),
        });
    }
    let layer = Layer {
        name: LAYER.into(),
        kind: Some(Effect::Foot),
        blend: BlendMode::Multiply,
        opacity: p.opacity,
        visible: true,
        pixels: LayerPixels::Tint {
            color: p.color,
            alpha,
        },
    };
    Ok(Produced {
        layers: vec![layer],
        layer_stats: vec![None],
        stats: Stats::Foot(stats),
    })
}

/// Per photo column of the wall's foot: the ground row, how high the
/// spatter reaches and where the tide mark lies, photo pixels.
struct Foot {
    ground: Vec<f32>,
    reach: Vec<f32>,
    tide: Vec<f32>,
    /// 0..1: toward the end of a stretch of ground the soiling fades out.
    fade: Vec<f32>,
}

/// The layer's alpha at the photo's size and its numbers, for `p` after
/// `rainfalls` rainfalls.
pub fn alpha(ctx: &Context, p: &FootParams, rainfalls: u32, seed: u64) -> (GrayImage, FootStats) {
    let (w, h) = ctx.size();
    let mut out = GrayImage::new(w, h);
    let grown = grown(p, rainfalls);
    let ground = ground_line(ctx);
    let columns = ground.iter().filter(|g| g.is_finite()).count() as u32;
    let mut stats = FootStats {
        grown,
        columns,
        pixels: 0,
        mean: 0.0,
    };
    let top = p.strength * grown;
    if columns == 0 || top <= 0.0 {
        return (out, stats);
    }
    let foot = columns_of(ctx, p, ground, grown, seed);
    let Some((y0, y1)) = band(&foot, h) else {
        return (out, stats);
    };
    let noise = |stream: u16, size_m: f32, octaves: u32| {
        let k = key(seed, (Effect::Foot, stream), 0, 0);
        let size = ctx.photo_px(size_m).max(1.5);
        Noise::new(k, w, y1 - y0, size, octaves)
    };
    let mottle = noise(MOTTLE, MOTTLE_M, 3);
    let specks = noise(SPECKS, p.speck_m, 1);
    // Specks smaller than a pixel or two blend into the tone: a street
    // photo a few centimetres a pixel shows the spatter as a darker band.
    let spatter = p.spatter * ((ctx.photo_px(p.speck_m) - 1.0) / 2.0).clamp(0.0, 1.0);
    let rim = ctx.photo_px(RIM_M).max(1.0);
    let tide = p.tide * grown;
    let (w, stride) = (w as usize, w as usize);
    let rows = &mut out.as_mut()[y0 as usize * stride..y1 as usize * stride];
    rows.par_chunks_mut(stride)
        .enumerate()
        .for_each(|(i, row)| {
            let y = (y0 as usize + i) as f32 + 0.5;
            let weights = ctx.wall.mask_row(y0 + i as u32);
            for x in 0..w {
                let g = foot.ground[x];
                if !g.is_finite() || y > g + 2.0 {
                    continue;
                }
                let weight = weights.map_or(1.0, |m| m[x] as f32 / 255.0);
                if weight == 0.0 {
                    continue;
                }
                let (xf, yn) = (x as f32, i as f32);
                let above = (g - y).max(0.0);
                let mut a = 0.0;
                let reach = foot.reach[x];
                if reach > 0.0 && above < reach * SPECK_REACH {
                    let t = above / reach;
                    let tone = (1.0 - t).max(0.0).powf(TONE_FALL);
                    let m = ((mottle.at(xf, yn) - 0.5) * 2.5 + 0.5).clamp(0.0, 1.0);
                    let dense = (1.0 - t / SPECK_REACH).max(0.0);
                    let cut = 1.0 - 0.6 * dense;
                    let speck = smoothstep(((specks.at(xf, yn) - cut) / 0.08).clamp(0.0, 1.0));
                    a = top
                        * ((1.0 - spatter) * tone * (0.55 + 0.45 * m)
                            + spatter * speck * (0.5 + 0.5 * dense));
                }
                if tide > 0.0 && above < foot.tide[x] {
                    let under = foot.tide[x] - above;
                    let edge = (1.0 - under / rim).max(0.0);
                    a = a.max(tide * (DAMP + (1.0 - DAMP) * edge * edge));
                }
                row[x] = (a.clamp(0.0, 1.0) * foot.fade[x] * weight * 255.0).round() as u8;
            }
        });
    let (n, sum) = rows
        .par_iter()
        .filter(|a| **a > 0)
        .fold(|| (0u64, 0u64), |(n, s), a| (n + 1, s + *a as u64))
        .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
    stats.pixels = n;
    stats.mean = if n > 0 {
        sum as f32 / n as f32 / 255.0
    } else {
        0.0
    };
    (out, stats)
}

/// The rows the soiling can reach: from the highest spatter or tide mark
/// to just under the lowest ground row; `None` when that is empty.
fn band(foot: &Foot, h: u32) -> Option<(u32, u32)> {
    let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
    for ((g, r), t) in foot.ground.iter().zip(&foot.reach).zip(&foot.tide) {
        if g.is_finite() {
            lo = lo.min(g - (r * SPECK_REACH).max(*t) - 1.0);
            hi = hi.max(g + 3.0);
        }
    }
    let (y0, y1) = (lo.max(0.0) as u32, (hi.max(0.0) as u32).min(h));
    (y1 > y0).then_some((y0, y1))
}

/// The per-column reach of the spatter and height of the tide mark over
/// `ground`: `height_m` varied along the wall by 1D fBm, lower while the
/// soiling is young, tapering to nothing at the ends of a stretch.
fn columns_of(ctx: &Context, p: &FootParams, ground: Vec<f32>, grown: f32, seed: u64) -> Foot {
    let w = ground.len();
    let along = |stream: u16, size_m: f32| {
        let k = key(seed, (Effect::Foot, stream), 0, 0);
        Noise::new(k, w as u32, 1, ctx.photo_px(size_m).max(1.5), 3)
    };
    let (top, tide_noise) = (along(TOP, p.top_size_m), along(TIDE, TIDE_SIZE_M));
    let taper = taper(&ground, ctx.photo_px(TAPER_M).max(1.0));
    let sure = sure_along(ctx, &ground);
    let height = ctx.photo_px(p.height_m) * (YOUNG_HEIGHT + (1.0 - YOUNG_HEIGHT) * grown);
    let tide_h = ctx.photo_px(p.tide_m);
    // fBm's values gather about 0.5: stretched so the top's rises and dips
    // span about +-`top_spread`.
    let vary = |n: f32, spread: f32| 1.0 + spread * ((n - 0.5) * 3.0).clamp(-1.0, 1.0);
    let reach = (0..w)
        .map(|x| {
            let low = TAPER_HEIGHT + (1.0 - TAPER_HEIGHT) * taper[x];
            height * vary(top.at(x as f32, 0.0), p.top_spread) * low
        })
        .collect();
    let tide = (0..w)
        .map(|x| match p.tide > 0.0 {
            true => tide_h * vary(tide_noise.at(x as f32, 0.0), TIDE_SPREAD) * taper[x],
            false => 0.0,
        })
        .collect();
    let fade = taper.iter().zip(&sure).map(|(t, s)| t * s).collect();
    Foot {
        ground,
        reach,
        tide,
        fade,
    }
}

/// Per column of `ground`, how sure the scene is of it
/// ([`crate::pipeline::Site::ground_sure_at`]), carried across the gaps
/// [`ground_line`] bridged (linearly, as the ground row); 0 off the ground.
fn sure_along(ctx: &Context, ground: &[f32]) -> Vec<f32> {
    let known: Vec<f32> = (0..ground.len())
        .map(|x| {
            let s = ctx.site.ground_sure_at(x as u32);
            match ctx.site.ground_at(x as u32).is_some() && s >= SURE {
                true => s,
                false => f32::NAN,
            }
        })
        .collect();
    let bridged = bridge(&known, ground.len() as f32);
    ground
        .iter()
        .zip(bridged)
        .map(|(g, s)| {
            if g.is_finite() && s.is_finite() {
                s
            } else {
                0.0
            }
        })
        .collect()
}

/// The scene's ground row per photo column where the wall stands on the
/// ground ([`crate::pipeline::Site::ground_at`]) and the scene is at least
/// [`SURE`] sure of it, narrow gaps bridged and
/// smoothed by a running median; `NaN` elsewhere.
pub fn ground_line(ctx: &Context) -> Vec<f32> {
    let (w, _) = ctx.size();
    let raw: Vec<f32> = (0..w)
        .map(|x| match ctx.site.ground_sure_at(x) >= SURE {
            true => ctx.site.ground_at(x).unwrap_or(f32::NAN),
            false => f32::NAN,
        })
        .collect();
    let bridged = bridge(&raw, ctx.photo_px(GAP_M));
    let trend = median(&bridged, (ctx.photo_px(TREND_M) * 0.5).round() as usize);
    let off = ctx.photo_px(OFF_TREND_M).max(1.5);
    let on: Vec<f32> = bridged
        .iter()
        .zip(&trend)
        .map(|(g, t)| if (g - t).abs() <= off { *g } else { f32::NAN })
        .collect();
    let long = drop_short(&on, ctx.photo_px(MIN_RUN_M));
    median(&long, (ctx.photo_px(SMOOTH_M) * 0.5).round() as usize)
}

/// `line` with runs of finite values shorter than `min` set to `NaN`.
fn drop_short(line: &[f32], min: f32) -> Vec<f32> {
    let mut out = line.to_vec();
    let mut start = 0;
    for x in 0..=line.len() {
        let end = x == line.len() || !line[x].is_finite();
        if end {
            if ((x - start) as f32) < min {
                out[start..x].fill(f32::NAN);
            }
            start = x + 1;
        }
    }
    out
}

/// `line` with runs of `NaN` narrower than `gap` between two finite values
/// filled in linearly.
fn bridge(line: &[f32], gap: f32) -> Vec<f32> {
    let mut out = line.to_vec();
    let mut last: Option<usize> = None;
    for x in 0..line.len() {
        if !line[x].is_finite() {
            continue;
        }
        if let Some(l) = last
            && x > l + 1
            && ((x - l - 1) as f32) < gap
        {
            let (a, b) = (line[l], line[x]);
            for (k, v) in out[l + 1..x].iter_mut().enumerate() {
                *v = a + (b - a) * (k + 1) as f32 / (x - l) as f32;
            }
        }
        last = Some(x);
    }
    out
}

/// The median of the finite values within `r` of each finite value.
fn median(line: &[f32], r: usize) -> Vec<f32> {
    (0..line.len())
        .into_par_iter()
        .map(|x| {
            if !line[x].is_finite() || r == 0 {
                return line[x];
            }
            let lo = x.saturating_sub(r);
            let hi = (x + r + 1).min(line.len());
            let mut near: Vec<f32> = line[lo..hi]
                .iter()
                .copied()
                .filter(|v| v.is_finite())
                .collect();
            near.sort_by(f32::total_cmp);
            near[near.len() / 2]
        })
        .collect()
}

/// Per column, 0..1: how far in from the nearest column without ground
/// (the photo's own edges do not count), smoothstepped over `over` pixels.
fn taper(line: &[f32], over: f32) -> Vec<f32> {
    let n = line.len();
    let mut dist = vec![f32::INFINITY; n];
    let mut run = f32::INFINITY;
    for x in 0..n {
        run = if line[x].is_finite() { run + 1.0 } else { 0.0 };
        dist[x] = run;
    }
    run = f32::INFINITY;
    for x in (0..n).rev() {
        run = if line[x].is_finite() { run + 1.0 } else { 0.0 };
        dist[x] = dist[x].min(run);
    }
    dist.iter()
        .map(|d| smoothstep((d / over).clamp(0.0, 1.0)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn narrow_gaps_are_bridged_and_wide_ones_kept() {
        let nan = f32::NAN;
        let line = [10.0, nan, nan, 16.0, nan, nan, nan, nan, nan, 20.0];
        let out = bridge(&line, 3.0);
        assert_eq!(&out[..4], &[10.0, 12.0, 14.0, 16.0]);
        assert!(out[4..9].iter().all(|v| v.is_nan()));
    }

    #[test]
    fn short_runs_are_dropped() {
        let nan = f32::NAN;
        let line = [1.0, 1.0, nan, 2.0, 2.0, 2.0, nan, 3.0];
        let out = drop_short(&line, 3.0);
        assert!(out[..2].iter().all(|v| v.is_nan()) && out[7].is_nan());
        assert_eq!(&out[3..6], &[2.0, 2.0, 2.0]);
    }

    #[test]
    fn the_taper_falls_to_nothing_at_a_gap_but_not_at_the_frame() {
        let mut line = vec![1.0; 40];
        line[20] = f32::NAN;
        let t = taper(&line, 10.0);
        assert_eq!(t[0], 1.0);
        assert_eq!(t[20], 0.0);
        assert!(t[19] < 0.05 && t[25] < t[29] && t[31] == 1.0, "{t:?}");
    }

    #[test]
    fn the_soiling_grows_with_the_rainfalls_and_saturates() {
        let p = FootParams::default();
        assert_eq!(grown(&p, 0), 0.0);
        let g: Vec<f32> = [4, 12, 40, 200].map(|n| grown(&p, n)).to_vec();
        assert!(g.windows(2).all(|w| w[0] < w[1]), "{g:?}");
        assert!(g[3] <= 1.0 && g[3] > 0.99);
    }
}
