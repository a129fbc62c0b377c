//! Twin ledges: like windows in one storey, or stacked in one column,
//! have the same sill detailing and the same exposure, so they stain
//! alike, not identically (`how-facades-age.md`, "Where water goes": the
//! pattern follows the building's geometry, and repeats where it does).
//!
//! [choice, beyond the per-ledge drain:] each ledge draws a log-normal
//! drain ([`super::sources`], `LEDGE_SPREAD`), so two twin sills shed up to
//! five times each other's water, and with the strength laid after the
//! film (`rain.after_film`) one window of a row showed a comb of dark
//! drips and its twin none (blind review 30, img_2308). Ledges are grouped
//! into families from their geometry alone ([`families`]): like kind,
//! like width, and either side by side at one level or stacked with like
//! spans; a family draws its drain once from the seed and each member
//! keeps a small share of its own ([`super::sources::TWIN_OWN`]), and a
//! family shares one sureness ([`Twins::sure`]). Each twin keeps its own
//! drip points, ends and onsets, so no two streak the same.

use crate::analysis::LedgeKind;

/// What a ledge is, for finding its twins.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kin {
    /// A sill or a window head [choice: one kin; the analysis names a
    /// window's lower frame either (img_2308: the left window's a sill,
    /// its twin's a window head)].
    Window,
    /// A cornice, coping, string course or roof line: bands.
    Band,
    /// A balcony slab.
    Balcony,
    /// A line the analysis did not find (a preset's or the user's own).
    Given,
}

impl Kin {
    fn of(kind: Option<LedgeKind>) -> Kin {
        match kind {
            Some(LedgeKind::Sill | LedgeKind::WindowHead) => Kin::Window,
            Some(LedgeKind::Balcony) => Kin::Balcony,
            Some(_) => Kin::Band,
            None => Kin::Given,
        }
    }
}

/// Where a ledge lies: its kin, its columns and its mean row.
#[derive(Debug, Clone, Copy)]
struct Extent {
    kin: Kin,
    x0: f32,
    x1: f32,
    y: f32,
}

impl Extent {
    /// The extent of polyline `line` (any units; `None` when empty).
    fn of(line: &[[f32; 2]], kind: Option<LedgeKind>) -> Option<Extent> {
        if line.is_empty() {
            return None;
        }
        let xs = line.iter().map(|p| p[0]);
        Some(Extent {
            kin: Kin::of(kind),
            x0: xs.clone().fold(f32::INFINITY, f32::min),
            x1: xs.fold(f32::NEG_INFINITY, f32::max),
            y: line.iter().map(|p| p[1]).sum::<f32>() / line.len() as f32,
        })
    }

    fn width(&self) -> f32 {
        self.x1 - self.x0
    }
}

/// The most two twins' widths differ, as a ratio [choice: 1.25, the
/// brief's "like width within ~25%": a row of like windows seen at an
/// angle shrinks a little from one to the next].
const WIDTH_RATIO: f32 = 1.25;

/// How far apart two twins in a row may lie vertically, in their mean
/// width [choice: 0.4, about a seventh of a storey for a 1.2 m window;
/// the storey from the scale is no yardstick (img_2308's scale gives a
/// 36 px storey where its windows stand 190 px tall), a window's width
/// is. It takes in a row seen at an angle and a window's frame found a
/// little higher than its twin's].
const LEVEL: f32 = 0.4;

/// How far the ends of two stacked twins may lie from each other's, in
/// their mean width [choice: 0.25, a window of one storey over the like
/// window of the next].
const SPAN: f32 = 0.25;

/// Whether `a` and `b` are twins: like kin and width, side by side at
/// one level or stacked with like spans.
fn twins(a: &Extent, b: &Extent) -> bool {
    let (narrow, wide) = (a.width().min(b.width()), a.width().max(b.width()));
    if a.kin != b.kin || narrow <= 0.0 || wide > WIDTH_RATIO * narrow {
        return false;
    }
    let width = 0.5 * (narrow + wide);
    let level = (a.y - b.y).abs() <= LEVEL * width;
    let apart = a.x1 < b.x0 || b.x1 < a.x0;
    let stacked = (a.x0 - b.x0).abs() <= SPAN * width && (a.x1 - b.x1).abs() <= SPAN * width;
    (level && apart) || (!level && stacked)
}

/// Per ledge, its family: the index of the family's first ledge (twins
/// of twins are one family).
fn families(extents: &[Option<Extent>]) -> Vec<usize> {
    let mut parent: Vec<usize> = (0..extents.len()).collect();
    fn root(parent: &[usize], mut i: usize) -> usize {
        while parent[i] != i {
            i = parent[i];
        }
        i
    }
    for i in 0..extents.len() {
        for j in i + 1..extents.len() {
            if let (Some(a), Some(b)) = (&extents[i], &extents[j])
                && twins(a, b)
            {
                let (ri, rj) = (root(&parent, i), root(&parent, j));
                parent[ri.max(rj)] = ri.min(rj);
            }
        }
    }
    (0..extents.len()).map(|i| root(&parent, i)).collect()
}

