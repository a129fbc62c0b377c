//! The shape of a ledge's top band in the photo: the straight line it
//! follows, how sure that line is a ledge, and how soft its edges are.
//!
//! A ledge is a straight edge on the building, so a straight line in the
//! photo (a pinhole camera keeps lines straight): a found polyline that
//! bends (an arc over a sign's lettering, a V across it) is not a ledge,
//! and one that wobbles a pixel is a straight ledge found with noise. The
//! band follows the line fitted to it, and is as soft as the photo's own
//! edge there: a ledge's dirt in a photo is a few pixels of soft dark,
//! never sharper than the ledge's edge it lies on (blind review p55: "thin,
//! crisp dark lines ... sharper than anything else in this soft photo").

use crate::effects::Context;

/// How far a polyline may stray from its fitted line and still be a
/// straight ledge, photo pixels, or this share of its length if more
/// [choice: the analysis's polylines step by a pixel or two on a straight
/// sill; art738's "roof lines" over a sign's lettering stray 5-9 px over
/// 70-150 px].
pub const BEND_OK_PX: f32 = 1.5;

/// The same as a share of the polyline's length (a long ledge in a wide
/// lens bows a little).
pub const BEND_OK_SHARE: f32 = 0.005;

/// At this many times the allowed stray a polyline is no ledge at all
/// (its band gone); between, its band fades linearly.
pub const BEND_DROP: f32 = 2.0;

/// The softest a band's edge may be, photo pixels (the width its edges
/// ramp over): the sharpest photo's ledge edge is still a pixel and a half
/// to two wide once demosaiced and compressed, and a ledge top's dirt is
/// seen over a pixel of the drip edge's own rounding [choice: 1 px drew
/// the hairlines p55 named; 2 px still a dark line on dsc07036's
/// balconies at 400%].
pub const SOFT_MIN_PX: f32 = 2.5;

/// The softest edge used, photo pixels (past it the photo's edge is a
/// shadow's or a blur's, not the ledge's).
pub const SOFT_MAX_PX: f32 = 6.0;

/// Rows each side of the line the photo's edge width is measured over,
/// grid cells.
const EDGE_REACH: i64 = 4;

/// The least contrast (luma levels) across a ledge at a column for its
/// edge width to be read there.
const EDGE_CONTRAST: f32 = 12.0;

/// A ledge's polyline as the straight line `row = a + b x` through it
/// (least squares over its vertices), and how far a vertex strays from
/// it at most, photo pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fit {
    /// The row at column 0.
    pub a: f32,
    /// Rows per column.
    pub b: f32,
    /// The farthest a vertex lies from the line, pixels.
    pub stray: f32,
}

impl Fit {
    /// The fitted line's row at column `x`.
    pub fn row(&self, x: f32) -> f32 {
        self.a + self.b * x
    }
}

/// The least-squares line through `line`'s vertices (at least two).
pub fn fit(line: &[[f32; 2]]) -> Fit {
    let n = line.len().max(1) as f32;
    let mx = line.iter().map(|p| p[0]).sum::<f32>() / n;
    let my = line.iter().map(|p| p[1]).sum::<f32>() / n;
    let sxx: f32 = line.iter().map(|p| (p[0] - mx).powi(2)).sum();
    let sxy: f32 = line.iter().map(|p| (p[0] - mx) * (p[1] - my)).sum();
    let b = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    let a = my - b * mx;
    let stray = line
        .iter()
        .map(|p| (p[1] - (a + b * p[0])).abs())
        .fold(0.0, f32::max);
    Fit { a, b, stray }
}

/// How sure a polyline is a straight ledge, 0..1: 1 while its stray is
/// within [`BEND_OK_PX`] (or [`BEND_OK_SHARE`] of its length), 0 from
/// [`BEND_DROP`] times that.
pub fn straight(fit: &Fit, length: f32) -> f32 {
    let ok = BEND_OK_PX.max(BEND_OK_SHARE * length);
    (1.0 - (fit.stray - ok) / ((BEND_DROP - 1.0) * ok)).clamp(0.0, 1.0)
}

