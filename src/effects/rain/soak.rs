//! Where a deposit shows: thin dirt soaks into the wall's recesses first,
//! only thick dirt covers its face.
//!
//! [choice, beyond Chang, whose stain is one coverage for every pixel:]
//! the blind critics' longest-standing tell is "airbrushed grime that dims
//! whatever is underneath evenly instead of soaking into pores, mortar
//! joints and paint" (`docs/blind-review.md`). Run-off dirt is carried in
//! a water film; where the film thins and dries it is held first in the
//! pores, the joints and the shadowed laps, which stay wet longest and
//! hold the most water (`how-facades-age.md`: "dirt collects in joints and
//! recesses"; `rain-and-moss.md`: the film dries from its edges), and only
//! a thick deposit reaches across the proud, lit face.
//!
//! So each pixel has a soaking exponent `g` from the photo
//! ([`Soak::new`]): how much darker it is than its neighbourhood at two
//! scales ([`FINE_M`]: pores and joints; [`RELIEF_M`]: laps and shadowed
//! relief), in units of that relative darkness's own spread around it
//! ([`SPREAD_M`], never below [`FLOOR`], so smooth render is not read for
//! grain it does not have), plus a seeded pore noise ([`PORE`], in
//! metres). The rain layers' coverage so far, `E` (as they composite:
//! `1 - prod(1 - o a_j)` for opacity `o` = [`OPACITY`]), measured against a full film
//! `F = 1 - (1 - o)^L` ([`super::stain::FILM_LAYERS`] = L), shows as `E' =
//! F (E / F)^g`: a recess (`g < 1`) darkens early, a face (`g > 1`) late,
//! and at a full film every pixel shows all of it. Each layer gets the
//! increment that takes the stack from one `E'` to the next, `a'_k = (1 -
//! (1 - E'_k) / (1 - E'_{k-1})) / o` ([`Soak::lay`]), so the layers still
//! composite to the aged image, more rain never lightens a pixel (the
//! transfer is monotone in `E`), layer k depends only on the rainfalls up
//! to it (a time-lapse's frames stay prefixes), and outside the region's
//! mask the alpha stays 0.

use image::GrayImage;
use rayon::prelude::*;

use super::deposit::box_blur;
use super::stain::FILM_LAYERS;
use crate::effects::{Context, Effect};
use crate::random::{Noise, key};

/// The fine window a pixel's darkness is measured against, metres (half
/// its side), at least [`FINE_MIN_PX`] [choice: 3 cm, a brick's height
/// and its joint, a lap of siding, a few pores; the window of the former
/// linear `deposit::catch`].
pub const FINE_M: f32 = 0.03;

/// The coarse window, metres (half its side), at least twice the fine one
/// [choice: 0.1 m: the shadowed relief, a course's lap, a panel's edge].
pub const RELIEF_M: f32 = 0.1;

/// The window the relative darkness's spread is measured over, metres
/// (half its side) [choice: 0.3 m, as `deposit::LOCAL_M`: the same wall
/// material, so a brick band and the render beside it each soak by their
/// own grain].
pub const SPREAD_M: f32 = 0.3;

/// The least spread of relative darkness a wall's grain is read against
/// [choice: 0.05: the sensor noise and JPEG blocks of a smooth render
/// stay below it, so their specks do not become soak patterns; brick's
/// joints and stone's pores are well above it].
pub const FLOOR: f32 = 0.05;

/// The largest soak score either way, in units of the spread [choice: 2,
/// so the deepest joint's exponent stays above `exp(-2 SOAK)` and no
/// single dark pixel turns black at the first rainfall].
const Z_MAX: f32 = 2.0;

/// The exponent per unit of soak score: `g = exp(-SOAK z)` [choice: 0.7:
/// a joint two spreads darker takes `g` = 0.25 and a face half a spread
/// lighter 1.4, so at a tenth of a film the joint shows 0.56 of it and
/// the face 0.04; 0.45 left main's smooth, even veil on render (see
/// `BENCHMARKS.md`)].
pub const SOAK: f32 = 0.7;

