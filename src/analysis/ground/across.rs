//! The road across a shadow's edge. A stretch of the bottom row grows with
//! its own colour model and stops at a colour step ([`super::ground`]):
//! where a building's shadow lies across the road at the photo's foot, the
//! fill ends at the shadow's edge and the sunlit road beyond it, up to the
//! kerb, stays wall (madrid img_0828: rows 350-465 of 512, where the rain
//! took the kerb and the road's markings for sills and streaked the road
//! from them; puigpunyent IMG_4220). [`super::flat_ground`] misses such a
//! road when its near asphalt's grain runs every way (not flat) and the
//! shadow is blue under the open sky (too saturated for ground).

use super::super::perspective::oblique;
use super::crest::{MODEL_ROWS, Road, climb, with_rim};
use super::{JOINT_BAND, NARROW, OBLIQUE, median3, up_to_the_limit};

/// Grows the ground in `g` across the colour step its top stops at: in
/// each column, the first smooth, unsaturated wall pixel (`road.basic`)
/// within [`GAP`] rows above the column's highest ground is a seed (the
/// step's own pixels are textured). Each run of at least a [`NARROW`]th
/// of the width of seeded columns climbs ([`climb`]) with its own colour
/// model, the median of the ground-like pixels in the [`MODEL_ROWS`]th of
/// the height above its seeds (as the crest step reads it under the cut), on the terms the road past the flat
/// ground's cut is kept on (it lies flat, is not like what lies above it,
/// and loses what it climbed), runs oblique with its rim or alone
/// ([`runs_oblique`]), and stops below the 45% limit
/// ([`below_the_limit`]).
pub(super) fn past_the_step(road: &Road, stretches: &[bool], g: &mut [bool]) {
    let (w, h, top) = (road.f.w, road.f.h, road.top);
    let seed: Vec<Option<usize>> = (0..w).map(|x| seed_of(road, stretches, g, x)).collect();
    let mut x = 0;
    while x < w {
        let start = x;
        while x < w && seed[x].is_some() {
            x += 1;
        }
        if x - start >= (w / NARROW).max(1) {
            let seeds: Vec<usize> = seed[start..x].iter().flatten().copied().collect();
            if let Some(model) = model_above(road, g, &seeds) {
                climb(
                    road,
                    &seeds,
                    model,
                    top..h,
                    |p| runs_oblique(road, p) && below_the_limit(p, w, top),
                    g,
                );
            }
        }
        if x == start {
            x += 1;
        }
    }
}

/// Column `x`'s seed: the first pixel of `road.basic` not in `g` within
/// [`GAP`] rows above the highest pixel of `g` in the column, which lies
/// below the 45% limit.
fn seed_of(road: &Road, stretches: &[bool], g: &[bool], x: usize) -> Option<usize> {
    let (w, h, top) = (road.f.w, road.f.h, road.top);
    let y = (top + 1..h).find(|&y| stretches[y * w + x])?;
    if (y as f32) < h as f32 * JOINT_BAND {
        return None;
    }
    (y.saturating_sub(GAP).max(top)..y)
        .rev()
        .map(|y| y * w + x)
        .find(|&i| road.basic[i] && !g[i])
}

/// The median colour of the pixels of `road.basic` not in `g` in the
/// [`MODEL_ROWS`]th of the height above each seed; `None` when there are
/// none.
fn model_above(road: &Road, g: &[bool], seeds: &[usize]) -> Option<[f32; 3]> {
    let (w, h, top) = (road.f.w, road.f.h, road.top);
    let n = h / MODEL_ROWS;
    let mut v: Vec<[f32; 3]> = Vec::new();
    for &s in seeds {
        let (x, y) = (s % w, s / w);
        v.extend(
            (y.saturating_sub(n).max(top)..=y)
                .map(|y| y * w + x)
                .filter(|&i| road.basic[i] && !g[i])
                .map(road.at),
        );
    }
    (!v.is_empty()).then(|| median3(&mut v))
}

