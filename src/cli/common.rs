//! Pieces `run` and `batch` share: preset loading and the progress bar.

use std::io::IsTerminal;
use std::path::Path;

use anyhow::Context;
use clap::Args;
use grime::clock::{self, Pins};
use grime::preset::{self, Preset};

/// Flags that choose and adjust the preset.
#[derive(Debug, Clone, Args)]
pub struct PresetFlags {
    /// Preset: a built-in name (see `grime preset --list`) or a .toml file.
    #[arg(long, value_name = "NAME|FILE")]
    pub preset: Option<String>,
    /// Say how old, e.g. `--say "very rusty near the railings, slightly
    /// scratched"`: adverbs (slightly .. completely) set coverage, applied
    /// over the preset and before --set.
    #[arg(long, value_name = "SENTENCE")]
    pub say: Option<String>,
    /// Override one preset field, e.g. `--set rain.k_a=0.7` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Number of rainfalls (same as `--set rain.layers=N`).
    #[arg(long, value_name = "N")]
    pub layers: Option<u32>,
    /// Age of the wall in years (same as `--set age.years=N`): sets the
    /// rainfalls, moss years and dust days from the rates in the preset's
    /// [age] section. Fields given with --layers or --set, or written in the
    /// preset file, win over it.
    #[arg(long, value_name = "N")]
    pub years: Option<u32>,
    /// Random seed (same as `--set seed=N`).
    #[arg(long, value_name = "N")]
    pub seed: Option<u64>,
    /// Refuse a photo whose run would need more memory than SIZE (e.g. 12G,
    /// 800M). Estimated before decoding at 37 bytes per pixel; default 4G,
    /// or the GRIME_MAX_MEMORY environment variable.
    #[arg(long, value_name = "SIZE", value_parser = grime::io::limits::parse_size)]
    pub max_memory: Option<u64>,
}

impl PresetFlags {
    /// The preset after the file or name, then `--say`, `--set`,
    /// `--layers`, `--years`, `--seed`, then the clock ([`grime::clock`]);
    /// and the fields the user pinned, the sentence's included
    /// (`--max-memory` is set for the process).
    pub fn resolve(&self) -> anyhow::Result<(Preset, Pins)> {
        if let Some(bytes) = self.max_memory {
            grime::io::limits::set_max_memory(bytes);
        }
        let mut pins = Pins::of_keys(self.set.iter().filter_map(|s| Some(s.split_once('=')?.0)));
        if self.layers.is_some() {
            pins = pins.union(Pins::of_keys(["rain.layers"]));
        }
        let mut p = match &self.preset {
            None => Preset::default(),
            Some(name) if !name.ends_with(".toml") && !Path::new(name).exists() => {
                preset::builtin(name)?
            }
            Some(file) => {
                let text = std::fs::read_to_string(file)
                    .with_context(|| format!("{file}: cannot read preset"))?;
                pins = pins.union(Pins::in_toml(&text));
                Preset::from_toml(&text).with_context(|| file.clone())?
            }
        };
        if let Some(sentence) = &self.say {
            let said = grime::say::apply(&mut p, sentence)?;
            pins = pins.union(Pins::of_keys(said.set.iter().map(|(k, _)| k.as_str())));
            for note in said.notes {
                eprintln!("grime: note: {note}");
            }
        }
        for s in &self.set {
            p.set(s)?;
        }
        if let Some(n) = self.layers {
            p.set(&format!("rain.layers={n}"))?;
        }
        if let Some(years) = self.years {
            p.age.years = Some(years);
        }
        if let Some(seed) = self.seed {
            p.seed = seed;
        }
        Ok((clock::resolve(&p, pins)?, pins))
    }
}

/// A progress bar on stderr, hidden when stderr is not a terminal or `quiet`.
pub fn progress_bar(quiet: bool, len: u64, template: &str) -> indicatif::ProgressBar {
    if quiet || !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(len);
    if let Ok(style) = indicatif::ProgressStyle::with_template(template) {
        bar.set_style(style.progress_chars("=> "));
    }
    bar
}

/// Flags that say how grime finds the wall in a photo without a mask.
#[derive(Debug, Clone, Args)]
pub struct SceneFlags {
    /// Where the wall is when no --mask is given: `auto` (the scene
    /// analysis leaves out sky, vegetation, glass and ground; a close-up of
    /// a wall is all wall) or `full` (every pixel is wall).
    #[arg(long, value_name = "auto|full", default_value = "auto", value_parser = ["auto", "full"])]
    pub region: String,
    /// Where rain water starts when the preset names no source lines:
    /// `auto` (the ledges the analysis finds: sills, cornices, copings, the
    /// roof line) or `top` (only the region's top edge).
    #[arg(long, value_name = "auto|top", default_value = "auto", value_parser = ["auto", "top"])]
    pub sources: String,
    /// The wall's width, e.g. `14m` or `850cm`: sets the scene's scale
    /// (metres per pixel) instead of estimating it from storeys and windows.
    #[arg(long, value_name = "METRES")]
    pub wall_width: Option<String>,
}

impl SceneFlags {
    /// What the flags ask for.
    pub fn seeing(&self) -> anyhow::Result<grime::batch::Seeing> {
        use grime::age::{RegionMode, SourcesMode};
        Ok(grime::batch::Seeing {
            region: match self.region.as_str() {
                "full" => RegionMode::Full,
                _ => RegionMode::Auto,
            },
            sources: match self.sources.as_str() {
                "top" => SourcesMode::Top,
                _ => SourcesMode::Auto,
            },
            wall_width_m: self
                .wall_width
                .as_deref()
                .map(grime::analysis::parse_metres)
                .transpose()?,
        })
    }
}
