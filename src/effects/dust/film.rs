//! The opacity film (Santos sec. 5.2, eqs. 2-5): fine particles, one pixel
//! each, in a few greys. Each pixel keeps a count per grey; the film's colour
//! is their mean and its opacity their weighted count.

use rand::Rng as _;
use rayon::prelude::*;

use super::Task;
use crate::effects::region::Region;
use crate::error::Result;
use crate::preset::DustParams;
use crate::progress::Progress;
use crate::random::{self, Stream};

/// Number of particle colours (the paper's three greys).
pub const COLORS: usize = 3;

/// The counters are split into at most this many bands (of a power-of-two
/// length); each band is updated by one thread, without atomics.
const BANDS: usize = 64;
/// Tasks generated before their particles are counted (bounds the memory of
/// a long run to about 2 MB of particle codes per thread).
const BATCH: usize = 64;

/// Per-pixel, per-grey particle counts p_{x,y,i} (Santos fig. 6).
///
/// Particles are generated in parallel, task by task, each into buckets by
/// band of the counter array; then every band adds up its buckets. Increments
/// commute, so the counts do not depend on scheduling. (Atomic increments
/// would be simpler, but a locked read-modify-write per particle serialises
/// the cache misses of random pixels and ran 5x slower.) A count saturates at
/// 65535 particles of one grey in one pixel, far beyond where RO reaches 1.
#[derive(Debug, Clone)]
pub struct Film {
    width: u32,
    counts: Vec<u16>,
}

/// How counts become colour and opacity (eqs. 2-4).
#[derive(Debug, Clone, Copy)]
pub struct Look {
    /// Grey level c_i of each particle kind.
    pub greys: [f32; COLORS],
    /// Opacity weight w_i of each kind.
    pub weights: [f32; COLORS],
    /// ANP_max.
    pub anp_max: f32,
}

impl Look {
    /// The look of a dust preset.
    pub fn new(p: &DustParams) -> Look {
        Look {
            greys: p.film_greys.map(f32::from),
            weights: p.film_weights,
            anp_max: p.anp_max.max(f32::MIN_POSITIVE),
        }
    }
}

impl Film {
    /// An empty film for a `width` x `height` texture.
    pub fn new(width: u32, height: u32) -> Film {
        let n = width as usize * height as usize * COLORS;
        Film {
            width,
            counts: vec![0; n],
        }
    }

    /// Particles of grey `i` at (x, y).
    pub fn count(&self, x: u32, y: u32, i: usize) -> u16 {
        self.counts[self.index(x, y) + i]
    }

    /// Total particles in the film.
    pub fn total(&self) -> u64 {
        self.counts.par_iter().map(|&c| c as u64).sum()
    }

    fn index(&self, x: u32, y: u32) -> usize {
        (y as usize * self.width as usize + x as usize) * COLORS
    }

    /// Lands each task's particles at uniformly random wall pixels, each with
    /// a uniformly random grey (Santos sec. 5.2). Returns how many landed.
    pub(crate) fn place(
        &mut self,
        region: &Region,
        tasks: &[Task],
        seed: u64,
        progress: &Progress,
    ) -> Result<u64> {
        let shift = self
            .counts
            .len()
            .div_ceil(BANDS)
            .max(1)
            .next_power_of_two()
            .trailing_zeros();
        let band_len = 1usize << shift;
        let mut placed = 0;
        for batch in tasks.chunks(BATCH) {
            progress.check()?;
            // Counter index (pixel * COLORS + grey) of every particle, by
            // band: the draws of `region.sample` and then the grey, with
            // the pixel's index found without dividing by the width.
            let buckets: Vec<Vec<Vec<usize>>> = batch
                .par_iter()
                .map(|t| {
                    let mut rng = random::rng(seed, Stream::DustFilm, t.day as u64, t.chunk);
                    let mut bands = vec![Vec::new(); BANDS];
                    for _ in 0..t.count {
                        let k = rng.random_range(0..region.area());
                        let pixel = region.nth_index(k) as usize;
                        let i = pixel * COLORS + rng.random_range(0..COLORS);
                        bands[i >> shift].push(i);
                    }
                    bands
                })
                .collect();
            self.counts
                .par_chunks_mut(band_len)
                .enumerate()
                .for_each(|(band, counts)| {
                    let base = band * band_len;
                    for task in &buckets {
                        for &i in &task[band] {
                            let c = &mut counts[i - base];
                            *c = c.saturating_add(1);
                        }
                    }
                });
            placed += batch.iter().map(|t| t.count).sum::<u64>();
        }
        Ok(placed)
    }