/// The pore noise's standard deviation, in units of the soak score
/// [choice: 0.2: on smooth render (no grain above [`FLOOR`]) a thin
/// stain's edge still dries a little unevenly, in spots of [`PORE_M`]; at
/// 0.5 the streaks on render (IMG_8498, img_2049) broke into leopard
/// spots].
pub const PORE: f32 = 0.2;

/// The pore noise's feature size, metres, at least [`PORE_MIN_PX`]
/// [choice: 4 cm, the blotches a drying film leaves on render. It was 2
/// cm, which [`PORE_MIN_PX`] raised to 3 pixels on every photo coarser
/// than 7 mm a pixel (4-9 cm at the usual 0.013-0.03 m a pixel, the look
/// the critics judged), so a finer photo got finer blotches in metres and
/// its streaks read narrower (ink over peak, the blotches raise a row's
/// peak; `BENCHMARKS.md`, thirty-sixth pass); at 4 cm the size is the
/// same in metres on every photo finer than 1.3 cm a pixel, and unchanged
/// on the coarser ones].
pub const PORE_M: f32 = 0.04;

/// The smallest fine window, photo pixels.
const FINE_MIN_PX: f32 = 2.0;

/// The smallest pore, photo pixels (finer noise is speckle).
const PORE_MIN_PX: f32 = 3.0;

/// The standard deviation of two-octave value noise about its mean 0.5
/// (`texture.rs`).
const SPREAD: f32 = 0.16;

/// The pore noise's stream.
const PORES: u16 = 13;

/// The layer opacity the transfer is worked out for [choice: the default
/// `stain.opacity`, a constant: a layer's alpha must not depend on its
/// opacity, so restyling the stain keeps a run (as [`super::stain::Film`]);
/// at the default the layers stack exactly to `E'`, at another opacity
/// they follow it closely (the same alphas, each weighed by it)].
pub const OPACITY: f32 = 0.25;

/// The soak of one run's rain layers at photo resolution.
#[derive(Debug)]
pub struct Soak {
    /// The soaking exponent per pixel.
    gamma: Vec<f32>,
    /// `1 - E`: the share the layers' own coverage left bare so far.
    raw: Vec<f32>,
    /// `1 - E'` as the layers given so far composite (rounded as they are).
    shown: Vec<f32>,
    width: usize,
    /// [`OPACITY`].
    opacity: f32,
    /// A full film's coverage, `1 - (1 - o)^L`.
    full: f32,
}

impl Soak {
    /// The soak on `ctx`'s photo, its pore noise from `seed`.
    pub fn new(ctx: &Context, seed: u64) -> Soak {
        let (w, h) = ctx.size();
        let mut luma = vec![0.0f32; w as usize * h as usize];
        luma.par_chunks_mut((w as usize).max(1))
            .enumerate()
            .for_each(|(y, row)| ctx.photo.luma_row(y as u32, row));
        let px = |m: f32, min: f32| ctx.photo_px(m).max(min);
        let windows = Windows {
            fine: px(FINE_M, FINE_MIN_PX),
            relief: px(RELIEF_M, 2.0 * FINE_MIN_PX),
            spread: px(SPREAD_M, 4.0 * FINE_MIN_PX),
            pore: px(PORE_M, PORE_MIN_PX),
        };
        Soak::from_luma(&luma, w as usize, h as usize, &windows, seed)
    }

