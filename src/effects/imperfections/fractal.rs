//! 2D fBm by midpoint subdivision (diamond-square), the fractal Becket &
//! Badler build splotches, stains and smudges from: random values on a
//! coarse lattice `size` apart, then each level halves the spacing and
//! adds midpoints displaced by `roughness` times the level above's amount.

use crate::random::{StreamId, key};

/// Longest side of the subdivision lattice, in cells.
const MAX_CELLS: usize = 2048;

/// A fractal over a photo, normalised to 0..1.
#[derive(Debug, Clone)]
pub struct Fractal {
    side: usize,
    /// Photo pixels per lattice cell.
    cell: f32,
    values: Vec<f32>,
}

impl Fractal {
    /// A fractal over a `w` x `h` photo whose coarsest features are `size`
    /// pixels apart; `roughness` is the displacement ratio per level.
    pub fn new(
        seed: u64,
        stream: impl StreamId,
        w: usize,
        h: usize,
        size: f32,
        roughness: f32,
    ) -> Fractal {
        let longest = w.max(h).max(2) as f32;
        let mut n = 1;
        while (1usize << n) < MAX_CELLS && ((1usize << n) as f32) < longest {
            n += 1;
        }
        let cells = 1usize << n;
        let cell = (longest / cells as f32).max(1.0 / 1024.0);
        let mut m = 0;
        while m < n && ((1usize << (m + 1)) as f32) * cell <= size {
            m += 1;
        }
        let side = cells + 1;
        let mut v = vec![0.0f32; side * side];
        let rand = |i: usize, level: u64| -> f32 {
            let k = key(seed, stream, level, i as u64);
            (k >> 40) as f32 / (1u64 << 24) as f32 - 0.5
        };
        let mut step = 1usize << m.max(1);
        for y in (0..side).step_by(step) {
            for x in (0..side).step_by(step) {
                v[y * side + x] = rand(y * side + x, 0) * 2.0;
            }
        }
        let mut amp = roughness;
        let mut level = 1;
        while step > 1 {
            let half = step / 2;
            // Diamond: centres of squares.
            for y in (half..side).step_by(step) {
                for x in (half..side).step_by(step) {
                    let at = |dx: isize, dy: isize| {
                        v[(y as isize + dy) as usize * side + (x as isize + dx) as usize]
                    };
                    let h = half as isize;
                    let mean = (at(-h, -h) + at(h, -h) + at(-h, h) + at(h, h)) / 4.0;
                    v[y * side + x] = mean + amp * rand(y * side + x, level);
                }
            }
            // Square: edge midpoints.
            for y in (0..side).step_by(half) {
                let start = if (y / half).is_multiple_of(2) {
                    half
                } else {
                    0
                };
                for x in (start..side).step_by(step) {
                    let mut sum = 0.0;
                    let mut k = 0.0;
                    for (dx, dy) in [(-1, 0), (1, 0), (0, -1), (0, 1)] {
                        let (xx, yy) = (
                            x as isize + dx * half as isize,
                            y as isize + dy * half as isize,
                        );
                        if xx >= 0 && yy >= 0 && (xx as usize) < side && (yy as usize) < side {
                            sum += v[yy as usize * side + xx as usize];
                            k += 1.0;
                        }
                    }
                    v[y * side + x] = sum / k + amp * rand(y * side + x, level);
                }
            }
            step = half;
            amp *= roughness;
            level += 1;
        }
        let (lo, hi) = v
            .iter()
            .fold((f32::MAX, f32::MIN), |(a, b), &x| (a.min(x), b.max(x)));
        let span = (hi - lo).max(1e-9);
        v.iter_mut().for_each(|x| *x = (*x - lo) / span);
        Fractal {
            side,
            cell,
            values: v,
        }
    }

    /// The value at photo point (x, y), bilinear.
    pub fn at(&self, x: f32, y: f32) -> f32 {
        let max = (self.side - 1) as f32;
        let gx = (x / self.cell).clamp(0.0, max - 1e-3);
        let gy = (y / self.cell).clamp(0.0, max - 1e-3);
        let (ix, iy) = (gx as usize, gy as usize);
        let (tx, ty) = (gx - ix as f32, gy - iy as f32);
        let v = &self.values;
        let i = iy * self.side + ix;
        let top = v[i] + (v[i + 1] - v[i]) * tx;
        let bottom = v[i + self.side] + (v[i + self.side + 1] - v[i + self.side]) * tx;
        top + (bottom - top) * ty
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::Effect;

    #[test]
    fn values_span_zero_to_one_and_repeat_with_the_seed() {
        let a = Fractal::new(3, (Effect::Gammaton, 9), 300, 200, 40.0, 0.5);
        let b = Fractal::new(3, (Effect::Gammaton, 9), 300, 200, 40.0, 0.5);
        let vals: Vec<f32> = (0..200).map(|i| a.at(i as f32 * 1.5, i as f32)).collect();
        assert!(vals.iter().all(|v| (0.0..=1.0).contains(v)));
        assert_eq!(a.at(17.3, 99.1), b.at(17.3, 99.1));
        // Rougher fractals vary more between neighbouring pixels.
        let r = Fractal::new(3, (Effect::Gammaton, 9), 300, 200, 40.0, 0.9);
        let jump = |f: &Fractal| -> f32 {
            (0..299)
                .map(|x| (f.at(x as f32 + 1.0, 50.0) - f.at(x as f32, 50.0)).abs())
                .sum()
        };
        assert!(jump(&r) > jump(&a));
    }
}
