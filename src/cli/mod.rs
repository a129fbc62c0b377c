//! Subcommands. clap's doc comments are the `--help` text.

mod batch;
mod common;
#[cfg(feature = "gui")]
mod gui;
mod preset;
mod recipe;
mod run;
mod scene;
pub mod signals;

use clap::{Parser, Subcommand};

/// Age photos of buildings: rain streaks that run down from ledges and darken
/// over the years, moss and dust, as layers you can finish in an editor.
#[derive(Debug, Parser)]
#[command(name = "grime", version, propagate_version = true)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Age one photo.
    Run(run::RunArgs),
    /// Age every photo in a folder, in parallel.
    Batch(batch::BatchArgs),
    /// Analyse a photo: wall region, ledges, rain shelter and scale.
    Scene(scene::SceneArgs),
    /// Print a preset as commented TOML (start your own from it).
    Preset(preset::PresetArgs),
    /// Print the recipe stored in an output: preset, seed, version, input hashes.
    Recipe(recipe::RecipeArgs),
    /// Open the interactive editor (region, source lines, perspective, live preview).
    #[cfg(feature = "gui")]
    Gui(gui::GuiArgs),
}

/// Runs the chosen subcommand.
pub fn dispatch(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Run(args) => {
            signals::install();
            run::run(args)
        }
        Command::Batch(args) => {
            signals::install();
            batch::run(args)
        }
        Command::Preset(args) => preset::run(args),
        Command::Recipe(args) => recipe::run(args),
        Command::Scene(args) => scene::run(args),
        #[cfg(feature = "gui")]
        Command::Gui(args) => gui::run(args),
    }
}
