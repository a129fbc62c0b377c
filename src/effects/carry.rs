//! What the frames of a time-lapse carry from one to the next
//! ([`crate::pipeline::run_frames`]): the dust so far, which only grows
//! ([`DustState::advance_to`] gives the same state in steps as at once),
//! and the maps that do not change with the age. Each is kept with the
//! parameters and seed it was made from and made afresh when they differ,
//! so a frame equals a run at its age. A carry serves one scene (one
//! [`super::Context`]).

use image::{GrayImage, RgbImage, RgbaImage};

use super::dust::{DustState, DustStats};
use super::region::Region;
use crate::error::Result;
use crate::field::RowMajor;
use crate::preset::{ClimateParams, DustParams, MossParams, Preset};
use crate::progress::Progress;

/// The state kept between frames.
#[derive(Debug, Clone, Default)]
pub struct Carry {
    /// The dust so far, with its params (days aside) and seed.
    dust: Option<(DustParams, u64, DustState)>,
    /// Where dust settles ([`super::habitat`]), at photo size, with what
    /// it was made from.
    settle: Option<((f32, f32, f32, ClimateParams), GrayImage)>,
    /// Where moss takes, with its params (years aside), seed and climate.
    habitat: Option<((MossParams, u64, ClimateParams), RowMajor<f32>)>,
}

impl Carry {
    /// The dust after `p.days` days (as [`super::dust::accumulate`]),
    /// advanced from the last frame's when it is made alike and not later.
    ///
    /// # Errors
    /// As [`super::dust::accumulate`].
    pub(crate) fn dust(
        &mut self,
        region: &Region,
        normals: Option<&RgbImage>,
        p: &DustParams,
        seed: u64,
        progress: &Progress,
    ) -> Result<(RgbaImage, GrayImage, DustStats)> {
        let key = DustParams {
            days: 0,
            ..p.clone()
        };
        let state = match self.dust.take() {
            Some((k, s, state)) if k == key && s == seed && state.day() <= p.days => state,
            _ => DustState::new(region, p, seed)?,
        };
        let (_, _, state) = self.dust.insert((key, seed, state));
        state.advance_to(region, p.days, p, progress)?;
        progress.check()?;
        let out = state.render(region, p, normals)?;
        progress.update("dust", 1.0);
        Ok(out)
    }

    /// Where dust settles for `p`'s `open_wall`, `ledge_top_m` and
    /// `by_light` under `climate`, made by `make` the first time.
    pub(crate) fn settle(
        &mut self,
        p: &DustParams,
        climate: &ClimateParams,
        make: impl FnOnce() -> GrayImage,
    ) -> &GrayImage {
        let key = (p.open_wall, p.ledge_top_m, p.by_light, climate.clone());
        kept(&mut self.settle, key, make)
    }

    /// Where moss takes for the preset's moss (its years aside), seed and
    /// climate, made by `make` the first time.
    pub(crate) fn habitat(
        &mut self,
        preset: &Preset,
        make: impl FnOnce() -> RowMajor<f32>,
    ) -> &RowMajor<f32> {
        let key = MossParams {
            years: 0,
            ..preset.moss.clone()
        };
        kept(
            &mut self.habitat,
            (key, preset.seed, preset.climate.clone()),
            make,
        )
    }
}

/// The value in `slot` when it was made from `key`, else `make`'s.
fn kept<K: PartialEq, V>(slot: &mut Option<(K, V)>, key: K, make: impl FnOnce() -> V) -> &V {
    if slot.as_ref().is_some_and(|(k, _)| *k != key) {
        *slot = None;
    }
    &slot.get_or_insert_with(|| (key, make())).1
}
