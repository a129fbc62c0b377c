//! Scratches (Becket & Badler): straight lines whose length is Gaussian
//! around `length`, whose direction is Gaussian around the dominant
//! `angle`, and whose intensity is Gaussian too. They are drawn one at a
//! time until they cover `coverage` of the placement area.

use image::GrayImage;
use rand::Rng as _;

use super::placement::{AREA, Placed};
use super::{Gen, alpha_byte};
use crate::effects::Context;
use crate::preset::ScratchParams;
use crate::random::{box_muller, rng};

/// Most scratches one layer draws (bounds the time at full coverage).
const MAX_SCRATCHES: usize = 200_000;

/// One scratch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scratch {
    /// Centre, photo pixels.
    pub centre: (f32, f32),
    /// Length, photo pixels.
    pub length: f32,
    /// Direction, degrees from horizontal.
    pub angle: f32,
    /// Alpha, 0..1 (times the share of a pixel its width covers).
    pub intensity: f32,
}

/// What was drawn.
pub struct Drawn {
    /// The scratches' alpha.
    pub alpha: GrayImage,
    /// The scratches, in drawing order.
    pub scratches: Vec<Scratch>,
}

/// Draws scratches until they cover `coverage` x area pixels.
pub fn draw(ctx: &Context, p: &ScratchParams, placed: &Placed, seed: u64) -> Drawn {
    let (w, h) = (placed.width, placed.height);
    let mut alpha = vec![0u8; w * h];
    let want = (p.coverage.clamp(0.0, 1.0) as f64 * placed.area as f64).round() as u64;
    let mut covered = 0u64;
    let mut scratches = Vec::new();
    let px = |m: f32| ctx.photo_px(m);
    let half = (px(p.width) * 0.5).max(0.5);
    // A scratch thinner than a pixel covers only part of it: fainter.
    let thin = px(p.width).min(1.0);
    let mut index = 0u64;
    while covered < want && scratches.len() < MAX_SCRATCHES && placed.area > 0 {
        let mut r = rng(seed, Gen::Scratches.stream(0), 0, index);
        index += 1;
        let (x, y) = (r.random_range(0..w), r.random_range(0..h));
        if placed.weight[y * w + x] < AREA {
            continue;
        }
        let (g1, g2) = box_muller(&mut r);
        let (g3, _) = box_muller(&mut r);
        let s = Scratch {
            centre: (x as f32 + r.random::<f32>(), y as f32 + r.random::<f32>()),
            length: (p.length + p.length_spread * g1)
                .max(p.length * 0.2)
                .max(0.0)
                / ctx.site.metres_per_pixel,
            angle: p.angle + p.angle_spread * g2,
            intensity: (p.intensity + p.intensity_spread * g3).clamp(0.05, 1.0) * thin,
        };
        covered += stroke(&s, half, placed, &mut alpha);
        scratches.push(s);
    }
    Drawn {
        alpha: GrayImage::from_raw(w as u32, h as u32, alpha).unwrap_or_default(),
        scratches,
    }
}

/// Draws one scratch (max with what is there); returns the pixels it
/// newly covered.
fn stroke(s: &Scratch, half: f32, placed: &Placed, alpha: &mut [u8]) -> u64 {
    let (w, h) = (placed.width as isize, placed.height as isize);
    let (dx, dy) = (s.angle.to_radians().cos(), -s.angle.to_radians().sin());
    let steps = (s.length * 2.0).ceil().max(1.0) as usize;
    let a = alpha_byte(s.intensity);
    let reach = half.ceil() as isize;
    let mut new = 0;
    for k in 0..=steps {
        let t = k as f32 / steps as f32 - 0.5;
        let (cx, cy) = (
            s.centre.0 + dx * s.length * t,
            s.centre.1 + dy * s.length * t,
        );
        for oy in -reach..=reach {
            for ox in -reach..=reach {
                let (x, y) = (cx as isize + ox, cy as isize + oy);
                if x < 0 || y < 0 || x >= w || y >= h {
                    continue;
                }
                // Distance from the pixel centre to the line.
                let (rx, ry) = (x as f32 + 0.5 - cx, y as f32 + 0.5 - cy);
                if (rx * dy - ry * dx).abs() > half {
                    continue;
                }
                let i = (y * w + x) as usize;
                if placed.weight[i] <= 0.0 {
                    continue;
                }
                if alpha[i] == 0 {
                    new += 1;
                }
                alpha[i] = alpha[i].max(a);
            }
        }
    }
    new
}
