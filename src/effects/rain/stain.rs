//! From deposited dirt to stain coverage: `alpha = strength * D / D_max`,
//! with a soft edge. Layers are later stacked in time order with multiply,
//! so streaks start thin and faint and grow wider and darker as rainfalls
//! recur near the same paths.

use image::{ImageBuffer, Luma};

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
pub fn coverage(deposit: &[f32], width: usize, height: usize, d_max: f32, p: &StainParams) -> Vec<f32> {
    let alpha: Vec<f32> = deposit
        .iter()
        .map(|&d| (p.strength * d / d_max).clamp(0.0, 1.0))
        .collect();
    if p.softness <= 0.0 || width == 0 || height == 0 {
        return alpha;
    }
    let img: ImageBuffer<Luma<f32>, Vec<f32>> =
        ImageBuffer::from_raw(width as u32, height as u32, alpha).expect("size matches");
    imageproc::filter::gaussian_blur_f32(&img, p.softness).into_raw()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::rain::LayerStats;

    fn layer(deposit: Vec<f32>) -> RainLayer {
        RainLayer { deposit, stats: LayerStats::default(), paths: vec![] }
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
        let p = StainParams { softness: 0.0, strength: 1.0, ..StainParams::default() };
        let a = coverage(&[0.0, 1.0, 2.0, 10.0], 4, 1, 4.0, &p);
        assert_eq!(a, vec![0.0, 0.25, 0.5, 1.0]);
    }

    #[test]
    fn softness_spreads_but_keeps_total_roughly() {
        let p = StainParams { softness: 1.5, strength: 1.0, ..StainParams::default() };
        let mut d = vec![0.0; 21 * 21];
        d[10 * 21 + 10] = 0.5;
        let a = coverage(&d, 21, 21, 1.0, &p);
        assert!(a[10 * 21 + 11] > 0.0, "edge is soft");
        let total: f32 = a.iter().sum();
        assert!((total - 0.5).abs() < 0.02, "{total}");
    }
}
