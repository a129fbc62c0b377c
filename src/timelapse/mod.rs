//! The time-lapse: the wall ageing from the photo (year 0) to the run's
//! age, as an animated GIF, an animated PNG (APNG) or a folder of PNG
//! frames. The frames come from one run ([`crate::pipeline::run_frames`]):
//! the rain is simulated once; each frame equals `grime run --years K`.
//! An animation of a photo larger than its frame size is drawn at that
//! size instead, from the full-size run's layers shrunk
//! ([`crate::pipeline::run_previews`]): a preview of the full-size run at
//! each age.

pub mod caption;

use std::path::{Path, PathBuf};

use image::{DynamicImage, RgbaImage};

use crate::clock::{self, Pins};
use crate::error::{Error, Result};
use crate::io;
use crate::pipeline::{self, Outcome, Scene};
use crate::preset::Preset;
use crate::progress::Progress;
use crate::recipe::{Recipe, embed};

/// What a time-lapse is written as, from its path.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// `.gif`: 256 colours, one palette for all frames.
    Gif,
    /// `.png` or `.apng`: an animated PNG, exact colours.
    Apng,
    /// A folder (a path ending in `/`, without extension, or an existing
    /// folder): one PNG per frame, `year-005.png`, each the file
    /// `grime run --years 5 -o …png` writes.
    Folder,
}

/// A time-lapse to write alongside a run.
#[derive(Debug, Clone)]
pub struct Timelapse {
    /// Where: a `.gif`, a `.png` (APNG) or a folder.
    pub path: PathBuf,
    /// The frames' ages in years, in order; empty = [`default_years`].
    pub years: Vec<u32>,
    /// The fields pinned against the clock ([`crate::clock`]), as for the run.
    pub pins: Pins,
    /// Write "N years" on each frame.
    pub caption: bool,
    /// Longest side of an animation's frames (GIF, APNG); 0 = the photo's.
    /// Folder frames are always full size.
    pub max_side: u32,
    /// How long each frame shows, milliseconds (the last shows 4 times as long).
    pub frame_ms: u16,
}

impl Timelapse {
    /// A time-lapse at `path` with the default frames, no caption.
    pub fn new(path: impl Into<PathBuf>) -> Timelapse {
        Timelapse {
            path: path.into(),
            years: Vec::new(),
            pins: Pins::none(),
            caption: false,
            max_side: 1024,
            frame_ms: 250,
        }
    }

    /// What the path asks for.
    ///
    /// # Errors
    /// [`Error::UnknownFormat`] for a file that is not `.gif`, `.png` or `.apng`.
    pub fn kind(&self) -> Result<Kind> {
        let p = &self.path;
        let ext = p
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        if p.to_string_lossy().ends_with('/') || p.is_dir() || ext.is_none() {
            return Ok(Kind::Folder);
        }
        match ext.as_deref() {
            Some("gif") => Ok(Kind::Gif),
            Some("png" | "apng") => Ok(Kind::Apng),
            _ => Err(Error::Preset(format!(
                "--timelapse {}: use a .gif, a .png (animated PNG) or a folder/",
                p.display()
            ))),
        }
    }

    /// The frame file of `years` in a [`Kind::Folder`] time-lapse.
    pub fn frame_path(&self, years: u32) -> PathBuf {
        self.path.join(format!("year-{years:03}.png"))
    }

    /// The files it writes, for the overwrite guard: its file, or each
    /// frame's when it is a folder (`run_years` is the run's age).
    ///
    /// # Errors
    /// As [`Timelapse::kind`].
    pub fn files(&self, run_years: Option<u32>) -> Result<Vec<PathBuf>> {
        Ok(match self.kind()? {
            Kind::Folder => self
                .frame_years(run_years.unwrap_or(0))
                .into_iter()
                .map(|y| self.frame_path(y))
                .collect(),
            _ => vec![self.path.clone()],
        })
    }

