//! Where droplets start: the top edge of the region and user source lines,
//! and where along them water leaves ([`Release`]).
//!
//! [choice, beyond Chang, who starts droplets uniformly along a source:]
//! run-off concentrates (Verhoef; `how-facades-age.md`): a ledge collects
//! water and releases it at a few points, the two ends of a sill and drip
//! points along a long cornice, so a wall shows separate streaks, not an
//! even comb. A source's release density is a mixture of Gaussians of
//! width [`Release::width`] at its two ends (weight `end_share`) and at
//! drip points about `spacing` apart (drawn from the seed), over a small
//! uniform floor; Chang's start position u (eqs. 16-17 walk it between
//! rainfalls) is mapped through the density's inverse CDF, so droplets
//! that start near each other stay in the same streak.
//!
//! [choice:] how much water a drip point gathers differs a lot along a real
//! ledge (it is never level: low points drain long stretches), so a drip's
//! share is log-normal ([`DRIP_SPREAD`]), and the [`Warp`] also tabulates
//! each point's water in metres of ledge drained per drip spacing
//! ([`Warp::water`]), which sets its streak's length (`fall.rs`), and where
//! the water meets the wall below the ledge ([`Warp::onset`]).
//!
//! [choice:] how dark a streak reads follows its water too
//! ([`Warp::strength`], `rain.uneven`). The dirt film (`stain.rs`) takes
//! every streak fed by more than a trickle to the same dark within a few
//! of fifty years' forty rainfalls, so the log-normal shares above showed
//! only in the streaks' lengths: blind checks p31-p34 saw "one
//! icicle-shaped drip under every edge, full dark at the edge, evenly
//! spaced". Each ledge also drains a log-normal share of the rain it
//! catches ([`LEDGE_SPREAD`]: a drip edge throws water clear, a ledge tilted
//! back sends it all down the face), and a streak's stain is scaled by its
//! water over [`FULL_WATER`] (at most 1), laid after the film
//! (`rain.after_film`: `fall.rs`), so a few streaks keep their darkness
//! and the many fed by little water are faint in proportion, narrow (the
//! flanks of a release point get less water than its centre) or gone.

/// How a ledge releases its water, in grid pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Release {
    /// Mean spacing of drip points along a ledge; 0 = uniform release
    /// (Chang's own).
    pub spacing: f32,
    /// Standard deviation of a release point: a streak's width at its top.
    pub width: f32,
    /// Share of a source's water released at its two ends.
    pub end_share: f32,
    /// How unequal the streaks' strength is: the power of a release
    /// point's water its stain's strength follows ([`Warp::strength`]);
    /// 0 = every streak at full strength.
    pub uneven: f32,
    /// Whether each ledge draws its own habit (`habit.rs`: a tilt, its
    /// drip points' spacing, a wash), `rain.habits`.
    pub habits: bool,
}

impl Release {
    /// Chang's own: droplets start anywhere along a source.
    pub const UNIFORM: Release = Release {
        spacing: 0.0,
        width: 1.0,
        end_share: 0.0,
        uneven: 0.0,
        habits: false,
    };
}

/// Share of the water released uniformly along a source (diffuse run-off).
const FLOOR: f32 = 0.04;

/// Standard deviation of a drip point's log water share [choice: 0.9, a
/// coefficient of variation of 1.5; with the uniform 0.3..1 of before, the
/// drips under a string course held nearly equal water and left a comb of
/// equal streaks (blind review 13); with it and the streak lengths of
/// `fall.rs`, the streak lengths' CV under the long ledge of
/// `tests/streaks.rs` rose from 0.03 to 0.22].
const DRIP_SPREAD: f32 = 0.9;

/// Standard deviation of a release point's log width [choice: 0.4, so
/// one streak starts twice as wide as its neighbour about one time in
/// four; with one width for all, the streaks under a row of sills and
/// along siding read as stamped columns of equal width (blind review 21,
/// tell 3)]; at most [`WIDEST`] times the mean width, at least its
/// inverse.
const WIDTH_SPREAD: f32 = 0.4;

