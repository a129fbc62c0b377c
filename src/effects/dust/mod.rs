//! Dust settling over days (Santos & Baranoski 2022, "Observation-driven
//! generation of texture maps depicting dust accumulation over time").
//!
//! Two components, each a layer:
//! - the **opacity film** ([`film`]): fine particles, one pixel each, in
//!   three greys, counted per pixel (eqs. 2-5);
//! - the **granularity mask** ([`granules`]): coarse arcs, clumps and hairs,
//!   opaque, one colour (eqs. 6-7).
//!
//! [`shade`] puts them on the wall for a viewing and a light angle
//! (eqs. 8-11), optionally per pixel from a normal map.
//!
//! The texture is the photo's own pixel grid: A (eq. 1) is the region's area
//! in pixels / ppi^2. Particles never move, so the state at day T is the
//! state at day T-1 plus day T's particles: [`DustState::advance_to`] is
//! incremental, and day 200 holds exactly day 100's particles plus those of
//! days 101-200. Every day's particles come from their own random streams,
//! in fixed-size chunks, so the result is byte-identical at any thread count.
//! Past [`BULK_FILM`] particles per wall pixel the film is drawn per pixel
//! (from one uniform number per pixel and grey, through the inverse Poisson
//! CDF) and past [`SATURATED_MASK`] elements per pixel the granule mask is
//! full: such a day costs the same after a year or a century. Both are
//! reached the same way in one step or several, so a state advanced frame
//! by frame (a time-lapse) equals a state advanced at once, byte for byte.

pub mod band;
pub mod film;
pub mod granules;
pub mod settle;
pub mod shade;

use image::{GrayImage, RgbImage, RgbaImage};
use rayon::prelude::*;
use serde::Serialize;

use crate::effects::region::Region;
use crate::error::{Error, Result};
use crate::grid::WALL;
use crate::preset::{DustParams, Segment};
use crate::progress::Progress;

/// Particles (or coarse elements) per random stream.
pub const CHUNK: u64 = 4096;

/// Expected number of elements placed in days 1..=t (the sum of eq. 1).
///
/// Segments follow each other; each is eq. 1 restarted on its first day
/// [choice: Santos apply "distinct versions of Eq. 1 in a piecewise
/// fashion", so a segment's beta is a one-off extra on its own first day].
/// The last segment runs on past its `days` [choice: a time slider beyond the
/// listed segments keeps the last rate rather than stopping].
///
/// ```
/// use grime::preset::Segment;
/// use grime::effects::dust::cumulative;
/// let rate = [Segment::new(0, 2.0, 5.0)];
/// // A (alpha + beta) + A alpha (T - 1) with A = 10, T = 3.
/// assert_eq!(cumulative(&rate, 10.0, 3), 10.0 * 7.0 + 10.0 * 2.0 * 2.0);
/// ```
pub fn cumulative(segments: &[Segment], area: f64, t: u32) -> f64 {
    let mut total = 0.0;
    let mut start = 1u64;
    for (i, s) in segments.iter().enumerate() {
        let last = i + 1 == segments.len();
        let end = if last || s.days == 0 {
            u64::MAX
        } else {
            start + s.days as u64 - 1
        };
        if (t as u64) < start {
            break;
        }
        let n = (t as u64).min(end) - start + 1;
        // Santos eq. (1): A (alpha + beta) on the first day, A alpha after.
        total += area * (s.alpha + s.beta) + area * s.alpha * (n - 1) as f64;
        if end == u64::MAX {
            break;
        }
        start = end + 1;
    }
    total
}

/// Elements in days 1..=t: [`cumulative`] rounded to the nearest integer
/// [choice: A is fractional, so day t adds round(P(t)) - round(P(t-1));
/// the total after T days is then exactly round(A(alpha+beta) + A alpha (T-1))].
pub fn total(segments: &[Segment], area: f64, t: u32) -> u64 {
    cumulative(segments, area, t).round().max(0.0) as u64
}

/// Elements added on day `t` (1-based), Santos eq. (1).
pub fn added_on_day(segments: &[Segment], area: f64, t: u32) -> u64 {
    if t == 0 {
        return 0;
    }
    total(segments, area, t).saturating_sub(total(segments, area, t - 1))
}

