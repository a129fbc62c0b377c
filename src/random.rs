//! Seeded random streams and smooth noise.
//!
//! Every random process draws from its own stream, derived from
//! (master seed, effect, layer, index) by SplitMix64 mixing. Nothing depends
//! on thread scheduling, so output is byte-identical at any thread count.

use rand::SeedableRng;

use crate::effects::Effect;
use rand_pcg::Pcg64Mcg;

/// The random generator used everywhere (fast, value-stable across versions).
pub type Rng = Pcg64Mcg;

/// Effect identifiers that keep the streams of different effects apart.
#[derive(Debug, Clone, Copy)]
#[repr(u64)]
pub enum Stream {
    /// Per-rainfall draws (drying factor).
    RainLayer = 1,
    /// One droplet's start, mass and scatter.
    Droplet = 2,
    /// Fresh-grime noise lattice.
    Grime = 3,
    /// Moss colonies.
    Moss = 4,
    /// Dust film particles.
    DustFilm = 5,
    /// Dust granules.
    DustGranules = 6,
}

/// SplitMix64 finaliser: a bijective 64-bit mix.
pub fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// What names a random stream: a [`Stream`] of the first effects, or, for
/// any effect, `(Effect, n)` (its own stream number `n`), so a new effect
/// keeps its streams apart without a new [`Stream`] variant.
pub trait StreamId: Copy {
    /// The number mixed into the key.
    fn id(self) -> u64;
}

impl StreamId for Stream {
    fn id(self) -> u64 {
        self as u64
    }
}

impl StreamId for (Effect, u16) {
    /// Above every [`Stream`] value: `2^32 + effect * 2^16 + n`.
    fn id(self) -> u64 {
        (1 << 32) | ((self.0 as u64) << 16) | self.1 as u64
    }
}

/// A 64-bit key for (seed, stream, layer, index).
pub fn key(seed: u64, stream: impl StreamId, layer: u64, index: u64) -> u64 {
    mix(mix(mix(mix(seed) ^ stream.id()) ^ layer) ^ index)
}

/// An independent generator for (seed, stream, layer, index).
pub fn rng(seed: u64, stream: impl StreamId, layer: u64, index: u64) -> Rng {
    Rng::seed_from_u64(key(seed, stream, layer, index))
}

/// A uniform value in [0, 1) from a hash (for lattice noise).
fn unit(h: u64) -> f32 {
    (h >> 40) as f32 / (1u64 << 24) as f32
}

/// One octave of value noise: random values on a lattice `scale` pixels
/// apart, interpolated with smoothstep. The lattice is computed once, so a
/// sample costs a few loads and multiplies.
#[derive(Debug, Clone)]
struct Lattice {
    cols: usize,
    rows: usize,
    inv_scale: f32,
    values: Vec<f32>,
}

impl Lattice {
    fn new(seed: u64, width: u32, height: u32, scale: f32) -> Lattice {
        let scale = scale.max(0.5);
        let cols = (width as f32 / scale) as usize + 2;
        let rows = (height as f32 / scale) as usize + 2;
        let values = (0..cols * rows)
            .map(|i| unit(mix(seed ^ mix((i % cols) as u64 ^ mix((i / cols) as u64)))))
            .collect();
        Lattice {
            cols,
            rows,
            inv_scale: 1.0 / scale,
            values,
        }
    }

    /// Lattice cell and smoothstep weight along one axis.
    fn cell(&self, v: f32, cells: usize) -> (usize, f32) {
        let g = (v * self.inv_scale).clamp(0.0, (cells - 2) as f32);
        let i = g as usize;
        (i, smoothstep(g - i as f32))
    }

    fn at(&self, x: f32, y: f32) -> f32 {
        let (ix, tx) = self.cell(x, self.cols);
        let (iy, ty) = self.cell(y, self.rows);
        let v = &self.values;
        let i = iy * self.cols + ix;
        let top = v[i] + (v[i + 1] - v[i]) * tx;
        let bottom = v[i + self.cols] + (v[i + self.cols + 1] - v[i + self.cols]) * tx;
        top + (bottom - top) * ty
    }

