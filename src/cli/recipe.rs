//! `grime recipe`: print the recipe stored in an output.

use std::path::PathBuf;

use clap::Args;

/// Print how an output was made: its preset (TOML), seed, grime's version
/// and the SHA-256 of its input and mask. Re-make it with
/// `grime run PHOTO -o OUT --recipe-from FILE`.
#[derive(Debug, Args)]
pub struct RecipeArgs {
    /// A PNG, JPEG, TIFF, WebP, PSD or ORA file grime wrote.
    file: PathBuf,
}

pub fn run(args: RecipeArgs) -> anyhow::Result<()> {
    print!("{}", grime::recipe::read::from_file(&args.file)?);
    Ok(())
}