/// One unit of parallel work: `count` elements of day `day`, drawn from the
/// random stream (day, `chunk`).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Task {
    pub day: u32,
    pub chunk: u64,
    pub count: u64,
}

/// The tasks of days `from..=to`, in a fixed order.
pub(crate) fn tasks(segments: &[Segment], area: f64, from: u32, to: u32) -> Vec<Task> {
    let mut out = Vec::new();
    for day in from.max(1)..=to {
        let n = added_on_day(segments, area, day);
        for chunk in 0..n.div_ceil(CHUNK) {
            out.push(Task {
                day,
                chunk,
                count: CHUNK.min(n - chunk * CHUNK),
            });
        }
    }
    out
}

/// Above this many fine particles per wall pixel in all, the film's counts
/// are drawn per pixel ([`film::Film::place_bulk`]) instead of particle by
/// particle, so the cost stops growing with the days (issue 13: `dust.days = 36500` with
/// `dust.ppi = 1` ran 75 minutes). The default preset places 0.04 per pixel.
pub const BULK_FILM: u64 = 16;

/// Coarse elements per wall pixel after which the granularity mask is full:
/// each element covers several pixels around a wall pixel, so after 8 per
/// pixel a pixel is left uncovered with probability below e^-40; the rest
/// are counted but not drawn.
pub const SATURATED_MASK: u64 = 8;

/// Santos' texture resolution, pixels per inch: the film's `anp_max` and
/// the granules' sizes are measured at it (Table 1).
pub const REFERENCE_PPI: f64 = 150.0;

/// Coarse elements narrower than this many pixels are not drawn: at facade
/// scale a 2 mm hair is a fraction of a pixel, part of the film's tone.
pub const MIN_GRANULE_PX: f32 = 1.5;

/// `p` for a photo of `metres_per_pixel`: with `ppi = 0` the wall's own
/// resolution (0.0254 m per inch over metres per pixel), and the film's
/// saturation count and the granules' size scaled from Santos' 150 ppi
/// [choice: a fine particle covers a fixed area of wall, so a pixel that
/// holds (150 / ppi)^2 of Santos' pixels takes as many times the particles
/// to be covered; a granule is a fixed width in millimetres].
pub fn at_scale(p: &DustParams, metres_per_pixel: f32) -> DustParams {
    if p.ppi > 0.0 {
        return p.clone();
    }
    let ppi = 0.0254 / metres_per_pixel.max(1e-9) as f64;
    let k = (ppi / REFERENCE_PPI) as f32;
    DustParams {
        ppi,
        anp_max: p.anp_max / (k * k),
        granule_size: p.granule_size * k,
        ..p.clone()
    }
}

/// Random-stream key of the bulk film's draws: above every day number.
const BULK_KEY: u64 = 1 << 32;

/// Cuts `tasks` (in order) to at most `max` elements; returns how many
/// were cut.
pub(crate) fn saturate(tasks: &mut Vec<Task>, max: u64) -> u64 {
    let mut left = max;
    let mut cut = 0;
    tasks.retain_mut(|t| {
        let keep = t.count.min(left);
        left -= keep;
        cut += t.count - keep;
        t.count = keep;
        keep > 0
    });
    cut
}

/// What a dust run placed.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct DustStats {
    /// Days accumulated.
    pub days: u32,
    /// Area A of the region in square inches (eq. 1).
    pub area_in2: f64,
    /// Fine particles in the film.
    pub film_particles: u64,
    /// Coarse elements in the granularity mask.
    pub granules: u64,
    /// Of which arcs.
    pub arcs: u64,
    /// Of which clumps.
    pub clumps: u64,
    /// Of which hairs.
    pub hairs: u64,
    /// Fraction of wall pixels holding at least one fine particle.
    pub film_coverage: f64,
    /// Fraction of wall pixels covered by a coarse element.
    pub granule_coverage: f64,
}

/// Dust accumulated up to some day: the film's particle counts and the
/// granularity mask. Advance it day by day; render it at any time. It is
/// made for one region: pass the same one to every call.
#[derive(Debug, Clone)]
pub struct DustState {
    seed: u64,
    area_in2: f64,
    /// Wall pixels of the region.
    wall: u64,
    film_rate: Vec<Segment>,
    mask_rate: Vec<Segment>,
    /// Fine particle counts (eqs. 2-3).
    pub film: film::Film,
    /// Coarse elements (eq. 6).
    pub mask: granules::Mask,
    day: u32,
    /// Coarse elements drawn so far: arcs, clumps, hairs.
    drawn: [u64; 3],
    /// Coarse elements counted but not drawn (past [`SATURATED_MASK`]).
    skipped: u64,
    stats: DustStats,
}

