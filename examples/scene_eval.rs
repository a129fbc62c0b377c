//! Measures `grime::analysis` against labelled photos (issue 11's targets).
//!
//! ```text
//! cargo run --release --example scene_eval -- labelmefacade DIR   # DIR has train.txt, images/, labels/
//! cargo run --release --example scene_eval -- cmp DIR             # DIR has cmp_bNNNN.jpg + .png
//! cargo run --release --example scene_eval -- synthetic N [--size 4000x3000]
//! ```
//! Add `--dump OUT` to write each photo's overlay, classes and matte into OUT,
//! `--each` to print each photo's numbers.
//! The datasets are research-only: keep them outside the repository.

use std::path::{Path, PathBuf};

use anyhow::{Context, bail};
use grime::analysis::eval::{
    self, CAR, GROUND, IGNORE, Metrics, SKY, Truth, VEGETATION, WALL_LABEL,
};
use grime::analysis::{self, Options, synthetic};
use grime::photo::Photo;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dump = args
        .iter()
        .position(|a| a == "--dump")
        .and_then(|i| args.get(i + 1))
        .map(PathBuf::from);
    // `--size WxH` for synthetic scenes (default 640x480).
    let size = args
        .iter()
        .position(|a| a == "--size")
        .and_then(|i| args.get(i + 1))
        .and_then(|v| v.split_once('x'))
        .and_then(|(w, h)| Some((w.parse().ok()?, h.parse().ok()?)))
        .unwrap_or((640u32, 480u32));
    let (kind, arg) = match (args.first(), args.get(1)) {
        (Some(k), Some(a)) => (k.as_str(), a.as_str()),
        _ => bail!("usage: scene_eval labelmefacade|cmp DIR | synthetic N [--dump OUT]"),
    };
    let items: Vec<(String, Photo, Truth)> = match kind {
        "labelmefacade" => labelmefacade(Path::new(arg))?,
        "cmp" => cmp(Path::new(arg))?,
        "synthetic" => (0..arg.parse::<u64>()?)
            .map(|s| {
                let sc = synthetic::scene(s, size.0, size.1);
                (format!("synthetic-{s}"), sc.photo, sc.truth)
            })
            .collect(),
        _ => bail!("unknown data set {kind:?}"),
    };
    let mut m = Metrics::default();
    for (name, photo, truth) in &items {
        let opts = Options {
            name: name.clone(),
            ..Options::default()
        };
        let a = analysis::analyse(photo, &opts).ok();
        if let (Some(dir), Some(a)) = (&dump, &a) {
            a.overlay(photo)
                .save(dir.join(format!("{name}.png")))
                .with_context(|| dir.display().to_string())?;
            let (w, h) = (a.analysis_width, a.analysis_height);
            let colours = image::RgbImage::from_fn(w, h, |x, y| {
                image::Rgb(match a.classes[(y * w + x) as usize] {
                    analysis::Class::Wall => [128, 0, 0],
                    analysis::Class::Sky => [0, 128, 128],
                    analysis::Class::Vegetation => [0, 128, 0],
                    analysis::Class::Glass => [0, 0, 128],
                    analysis::Class::Ground => [128, 128, 128],
                    analysis::Class::Thing => [128, 0, 128],
                })
            });
            colours.save(dir.join(format!("{name}-classes.png")))?;
            a.matte.save(dir.join(format!("{name}-matte.png")))?;
            if let Some(labels) = &truth.labels {
                foot_overlay(photo, a, labels).save(dir.join(format!("{name}-foot.png")))?;
            }
        }
        m.add(a.as_ref(), truth);
        if args.iter().any(|a| a == "--each") {
            let mut one = Metrics::default();
            one.add(a.as_ref(), truth);
            println!(
                "{name}: iou {:.2} spill {:.2} sky {:.2} ({} sky px, {} sky as wall px, {} vegetation as wall px) wall as ground {} px, ground as wall {} px, car as wall {} px, various as wall {}/{} px, ledge on car {} px, ledges found {}/{}",
                one.mean_iou(),
                one.spill(),
                one.sky_spill(),
                one.sky,
                one.spill_by[SKY as usize].1,
                one.spill_by[VEGETATION as usize].1,
                one.miss_by[analysis::Class::Ground as usize],
                one.spill_by[eval::GROUND as usize].1,
                one.spill_by[CAR as usize].1,
                one.various_wall,
                one.various,
                one.ledge_on[CAR as usize],
                one.bands_found,
                one.bands
            );
            // The storey as estimated and as labelled, photo pixels.
            if let (Some(a), Some(storey)) = (&a, truth.storey_px) {
                let est = eval::STOREY_M / a.scale.metres_per_pixel;
                println!(
                    "{name}: storey {est:.0} px, labels {storey:.0} px (x{:.2}, {:?})",
                    est / storey,
                    a.scale.source
                );
            }
        }
    }
    print!("{}", m.report());
    Ok(())
}

