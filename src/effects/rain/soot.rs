//! Soot in the rain shelter: the wall just under an eave, a cornice or a
//! balcony that the rain never washes.
//!
//! [choice, beyond Chang, whose stains come only from running water:]
//! `how-facades-age.md`, "Rain shelter": the wall under a projection stays
//! dry, soot settles there and is never washed, so sheltered zones are the
//! darkest, "with a fairly sharp line where the driving rain begins to
//! reach". Blind review 16's sixth tell was the open wall left clean, grime
//! only in streaks under edges. Between rainfalls, dry deposition lays a
//! share (`stain.soot`, by default [`PER_RAINFALL`]) of a soot film on a band [`DEPTH_M`] deep under
//! each deep projection; its lower line wanders up and down by about
//! [`WOBBLE`] of that over [`LINE_NOISE_M`], the soot fades toward it
//! ([`SOFT_M`]), and
//! the band narrows to nothing over [`TAPER_M`] at the ledge's ends. The
//! soot goes into each rainfall's layer before the dirt film
//! ([`super::stain::Film`]) saturates it, so it darkens with the years,
//! never past the film's floor, and a time-lapse's frames stay prefixes of
//! the run.

use rayon::prelude::*;

use crate::effects::Effect;
use crate::field::RowMajor;
use crate::random::{Noise, key, smoothstep};

/// The share of a full soot film one rainfall's interval lays in the
/// shelter, `stain.soot`'s default [choice: 0.04; over forty rainfalls (fifty years at the default
/// rates) the film stack there reads about 0.77 of the clean wall, a tone
/// and not a coat].
pub const PER_RAINFALL: f32 = 0.04;

/// How deep the sooted band under a projection is, metres [choice: 0.5 m,
/// where rain slanting 30-45 degrees reaches behind an eave or cornice
/// projecting 0.3-0.5 m].
pub const DEPTH_M: f32 = 0.5;

/// How far the band's lower line moves up and down, as a share of its
/// depth.
const WOBBLE: f32 = 0.4;

/// The softness of the band's lower line, metres, plus [`FADE`] of the
/// band's depth: the soot is darkest under the ledge and fades toward the
/// line [choice: an even band with a 0.08 m edge read as a painted stripe
/// on a sunlit gable].
const SOFT_M: f32 = 0.08;

/// See [`SOFT_M`].
const FADE: f32 = 0.6;

/// The wobble's feature size along the line, metres.
const LINE_NOISE_M: f32 = 0.8;

/// Over how far the band narrows to nothing at a ledge's ends, metres.
pub const TAPER_M: f32 = 0.4;

/// The soot's own noise stream (the release's is 1, the wander's 2, the
/// stains' texture's 3-5, the twins' 11; it was 3 until the twenty-third
/// pass, the texture's stria stream too, so the soot line's wobble and the
/// stria were drawn from one lattice).
const SOOT: u16 = 6;

/// How much soot each rainfall's interval lays, per grid pixel.
#[derive(Debug, Clone)]
pub struct Soot {
    per_rainfall: RowMajor<f32>,
}

impl Soot {
    /// The soot, `share` of a full film per rainfall, on a grid whose
    /// pixels lie `below` metres under a deep projection
    /// ([`crate::effects::habitat::below_projections`], with [`TAPER_M`]),
    /// `px_per_m` grid pixels per metre, from `seed`.
    pub fn new(seed: u64, share: f32, below: &RowMajor<f32>, px_per_m: f32) -> Soot {
        let (w, h) = (below.width(), below.height());
        let scale = (LINE_NOISE_M * px_per_m).max(2.0);
        let noise = Noise::new(
            key(seed, (Effect::Rain, SOOT), 0, 0),
            w as u32,
            h as u32,
            scale,
            2,
        );
        let lines = noise.lines(w, 2.0 * WOBBLE);
        let mut per_rainfall = RowMajor::filled(w, h, 0.0);
        let mut wobble = vec![0.0; w];
        for (y, (row, below)) in per_rainfall
            .data_mut()
            .chunks_mut(w.max(1))
            .zip(below.data().chunks(w.max(1)))
            .enumerate()
        {
            lines.line(y, &mut wobble);
            for ((v, &d), n) in row.iter_mut().zip(below).zip(&wobble) {
                let line = DEPTH_M * (1.0 + n - WOBBLE);
                let t = ((line - d) / (SOFT_M + FADE * line)).clamp(0.0, 1.0);
                *v = share * smoothstep(t);
            }
        }
        Soot { per_rainfall }
    }