    /// Each column's lattice cell along a row `width` pixels wide, as runs
    /// of columns in the same cell.
    fn columns(&self, width: usize) -> Columns {
        let mut runs: Vec<(usize, usize, usize)> = Vec::new();
        let mut weights = Vec::with_capacity(width);
        for x in 0..width {
            let (ix, tx) = self.cell(x as f32, self.cols);
            weights.push(tx);
            match runs.last_mut() {
                Some(run) if run.0 == ix => run.2 = x + 1,
                _ => runs.push((ix, x, x + 1)),
            }
        }
        Columns { runs, weights }
    }

    /// Adds `weight * noise` to a whole row, with the row's `columns`.
    fn add_row(&self, y: f32, columns: &Columns, weight: f32, out: &mut [f32]) {
        let (iy, ty) = self.cell(y, self.rows);
        let top = &self.values[iy * self.cols..(iy + 1) * self.cols];
        let bottom = &self.values[(iy + 1) * self.cols..(iy + 2) * self.cols];
        for &(ix, start, end) in &columns.runs {
            let (t0, t1, b0, b1) = (top[ix], top[ix + 1], bottom[ix], bottom[ix + 1]);
            for (o, &tx) in out[start..end].iter_mut().zip(&columns.weights[start..end]) {
                let t = t0 + (t1 - t0) * tx;
                let b = b0 + (b1 - b0) * tx;
                *o += weight * (t + (b - t) * ty);
            }
        }
    }
}

/// A row's columns in an octave's lattice: runs (cell, first, end) and
/// each column's smoothstep weight.
#[derive(Debug, Clone)]
struct Columns {
    runs: Vec<(usize, usize, usize)>,
    weights: Vec<f32>,
}

/// Smooth fractal value noise (fBm) over a `width` x `height` area, in [0, 1].
///
/// `scale` is the feature size of the coarsest octave in pixels; each further
/// octave halves the size and the weight.
/// ```
/// let noise = grime::random::Noise::new(7, 64, 64, 16.0, 4);
/// let n = noise.at(10.0, 3.0);
/// assert!((0.0..=1.0).contains(&n));
/// ```
#[derive(Debug, Clone)]
pub struct Noise {
    octaves: Vec<Lattice>,
}

impl Noise {
    /// Noise with `octaves` octaves (at least 1).
    pub fn new(seed: u64, width: u32, height: u32, scale: f32, octaves: u32) -> Noise {
        let octaves = (0..octaves.max(1))
            .map(|o| {
                Lattice::new(
                    mix(seed ^ o as u64),
                    width,
                    height,
                    scale / (1u32 << o) as f32,
                )
            })
            .collect();
        Noise { octaves }
    }

    /// Row-by-row access to `amplitude * noise`, `width` pixels wide: the
    /// same values as [`Noise::at`] at pixel coordinates, much faster, for
    /// passes that consume the noise as they go.
    pub fn lines(&self, width: usize, amplitude: f32) -> NoiseLines<'_> {
        let norm: f32 = (0..self.octaves.len()).map(|o| 0.5f32.powi(o as i32)).sum();
        let tables = self.octaves.iter().map(|o| o.columns(width)).collect();
        NoiseLines {
            noise: self,
            tables,
            amplitude: amplitude / norm,
        }
    }

    /// The noise value at (x, y).
    pub fn at(&self, x: f32, y: f32) -> f32 {
        let (mut sum, mut amp, mut norm) = (0.0, 1.0, 0.0);
        for o in &self.octaves {
            sum += amp * o.at(x, y);
            norm += amp;
            amp *= 0.5;
        }
        sum / norm
    }
}

