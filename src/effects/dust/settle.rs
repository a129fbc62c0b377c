//! Where the dust stays on a facade: the settle map that scales the film's
//! and the granules' alpha per photo pixel.
//!
//! Santos & Baranoski's dust settles evenly; on a building, rain washes the
//! open wall and the dirt is left where a building holds it
//! (`how-facades-age.md`, "Where water goes"): on the **tops of ledges**
//! (sills, cornices, string courses: surfaces facing up, which collect
//! more dust, Santos after Hsu & Wong), in the **rain shelter** under a
//! projection, and, soaked in, in the **joints** there. The open wall keeps
//! `open_wall` of it.
//!
//! The map is 0..255 per photo pixel, [`ONE`] meaning "all of the dust a
//! flat wall shows" (Santos eq. 11 at the preset's angles); ledge tops go
//! above it, to [`UP_GAIN`] times that, as a surface facing up does.

use image::GrayImage;
use rayon::prelude::*;

use super::band;
use crate::analysis::LedgeKind;
use crate::effects::{Context, habitat};
use crate::field::RowMajor;
use crate::preset::DustParams;

/// The settle value (out of 255) that keeps a pixel's dust as it is.
pub const ONE: f32 = 127.0;

/// How much more film a ledge's top shows than the vertical wall: Santos
/// eqs. (8)-(9) with the normal facing up (0, 1, 0) against the flat wall's
/// (0, 0, 1), at the default theta_v = 60, theta_i = 45 (`shade::Shading`:
/// V L = 1 x 0.646 against 0.5 x 0.646 = 0.323, so 2.0) [choice: a constant
/// rather than the preset's angles, so the cached map does not depend on
/// them; at theta_v = 60 the street's view grazes the top].
pub const UP_GAIN: f32 = 2.0;

/// The thinnest band drawn on a ledge's top, photo pixels: the 6 cm of
/// `dust.ledge_top_m` is 1.5 px at the LMF photos' usual 4 cm a pixel and
/// 0.6 px at 10 cm; with [`band::across`]'s soft edges a band covers its
/// depth plus its edges' width [choice: 2 px drew a preview's band (a time-lapse
/// drawn at a third of the size) three times as deep in metres as the
/// run's, 0.20 levels off in `tests/years.rs`].
pub const MIN_BAND_PX: f32 = 1.0;

/// How far in from a ledge's ends its top band reaches full strength,
/// metres: rain runs off at the ends (the release points of
/// `how-facades-age.md`), so a long ledge is darkest in its middle.
pub const END_TAPER_M: f32 = 0.5;

/// The band's strength at a ledge's very end, against 1 in its middle.
pub const END_SHARE: f32 = 0.4;

/// How much of a ledge's top dust the rain shelter holds [choice: the
/// spec's shelter is the darkest place, but the analysis's shelter is a
/// coarse rectangle under each ledge, and a full share read as a grey box;
/// main had 0.5 painted over, which hardly showed].
pub const SHELTER_SHARE: f32 = 0.75;

/// A window head's top band against a sill's [choice: a hood mould or a
/// lintel's top holds dirt, a flush head does not; the analysis does not
/// tell them apart].
pub const WINDOW_HEAD_SHARE: f32 = 0.5;

/// A ledge's confidence at which its band is full; below it the band is
/// as much weaker [choice: the analysis's confidences run 0.25-0.8 on LMF,
/// and weighting by them as they are left a found sill at a third].
pub const SURE_FULL: f32 = 0.6;

/// Size of the patches dirt keeps to along a ledge and in shelter, metres
/// (fBm, 3 octaves): soot lies in drifts, not as an even coat.
pub const PATCH_M: f32 = 0.3;

/// The dust's own stream for its patches.
const PATCHES: u16 = 1;

/// How much more dust a joint or crack keeps than the face beside it,
/// within the dusty places (soot soaks into the mortar): the settle value
/// there is (1 + JOINT_GAIN j) times the face's, j the joint depth 0..1
/// (`habitat::joints`).
pub const JOINT_GAIN: f32 = 0.6;

/// How strongly a ledge's top is dusty at photo column `x` for a ledge
/// spanning `first..=last`: [`END_SHARE`] at its ends, rising smoothly to 1
/// at `taper` pixels in.
pub fn along(x: f32, first: f32, last: f32, taper: f32) -> f32 {
    let t = ((x - first).min(last - x) / taper.max(1.0)).clamp(0.0, 1.0);
    let smooth = t * t * (3.0 - 2.0 * t);
    END_SHARE + (1.0 - END_SHARE) * smooth
}