/// The least sureness ([`super::fall::sure`]) of a ledge with twins
/// [choice: 0.25, a confidence of 0.15 at `rain.sure_at` 0.6. A family
/// shares one sureness ([`Twins::sure`]); when it was the members' mean,
/// with no floor the bottom edge of a road sign (img_2308, confidence
/// 0.05) took its family's 0.8 and shed a streak down the post, and with
/// the least, one such edge would fade a whole row of sure sills; 182 of the 1344
/// twinned sills and window heads of the 100 LMF train photos are under
/// 0.1, 14% of them at a labelled window's edge (33% of those over 0.6)].
const LEAST_SURE: f32 = 0.25;

/// The rain's own stream (with `Effect::Rain`) for the families' drains.
const TWINS: u16 = 11;

/// The ledges' families and what they share.
#[derive(Debug, Clone, PartialEq)]
pub struct Twins {
    /// Per ledge, its family's first ledge.
    family: Vec<usize>,
    /// Per ledge, its family's standard normal draw for the drain; `None`
    /// for a ledge with no twin.
    draw: Vec<Option<f32>>,
}

impl Twins {
    /// The families of `lines` (photo pixels, `rain.source_lines`) of
    /// `kinds` (the analysis's, `None` for a given line) and sureness
    /// `sure` ([`super::fall::sure`]), drawn from `seed`; every ledge
    /// alone when not `on` (`rain.twins` off). A ledge less sure than
    /// [`LEAST_SURE`] has no twin.
    pub fn new(
        seed: u64,
        lines: &[Vec<[f32; 2]>],
        kinds: &[Option<LedgeKind>],
        sure: &[f32],
        on: bool,
    ) -> Twins {
        let family = match on {
            true => {
                let extents: Vec<_> = lines
                    .iter()
                    .enumerate()
                    .map(
                        |(i, l)| match sure.get(i).copied().unwrap_or(1.0) >= LEAST_SURE {
                            true => Extent::of(l, kinds.get(i).copied().flatten()),
                            false => None,
                        },
                    )
                    .collect();
                families(&extents)
            }
            false => (0..lines.len()).collect(),
        };
        let mut size = vec![0usize; lines.len()];
        family.iter().for_each(|&f| size[f] += 1);
        let draw = family
            .iter()
            .map(|&f| {
                (size[f] > 1).then(|| {
                    let stream = (crate::effects::Effect::Rain, TWINS);
                    // Keyed by the family's first line, not its number: a
                    // ledge found elsewhere does not re-deal the family.
                    let head: Vec<(f32, f32)> = lines[f].iter().map(|p| (p[0], p[1])).collect();
                    let key = super::sources::line_key(&head);
                    let mut rng = crate::random::rng(seed, stream, key, 0);
                    crate::random::box_muller(&mut rng).0
                })
            })
            .collect();
        Twins { family, draw }
    }

    /// Ledge `i`'s warp in its family ([`super::sources::Warp::in_family`]).
    pub fn warp(
        &self,
        i: usize,
        warp: Option<super::sources::Warp>,
    ) -> Option<super::sources::Warp> {
        match self.draw.get(i).copied().flatten() {
            Some(z) => warp.map(|w| w.in_family(z)),
            None => warp,
        }
    }

    /// Per ledge, how sure its family is: its least sure member's `sure`
    /// ([`super::fall::sure`]) [choice, by blind checks and measuring on
    /// the 100 LMF train photos (BENCHMARKS.md, twenty-third pass, twins25
    /// and the lead's p48/p49): the mean took the twins' ink's CV across a
    /// family from 0.414 to 0.322 with +1% total darkening and +5.4% under
    /// doubtful ledges, and lost blind check p48 (main better 4, twins 1: heavier streaks on a
    /// person and on signs the analysis called wall); the least takes the CV
    /// to 0.337 with -5% darkening (p49: twins better 4, main 3); the max to
    /// 0.326 but raised the ink under doubtful ledges 22% (film24's false
    /// ledges: streaks off a roof eave taken for a window head, IMG_0692)].
    pub fn sure(&self, sure: &[f32]) -> Vec<f32> {
        let family = |i: usize| self.family.get(i).copied().unwrap_or(i).min(sure.len() - 1);
        let mut least = vec![f32::INFINITY; sure.len()];
        for (i, &s) in sure.iter().enumerate() {
            let f = family(i);
            least[f] = least[f].min(s);
        }
        (0..sure.len()).map(|i| least[family(i)]).collect()
    }

