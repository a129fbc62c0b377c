//! The light a photo was taken under, taken out before the ground's grey
//! tests ([`Light`]).

use rayon::prelude::*;

use super::features::Features;
use super::wall::Class;

/// A photo whose wall (with the ground) is darker than this mean luma is
/// lit by street lamps, whose colour [`Light`] takes out (LabelMeFacade
/// train: barcelona night img_1941 at 0.15 is the only one under it).
const NIGHT: f32 = 0.2;
/// A photo whose mean blue (over what is still wall) is under this share
/// of its mean red is lit by sodium lamps (see [`Light::Sodium`]).
const SODIUM: f32 = 0.2;

/// The light a photo was taken under, taken out before the ground's grey
/// tests: a road at dusk, or in the shade of a clear sky, is blue, and
/// under street lamps orange, and was wall for being too saturated
/// (street_gre91, street_gre86, barcelona night img_1941).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Light {
    /// Gains per channel that make the light grey (ones for white light).
    Cast([f32; 3]),
    /// Sodium street lamps: their light is nearly one wavelength, yellow,
    /// with no blue to scale up, so colour tells nothing and every pixel
    /// is taken as grey (review 20's barcelona night img_1934: mean blue
    /// 0.08 of the mean red; the least blue photo by day of LabelMeFacade
    /// and CMP is at 0.56).
    Sodium,
}

impl Light {
    /// White light: the photo's own colours.
    pub(super) const WHITE: Light = Light::Cast([1.0; 3]);

    /// The light of the photo from what is still wall (buildings and the
    /// ground; sky and vegetation left out: a blue sky is not the light),
    /// by grey world (G. Buchsbaum, "A spatial processor model for object
    /// colour perception", J. Franklin Inst. 310, 1980): its mean colour
    /// is taken to be grey. Only a light that is blue (mean blue over the
    /// mean red and green), dim as night (mean luma under [`NIGHT`]) or
    /// sodium (mean blue under [`SODIUM`] of the mean red) is taken out: a
    /// warm cast by day looks the same as an ochre facade filling the
    /// frame (CMP's), whose plinth the road's fill then climbs. Half of a
    /// cast (the square root of the gains), as the mean holds the facade's
    /// own colour too (a pink arcade at dusk).
    pub(super) fn of(f: &Features, class: &[Class]) -> Light {
        let (sum, n) = (0..f.w * f.h)
            .into_par_iter()
            .filter(|&i| class[i] == Class::Wall)
            .map(|i| (f.rgb_at(i), 1usize))
            .reduce(
                || ([0.0; 3], 0),
                |(a, n), (b, m)| ([a[0] + b[0], a[1] + b[1], a[2] + b[2]], n + m),
            );
        if n == 0 {
            return Light::WHITE;
        }
        let m = sum.map(|c| c / n as f32);
        if m[2] < SODIUM * m[0] {
            return Light::Sodium;
        }
        if m[2] <= m[0].max(m[1]) && super::features::luma(m) >= NIGHT {
            return Light::WHITE;
        }
        let grey = (m[0] + m[1] + m[2]) / 3.0;
        Light::Cast(m.map(|c| (grey / c.max(1e-3)).sqrt()))
    }

    /// The HSV saturation of `c` under this light.
    pub(super) fn saturation(self, [r, g, b]: [f32; 3]) -> f32 {
        match self {
            Light::Cast(k) => super::plane::saturation([r * k[0], g * k[1], b * k[2]]),
            Light::Sodium => 0.0,
        }
    }
}