/// Ledge tops on the grid: for each cell the strongest band over it, the
/// ledge's confidence (full from [`SURE_FULL`]) times how straight it is
/// ([`band::straight`]) times [`along`] times [`band::across`] about its
/// fitted line, as soft as the photo's edge there ([`band::edge_width`]),
/// times the patches (`patch`, 0..1) read on the line: they make the band
/// stronger and weaker along the ledge, never move its edges. Window
/// heads [`WINDOW_HEAD_SHARE`] of that.
pub fn ledge_tops(ctx: &Context, depth_m: f32, patch: &Patches) -> RowMajor<f32> {
    let depth = ctx.photo_px(depth_m).max(MIN_BAND_PX);
    let taper = ctx.photo_px(END_TAPER_M);
    let bands: Vec<Band> = ctx
        .site
        .ledges
        .iter()
        .filter(|l| l.polyline.len() >= 2)
        .filter_map(|l| {
            let kind = match l.kind {
                LedgeKind::WindowHead => WINDOW_HEAD_SHARE,
                _ => 1.0,
            };
            let (a, b) = (l.polyline[0][0], l.polyline[l.polyline.len() - 1][0]);
            let (first, last) = (a.min(b), a.max(b));
            let fit = band::fit(&l.polyline);
            let sure =
                (l.confidence / SURE_FULL).clamp(0.0, 1.0) * band::straight(&fit, last - first);
            let strength = kind * sure;
            (strength > 0.0).then(|| Band {
                fit,
                first,
                last,
                strength,
                soft: band::edge_width(ctx, &fit, first, last),
            })
        })
        .collect();
    habitat::on_grid(ctx, |x, y| {
        bands
            .iter()
            .filter(|b| x >= b.first && x <= b.last)
            .map(|b| {
                let r = b.fit.row(x);
                let cover = band::across(r - y, depth, b.soft);
                if cover <= 0.0 {
                    return 0.0;
                }
                b.strength * along(x, b.first, b.last, taper) * cover * patch.at(x, r)
            })
            .fold(0.0, f32::max)
    })
}

/// One ledge's band: its fitted line, its columns, its strength 0..1 and
/// the width of its edges in photo pixels.
struct Band {
    fit: band::Fit,
    first: f32,
    last: f32,
    strength: f32,
    soft: f32,
}

/// How much dust stays per grid cell, 1 = a flat wall's full dust: the
/// open wall's `open_wall`, up to [`UP_GAIN`] on ledge tops (`tops`, its
/// patches already in) and [`SHELTER_SHARE`] in rain shelter, in patches
/// (`patch`, 0..1) and more in joints there; the climate's light
/// (`light`) then moves it. [choice] The joints soak the shelter's dirt,
/// not the ledge top's band: a joint's pixel in the band made its edge
/// speckled (p55: "jagged and speckled" at bost29's string courses).
pub fn stays(
    p: &DustParams,
    tops: &RowMajor<f32>,
    shelter: &RowMajor<f32>,
    joints: &RowMajor<f32>,
    patch: &RowMajor<f32>,
    light: &RowMajor<f32>,
) -> RowMajor<f32> {
    let mut out = tops.clone();
    for (i, v) in out.data_mut().iter_mut().enumerate() {
        let sheltered = SHELTER_SHARE
            * shelter.data()[i]
            * patch.data()[i]
            * (1.0 + JOINT_GAIN * joints.data()[i]);
        let held = (UP_GAIN * *v).max(sheltered);
        *v = (p.open_wall + (1.0 - p.open_wall) * held) * light.data()[i];
    }
    out
}

/// The patches dirt keeps to: fBm [`PATCH_M`] across, stretched to 0.25..1
/// [choice: about a fifth of the places at the floor, none bare: a ledge
/// top is never clean]. The noise is laid out in centimetres of wall, so
/// a time-lapse's preview (the photo drawn smaller, its scale with it)
/// shows the run's patches.
pub struct Patches {
    noise: crate::random::Noise,
    px_per_cm: f32,
}

