//! Scene analysis: what grime sees in a photo of a building. The wall (a
//! soft matte, not sky, vegetation, glass, ground), the ledges water drips
//! from (sills, cornices, window heads, ...), where projecting ledges shelter
//! the wall from rain, and metres per pixel.
//!
//! Classical vision at about 1 MP (colour and texture statistics, gradient
//! edge tracing), pure and deterministic at any thread count: no model
//! weights. The matte is refined with a (fast) guided filter on the photo
//! and upsampled to the photo's size.
//!
//! ```
//! use grime::analysis::{self, Options};
//! let d = grime::demo::facade(320, 240);
//! let a = analysis::analyse(&d.photo, &Options::default()).unwrap();
//! assert_eq!(a.matte.dimensions(), (320, 240));
//! assert!(a.wall_fraction > 0.5);
//! assert!(!a.source_lines().is_empty());
//! ```

mod appearance;
mod courses;
mod crowns;
pub mod eval;
mod features;
mod flips;
mod foliage;
pub mod foot_line;
mod glass;
mod ground;
mod joints;
mod lamps;
mod laps;
mod lawn;
mod ledge_kinds;
mod ledges;
mod light;
mod matte;
mod overlay;
mod perspective;
mod plane;
mod roof;
mod scale;
pub mod shelter;
mod silhouette;
mod sky_windows;
mod slants;
pub mod synthetic;
mod things;
mod twigs;
mod vehicles;
mod wall;

use std::time::Instant;

use image::{GrayImage, RgbImage};
use serde::Serialize;

use crate::error::{Error, Result};
use crate::photo::Photo;
use crate::preset::SourceLine;

pub use features::Features;
pub use scale::parse_metres;
pub use wall::Class;

/// How the analysis runs.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    /// Longest side of the analysis image in pixels (the photo is
    /// downsampled to it; smaller photos are analysed as they are).
    pub analysis_side: u32,
    /// The wall's width in metres, if the user knows it (`--wall-width`):
    /// overrides the scale estimate.
    pub wall_width_m: Option<f32>,
    /// Name of the photo, for error messages.
    pub name: String,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            analysis_side: 1024,
            wall_width_m: None,
            name: "the photo".into(),
        }
    }
}

/// What a ledge is; each is a water source.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LedgeKind {
    /// A window sill: water gathers toward its ends.
    Sill,
    /// A cornice: the projecting band under the roof.
    Cornice,
    /// A coping or parapet top.
    Coping,
    /// The head (lintel) of a window.
    WindowHead,
    /// A balcony slab.
    Balcony,
    /// A string course: a horizontal band across the facade.
    StringCourse,
    /// Where the wall meets the sky.
    RoofLine,
}

impl LedgeKind {
    /// Short lower-case label (also the JSON name).
    pub fn label(self) -> &'static str {
        match self {
            LedgeKind::Sill => "sill",
            LedgeKind::Cornice => "cornice",
            LedgeKind::Coping => "coping",
            LedgeKind::WindowHead => "window head",
            LedgeKind::Balcony => "balcony",
            LedgeKind::StringCourse => "string course",
            LedgeKind::RoofLine => "roof line",
        }
    }
}

/// One ledge.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Ledge {
    /// What it is.
    pub kind: LedgeKind,
    /// Polyline in photo pixels, left to right, just below the ledge's
    /// drip edge (where water leaves it).
    pub polyline: Vec<[f32; 2]>,
    /// 0..1: how sure the detector is.
    pub confidence: f32,
}

/// How metres per pixel were estimated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ScaleSource {
    /// From the spacing of storeys (rows of sills or windows), 3.1 m each.
    StoreyHeight,
    /// From the windows' height, 1.4 m each.
    WindowSize,
    /// From the wall width the user gave.
    UserWidth,
    /// Nothing to go by: the wall is taken to be 10 m wide.
    Default,
}

/// Metres per photo pixel and how they were found.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Scale {
    /// Metres per photo pixel.
    pub metres_per_pixel: f32,
    /// How.
    pub source: ScaleSource,
}

/// Milliseconds spent per stage.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct Timings {
    /// Downsampling and features.
    pub features_ms: f32,
    /// Classes.
    pub classes_ms: f32,
    /// Ledges and shelter (alongside the matte's refinement).
    pub ledges_ms: f32,
    /// Matte refinement (alongside the ledges) and upsampling.
    pub matte_ms: f32,
    /// Everything.
    pub total_ms: f32,
}

