//! The photo's light on a growth layer: moss and lichen take the colour and
//! the strength of the light that falls on the wall where they grow, and
//! the wall's fine relief (joints, pores) shows through them
//! (`how-facades-age.md`, "Living growth": growth keeps the surface's
//! relief; the blind review read moss lit by grey light only as paint,
//! "one olive hue in warm evening light").
//!
//! A photo's pixel is the wall's albedo times the light (Land & McCann,
//! "Lightness and Retinex Theory", 1971); a colony on the wall is its own
//! albedo times the same light. The light at a pixel is split in two:
//! - the **local light**: the wall's local space average colour (Ebner,
//!   "Color constancy based on local space average color", Machine Vision
//!   and Applications 20, 2009: the illuminant at a pixel is the mean
//!   colour around it, the grey world taken locally), over `radius` grid
//!   cells. Its luma against the wall's mean is sun or shade; its chroma
//!   the light's colour, warm in evening sun, blue in shade [choice: a
//!   wall's own colour (red brick, ochre render) also counts as light, so
//!   the chroma is taken at `TINT_STRENGTH`];
//! - the **relief**: the pixel's luma over the local average luma, the
//!   wall's detail finer than the window (joints, pores, a brick's grain).
//!
//! The relief also thickens a colony in the recesses (a joint holds water
//! and the spores, `how-facades-age.md`) and thins it on the proud parts.

use image::RgbaImage;
use rayon::prelude::*;

use crate::effects::box_mean::box_mean;
use crate::field::RowMajor;
use crate::grid::Grid;
use crate::photo::Photo;

/// Half the side of the window the local light is averaged over, metres
/// [choice: wider than a brick with its joints (0.065-0.22 m) so the
/// relief stays out of the light, narrower than a storey so a balcony's
/// shadow is light].
pub const LIGHT_M: f32 = 0.3;

/// Rec. 601 luma weights (as `Photo::luma_row`).
const LUMA: [f32; 3] = [0.299, 0.587, 0.114];

/// How much of the local light's chroma is applied, as an exponent
/// [choice: at 0.5 an evening photo's orange (IMG_3160's wall at R/Y 1.24,
/// B/Y 0.69) warms the moss by about a third of the wall's own warmth
/// (`(R - B) / Y` 0.25 -> 0.39, BENCHMARKS), a red brick in daylight
/// only tints it].
const TINT_STRENGTH: f32 = 0.5;

/// Bounds of a channel's ratio to the luma in the light's colour: no
/// light makes moss purple.
const CHROMA_RANGE: (f32, f32) = (0.7, 1.35);

/// Most the local light lightens a colony [choice, as the former
/// `surface::MAX_GAIN`: a part of the wall much brighter than its mean is
/// more often a lighter material (white trim, a stone sill) than stronger
/// light; lightened more it read as lime paint along every ledge in the
/// blind review].
const MAX_LIGHT: f32 = 1.15;

/// Bounds of the relief factor: a joint's shadow darkens a colony to at
/// most this share, a proud grain lightens it to at most this much
/// [choice: joints of a street photo are 1-2 px at 20-40% of the wall's
/// luma].
const RELIEF_RANGE: (f32, f32) = (0.3, 1.3);

/// How much thicker a colony is per unit of darkness of the relief (a
/// joint at half the luma around it takes 1 + 0.5 RECESS of the alpha),
/// and thinner on proud parts [choice: visible but not a grid of green
/// joints; the alpha is held within 0.6..1.5 of the drawn one].
const RECESS: f32 = 0.6;

/// The light over the wall, per grid cell.
#[derive(Debug, Clone)]
pub struct Light {
    /// Per cell: the light's R, G and B multipliers (its strength times
    /// its colour) and the local average luma (0 off the wall).
    cells: RowMajor<[f32; 4]>,
    /// What a pixel with no wall cell near takes: grey light of the
    /// wall's mean strength.
    fallback: [f32; 4],
    grid: Grid,
}

fn luma(c: [f32; 3]) -> f32 {
    c[0] * LUMA[0] + c[1] * LUMA[1] + c[2] * LUMA[2]
}

/// `c` over its luma, each channel within [`CHROMA_RANGE`].
fn chroma(c: [f32; 3]) -> [f32; 3] {
    let y = luma(c).max(1.0);
    c.map(|v| (v / y).clamp(CHROMA_RANGE.0, CHROMA_RANGE.1))
}