    /// The film after `n` particles in all, drawn per pixel: each wall pixel
    /// and grey gets a Poisson(n / (wall pixels x greys)) count, the limit
    /// of `n` uniform draws (Santos sec. 5.2) when `n` is many per pixel;
    /// the counts it held before are replaced. Costs one draw per pixel and
    /// grey however large `n` is.
    ///
    /// Each count is the inverse of the Poisson CDF at one uniform number
    /// that belongs to its pixel and grey for good (rows use their own
    /// streams, `key` and the row, so nothing depends on the thread count):
    /// the film after `n` particles is then the same whether it is drawn at
    /// once or after smaller steps, and a larger `n` never lowers a count.
    /// Returns how many landed.
    pub(crate) fn place_bulk(
        &mut self,
        region: &Region,
        n: u64,
        seed: u64,
        key: u64,
        progress: &Progress,
    ) -> Result<u64> {
        progress.check()?;
        let area = region.area().max(1);
        let poisson = Inverse::new(n as f64 / (area as f64 * COLORS as f64));
        let row_len = self.width as usize * COLORS;
        Ok(self
            .counts
            .par_chunks_mut(row_len.max(1))
            .enumerate()
            .map(|(y, row)| {
                let mut rng = random::rng(seed, Stream::DustFilm, key, y as u64);
                let mut landed = 0u64;
                for (x, px) in row.chunks_exact_mut(COLORS).enumerate() {
                    if !region.contains(x as f32 + 0.5, y as f32 + 0.5) {
                        px.fill(0);
                        continue;
                    }
                    for c in px {
                        *c = poisson.count(rng.random::<f64>());
                        landed += *c as u64;
                    }
                }
                landed
            })
            .sum())
    }

    /// The counts of row `y`, `COLORS` per pixel.
    pub fn row(&self, y: u32) -> &[u16] {
        let n = self.width as usize * COLORS;
        &self.counts[y as usize * n..(y as usize + 1) * n]
    }

    /// Mean grey u and relative opacity RO of pixel (x, y); (0, 0) without
    /// particles. C_op = u RO (Santos eq. 5) is the premultiplied film colour.
    pub fn pixel(&self, x: u32, y: u32, look: &Look) -> (u8, f32) {
        let i = self.index(x, y);
        look.shade(&self.counts[i..i + COLORS])
    }
}

/// The Poisson distribution drawn by inversion: its CDF tabled over the
/// counts that matter (the mass left out is below 1e-29), the counts
/// saturating at `u16::MAX` as the film's counters do.
struct Inverse {
    /// The first count in the table.
    lo: u64,
    /// P(X <= lo + i).
    cdf: Vec<f64>,
    /// The answer for every u in [j / G, (j + 1) / G), G = `guide.len()`
    /// a power of two (so u G is exact): the partition point of `cdf` at
    /// j / G, flagged with [`Inverse::WALK`] when a value of `cdf` lies
    /// inside the interval (then walked from there). Most draws read one
    /// entry instead of a binary search's eight (the bulk film's cost).
    guide: Vec<u32>,
}

impl Inverse {
    fn new(lambda: f64) -> Inverse {
        let lambda = lambda.max(0.0);
        let max = u16::MAX as f64;
        let spread = 12.0 * lambda.sqrt() + 16.0;
        if lambda - spread >= max {
            return Inverse::tabled(u16::MAX as u64, vec![1.0]);
        }
        let mode = lambda.floor() as u64;
        let lo = (lambda - spread).max(0.0) as u64;
        let hi = (lambda + spread) as u64;
        // The probabilities relative to the mode's, by the recurrence
        // p(k + 1) = p(k) lambda / (k + 1) (no factorial, no exp), then
        // normalised.
        let mut pmf = vec![0.0f64; (hi - lo + 1) as usize];
        let at = |k: u64| (k - lo) as usize;
        pmf[at(mode)] = 1.0;
        for k in mode + 1..=hi {
            pmf[at(k)] = pmf[at(k - 1)] * lambda / k as f64;
        }
        for k in (lo..mode).rev() {
            pmf[at(k)] = pmf[at(k + 1)] * (k + 1) as f64 / lambda;
        }
        let total: f64 = pmf.iter().sum();
        let mut sum = 0.0;
        let cdf = pmf
            .iter()
            .map(|p| {
                sum += p;
                sum / total
            })
            .collect();
        Inverse::tabled(lo, cdf)
    }

