//! `grime preset`: print presets.

use clap::Args;
use grime::preset::{self, BUILTIN, PARAMS};

/// Print a built-in preset as commented TOML.
#[derive(Debug, Args)]
pub struct PresetArgs {
    /// Built-in preset to print (`default`, `chang-table1`, ...).
    #[arg(default_value = "default")]
    name: String,
    /// List the built-in presets instead.
    #[arg(long)]
    list: bool,
    /// List every parameter with its symbol and range, one per line.
    #[arg(long)]
    params: bool,
}

pub fn run(args: PresetArgs) -> anyhow::Result<()> {
    if args.list {
        for (name, what) in BUILTIN {
            println!("{name:14} {what}");
        }
    } else if args.params {
        for p in PARAMS {
            println!(
                "{:28} {:8} {} ..= {}  {}",
                p.path, p.symbol, p.min, p.max, p.doc
            );
        }
    } else {
        print!("{}", preset::builtin(&args.name)?.to_commented_toml());
    }
    Ok(())
}