impl DustState {
    /// Clean wall at day 0.
    ///
    /// # Errors
    /// [`Error::OutOfRange`] for a non-positive `ppi`.
    pub fn new(region: &Region, p: &DustParams, seed: u64) -> Result<DustState> {
        if !(p.ppi.is_finite() && p.ppi > 0.0) {
            return Err(Error::OutOfRange {
                field: "dust.ppi".into(),
                value: p.ppi.to_string(),
                range: "above 0".into(),
            });
        }
        let (film_rate, mask_rate) = p.segments();
        let area_in2 = region.area() as f64 / (p.ppi * p.ppi);
        Ok(DustState {
            seed,
            area_in2,
            wall: region.area(),
            film_rate,
            mask_rate,
            film: film::Film::new(region.width(), region.height()),
            mask: granules::Mask::new(region.width(), region.height()),
            day: 0,
            drawn: [0; 3],
            skipped: 0,
            stats: DustStats {
                area_in2,
                ..DustStats::default()
            },
        })
    }

    /// The day reached so far.
    pub fn day(&self) -> u32 {
        self.day
    }

    /// Adds the particles and elements of days `day()+1 ..= day` on
    /// `region` (the state's). Going back in time is not possible
    /// (particles never leave); such a call does nothing. Any steps to a day
    /// give the same state as one step.
    ///
    /// # Errors
    /// [`Error::Cancelled`] when the progress's cancel flag is set.
    pub fn advance_to(
        &mut self,
        region: &Region,
        day: u32,
        p: &DustParams,
        progress: &Progress,
    ) -> Result<()> {
        if day <= self.day {
            return Ok(());
        }
        let film_total = total(&self.film_rate, self.area_in2, day);
        if film_total > BULK_FILM * self.wall {
            // The whole film of `day` at once, whatever the steps before.
            self.stats.film_particles = self
                .film
                .place_bulk(region, film_total, self.seed, BULK_KEY, progress)?;
        } else {
            let film_tasks = tasks(&self.film_rate, self.area_in2, self.day + 1, day);
            self.stats.film_particles +=
                self.film.place(region, &film_tasks, self.seed, progress)?;
        }
        progress.update("dust", 0.5);
        let looks = granules::Looks::new(p);
        let mut mask_tasks = tasks(&self.mask_rate, self.area_in2, self.day + 1, day);
        let limit = match p.granule_size < MIN_GRANULE_PX {
            true => 0,
            false => SATURATED_MASK * self.wall,
        };
        // The first `limit` elements of all days are drawn, in day order.
        let room = limit.saturating_sub(self.drawn.iter().sum());
        self.skipped += saturate(&mut mask_tasks, room);
        let drawn = self
            .mask
            .place(region, &mask_tasks, &looks, self.seed, progress)?;
        for (total, new) in self.drawn.iter_mut().zip(drawn) {
            *total += new;
        }
        // Elements past saturation change no pixel; count them by share.
        let [mut arcs, mut clumps, mut hairs] = self.drawn;
        let all = (arcs + clumps + hairs).max(1) as f64;
        let share = |k: u64| (self.skipped as f64 * k as f64 / all).round() as u64;
        let (a, c) = (share(arcs), share(clumps));
        arcs += a;
        clumps += c;
        hairs += self.skipped.saturating_sub(a + c);
        self.stats.arcs = arcs;
        self.stats.clumps = clumps;
        self.stats.hairs = hairs;
        self.stats.granules = arcs + clumps + hairs;
        self.day = day;
        self.stats.days = day;
        Ok(())
    }