/// The widest release point, in mean release widths.
const WIDEST: f32 = 2.5;

/// Standard deviation of the log share of a ledge's two ends [choice: 0.5:
/// no sill is level, so one end of it drains more, and its streak runs
/// longer (`fall.rs`); with equal halves every sill shed a pair of equal
/// streaks (blind review 21, tell 3)].
const END_SPREAD: f32 = 0.5;

/// A release point's width, in mean release widths (log-normal).
fn width_factor(rng: &mut crate::random::Rng) -> f32 {
    let (z, _) = crate::random::box_muller(rng);
    (WIDTH_SPREAD * z).exp().clamp(1.0 / WIDEST, WIDEST)
}

/// The closest two drip points come, as a share of the mean spacing
/// [choice: gaps are this plus an exponential share of the rest, a
/// coefficient of variation of 0.7; with uniform gaps of 0.5..1.5 (0.29)
/// a cornice still shed a comb of evenly spaced streaks (blind review 16)].
const CLOSEST: f32 = 0.3;

/// Standard deviation of a ledge's log drain, the factor on the water its
/// release points shed (mean 1) [choice: 0.8. A ledge is never level and
/// never like its neighbour: one with a working drip edge throws its water
/// clear of the wall, one tilted back or cracked sends all of it down the
/// face (`how-facades-age.md`, "Where water goes"); with every ledge
/// draining its share, every sill of a row shed the same pair of streaks
/// (blind checks p31-p34: "the same drip under every edge")].
const LEDGE_SPREAD: f32 = 0.8;

/// A ledge's drain from the standard normal draw `z`: log-normal with
/// spread [`LEDGE_SPREAD`] and mean 1.
fn drain_of(z: f32) -> f32 {
    (LEDGE_SPREAD * z - 0.5 * LEDGE_SPREAD * LEDGE_SPREAD).exp()
}

/// The share of a twin ledge's log drain that is its own, the rest its
/// family's (`twins.rs`) [choice: 0.3, so two twins' drains differ by a
/// log standard deviation of `0.8 * 0.3 * sqrt 2 = 0.34` (within 1.4x two
/// times in three) instead of `0.8 * sqrt 2 = 1.13` (up to ~5x): blind
/// review 30, "a comb of like drips under one window and none under its
/// twin"; each twin still has its own drip points, ends and onsets].
pub const TWIN_OWN: f32 = 0.3;

/// The water ([`Warp::water`], times the ledge's drain and catch) whose
/// stain shows at full strength [choice: 0.3, about the median drip's
/// share of a level ledge; at 1 (a drip's fair share) the streaks of
/// eight street photos lost half their darkening and whole string
/// courses went clean (BENCHMARKS.md, twentieth pass). With the strength
/// laid after the dirt film (`rain.after_film`), 0.8 with `rain.uneven` 2
/// and a 3x coverage before the film made the strong streaks' cores too
/// dark and hard (blind pairwise p39-p40: main's look better 11 to 4);
/// 0.3 with `uneven` 1 keeps the strong streaks as they were and only the
/// weak ones fainter (p41: better 3, worse 1, equal 6; twenty-second
/// pass)].
const FULL_WATER: f32 = 0.3;

/// How far the water is spread for [`Warp::water`], in release widths: a
/// streak's water is the same across its width.
const WATER_SPREAD: f32 = 3.0;

/// Spacing of the onset's knots along a ledge, in release widths: where
/// drips meet the wall changes over a few streak widths.
const ONSET_KNOTS: f32 = 4.0;

/// The inverse CDF of a source's release density, tabulated per grid pixel
/// of its length: `at(u)` maps a uniform position in `0..len` to where the
/// droplet leaves; with each position's water and onset.
#[derive(Debug, Clone, PartialEq)]
pub struct Warp {
    /// Position (0..len) at each of `len + 1` evenly spaced CDF values.
    inverse: Vec<f32>,
    /// Per grid pixel along the source: the water leaving there, as the
    /// length of ledge its release point drains over the drip spacing or
    /// the ledge's length if shorter (1 = a drip's fair share of a level
    /// ledge), spread over a streak's width.
    water: Vec<f32>,
    /// Per grid pixel along the source: how far below the ledge its water
    /// meets the wall, 0..1 of the onset length (smooth noise).
    onset: Vec<f32>,
    /// How much of the rain reaching it this ledge drains through its
    /// release points ([`LEDGE_SPREAD`]); 1 when [`Release::uneven`] is 0.
    drain: f32,
    /// The standard normal draw the drain is made from (0 when
    /// [`Release::uneven`] is 0).
    drain_z: f32,
    /// [`Release::uneven`].
    uneven: f32,
}

