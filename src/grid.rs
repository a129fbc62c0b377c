//! The simulation grid: the region's bounding box, resampled so its longest
//! side is at most `sim.max_side` pixels.
//!
//! [choice] The papers simulate on images about 1000 px wide, with streak
//! widths, droplet counts and diffusion tuned to that scale. grime runs the
//! rain on a grid of that size and upsamples the smooth stain coverage to the
//! photo, so a 6000 px photo gets the same look as a 1000 px one (not 6x
//! thinner streaks), at a cost that does not grow with the photo. With
//! `sim.max_side = 0` the grid is the photo itself.

use image::GrayImage;
use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::field::RowMajor;
use crate::photo::Photo;

/// Mask values at or above this are wall.
pub const WALL: u8 = 128;

/// Maps between photo pixels and simulation-grid pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grid {
    /// Bounding box origin in the photo.
    pub x0: u32,
    /// Bounding box origin in the photo.
    pub y0: u32,
    /// Bounding box width in photo pixels.
    pub box_w: u32,
    /// Bounding box height in photo pixels.
    pub box_h: u32,
    /// Grid width.
    pub width: usize,
    /// Grid height.
    pub height: usize,
    /// Photo pixels per grid pixel (>= 1).
    pub scale: f32,
}

impl Grid {
    /// The grid for a photo of `w` x `h` and an optional region mask.
    ///
    /// # Errors
    /// [`Error::EmptyRegion`] when the mask marks no wall pixel.
    pub fn new(w: u32, h: u32, region: Option<&GrayImage>, max_side: u32) -> Result<Grid> {
        let (x0, y0, x1, y1) = match region {
            None => (0, 0, w, h),
            Some(mask) => bounding_box(mask).ok_or(Error::EmptyRegion)?,
        };
        let (box_w, box_h) = (x1 - x0, y1 - y0);
        let longest = box_w.max(box_h) as f32;
        let scale = if max_side == 0 || longest <= max_side as f32 {
            1.0
        } else {
            longest / max_side as f32
        };
        Ok(Grid {
            x0,
            y0,
            box_w,
            box_h,
            width: ((box_w as f32 / scale).round() as usize).max(1),
            height: ((box_h as f32 / scale).round() as usize).max(1),
            scale,
        })
    }

    /// Photo point to grid point.
    pub fn to_grid(&self, x: f32, y: f32) -> (f32, f32) {
        (
            (x - self.x0 as f32) / self.scale,
            (y - self.y0 as f32) / self.scale,
        )
    }

    /// Grid point to photo point.
    pub fn to_photo(&self, x: f32, y: f32) -> (f32, f32) {
        (
            x * self.scale + self.x0 as f32,
            y * self.scale + self.y0 as f32,
        )
    }

    fn cell_span(&self, g: usize, origin: u32, len: u32, cells: usize) -> (u32, u32) {
        let a = origin + ((g as f32 * self.scale) as u32).min(len - 1);
        let b = origin + (((g + 1) as f32 * self.scale) as u32).clamp(a - origin + 1, len);
        let b = if g + 1 == cells { origin + len } else { b };
        (a, b)
    }

    /// Area-averaged luminance B on the grid.
    pub fn luma(&self, photo: &Photo) -> RowMajor<f32> {
        let mut out = RowMajor::filled(self.width, self.height, 0.0);
        out.data_mut()
            .par_chunks_mut(self.width)
            .enumerate()
            .for_each(|(gy, row)| {
                let (ya, yb) = self.cell_span(gy, self.y0, self.box_h, self.height);
                let mut line = vec![0.0; photo.width() as usize];
                let mut count = vec![0u32; self.width];
                for y in ya..yb {
                    photo.luma_row(y, &mut line);
                    for (gx, (acc, n)) in row.iter_mut().zip(count.iter_mut()).enumerate() {
                        let (xa, xb) = self.cell_span(gx, self.x0, self.box_w, self.width);
                        *acc += line[xa as usize..xb as usize].iter().sum::<f32>();
                        *n += xb - xa;
                    }
                }
                for (acc, n) in row.iter_mut().zip(count) {
                    *acc /= n.max(1) as f32;
                }
            });
        out
    }