    /// The soak of a `width` x `height` luma (0..255, row-major).
    fn from_luma(luma: &[f32], width: usize, height: usize, windows: &Windows, seed: u64) -> Soak {
        let score = score(luma, width, height, windows);
        let pores = Noise::new(
            key(seed, (Effect::Rain, PORES), 0, 0),
            width as u32 + 1,
            height as u32 + 1,
            windows.pore,
            2,
        );
        let lines = pores.lines(width, PORE / SPREAD);
        let mut gamma = score;
        gamma
            .par_chunks_mut(width.max(1))
            .enumerate()
            .for_each_init(Vec::new, |noise, (y, row)| {
                noise.resize(width, 0.0);
                lines.line(y, noise);
                for (g, n) in row.iter_mut().zip(noise.iter()) {
                    // The noise's mean is half its amplitude.
                    let z = *g + n - 0.5 * PORE / SPREAD;
                    *g = (-SOAK * z).exp();
                }
            });
        let o = OPACITY;
        Soak {
            gamma,
            raw: vec![1.0; width * height],
            shown: vec![1.0; width * height],
            width,
            opacity: o,
            full: 1.0 - (1.0 - o).powf(FILM_LAYERS),
        }
    }

    /// Turns the next rain layer's alpha (`alpha`, photo-sized, before the
    /// region's mask) into the alpha that shows its soak, then weighs it
    /// by `mask` (255 = all of it; 0 outside the region).
    pub fn lay(&mut self, alpha: &mut GrayImage, mask: Option<&GrayImage>) {
        let (o, full, w) = (self.opacity, self.full, self.width.max(1));
        alpha
            .par_chunks_mut(w)
            .zip(self.raw.par_chunks_mut(w))
            .zip(self.shown.par_chunks_mut(w))
            .zip(self.gamma.par_chunks(w))
            .enumerate()
            .for_each(|(y, (((row, raw), shown), gamma))| {
                let mask = mask.map(|m| &m.as_raw()[y * w..(y + 1) * w]);
                for x in 0..row.len() {
                    raw[x] *= 1.0 - o * f32::from(row[x]) / 255.0;
                    if raw[x] >= 1.0 {
                        row[x] = 0;
                        continue;
                    }
                    let e = 1.0 - raw[x];
                    let shows = match e < full {
                        true => full * (e / full).powf(gamma[x]),
                        false => e,
                    };
                    let want = (1.0 - (1.0 - shows) / shown[x].max(1e-6)) / o;
                    let q = (want.clamp(0.0, 1.0) * 255.0).round();
                    shown[x] *= 1.0 - o * q / 255.0;
                    let weight = mask.map_or(255.0, |m| f32::from(m[x]));
                    row[x] = (q * weight / 255.0).round() as u8;
                }
            });
    }
}

/// The windows of [`score`], photo pixels (half a side).
#[derive(Debug, Clone, Copy)]
struct Windows {
    fine: f32,
    relief: f32,
    spread: f32,
    pore: f32,
}