/// Rows of a [`Noise`], from [`Noise::lines`].
#[derive(Debug)]
pub struct NoiseLines<'a> {
    noise: &'a Noise,
    /// Per octave, each column's lattice cell and weight.
    tables: Vec<Columns>,
    amplitude: f32,
}

impl NoiseLines<'_> {
    /// Writes row `y` into `out`.
    pub fn line(&self, y: usize, out: &mut [f32]) {
        out.fill(0.0);
        let mut amp = self.amplitude;
        for (o, cols) in self.noise.octaves.iter().zip(&self.tables) {
            o.add_row(y as f32, cols, amp, out);
            amp *= 0.5;
        }
    }
}

/// The smoothstep `3 t^2 - 2 t^3` of `t` in 0..1: 0 and 1 at the ends,
/// level at both.
pub fn smoothstep(t: f32) -> f32 {
    t * t * (3.0 - 2.0 * t)
}

/// Two independent standard normal draws by Box-Muller (Chang eqs. 16-17).
pub fn box_muller(rng: &mut Rng) -> (f32, f32) {
    use rand::Rng as _;
    let xi3: f32 = rng.random::<f32>().max(f32::MIN_POSITIVE);
    let xi4: f32 = rng.random();
    let radius = (-2.0 * xi3.ln()).sqrt();
    let angle = std::f32::consts::TAU * xi4;
    (radius * angle.sin(), radius * angle.cos())
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::Rng as _;

    #[test]
    fn streams_differ_by_each_key_part() {
        let base = key(1, Stream::Droplet, 2, 3);
        assert_ne!(base, key(2, Stream::Droplet, 2, 3));
        assert_ne!(base, key(1, Stream::Moss, 2, 3));
        assert_ne!(base, key(1, Stream::Droplet, 3, 3));
        assert_ne!(base, key(1, Stream::Droplet, 2, 4));
        assert_ne!(base, key(1, (Effect::Rain, Stream::Droplet as u16), 2, 3));
        assert_ne!(
            key(1, (Effect::Rain, 0), 2, 3),
            key(1, (Effect::Moss, 0), 2, 3)
        );
        let a: u64 = rng(1, Stream::Droplet, 2, 3).random();
        let b: u64 = rng(1, Stream::Droplet, 2, 3).random();
        assert_eq!(a, b);
    }

    #[test]
    fn noise_is_smooth_and_in_range() {
        let noise = Noise::new(9, 500, 10, 32.0, 4);
        let mut max_step: f32 = 0.0;
        for i in 0..1000 {
            let x = i as f32 * 0.5;
            let a = noise.at(x, 3.0);
            let b = noise.at(x + 0.5, 3.0);
            assert!((0.0..=1.0).contains(&a));
            max_step = max_step.max((a - b).abs());
        }
        assert!(max_step < 0.2, "noise jumps by {max_step} in half a pixel");
    }

    #[test]
    fn lines_match_at() {
        let noise = Noise::new(3, 40, 30, 8.0, 3);
        let lines = noise.lines(40, 2.0);
        let mut out = vec![0.0; 40 * 30];
        for (y, row) in out.chunks_mut(40).enumerate() {
            lines.line(y, row);
        }
        for (i, v) in out.iter().enumerate() {
            let want = 2.0 * noise.at((i % 40) as f32, (i / 40) as f32);
            assert!((v - want).abs() < 1e-5, "{v} vs {want}");
        }
    }

    #[test]
    fn box_muller_is_standard_normal() {
        let mut r = rng(5, Stream::Droplet, 0, 0);
        let n = 20_000;
        let (mut s, mut s2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let (a, b) = box_muller(&mut r);
            for v in [a as f64, b as f64] {
                s += v;
                s2 += v * v;
            }
        }
        let mean = s / (2 * n) as f64;
        let var = s2 / (2 * n) as f64 - mean * mean;
        assert!(mean.abs() < 0.03, "mean {mean}");
        assert!((var - 1.0).abs() < 0.05, "variance {var}");
    }
}