    /// Renders the film and granules layers (eqs. 2-11) of `region` (the
    /// state's) for the current day.
    ///
    /// `normals`, if given, is a photo-sized tangent-space normal map (see
    /// [`shade`]). Returns the film (straight-alpha RGBA), the granules'
    /// alpha (colour `p.granule_color`) and the numbers.
    ///
    /// # Errors
    /// [`Error::NormalMapSize`] for a normal map of the wrong size.
    pub fn render(
        &self,
        region: &Region,
        p: &DustParams,
        normals: Option<&RgbImage>,
    ) -> Result<(RgbaImage, GrayImage, DustStats)> {
        let (w, h) = (region.width(), region.height());
        let shading = shade::Shading::new(p.theta_v, p.theta_i, normals, w, h)?;
        let look = film::Look::new(p);
        let mut film_img = RgbaImage::new(w, h);
        let mut gran_img = GrayImage::new(w, h);
        let (film_px, gran_px): (u64, u64) = film_img
            .par_chunks_mut(w as usize * 4)
            .zip(gran_img.par_chunks_mut(w as usize))
            .enumerate()
            .map(|(y, (film_row, gran_row))| {
                let y = y as u32;
                let mut factors = vec![shade::Factors::default(); w as usize];
                shading.row(y, &mut factors);
                let mask = region.mask_row(y);
                let counts = self.film.row(y).chunks_exact(film::COLORS);
                let (mut f_px, mut g_px) = (0u64, 0u64);
                for (x, (counts, covered)) in counts.zip(self.mask.row(y)).enumerate() {
                    let (wall, wt) = match mask {
                        None => (true, 1.0),
                        Some(m) => (m[x] >= WALL, m[x] as f32 / 255.0),
                    };
                    let (color, ro) = look.shade(counts);
                    if wall {
                        f_px += (ro > 0.0) as u64;
                        g_px += covered as u64;
                    }
                    if wt == 0.0 {
                        continue;
                    }
                    let f = factors[x];
                    if ro > 0.0 {
                        // Santos eq. (11) as a normal layer: colour u, alpha RO V L
                        // [choice: the paper's M (1 - V L) would darken dust-free
                        // pixels; with C_op = u RO as premultiplied colour the
                        // over operator gives C_op V L + M (1 - RO V L)].
                        let a = ro * f.film * wt;
                        film_row[x * 4..x * 4 + 4].copy_from_slice(&[
                            color,
                            color,
                            color,
                            to_u8(a),
                        ]);
                    }
                    if covered {
                        // Santos eq. (10): C = C_g L + M (1 - L), alpha L.
                        gran_row[x] = to_u8(f.granule * wt);
                    }
                }
                (f_px, g_px)
            })
            .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
        let mut stats = self.stats.clone();
        let area = region.area().max(1) as f64;
        stats.film_coverage = film_px as f64 / area;
        stats.granule_coverage = gran_px as f64 / area;
        Ok((film_img, gran_img, stats))
    }
}

/// Alpha in 0..1 to 0..255, rounded (without a libm call).
fn to_u8(a: f32) -> u8 {
    (a * 255.0 + 0.5).clamp(0.0, 255.0) as u8
}

