//! A ledge's habit: how this one ledge sheds its water, drawn per ledge
//! from the seed (`rain.habits`).
//!
//! [choice, beyond the per-point draws of `sources.rs`:] real sills at
//! fifty years differ from window to window (`how-facades-age.md`, "Where
//! water goes"): no sill is level, so one end drains most of it and the
//! other little; one has a few drip points and another none where its
//! drip groove works; some fan a soft wash under the middle. With every
//! ledge drawing only its points' positions, shares and widths about one
//! mean, each short sill shed the same pair of end drips, of one width
//! and fade (blind checks p55-p58: "the same short pair of drips under
//! every sill"; review 33, p1010237: drips "much alike from bay to bay").
//! A habit sets a ledge's whole release: its tilt ([`TILT_SPREAD`]), its
//! drip points' spacing ([`DENSITY_SPREAD`]) and whether it fans a wash
//! ([`WASH_CHANCE`]). [choice: no width per ledge: a log spread of 0.35
//! on every point's width of a ledge raised the twins' ink's |log ratio|
//! to 0.74 and cut the darkening 6% for no gain in unlikeness.]
//! Twins (`twins.rs`) keep sharing their drain, so they stain alike in
//! strength and differ in pattern: alike in kind, not in copy.

/// Standard deviation of a ledge's tilt, the log ratio of its two ends'
/// water [choice: 2, so the low end takes over 4x the other's water about
/// one ledge in two (log ratio over ln 4 = 1.39, `|z| > 0.69`) and over
/// 7x one in three (`|z| > 1`); with `sources.rs`'s own end spread alone (a
/// log ratio of standard deviation 0.71) the two ends of most sills shed
/// like drips (blind checks p55-p58)].
const TILT_SPREAD: f32 = 2.0;

/// Standard deviation of a ledge's log drip spacing, as a factor on
/// `rain.drip_spacing_m` [choice: 0.3, so a sill's drip points lie 1.35x
/// closer or further apart than its neighbour's one time in three, and a
/// 1.2 m sill at the 0.9 m spacing draws none to two of them. At 0.6
/// the twins' stain profiles' correlation under the sills of ten LMF
/// photos fell further but their ink's |log ratio| rose from main's 0.667
/// to 0.78 and their darkening fell 7% (fewer points each saturate,
/// `Warp::strength`); BENCHMARKS.md, twenty-sixth pass, drips28].
const DENSITY_SPREAD: f32 = 0.3;

/// The share of ledges that fan a soft wash under them [choice: 0.35,
/// "a wash fanning under the sill's middle ... for some"].
const WASH_CHANCE: f32 = 0.35;

/// The share of its water a washing ledge sheds as the wash [choice:
/// 0.3: the wash's water per streak width is a tenth to a third of a drip
/// point's, so it reads as a faint fan (`Warp::strength` follows it), not
/// a blotch].
const WASH_SHARE: f32 = 0.3;

/// The wash's standard deviation along the ledge, in ledge lengths
/// [choice: 0.18, a fan about two thirds of the sill wide].
const WASH_WIDTH: f32 = 0.18;

/// How a ledge sheds its water, as factors on the preset's release.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Habit {
    /// The log ratio of the water at its start's end to its far end's.
    pub tilt: f32,
    /// Factor on the drip spacing.
    pub spacing: f32,
    /// The wash: (centre, in ledge lengths 0..1; share of the water);
    /// `None` = no wash.
    pub wash: Option<(f32, f32)>,
}

impl Habit {
    /// The preset's release as it is: level, no wash (`rain.habits` off).
    pub const LEVEL: Habit = Habit {
        tilt: 0.0,
        spacing: 1.0,
        wash: None,
    };

    /// A ledge's habit drawn from `rng`.
    pub fn draw(rng: &mut crate::random::Rng) -> Habit {
        use rand::Rng as _;
        let (z_tilt, z_spacing) = crate::random::box_muller(rng);
        let washes = rng.random::<f32>() < WASH_CHANCE;
        let centre = rng.random_range(0.25..0.75);
        Habit {
            tilt: TILT_SPREAD * z_tilt,
            spacing: (DENSITY_SPREAD * z_spacing).exp(),
            wash: washes.then_some((centre, WASH_SHARE)),
        }
    }

    /// The habit of source `line` (0 = the top edge, then the preset's
    /// lines from 1) with `seed`, or [`Habit::LEVEL`] when not `on`: drawn
    /// from the release stream's second index, so the drip points'
    /// own draws are those of before.
    pub fn of(seed: u64, stream: u16, line: u64, on: bool) -> Habit {
        match on {
            true => {
                let mut rng =
                    crate::random::rng(seed, (crate::effects::Effect::Rain, stream), line, 1);
                Habit::draw(&mut rng)
            }
            false => Habit::LEVEL,
        }
    }