    /// Area-averaged R, G and B on the grid (as [`Grid::luma`]).
    pub fn rgb(&self, photo: &Photo) -> [RowMajor<f32>; 3] {
        let (w, h) = (self.width, self.height);
        let columns: Vec<(usize, usize)> = (0..w)
            .map(|gx| {
                let (a, b) = self.cell_span(gx, self.x0, self.box_w, w);
                (a as usize, b as usize)
            })
            .collect();
        let rows: Vec<Vec<[f32; 3]>> = (0..h)
            .into_par_iter()
            .map(|gy| {
                let (ya, yb) = self.cell_span(gy, self.y0, self.box_h, h);
                let mut line = vec![[0.0f32; 3]; photo.width() as usize];
                let mut acc = vec![[0.0f32; 3]; w];
                for y in ya..yb {
                    photo.rgb_row(y, &mut line);
                    for (a, &(xa, xb)) in acc.iter_mut().zip(&columns) {
                        for c in &line[xa..xb] {
                            for i in 0..3 {
                                a[i] += c[i];
                            }
                        }
                    }
                }
                let n = (yb - ya) as usize;
                acc.iter()
                    .zip(&columns)
                    .map(|(a, &(xa, xb))| a.map(|v| v / ((xb - xa) * n).max(1) as f32))
                    .collect()
            })
            .collect();
        [0, 1, 2].map(|i| {
            let data = rows.iter().flat_map(|r| r.iter().map(|c| c[i])).collect();
            RowMajor::new(w, h, data)
        })
    }

    /// The region on the grid: a cell is wall when at least half its photo
    /// pixels are (all cells without a mask).
    pub fn region(&self, mask: Option<&GrayImage>) -> RowMajor<bool> {
        let Some(mask) = mask else {
            return RowMajor::filled(self.width, self.height, true);
        };
        let mut out = RowMajor::filled(self.width, self.height, false);
        out.data_mut()
            .par_chunks_mut(self.width)
            .enumerate()
            .for_each(|(gy, row)| {
                let (ya, yb) = self.cell_span(gy, self.y0, self.box_h, self.height);
                for (gx, cell) in row.iter_mut().enumerate() {
                    let (xa, xb) = self.cell_span(gx, self.x0, self.box_w, self.width);
                    let mut wall = 0u32;
                    for y in ya..yb {
                        wall += (xa..xb)
                            .filter(|&x| mask.get_pixel(x, y)[0] >= WALL)
                            .count() as u32;
                    }
                    *cell = 2 * wall >= (yb - ya) * (xb - xa);
                }
            });
        out
    }

    /// Upsamples grid values in 0..1 (a field of the grid's size) to a
    /// photo-sized 8-bit coverage map, bilinearly, weighted by the mask
    /// (value / 255). Pixels outside the mask get exactly 0.
    pub fn upsample(
        &self,
        values: &RowMajor<f32>,
        mask: Option<&GrayImage>,
        photo_w: u32,
        photo_h: u32,
    ) -> GrayImage {
        let mut out = GrayImage::new(photo_w, photo_h);
        let (gw, gh) = (self.width, self.height);
        assert_eq!((values.width(), values.height()), (gw, gh), "grid field");
        let values = values.data();
        // Photo columns grouped by the pair of grid cells they interpolate
        // between: (left cell, first column, end column); tx per column.
        let mut spans: Vec<(usize, usize, usize)> = Vec::new();
        let mut tx = Vec::with_capacity(self.box_w as usize);
        for x in 0..self.box_w as usize {
            let g = ((x as f32 + 0.5) / self.scale - 0.5).clamp(0.0, (gw - 1) as f32);
            let a = g as usize;
            tx.push(g - a as f32);
            match spans.last_mut() {
                Some(s) if s.0 == a => s.2 = x + 1,
                _ => spans.push((a, x, x + 1)),
            }
        }
        let stride = photo_w as usize;
        let x0 = self.x0 as usize;
        out.par_chunks_mut(stride)
            .enumerate()
            .skip(self.y0 as usize)
            .take(self.box_h as usize)
            .for_each(|(y, row)| {
                let mask_row = mask.map(|m| &m.as_raw()[y * stride..(y + 1) * stride]);
                let to_u8 = |v: f32, x: usize| {
                    let weight = mask_row.map_or(255.0, |m| m[x] as f32);
                    (v * weight + 0.5).clamp(0.0, 255.0) as u8
                };
                if self.scale == 1.0 {
                    // The grid is the box: a copy.
                    let src = &values[(y - self.y0 as usize) * gw..][..gw];
                    for (x, (o, &v)) in row[x0..x0 + gw].iter_mut().zip(src).enumerate() {
                        *o = to_u8(v, x0 + x);
                    }
                    return;
                }
                let g = ((y as f32 - self.y0 as f32 + 0.5) / self.scale - 0.5)
                    .clamp(0.0, (gh - 1) as f32);
                let (ra, rb, ty) = (g as usize, (g as usize + 1).min(gh - 1), g.fract());
                let (top, bottom) = (
                    &values[ra * gw..(ra + 1) * gw],
                    &values[rb * gw..(rb + 1) * gw],
                );
                // Vertical interpolation once per grid column, then horizontal per pixel.
                let line: Vec<f32> = top
                    .iter()
                    .zip(bottom)
                    .map(|(t, b)| t + (b - t) * ty)
                    .collect();
                for &(a, start, end) in &spans {
                    let (va, vb) = (line[a], line[(a + 1).min(gw - 1)]);
                    if va == 0.0 && vb == 0.0 {
                        continue; // transparent span: most of a streak layer
                    }
                    for x in start..end {
                        row[x0 + x] = to_u8(va + (vb - va) * tx[x], x0 + x);
                    }
                }
            });
        out
    }
}