/// `c` raised to `k` per channel, renormalised to luma 1.
fn temper(c: [f32; 3], k: f32) -> [f32; 3] {
    let t = c.map(|v| v.max(1e-3).powf(k));
    let y = luma(t).max(1e-3);
    t.map(|v| v / y)
}

impl Light {
    /// The light of `photo` over the wall cells of `grid`; the local light
    /// is the mean over `radius` cells either side.
    pub fn of(photo: &Photo, grid: &Grid, region: &RowMajor<bool>, radius: usize) -> Light {
        let rgb = grid.rgb(photo);
        let wall_luma: Vec<f32> = (0..grid.width * grid.height)
            .filter(|i| region.data()[*i])
            .map(|i| luma([0, 1, 2].map(|c| rgb[c].data()[i])))
            .collect();
        let l_wall = (wall_luma.iter().map(|v| *v as f64).sum::<f64>()
            / wall_luma.len().max(1) as f64) as f32;
        let l_wall = l_wall.max(1.0);
        let low = rgb.map(|c| box_mean(&c, region, radius.max(1)));
        let cells = (0..grid.width * grid.height)
            .into_par_iter()
            .map(|i| {
                let c = [0, 1, 2].map(|k| low[k].data()[i]);
                let l_low = luma(c);
                if l_low <= 0.0 {
                    return [0.0; 4];
                }
                let strength = (l_low / l_wall).min(MAX_LIGHT);
                let [r, g, b] = temper(chroma(c), TINT_STRENGTH).map(|t| t * strength);
                [r, g, b, l_low.max(1.0)]
            })
            .collect();
        Light {
            cells: RowMajor::new(grid.width, grid.height, cells),
            fallback: [1.0, 1.0, 1.0, l_wall],
            grid: *grid,
        }
    }

    /// The light at photo pixel (x, y), bilinear over the wall's cells:
    /// its R, G and B multipliers (without the relief) and the local
    /// average luma.
    fn at(&self, x: f32, y: f32) -> [f32; 4] {
        let (gx, gy) = self.grid.to_grid(x + 0.5, y + 0.5);
        let (w, h) = (self.grid.width, self.grid.height);
        let (fx, fy) = ((gx - 0.5).max(0.0), (gy - 0.5).max(0.0));
        let (x0, y0) = ((fx as usize).min(w - 1), (fy as usize).min(h - 1));
        let (x1, y1) = ((x0 + 1).min(w - 1), (y0 + 1).min(h - 1));
        let (tx, ty) = ((fx - x0 as f32).min(1.0), (fy - y0 as f32).min(1.0));
        let mut acc = [0.0f32; 4];
        let mut weight = 0.0;
        for (cx, cy, k) in [
            (x0, y0, (1.0 - tx) * (1.0 - ty)),
            (x1, y0, tx * (1.0 - ty)),
            (x0, y1, (1.0 - tx) * ty),
            (x1, y1, tx * ty),
        ] {
            let c = self.cells.get(cx, cy);
            if k > 0.0 && c[3] > 0.0 {
                weight += k;
                for (a, v) in acc.iter_mut().zip(c) {
                    *a += k * v;
                }
            }
        }
        match weight > 1e-6 {
            true => acc.map(|v| v / weight),
            false => self.fallback,
        }
    }
}

/// Lights each painted pixel of `layer` (alpha > 0): its colour times the
/// local light's strength and colour and the wall's relief there, its alpha
/// thicker in the recesses.
pub fn light(layer: &mut RgbaImage, photo: &Photo, light: &Light) {
    super::each_painted(layer, photo, |x, y, px, l| {
        let [r, g, b, l_low] = light.at(x as f32, y as f32);
        let relief = (l / l_low).clamp(RELIEF_RANGE.0, RELIEF_RANGE.1);
        for (c, g) in px[..3].iter_mut().zip([r, g, b]) {
            *c = crate::round::to_u8(*c as f32 * g * relief);
        }
        let thick = (1.0 + RECESS * (1.0 - relief)).clamp(0.6, 1.5);
        px[3] = crate::round::to_u8(px[3] as f32 * thick);
    });
}
