//! From deposited dirt to stain coverage: `alpha = strength * D / D_max`,
//! with a soft edge. Layers are later stacked in time order with multiply,
//! so streaks start thin and faint and grow wider and darker as rainfalls
//! recur near the same paths; a [`Film`] makes that stack saturate.

use rayon::prelude::*;

use super::RainLayer;
use crate::effects::percentile::{Rank, percentile};
use crate::field::{ColumnMajor, RowMajor};
use crate::preset::StainParams;

/// D_max: the `percentile` of the first rainfall's positive deposits
/// [choice: a high percentile rather than the maximum, so one hot pixel where
/// a droplet dried does not wash out every other streak; later rainfalls are
/// measured against the same D_max, so accumulated dirt reads darker].
pub fn d_max(layers: &[RainLayer], q: f32) -> f32 {
    layers
        .iter()
        .find_map(|layer| high(&layer.deposit, q))
        .map_or(1.0, |v| v.max(f32::MIN_POSITIVE))
}

/// The washed runs' counterpart of D_max: the `percentile` of the positive
/// net washed dirt (1 when nothing was washed off).
pub fn w_max(washed: &ColumnMajor<f32>, q: f32) -> f32 {
    high(washed, q).map_or(1.0, |v| v.max(f32::MIN_POSITIVE))
}

/// The `q`-quantile of the positive values, if there are any.
fn high(values: &ColumnMajor<f32>, q: f32) -> Option<f32> {
    let positive = values.data().iter().copied().filter(|&v| v > 0.0);
    percentile(positive, q, Rank::Nearest)
}

/// Stain coverage for each rainfall in turn, reusing its buffers.
#[derive(Debug)]
pub struct Coverage {
    columns: ColumnMajor<f32>,
    rows: RowMajor<f32>,
}

impl Coverage {
    /// Coverage for deposits on a `width` x `height` grid.
    pub fn new(width: usize, height: usize) -> Coverage {
        Coverage {
            columns: ColumnMajor::filled(width, height, 0.0),
            rows: RowMajor::filled(width, height, 0.0),
        }
    }

    /// Coverage in 0..1 per grid pixel for one rainfall's `deposit`.
    /// `blur` is the edge's blur radius in grid pixels.
    pub fn of(
        &mut self,
        deposit: &ColumnMajor<f32>,
        d_max: f32,
        p: &StainParams,
        blur: f32,
    ) -> &mut RowMajor<f32> {
        let strength = p.strength;
        let alpha = |d: f32| (strength * d / d_max).clamp(0.0, 1.0);
        blur_transposed(deposit, blur, alpha, &mut self.columns, &mut self.rows);
        &mut self.rows
    }
}

/// The most full-strength rain layers the stains on one spot add up to
/// [choice: a dirt film saturates: however often dirt is laid on the same
/// spot, the wall reads at most as dark as a full film (blind review 14,
/// tell 2: forty multiplied rainfalls, 0.825^40, left near-black cores with
/// no brick or plaster in them). With the default stain (colour luma 0.30,
/// opacity 0.25) four layers' worth is a floor of 0.83^4 = 0.47 of the clean
/// wall's luma, dark as heavy soot streaks yet the brick still shows.
/// Measured on the one-ledge brick wall at 40 rainfalls, the darkest streak
/// core (12 x 12 px mean) relative to the clean wall: 0.012 before the film;
/// 0.58 with 3 (a faint haze), 0.49 with 4, 0.41 with 5 (mortar joints
/// fading)].
pub const FILM_LAYERS: f32 = 4.0;