impl Patches {
    /// The patches for `seed` over the photo of `ctx`.
    pub fn new(ctx: &Context, seed: u64) -> Self {
        let key = crate::random::key(seed, (crate::effects::Effect::Dust, PATCHES), 0, 0);
        let px_per_cm = ctx.photo_px(0.01).max(f32::MIN_POSITIVE);
        let (w, h) = ctx.size();
        // At most a kilometre of wall (the lattice's size): past it the
        // noise holds its last value.
        let cm = |px: u32| (px as f32 / px_per_cm).min(100_000.0);
        let (w_cm, h_cm) = (cm(w), cm(h));
        let scale = (PATCH_M * 100.0).max(1.0);
        let noise = crate::random::Noise::new(key, w_cm as u32 + 1, h_cm as u32 + 1, scale, 3);
        Patches { noise, px_per_cm }
    }

    /// The patch value, 0.25..1, at photo point (x, y).
    pub fn at(&self, x: f32, y: f32) -> f32 {
        let n = self.noise.at(x / self.px_per_cm, y / self.px_per_cm);
        (0.6 + 2.0 * (n - 0.5)).clamp(0.25, 1.0)
    }

    /// The patches on the grid.
    pub fn on_grid(&self, ctx: &Context) -> RowMajor<f32> {
        habitat::on_grid(ctx, |x, y| self.at(x, y))
    }
}

/// The rain shelter on the grid, its edges as soft as a ledge top's
/// band ([`band::SOFT_MIN_PX`]): the analysis's shelter is a box under
/// each ledge, stepped where its polyline steps, and its sides and top
/// drew lines of their own.
fn soft_shelter(ctx: &Context) -> RowMajor<f32> {
    let r = (band::SOFT_MIN_PX / ctx.grid.scale).round().max(1.0) as usize;
    crate::effects::climate::blur(&habitat::shelter(ctx), r)
}

/// The settle map at the photo's size, 0..255 with [`ONE`] = the flat
/// wall's full dust (see [`stays`]).
pub fn map(ctx: &Context, p: &DustParams, seed: u64, light: RowMajor<f32>) -> GrayImage {
    let patches = Patches::new(ctx, seed);
    let tops = ledge_tops(ctx, p.ledge_top_m, &patches);
    let shelter = soft_shelter(ctx);
    let joints = habitat::joints(ctx);
    let patch = patches.on_grid(ctx);
    let mut v = stays(p, &tops, &shelter, &joints, &patch, &light);
    // `upsample` writes v x 255 (x the mask's weight): store v x ONE.
    for x in v.data_mut() {
        *x = (*x * ONE / 255.0).min(1.0);
    }
    let (w, h) = ctx.size();
    ctx.grid.upsample(&v, ctx.mask, w, h)
}

/// Scales the alpha (the last of `channels` per pixel) of `pixels` by
/// `settle` / [`ONE`] (at most 255).
pub fn apply(pixels: &mut [u8], channels: usize, settle: &GrayImage) {
    pixels
        .par_chunks_exact_mut(channels)
        .zip(settle.as_raw().par_iter())
        .for_each(|(px, s)| {
            let a = &mut px[channels - 1];
            // Rounded down: a trace of dust on the washed wall is none.
            *a = (*a as f32 * *s as f32 / ONE).min(255.0) as u8;
        });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ledge_is_darkest_in_its_middle() {
        let (first, last, taper) = (0.0, 100.0, 20.0);
        assert!((along(0.0, first, last, taper) - END_SHARE).abs() < 1e-6);
        assert_eq!(along(50.0, first, last, taper), 1.0);
        assert!(along(5.0, first, last, taper) < along(15.0, first, last, taper));
    }

    #[test]
    fn ledge_tops_hold_more_than_shelter_and_joints_more_than_faces() {
        let p = DustParams::default();
        let one = |v: f32| RowMajor::filled(1, 1, v);
        let at = |t: f32, s: f32, j: f32| {
            stays(&p, &one(t), &one(s), &one(j), &one(1.0), &one(1.0)).data()[0]
        };
        assert!((at(0.0, 0.0, 0.0) - p.open_wall).abs() < 1e-6);
        assert!(at(1.0, 0.0, 0.0) > 1.9);
        assert!(at(0.0, 1.0, 0.0) < at(1.0, 0.0, 0.0));
        assert!(at(0.0, 1.0, 1.0) > at(0.0, 1.0, 0.0));
    }

    #[test]
    fn apply_scales_by_one_and_saturates() {
        let mut px = [10, 20, 30, 100, 0, 0, 0, 200];
        let settle = GrayImage::from_raw(2, 1, vec![ONE as u8, 255]).unwrap();
        apply(&mut px, 4, &settle);
        assert_eq!(px[3], 100);
        assert_eq!(px[7], 255);
    }
}