/// True when `part`'s gradients run oblique ([`OBLIQUE`], see
/// [`oblique`]) with its rim or alone: asphalt's grain runs every way, and
/// between a level kerb and a level shadow's edge the rim is level (madrid
/// img_0828's road 0.51 alone, 0.39 with the rim). Past the flat ground's
/// cut the rim must run oblique ([`super::crest`]): taking the part alone
/// there too kept cmp_b0123's plastered ground floor (0.41 alone, 0.39
/// with the rim) and lost two of its sills.
fn runs_oblique(road: &Road, part: &[bool]) -> bool {
    let (f, w, h) = (road.f, road.f.w, road.f.h);
    oblique(f, &with_rim(part, w, h)) > OBLIQUE || oblique(f, part) > OBLIQUE
}

/// True when at most [`AT_THE_LIMIT`] of `part`'s columns run up to the
/// `top` limit row: a road under a kerb ends at the kerb, below the
/// limit; the fill that runs up to the limit climbed a facade's smooth
/// ground floor between its windows (cmp_b0247, whose lower storey
/// turned ground up to the limit in 0.61 of the part's columns, cmp_b0123
/// 0.30).
fn below_the_limit(part: &[bool], w: usize, top: usize) -> bool {
    let (at_cap, cols) = up_to_the_limit(part, w, top);
    at_cap as f32 <= cols as f32 * AT_THE_LIMIT
}

/// The largest share of a climbed part's columns that may run up to the
/// 45% limit (measured: on LabelMeFacade train no part this climb keeps
/// reaches the limit in any column; cmp_b0123's 0.30 and cmp_b0247's 0.61
/// are a facade's ground floor).
const AT_THE_LIMIT: f32 = 0.1;

/// The step's own pixels (a shadow's soft edge, a seam) are textured and
/// not ground-like: the seed is looked for this many rows above the
/// ground's top.
const GAP: usize = 4;

#[cfg(test)]
mod tests {
    use super::super::tests::{classes_of, wall_in};

    /// The share of the road between a kerb (row 110 of 200) and a
    /// building's shadow across its foot (rows 172..) called wall: a 240 x
    /// 200 street, an orange wall over a pale pavement (rows 96..108), a
    /// dark kerb and a grey road whose faint grain runs oblique and lies
    /// flat (soft stripes across the view, three columns along per row
    /// down: sideways share 0.1, oblique share 0.6). The shadow is darker and its faint grain stands
    /// up, so the flat test cannot reach the road from the bottom row, and
    /// the bottom row's fill stops at the shadow's edge.
    fn shadowed_road() -> f32 {
        let (w, h) = (240usize, 200usize);
        let img = image::RgbImage::from_fn(w as u32, h as u32, |x, y| {
            image::Rgb(match y {
                ..96 => [204, 128, 76],
                96..108 => [190; 3],
                108..111 => [40; 3],
                172.. if x % 4 < 2 => [58; 3],
                172.. => [64; 3],
                _ => {
                    let phase = (x + 3 * y) as f32 * std::f32::consts::TAU / 36.0;
                    [(120.0 + 24.0 * phase.sin()) as u8; 3]
                }
            })
        });
        let class = classes_of(img);
        let wall = wall_in(&class, w, (0, w), (0, 90));
        assert!(wall > 0.99, "{wall} of the wall is wall");
        wall_in(&class, w, (0, w), (115, 165))
    }

    #[test]
    fn a_road_below_a_kerb_stays_ground_across_a_shadow_at_its_foot() {
        let road = shadowed_road();
        assert!(road < 0.2, "{road} of the road above the shadow is wall");
    }

    /// A part that runs up to the limit row (20 of 40) in half its
    /// columns climbed a ground floor; one whose top is a level kerb
    /// below the limit is a road.
    #[test]
    fn a_climb_up_to_the_limit_is_not_a_road_under_a_kerb() {
        let (w, h, top) = (40usize, 40usize, 20usize);
        let part = |kerb: fn(usize) -> usize| {
            let mut p = vec![false; w * h];
            for x in 0..w {
                (kerb(x)..h).for_each(|y| p[y * w + x] = true);
            }
            p
        };
        assert!(super::below_the_limit(&part(|_| 28), w, top));
        assert!(!super::below_the_limit(
            &part(|x| if x % 2 == 0 { 20 } else { 30 }),
            w,
            top
        ));
    }
}