    /// The two ends' weights `ends` tilted: the start's end times
    /// `exp(tilt / 2)`, the far end's over it.
    pub fn tilted(&self, ends: [f32; 2]) -> [f32; 2] {
        let t = (0.5 * self.tilt).exp();
        [ends[0] * t, ends[1] / t]
    }

    /// The wash of a ledge `len` long whose mean release width is
    /// `width`: its (centre, share of the water, width factor) as a release
    /// point of `sources.rs`'s mixture.
    pub fn wash_point(&self, len: f32, width: f32) -> Option<(f32, f32, f32)> {
        self.wash.map(|(c, share)| {
            (
                c * len,
                share,
                (WASH_WIDTH * len / width.max(1e-3)).max(1.0),
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn habits_tilt_thin_and_wash_some_ledges() {
        let habits: Vec<Habit> = (0..2000).map(|l| Habit::of(7, 1, l, true)).collect();
        let n = habits.len() as f32;
        let share = |f: &dyn Fn(&Habit) -> bool| habits.iter().filter(|h| f(h)).count() as f32 / n;
        // One end over four times the other's water about one ledge in two.
        let tilted = share(&|h| h.tilt.abs() > 4f32.ln());
        assert!((0.42..0.58).contains(&tilted), "tilted {tilted}");
        let washes = share(&|h| h.wash.is_some());
        assert!((0.3..0.4).contains(&washes), "washes {washes}");
        let sparse = share(&|h| h.spacing > 1.3);
        assert!((0.13..0.25).contains(&sparse), "sparse {sparse}");
        assert_eq!(Habit::of(7, 1, 3, false), Habit::LEVEL);
        assert_eq!(Habit::LEVEL.tilted([0.3, 0.7]), [0.3, 0.7]);
    }
}

/// Two twin sills drawn from the seed: alike in their streaks' total
/// strength, unlike in where along the sill it lies.
#[cfg(test)]
mod twin_sills {
    use super::super::sources::{Release, line_warp};

    /// A 1.2 m sill at 0.03 m a pixel, the default release.
    const LEN: f32 = 40.0;

    /// Droplets started along a sill.
    const DROPLETS: usize = 2000;

    /// The profile's bins along a sill (its ends, its middle).
    const BINS: usize = 5;

    fn release(habits: bool) -> Release {
        Release {
            spacing: 30.0,
            width: 2.0,
            end_share: 0.5,
            uneven: 1.0,
            habits,
        }
    }

    /// Per fifth of sill `line`, in the family whose shared draw is `z`:
    /// its ink, the share of the droplets starting there times their
    /// streak's strength.
    fn profile(seed: u64, line: usize, z: f32, habits: bool) -> Vec<f32> {
        let warp = line_warp(seed, line as u64 + 1, LEN, &release(habits))
            .map(|w| w.in_family(z))
            .expect("a sill with drip points");
        // Where a rainfall's droplets start (uniform positions through the
        // release's inverse CDF), each weighed by its streak's strength.
        let mut ink = vec![0.0; BINS];
        for k in 0..DROPLETS {
            let at = warp.at((k as f32 + 0.5) / DROPLETS as f32 * LEN, LEN);
            ink[((at / LEN * BINS as f32) as usize).min(BINS - 1)] +=
                warp.strength(warp.water(at) * warp.drain()) / DROPLETS as f32;
        }
        ink
    }

    /// (median ratio of a sill's weaker end's ink to its stronger end's,
    /// median |log ratio| of twin sills' total ink) over 400 seeds.
    fn likeness(habits: bool) -> (f32, f32) {
        let (mut ends, mut ratios) = (Vec::new(), Vec::new());
        for seed in 0..400u64 {
            let mut rng = crate::random::rng(seed, (crate::effects::Effect::Rain, 11), 1, 0);
            let z = crate::random::box_muller(&mut rng).0;
            let (a, b) = (profile(seed, 0, z, habits), profile(seed, 1, z, habits));
            for p in [&a, &b] {
                let (lo, hi) = (p[0].min(p[BINS - 1]), p[0].max(p[BINS - 1]));
                ends.push(lo / hi.max(1e-6));
            }
            let total = |p: &[f32]| p.iter().sum::<f32>().max(1e-6);
            ratios.push((total(&a) / total(&b)).ln().abs());
        }
        let median = |mut v: Vec<f32>| {
            v.sort_by(f32::total_cmp);
            v[v.len() / 2]
        };
        (median(ends), median(ratios))
    }

    /// Each sill has a low end: its drip takes most of the ends' water
    /// (main: the weaker end's ink 0.6 of the stronger's, the same pair of
    /// drips under every sill), and twins' total ink stays alike.
    #[test]
    fn twin_sills_have_a_low_end_and_stay_alike_in_ink() {
        let (level, own) = (likeness(false), likeness(true));
        eprintln!("level {level:?}, own habits {own:?}");
        assert!(level.0 > 0.45 && own.0 < 0.3, "ends {level:?} -> {own:?}");
        assert!(own.1 < 1.5f32.ln(), "total ink {level:?} -> {own:?}");
    }
}
