//! The wall's foot against the labels: per photo column, the labelled
//! wall's lowest row with road or pavement right below it (a column where
//! a car or anything else stands between has no true foot); a claimed
//! foot is right within [`TOLERANCE`] of the height of it.

use super::{GROUND, WALL_LABEL};
use crate::analysis::Analysis;

/// A claimed foot is right this close to the true one, share of the
/// photo's height (as the ledges' tolerance).
pub const TOLERANCE: f32 = 0.015;

/// Rows of other labels (a label's anti-aliased edge, a thin gap between
/// two polygons) between the wall and the ground that still make a foot.
const LABEL_GAP: usize = 3;

/// The lines measured: the class map's lowest wall row over ground
/// ([`Analysis::class_foot_rows`]), the seen foot ([`Analysis::foot`])
/// and its stretches at least [`SURE`] sure ([`Analysis::foot_sure`]).
pub const LINES: [&str; 3] = ["class map's lowest wall", "seen foot", "sure seen foot"];

use crate::analysis::foot_line::SURE;

/// Sums over a set of photos, per line of [`LINES`].
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FootScore {
    /// Photo columns with a true foot.
    pub truth: u64,
    /// Columns where a foot is claimed.
    pub claimed: [u64; 3],
    /// Claimed columns within [`TOLERANCE`] of a true foot.
    pub right: [u64; 3],
    /// True foot columns with a claim within [`TOLERANCE`].
    pub found: [u64; 3],
}

/// Per column of a `w`-wide label image, the row of the labelled wall's
/// foot (the first row below the wall), if the wall stands on road or
/// pavement there.
pub fn true_foot(labels: &[u8], w: usize) -> Vec<Option<f32>> {
    let h = labels.len() / w.max(1);
    (0..w)
        .map(|x| {
            let at = |y: usize| labels[y * w + x];
            (1..h).rev().find_map(|y| {
                if at(y) != GROUND {
                    return None;
                }
                // The nearest row above that is not ground, within the gap.
                let top = (y.saturating_sub(LABEL_GAP + 1)..y)
                    .rev()
                    .find(|&r| at(r) == WALL_LABEL)?;
                let between_ok = (top + 1..y).all(|r| at(r) != super::CAR);
                (between_ok && at(y - 1) != GROUND).then_some((top + 1) as f32)
            })
        })
        .collect()
}

impl FootScore {
    /// Adds one photo: the analysis (`None`: nothing claimed) against the
    /// labels (`w` wide, `h` high).
    pub fn add(&mut self, a: Option<&Analysis>, labels: &[u8], w: u32, h: u32) {
        let truth = true_foot(labels, w as usize);
        let tol = TOLERANCE * h as f32;
        self.truth += truth.iter().flatten().count() as u64;
        let Some(a) = a else { return };
        let seen = a.foot_rows(w, h);
        let sure = (seen.iter().zip(a.foot_sure_rows(w)))
            .map(|(&y, s)| if s >= SURE { y } else { f32::NAN })
            .collect();
        for (k, line) in [a.class_foot_rows(w, h), seen, sure].iter().enumerate() {
            for (t, &y) in truth.iter().zip(line) {
                let near = t.is_some_and(|t| (t - y).abs() <= tol);
                self.claimed[k] += y.is_finite() as u64;
                self.right[k] += (y.is_finite() && near) as u64;
                self.found[k] += near as u64;
            }
        }
    }

    /// Share of line `k`'s claimed columns that are right.
    pub fn precision(&self, k: usize) -> f64 {
        self.right[k] as f64 / self.claimed[k].max(1) as f64
    }

    /// Share of the true foot's columns line `k` found.
    pub fn recall(&self, k: usize) -> f64 {
        self.found[k] as f64 / self.truth.max(1) as f64
    }

    /// The report's lines.
    pub fn report(&self) -> String {
        let mut s = String::new();
        for (k, name) in LINES.iter().enumerate() {
            s.push_str(&format!(
                "foot {name:24} precision {:.3} ({}/{}) recall {:.3} ({}/{})\n",
                self.precision(k),
                self.right[k],
                self.claimed[k],
                self.recall(k),
                self.found[k],
                self.truth
            ));
        }
        s
    }
}