impl Warp {
    /// The warp of a source `len` pixels long; `rng` draws its drip points.
    pub fn new(len: f32, r: &Release, rng: &mut crate::random::Rng) -> Option<Warp> {
        Warp::with_habit(len, r, &Habit::LEVEL, rng)
    }

    /// The warp of a source `len` pixels long shedding its water by
    /// `habit` (`habit.rs`); `rng` draws its drip points.
    pub fn with_habit(
        len: f32,
        r: &Release,
        habit: &Habit,
        rng: &mut crate::random::Rng,
    ) -> Option<Warp> {
        use rand::Rng as _;
        if r.spacing <= 0.0 || len < 1.0 {
            return None;
        }
        let n = len.ceil() as usize + 1;
        // Release points (centre, weight, width factor); the two ends
        // share theirs unequally (no ledge is level), the more so by the
        // ledge's tilt.
        let (z0, z1) = crate::random::box_muller(rng);
        let ends = habit.tilted([z0, z1].map(|z| (END_SPREAD * z).exp()));
        let end = |k: usize| ends[k] / (ends[0] + ends[1]);
        let mut points = vec![
            (0.0, r.end_share * end(0), width_factor(rng)),
            (len, r.end_share * end(1), width_factor(rng)),
        ];
        let drips = drips(len, r.spacing * habit.spacing, rng);
        let drip_total: f32 = drips.iter().map(|d| d.1).sum();
        let drip_share = 1.0 - r.end_share.clamp(0.0, 1.0);
        if drip_total > 0.0 {
            points.extend(
                drips
                    .iter()
                    .map(|&(c, w, f)| (c, w / drip_total * drip_share, f)),
            );
        } else {
            // A ledge shorter than the spacing sheds everything at its ends.
            points
                .iter_mut()
                .enumerate()
                .for_each(|(k, p)| p.1 = end(k));
        }
        let width = r.width.max(0.5);
        if let Some(wash) = habit.wash_point(len, width) {
            // The wash takes its share of the water from every point.
            points.iter_mut().for_each(|p| p.1 *= 1.0 - wash.1);
            points.push(wash);
        }
        let mix = |u: f32, width: f32| -> f32 {
            points
                .iter()
                .map(|&(c, w, f)| {
                    let width = width * f;
                    let z = (u - c) / width;
                    w * (-0.5 * z * z).exp() / (width * 2.506_628)
                })
                .sum()
        };
        let density: Vec<f64> = (0..n)
            .map(|i| (FLOOR / len + (1.0 - FLOOR) * mix(i as f32, width)) as f64)
            .collect();
        // A point of share w drains w * len of ledge; its peak in the
        // spread mixture is w / (spread * sqrt(2 pi)). A fair share is the
        // spacing, or the whole ledge when it is shorter.
        let spread = WATER_SPREAD * width;
        let fair = r.spacing.min(len);
        let water = (0..n)
            .map(|i| mix(i as f32, spread) * spread * 2.506_628 * len / fair)
            .collect();
        let knot = ONSET_KNOTS * width;
        let knots: Vec<f32> = (0..=(len / knot).ceil() as usize + 1)
            .map(|_| rng.random())
            .collect();
        let onset = (0..n)
            .map(|i| {
                let g = i as f32 / knot;
                let k = (g as usize).min(knots.len() - 2);
                let t = (g - k as f32).clamp(0.0, 1.0);
                let t = crate::random::smoothstep(t);
                knots[k] + (knots[k + 1] - knots[k]) * t
            })
            .collect();
        let mut cdf = Vec::with_capacity(n);
        let mut total = 0.0;
        for d in &density {
            total += d;
            cdf.push(total);
        }
        let inverse = (0..=n)
            .map(|k| {
                let target = total * k as f64 / n as f64;
                let i = cdf.partition_point(|&c| c < target).min(n - 1);
                let below = if i == 0 { 0.0 } else { cdf[i - 1] };
                let t = ((target - below) / density[i].max(1e-12)).clamp(0.0, 1.0);
                ((i as f64 - 0.5 + t) as f32).clamp(0.0, len)
            })
            .collect();
        // Drawn last: the drip points and onsets are those of before.
        let (z, _) = crate::random::box_muller(rng);
        let (drain, drain_z) = match r.uneven > 0.0 {
            true => (drain_of(z), z),
            false => (1.0, 0.0),
        };
        Some(Warp {
            inverse,
            water,
            onset,
            drain,
            drain_z,
            uneven: r.uneven.max(0.0),
        })
    }