    /// Lays one interval's soot on a rainfall's `cover` (the same size):
    /// a union with what the rain stained.
    pub fn lay(&self, cover: &mut RowMajor<f32>) {
        cover
            .data_mut()
            .par_iter_mut()
            .zip(self.per_rainfall.data())
            .for_each(|(c, s)| *c += s * (1.0 - c.clamp(0.0, 1.0)));
    }

    /// [`Soot::lay`], when the rain's part of `cover` is to be scaled by
    /// `gain` after the film (`fall::Fall::gain`): `gain` becomes the
    /// factor on the union, the rain's share of it at its gain and the
    /// soot's in full, so the soot stays as dark whatever streak runs
    /// over it.
    pub fn lay_gained(&self, cover: &mut RowMajor<f32>, gain: &mut RowMajor<f32>) {
        cover
            .data_mut()
            .par_iter_mut()
            .zip(gain.data_mut())
            .zip(self.per_rainfall.data())
            .for_each(|((c, g), s)| {
                let soot = s * (1.0 - c.clamp(0.0, 1.0));
                let union = *c + soot;
                if union > 0.0 {
                    *g = (*g * *c + soot) / union;
                }
                *c = union;
            });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 100 px a metre; a ledge along row 10: metres below it.
    fn under_a_ledge(width: usize, height: usize) -> RowMajor<f32> {
        RowMajor::from_fn(width, height, |_, y| match y {
            0..10 => f32::INFINITY,
            _ => (y - 10) as f32 / 100.0,
        })
    }

    #[test]
    fn soot_lies_under_the_ledge_down_to_a_wandering_line() {
        let soot = Soot::new(5, PER_RAINFALL, &under_a_ledge(300, 120), 100.0);
        let sooted = |y: usize, share: f32| {
            (0..300)
                .filter(|&x| soot.per_rainfall.get(x, y) > share * PER_RAINFALL)
                .count()
        };
        assert_eq!(sooted(5, 0.0), 0, "above the ledge");
        assert_eq!(sooted(15, 0.99), 300, "just under it, full");
        assert_eq!(sooted(10 + 80, 0.0), 0, "past the deepest line");
        // The soot fades down the band.
        let mean = |y: usize| (0..300).map(|x| soot.per_rainfall.get(x, y)).sum::<f32>();
        assert!(mean(30) < mean(15) && mean(45) < mean(30));
        // Half a metre down, the line wanders: some columns are sooted,
        // some bare.
        let half = sooted(10 + 50, 0.0);
        assert!((30..270).contains(&half), "{half} of 300 sooted");
    }

    /// With a gain after the film, the soot keeps its own strength and
    /// only the rain's share of the union takes the gain.
    #[test]
    fn gained_soot_keeps_its_own_strength() {
        let soot = Soot::new(5, PER_RAINFALL, &under_a_ledge(8, 40), 100.0);
        let plain = |x: usize| if x < 4 { 0.5 } else { 0.0 };
        let mut cover = RowMajor::from_fn(8, 40, |x, _| plain(x));
        let mut gain = RowMajor::filled(8, 40, 0.2);
        let mut laid = cover.clone();
        soot.lay(&mut laid);
        soot.lay_gained(&mut cover, &mut gain);
        assert_eq!(cover.data(), laid.data(), "the same union");
        assert_eq!(gain.get(6, 12), 1.0, "soot alone: in full");
        assert_eq!(gain.get(1, 5), 0.2, "rain alone: its gain");
        let (c, s) = (cover.get(1, 12), soot.per_rainfall.get(1, 12));
        let want = (0.2 * 0.5 + s * 0.5) / c;
        assert!((gain.get(1, 12) - want).abs() < 1e-6);
    }

    #[test]
    fn soot_adds_to_a_stain_without_passing_full_cover() {
        let soot = Soot::new(5, PER_RAINFALL, &under_a_ledge(8, 40), 100.0);
        let mut cover = RowMajor::from_fn(8, 40, |x, _| if x < 4 { 1.0 } else { 0.0 });
        soot.lay(&mut cover);
        assert_eq!(cover.get(1, 12), 1.0, "a full stain stays full");
        assert!(cover.get(6, 12) > 0.0, "the bare wall takes soot");
        assert_eq!(cover.get(6, 5), 0.0, "nothing above the ledge");
    }
}