/// How wide the photo's own edge is along a ledge, photo pixels: at each
/// grid column along the fitted line, the luma's range over the rows
/// [`EDGE_REACH`] cells either side over its steepest one-cell step (a
/// step blurred by a Gaussian of sigma s measures 2.5 s); the median over
/// the columns with contrast, clamped to [`SOFT_MIN_PX`]..[`SOFT_MAX_PX`].
pub fn edge_width(ctx: &Context, fit: &Fit, first: f32, last: f32) -> f32 {
    let (w, h) = (ctx.grid.width as i64, ctx.grid.height as i64);
    let (g0, _) = ctx.grid.to_grid(first, 0.0);
    let (g1, _) = ctx.grid.to_grid(last, 0.0);
    let mut widths = Vec::new();
    for gx in (g0.floor().max(0.0) as i64)..=(g1.ceil().min((w - 1) as f32) as i64) {
        let (x, _) = ctx.grid.to_photo(gx as f32 + 0.5, 0.0);
        let (_, gy) = ctx.grid.to_grid(x, fit.row(x));
        let gy = gy.round() as i64;
        if gy - EDGE_REACH < 0 || gy + EDGE_REACH >= h {
            continue;
        }
        let col: Vec<f32> = (gy - EDGE_REACH..=gy + EDGE_REACH)
            .map(|y| ctx.luma.data()[(y * w + gx) as usize])
            .collect();
        let (lo, hi) = col
            .iter()
            .fold((f32::MAX, f32::MIN), |(lo, hi), v| (lo.min(*v), hi.max(*v)));
        let steep = col
            .windows(2)
            .map(|p| (p[1] - p[0]).abs())
            .fold(0.0, f32::max);
        if hi - lo >= EDGE_CONTRAST && steep > 0.0 {
            widths.push((hi - lo) / steep * ctx.grid.scale);
        }
    }
    if widths.is_empty() {
        return SOFT_MIN_PX;
    }
    widths.sort_by(f32::total_cmp);
    widths[widths.len() / 2].clamp(SOFT_MIN_PX, SOFT_MAX_PX)
}

/// How much of a ledge's top band covers a pixel whose centre is `above`
/// pixels above the ledge's drip line, for a band `depth` pixels deep
/// seen through an edge `soft` pixels wide: the band, from half a pixel
/// below the line to `depth` above it, averaged over `soft` pixels about
/// the pixel (a box blur: each edge ramps linearly over `soft` pixels, and
/// a band thinner than `soft` is as much paler and wider, its dirt spread
/// as the photo spreads a thin dark line, not drawn as a hairline).
pub fn across(above: f32, depth: f32, soft: f32) -> f32 {
    let soft = soft.max(1.0);
    let (lo, hi) = (-0.5, depth.max(0.0));
    let overlap = (above + soft / 2.0).min(hi) - (above - soft / 2.0).max(lo);
    (overlap / soft).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_straight_ledge_is_sure_and_a_bent_one_is_dropped() {
        let flat = [[0.0, 100.0], [50.0, 101.0], [100.0, 100.0], [150.0, 101.0]];
        let f = fit(&flat);
        assert!(f.stray < 1.0);
        assert_eq!(straight(&f, 150.0), 1.0, "a pixel's wobble is a ledge");
        // art738's "roof line" over a sign: a step of 9 px in 150.
        let bent = [
            [0.0, 132.0],
            [10.0, 123.0],
            [40.0, 119.0],
            [60.0, 124.0],
            [150.0, 124.0],
        ];
        let f = fit(&bent);
        assert_eq!(straight(&f, 150.0), 0.0, "stray {}", f.stray);
        // A V across a sign's lettering.
        let v = [[0.0, 118.0], [30.0, 118.0], [50.0, 129.0], [70.0, 129.0]];
        assert_eq!(straight(&fit(&v), 70.0), 0.0);
    }

    #[test]
    fn the_fitted_line_follows_a_sloping_ledge() {
        let f = fit(&[[0.0, 10.0], [100.0, 20.0]]);
        assert!((f.row(50.0) - 15.0).abs() < 1e-4);
        assert!(f.stray < 1e-4);
    }

    #[test]
    fn the_band_is_soft_and_sits_on_the_line() {
        let (depth, soft) = (2.0, 2.5);
        assert!(across(0.75, depth, soft) > 0.75, "strong in its middle");
        assert!(
            (across(-0.5, depth, soft) - 0.5).abs() < 1e-6,
            "half at its bottom"
        );
        assert!(
            (across(depth, depth, soft) - 0.5).abs() < 1e-6,
            "half at its top"
        );
        assert_eq!(across(-2.0, depth, soft), 0.0, "below the ledge");
        assert_eq!(across(depth + 1.5, depth, soft), 0.0, "above the band");
        // Its edges ramp over `soft` pixels: no step of more than
        // 1 / soft of the band's strength from one pixel to the next.
        for i in -4..6 {
            let (a, b) = (
                across(i as f32, depth, soft),
                across(i as f32 + 1.0, depth, soft),
            );
            assert!((a - b).abs() <= 1.0 / soft + 1e-6, "{i}: {a} -> {b}");
        }
        // A band thinner than the photo's edge is paler and wider, its
        // dirt the same: a pixel's 1.5 px band through a 4 px edge.
        let thin = |y: f32| across(y, 1.0, 4.0);
        assert!(thin(0.25) < 0.5);
        let sum: f32 = (-8..8).map(|i| thin(i as f32)).sum();
        assert!((sum - 1.5).abs() < 0.01, "{sum}");
    }
}