    /// Peak memory of a run `run_years` old on a `w` x `h` photo with this
    /// time-lapse ([`io::limits::estimate_timelapse`]).
    pub fn memory(&self, w: u32, h: u32, run_years: u32) -> u64 {
        let kept = match self.kind() {
            Ok(Kind::Folder) | Err(_) => 0,
            Ok(_) => self.frame_years(run_years).len() as u64,
        };
        io::limits::estimate_timelapse(w, h, kept, self.max_side)
    }

    /// The frames' ages for a run `run_years` old.
    pub fn frame_years(&self, run_years: u32) -> Vec<u32> {
        match self.years.is_empty() {
            true => default_years(run_years),
            false => self.years.clone(),
        }
    }
}

/// The default frames for a run `years` old: every year up to 30 years,
/// then 31 frames evenly spread; frame 0 is the photo.
pub fn default_years(years: u32) -> Vec<u32> {
    let n = years.min(30);
    let mut out: Vec<u32> = (0..=n)
        .map(|i| (i as u64 * years as u64).div_ceil(n.max(1) as u64) as u32)
        .collect();
    out.dedup();
    out
}

/// Parses `--frames 0,5,10,20,30`.
///
/// # Errors
/// [`Error::Preset`] naming the entry that is not a whole number of years.
pub fn parse_years(text: &str) -> Result<Vec<u32>> {
    text.split(',')
        .map(|s| {
            s.trim().parse().map_err(|_| {
                Error::Preset(format!(
                    "--frames: {s:?} is not a whole number of years; e.g. --frames 0,5,10,20,30"
                ))
            })
        })
        .collect()
}

/// Runs `scene` at `preset` (the run's age) and writes the time-lapse `t`
/// of it; returns the run's outcome.
///
/// # Errors
/// [`Error::OutOfRange`] when `preset` has no age or a frame is older than
/// the run; the pipeline's and the writers' errors.
pub fn run(
    scene: &Scene,
    preset: &Preset,
    t: &Timelapse,
    recipe: &Recipe,
    progress: &Progress,
) -> Result<Outcome> {
    let kind = t.kind()?;
    let run_years = preset.age.years.ok_or_else(|| Error::OutOfRange {
        field: "age.years".into(),
        value: "unset".into(),
        range: "a number of years: a time-lapse needs --years N (or age.years in the preset)"
            .into(),
    })?;
    let years = t.frame_years(run_years);
    if let Some(&late) = years.iter().find(|&&y| y > run_years) {
        return Err(Error::OutOfRange {
            field: "--frames".into(),
            value: late.to_string(),
            range: format!("0 ..= {run_years} (the run's --years)"),
        });
    }
    let presets = years
        .iter()
        .map(|&y| clock::at(preset, y, t.pins))
        .collect::<Result<Vec<_>>>()?;
    if kind == Kind::Folder {
        std::fs::create_dir_all(&t.path).map_err(|e| Error::io(&t.path, e))?;
    }
    let (w, h) = scene.size();
    if kind != Kind::Folder && t.max_side > 0 && w.max(h) > t.max_side {
        return previews(scene, preset, (&presets, &years), t, recipe, progress);
    }
    let mut frames = Vec::new();
    let icc = scene.photo.icc.as_deref();
    let out = pipeline::run_frames(scene, preset, &presets, progress, &mut |i, frame| {
        let img = frame.composite();
        let text = recipe.with_preset(&presets[i]).to_text();
        if kind == Kind::Folder && !t.caption {
            // As `export::save_with` writes the stack to a PNG.
            return io::save_image_with(&img, icc, &t.frame_path(years[i]), Some(&text));
        }
        let mut rgba = img.to_rgba8();
        if t.caption {
            caption::draw(&mut rgba, years[i]);
        }
        match kind {
            Kind::Folder => {
                let img = DynamicImage::ImageRgba8(rgba);
                io::save_image_with(&img, None, &t.frame_path(years[i]), Some(&text))
            }
            _ => {
                frames.push(rgba);
                Ok(())
            }
        }
    })?;
    write_animation(t, kind, &frames, recipe)?;
    Ok(out)
}