    /// The flag of a guide entry whose interval holds a value of the CDF.
    const WALK: u32 = 1 << 31;

    /// The distribution of `cdf` from `lo` on, with its guide table.
    fn tabled(lo: u64, cdf: Vec<f64>) -> Inverse {
        let g = (16 * cdf.len()).next_power_of_two().clamp(1 << 10, 1 << 16);
        let guide = (0..g)
            .map(|j| {
                let (from, to) = (j as f64 / g as f64, (j + 1) as f64 / g as f64);
                let at = cdf.partition_point(|&c| c <= from);
                let pure = at == cdf.partition_point(|&c| c < to);
                at as u32 | if pure { 0 } else { Inverse::WALK }
            })
            .collect();
        Inverse { lo, cdf, guide }
    }

    /// The count at uniform `u` in [0, 1): the least k with P(X <= k) > u.
    fn count(&self, u: f64) -> u16 {
        (self.lo + self.find(u).min(self.cdf.len() - 1) as u64).min(u16::MAX as u64) as u16
    }

    /// The number of entries of `cdf` at most `u` in [0, 1) (its
    /// partition point), from the guide.
    #[inline]
    fn find(&self, u: f64) -> usize {
        let j = ((u * self.guide.len() as f64) as usize).min(self.guide.len() - 1);
        let entry = self.guide[j];
        let mut i = (entry & !Inverse::WALK) as usize;
        if entry & Inverse::WALK != 0 {
            while i < self.cdf.len() && self.cdf[i] <= u {
                i += 1;
            }
        }
        i
    }
}

