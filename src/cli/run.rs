//! `grime run`: age one photo.

use std::path::PathBuf;

use anyhow::{Context, bail};
use clap::Args;
use grime::age::{self, Inputs, Outputs, Source};
use grime::perspective;
use grime::progress::Progress;
use grime::recipe::Recipe;
use grime::timelapse::{self, Timelapse};

use super::common::{PresetFlags, SceneFlags, progress_bar};

/// Age one photo and write the result (and optionally its layers and a report).
///
/// The output format follows the extension of -o: .png .jpg .tif .webp give
/// the flattened image; .psd (Photoshop) and .ora (OpenRaster: GIMP, Krita)
/// give a layered document.
#[derive(Debug, Args)]
#[command(after_help = "Examples:
  grime run --demo -o aged.png
  grime run photo.jpg -o aged.png                  # wall and ledges found automatically
  grime run photo.jpg -o aged.png --region full    # every pixel is wall
  grime run facade.jpg -o aged.png --mask wall.png --layers 12 --seed 7
  grime run facade.jpg -o aged.png --preset heavy-rain --set rain.k_a=0.7
  grime run facade.jpg -o aged.png --layers-dir layers/ --report report.json
  grime run street.jpg -o aged.psd --quad 120,80,900,140,880,700,140,690
  grime run photo.jpg -o aged.png --years 30 --timelapse ageing.gif
  grime run photo.jpg -o aged.png --years 30 --timelapse frames/ --frames 0,5,10,20,30
  grime run photo.jpg -o again.png --recipe-from aged.png")]
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
    /// The wall plane: four corners `x1,y1,...,x4,y4` in photo pixels
    /// (top-left, top-right, bottom-right, bottom-left) of a rectangle on the
    /// wall. The effects then run in that plane, so streaks follow the wall's
    /// vertical and shrink with distance.
    #[arg(long, value_name = "X1,Y1,...,X4,Y4", allow_hyphen_values = true)]
    quad: Option<String>,
    /// Normal map of the wall, the photo's size (tangent space, RGB =
    /// (n + 1) / 2, green = up): dust then takes its view and light angles
    /// per pixel, and surfaces facing down collect less of it.
    #[arg(long, value_name = "FILE")]
    normal_map: Option<PathBuf>,
    #[command(flatten)]
    preset: PresetFlags,
    #[command(flatten)]
    scene: SceneFlags,
    /// Also write each layer as an RGBA PNG plus manifest.json into DIR.
    #[arg(long, value_name = "DIR")]
    layers_dir: Option<PathBuf>,
    /// Write what happened (sizes, droplets, dirt, timings) as JSON to FILE.
    #[arg(long, value_name = "FILE")]
    report: Option<PathBuf>,
    /// Also write the wall ageing from the photo (year 0) to --years: an
    /// animated .gif, an animated .png (APNG), or a folder/ of PNG frames
    /// (each the file `--years K` would write).
    #[arg(long, value_name = "FILE|DIR/")]
    timelapse: Option<PathBuf>,
    /// The time-lapse's frames in years, e.g. `0,5,10,20,30` (default:
    /// every year up to 30, then 31 frames evenly spread).
    #[arg(long, value_name = "Y1,Y2,...", requires = "timelapse")]
    frames: Option<String>,
    /// Write the age ("12 years") on each time-lapse frame.
    #[arg(long, requires = "timelapse")]
    caption: bool,
    /// Longest side of a .gif or .png time-lapse's frames, pixels (0 = the
    /// photo's). A larger photo's frames are drawn at this size, as
    /// previews of the full-size run; a frames folder is always full size
    /// and exact.
    #[arg(
        long,
        value_name = "PX",
        default_value_t = 1024,
        requires = "timelapse"
    )]
    frame_size: u32,
    /// Age with the recipe stored in FILE (an output of grime): the same
    /// input gives a byte-identical output.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["preset", "set", "layers", "years", "seed", "region", "sources", "wall_width", "quad"])]
    recipe_from: Option<PathBuf>,
    /// Use --recipe-from's recipe even on an input that is not its own.
    #[arg(long, requires = "recipe_from")]
    force: bool,
    /// No progress bar.
    #[arg(short, long)]
    quiet: bool,
}

pub fn run(args: RunArgs) -> anyhow::Result<()> {
    let (preset, pins) = args.preset.resolve()?;
    let source = match (&args.demo, &args.input) {
        (Some(name), _) => Source::Demo(name.clone()),
        (None, Some(input)) => Source::File(input.clone()),
        (None, None) => bail!("give an input photo or --demo"),
    };
    let seeing = args.scene.seeing()?;
    let inputs = Inputs {
        source,
        mask: args.mask,
        normal_map: args.normal_map,
        quad: args
            .quad
            .as_deref()
            .map(perspective::parse_quad)
            .transpose()?,
        region: seeing.region,
        sources: seeing.sources,
        wall_width_m: seeing.wall_width_m,
    };
    let (inputs, preset) = match &args.recipe_from {
        None => (inputs, preset),
        Some(file) => {
            let text = grime::recipe::read::from_file(file)?;
            let recipe = Recipe::from_text(&text)?;
            if recipe.grime != env!("CARGO_PKG_VERSION") {
                eprintln!(
                    "grime: warning: the recipe was made by grime {}, this is {}; the output may differ",
                    recipe.grime,
                    env!("CARGO_PKG_VERSION")
                );
            }
            (recipe.apply(&inputs, args.force)?, recipe.preset)
        }
    };
    let timelapse = match &args.timelapse {
        None => None,
        Some(path) => {
            let mut t = Timelapse::new(path);
            t.pins = pins;
            t.caption = args.caption;
            t.max_side = args.frame_size;
            let Some(years) = preset.age.years else {
                bail!("--timelapse needs an age: add --years N (or age.years in the preset)");
            };
            t.years = match &args.frames {
                Some(list) => timelapse::parse_years(list)?,
                None => timelapse::default_years(years),
            };
            if let Some(late) = t.years.iter().find(|&&y| y > years) {
                bail!(
                    "--frames {late} is later than --years {years}; give frames from 0 to {years}"
                );
            }
            if t.kind()? == timelapse::Kind::Folder {
                std::fs::create_dir_all(path).with_context(|| {
                    format!("{}: cannot create the frames folder", path.display())
                })?;
            }
            Some(t)
        }
    };
    let outputs = Outputs {
        images: vec![args.output],
        layers_dir: args.layers_dir,
        report: args.report,
        create_dirs: false,
        timelapse,
    };

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
    age::age(
        &inputs,
        &preset,
        &outputs,
        &Progress::new(Some(&update), Some(cancel)),
    )?;
    bar.finish_and_clear();
    Ok(())
}
