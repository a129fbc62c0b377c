//! `grime run`: age one photo.

use std::path::{Path, PathBuf};

use anyhow::{Context, bail};
use clap::Args;
use grime::io::{self, Format};
use grime::pipeline::{self, Scene};
use grime::progress::Progress;
use grime::{demo, export};

use super::common::{PresetFlags, progress_bar};

/// Age one photo and write the result (and optionally its layers and a report).
///
/// The output format follows the extension of -o: .png .jpg .tif .webp give
/// the flattened image; .psd (Photoshop) and .ora (OpenRaster: GIMP, Krita)
/// give a layered document.
#[derive(Debug, Args)]
#[command(after_help = "Examples:
  grime run --demo -o aged.png
  grime run facade.jpg -o aged.png --mask wall.png --layers 12 --seed 7
  grime run facade.jpg -o aged.png --preset heavy-rain --set rain.k_a=0.7
  grime run facade.jpg -o aged.png --layers-dir layers/ --report report.json")]
pub struct RunArgs {
    /// The photo to age (PNG, JPEG, TIFF or WebP; 8 or 16 bit).
    #[arg(required_unless_present = "demo")]
    input: Option<PathBuf>,
    /// Use an embedded sample instead of INPUT: `facade` (procedural, with
    /// region and ledges) or `brick` (CC0 photo).
    #[arg(long, value_name = "NAME", num_args = 0..=1, default_missing_value = "facade", conflicts_with = "input")]
    demo: Option<String>,
    /// Output file; never the input.
    #[arg(short, long, value_name = "FILE")]
    output: PathBuf,
    /// Region mask: greyscale image of the photo's size, white = wall.
    /// Pixels outside it are left byte-identical.
    #[arg(long, value_name = "FILE")]
    mask: Option<PathBuf>,
    /// Normal map of the wall, the photo's size (tangent space, RGB =
    /// (n + 1) / 2, green = up): dust then takes its view and light angles
    /// per pixel, and surfaces facing down collect less of it.
    #[arg(long, value_name = "FILE")]
    normal_map: Option<PathBuf>,
    #[command(flatten)]
    preset: PresetFlags,
    /// Also write each layer as an RGBA PNG plus manifest.json into DIR.
    #[arg(long, value_name = "DIR")]
    layers_dir: Option<PathBuf>,
    /// Write what happened (sizes, droplets, dirt, timings) as JSON to FILE.
    #[arg(long, value_name = "FILE")]
    report: Option<PathBuf>,
    /// No progress bar.
    #[arg(short, long)]
    quiet: bool,
}

pub fn run(args: RunArgs) -> anyhow::Result<()> {
    let mut preset = args.preset.resolve()?;
    Format::from_path(&args.output)?;
    let (photo, mut region) = match (&args.demo, &args.input) {
        (Some(name), _) => {
            let d = demo::load(name)?;
            if preset.rain.source_lines.is_empty() {
                preset.rain.source_lines = d.source_lines;
            }
            (d.photo, d.region)
        }
        (None, Some(input)) => {
            refuse_overwrite(input, &args.output)?;
            (io::load_photo(input)?, None)
        }
        (None, None) => bail!("give an input photo or --demo"),
    };
    if let Some(mask) = &args.mask {
        if let Some(input) = &args.input {
            refuse_overwrite(mask, &args.output)?;
            refuse_overwrite(input, &args.output)?;
        }
        region = Some(io::load_mask(mask, photo.width(), photo.height())?);
    }
    let mut scene = Scene::new(photo, region)?;
    if let Some(path) = &args.normal_map {
        refuse_overwrite(path, &args.output)?;
        let normals = io::load_photo(path)?.into_image().to_rgb8();
        scene = scene
            .with_normals(normals)
            .with_context(|| path.display().to_string())?;
    }

    let bar = progress_bar(
        args.quiet,
        1000,
        "{spinner} {msg:8} [{bar:40}] {percent:>3}% {elapsed}",
    );
    let cancel = super::signals::cancel_flag();
    let update = |stage: &str, f: f32| {
        bar.set_message(stage.to_string());
        bar.set_position((f * 1000.0) as u64);
    };
    let outcome = pipeline::run(&scene, &preset, &Progress::new(Some(&update), Some(cancel)))?;
    bar.finish_and_clear();

    export::save(&outcome.stack, &args.output)?;
    if let Some(dir) = &args.layers_dir {
        export::layers_dir::write(&outcome.stack, dir)?;
    }
    if let Some(path) = &args.report {
        let text = serde_json::to_string_pretty(&outcome.report)?;
        io::write_atomic(path, |out| {
            std::io::Write::write_all(out, text.as_bytes()).map_err(|e| grime::Error::io(path, e))
        })
        .with_context(|| "cannot write the report")?;
    }
    Ok(())
}

fn refuse_overwrite(input: &Path, output: &Path) -> anyhow::Result<()> {
    if io::same_file(input, output) {
        return Err(grime::Error::WouldOverwriteInput {
            path: output.to_path_buf(),
        }
        .into());
    }
    Ok(())
}