/// An animation of a photo larger than its frames: the run at full size,
/// and the frames drawn at their size on the scene and presets scaled to
/// it ([`Scene::scaled`], [`Preset::scaled`]): the full-size run's layers
/// shrunk once, its rain kept at each frame's rainfalls, moss, dust and
/// washed runs made at a few key frames and cross-faded between them
/// ([`pipeline::run_previews`]). A frame is so a preview of the full-size
/// run at its age (tested within a tolerance). In a wall plane, whose rain
/// is not handed over, each frame is the run of the scaled scene at its age
/// ([`pipeline::run_frames`]).
fn previews(
    scene: &Scene,
    preset: &Preset,
    (presets, years): (&[Preset], &[u32]),
    t: &Timelapse,
    recipe: &Recipe,
    progress: &Progress,
) -> Result<Outcome> {
    // The rain is kept only where the key frames need it.
    let keys: Vec<Preset> = pipeline::key_frames(presets)
        .into_iter()
        .map(|k| presets[k].clone())
        .collect();
    let (out, rain) = pipeline::run_sharing_rain(scene, preset, &keys, &progress.span(0.0, 0.5))?;
    let (w, h) = scene.size();
    let (fw, fh) = crate::shrink::fit(w, h, t.max_side);
    let (sx, sy) = (fw as f32 / w as f32, fh as f32 / h as f32);
    let small = scene.scaled(fw, fh);
    let small_presets: Vec<Preset> = presets.iter().map(|p| p.scaled(sx, sy)).collect();
    let small_last = preset.scaled(sx, sy);
    let mut frames = Vec::with_capacity(presets.len());
    let mut each = |i: usize, frame: pipeline::Frame| {
        let mut rgba = frame.composite().to_rgba8();
        if t.caption {
            caption::draw(&mut rgba, years[i]);
        }
        frames.push(rgba);
        Ok(())
    };
    let span = progress.span(0.5, 1.0);
    match &rain {
        Some(rain) => pipeline::run_previews(
            &small,
            &small_last,
            &small_presets,
            &out,
            rain,
            &span,
            &mut each,
        )?,
        // In a wall plane: the frames' own rain.
        None => {
            pipeline::run_frames(&small, &small_last, &small_presets, &span, &mut each)?;
        }
    }
    write_animation(t, t.kind()?, &frames, recipe)?;
    Ok(out)
}

/// Writes `frames` as the GIF or APNG `t` names (nothing for a folder,
/// whose frames are written as they come).
fn write_animation(t: &Timelapse, kind: Kind, frames: &[RgbaImage], recipe: &Recipe) -> Result<()> {
    match kind {
        Kind::Folder => Ok(()),
        Kind::Gif => write_gif(&t.path, frames, t.frame_ms),
        Kind::Apng => write_apng(&t.path, frames, t.frame_ms, &recipe.to_text()),
    }
}

/// Each frame's delay; the last holds longer.
fn delay(i: usize, n: usize, frame_ms: u16) -> u16 {
    if i + 1 == n {
        frame_ms.saturating_mul(4)
    } else {
        frame_ms
    }
}

fn encode_error(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Encode {
        path: path.to_path_buf(),
        reason: e.to_string(),
    }
}