    /// This warp's ledge in a family of twins (`twins.rs`) whose shared
    /// standard normal draw is `family`: its drain is drawn from that
    /// draw, times its own by a share [`TWIN_OWN`], with the log spread
    /// and mean of a lone ledge's. Nothing changes when [`Release::uneven`]
    /// is 0 (every drain 1).
    pub fn in_family(mut self, family: f32) -> Warp {
        if self.uneven > 0.0 {
            let shared = (1.0 - TWIN_OWN * TWIN_OWN).sqrt();
            self.drain_z = shared * family + TWIN_OWN * self.drain_z;
            self.drain = drain_of(self.drain_z);
        }
        self
    }

    /// Where a droplet at uniform position `u` (0..len) leaves the source.
    pub fn at(&self, u: f32, len: f32) -> f32 {
        let n = self.inverse.len() - 1;
        let g = (u / len.max(1e-6) * n as f32).clamp(0.0, n as f32);
        let i = (g as usize).min(n - 1);
        let t = g - i as f32;
        self.inverse[i] + (self.inverse[i + 1] - self.inverse[i]) * t
    }

    /// The water leaving at arc length `u` (see [`Warp::water`]'s field).
    pub fn water(&self, u: f32) -> f32 {
        sample(&self.water, u)
    }

    /// Where the water leaving at arc length `u` meets the wall, 0..1 of
    /// the onset length.
    pub fn onset(&self, u: f32) -> f32 {
        sample(&self.onset, u)
    }

    /// The ledge's drain ([`LEDGE_SPREAD`]): a factor on its water.
    pub fn drain(&self) -> f32 {
        self.drain
    }

    /// How strong the stain of a release point's `water` is, 0..1: that
    /// water (its [`Warp::water`] times the ledge's drain and catch) over
    /// [`FULL_WATER`], at most 1, to the power [`Release::uneven`]; 1
    /// whatever the water when that is 0.
    pub fn strength(&self, water: f32) -> f32 {
        if self.uneven <= 0.0 {
            return 1.0;
        }
        (water / FULL_WATER).min(1.0).powf(self.uneven)
    }
}

/// The drip points along a ledge `len` long: (position, share of the
/// drips' water before normalising), about `spacing` apart.
fn drips(len: f32, spacing: f32, rng: &mut crate::random::Rng) -> Vec<(f32, f32, f32)> {
    use rand::Rng as _;
    let mut drips = Vec::new();
    let mut x = spacing * rng.random_range(0.2..1.0);
    while x < len - 0.2 * spacing {
        let (z, _) = crate::random::box_muller(rng);
        drips.push((x, (DRIP_SPREAD * z).exp(), width_factor(rng)));
        let exp = -(1.0 - rng.random::<f32>()).ln();
        x += spacing * (CLOSEST + (1.0 - CLOSEST) * exp);
    }
    drips
}

/// `table` (one value per grid pixel) at `u`, clamped to its ends.
fn sample(table: &[f32], u: f32) -> f32 {
    let i = (u.max(0.0).round() as usize).min(table.len() - 1);
    table[i]
}