/// Bounding box (x0, y0, x1, y1), exclusive end, of mask pixels >= [`WALL`].
pub fn bounding_box(mask: &GrayImage) -> Option<(u32, u32, u32, u32)> {
    let (w, h) = mask.dimensions();
    let mut bb: Option<(u32, u32, u32, u32)> = None;
    for y in 0..h {
        let row = &mask.as_raw()[(y * w) as usize..((y + 1) * w) as usize];
        let (Some(first), Some(last)) = (
            row.iter().position(|&v| v >= WALL),
            row.iter().rposition(|&v| v >= WALL),
        ) else {
            continue;
        };
        let (first, last) = (first as u32, last as u32 + 1);
        bb = Some(match bb {
            None => (first, y, last, y + 1),
            Some((a, b, c, _)) => (a.min(first), b, c.max(last), y + 1),
        });
    }
    bb
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::{DynamicImage, Luma, RgbImage};

    #[test]
    fn grid_covers_the_mask_box_and_caps_its_side() {
        let mut mask = GrayImage::new(400, 300);
        for y in 50..250 {
            for x in 100..300 {
                mask.put_pixel(x, y, Luma([255]));
            }
        }
        let g = Grid::new(400, 300, Some(&mask), 100).unwrap();
        assert_eq!((g.x0, g.y0, g.box_w, g.box_h), (100, 50, 200, 200));
        assert_eq!((g.width, g.height, g.scale), (100, 100, 2.0));
        assert!(Grid::new(400, 300, Some(&GrayImage::new(400, 300)), 0).is_err());
    }

    #[test]
    fn luma_is_area_averaged() {
        let img = RgbImage::from_fn(4, 2, |x, _| {
            if x % 2 == 0 {
                image::Rgb([0, 0, 0])
            } else {
                image::Rgb([200, 200, 200])
            }
        });
        let photo = Photo::new(DynamicImage::ImageRgb8(img));
        let g = Grid::new(4, 2, None, 2).unwrap();
        assert_eq!((g.width, g.height), (2, 1));
        for &v in g.luma(&photo).data() {
            assert!((v - 100.0).abs() < 0.1, "{v}");
        }
    }

    #[test]
    fn upsample_is_identity_at_scale_one_and_zero_outside_mask() {
        let g = Grid::new(3, 2, None, 0).unwrap();
        let vals = RowMajor::new(3, 2, vec![0.0, 0.5, 1.0, 0.2, 0.4, 0.6]);
        let mut mask = GrayImage::from_pixel(3, 2, Luma([255]));
        mask.put_pixel(1, 1, Luma([0]));
        let up = g.upsample(&vals, Some(&mask), 3, 2);
        assert_eq!(up.as_raw(), &vec![0, 128, 255, 51, 0, 153]);
    }
}
