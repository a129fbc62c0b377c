//! The `[age]` section: one clock for every effect (see [`crate::clock`]).

use serde::{Deserialize, Serialize};

/// How old the wall is, and how much of each effect one year brings.
///
/// With `years` unset every effect keeps its own count (`rain.layers`,
/// `moss.years`, `dust.days`). With `years = N` the clock sets those three
/// from the rates below; [`crate::clock`] says which explicit fields win.
/// The default rates give the default preset at 15 years: 12 rainfalls,
/// 15 years of moss, 15 years (5475 days) of dust.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AgeParams {
    /// Age of the wall in years; unset = no clock.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub years: Option<u32>,
    /// Rainfalls (rain layers) per year.
    pub rainfalls_per_year: f32,
    /// Years of moss growth per year of age.
    pub moss_years_per_year: f32,
    /// Days of dust settling per year of age (the dust keeps to ledge tops
    /// and rain shelter, `dust.open_wall`, so every day counts).
    pub dust_days_per_year: f32,
}

impl Default for AgeParams {
    fn default() -> Self {
        AgeParams {
            years: None,
            rainfalls_per_year: 0.8,
            moss_years_per_year: 1.0,
            dust_days_per_year: 365.0,
        }
    }
}