/// The photo with the wall's foot drawn on it: the labelled foot green,
/// the class map's lowest wall row over ground red, the seen foot blue.
fn foot_overlay(photo: &Photo, a: &analysis::Analysis, labels: &[u8]) -> image::RgbImage {
    let mut img = photo.image().to_rgb8();
    let (w, h) = img.dimensions();
    let truth = eval::true_foot(labels, w as usize);
    let lines = [
        (
            truth.iter().map(|t| t.unwrap_or(f32::NAN)).collect(),
            [0, 255, 0],
            0,
        ),
        (a.class_foot_rows(w, h), [255, 0, 0], 2),
        (a.foot_rows(w, h), [0, 80, 255], 4),
    ];
    for (line, colour, dy) in lines {
        let line: Vec<f32> = line;
        for (x, y) in line.iter().enumerate() {
            if y.is_finite() {
                for k in 0..2 {
                    let yy = (*y as i64 + dy + k - 3).clamp(0, h as i64 - 1) as u32;
                    img.put_pixel(x as u32, yy, image::Rgb(colour));
                }
            }
        }
    }
    img
}

fn load(path: &Path) -> anyhow::Result<Photo> {
    Ok(grime::io::load_photo(path)?)
}

/// LabelMeFacade training split: colour labels; building = wall; window,
/// door, various ignored (various counted on its own); sky, vegetation,
/// road, pavement, car negative.
fn labelmefacade(dir: &Path) -> anyhow::Result<Vec<(String, Photo, Truth)>> {
    let list = std::fs::read_to_string(dir.join("train.txt"))?;
    let mut out = Vec::new();
    for line in list.lines().filter(|l| !l.trim().is_empty()) {
        let img = dir.join(line.trim());
        let stem = img
            .file_stem()
            .unwrap_or_default()
            .to_string_lossy()
            .to_string();
        let lab = grime::io::load_photo(&dir.join("labels").join(format!("{stem}.png")))?;
        let lab = lab.image().to_rgb8();
        let windows: Vec<bool> = lab.pixels().map(|p| p.0 == [0, 0, 128]).collect();
        // The storey from the labelled windows' rows, as on CMP.
        let (w, h) = (lab.width() as usize, lab.height() as usize);
        let index: Vec<u8> = windows.iter().map(|&b| b as u8).collect();
        let storey_px = eval::storey_from_windows(
            &eval::components(&index, w, h, &[1], (w * h) / 20000),
            h as f32,
        );
        let various = lab.pixels().map(|p| p.0 == [0, 0, 0]).collect();
        let labels = lab
            .pixels()
            .map(|p| match p.0 {
                [128, 0, 0] => WALL_LABEL,
                [0, 128, 128] => SKY,
                [0, 128, 0] => VEGETATION,
                [128, 128, 128] | [128, 64, 0] => GROUND,
                [128, 0, 128] => CAR,
                _ => IGNORE,
            })
            .collect();
        let photo = load(&img)?;
        let truth = Truth {
            width: photo.width(),
            height: photo.height(),
            labels: Some(labels),
            storey_px,
            windows: Some(windows),
            various: Some(various),
            ..Truth::default()
        };
        out.push((stem, photo, truth));
    }
    Ok(out)
}

