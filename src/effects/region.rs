//! The wall region at photo resolution, for effects that place things on
//! individual pixels (moss dots, dust particles): uniform sampling of wall
//! pixels, membership and the soft-edge weight.
//!
//! A pixel is wall when its mask value is at least [`WALL`]; its weight is
//! value / 255, so a layer's alpha is exactly 0 where the mask is 0.

use image::GrayImage;
use rand::Rng as _;

use crate::error::{Error, Result};
use crate::grid::WALL;
use crate::random::Rng;

/// A horizontal run of wall pixels.
#[derive(Debug, Clone, Copy)]
struct Run {
    /// Wall pixels in all earlier runs.
    before: u64,
    x: u32,
    y: u32,
}

/// Wall pixels of a photo, ready for uniform sampling.
///
/// ```
/// use image::{GrayImage, Luma};
/// let mut mask = GrayImage::new(4, 4);
/// mask.put_pixel(1, 2, Luma([255]));
/// mask.put_pixel(3, 2, Luma([200]));
/// let region = grime::effects::region::Region::new(4, 4, Some(&mask)).unwrap();
/// assert_eq!(region.area(), 2);
/// let mut rng = grime::random::rng(1, grime::random::Stream::DustFilm, 0, 0);
/// let (x, y) = region.sample(&mut rng);
/// assert!(y == 2 && (x == 1 || x == 3));
/// ```
#[derive(Debug, Clone)]
pub struct Region<'a> {
    width: u32,
    height: u32,
    mask: Option<&'a GrayImage>,
    runs: Vec<Run>,
    area: u64,
}

impl<'a> Region<'a> {
    /// The region of a `width` x `height` photo; `None` = the whole photo.
    ///
    /// # Errors
    /// [`Error::MaskSize`] for a mask of another size, [`Error::EmptyRegion`]
    /// when no pixel is wall.
    pub fn new(width: u32, height: u32, mask: Option<&'a GrayImage>) -> Result<Region<'a>> {
        let Some(m) = mask else {
            if width == 0 || height == 0 {
                return Err(Error::EmptyRegion);
            }
            return Ok(Region {
                width,
                height,
                mask,
                runs: Vec::new(),
                area: width as u64 * height as u64,
            });
        };
        if m.dimensions() != (width, height) {
            return Err(Error::MaskSize {
                mask_w: m.width(),
                mask_h: m.height(),
                img_w: width,
                img_h: height,
            });
        }
        let mut runs = Vec::new();
        let mut area = 0u64;
        for (y, row) in m.as_raw().chunks_exact(width.max(1) as usize).enumerate() {
            let mut x = 0;
            while x < row.len() {
                if row[x] < WALL {
                    x += 1;
                    continue;
                }
                let start = x;
                while x < row.len() && row[x] >= WALL {
                    x += 1;
                }
                runs.push(Run {
                    before: area,
                    x: start as u32,
                    y: y as u32,
                });
                area += (x - start) as u64;
            }
        }
        if area == 0 {
            return Err(Error::EmptyRegion);
        }
        Ok(Region {
            width,
            height,
            mask,
            runs,
            area,
        })
    }

    /// Photo width.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Photo height.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Number of wall pixels.
    pub fn area(&self) -> u64 {
        self.area
    }

    /// The `k`-th wall pixel in row-major order, `k < area()`.
    pub fn nth(&self, k: u64) -> (u32, u32) {
        if self.mask.is_none() {
            let w = self.width as u64;
            return ((k % w) as u32, (k / w) as u32);
        }
        let i = self.runs.partition_point(|r| r.before <= k) - 1;
        let r = self.runs[i];
        (r.x + (k - r.before) as u32, r.y)
    }

    /// The row-major index (y width + x) of [`Region::nth`]`(k)`.
    pub fn nth_index(&self, k: u64) -> u64 {
        if self.mask.is_none() {
            return k;
        }
        let i = self.runs.partition_point(|r| r.before <= k) - 1;
        let r = self.runs[i];
        r.y as u64 * self.width as u64 + r.x as u64 + (k - r.before)
    }

    /// A uniformly random wall pixel.
    pub fn sample(&self, rng: &mut Rng) -> (u32, u32) {
        self.nth(rng.random_range(0..self.area))
    }

    /// Whether the pixel containing photo point (x, y) is wall.
    pub fn contains(&self, x: f32, y: f32) -> bool {
        if !(x >= 0.0 && y >= 0.0 && x < self.width as f32 && y < self.height as f32) {
            return false;
        }
        self.mask
            .is_none_or(|m| m.get_pixel(x as u32, y as u32)[0] >= WALL)
    }

    /// Mask values of row `y`; `None` without a mask (every pixel is wall
    /// with weight 1).
    pub fn mask_row(&self, y: u32) -> Option<&[u8]> {
        let w = self.width as usize;
        self.mask
            .map(|m| &m.as_raw()[y as usize * w..(y as usize + 1) * w])
    }

    /// Mask weights of row `y` (value / 255; all 1 without a mask).
    pub fn weights(&self, y: u32, out: &mut [f32]) {
        match self.mask {
            None => out.fill(1.0),
            Some(m) => {
                let w = self.width as usize;
                let row = &m.as_raw()[y as usize * w..(y as usize + 1) * w];
                for (o, &v) in out.iter_mut().zip(row) {
                    *o = v as f32 / 255.0;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::Luma;

    #[test]
    fn nth_enumerates_wall_pixels_in_order() {
        let mask = GrayImage::from_fn(7, 5, |x, y| {
            Luma([if (x + 2 * y) % 3 == 0 || x == 6 {
                255
            } else {
                40
            }])
        });
        let r = Region::new(7, 5, Some(&mask)).unwrap();
        let want: Vec<(u32, u32)> = (0..5)
            .flat_map(|y| (0..7).map(move |x| (x, y)))
            .filter(|&(x, y)| mask.get_pixel(x, y)[0] >= WALL)
            .collect();
        let got: Vec<_> = (0..r.area()).map(|k| r.nth(k)).collect();
        assert_eq!(got, want);
        for (k, (x, y)) in want.iter().enumerate() {
            assert_eq!(r.nth_index(k as u64), (y * 7 + x) as u64);
        }
        let plain = Region::new(7, 5, None).unwrap();
        assert_eq!(plain.nth_index(12), 12);
        assert!(Region::new(7, 5, Some(&GrayImage::new(7, 5))).is_err());
        assert!(Region::new(6, 5, Some(&mask)).is_err());
    }
}
