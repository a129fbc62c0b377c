//! Wall-region masks as plain functions on a [`GrayImage`] (255 = wall):
//! rectangle and polygon fills, the colour wand, invert and fill. Each
//! edits the mask in place and returns the box of pixels it touched, so a
//! caller (the GUI's undo, its preview proxy) can follow only that part.
//!
//! ```
//! use grime::masks::{self, Mode};
//! let mut m = image::GrayImage::new(4, 4);
//! let r = masks::fill_polygon(&mut m, &[[0.0, 0.0], [4.0, 0.0], [4.0, 2.0], [0.0, 2.0]], Mode::Add);
//! assert_eq!(r.map(|r| (r.width(), r.height())), Some((4, 2)));
//! assert_eq!(m.iter().filter(|&&v| v == 255).count(), 8);
//! ```

use std::collections::VecDeque;

use image::{GrayImage, RgbImage};
use serde::{Deserialize, Serialize};

/// A box of pixels, exclusive end.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PixelRect {
    /// Left.
    pub x0: u32,
    /// Top.
    pub y0: u32,
    /// Right, exclusive.
    pub x1: u32,
    /// Bottom, exclusive.
    pub y1: u32,
}

impl PixelRect {
    /// The whole of a `w` x `h` image.
    pub fn full(w: u32, h: u32) -> PixelRect {
        PixelRect {
            x0: 0,
            y0: 0,
            x1: w,
            y1: h,
        }
    }

    /// The pixels touched by the continuous box `[x0, x1) x [y0, y1)`,
    /// clipped to a `w` x `h` image; `None` if nothing is left.
    pub fn around(x0: f32, y0: f32, x1: f32, y1: f32, w: u32, h: u32) -> Option<PixelRect> {
        let c = |v: f32, max: u32| v.clamp(0.0, max as f32) as u32;
        let r = PixelRect {
            x0: c(x0.floor(), w),
            y0: c(y0.floor(), h),
            x1: c(x1.ceil(), w),
            y1: c(y1.ceil(), h),
        };
        (r.x1 > r.x0 && r.y1 > r.y0).then_some(r)
    }

    /// Width.
    pub fn width(&self) -> u32 {
        self.x1 - self.x0
    }

    /// Height.
    pub fn height(&self) -> u32 {
        self.y1 - self.y0
    }

    /// The smallest box holding both.
    pub fn union(&self, o: &PixelRect) -> PixelRect {
        PixelRect {
            x0: self.x0.min(o.x0),
            y0: self.y0.min(o.y0),
            x1: self.x1.max(o.x1),
            y1: self.y1.max(o.y1),
        }
    }
}

/// Whether a shape adds to or subtracts from the region.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Mode {
    /// Add wall.
    Add,
    /// Remove wall.
    Subtract,
}

fn set(px: &mut u8, mode: Mode) {
    *px = match mode {
        Mode::Add => 255,
        Mode::Subtract => 0,
    };
}

/// Fills the pixels whose centres lie in the box between corners `a` and `b`.
pub fn fill_rect(mask: &mut GrayImage, a: [f32; 2], b: [f32; 2], mode: Mode) -> Option<PixelRect> {
    let (w, h) = mask.dimensions();
    let (x0, x1) = (a[0].min(b[0]), a[0].max(b[0]));
    let (y0, y1) = (a[1].min(b[1]), a[1].max(b[1]));
    // Pixels whose centre v + 0.5 lies in [lo, hi).
    let span = |lo: f32, hi: f32, max: u32| {
        let c = |v: f32| (v - 0.5).ceil().clamp(0.0, max as f32) as u32;
        (c(lo), c(hi))
    };
    let ((xa, xb), (ya, yb)) = (span(x0, x1, w), span(y0, y1, h));
    if xb <= xa || yb <= ya {
        return None;
    }
    let rect = PixelRect {
        x0: xa,
        y0: ya,
        x1: xb,
        y1: yb,
    };
    for y in rect.y0..rect.y1 {
        for x in rect.x0..rect.x1 {
            set(&mut mask.get_pixel_mut(x, y)[0], mode);
        }
    }
    Some(rect)
}

/// Fills a polygon (even-odd rule, pixel centres).
pub fn fill_polygon(mask: &mut GrayImage, pts: &[[f32; 2]], mode: Mode) -> Option<PixelRect> {
    if pts.len() < 3 {
        return None;
    }
    let (w, h) = mask.dimensions();
    let (mut x0, mut y0, mut x1, mut y1) = (f32::MAX, f32::MAX, f32::MIN, f32::MIN);
    for p in pts {
        x0 = x0.min(p[0]);
        y0 = y0.min(p[1]);
        x1 = x1.max(p[0]);
        y1 = y1.max(p[1]);
    }
    let bbox = PixelRect::around(x0, y0, x1, y1, w, h)?;
    let mut touched: Option<PixelRect> = None;
    let mut xs = Vec::new();
    for y in bbox.y0..bbox.y1 {
        let cy = y as f32 + 0.5;
        xs.clear();
        for i in 0..pts.len() {
            let (a, b) = (pts[i], pts[(i + 1) % pts.len()]);
            if (a[1] <= cy) != (b[1] <= cy) {
                xs.push(a[0] + (cy - a[1]) / (b[1] - a[1]) * (b[0] - a[0]));
            }
        }
        xs.sort_by(f32::total_cmp);
        for pair in xs.chunks_exact(2) {
            // Pixels whose centre x + 0.5 lies in [pair[0], pair[1]).
            let xa = (pair[0] - 0.5).ceil().clamp(0.0, w as f32) as u32;
            let xb = (pair[1] - 0.5).ceil().clamp(0.0, w as f32) as u32;
            for x in xa..xb {
                set(&mut mask.get_pixel_mut(x, y)[0], mode);
            }
            if xb > xa {
                let r = PixelRect {
                    x0: xa,
                    y0: y,
                    x1: xb,
                    y1: y + 1,
                };
                touched = Some(touched.map_or(r, |t| t.union(&r)));
            }
        }
    }
    touched
}