/// A source line's own key (grid coordinates, each vertex rounded to the
/// pixel): the same line gives the same draws whatever other lines there
/// are ([`super::owners`]); never 0, the top edge's.
pub fn line_key(line: &[(f32, f32)]) -> u64 {
    let key = line.iter().fold(0x9e37_79b9_7f4a_7c15u64, |h, &(x, y)| {
        let (x, y) = (x.round() as i64 as u64, y.round() as i64 as u64);
        crate::random::mix(crate::random::mix(h ^ x) ^ y)
    });
    key.max(1)
}

/// The warp of a source line with key `key` ([`line_key`]) `len` grid
/// pixels long, from the rain's own stream: the simulation and the stain
/// draw the same drip points.
pub fn line_warp(seed: u64, key: u64, len: f32, release: &Release) -> Option<Warp> {
    let mut rng = crate::random::rng(seed, (crate::effects::Effect::Rain, RELEASE), key, 0);
    let habit = Habit::of(seed, RELEASE, key, release.habits);
    Warp::with_habit(len, release, &habit, &mut rng)
}

/// The warp of the region's top edge.
pub fn top_warp(seed: u64, len: f32, release: &Release) -> Option<Warp> {
    let mut rng = crate::random::rng(seed, (crate::effects::Effect::Rain, RELEASE), 0, 0);
    let habit = Habit::of(seed, RELEASE, 0, release.habits);
    Warp::with_habit(len, release, &habit, &mut rng)
}

/// The rain's own stream (with `Effect::Rain`) for each source's drip
/// points.
const RELEASE: u16 = 1;

use super::habit::Habit;

/// One water source on the padded grid.
#[derive(Debug, Clone)]
pub enum Source {
    /// The region's top edge: for each grid column, the first region row.
    TopEdge(Vec<(f32, f32)>),
    /// A polyline (a sill or a cornice); droplets start just below it.
    Line {
        /// Vertices, padded grid coordinates.
        points: Vec<(f32, f32)>,
        /// Cumulative length at each vertex.
        lengths: Vec<f32>,
    },
}

impl Source {
    /// A polyline source.
    pub fn line(points: Vec<(f32, f32)>) -> Source {
        let mut lengths = vec![0.0];
        for pair in points.windows(2) {
            let d = ((pair[1].0 - pair[0].0).powi(2) + (pair[1].1 - pair[0].1).powi(2)).sqrt();
            lengths.push(lengths.last().copied().unwrap_or(0.0) + d);
        }
        Source::Line { points, lengths }
    }

    /// Length along which droplets start, in grid pixels.
    pub fn length(&self) -> f32 {
        match self {
            Source::TopEdge(cols) => cols.len() as f32,
            Source::Line { lengths, .. } => lengths.last().copied().unwrap_or(0.0),
        }
    }

    /// The start point at arc length `u` (clamped into the source).
    pub fn point(&self, u: f32) -> (f32, f32) {
        match self {
            Source::TopEdge(cols) => {
                let u = u.clamp(0.0, cols.len() as f32 - 1e-3);
                let (x, y) = cols[u as usize];
                (x + u.fract(), y + 0.5)
            }
            Source::Line { points, lengths } => {
                let total = lengths.last().copied().unwrap_or(0.0);
                let u = u.clamp(0.0, total);
                let k = lengths
                    .partition_point(|&l| l <= u)
                    .clamp(1, points.len() - 1);
                let (a, b) = (points[k - 1], points[k]);
                let seg = (lengths[k] - lengths[k - 1]).max(1e-6);
                let t = ((u - lengths[k - 1]) / seg).clamp(0.0, 1.0);
                // One pixel below the line: water drips off the ledge's lower edge.
                (a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t + 1.0)
            }
        }
    }
}

/// The region's top edge on the padded grid: (x, first region row) per column.
pub fn top_edge(wall: &Wall) -> Vec<(f32, f32)> {
    (1..wall.cols - 1)
        .filter_map(|x| {
            (1..wall.rows - 1)
                .find(|&y| wall.inside[wall.idx(x, y)] > 0.0)
                .map(|y| (x as f32, y as f32))
        })
        .collect()
}

