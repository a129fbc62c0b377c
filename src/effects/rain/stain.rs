//! From deposited dirt to stain coverage: `alpha = strength * D / D_max`,
//! with a soft edge. Layers are later stacked in time order with multiply,
//! so streaks start thin and faint and grow wider and darker as rainfalls
//! recur near the same paths.

use rayon::prelude::*;

use super::RainLayer;
use crate::preset::StainParams;

/// D_max: the `percentile` of the first rainfall's positive deposits
/// [choice: a high percentile rather than the maximum, so one hot pixel where
/// a droplet dried does not wash out every other streak; later rainfalls are
/// measured against the same D_max, so accumulated dirt reads darker].
pub fn d_max(layers: &[RainLayer], percentile: f32) -> f32 {
    for layer in layers {
        let mut positive: Vec<f32> = layer.deposit.iter().copied().filter(|&d| d > 0.0).collect();
        if positive.is_empty() {
            continue;
        }
        let k = ((positive.len() - 1) as f32 * percentile.clamp(0.0, 1.0)).round() as usize;
        let (_, v, _) = positive.select_nth_unstable_by(k, f32::total_cmp);
        return v.max(f32::MIN_POSITIVE);
    }
    1.0
}

/// Coverage in 0..1 per grid pixel for one rainfall's deposits.
pub fn coverage(
    deposit: &[f32],
    width: usize,
    height: usize,
    d_max: f32,
    p: &StainParams,
) -> Vec<f32> {
    let alpha: Vec<f32> = deposit
        .iter()
        .map(|&d| (p.strength * d / d_max).clamp(0.0, 1.0))
        .collect();
    blur(alpha, width, height, p.softness)
}

/// Separable Gaussian blur with standard deviation `sigma`, edges clamped.
pub fn blur(mut values: Vec<f32>, width: usize, height: usize, sigma: f32) -> Vec<f32> {
    if sigma <= 0.0 || width == 0 || height == 0 {
        return values;
    }
    let radius = (3.0 * sigma).ceil() as isize;
    let mut kernel: Vec<f32> = (-radius..=radius)
        .map(|i| (-(i * i) as f32 / (2.0 * sigma * sigma)).exp())
        .collect();
    let sum: f32 = kernel.iter().sum();
    kernel.iter_mut().for_each(|k| *k /= sum);
    let clamp = |i: isize, n: usize| i.clamp(0, n as isize - 1) as usize;
    // Horizontal pass, row by row.
    let mut tmp = vec![0.0; values.len()];
    tmp.par_chunks_mut(width)
        .zip(values.par_chunks(width))
        .for_each(|(out, row)| {
            for (x, o) in out.iter_mut().enumerate() {
                *o = kernel
                    .iter()
                    .enumerate()
                    .map(|(k, w)| w * row[clamp(x as isize + k as isize - radius, width)])
                    .sum();
            }
        });
    // Vertical pass, row by row over whole rows (cache-friendly).
    values
        .par_chunks_mut(width)
        .enumerate()
        .for_each(|(y, out)| {
            out.fill(0.0);
            for (k, w) in kernel.iter().enumerate() {
                let src = clamp(y as isize + k as isize - radius, height);
                for (o, v) in out.iter_mut().zip(&tmp[src * width..(src + 1) * width]) {
                    *o += w * v;
                }
            }
        });
    values
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::rain::LayerStats;

    fn layer(deposit: Vec<f32>) -> RainLayer {
        RainLayer {
            deposit,
            stats: LayerStats::default(),
            paths: vec![],
        }
    }

    #[test]
    fn d_max_is_a_percentile_of_the_first_nonempty_layer() {
        let mut deposit: Vec<f32> = (1..=100).map(|v| v as f32).collect();
        deposit.push(0.0);
        let layers = vec![layer(vec![0.0; 4]), layer(deposit), layer(vec![1000.0])];
        assert_eq!(d_max(&layers, 1.0), 100.0);
        assert_eq!(d_max(&layers, 0.5), 51.0);
    }

    #[test]
    fn coverage_scales_with_dirt_and_clamps() {
        let p = StainParams {
            softness: 0.0,
            strength: 1.0,
            ..StainParams::default()
        };
        let a = coverage(&[0.0, 1.0, 2.0, 10.0], 4, 1, 4.0, &p);
        assert_eq!(a, vec![0.0, 0.25, 0.5, 1.0]);
    }

    #[test]
    fn blur_matches_a_plain_2d_convolution() {
        let (w, h, sigma) = (9, 7, 1.2f32);
        let v: Vec<f32> = (0..w * h).map(|i| ((i * 31) % 17) as f32).collect();
        let got = blur(v.clone(), w, h, sigma);
        let r = (3.0 * sigma).ceil() as isize;
        let g = |i: isize| (-(i * i) as f32 / (2.0 * sigma * sigma)).exp();
        let norm: f32 = (-r..=r).map(g).sum();
        for y in 0..h as isize {
            for x in 0..w as isize {
                let mut want = 0.0;
                for dy in -r..=r {
                    for dx in -r..=r {
                        let sx = (x + dx).clamp(0, w as isize - 1) as usize;
                        let sy = (y + dy).clamp(0, h as isize - 1) as usize;
                        want += g(dx) * g(dy) / (norm * norm) * v[sy * w + sx];
                    }
                }
                let i = y as usize * w + x as usize;
                assert!((got[i] - want).abs() < 1e-3, "{} vs {want}", got[i]);
            }
        }
    }

    #[test]
    fn softness_spreads_but_keeps_total_roughly() {
        let p = StainParams {
            softness: 1.5,
            strength: 1.0,
            ..StainParams::default()
        };
        let mut d = vec![0.0; 21 * 21];
        d[10 * 21 + 10] = 0.5;
        let a = coverage(&d, 21, 21, 1.0, &p);
        assert!(a[10 * 21 + 11] > 0.0, "edge is soft");
        let total: f32 = a.iter().sum();
        assert!((total - 0.5).abs() < 0.02, "{total}");
    }
}