/// The dirt film the rainfalls lay, one after another: turns each
/// rainfall's coverage `a_k` into its layer's alpha so the multiplied stack
/// saturates. Each rainfall films a share `a_k / L` of the spot
/// ([`FILM_LAYERS`] = L) and shares combine like a union, `C_k = 1 -
/// prod(1 - a_j / L)`; layer k gets the alpha that adds what the union grew
/// by, `L (C_k - C_{k-1}) = a_k (1 - C_{k-1})`. So the alphas on a spot sum
/// to `L C_k < L`, and a stack of multiply layers of darkening `s` (colour
/// and opacity) reads at least `(1 - s)^L` of the wall whatever the number
/// of rainfalls (as `1 - a s >= (1 - s)^a` for `a` in 0..1), while more rain
/// never lightens (alphas stay >= 0). The first rainfall keeps its coverage;
/// the alphas do not depend on the stain's colour or opacity, so restyling
/// those keeps a run and its time-lapse prefixes the same. Layer k depends
/// only on the rainfalls before it: the first N layers are the N-rainfall
/// run's.
#[derive(Debug)]
pub struct Film {
    /// `1 - C`, per grid pixel: the share no rainfall has filmed yet.
    bare: RowMajor<f32>,
}

impl Film {
    /// A clean wall on a `width` x `height` grid.
    pub fn new(width: usize, height: usize) -> Film {
        Film {
            bare: RowMajor::filled(width, height, 1.0),
        }
    }

    /// Lays one rainfall of coverage `cover` (0..1 per grid pixel), turning
    /// it into its layer's alpha.
    pub fn lay(&mut self, cover: &mut RowMajor<f32>) {
        cover
            .data_mut()
            .par_iter_mut()
            .zip(self.bare.data_mut())
            .for_each(|(a, bare)| {
                let given = a.clamp(0.0, 1.0);
                *a = given * *bare;
                *bare *= 1.0 - given / FILM_LAYERS;
            });
    }
}

/// Multiplies `alpha` by `by` (the same size), pixel by pixel: a
/// rainfall's filmed alpha by its streaks' gain (`fall::Fall::gain`), so
/// the alphas on a spot sum to `gain * L * C_k` instead of `L * C_k` and
/// the stack reads at least `(1 - s)^(gain L)` of the wall ([`Film`]).
pub fn scale(alpha: &mut RowMajor<f32>, by: &RowMajor<f32>) {
    alpha
        .data_mut()
        .par_iter_mut()
        .zip(by.data())
        .for_each(|(a, g)| *a *= g);
}

/// Outputs a blur pass computes together.
const RUN: usize = 16;

