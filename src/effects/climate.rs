//! Sun and humidity on the wall (Riihiaho 2020, sec. 3.2), as maps on the
//! simulation grid that any effect can read: direct light (eq. 3.5),
//! indirect light (eq. 3.6) and humidity (eq. 3.8), all through the
//! sigmoid of eq. 3.7.
//!
//! In 2D: the normal comes from `--normal-map` when given, else from the
//! photo's shading read as relief; accessibility from how much darker a
//! pixel is than its surroundings (crevices, recesses) and, for the sky,
//! the rain shelter of the scene analysis; the height z is the distance
//! above the ground line (or the wall's foot) over the wall's height.

use rayon::prelude::*;

use super::Context;
use crate::field::RowMajor;
use crate::preset::ClimateParams;

/// The sigmoid of Riihiaho eq. 3.7: `S(x) = (x - s_o) / (2 sqrt(1/s_s +
/// (x - s_o)^2)) + 1/2`, offset `s_o`, steepness `s_s`.
pub fn sigmoid(x: f32, s_o: f32, s_s: f32) -> f32 {
    let d = x - s_o;
    d / (2.0 * (1.0 / s_s.max(1e-6) + d * d).sqrt()) + 0.5
}

/// The maps, grid-sized, all in 0..1.
#[derive(Debug, Clone)]
pub struct Climate {
    /// Direct light l_d (eq. 3.5).
    pub light: RowMajor<f32>,
    /// Indirect light l_i (eq. 3.6).
    pub indirect: RowMajor<f32>,
    /// Humidity h (eq. 3.8).
    pub humidity: RowMajor<f32>,
}

/// Direct light on the grid (eq. 3.5).
pub fn light(ctx: &Context, p: &ClimateParams) -> RowMajor<f32> {
    maps(ctx, p).light
}

/// Humidity on the grid (eq. 3.8): wetter near the ground, dried by air
/// and light.
pub fn humidity(ctx: &Context, p: &ClimateParams) -> RowMajor<f32> {
    maps(ctx, p).humidity
}

/// The sun's three vectors (eq. 3.5): the main one and two side ones of
/// power k1, elevation k2 θ and azimuth φ ± k3. Wall coordinates: x right,
/// y up, z out of the wall.
pub fn suns(p: &ClimateParams) -> [[f32; 3]; 3] {
    let v = |r: f32, el: f32, az: f32| {
        let (el, az) = (el.to_radians(), az.to_radians());
        [
            r * el.cos() * az.sin(),
            r * el.sin(),
            r * el.cos() * az.cos(),
        ]
    };
    let (el, az) = (p.sun_elevation, p.sun_azimuth);
    [
        v(1.0, el, az),
        v(p.k1, p.k2 * el, az + p.k3),
        v(p.k1, p.k2 * el, az - p.k3),
    ]
}

/// Unit normals per grid cell: the normal map's when given (tangent
/// space, green up), else the luminance read as height.
pub fn normals(ctx: &Context, relief: f32) -> Vec<[f32; 3]> {
    let (gw, gh) = (ctx.grid.width, ctx.grid.height);
    let luma = blur(ctx.luma, 1);
    (0..gw * gh)
        .into_par_iter()
        .map(|i| {
            let (x, y) = (i % gw, i / gw);
            let n = match ctx.normals {
                Some(map) => {
                    let (px, py) = ctx.grid.to_photo(x as f32 + 0.5, y as f32 + 0.5);
                    let q = map.get_pixel(
                        (px as u32).min(map.width() - 1),
                        (py as u32).min(map.height() - 1),
                    );
                    q.0.map(|c| c as f32 / 127.5 - 1.0)
                }
                None => {
                    let l = |x: usize, y: usize| luma.get(x, y) / 255.0;
                    let dx = l((x + 1).min(gw - 1), y) - l(x.saturating_sub(1), y);
                    // Rows grow downward; y is up.
                    let dy = l(x, y.saturating_sub(1)) - l(x, (y + 1).min(gh - 1));
                    [-relief * dx, -relief * dy, 1.0]
                }
            };
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt().max(1e-6);
            n.map(|c| c / len)
        })
        .collect()
}

/// Accessibility: 1 in the open, less where a cell is darker than its
/// surroundings within `radius` grid cells (a crevice, a recess).
fn accessibility(ctx: &Context, radius: usize) -> RowMajor<f32> {
    let around = blur(ctx.luma, radius);
    RowMajor::from_fn(ctx.grid.width, ctx.grid.height, |x, y| {
        (1.0 + (ctx.luma.get(x, y) - around.get(x, y)) / 96.0).clamp(0.0, 1.0)
    })
}

