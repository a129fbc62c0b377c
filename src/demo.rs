//! Embedded samples: a procedural facade whose ledges are known exactly, and
//! a CC0 photo of a brick wall (see `samples/README.md`).

use image::{DynamicImage, GrayImage, Luma, Rgb, RgbImage};

use crate::analysis::{Ledge, LedgeKind};
use crate::error::{Error, Result};
use crate::photo::Photo;
use crate::pipeline::Site;
use crate::preset::SourceLine;
use crate::random;

/// The brick-wall photo (CC0, via scikit-image), 512x512 greyscale.
pub const BRICK_PNG: &[u8] = include_bytes!("../samples/brick-wall-cc0.png");

/// A ready-made scene: photo, region and the ledges water drips from.
#[derive(Debug, Clone)]
pub struct Demo {
    /// The photo.
    pub photo: Photo,
    /// The wall region (255 = wall), if the sample has one.
    pub region: Option<GrayImage>,
    /// Ledges, photo pixels.
    pub source_lines: Vec<SourceLine>,
    /// Its scale and ledges, known by construction.
    pub site: Site,
}

/// Metres per pixel of the brick sample: a brick's 6.5 cm face plus its
/// 1 cm joint spans about 33 pixels.
const BRICK_METRES_PER_PIXEL: f32 = 0.075 / 33.0;

/// Storey height of the procedural facade, in metres.
const STOREY_M: f32 = 3.1;

/// The built-in samples, by name.
pub const NAMES: &[&str] = &["facade", "brick"];

/// Loads a built-in sample by name.
///
/// # Errors
/// [`Error::Preset`] for an unknown name.
pub fn load(name: &str) -> Result<Demo> {
    match name {
        "facade" => Ok(facade(960, 720)),
        "brick" => {
            let img = image::load_from_memory(BRICK_PNG).map_err(|e| Error::Decode {
                path: "samples/brick-wall-cc0.png".into(),
                reason: e.to_string(),
            })?;
            let site = Site {
                metres_per_pixel: BRICK_METRES_PER_PIXEL,
                ..Site::assumed(img.width())
            };
            Ok(Demo {
                photo: Photo::new(img),
                region: None,
                source_lines: Vec::new(),
                site,
            })
        }
        _ => Err(Error::Preset(format!(
            "unknown demo {name:?}; choose one of: {}",
            NAMES.join(", ")
        ))),
    }
}

/// Geometry of the procedural facade, in fractions of its size.
pub struct Layout {
    /// Sky above this row (not wall).
    pub roof: u32,
    /// Pavement from this row down (not wall): the wall stands on it.
    pub ground: u32,
    /// Cornice band: top and bottom rows.
    pub cornice: (u32, u32),
    /// Windows as (x0, y0, x1, y1), exclusive ends; their sills lie below.
    pub windows: Vec<(u32, u32, u32, u32)>,
    /// Sill rectangles (x0, y0, x1, y1).
    pub sills: Vec<(u32, u32, u32, u32)>,
}

/// The facade's layout for a `w` x `h` image.
pub fn layout(w: u32, h: u32) -> Layout {
    let roof = h / 14;
    let cornice = (roof + h / 40, roof + h / 40 + h / 28);
    let (cols, rows) = (4, 2);
    let (ww, wh) = (w / 9, h / 4);
    let mut windows = Vec::new();
    let mut sills = Vec::new();
    for r in 0..rows {
        for c in 0..cols {
            let x0 = w / (2 * cols) + c * w / cols - ww / 2;
            let y0 = cornice.1 + h / 10 + r * (h * 2 / 5);
            windows.push((x0, y0, x0 + ww, y0 + wh));
            let over = ww / 8;
            sills.push((x0 - over, y0 + wh, x0 + ww + over, y0 + wh + h / 60 + 2));
        }
    }
    Layout {
        roof,
        ground: h - h / 20,
        cornice,
        windows,
        sills,
    }
}

fn inside(r: &(u32, u32, u32, u32), x: u32, y: u32) -> bool {
    x >= r.0 && x < r.2 && y >= r.1 && y < r.3
}

