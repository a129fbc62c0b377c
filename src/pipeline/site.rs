//! What grime knows of the building around the wall: its scale in metres,
//! where the wall meets the ground, its ledges and where they shelter it
//! from rain. The scene analysis fills it for a photo ([`Site::seen`]); the
//! demo knows its own; a scene without one gets [`Site::assumed`].
//!
//! Effects size what they draw in metres through [`Site::metres_per_pixel`]
//! (issue "looks like a photograph": a lichen colony is centimetres, a
//! streak fades over a metre or two), and place moss and dust with the
//! ground line, the ledges and the shelter.

use std::sync::Arc;

use image::GrayImage;

use crate::analysis::{Analysis, Ledge};

/// Width of the wall when nothing says otherwise, in metres (the analysis
/// makes the same assumption, `ScaleSource::Default`).
pub const ASSUMED_WALL_WIDTH_M: f32 = 10.0;

/// The building around the wall, in photo pixels.
#[derive(Debug, Clone)]
pub struct Site {
    /// Metres per photo pixel.
    pub metres_per_pixel: f32,
    /// Per photo column, the row where the wall stands on the ground, when
    /// the photo shows the ground below it (`NaN` where it does not).
    /// Empty when unknown.
    pub ground: Vec<f32>,
    /// Per photo column, how sure the ground row there is the wall's foot,
    /// 0..1 ([`Analysis::foot_sure`]); empty when the ground is known (sure
    /// everywhere).
    pub ground_sure: Vec<f32>,
    /// Ledges (sills, cornices, ...), photo pixels, top to bottom.
    pub ledges: Vec<Ledge>,
    /// Rain shelter at the photo's size, 255 = fully sheltered; `None` =
    /// unknown (nothing sheltered).
    pub shelter: Option<Arc<GrayImage>>,
}

/// Two sites are equal when they say the same: a column with no ground
/// seen (`NaN`) equals another such column.
impl PartialEq for Site {
    fn eq(&self, other: &Site) -> bool {
        let same = |a: &f32, b: &f32| a == b || (a.is_nan() && b.is_nan());
        self.metres_per_pixel == other.metres_per_pixel
            && self.ground.len() == other.ground.len()
            && self
                .ground
                .iter()
                .zip(&other.ground)
                .all(|(a, b)| same(a, b))
            && self.ground_sure == other.ground_sure
            && self.ledges == other.ledges
            && self.shelter == other.shelter
    }
}

impl Site {
    /// Nothing known: the photo is taken to show a wall
    /// [`ASSUMED_WALL_WIDTH_M`] wide.
    pub fn assumed(width: u32) -> Site {
        Site {
            metres_per_pixel: ASSUMED_WALL_WIDTH_M / width.max(1) as f32,
            ground: Vec::new(),
            ground_sure: Vec::new(),
            ledges: Vec::new(),
            shelter: None,
        }
    }

    /// What the scene analysis saw.
    pub fn seen(a: &Analysis) -> Site {
        Site::seen_at(a, a.width, a.height)
    }

    /// What the scene analysis saw, for the photo scaled to `w` x `h` (a
    /// GUI's preview proxy): metres per pixel, ground rows, ledges and
    /// shelter in that image's pixels.
    pub fn seen_at(a: &Analysis, w: u32, h: u32) -> Site {
        let (fx, fy) = (
            a.width as f32 / w.max(1) as f32,
            a.height as f32 / h.max(1) as f32,
        );
        let ledges = a
            .ledges
            .iter()
            .map(|l| Ledge {
                polyline: l.polyline.iter().map(|p| [p[0] / fx, p[1] / fy]).collect(),
                ..l.clone()
            })
            .collect();
        Site {
            metres_per_pixel: a.scale.metres_per_pixel * fx,
            ground: a.foot_rows(w, h),
            ground_sure: a.foot_sure_rows(w),
            ledges,
            shelter: Some(Arc::new(GrayImage::from_fn(w, h, |x, y| {
                let s = a.shelter_at((x as f32 + 0.5) * fx, (y as f32 + 0.5) * fy);
                image::Luma([(s.clamp(0.0, 1.0) * 255.0).round() as u8])
            }))),
        }
    }

    /// The site of the photo scaled from `w` x `h` to `ow` x `oh` (an
    /// animation's frame size): metres per pixel, ground rows, ledges and
    /// shelter in the scaled photo's pixels.
    pub fn scaled(&self, (w, h): (u32, u32), (ow, oh): (u32, u32)) -> Site {
        let (sx, sy) = (ow as f32 / w.max(1) as f32, oh as f32 / h.max(1) as f32);
        let ground = match self.ground.len() {
            0 => Vec::new(),
            n => (0..ow)
                .map(|x| self.ground[(((x as f32 + 0.5) / sx) as usize).min(n - 1)] * sy)
                .collect(),
        };
        let ground_sure = match self.ground_sure.len() {
            0 => Vec::new(),
            n => (0..ow)
                .map(|x| self.ground_sure[(((x as f32 + 0.5) / sx) as usize).min(n - 1)])
                .collect(),
        };
        Site {
            metres_per_pixel: self.metres_per_pixel / sx,
            ground,
            ground_sure,
            ledges: self
                .ledges
                .iter()
                .map(|l| Ledge {
                    polyline: l.polyline.iter().map(|p| [p[0] * sx, p[1] * sy]).collect(),
                    ..l.clone()
                })
                .collect(),
            shelter: self
                .shelter
                .as_ref()
                .map(|s| Arc::new(crate::shrink::buffer_to_size(s, ow, oh))),
        }
    }