    /// How many ledges have a twin.
    pub fn twinned(&self) -> usize {
        self.draw.iter().filter(|d| d.is_some()).count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(x0: f32, x1: f32, y: f32) -> Vec<[f32; 2]> {
        vec![[x0, y], [x1, y]]
    }

    #[test]
    fn a_row_and_a_column_of_like_windows_are_one_family() {
        let sill = Some(LedgeKind::Sill);
        let lines = [
            line(100.0, 160.0, 200.0),
            line(300.0, 362.0, 205.0), // its twin in the row
            line(500.0, 620.0, 200.0), // twice as wide: not
            line(102.0, 158.0, 400.0), // stacked under the first
            line(700.0, 760.0, 300.0), // a storey lower, elsewhere: not
            line(310.0, 350.0, 205.0), // overlaps the second: not
        ];
        let kinds = [sill; 6];
        let t = Twins::new(1, &lines, &kinds, &[1.0; 6], true);
        assert_eq!(t.family, [0, 0, 2, 0, 4, 5]);
        assert_eq!(t.twinned(), 3);
        let same = t.draw[0];
        assert!(same.is_some() && t.draw[1] == same && t.draw[3] == same);
        assert_eq!(t.draw[2], None);
        let off = Twins::new(1, &lines, &kinds, &[1.0; 6], false);
        assert_eq!(off.family, [0, 1, 2, 3, 4, 5]);
        assert_eq!(off.twinned(), 0);
        // A cornice is no sill's twin.
        let mixed = [sill, Some(LedgeKind::Cornice), sill, sill, sill, sill];
        assert_eq!(Twins::new(1, &lines, &mixed, &[1.0; 6], true).family[1], 1);
        // Nor is a ledge the analysis barely believes.
        let doubtful = [1.0, 0.2, 1.0, 1.0, 1.0, 1.0];
        let t = Twins::new(1, &lines, &kinds, &doubtful, true);
        assert_eq!(t.family, [0, 1, 2, 0, 4, 5]);
    }

    /// Twins' drains differ by a log standard deviation of about
    /// `0.8 * 0.3 * sqrt 2 = 0.34` (two lone ledges': 1.13), and a twin's
    /// drain keeps a lone ledge's mean of 1.
    #[test]
    fn twins_drain_alike_about_a_mean_of_one() {
        use super::super::sources::{Release, Warp};
        let release = Release {
            spacing: 20.0,
            width: 2.0,
            end_share: 0.5,
            uneven: 1.0,
            habits: false,
        };
        let warp = |seed: u64, k: u64| {
            let stream = (crate::effects::Effect::Rain, 1);
            let mut rng = crate::random::rng(seed, stream, k, 0);
            Warp::new(100.0, &release, &mut rng).unwrap()
        };
        let (mut lone, mut twin, mut drains) = (Vec::new(), Vec::new(), Vec::new());
        for seed in 0..2000 {
            let (a, b) = (warp(seed, 1), warp(seed, 2));
            lone.push((a.drain() / b.drain()).ln());
            let mut rng = crate::random::rng(seed, (crate::effects::Effect::Rain, TWINS), 1, 0);
            let z = crate::random::box_muller(&mut rng).0;
            let (a, b) = (a.in_family(z), b.in_family(z));
            twin.push((a.drain() / b.drain()).ln());
            drains.extend([a.drain(), b.drain()]);
        }
        let sd = |v: &[f32]| (v.iter().map(|x| x * x).sum::<f32>() / v.len() as f32).sqrt();
        let mean = drains.iter().sum::<f32>() / drains.len() as f32;
        assert!((1.0..1.25).contains(&sd(&lone)), "lone {}", sd(&lone));
        assert!((0.29..0.39).contains(&sd(&twin)), "twins {}", sd(&twin));
        assert!((0.92..1.08).contains(&mean), "mean drain {mean}");
        // With every drain 1 (`rain.uneven` 0) a family changes nothing.
        let even = Release {
            uneven: 0.0,
            ..release
        };
        let mut rng = crate::random::rng(1, (crate::effects::Effect::Rain, 1), 1, 0);
        let w = Warp::new(100.0, &even, &mut rng).unwrap();
        assert_eq!(w.clone().in_family(2.0), w);
    }

    #[test]
    fn a_family_shares_its_sureness() {
        let lines = [
            line(0.0, 50.0, 10.0),
            line(100.0, 150.0, 10.0),
            line(300.0, 400.0, 10.0),
        ];
        let t = Twins::new(3, &lines, &[Some(LedgeKind::Sill); 3], &[1.0; 3], true);
        let sure = t.sure(&[1.0, 0.5, 0.3]);
        assert_eq!(sure[0], sure[1]);
        assert_eq!(sure[2], 0.3);
    }
}
