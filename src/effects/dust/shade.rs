//! Putting dust on the wall for a viewing and a light angle (Santos sec. 5.4,
//! eqs. 8-11): the film shows at grazing views, granules at any view, both
//! more under grazing light.
//!
//! Without a normal map the wall is flat: theta_v and theta_i are the same
//! at every pixel. With one, each pixel's angles come from its normal:
//! - the map is in the wall's tangent space, OpenGL convention: RGB =
//!   (n + 1) / 2 with x right, y up (green = up), z out of the wall;
//! - [choice] the camera is below the wall and the light above it (a photo
//!   from the street under the sky): view direction (0, -sin theta_v,
//!   cos theta_v), light direction (0, sin theta_i, cos theta_i). A flat
//!   normal (0, 0, 1) gives back the global angles;
//! - spatial falloff z_m (Santos after Hsu & Wong: surfaces facing up
//!   collect more dust) [choice: z_m = clamp(1 + n_y, 0, 1), so vertical and
//!   upward-facing pixels keep all their dust, which is the no-map default,
//!   and downward-facing ones (soffits, undersides of sills) lose it].

use image::RgbImage;

use crate::error::{Error, Result};

/// Santos eq. (8): V = 1 - cos(theta_v), theta_v in degrees from the normal.
pub fn view_factor(theta_v: f32) -> f32 {
    1.0 - theta_v.clamp(0.0, 90.0).to_radians().cos()
}

/// Santos eq. (9): L = 1 - cos(theta_i) / 2, theta_i in degrees.
pub fn light_factor(theta_i: f32) -> f32 {
    1.0 - 0.5 * theta_i.clamp(0.0, 90.0).to_radians().cos()
}

/// What multiplies each layer's alpha at one pixel.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Factors {
    /// Film: V L z_m (eq. 11).
    pub film: f32,
    /// Granules: L z_m (eq. 10).
    pub granule: f32,
}

/// Per-pixel view and light factors.
#[derive(Debug, Clone)]
pub struct Shading<'a> {
    flat: Factors,
    normals: Option<&'a RgbImage>,
    view: [f32; 3],
    light: [f32; 3],
}

impl<'a> Shading<'a> {
    /// Shading for angles in degrees and an optional `width` x `height`
    /// normal map.
    ///
    /// # Errors
    /// [`Error::NormalMapSize`] when the normal map has another size.
    pub fn new(
        theta_v: f32,
        theta_i: f32,
        normals: Option<&'a RgbImage>,
        width: u32,
        height: u32,
    ) -> Result<Self> {
        if let Some(n) = normals
            && n.dimensions() != (width, height)
        {
            return Err(Error::NormalMapSize {
                map_w: n.width(),
                map_h: n.height(),
                img_w: width,
                img_h: height,
            });
        }
        let (v, l) = (view_factor(theta_v), light_factor(theta_i));
        let (tv, ti) = (
            theta_v.clamp(0.0, 90.0).to_radians(),
            theta_i.clamp(0.0, 90.0).to_radians(),
        );
        Ok(Shading {
            flat: Factors {
                film: v * l,
                granule: l,
            },
            normals,
            view: [0.0, -tv.sin(), tv.cos()],
            light: [0.0, ti.sin(), ti.cos()],
        })
    }

    /// Factors of one pixel with tangent-space normal `n` (unit length).
    pub fn at_normal(&self, n: [f32; 3]) -> Factors {
        let dot = |a: [f32; 3]| (a[0] * n[0] + a[1] * n[1] + a[2] * n[2]).clamp(0.0, 1.0);
        let v = 1.0 - dot(self.view); // eq. (8)
        let l = 1.0 - 0.5 * dot(self.light); // eq. (9)
        let z_m = (1.0 + n[1]).clamp(0.0, 1.0);
        Factors {
            film: v * l * z_m,
            granule: l * z_m,
        }
    }

    /// Factors of row `y`, written to `out` (length = width).
    pub fn row(&self, y: u32, out: &mut [Factors]) {
        let Some(map) = self.normals else {
            out.fill(self.flat);
            return;
        };
        let w = map.width() as usize;
        let row = &map.as_raw()[y as usize * w * 3..(y as usize + 1) * w * 3];
        for (o, px) in out.iter_mut().zip(row.chunks_exact(3)) {
            let n = [0, 1, 2].map(|k| px[k] as f32 / 127.5 - 1.0);
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            *o = if len > 1e-3 {
                self.at_normal([n[0] / len, n[1] / len, n[2] / len])
            } else {
                self.flat
            };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn film_grows_with_view_angle_and_vanishes_head_on() {
        assert_eq!(view_factor(0.0), 0.0);
        let mut last = -1.0;
        for deg in (0..=90).step_by(10) {
            let v = view_factor(deg as f32);
            assert!(v > last);
            last = v;
        }
        assert!((view_factor(90.0) - 1.0).abs() < 1e-6);
        assert!((light_factor(0.0) - 0.5).abs() < 1e-6 && (light_factor(90.0) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn flat_normals_reproduce_the_global_angles_and_soffits_lose_dust() {
        let s = Shading::new(60.0, 30.0, None, 1, 1).unwrap();
        let flat = s.at_normal([0.0, 0.0, 1.0]);
        assert!(
            (flat.film - s.flat.film).abs() < 1e-6 && (flat.granule - s.flat.granule).abs() < 1e-6
        );
        let down = s.at_normal([0.0, -1.0, 0.0]);
        assert_eq!(
            down,
            Factors {
                film: 0.0,
                granule: 0.0
            }
        );
        let map = RgbImage::from_pixel(2, 1, image::Rgb([128, 128, 255]));
        let sm = Shading::new(60.0, 30.0, Some(&map), 2, 1).unwrap();
        let mut row = [Factors::default(); 2];
        sm.row(0, &mut row);
        assert!((row[0].film - s.flat.film).abs() < 0.01, "{row:?}");
        assert!(Shading::new(60.0, 30.0, Some(&map), 3, 1).is_err());
    }
}