/// Everything the analysis found.
#[derive(Debug, Clone, Serialize)]
pub struct Analysis {
    /// Photo width.
    pub width: u32,
    /// Photo height.
    pub height: u32,
    /// Analysis width.
    pub analysis_width: u32,
    /// Analysis height.
    pub analysis_height: u32,
    /// Wall matte at the photo's size, 255 = wall, soft edges.
    #[serde(skip)]
    pub matte: GrayImage,
    /// Class per analysis pixel, row-major (`analysis_width` wide).
    #[serde(skip)]
    pub classes: Vec<Class>,
    /// Share of the photo that is wall, 0..1.
    pub wall_fraction: f32,
    /// Ledges, top to bottom.
    pub ledges: Vec<Ledge>,
    /// The wall's foot seen in the photo, where the wall stands on the
    /// ground in view ([`foot_line`]): polylines in photo pixels, left to
    /// right, each from the left edge of its first column to the right
    /// edge of its last.
    pub foot: Vec<Vec<[f32; 2]>>,
    /// How sure each polyline of [`Analysis::foot`] is to be the wall's
    /// foot, 0..1, in the same order ([`foot_line`]'s `sure`).
    pub foot_sure: Vec<f32>,
    /// Rain shelter at analysis resolution, 0..1 (1 = fully sheltered).
    #[serde(skip)]
    pub shelter: Vec<f32>,
    /// Metres per pixel.
    pub scale: Scale,
    /// How long each stage took.
    pub timings: Timings,
}

/// Analyses a photo.
///
/// # Errors
/// [`Error::NoWall`] when (almost) nothing in the photo is wall.
pub fn analyse(photo: &Photo, opts: &Options) -> Result<Analysis> {
    let t0 = Instant::now();
    let ms = |t: Instant| t.elapsed().as_secs_f32() * 1000.0;
    let f = Features::new(photo, opts.analysis_side.max(16));
    let t_features = ms(t0);
    let t1 = Instant::now();
    let mut classes = wall::classify(&f);
    vehicles::islands(&f, &mut classes);
    vehicles::short_pieces(&f, &mut classes);
    things::mark(&f, &mut classes);
    let t_classes = ms(t1);
    let t3 = Instant::now();
    // Ledges and the matte need only the classes: side by side.
    let (((foot, (ledges, shelter, storey, glass_rows)), t_ledges), small) = rayon::join(
        || {
            let t2 = Instant::now();
            // The foot needs only the classes too: beside the ledges.
            let found = rayon::join(
                || foot_line::find(&f, &classes),
                || {
                    let glass_rows = scale::glass_rows(&f, &classes);
                    let storey = scale::jamb_periods(&f, &classes).checked(glass_rows);
                    let ledges = ledges::detect(&f, &classes, storey);
                    let shelter = shelter::map(&f, &ledges);
                    (ledges, shelter, storey, glass_rows)
                },
            );
            (found, ms(t2))
        },
        || matte::refine(&f, &classes),
    );
    // Windows between their frame's members (the ledges found): glass,
    // and out of the wall's matte.
    let mut small = small;
    for i in glass::frames::find(&f, &classes, &ledges) {
        classes[i] = Class::Glass;
        small[i] = 0.0;
    }
    let wall_fraction = small.iter().sum::<f32>() / small.len().max(1) as f32;
    if wall_fraction < 0.01 {
        return Err(Error::NoWall {
            name: opts.name.clone(),
        });
    }
    let matte = matte::upsample(&small, &f, photo.width(), photo.height());
    let t_matte = ms(t3);
    let to_photo = |p: [f32; 2]| [p[0] * f.sx, p[1] * f.sy];
    let ledges: Vec<Ledge> = ledges
        .into_iter()
        .map(|l| Ledge {
            polyline: l.polyline.into_iter().map(to_photo).collect(),
            ..l
        })
        .collect();
    let (foot, foot_sure): (Vec<_>, Vec<_>) = foot
        .into_iter()
        .map(|(l, s)| (l.into_iter().map(to_photo).collect(), s))
        .unzip();
    let scale = scale::estimate(&f, &classes, &ledges, storey, glass_rows, opts.wall_width_m);
    Ok(Analysis {
        width: photo.width(),
        height: photo.height(),
        analysis_width: f.w as u32,
        analysis_height: f.h as u32,
        matte,
        classes,
        wall_fraction,
        ledges,
        foot,
        foot_sure,
        shelter,
        scale,
        timings: Timings {
            features_ms: t_features,
            classes_ms: t_classes,
            ledges_ms: t_ledges,
            matte_ms: t_matte,
            total_ms: ms(t0),
        },
    })
}

