//! A preset for the photo scaled (an animation's frames drawn at their
//! size): what it gives in photo pixels scales with the photo.

use super::{Imperfection, Preset};

impl Preset {
    /// The preset for the photo scaled by `sx` across and `sy` down: the
    /// rain's source lines, the γ-ton sources' points and each
    /// imperfection's point and area move with the photo. A dust given at a
    /// fixed `ppi` keeps its wall: its ppi and granules scale, and a pixel
    /// holds as many more particles before it is covered. Everything else
    /// is in metres, in grid pixels or without a unit, and stays.
    pub fn scaled(&self, sx: f32, sy: f32) -> Preset {
        let mut p = self.clone();
        let at = |q: &mut [f32; 2]| *q = [q[0] * sx, q[1] * sy];
        p.rain.source_lines.iter_mut().flatten().for_each(at);
        p.gammaton
            .sources
            .iter_mut()
            .flat_map(|s| &mut s.points)
            .for_each(at);
        let placed: [&mut dyn Imperfection; 7] = [
            &mut p.scratches,
            &mut p.splotches,
            &mut p.stains,
            &mut p.mould,
            &mut p.rust,
            &mut p.smudges,
            &mut p.corrosion,
        ];
        for imperfection in placed {
            imperfection.scale_place(sx, sy);
        }
        if p.dust.ppi > 0.0 {
            let s = (sx * sy).sqrt();
            p.dust.ppi *= s as f64;
            p.dust.granule_size *= s;
            p.dust.anp_max /= s * s;
        }
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::preset::Placement;

    #[test]
    fn what_is_in_photo_pixels_scales_and_the_rest_stays() {
        let mut p = Preset::default();
        p.rain.source_lines = vec![vec![[100.0, 40.0], [300.0, 42.0]]];
        p.rust.placement = Placement::Point;
        p.rust.around = [50.0, 60.0];
        p.stains.area = vec![[0.0, 0.0], [200.0, 0.0], [200.0, 100.0]];
        let q = p.scaled(0.5, 0.25);
        assert_eq!(q.rain.source_lines, [vec![[50.0, 10.0], [150.0, 10.5]]]);
        assert_eq!(q.rust.around, [25.0, 15.0]);
        assert_eq!(q.stains.area[2], [100.0, 25.0]);
        // Sizes in metres and the dust at the scene's own scale stay.
        assert_eq!(q.moss, p.moss);
        assert_eq!(q.dust, p.dust);
        let mut fixed = p.clone();
        fixed.dust.ppi = 100.0;
        let d = fixed.scaled(0.5, 0.5).dust;
        assert_eq!((d.ppi, d.granule_size), (50.0, p.dust.granule_size * 0.5));
        assert_eq!(d.anp_max, p.dust.anp_max * 4.0);
    }
}
