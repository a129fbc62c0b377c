//! Growth and deposits bound to the wall's surface: a layer's colour is
//! modulated by the photo's own luminance, so the wall's texture, joints
//! and light show through the moss instead of disappearing under a flat
//! colour (issue "looks like a photograph"). The dust film needs none of
//! this: it multiplies the wall (`stages::dust`).
//!
//! [choice] A pixel's colour becomes `c * L / L_wall` (at most 1.4 c), with L the photo's
//! luminance there and L_wall the wall's mean luminance: the layer stays a
//! normal-blended RGBA layer that any editor shows as it is, and what it
//! paints carries the light and relief of the wall under it (a colony in a
//! joint's shadow is darker; a sunlit one lighter). Moss takes the light's
//! colour as well, and its relief after its softening ([`light`]).

pub mod light;

use image::{GrayImage, ImageBuffer, Rgba, RgbaImage};
use rayon::prelude::*;

use crate::field::RowMajor;
use crate::photo::Photo;

/// Most a pixel's colour is lightened: bright highlights do not bleach it
/// [choice: a part of the wall much brighter than its mean is more often a
/// lighter material (white trim, a stone sill) than stronger light, and a
/// lichen there keeps its own colour; lightened 1.4x it read as lime paint
/// along every ledge in the blind review].
const MAX_GAIN: f32 = 1.15;

/// Mean luminance over the wall cells of the grid (128 when there are none).
pub fn wall_luma(luma: &RowMajor<f32>, region: &RowMajor<bool>) -> f32 {
    wall_mean(luma, region).map_or(128.0, |m| m.max(1.0))
}

/// Mean of `values` over the wall cells of the grid, if there are any.
pub fn wall_mean(values: &RowMajor<f32>, region: &RowMajor<bool>) -> Option<f32> {
    let (sum, n) = values
        .data()
        .iter()
        .zip(region.data())
        .filter(|(_, r)| **r)
        .fold((0.0f64, 0u64), |(s, n), (l, _)| (s + *l as f64, n + 1));
    (n > 0).then(|| (sum / n as f64) as f32)
}

/// Multiplies each painted pixel of `layer` (alpha > 0) by the photo's
/// luminance over `l_wall`.
pub fn modulate(layer: &mut RgbaImage, photo: &Photo, l_wall: f32) {
    each_painted(layer, photo, |_, _, px, l| {
        let gain = (l / l_wall).min(MAX_GAIN);
        for c in &mut px[..3] {
            *c = crate::round::to_u8(*c as f32 * gain);
        }
    });
}

/// Calls `f(x, y, pixel, luma)` on each painted pixel of `layer` (alpha >
/// 0) with the photo's luminance there, rows in parallel (rows with
/// nothing painted are skipped).
pub fn each_painted(
    layer: &mut RgbaImage,
    photo: &Photo,
    f: impl Fn(usize, usize, &mut [u8], f32) + Sync,
) {
    let w = layer.width() as usize;
    layer.par_chunks_mut(w * 4).enumerate().for_each_init(
        || vec![0.0f32; w],
        |line, (y, row)| {
            if row.chunks_exact(4).all(|px| px[3] == 0) {
                return;
            }
            photo.luma_row(y as u32, line);
            for (x, (px, l)) in row.chunks_exact_mut(4).zip(line.iter()).enumerate() {
                if px[3] != 0 {
                    f(x, y, px, *l);
                }
            }
        },
    );
}

/// Blurs a straight-alpha layer by a Gaussian of `sigma` pixels, with
/// colour weighted by alpha (premultiplied, so no colour bleeds in from
/// transparent pixels), then keeps it inside `mask` (the region's weights).
pub fn soften(layer: &mut RgbaImage, sigma: f32, mask: Option<&GrayImage>) {
    if sigma <= 0.0 {
        return;
    }
    let pre: ImageBuffer<Rgba<f32>, Vec<f32>> =
        ImageBuffer::from_fn(layer.width(), layer.height(), |x, y| {
            let [r, g, b, a] = layer.get_pixel(x, y).0.map(f32::from);
            let k = a / 255.0;
            Rgba([r * k, g * k, b * k, a])
        });
    let blurred = imageproc::filter::gaussian_blur_f32(&pre, sigma);
    let w = layer.width() as usize;
    layer
        .par_chunks_mut(w * 4)
        .zip(blurred.par_chunks(w * 4))
        .enumerate()
        .for_each(|(y, (row, src))| {
            for (x, (px, s)) in row.chunks_exact_mut(4).zip(src.chunks_exact(4)).enumerate() {
                let weight =
                    mask.map_or(1.0, |m| m.get_pixel(x as u32, y as u32)[0] as f32 / 255.0);
                let a = s[3] * weight;
                if a < 0.5 {
                    px.copy_from_slice(&[0; 4]);
                    continue;
                }
                let k = 255.0 / s[3];
                for c in 0..3 {
                    px[c] = (s[c] * k).round().clamp(0.0, 255.0) as u8;
                }
                px[3] = a.round().min(255.0) as u8;
            }
        });
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::{DynamicImage, GrayImage, Luma};

    #[test]
    fn the_wall_shows_through_and_bare_pixels_stay_bare() {
        let photo = Photo::new(DynamicImage::ImageLuma8(GrayImage::from_fn(
            4,
            1,
            |x, _| Luma([[50, 100, 200, 100][x as usize]]),
        )));
        let mut layer = RgbaImage::from_fn(4, 1, |x, _| {
            image::Rgba([100, 100, 100, if x == 3 { 0 } else { 255 }])
        });
        modulate(&mut layer, &photo, 100.0);
        let r: Vec<u8> = layer.pixels().map(|p| p[0]).collect();
        assert_eq!(
            r,
            [50, 100, 115, 100],
            "darker, same, capped lighter, untouched"
        );
    }

    #[test]
    fn a_softened_speck_spreads_keeps_its_colour_and_stays_in_the_mask() {
        // One green pixel on a transparent layer; the right half is off
        // the wall.
        let mut layer = RgbaImage::new(9, 9);
        layer.put_pixel(4, 4, image::Rgba([40, 160, 60, 255]));
        let mask = GrayImage::from_fn(9, 9, |x, _| Luma([if x < 5 { 255 } else { 0 }]));
        let mass = |l: &RgbaImage| l.pixels().map(|p| p[3] as u32).sum::<u32>();
        let before = mass(&layer);
        soften(&mut layer, 0.8, Some(&mask));
        let centre = layer.get_pixel(4, 4);
        assert!(centre[3] < 255 && layer.get_pixel(3, 4)[3] > 0, "spread");
        assert_eq!(&centre.0[..3], &[40, 160, 60], "no colour bleeds in");
        assert!(
            layer
                .pixels()
                .enumerate()
                .all(|(i, p)| i % 9 < 5 || p[3] == 0)
        );
        // About half its coverage fell off the wall.
        let kept = mass(&layer) as f32 / before as f32;
        assert!((0.5..0.85).contains(&kept), "{kept}");
    }
}