/// An animated GIF, looping, with one palette for all frames (NeuQuant,
/// trained on the first and last frame): a colour keeps its index from
/// frame to frame, so the wall does not flicker as it ages. Each frame's
/// pixels are mapped to it (through a table of colours at 6 bits a
/// channel) and LZW-coded in parallel.
fn write_gif(path: &Path, frames: &[RgbaImage], frame_ms: u16) -> Result<()> {
    use rayon::prelude::*;
    let (Some(first), Some(last)) = (frames.first(), frames.last()) else {
        return Err(encode_error(path, "no frames"));
    };
    let (Ok(w), Ok(h)) = (u16::try_from(first.width()), u16::try_from(first.height())) else {
        return Err(encode_error(
            path,
            "a GIF frame is at most 65535 pixels wide",
        ));
    };
    let mut sample = first.as_raw().clone();
    sample.extend_from_slice(last.as_raw());
    let quant = color_quant::NeuQuant::new(10, 256, &sample);
    // Each colour's palette index, read from a table of colours at 6 bits
    // a channel (the centre of each cell mapped once): a colour is at most
    // 2 levels a channel from its cell's, against the palette's 256
    // colours for the photo's millions.
    let lut: Vec<u8> = (0..1usize << 18)
        .into_par_iter()
        .map(|i| {
            let level = |shift: usize| (((i >> shift) & 63) << 2 | 2) as u8;
            quant.index_of(&[level(12), level(6), level(0), 255]) as u8
        })
        .collect();
    let indexed: Vec<gif::Frame> = frames
        .par_iter()
        .enumerate()
        .map(|(i, f)| {
            let mut frame = gif::Frame {
                width: w,
                height: h,
                buffer: f
                    .as_raw()
                    .chunks_exact(4)
                    .map(|p| lut[lut_index(p)])
                    .collect::<Vec<u8>>()
                    .into(),
                delay: delay(i, frames.len(), frame_ms) / 10,
                ..gif::Frame::default()
            };
            frame.make_lzw_pre_encoded();
            frame
        })
        .collect();
    io::write_atomic(path, |out| {
        let mut gif = gif::Encoder::new(out, w, h, &quant.color_map_rgb())
            .map_err(|e| encode_error(path, e))?;
        gif.set_repeat(gif::Repeat::Infinite)
            .map_err(|e| encode_error(path, e))?;
        for frame in &indexed {
            gif.write_lzw_pre_encoded_frame(frame)
                .map_err(|e| encode_error(path, e))?;
        }
        Ok(())
    })
}

/// The cell of a colour (RGBA, alpha ignored) in the 6-bit table.
fn lut_index(p: &[u8]) -> usize {
    ((p[0] as usize >> 2) << 12) | ((p[1] as usize >> 2) << 6) | (p[2] as usize >> 2)
}

/// An animated PNG (8-bit RGBA), looping, with the run's recipe.
fn write_apng(path: &Path, frames: &[RgbaImage], frame_ms: u16, recipe: &str) -> Result<()> {
    let Some(first) = frames.first() else {
        return Err(encode_error(path, "no frames"));
    };
    io::write_atomic(path, |out| {
        let mut enc = png::Encoder::new(out, first.width(), first.height());
        // Fast deflate: default compression took 0.15 s a 1 MP frame.
        enc.set_compression(png::Compression::Fast);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_animated(frames.len() as u32, 0)
            .map_err(|e| encode_error(path, e))?;
        enc.add_itxt_chunk(embed::KEY.into(), recipe.into())
            .map_err(|e| encode_error(path, e))?;
        let mut w = enc.write_header().map_err(|e| encode_error(path, e))?;
        for (i, f) in frames.iter().enumerate() {
            w.set_frame_delay(delay(i, frames.len(), frame_ms), 1000)
                .map_err(|e| encode_error(path, e))?;
            w.write_image_data(f.as_raw())
                .map_err(|e| encode_error(path, e))?;
        }
        w.finish().map_err(|e| encode_error(path, e))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_frames_are_every_year_then_31() {
        assert_eq!(default_years(3), [0, 1, 2, 3]);
        assert_eq!(default_years(0), [0]);
        let long = default_years(100);
        assert_eq!((long.len(), long[0], *long.last().unwrap()), (31, 0, 100));
    }

    #[test]
    fn frames_parse_and_kinds_follow_the_path() {
        assert_eq!(parse_years("0, 5,10").unwrap(), [0, 5, 10]);
        assert!(parse_years("0,x").is_err());
        assert_eq!(Timelapse::new("a.gif").kind().unwrap(), Kind::Gif);
        assert_eq!(Timelapse::new("a.PNG").kind().unwrap(), Kind::Apng);
        assert_eq!(Timelapse::new("frames/").kind().unwrap(), Kind::Folder);
        assert!(Timelapse::new("a.jpg").kind().is_err());
    }
}
