//! The built-in presets.

use super::{Preset, gammaton};
use crate::error::{Error, Result};

/// Built-in presets, by name: what `grime preset NAME` prints and
/// `--preset NAME` loads.
pub const BUILTIN: &[(&str, &str)] = &[
    ("default", "the defaults: 12 rainfalls"),
    (
        "chang-table1",
        "the paper's Table 1 values (k_S 0.7, k_a 0.5, 600 droplets, r 100)",
    ),
    ("light-rain", "4 rainfalls, a recently weathered wall"),
    ("heavy-rain", "20 rainfalls, wetter and dirtier"),
    (
        "rust-runs",
        "gamma-tons: orange-brown rust runs below the ledges and fixings",
    ),
    (
        "salt-bloom",
        "gamma-tons: white efflorescence where water evaporates near the ground",
    ),
    (
        "splash",
        "gamma-tons: dirt thrown up the foot of the wall, and its splash zone soiling",
    ),
];

/// Returns a built-in preset by name.
///
/// # Errors
/// [`Error::Preset`] listing the known names.
pub fn builtin(name: &str) -> Result<Preset> {
    let mut p = Preset::default();
    match name {
        "default" => {}
        "chang-table1" => {
            p.rain.reference_width = 0;
            p.rain.droplets = 600;
            p.rain.k_s = 0.7;
            p.rain.k_a = 0.5;
            p.rain.r = 100.0;
            p.rain.initial_dirt = 5.0;
            // The paper's uniform release and unfaded stains.
            p.rain.drip_spacing_m = 0.0;
            p.rain.end_share = 0.0;
            p.rain.fall_m = 0.0;
            p.rain.sure_at = 0.0;
            p.stain.blur_m = 0.0;
            p.stain.washed_opacity = 0.0;
            p.stain.soot = 0.0;
            p.stain.wall_hue = 0.0;
            p.stain.texture = 0.0;
            p.stain.run_out_m = 0.0;
            p.stain.softness = 0.8;
            p.moss.baseline = 1.0 / 40.0;
            p.moss.mixed_species = false;
            p.moss.open_wall = 1.0;
        }
        "light-rain" => p.rain.layers = 4,
        "heavy-rain" => {
            p.rain.layers = 20;
            p.rain.droplets = 900;
            p.rain.ledge_dirt = 4.0;
            p.rain.mass_max = 160.0;
        }
        "rust-runs" | "salt-bloom" => p.gammaton = gammaton::builtin(name),
        "splash" => {
            p.gammaton = gammaton::builtin(name);
            p.foot.enabled = true;
        }
        _ => {
            let names: Vec<_> = BUILTIN.iter().map(|(n, _)| *n).collect();
            return Err(Error::Preset(format!(
                "unknown preset {name:?}; built-in presets: {}; or pass a .toml file",
                names.join(", ")
            )));
        }
    }
    Ok(p)
}
