//! Seeded random streams and smooth noise.
//!
//! Every random process draws from its own stream, derived from
//! (master seed, effect, layer, index) by SplitMix64 mixing. Nothing depends
//! on thread scheduling, so output is byte-identical at any thread count.

use rand::SeedableRng;
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

/// A 64-bit key for (seed, stream, layer, index).
pub fn key(seed: u64, stream: Stream, layer: u64, index: u64) -> u64 {
    mix(mix(mix(mix(seed) ^ stream as u64) ^ layer) ^ index)
}

/// An independent generator for (seed, stream, layer, index).
pub fn rng(seed: u64, stream: Stream, layer: u64, index: u64) -> Rng {
    Rng::seed_from_u64(key(seed, stream, layer, index))
}

/// A uniform value in [0, 1) from a hash (for lattice noise).
fn unit(h: u64) -> f32 {
    (h >> 40) as f32 / (1u64 << 24) as f32
}

/// Smooth fractal value noise (fBm, 4 octaves) in [0, 1].
///
/// `scale` is the feature size of the coarsest octave in pixels.
/// ```
/// let n = grime::random::fbm(7, 10.0, 3.0, 16.0);
/// assert!((0.0..=1.0).contains(&n));
/// ```
pub fn fbm(seed: u64, x: f32, y: f32, scale: f32) -> f32 {
    let mut sum = 0.0;
    let mut amp = 0.5;
    let mut norm = 0.0;
    let mut f = 1.0 / scale.max(1e-3);
    for octave in 0..4u64 {
        sum += amp * value_noise(mix(seed ^ octave), x * f, y * f);
        norm += amp;
        amp *= 0.5;
        f *= 2.0;
    }
    (sum / norm).clamp(0.0, 1.0)
}

/// Smooth value noise (2 octaves) in [0, 1]: large features only, for
/// fields that diffuse, where fine octaves would turn into speckle.
pub fn smooth_noise(seed: u64, x: f32, y: f32, scale: f32) -> f32 {
    let f = 1.0 / scale.max(1e-3);
    let a = value_noise(mix(seed), x * f, y * f);
    let b = value_noise(mix(seed ^ 1), x * f * 2.0, y * f * 2.0);
    (a * 2.0 + b) / 3.0
}

fn value_noise(seed: u64, x: f32, y: f32) -> f32 {
    let (xf, yf) = (x.floor(), y.floor());
    let (ix, iy) = (xf as i64, yf as i64);
    let (tx, ty) = (smooth(x - xf), smooth(y - yf));
    let corner = |dx: i64, dy: i64| {
        unit(mix(seed ^ mix((ix + dx) as u64 ^ mix((iy + dy) as u64))))
    };
    let top = corner(0, 0) + (corner(1, 0) - corner(0, 0)) * tx;
    let bottom = corner(0, 1) + (corner(1, 1) - corner(0, 1)) * tx;
    top + (bottom - top) * ty
}

fn smooth(t: f32) -> f32 {
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
        let a: u64 = rng(1, Stream::Droplet, 2, 3).random();
        let b: u64 = rng(1, Stream::Droplet, 2, 3).random();
        assert_eq!(a, b);
    }

    #[test]
    fn fbm_is_smooth_and_in_range() {
        let mut max_step: f32 = 0.0;
        for i in 0..1000 {
            let x = i as f32 * 0.5;
            let a = fbm(9, x, 3.0, 32.0);
            let b = fbm(9, x + 0.5, 3.0, 32.0);
            assert!((0.0..=1.0).contains(&a));
            max_step = max_step.max((a - b).abs());
        }
        assert!(max_step < 0.2, "noise jumps by {max_step} in half a pixel");
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
