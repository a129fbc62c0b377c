//! `grime scene`: what grime sees in a photo.

use std::path::{Path, PathBuf};

use anyhow::Context;
use clap::Args;
use grime::analysis::{self, Options};
use grime::io;
use image::DynamicImage;

/// Analyse a photo of a building: where the wall is (not sky, vegetation,
/// window glass or ground), the ledges water drips from (sills, cornices,
/// window heads, balconies, string courses, the roof line), where ledges
/// shelter the wall from rain, and metres per pixel.
///
/// With no output flag the scene is printed as JSON.
#[derive(Debug, Args)]
#[command(after_help = "Examples:
  grime scene photo.jpg -o scene.json --mask-out wall.png --overlay seen.png
  grime scene photo.jpg --wall-width 14m
  grime run photo.jpg -o aged.png --mask wall.png   # use (or edit) the mask")]
pub struct SceneArgs {
    /// The photo (PNG, JPEG, TIFF or WebP).
    input: PathBuf,
    /// Write the scene as JSON: image size, wall fraction, metres per pixel
    /// and how it was estimated, every ledge (kind, polyline in pixels,
    /// confidence), timings.
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
    /// Write the wall matte: greyscale image of the photo's size, white =
    /// wall, soft edges (usable as `grime run --mask`).
    #[arg(long, value_name = "FILE")]
    mask_out: Option<PathBuf>,
    /// Write the photo with what grime saw: the wall tinted, other classes
    /// named, each ledge drawn and named by its kind.
    #[arg(long, value_name = "FILE")]
    overlay: Option<PathBuf>,
    /// The wall's real width (e.g. 14m): sets metres per pixel instead of
    /// estimating it from storeys and windows.
    #[arg(long, value_name = "LENGTH")]
    wall_width: Option<String>,
}

pub fn run(args: SceneArgs) -> anyhow::Result<()> {
    let named: Vec<(PathBuf, String)> = [
        (&args.output, "-o"),
        (&args.mask_out, "--mask-out"),
        (&args.overlay, "--overlay"),
    ]
    .into_iter()
    .filter_map(|(p, flag)| p.clone().map(|p| (p, flag.to_string())))
    .collect();
    grime::age::guard_paths(&[&args.input], &named, None, false)?;
    for img in [&args.mask_out, &args.overlay].into_iter().flatten() {
        io::Format::from_path(img)?;
    }
    let wall_width_m = args
        .wall_width
        .as_deref()
        .map(analysis::parse_metres)
        .transpose()?;
    let photo = io::load_photo(&args.input)?;
    let opts = Options {
        wall_width_m,
        name: args.input.display().to_string(),
        ..Options::default()
    };
    let scene = analysis::analyse(&photo, &opts)?;
    let json = scene.to_json();
    match &args.output {
        Some(path) => write_text(path, &json).context("cannot write the scene")?,
        None if args.mask_out.is_none() && args.overlay.is_none() => println!("{json}"),
        None => {}
    }
    if let Some(path) = &args.mask_out {
        io::save_image(&DynamicImage::ImageLuma8(scene.matte.clone()), None, path)?;
    }
    if let Some(path) = &args.overlay {
        let img = DynamicImage::ImageRgb8(scene.overlay(&photo));
        io::save_image(&img, photo.icc.as_deref(), path)?;
    }
    Ok(())
}

fn write_text(path: &Path, text: &str) -> grime::Result<()> {
    io::write_atomic(path, |out| {
        std::io::Write::write_all(out, text.as_bytes()).map_err(|e| grime::Error::io(path, e))
    })
}