/// Per pixel, how much darker than its neighbourhood it is (the mean of
/// its relative darkness against the fine and the relief window, after a
/// 3 x 3 mean so single noisy pixels do not count), over that darkness's
/// spread within the spread window (at least [`FLOOR`]), within
/// ±[`Z_MAX`].
fn score(luma: &[f32], width: usize, height: usize, windows: &Windows) -> Vec<f32> {
    let r = |px: f32| px.round().max(1.0) as usize;
    let own = box_blur(luma, width, height, 1);
    let fine = box_blur(luma, width, height, r(windows.fine));
    let relief = box_blur(luma, width, height, r(windows.relief));
    let dark: Vec<f32> = own
        .par_iter()
        .zip(&fine)
        .zip(&relief)
        .map(|((l, f), c)| 0.5 * ((f - l) / f.max(1.0) + (c - l) / c.max(1.0)))
        .collect();
    let squares: Vec<f32> = dark.par_iter().map(|d| d * d).collect();
    let spread = box_blur(&squares, width, height, r(windows.spread));
    dark.par_iter()
        .zip(&spread)
        .map(|(d, s)| (d / s.sqrt().max(FLOOR)).clamp(-Z_MAX, Z_MAX))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brick 6 px courses with 1 px dark joints, 8 x 8 px windows.
    fn bricks(width: usize, height: usize) -> (Vec<f32>, Vec<bool>) {
        let joint: Vec<bool> = (0..width * height)
            .map(|i| {
                let (x, y) = (i % width, i / width);
                let offset = if (y / 7).is_multiple_of(2) { 0 } else { 10 };
                y % 7 == 6 || (x + offset) % 21 == 20
            })
            .collect();
        let luma = joint
            .iter()
            .map(|j| if *j { 90.0 } else { 150.0 })
            .collect();
        (luma, joint)
    }

    fn windows() -> Windows {
        Windows {
            fine: 3.0,
            relief: 10.0,
            spread: 30.0,
            pore: 3.0,
        }
    }

    /// The mean shown coverage on joints and on faces after `layers`
    /// layers of alpha `a` everywhere.
    fn shown(layers: usize, a: u8) -> (f32, f32) {
        let (w, h) = (84, 70);
        let (luma, joint) = bricks(w, h);
        let mut soak = Soak::from_luma(&luma, w, h, &windows(), 7);
        for _ in 0..layers {
            let mut alpha = GrayImage::from_pixel(w as u32, h as u32, image::Luma([a]));
            soak.lay(&mut alpha, None);
        }
        let mean = |on: bool| {
            let v: Vec<f32> = soak
                .shown
                .iter()
                .zip(&joint)
                .filter(|(_, j)| **j == on)
                .map(|(s, _)| 1.0 - s)
                .collect();
            v.iter().sum::<f32>() / v.len() as f32
        };
        (mean(true), mean(false))
    }

    #[test]
    fn thin_dirt_soaks_the_joints_thick_dirt_covers_the_face() {
        let (joints, faces) = shown(1, 20);
        assert!(joints > 3.0 * faces, "thin: joints {joints}, faces {faces}");
        let (joints, faces) = shown(40, 255);
        assert!(
            faces > 0.8 * joints,
            "thick: joints {joints}, faces {faces}"
        );
    }

    /// The layers composite to the coverage the soak tracks, and that is
    /// the transfer of the layers' own coverage.
    #[test]
    fn the_layers_stack_to_the_transfer_of_their_coverage() {
        let (w, h) = (84, 70);
        let (luma, _) = bricks(w, h);
        let mut soak = Soak::from_luma(&luma, w, h, &windows(), 3);
        let mut bare = vec![1.0f32; w * h];
        for k in 0..30u32 {
            let a = ((k * 37) % 60) as u8;
            let mut alpha = GrayImage::from_pixel(w as u32, h as u32, image::Luma([a]));
            soak.lay(&mut alpha, None);
            for (b, q) in bare.iter_mut().zip(alpha.as_raw()) {
                *b *= 1.0 - 0.25 * f32::from(*q) / 255.0;
            }
        }
        for (b, s) in bare.iter().zip(&soak.shown) {
            assert!((b - s).abs() < 1e-4);
        }
        let e = 1.0 - soak.raw[0];
        let want = soak.full * (e / soak.full).powf(soak.gamma[0]);
        assert!((1.0 - soak.shown[0] - want).abs() < 0.01);
    }

    /// A pixel the mask leaves out stays untouched however much rain.
    #[test]
    fn nothing_outside_the_mask() {
        let (w, h) = (84, 70);
        let (luma, _) = bricks(w, h);
        let mut soak = Soak::from_luma(&luma, w, h, &windows(), 3);
        let mask = GrayImage::from_fn(w as u32, h as u32, |x, _| image::Luma([(x * 3) as u8]));
        for _ in 0..10 {
            let mut alpha = GrayImage::from_pixel(w as u32, h as u32, image::Luma([200]));
            soak.lay(&mut alpha, Some(&mask));
            assert!(alpha.as_raw().iter().step_by(w).all(|a| *a == 0));
        }
    }
}