/// A procedural plaster facade: sky, cornice, two rows of windows with
/// sills, standing on a pavement. The region is the wall (not sky, not glass); the source lines are
/// the lower edges of the cornice and of every sill.
pub fn facade(w: u32, h: u32) -> Demo {
    let l = layout(w, h);
    let frame = (w / 120).max(2);
    let grain_noise = random::Noise::new(11, w, h, 3.0, 4);
    let mottle_noise = random::Noise::new(12, w, h, 90.0, 4);
    let img = RgbImage::from_fn(w, h, |x, y| {
        let (fx, fy) = (x as f32, y as f32);
        if y < l.roof {
            let t = fy / l.roof as f32;
            return Rgb([(150.0 + 40.0 * t) as u8, (180.0 + 30.0 * t) as u8, 215]);
        }
        let grain = grain_noise.at(fx, fy) - 0.5;
        let mottle = mottle_noise.at(fx, fy) - 0.5;
        let shade =
            |base: [f32; 3], k: f32| Rgb(base.map(|c| (c * (1.0 + k)).clamp(0.0, 255.0) as u8));
        if y >= l.ground {
            // Asphalt.
            return shade([96.0, 96.0, 100.0], 0.25 * grain + 0.1 * mottle);
        }
        if y >= l.cornice.0 && y < l.cornice.1 {
            let ridge = if (y - l.cornice.0) % 6 < 2 {
                -0.08
            } else {
                0.0
            };
            return shade([226.0, 220.0, 204.0], 0.10 * grain + ridge);
        }
        if y >= l.cornice.1 && y < l.cornice.1 + 4 {
            return shade([120.0, 112.0, 100.0], 0.1 * grain);
        }
        for s in &l.sills {
            if inside(s, x, y) {
                return shade([232.0, 228.0, 214.0], 0.08 * grain);
            }
            if x >= s.0 && x < s.2 && y >= s.3 && y < s.3 + 3 {
                return shade([130.0, 120.0, 105.0], 0.1 * grain);
            }
        }
        for win in &l.windows {
            if inside(win, x, y) {
                let inner = (win.0 + frame, win.1 + frame, win.2 - frame, win.3 - frame);
                let mullion = x.abs_diff((win.0 + win.2) / 2) < frame / 2 + 1;
                if !inside(&inner, x, y) || mullion {
                    return shade([238.0, 236.0, 230.0], 0.03 * grain);
                }
                let sky = 0.15 * (1.0 - (fy - win.1 as f32) / (win.3 - win.1) as f32);
                return shade([58.0, 68.0, 80.0], sky + 0.05 * grain);
            }
        }
        shade([214.0, 196.0, 168.0], 0.16 * grain + 0.10 * mottle)
    });
    let region = GrayImage::from_fn(w, h, |x, y| {
        let wall = y >= l.roof && y < l.ground && !l.windows.iter().any(|win| inside(win, x, y));
        Luma([if wall { 255 } else { 0 }])
    });
    let mut source_lines: Vec<SourceLine> = vec![vec![
        [0.0, l.cornice.1 as f32 + 3.0],
        [w as f32, l.cornice.1 as f32 + 3.0],
    ]];
    for s in &l.sills {
        source_lines.push(vec![
            [s.0 as f32, s.3 as f32 + 2.0],
            [s.2 as f32, s.3 as f32 + 2.0],
        ]);
    }
    let ledges = source_lines
        .iter()
        .enumerate()
        .map(|(i, line)| Ledge {
            kind: if i == 0 {
                LedgeKind::Cornice
            } else {
                LedgeKind::Sill
            },
            polyline: line.clone(),
            confidence: 1.0,
        })
        .collect();
    // A storey is the vertical spacing of the window rows (see `layout`).
    let storey_px = (h * 2 / 5).max(1) as f32;
    let site = Site {
        metres_per_pixel: STOREY_M / storey_px,
        ground: vec![l.ground as f32; w as usize],
        ground_sure: Vec::new(),
        ledges,
        shelter: None,
    };
    Demo {
        photo: Photo::new(DynamicImage::ImageRgb8(img)),
        region: Some(region),
        source_lines,
        site,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn facade_has_ledges_at_known_rows_and_glass_outside_the_region() {
        let d = facade(480, 360);
        let l = layout(480, 360);
        let region = d.region.as_ref().unwrap();
        let win = l.windows[0];
        assert_eq!(
            region.get_pixel((win.0 + win.2) / 2 - 10, (win.1 + win.3) / 2)[0],
            0
        );
        assert_eq!(region.get_pixel(2, l.roof + 1)[0], 255);
        assert_eq!(d.source_lines.len(), 1 + l.sills.len());
        assert!(
            d.source_lines
                .iter()
                .skip(1)
                .all(|s| s[0][1] > l.cornice.1 as f32)
        );
    }

    #[test]
    fn brick_sample_decodes() {
        let d = load("brick").unwrap();
        assert_eq!((d.photo.width(), d.photo.height()), (512, 512));
        assert!(load("nope").is_err());
    }
}