/// Dust after `p.days` days: the film layer (straight-alpha RGBA), the
/// granules' alpha and the numbers.
///
/// # Errors
/// [`Error::Cancelled`] when cancelled, [`Error::NormalMapSize`] for a normal map
/// of the wrong size, [`Error::OutOfRange`] for a bad `ppi`.
pub fn accumulate(
    region: &Region,
    normals: Option<&RgbImage>,
    p: &DustParams,
    seed: u64,
    progress: &Progress,
) -> Result<(RgbaImage, GrayImage, DustStats)> {
    let mut state = DustState::new(region, p, seed)?;
    state.advance_to(region, p.days, p, progress)?;
    progress.check()?;
    let out = state.render(region, p, normals)?;
    progress.update("dust", 1.0);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::preset::DustEnvironment;

    #[test]
    fn daily_counts_follow_eq_1_and_sum_to_the_closed_form() {
        let rate = [Segment::new(0, 2.4, 0.8)];
        let area = 24.37;
        for t in [1u32, 2, 10, 100, 365] {
            let by_day: u64 = (1..=t).map(|d| added_on_day(&rate, area, d)).sum();
            let want = (area * (2.4 + 0.8) + area * 2.4 * (t - 1) as f64).round() as u64;
            assert_eq!(by_day, want, "t = {t}");
        }
        // Day 1 carries the extra A beta.
        let extra = added_on_day(&rate, area, 1) as f64 - added_on_day(&rate, area, 2) as f64;
        assert!((extra - area * 0.8).abs() <= 1.0, "{extra}");
    }

    #[test]
    fn piecewise_segments_switch_rate_after_their_days() {
        let (film, _) = DustEnvironment::SteepStart.segments().unwrap();
        let area = 100.0;
        assert_eq!(
            added_on_day(&film, area, 1),
            ((11.1 + 5.1) * area).round() as u64
        );
        assert_eq!(added_on_day(&film, area, 5), (11.1 * area) as u64);
        assert_eq!(
            added_on_day(&film, area, 6),
            (2.8 * area) as u64,
            "the second segment's beta is 0"
        );
        assert_eq!(added_on_day(&film, area, 400), (2.8 * area) as u64);
        let tasks = tasks(&film, area, 1, 3);
        assert_eq!(
            tasks.iter().map(|t| t.count).sum::<u64>(),
            total(&film, area, 3)
        );
    }

    #[test]
    fn saturate_keeps_the_first_elements_in_order() {
        let t = |day, count| Task {
            day,
            chunk: 0,
            count,
        };
        let mut v = vec![t(1, 5), t(2, 5), t(3, 5)];
        assert_eq!(saturate(&mut v, 7), 8);
        assert_eq!(
            v.iter().map(|t| (t.day, t.count)).collect::<Vec<_>>(),
            [(1, 5), (2, 2)]
        );
    }

    /// A time-lapse advances one state frame by frame: every step must give
    /// the state a run to that day makes, across the bulk film and the
    /// saturated mask.
    #[test]
    fn steps_to_a_day_equal_one_step() {
        let region = Region::new(64, 48, None).unwrap();
        let p = DustParams {
            ppi: 3.0,
            ..DustParams::default()
        };
        let wall = region.area();
        let (film_rate, mask_rate) = p.segments();
        let area = wall as f64 / 9.0;
        let first_bulk = (1..)
            .find(|&d| total(&film_rate, area, d) > BULK_FILM * wall)
            .unwrap();
        let full_mask = (1..)
            .find(|&d| total(&mask_rate, area, d) > SATURATED_MASK * wall)
            .unwrap();
        let mut stepped = DustState::new(&region, &p, 3).unwrap();
        let none = Progress::none();
        for day in [
            1,
            9,
            first_bulk - 1,
            first_bulk,
            first_bulk + 7,
            full_mask - 1,
            full_mask + 30,
        ] {
            stepped.advance_to(&region, day, &p, &none).unwrap();
            let mut once = DustState::new(&region, &p, 3).unwrap();
            once.advance_to(&region, day, &p, &none).unwrap();
            let a = stepped.render(&region, &p, None).unwrap();
            let b = once.render(&region, &p, None).unwrap();
            assert_eq!(a.0, b.0, "film at day {day}");
            assert_eq!(a.1, b.1, "granules at day {day}");
            assert_eq!(a.2, b.2, "numbers at day {day}");
            assert!((0..48).all(|y| stepped.film.row(y) == once.film.row(y)));
        }
        assert!(stepped.skipped > 0, "the mask saturated");
    }

    /// Issue 13: a century of dust at 1 ppi drew every particle one by one
    /// (75 minutes on a 0.2 MP photo; about 40 s on this 64 x 64 wall).
    #[test]
    fn a_century_of_dust_costs_no_more_than_a_year() {
        let region = Region::new(64, 64, None).unwrap();
        let p = DustParams {
            days: 36500,
            ppi: 1.0,
            ..DustParams::default()
        };
        let t = std::time::Instant::now();
        let mut state = DustState::new(&region, &p, 7).unwrap();
        state
            .advance_to(&region, p.days, &p, &Progress::none())
            .unwrap();
        let secs = t.elapsed().as_secs_f64();
        let expected = total(&state.film_rate, state.area_in2, p.days) as f64;
        let got = state.stats.film_particles as f64;
        assert!(
            (got - expected).abs() < expected * 0.01,
            "{got} vs {expected}"
        );
        let mask_expected = total(&state.mask_rate, state.area_in2, p.days);
        assert_eq!(state.stats.granules, mask_expected);
        assert!(secs < 5.0, "{secs} s");
    }
}
