//! Subcommands. clap's doc comments are the `--help` text.

mod common;
mod preset;
mod run;

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
    /// Print a preset as commented TOML (start your own from it).
    Preset(preset::PresetArgs),
}

/// Runs the chosen subcommand.
pub fn dispatch(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Run(args) => run::run(args),
        Command::Preset(args) => preset::run(args),
    }
}
