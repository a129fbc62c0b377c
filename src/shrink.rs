//! Images at an animation's frame size: each output pixel is the mean of
//! the pixels it covers (area averaging, parts of pixels counted by their
//! share), output rows in parallel. The photo, its masks and maps are
//! shrunk so for a preview scene ([`crate::pipeline::Scene::scaled`]).

use image::{DynamicImage, ImageBuffer, Pixel, RgbaImage};
use rayon::prelude::*;

/// `img` as RGBA with its longest side at most `max_side` (0 = as is).
pub fn shrink(img: &DynamicImage, max_side: u32) -> RgbaImage {
    let (w, h) = (img.width(), img.height());
    if max_side == 0 || w.max(h) <= max_side {
        return img.to_rgba8();
    }
    let (ow, oh) = fit(w, h, max_side);
    match to_size(img, ow, oh) {
        DynamicImage::ImageRgba8(rgba) => rgba,
        other => other.to_rgba8(),
    }
}

/// `img` at `ow` x `oh`, as 8-bit RGB or, with an alpha channel, RGBA.
pub fn to_size(img: &DynamicImage, ow: u32, oh: u32) -> DynamicImage {
    match img {
        DynamicImage::ImageRgb8(rgb) => DynamicImage::ImageRgb8(buffer_to_size(rgb, ow, oh)),
        DynamicImage::ImageRgba8(rgba) => DynamicImage::ImageRgba8(buffer_to_size(rgba, ow, oh)),
        other if other.color().has_alpha() => {
            DynamicImage::ImageRgba8(buffer_to_size(&other.to_rgba8(), ow, oh))
        }
        other => DynamicImage::ImageRgb8(buffer_to_size(&other.to_rgb8(), ow, oh)),
    }
}

/// An 8-bit image buffer (grey, RGB, RGBA) at `ow` x `oh`.
pub fn buffer_to_size<P: Pixel<Subpixel = u8>>(
    img: &ImageBuffer<P, Vec<u8>>,
    ow: u32,
    oh: u32,
) -> ImageBuffer<P, Vec<u8>> {
    let mut out = ImageBuffer::new(ow, oh);
    let channels = P::CHANNEL_COUNT as usize;
    area_mean(
        img.as_raw(),
        channels,
        img.dimensions(),
        &mut out,
        ow as usize,
    );
    out
}

/// The size of a `w` x `h` image with its longest side `max_side`, the
/// other rounded (at least 1).
pub fn fit(w: u32, h: u32, max_side: u32) -> (u32, u32) {
    let scale =
        |a: u32, b: u32| ((a as u64 * max_side as u64 + b as u64 / 2) / b as u64).max(1) as u32;
    match w >= h {
        true => (max_side, scale(h, w)),
        false => (scale(w, h), max_side),
    }
}

/// For each of `out` pixels along an axis of `len`: its first source pixel
/// and the share of it each source pixel from there covers.
fn weights(len: u32, out: u32) -> Vec<(usize, Vec<f32>)> {
    let step = len as f64 / out as f64;
    (0..out)
        .map(|o| {
            let (a, b) = (o as f64 * step, (o + 1) as f64 * step);
            let first = a.floor() as usize;
            let last = (b.ceil() as usize).min(len as usize);
            let w = (first..last)
                .map(|i| ((b.min(i as f64 + 1.0) - a.max(i as f64)) / step) as f32)
                .collect();
            (first, w)
        })
        .collect()
}

/// Area-averages `src` (`channels` per pixel, `w` x `h`) into `out`, rows
/// of `ow` pixels.
fn area_mean(src: &[u8], channels: usize, (w, h): (u32, u32), out: &mut [u8], ow: usize) {
    let oh = out.len() / (ow * channels).max(1);
    let (cols, rows) = (weights(w, ow as u32), weights(h, oh as u32));
    let row_len = w as usize * channels;
    out.par_chunks_exact_mut(ow * channels)
        .zip(rows.par_iter())
        .for_each(|(line, (first, wy))| {
            let mut sum = vec![0.0f32; row_len];
            for (k, wy) in wy.iter().enumerate() {
                let row = &src[(first + k) * row_len..(first + k + 1) * row_len];
                for (s, v) in sum.iter_mut().zip(row) {
                    *s += *v as f32 * wy;
                }
            }
            for (px, (x0, wx)) in line.chunks_exact_mut(channels).zip(&cols) {
                let mut acc = [0.0f32; 4];
                for (k, wx) in wx.iter().enumerate() {
                    let at = (x0 + k) * channels;
                    for (c, a) in acc.iter_mut().enumerate().take(channels) {
                        *a += sum[at + c] * wx;
                    }
                }
                for (o, a) in px.iter_mut().zip(acc) {
                    *o = (a + 0.5).clamp(0.0, 255.0) as u8;
                }
            }
        });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_pixel_is_the_mean_of_what_it_covers() {
        // 4 x 2 to 2 x 1: each output pixel averages a 2 x 2 block.
        let img = image::RgbImage::from_raw(
            4,
            2,
            vec![
                0, 0, 0, 100, 100, 100, 10, 20, 30, 10, 20, 30, //
                0, 0, 0, 100, 100, 100, 30, 40, 50, 30, 40, 50,
            ],
        )
        .unwrap();
        let out = shrink(&DynamicImage::ImageRgb8(img), 2);
        assert_eq!(out.dimensions(), (2, 1));
        assert_eq!(out.as_raw(), &[50, 50, 50, 255, 20, 30, 40, 255]);
        // 4 to 3: the first output pixel covers source pixel 0 and a third
        // of pixel 1, which count by their share of its 4/3.
        let w = weights(4, 3);
        assert_eq!(w[0].0, 0);
        assert!((w[0].1[0] - 0.75).abs() < 1e-6 && (w[0].1[1] - 0.25).abs() < 1e-6);
        assert_eq!(w[2].0, 2);
        assert_eq!(fit(4000, 3000, 1024), (1024, 768));
        assert_eq!(fit(10, 3000, 1024), (3, 1024));
        let flat =
            DynamicImage::ImageRgba8(RgbaImage::from_pixel(37, 23, image::Rgba([9, 99, 199, 42])));
        assert!(shrink(&flat, 10).pixels().all(|p| p.0 == [9, 99, 199, 42]));
    }
}