/// Light and humidity (eqs. 3.5-3.8).
pub fn maps(ctx: &Context, p: &ClimateParams) -> Climate {
    let (gw, gh) = (ctx.grid.width, ctx.grid.height);
    let n = normals(ctx, p.relief);
    let local = accessibility(ctx, (ctx.grid_px(0.1).round() as usize).max(1));
    let global = accessibility(ctx, (ctx.grid_px(1.0).round() as usize).max(2));
    let suns = suns(p);
    let height = heights(ctx);
    let cells: Vec<[f32; 3]> = (0..gw * gh)
        .into_par_iter()
        .map(|i| {
            let (x, y) = (i % gw, i / gw);
            let (px, py) = ctx.grid.to_photo(x as f32 + 0.5, y as f32 + 0.5);
            let shelter = ctx.site.shelter_at(px as u32, py as u32);
            // The sky is harder to reach under a ledge.
            let a_g = global.get(x, y) * (1.0 - 0.7 * shelter);
            let a_l = local.get(x, y);
            let dots: f32 = suns
                .iter()
                .map(|v| (v[0] * n[i][0] + v[1] * n[i][1] + v[2] * n[i][2]).max(0.0))
                .sum();
            let l_d = (p.light_scale * a_g * dots).clamp(0.0, 1.0);
            let l_i = p.light_scale * sigmoid(a_l, p.indirect_offset, p.indirect_steepness);
            let alpha = sigmoid(1.0 - height.get(x, y), p.ground_offset, p.ground_steepness)
                + p.base_humidity;
            let s = |v| sigmoid(v, p.indirect_offset, p.indirect_steepness);
            let beta = p.c1 * s(a_g) + p.c2 * l_d + p.c3 * l_i;
            let h = (p.humidity_scale * (alpha - beta)).clamp(0.0, 1.0);
            [l_d, l_i, h]
        })
        .collect();
    let map = |k: usize| RowMajor::new(gw, gh, cells.iter().map(|c| c[k]).collect());
    Climate {
        light: map(0),
        indirect: map(1),
        humidity: map(2),
    }
}

/// Height z per grid cell: 0 at the ground line (or the wall's foot in
/// that column), 1 at the wall's top in that column.
pub fn heights(ctx: &Context) -> RowMajor<f32> {
    let (gw, gh) = (ctx.grid.width, ctx.grid.height);
    let mut z = RowMajor::filled(gw, gh, 0.0);
    for x in 0..gw {
        let top = (0..gh).find(|&y| ctx.region.get(x, y)).unwrap_or(0) as f32;
        let foot = (0..gh)
            .rev()
            .find(|&y| ctx.region.get(x, y))
            .unwrap_or(gh - 1) as f32;
        let (px, _) = ctx.grid.to_photo(x as f32 + 0.5, 0.0);
        let ground = ctx
            .site
            .ground_at(px as u32)
            .map_or(foot + 1.0, |g| ctx.grid.to_grid(px, g).1);
        let span = (ground - top).max(1.0);
        for y in 0..gh {
            z.data_mut()[y * gw + x] = ((ground - y as f32 - 0.5) / span).clamp(0.0, 1.0);
        }
    }
    z
}

/// How much more (or less) an effect takes at each cell because of a
/// climate map `m` (humidity or light), by Riihiaho's environment
/// (sec. 3, `e = encourage - discourage`) with weight `k`: `1 + k (m / m_mean - 1)`, clamped to
/// [0, 2], with `m_mean` the map's mean over the region [choice: relative to
/// the wall's own mean, so the climate moves an effect around the wall
/// without changing how much of it there is; negative `k` discourages].
/// 1 everywhere when `k` is 0 or the map is 0 on the wall.
pub fn encouragement(m: &RowMajor<f32>, region: &RowMajor<bool>, k: f32) -> RowMajor<f32> {
    let mean = super::surface::wall_mean(m, region).unwrap_or(0.0);
    let values = m
        .data()
        .iter()
        .map(|&v| match mean > 1e-6 {
            true => (1.0 + k * (v / mean - 1.0)).clamp(0.0, 2.0),
            false => 1.0,
        })
        .collect();
    RowMajor::new(m.width(), m.height(), values)
}