use super::wall::Wall;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::RowMajor;

    #[test]
    fn line_points_lie_just_below_the_polyline() {
        let s = Source::line(vec![(10.0, 20.0), (30.0, 20.0), (30.0, 40.0)]);
        assert_eq!(s.length(), 40.0);
        assert_eq!(s.point(5.0), (15.0, 21.0));
        assert_eq!(s.point(30.0), (30.0, 31.0));
        assert_eq!(s.point(-3.0), (10.0, 21.0), "clamped to the start");
        assert_eq!(s.point(99.0), (30.0, 41.0), "clamped to the end");
    }

    #[test]
    fn top_edge_follows_the_region() {
        // 3x3 grid; column 1 starts one row lower.
        let region = [true, false, true, true, true, false, false, false, true];
        let wall = Wall::new(
            &RowMajor::filled(3, 3, 0.0),
            &RowMajor::new(3, 3, region.to_vec()),
        );
        assert_eq!(top_edge(&wall), vec![(1.0, 1.0), (2.0, 2.0), (3.0, 1.0)]);
    }

    #[test]
    fn drip_gaps_are_irregular_about_the_spacing() {
        let mut rng = crate::random::rng(5, (crate::effects::Effect::Rain, RELEASE), 9, 0);
        let points = drips(20_000.0, 20.0, &mut rng);
        let gaps: Vec<f32> = points.windows(2).map(|p| p[1].0 - p[0].0).collect();
        let n = gaps.len() as f32;
        let mean = gaps.iter().sum::<f32>() / n;
        let cv = (gaps.iter().map(|g| (g - mean).powi(2)).sum::<f32>() / n).sqrt() / mean;
        assert!((18.0..22.0).contains(&mean), "mean gap {mean}");
        // Uniform gaps of 0.5..1.5 spacings (a comb, blind review 16): 0.29.
        assert!(cv > 0.5, "gap CV {cv}");
        assert!(gaps.iter().all(|&g| g >= CLOSEST * 20.0 - 1e-3));
    }

    /// The streaks' strength leaves the release alone (the simulation's
    /// drip points, water and onsets are those of `uneven` 0, so its water
    /// and dirt are too), follows the water along a ledge, and differs
    /// from ledge to ledge about a mean drain of 1.
    #[test]
    fn the_strength_follows_the_water_and_leaves_the_release_alone() {
        let release = |uneven| Release {
            spacing: 20.0,
            width: 2.0,
            end_share: 0.5,
            uneven,
            habits: false,
        };
        let warp = |seed, uneven| {
            let mut rng = crate::random::rng(seed, (crate::effects::Effect::Rain, RELEASE), 1, 0);
            Warp::new(400.0, &release(uneven), &mut rng).unwrap()
        };
        let mut drains = Vec::new();
        for seed in 0..400 {
            let (even, uneven) = (warp(seed, 0.0), warp(seed, 1.0));
            assert_eq!(
                (&even.inverse, &even.water, &even.onset),
                (&uneven.inverse, &uneven.water, &uneven.onset)
            );
            assert_eq!(even.drain(), 1.0);
            assert!((0..=400).all(|u| even.strength(even.water(u as f32)) == 1.0));
            let mut by_water: Vec<(f32, f32)> = (0..=400)
                .map(|u| {
                    let water = uneven.water(u as f32);
                    (water, uneven.strength(water * uneven.drain()))
                })
                .collect();
            by_water.sort_by(|a, b| a.0.total_cmp(&b.0));
            assert!(by_water.windows(2).all(|p| p[1].1 >= p[0].1));
            assert!(by_water.iter().all(|p| (0.0..=1.0).contains(&p.1)));
            drains.push(uneven.drain());
        }
        let mean = drains.iter().sum::<f32>() / drains.len() as f32;
        assert!((0.85..1.15).contains(&mean), "mean drain {mean}");
        let weak = drains.iter().filter(|&&d| d < 0.5).count();
        assert!(
            (60..160).contains(&weak),
            "{weak} of 400 ledges drain under half"
        );
    }
}