/// Separable Gaussian blur with standard deviation `sigma` (edges clamped)
/// of `map(v)` for each value of `values`, into `out` (of the same size);
/// `tmp` (the same size too) is a buffer.
pub fn blur_transposed(
    values: &ColumnMajor<f32>,
    sigma: f32,
    map: impl Fn(f32) -> f32 + Sync,
    tmp: &mut ColumnMajor<f32>,
    out: &mut RowMajor<f32>,
) {
    assert!(values.same_size(tmp) && values.same_size(out), "blur sizes");
    let (width, height) = (values.width(), values.height());
    let (values, tmp, out) = (values.data(), tmp.data_mut(), out.data_mut());
    if width == 0 || height == 0 {
        return;
    }
    let radius = if sigma > 0.0 {
        (3.0 * sigma).ceil() as usize
    } else {
        0
    };
    let mut kernel: Vec<f32> = (0..=2 * radius)
        .map(|i| {
            let d = i as f32 - radius as f32;
            if sigma > 0.0 {
                (-(d * d) / (2.0 * sigma * sigma)).exp()
            } else {
                1.0
            }
        })
        .collect();
    let sum: f32 = kernel.iter().sum();
    kernel.iter_mut().for_each(|k| *k /= sum);
    // Down each column, through a copy padded with its end values.
    tmp.par_chunks_mut(height)
        .zip(values.par_chunks(height))
        .for_each_init(Vec::new, |padded, (out, column)| {
            padded.clear();
            padded.resize(radius, map(column[0]));
            padded.extend(column.iter().map(|&v| map(v)));
            padded.resize(height + 2 * radius, map(column[height - 1]));
            out.fill(0.0);
            for (k, w) in kernel.iter().enumerate() {
                for (o, v) in out.iter_mut().zip(&padded[k..k + height]) {
                    *o += w * v;
                }
            }
        });
    // Across the columns, a band of output rows at a time, in tiles that
    // are written out row by row.
    const BAND: usize = RUN;
    const TILE: usize = 64;
    let tmp = &*tmp;
    out.par_chunks_mut(BAND * width)
        .enumerate()
        .for_each(|(band, out)| {
            let y0 = band * BAND;
            let rows = out.len() / width;
            let mut tile = [0.0f32; BAND * TILE];
            let mut acc = [0.0f32; BAND];
            for x0 in (0..width).step_by(TILE) {
                let cols = TILE.min(width - x0);
                for dx in 0..cols {
                    acc.fill(0.0);
                    for (k, w) in kernel.iter().enumerate() {
                        let c = (x0 + dx + k).saturating_sub(radius).min(width - 1);
                        let src = &tmp[c * height + y0..c * height + y0 + rows];
                        for (a, v) in acc.iter_mut().zip(src) {
                            *a += w * v;
                        }
                    }
                    for (dy, a) in acc[..rows].iter().enumerate() {
                        tile[dy * TILE + dx] = *a;
                    }
                }
                for dy in 0..rows {
                    out[dy * width + x0..dy * width + x0 + cols]
                        .copy_from_slice(&tile[dy * TILE..dy * TILE + cols]);
                }
            }
        });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::rain::LayerStats;

    fn layer(deposit: Vec<f32>) -> RainLayer {
        RainLayer {
            deposit: ColumnMajor::new(deposit.len(), 1, deposit),
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
        let mut cov = Coverage::new(4, 1);
        let deposit = ColumnMajor::new(4, 1, vec![0.0, 1.0, 2.0, 10.0]);
        assert_eq!(cov.of(&deposit, 4.0, &p, 0.0).data(), [0.0, 0.25, 0.5, 1.0]);
    }

    /// Many rainfalls on one spot: the darkening the stacked multiply layers
    /// give (as in `stack.rs`) never goes below the film's floor, and each
    /// rainfall darkens or keeps; on the stack of today's alphas forty
    /// rainfalls of 0.6 fall to 0.825^24, near black.
    #[test]
    fn a_film_saturates_and_never_lightens() {
        let s = 0.25 * (1.0 - 0.30f32);
        let floor = (1.0 - s).powf(FILM_LAYERS);
        for strength in [0.05f32, 0.3, 0.6, 1.0] {
            let mut film = Film::new(1, 1);
            let mut m = 1.0f32;
            for k in 0..200 {
                let mut cover = RowMajor::filled(1, 1, strength);
                film.lay(&mut cover);
                let a = cover.data()[0];
                assert!((0.0..=1.0).contains(&a), "alpha {a}");
                if k == 0 {
                    assert_eq!(a, strength, "the first rainfall keeps its coverage");
                }
                let next = m * (1.0 - a * s);
                assert!(next <= m, "rainfall {k} lightened");
                m = next;
                assert!(m >= floor - 1e-6, "{m} below the floor {floor}");
            }
            assert!(
                m < floor + 0.07,
                "{strength}: 200 rainfalls reach {m}, floor {floor}"
            );
        }
    }

    #[test]
    fn blur_matches_a_plain_2d_convolution() {
        let (w, h, sigma) = (9, 7, 1.2f32);
        let v: Vec<f32> = (0..w * h).map(|i| ((i * 31) % 17) as f32).collect();
        let columns = ColumnMajor::from_fn(w, h, |x, y| v[y * w + x]);
        let mut tmp = ColumnMajor::filled(w, h, 0.0);
        let mut got = RowMajor::filled(w, h, 0.0);
        blur_transposed(&columns, sigma, |v| v, &mut tmp, &mut got);
        let got = got.data();
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
            strength: 1.0,
            ..StainParams::default()
        };
        let mut d = ColumnMajor::filled(21, 21, 0.0);
        d.data_mut()[10 * 21 + 10] = 0.5;
        let mut cov = Coverage::new(21, 21);
        let a = cov.of(&d, 1.0, &p, 1.5).data();
        assert!(a[10 * 21 + 11] > 0.0, "edge is soft");
        let total: f32 = a.iter().sum();
        assert!((total - 0.5).abs() < 0.02, "{total}");
    }
}