/// Box blur of radius `r` (separable, clamped at the borders): a running
/// sum along each row, then one down the columns, a whole row at a time.
pub fn blur(v: &RowMajor<f32>, r: usize) -> RowMajor<f32> {
    let (w, h) = (v.width(), v.height());
    let n = (2 * r + 1) as f32;
    let mut rows = vec![0.0; w * h];
    rows.par_chunks_mut(w)
        .zip(v.data().par_chunks(w))
        .for_each(|(out, src)| {
            let at = |i: isize| src[i.clamp(0, w as isize - 1) as usize];
            let mut sum = 0.0;
            for i in -(r as isize)..=(r as isize) {
                sum += at(i);
            }
            for (i, o) in out.iter_mut().enumerate() {
                *o = sum / n;
                sum += at(i as isize + r as isize + 1) - at(i as isize - r as isize);
            }
        });
    let row = |y: isize| {
        let y = y.clamp(0, h as isize - 1) as usize;
        &rows[y * w..(y + 1) * w]
    };
    let mut sum = vec![0.0f32; w];
    for y in -(r as isize)..=(r as isize) {
        sum.iter_mut().zip(row(y)).for_each(|(s, v)| *s += v);
    }
    let mut out = vec![0.0; w * h];
    for (y, line) in out.chunks_exact_mut(w).enumerate() {
        let (add, drop) = (
            row(y as isize + r as isize + 1),
            row(y as isize - r as isize),
        );
        for (((o, s), a), d) in line.iter_mut().zip(sum.iter_mut()).zip(add).zip(drop) {
            *o = *s / n;
            *s += a - d;
        }
    }
    RowMajor::new(w, h, out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sigmoid_is_a_half_at_its_offset_and_steeper_with_s_s() {
        assert!((sigmoid(0.3, 0.3, 10.0) - 0.5).abs() < 1e-6);
        assert!(sigmoid(0.4, 0.3, 1000.0) > sigmoid(0.4, 0.3, 10.0));
        assert!(sigmoid(-5.0, 0.5, 100.0) < 0.01 && sigmoid(5.0, 0.5, 100.0) > 0.99);
    }

    #[test]
    fn a_sun_in_front_lights_a_flat_wall_and_side_suns_orbit_it() {
        let p = ClimateParams {
            sun_azimuth: 0.0,
            sun_elevation: 0.0,
            k1: 0.5,
            k3: 90.0,
            ..ClimateParams::default()
        };
        let s = suns(&p);
        assert!((s[0][2] - 1.0).abs() < 1e-6);
        assert!((s[1][0] - 0.5).abs() < 1e-5 && (s[2][0] + 0.5).abs() < 1e-5);
    }

    #[test]
    fn encouragement_follows_the_map_around_its_wall_mean() {
        let m = RowMajor::from_fn(4, 1, |x, _| [0.2, 0.4, 0.6, 0.0][x]);
        let region = RowMajor::from_fn(4, 1, |x, _| x < 3);
        let e = encouragement(&m, &region, 0.5);
        // Mean over the wall 0.4: below it less, above it more, the mean
        // cell unchanged; k = -0.5 mirrors it; k = 0 changes nothing.
        assert!((e.get(0, 0) - 0.75).abs() < 1e-5);
        assert!((e.get(1, 0) - 1.0).abs() < 1e-5);
        assert!((e.get(2, 0) - 1.25).abs() < 1e-5);
        let d = encouragement(&m, &region, -0.5);
        assert!((d.get(0, 0) - 1.25).abs() < 1e-5 && (d.get(2, 0) - 0.75).abs() < 1e-5);
        assert!(
            encouragement(&m, &region, 0.0)
                .data()
                .iter()
                .all(|&v| v == 1.0)
        );
        let dry = RowMajor::filled(4, 1, 0.0);
        assert!(
            encouragement(&dry, &region, 1.0)
                .data()
                .iter()
                .all(|&v| v == 1.0)
        );
    }

    #[test]
    fn a_box_blur_keeps_a_constant_and_the_mean() {
        let v = RowMajor::from_fn(9, 7, |x, y| (x * 3 + y) as f32);
        let b = blur(&RowMajor::filled(9, 7, 2.0), 2);
        assert!(b.data().iter().all(|&x| (x - 2.0).abs() < 1e-5));
        let m = |f: &RowMajor<f32>| f.data().iter().sum::<f32>() / 63.0;
        assert!((m(&blur(&v, 1)) - m(&v)).abs() < 1.0);
    }
}
