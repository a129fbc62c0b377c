//! `grime batch`: age a whole folder in parallel.

use std::path::PathBuf;

use anyhow::bail;
use clap::Args;
use grime::batch::{self, OutputFormat, Shard};

use super::common::{PresetFlags, SceneFlags, progress_bar};

/// Age every photo in a folder, in parallel, into a mirrored output folder.
///
/// Each image runs with its own seed, derived from the preset seed and its
/// path relative to INPUT (shown by --json), so its output is the same alone,
/// in any batch, order or shard: `grime run INPUT/REL -o out.png --seed
/// SEED` gives the same image. A file that cannot be read is reported and the
/// others go on; the exit code is then 1. Outputs are written to a temporary
/// file and renamed, so an interrupted batch leaves no half-written image and
/// --skip-existing resumes it.
///
/// A photo's wall plane (as `grime run --quad`) can sit beside it in a
/// sidecar file named after it plus `.quad` (`door.jpg.quad`), holding
/// `x1,y1,...,x4,y4` in photo pixels.
#[derive(Debug, Args)]
pub struct BatchArgs {
    /// Folder of photos (PNG, JPEG, TIFF, WebP; extensions in any case).
    input: PathBuf,
    /// Output folder (created if missing); sub-folders mirror INPUT's. Never
    /// INPUT itself, and not inside it unless --allow-inside-input.
    #[arg(short, long, value_name = "DIR")]
    output: PathBuf,
    #[command(flatten)]
    preset: PresetFlags,
    #[command(flatten)]
    scene: SceneFlags,
    /// Output formats, comma-separated: keep (the input's own), png, jpg,
    /// tif, webp, psd, ora. An output in the input's format keeps its name;
    /// others take its stem and the format's extension.
    #[arg(
        long,
        value_name = "LIST",
        value_delimiter = ',',
        default_value = "keep"
    )]
    format: Vec<OutputFormat>,
    /// Descend into sub-folders (symbolic links to folders are not followed).
    #[arg(short, long)]
    recursive: bool,
    /// Threads [default: all cores]. Each ages one image at a time and the
    /// pipeline's parallel loops share them, so at most N images are in
    /// memory: about N x 115 MiB for 2 MP photos.
    #[arg(short, long, value_name = "N")]
    jobs: Option<usize>,
    /// Skip images whose outputs all exist (resume an interrupted batch), and
    /// remove grime's temporary files orphaned in OUTPUT by a killed run.
    #[arg(long)]
    skip_existing: bool,
    /// Process only shard K of N: the images whose index in the sorted
    /// listing of the whole folder is K-1 modulo N. Machines given 1/N ..
    /// N/N share a folder with no coordinator.
    #[arg(long, value_name = "K/N")]
    shard: Option<Shard>,
    /// Region masks: the mask of INPUT/REL is DIR/REL with extension .png
    /// (greyscale, white = wall). An image without its mask fails.
    #[arg(long, value_name = "DIR")]
    masks: Option<PathBuf>,
    /// Also write each image's layers (PNGs + manifest.json) into
    /// OUTPUT/REL.layers/.
    #[arg(long)]
    layers_dirs: bool,
    /// Allow OUTPUT inside INPUT (it is then left out of the listing).
    #[arg(long)]
    allow_inside_input: bool,
    /// Print the summary, with every image's status, seed and outputs, as
    /// JSON on stdout.
    #[arg(long)]
    json: bool,
    /// No progress bar.
    #[arg(short, long)]
    quiet: bool,
}

pub fn run(args: BatchArgs) -> anyhow::Result<()> {
    let (preset, _) = args.preset.resolve()?;
    preset.validate()?;
    if args.jobs == Some(0) {
        bail!("--jobs must be at least 1");
    }
    let opts = batch::Options {
        seeing: args.scene.seeing()?,
        recursive: args.recursive,
        formats: args.format.clone(),
        shard: args.shard,
        skip_existing: args.skip_existing,
        allow_inside_input: args.allow_inside_input,
        masks: args.masks.clone(),
        layers_dirs: args.layers_dirs,
    };
    if args.skip_existing {
        // Temporary files of a killed run (SIGKILL gives no time to clean up).
        let orphans = grime::io::temp::remove_orphans(&args.output, true);
        if !orphans.is_empty() {
            eprintln!("grime: removed {} orphaned temporary files", orphans.len());
        }
    }
    let plan = batch::plan(&args.input, &args.output, &opts)?;
    if plan.found == 0 {
        eprintln!(
            "grime: no images (.png .jpg .jpeg .tif .tiff .webp) in {}",
            args.input.display()
        );
    }
    for e in &plan.listing_errors {
        eprintln!("grime: {}: {}", args.input.join(&e.path).display(), e.error);
    }

    let bar = progress_bar(
        args.quiet,
        plan.jobs.len() as u64,
        "{bar:40} {pos}/{len} images  {per_sec}  ETA {eta}  {msg}",
    );
    let on_done = |r: &batch::FileReport| {
        if let Some(err) = &r.error {
            let path = args.input.join(&r.path);
            bar.suspend(|| eprintln!("grime: {}: {err}", path.display()));
        }
        bar.inc(1);
    };
    let cancel = Some(super::signals::cancel_flag());
    let summary = batch::run(&plan, &preset, args.jobs.unwrap_or(0), &on_done, cancel)?;
    bar.finish_and_clear();

    if args.json {
        println!("{}", serde_json::to_string_pretty(&summary)?);
    }
    eprintln!("{}", summary.line());
    if summary.failed > 0 {
        bail!(
            "{} failed (listed above); the other images were written",
            summary.failed
        );
    }
    Ok(())
}