impl Analysis {
    /// The ledges as rain source lines (photo pixels), the format of
    /// `preset.rain.source_lines`.
    pub fn source_lines(&self) -> Vec<SourceLine> {
        self.ledges.iter().map(|l| l.polyline.clone()).collect()
    }

    /// The scene as pretty JSON (scene.json): sizes, wall fraction, scale,
    /// ledges, timings.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_else(|_| "{}".into())
    }

    /// The photo with what grime saw drawn on it: the wall tinted, other
    /// classes coloured and named, each ledge drawn and labelled.
    pub fn overlay(&self, photo: &Photo) -> RgbImage {
        overlay::draw(self, photo)
    }

    /// Rain shelter at photo pixel (x, y), 0..1.
    pub fn shelter_at(&self, x: f32, y: f32) -> f32 {
        let ax = (x * self.analysis_width as f32 / self.width as f32).max(0.0) as usize;
        let ay = (y * self.analysis_height as f32 / self.height as f32).max(0.0) as usize;
        let w = self.analysis_width as usize;
        let ax = ax.min(w - 1);
        let ay = ay.min(self.analysis_height as usize - 1);
        self.shelter[ay * w + ax]
    }

    /// Per column of the photo scaled to `w` x `h`, the row of the wall's
    /// foot ([`Analysis::foot`]) in that image's pixels, `NaN` where none
    /// is seen.
    pub fn foot_rows(&self, w: u32, h: u32) -> Vec<f32> {
        let (fx, fy) = (
            self.width as f32 / w.max(1) as f32,
            self.height as f32 / h.max(1) as f32,
        );
        (0..w)
            .map(|x| {
                let px = (x as f32 + 0.5) * fx;
                self.foot_at(px).map_or(f32::NAN, |(y, _)| y / fy)
            })
            .collect()
    }

    /// The seen foot's row under photo column `px` and how sure its
    /// stretch is (the first polyline of [`Analysis::foot`] spanning it).
    fn foot_at(&self, px: f32) -> Option<(f32, f32)> {
        self.foot.iter().enumerate().find_map(|(i, l)| {
            let sure = self.foot_sure.get(i).copied().unwrap_or(0.0);
            crate::effects::habitat::row_at(l, px).map(|y| (y, sure))
        })
    }

    /// Per column of the photo scaled to `w` wide, how sure the wall's
    /// foot there is ([`Analysis::foot_sure`]), 0 where none is seen.
    pub fn foot_sure_rows(&self, w: u32) -> Vec<f32> {
        let fx = self.width as f32 / w.max(1) as f32;
        (0..w)
            .map(|x| {
                let px = (x as f32 + 0.5) * fx;
                self.foot_at(px).map_or(0.0, |(_, s)| s)
            })
            .collect()
    }

    /// Per column of the photo scaled to `w` x `h`, the class map's lowest
    /// wall row with ground right below it, in that image's pixels, `NaN`
    /// where the column ends in anything else ([`foot_line::class_line`]:
    /// what the effects took for the foot before [`Analysis::foot`]).
    pub fn class_foot_rows(&self, w: u32, h: u32) -> Vec<f32> {
        let (aw, ah) = (self.analysis_width as usize, self.analysis_height as usize);
        let line = foot_line::class_line(&self.classes, aw, ah);
        (0..w)
            .map(|x| line[(x as usize * aw / w.max(1) as usize).min(aw - 1)] * h as f32 / ah as f32)
            .collect()
    }

    /// Class at photo pixel (x, y).
    pub fn class_at(&self, x: u32, y: u32) -> Class {
        let w = self.analysis_width as usize;
        let ax = ((x as u64 * w as u64) / self.width as u64) as usize;
        let ay = ((y as u64 * self.analysis_height as u64) / self.height as u64) as usize;
        self.classes[ay.min(self.analysis_height as usize - 1) * w + ax.min(w - 1)]
    }
}

/// The 4-neighbours of pixel `i` of a `w` x `h` row-major grid.
pub(crate) fn neighbours(i: usize, w: usize, h: usize) -> impl Iterator<Item = usize> {
    let (x, y) = (i % w, i / w);
    [
        (x > 0).then(|| i - 1),
        (x + 1 < w).then(|| i + 1),
        (y > 0).then(|| i - w),
        (y + 1 < h).then(|| i + w),
    ]
    .into_iter()
    .flatten()
}