    /// Photo pixels for a length in metres.
    pub fn px(&self, metres: f32) -> f32 {
        metres / self.metres_per_pixel
    }

    /// The ground row under photo column `x`, if the wall meets the ground
    /// there.
    pub fn ground_at(&self, x: u32) -> Option<f32> {
        self.ground
            .get(x as usize)
            .copied()
            .filter(|g| g.is_finite())
    }

    /// How sure the ground row under photo column `x` is the wall's foot,
    /// 0..1 (1 where the site does not say).
    pub fn ground_sure_at(&self, x: u32) -> f32 {
        match self.ground_sure.len() {
            0 => 1.0,
            _ => self.ground_sure.get(x as usize).copied().unwrap_or(0.0),
        }
    }

    /// Rain shelter at photo pixel (x, y), 0..1.
    pub fn shelter_at(&self, x: u32, y: u32) -> f32 {
        match &self.shelter {
            Some(s) if x < s.width() && y < s.height() => s.get_pixel(x, y)[0] as f32 / 255.0,
            _ => 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::{self, Options};

    #[test]
    fn an_assumed_site_is_ten_metres_wide() {
        let s = Site::assumed(1000);
        assert!((s.px(1.0) - 100.0).abs() < 1e-3);
        assert_eq!(s.ground_at(5), None);
        assert_eq!(s.shelter_at(5, 5), 0.0);
    }

    #[test]
    fn a_site_with_columns_of_no_ground_equals_its_copy() {
        let mut site = Site::assumed(4);
        site.ground = vec![f32::NAN, 3.0, f32::NAN, 2.5];
        assert_eq!(site, site.clone());
        let mut other = site.clone();
        other.ground[0] = 1.0;
        assert_ne!(site, other);
    }

    #[test]
    fn a_seen_site_finds_the_ground_under_a_synthetic_wall() {
        // A plaster wall with pilasters over a road; the ground's fill
        // climbs the shaded boards of its left third, where no foot is
        // seen. (The road of `synthetic::scene` is grain without joints:
        // nothing there lies flatter than the wall, so no foot is seen.)
        let sc = analysis::synthetic::kerbside(analysis::synthetic::Kerb::ShadedBoards, 480, 360);
        let a = analysis::analyse(&sc.photo, &Options::default()).unwrap();
        let site = Site::seen(&a);
        assert_eq!(site.ground.len(), 480);
        assert_eq!(site.metres_per_pixel, a.scale.metres_per_pixel);
        let found: Vec<f32> = (0..480).filter_map(|x| site.ground_at(x)).collect();
        assert!(found.len() > 160, "ground found in {} columns", found.len());
        let mean = found.iter().sum::<f32>() / found.len() as f32;
        assert!(mean > 180.0, "the ground is in the lower half: {mean}");

        // At half the size (a preview proxy): pixels twice as large, the
        // ground and the ledges at half the coordinates.
        let half = Site::seen_at(&a, 240, 180);
        assert_eq!(half.metres_per_pixel, 2.0 * site.metres_per_pixel);
        assert_eq!(half.ground.len(), 240);
        assert_eq!(half.shelter.as_ref().unwrap().dimensions(), (240, 180));
        for x in (0..240).step_by(7) {
            match (half.ground_at(x), site.ground_at(2 * x)) {
                // The foot is a sloping line sampled at each column's
                // centre, half a photo pixel apart.
                (Some(a), Some(b)) => assert!((2.0 * a - b).abs() < 0.5, "{x}: {a} {b}"),
                (None, None) => {}
                // Only at a stretch's end, which falls between the two
                // photo columns a half-size column covers.
                _ => assert_ne!(
                    site.ground_at(2 * x).is_some(),
                    site.ground_at(2 * x + 1).is_some(),
                    "{x}"
                ),
            }
        }
        assert_eq!(half.ledges.len(), site.ledges.len());
        for (l, m) in half.ledges.iter().zip(&site.ledges) {
            assert_eq!(l.kind, m.kind);
            assert!((2.0 * l.polyline[0][1] - m.polyline[0][1]).abs() < 1e-3);
        }
        // The full-size site scaled (an animation's frames) agrees.
        let scaled = site.scaled((480, 360), (240, 180));
        assert_eq!(scaled.metres_per_pixel, half.metres_per_pixel);
        assert_eq!(scaled.ledges, half.ledges);
        assert_eq!(scaled.ground.len(), 240);
        // Each samples its column at another point: they may part at the
        // ends of a stretch of ground.
        let mut parted = 0;
        for x in 0..240 {
            match (scaled.ground_at(x), half.ground_at(x)) {
                (Some(a), Some(b)) => assert!((a - b).abs() <= 1.0, "{x}: {a} {b}"),
                (a, b) => parted += usize::from(a.is_some() != b.is_some()),
            }
        }
        // They may part only where the two photo columns a half-size
        // column covers disagree on whether there is ground.
        let split = (0..240)
            .filter(|&x| site.ground_at(2 * x).is_some() != site.ground_at(2 * x + 1).is_some())
            .count();
        assert!(parted <= split, "{parted} columns parted, {split} split");
        let (s, h) = (scaled.shelter.unwrap(), half.shelter.unwrap());
        assert_eq!(s.dimensions(), h.dimensions());
        let off: u64 = s
            .pixels()
            .zip(h.pixels())
            .map(|(a, b)| a[0].abs_diff(b[0]) as u64)
            .sum();
        assert!(off as f64 / (240.0 * 180.0) < 8.0, "shelter {off}");
    }
}
