//! The opacity film (Santos sec. 5.2, eqs. 2-5): fine particles, one pixel
//! each, in a few greys. Each pixel keeps a count per grey; the film's colour
//! is their mean and its opacity their weighted count.

use std::sync::atomic::{AtomicU16, Ordering};

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

/// Per-pixel, per-grey particle counts p_{x,y,i} (Santos fig. 6).
///
/// Counts are atomic so chunks can land particles in parallel: increments
/// commute, so the counts do not depend on scheduling. A count saturates at
/// 65535 particles of one grey in one pixel (far beyond where RO reaches 1).
#[derive(Debug)]
pub struct Film {
    width: u32,
    counts: Vec<AtomicU16>,
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
        Film { width, counts: (0..n).into_par_iter().map(|_| AtomicU16::new(0)).collect() }
    }

    /// Particles of grey `i` at (x, y).
    pub fn count(&self, x: u32, y: u32, i: usize) -> u16 {
        self.counts[self.index(x, y) + i].load(Ordering::Relaxed)
    }

    /// Total particles in the film.
    pub fn total(&self) -> u64 {
        self.counts.par_iter().map(|c| c.load(Ordering::Relaxed) as u64).sum()
    }

    fn index(&self, x: u32, y: u32) -> usize {
        (y as usize * self.width as usize + x as usize) * COLORS
    }

    /// Lands each task's particles at uniformly random wall pixels, each with
    /// a uniformly random grey (Santos sec. 5.2). Returns how many landed.
    pub(crate) fn place(&self, region: &Region, tasks: &[Task], seed: u64, progress: &Progress) -> Result<u64> {
        tasks
            .par_iter()
            .map(|t| {
                progress.check()?;
                let mut rng = random::rng(seed, Stream::DustFilm, t.day as u64, t.chunk);
                for _ in 0..t.count {
                    let (x, y) = region.sample(&mut rng);
                    let i = rng.random_range(0..COLORS);
                    let _ = self.counts[self.index(x, y) + i].fetch_update(Ordering::Relaxed, Ordering::Relaxed, |v| {
                        v.checked_add(1)
                    });
                }
                Ok(t.count)
            })
            .try_reduce(|| 0, |a, b| Ok(a + b))
    }

    /// Mean grey u and relative opacity RO of pixel (x, y); (0, 0) without
    /// particles. C_op = u RO (Santos eq. 5) is the premultiplied film colour.
    pub fn pixel(&self, x: u32, y: u32, look: &Look) -> (u8, f32) {
        let i = self.index(x, y);
        let p: [f32; COLORS] = std::array::from_fn(|k| self.counts[i + k].load(Ordering::Relaxed) as f32);
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
        (u.round().clamp(0.0, 255.0) as u8, ro)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::dust::tasks;
    use crate::preset::Segment;

    fn look() -> Look {
        Look { greys: [100.0, 150.0, 200.0], weights: [1.0, 0.8, 0.6], anp_max: 1.2 }
    }

    #[test]
    fn colour_and_opacity_follow_eqs_2_to_4() {
        let f = Film::new(2, 1);
        f.counts[0].store(1, Ordering::Relaxed); // one dark
        f.counts[2].store(1, Ordering::Relaxed); // one light
        let (u, ro) = f.pixel(0, 0, &look());
        assert_eq!(u, 150, "mean of 100 and 200");
        assert_eq!(ro, 1.0, "ANP 1.6 > ANP_max 1.2 saturates");
        f.counts[5].store(1, Ordering::Relaxed);
        let (u, ro) = f.pixel(1, 0, &look());
        assert_eq!((u, ro), (200, 0.5), "one light particle: 0.6 / 1.2");
        assert_eq!(f.pixel(0, 0, &look()).0, 150);
    }

    #[test]
    fn every_particle_is_counted_once_and_days_add_up() {
        let region = Region::new(40, 30, None).unwrap();
        let rate = [Segment::new(0, 3.0, 10.0)];
        let area = 1.0;
        let all = Film::new(40, 30);
        let placed = all.place(&region, &tasks(&rate, area, 1, 200), 9, &Progress::none()).unwrap();
        assert_eq!(placed, all.total());
        assert_eq!(placed, (area * 13.0 + area * 3.0 * 199.0).round() as u64);
        // Incremental: days 1-100, then 101-200, equal days 1-200 pixel for pixel.
        let steps = Film::new(40, 30);
        steps.place(&region, &tasks(&rate, area, 1, 100), 9, &Progress::none()).unwrap();
        let early: Vec<u16> = steps.counts.iter().map(|c| c.load(Ordering::Relaxed)).collect();
        steps.place(&region, &tasks(&rate, area, 101, 200), 9, &Progress::none()).unwrap();
        for (i, (a, b)) in all.counts.iter().zip(&steps.counts).enumerate() {
            let b = b.load(Ordering::Relaxed);
            assert_eq!(a.load(Ordering::Relaxed), b);
            assert!(b >= early[i]);
        }
    }
}