/// CMP base: palette-indexed labels (5 cornice, 6 sill, 3 window; for the
/// lenient precision 7 balcony, 10 molding).
fn cmp(dir: &Path) -> anyhow::Result<Vec<(String, Photo, Truth)>> {
    let mut names: Vec<PathBuf> = std::fs::read_dir(dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "jpg"))
        .collect();
    names.sort();
    let mut out = Vec::new();
    for img in names {
        let png = img.with_extension("png");
        let index = palette_indices(&png)?;
        let photo = load(&img)?;
        let (w, h) = (photo.width() as usize, photo.height() as usize);
        if index.len() != w * h {
            bail!("{}: label size differs from the photo", png.display());
        }
        let min_px = (w * h) / 20000;
        let ledges = eval::components(&index, w, h, &[5, 6], min_px);
        let windows = eval::components(&index, w, h, &[3], min_px);
        // Lenient: also horizontal mouldings (string courses; not the
        // surrounds of windows) and the top and foot of each balcony.
        let mut ledge_like = ledges.clone();
        let runs = horizontal_runs(&index, w, 10, (w / 30).max(8));
        ledge_like.extend(
            eval::components(&runs, w, h, &[1], min_px)
                .into_iter()
                .filter(|b| b.x1 - b.x0 >= 3.0 * (b.y1 - b.y0)),
        );
        for b in eval::components(&index, w, h, &[7], min_px) {
            ledge_like.push(eval::Band {
                y1: b.y0 + 1.0,
                ..b
            });
            ledge_like.push(eval::Band {
                y0: b.y1 - 1.0,
                ..b
            });
        }
        let truth = Truth {
            width: w as u32,
            height: h as u32,
            labels: None,
            ledges,
            ledge_like,
            storey_px: eval::storey_from_windows(&windows, h as f32),
            windows: Some(index.iter().map(|&l| l == 3).collect()),
            various: None,
        };
        let stem = img
            .file_stem()
            .unwrap_or_default()
            .to_string_lossy()
            .to_string();
        out.push((stem, photo, truth));
    }
    Ok(out)
}

/// 1 where `label` runs along its row for at least `min_run` pixels (the
/// horizontal parts of a moulding, not the jambs of a window surround).
fn horizontal_runs(index: &[u8], w: usize, label: u8, min_run: usize) -> Vec<u8> {
    let mut out = vec![0u8; index.len()];
    for (row, o) in index.chunks_exact(w).zip(out.chunks_exact_mut(w)) {
        let mut x = 0;
        while x < w {
            let start = x;
            while x < w && row[x] == label {
                x += 1;
            }
            if x - start >= min_run {
                o[start..x].fill(1);
            }
            x = x.max(start + 1);
        }
    }
    out
}

/// Palette indices of an indexed PNG: decoded to RGB, then mapped back
/// through the PLTE chunk.
fn palette_indices(path: &Path) -> anyhow::Result<Vec<u8>> {
    let bytes = std::fs::read(path)?;
    let mut pos = 8;
    let mut palette: Vec<[u8; 3]> = Vec::new();
    while pos + 8 <= bytes.len() {
        let len = u32::from_be_bytes(bytes[pos..pos + 4].try_into()?) as usize;
        let kind = &bytes[pos + 4..pos + 8];
        if kind == b"PLTE" {
            palette = bytes[pos + 8..pos + 8 + len]
                .chunks_exact(3)
                .map(|c| [c[0], c[1], c[2]])
                .collect();
            break;
        }
        pos += 12 + len;
    }
    if palette.is_empty() {
        bail!("{}: not a palette PNG", path.display());
    }
    let rgb = image::open(path)?.to_rgb8();
    Ok(rgb
        .pixels()
        .map(|p| palette.iter().position(|c| *c == p.0).unwrap_or(0) as u8)
        .collect())
}