/// The connected (4-neighbour) area around `seed` whose colour is within
/// `tolerance` of the seed's in every channel joins (or leaves) the region.
pub fn wand(
    rgb: &RgbImage,
    mask: &mut GrayImage,
    seed: [f32; 2],
    tolerance: f32,
    mode: Mode,
) -> Option<PixelRect> {
    let (w, h) = rgb.dimensions();
    if mask.dimensions() != (w, h) || !(seed[0] >= 0.0 && seed[1] >= 0.0) {
        return None;
    }
    let (sx, sy) = (seed[0] as u32, seed[1] as u32);
    if sx >= w || sy >= h {
        return None;
    }
    let raw = rgb.as_raw();
    let target = rgb.get_pixel(sx, sy).0;
    let tol = tolerance.clamp(0.0, 255.0);
    let similar =
        |i: usize| (0..3).all(|c| (raw[i * 3 + c] as f32 - target[c] as f32).abs() <= tol);
    let mut seen = vec![false; (w * h) as usize];
    let mut queue = VecDeque::from([(sx, sy)]);
    seen[(sy * w + sx) as usize] = true;
    let mut rect = PixelRect {
        x0: sx,
        y0: sy,
        x1: sx + 1,
        y1: sy + 1,
    };
    let m: &mut [u8] = mask;
    while let Some((x, y)) = queue.pop_front() {
        set(&mut m[(y * w + x) as usize], mode);
        rect = rect.union(&PixelRect {
            x0: x,
            y0: y,
            x1: x + 1,
            y1: y + 1,
        });
        let mut visit = |nx: u32, ny: u32| {
            let i = (ny * w + nx) as usize;
            if !seen[i] && similar(i) {
                seen[i] = true;
                queue.push_back((nx, ny));
            }
        };
        if x > 0 {
            visit(x - 1, y);
        }
        if x + 1 < w {
            visit(x + 1, y);
        }
        if y > 0 {
            visit(x, y - 1);
        }
        if y + 1 < h {
            visit(x, y + 1);
        }
    }
    Some(rect)
}

/// Inverts the region.
pub fn invert(mask: &mut GrayImage) -> PixelRect {
    mask.iter_mut().for_each(|p| *p = 255 - *p);
    PixelRect::full(mask.width(), mask.height())
}

/// Sets the whole region to `value` (0 = clear, 255 = all wall).
pub fn fill_all(mask: &mut GrayImage, value: u8) -> PixelRect {
    mask.iter_mut().for_each(|p| *p = value);
    PixelRect::full(mask.width(), mask.height())
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::Luma;

    #[test]
    fn rect_polygon_and_wand_fill_what_they_should() {
        let mut m = GrayImage::new(20, 20);
        let r = fill_rect(&mut m, [12.0, 15.0], [2.0, 5.0], Mode::Add).unwrap();
        assert_eq!(
            r,
            PixelRect {
                x0: 2,
                y0: 5,
                x1: 12,
                y1: 15
            }
        );
        assert_eq!(m.iter().filter(|&&v| v == 255).count(), 100);
        let mut p = GrayImage::new(20, 20);
        fill_polygon(
            &mut p,
            &[[2.0, 2.0], [12.0, 2.0], [12.0, 12.0], [2.0, 12.0]],
            Mode::Add,
        )
        .unwrap();
        assert_eq!(p.iter().filter(|&&v| v == 255).count(), 100);
        fill_polygon(
            &mut p,
            &[[2.0, 2.0], [12.0, 2.0], [2.0, 12.0]],
            Mode::Subtract,
        );
        assert_eq!(p.get_pixel(3, 3)[0], 0);
        assert_eq!(p.get_pixel(11, 11)[0], 255);

        let rgb = RgbImage::from_fn(20, 20, |x, _| {
            if x < 8 {
                image::Rgb([200, 10, 10])
            } else {
                image::Rgb([10, 10, 200])
            }
        });
        let mut w = GrayImage::new(20, 20);
        let r = wand(&rgb, &mut w, [3.0, 3.0], 10.0, Mode::Add).unwrap();
        assert_eq!(
            r,
            PixelRect {
                x0: 0,
                y0: 0,
                x1: 8,
                y1: 20
            }
        );
        assert_eq!(w.iter().filter(|&&v| v == 255).count(), 160);
        assert!(wand(&rgb, &mut w, [-3.0, 3.0], 10.0, Mode::Add).is_none());
    }

    #[test]
    fn invert_and_clear() {
        let mut m = GrayImage::from_pixel(4, 4, Luma([255]));
        m.put_pixel(0, 0, Luma([0]));
        invert(&mut m);
        assert_eq!(m.get_pixel(0, 0)[0], 255);
        assert_eq!(m.get_pixel(1, 0)[0], 0);
        fill_all(&mut m, 0);
        assert!(m.iter().all(|&v| v == 0));
    }
}