impl Look {
    /// Mean grey u and relative opacity RO of one pixel's counts.
    #[inline]
    pub fn shade(&self, counts: &[u16]) -> (u8, f32) {
        let look = self;
        let p: [f32; COLORS] = std::array::from_fn(|k| counts[k] as f32);
        let total: f32 = p.iter().sum();
        if total == 0.0 {
            return (0, 0.0);
        }
        // Santos eq. (2): u = sum_i p_i c_i / p.
        let u: f32 = (0..COLORS).map(|k| p[k] * look.greys[k]).sum::<f32>() / total;
        // Santos eq. (3): ANP = sum_i w_i p_i.
        let anp: f32 = (0..COLORS).map(|k| p[k] * look.weights[k]).sum();
        // Santos eq. (4): RO = ANP / ANP_max, in [0, 1].
        let ro = (anp / look.anp_max).clamp(0.0, 1.0);
        // (u + 0.5) truncated: round() is a libm call on baseline x86-64.
        ((u + 0.5).min(255.0) as u8, ro)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::dust::tasks;
    use crate::preset::Segment;

    fn look() -> Look {
        Look {
            greys: [100.0, 150.0, 200.0],
            weights: [1.0, 0.8, 0.6],
            anp_max: 1.2,
        }
    }

    #[test]
    fn colour_and_opacity_follow_eqs_2_to_4() {
        let mut f = Film::new(2, 1);
        f.counts[0] = 1; // one dark
        f.counts[2] = 1; // one light
        let (u, ro) = f.pixel(0, 0, &look());
        assert_eq!(u, 150, "mean of 100 and 200");
        assert_eq!(ro, 1.0, "ANP 1.6 > ANP_max 1.2 saturates");
        f.counts[5] = 1;
        let (u, ro) = f.pixel(1, 0, &look());
        assert_eq!((u, ro), (200, 0.5), "one light particle: 0.6 / 1.2");
        assert_eq!(f.pixel(0, 0, &look()).0, 150);
    }

    #[test]
    fn every_particle_is_counted_once_and_days_add_up() {
        let region = Region::new(40, 30, None).unwrap();
        let rate = [Segment::new(0, 3.0, 10.0)];
        let area = 1.0;
        let mut all = Film::new(40, 30);
        let placed = all
            .place(&region, &tasks(&rate, area, 1, 200), 9, &Progress::none())
            .unwrap();
        assert_eq!(placed, all.total());
        assert_eq!(placed, (area * 13.0 + area * 3.0 * 199.0).round() as u64);
        // Incremental: days 1-100, then 101-200, equal days 1-200 pixel for pixel.
        let mut steps = Film::new(40, 30);
        steps
            .place(&region, &tasks(&rate, area, 1, 100), 9, &Progress::none())
            .unwrap();
        let early = steps.counts.clone();
        steps
            .place(&region, &tasks(&rate, area, 101, 200), 9, &Progress::none())
            .unwrap();
        assert_eq!(all.counts, steps.counts);
        assert!(early.iter().zip(&steps.counts).all(|(a, b)| b >= a));
    }

    #[test]
    fn bulk_counts_are_poisson_and_the_same_in_one_step_or_several() {
        let region = Region::new(200, 150, None).unwrap();
        let px = 200.0 * 150.0 * COLORS as f64;
        let bulk = |steps: &[u64]| {
            let mut f = Film::new(200, 150);
            let mut landed = 0;
            for &n in steps {
                landed = f
                    .place_bulk(&region, n, 5, 1 << 32, &Progress::none())
                    .unwrap();
            }
            (f, landed)
        };
        let n = (7.5 * px) as u64;
        let (once, landed) = bulk(&[n]);
        let (steps, _) = bulk(&[n / 3, n / 2, n]);
        assert_eq!(once.counts, steps.counts);
        assert_eq!(landed, once.total());
        // Poisson(7.5): mean and variance 7.5.
        let mean = landed as f64 / px;
        let var = once
            .counts
            .iter()
            .map(|&c| (c as f64 - mean).powi(2))
            .sum::<f64>()
            / px;
        assert!((mean - 7.5).abs() < 0.05, "mean {mean}");
        assert!((var - 7.5).abs() < 0.2, "variance {var}");
        // More particles never lower a count.
        let (more, _) = bulk(&[2 * n]);
        assert!(once.counts.iter().zip(&more.counts).all(|(a, b)| b >= a));
        // Far past saturation every count is full.
        let (full, _) = bulk(&[u64::MAX / 2]);
        assert!(full.counts.iter().all(|&c| c == u16::MAX));
    }

    #[test]
    fn the_guide_finds_what_a_binary_search_finds() {
        use rand::SeedableRng as _;
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(3);
        for lambda in [0.0, 0.3, 2.0, 17.0, 85.4, 1000.0, 1e6] {
            let p = Inverse::new(lambda);
            let mut us: Vec<f64> = (0..20_000).map(|_| rng.random::<f64>()).collect();
            // The table's own values, either side of them, and the ends.
            for &c in &p.cdf {
                us.extend([c, c.next_down(), c.next_up()]);
            }
            us.extend([0.0, 1.0f64.next_down()]);
            for u in us.into_iter().filter(|u| (0.0..1.0).contains(u)) {
                assert_eq!(
                    p.find(u),
                    p.cdf.partition_point(|&c| c <= u),
                    "{lambda} {u}"
                );
            }
        }
    }

    #[test]
    fn inverse_poisson_matches_its_probabilities() {
        // P(X = 0) = e^-2, P(X <= 1) = 3 e^-2 for lambda = 2.
        let p = Inverse::new(2.0);
        let e = (-2.0f64).exp();
        assert_eq!(p.count(e * 0.999), 0);
        assert_eq!(p.count(e * 1.001), 1);
        assert_eq!(p.count(3.0 * e * 1.001), 2);
        assert_eq!(Inverse::new(0.0).count(0.999), 0);
        assert_eq!(Inverse::new(1e6).count(0.5), u16::MAX, "saturated");
        let mid = Inverse::new(10_000.0);
        assert!((mid.count(0.5) as i64 - 10_000).abs() <= 1);
        assert!(
            (mid.count(0.841_344_7) as i64 - 10_100).abs() <= 2,
            "one sigma"
        );
    }
}
