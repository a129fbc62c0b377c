//! Surface roughness from luminance, Chang, Yoshida & Mukai eq. (1):
//!
//! `M_x = |B(x,y) - (B(x+1,y) + B(x-1,y)) / 2| / 255`,
//! `M_y = |B(x,y) - B(x,y+1)| / 255`,
//!
//! with B the luminance in 0..255 and indices clamped at the edges. The
//! rain brakes and scatters droplets with it; moss grows where M_y is high.

use crate::field::{Field, Order};

/// Chang eq. (1) M_x of a pixel of luminance `b` between `left` and `right`.
#[inline(always)]
pub fn m_x(b: f32, left: f32, right: f32) -> f32 {
    (b - 0.5 * (right + left)).abs() / 255.0
}

/// Chang eq. (1) M_y of a pixel of luminance `b` above `below`.
#[inline(always)]
pub fn m_y(b: f32, below: f32) -> f32 {
    (b - below).abs() / 255.0
}

/// (M_x, M_y) at storage index `i` of a height field whose neighbours are
/// `across` indices away in x and `down` in y. The caller keeps `i` off the
/// edges (the rain's wall is padded with copies of its edge, which is eq.
/// 1's clamping).
#[inline(always)]
pub fn at(b: &[f32], i: usize, across: usize, down: usize) -> (f32, f32) {
    (
        m_x(b[i], b[i - across], b[i + across]),
        m_y(b[i], b[i + down]),
    )
}

/// M_y at (x, y) of a luminance field, the row below clamped to the last.
#[inline]
pub fn m_y_clamped<O: Order>(b: &Field<f32, O>, x: usize, y: usize) -> f32 {
    m_y(b.get(x, y), b.get(x, (y + 1).min(b.height() - 1)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::{ColumnMajor, RowMajor};

    #[test]
    fn matches_eq_1() {
        // 3 x 2, row-major: 10 20 60 / 10 30 70.
        let luma = [10.0, 20.0, 60.0, 10.0, 30.0, 70.0];
        let (mx, my) = at(&luma, 1, 1, 3);
        assert!((mx - (20.0f32 - 35.0).abs() / 255.0).abs() < 1e-6);
        assert!((my - 10.0 / 255.0).abs() < 1e-6);
        let rows = RowMajor::new(3, 2, luma.to_vec());
        let cols = ColumnMajor::from_fn(3, 2, |x, y| rows.get(x, y));
        assert_eq!(m_y_clamped(&rows, 1, 0), my);
        assert_eq!(m_y_clamped(&cols, 1, 0), my, "any storage order");
        assert_eq!(m_y_clamped(&rows, 2, 1), 0.0, "the last row is clamped");
    }
}
