//! Synthetic labelled street scenes: sky, a plaster or brick facade with
//! storeys of windows, sills and a cornice, a road, sometimes a tree. The
//! truth is known exactly, so the evaluation can run anywhere (CI) with
//! data free of any licence.

use image::{DynamicImage, Rgb, RgbImage};
use rand::{Rng as _, SeedableRng};

use super::eval::{Band, CAR, GROUND, NEGATIVE, SKY, Truth, WALL_LABEL};
use crate::photo::Photo;
use crate::random::{Noise, Rng, mix};

/// A photo and what is in it.
#[derive(Debug, Clone)]
pub struct Scene {
    /// The photo.
    pub photo: Photo,
    /// Its labels, ledges and storey height.
    pub truth: Truth,
}

/// The scene for `seed`, `w` x `h` pixels.
pub fn scene(seed: u64, w: u32, h: u32) -> Scene {
    let mut rng = Rng::seed_from_u64(mix(seed ^ 0x5CE7E));
    let (fw, fh) = (w as f32, h as f32);
    let roof = (fh * rng.random_range(0.06..0.22)) as u32;
    let ground = (fh * rng.random_range(0.82..0.92)) as u32;
    let cornice = (roof + (fh * 0.02) as u32, roof + (fh * 0.045) as u32);
    let storeys = rng.random_range(3..=4u32);
    let storey = (ground - cornice.1) as f32 / storeys as f32;
    let cols = rng.random_range(3..=5u32);
    let bay = fw / cols as f32;
    let (win_w, win_h) = (bay * rng.random_range(0.35..0.5), storey * 0.5);
    let sill_h = (storey * 0.05).max(3.0);
    let shadow = (storey * 0.04).max(2.0);
    let brick = rng.random_bool(0.4);
    let wall_rgb: [f32; 3] = if brick {
        [rng.random_range(140.0..180.0), 80.0, 60.0]
    } else {
        let v = rng.random_range(170.0..225.0);
        [v, v * 0.93, v * 0.82]
    };
    let sky_rgb = [
        rng.random_range(110.0..170.0),
        rng.random_range(160.0..200.0),
        235.0,
    ];
    let road = rng.random_range(70.0..120.0);
    let tree = rng.random_bool(0.5).then(|| {
        let r = fh * rng.random_range(0.12..0.2);
        let cx = if rng.random_bool(0.5) {
            r * 0.8
        } else {
            fw - r * 0.8
        };
        (cx, ground as f32 - r * 0.6, r)
    });
    let mut windows = Vec::new();
    let mut ledges = Vec::new();
    for s in 0..storeys {
        let top = cornice.1 as f32 + s as f32 * storey + storey * 0.2;
        for c in 0..cols {
            let x0 = c as f32 * bay + (bay - win_w) / 2.0;
            windows.push([x0, top, x0 + win_w, top + win_h]);
            let over = win_w * 0.08;
            ledges.push(Band {
                x0: x0 - over,
                y0: top + win_h,
                x1: x0 + win_w + over,
                y1: top + win_h + sill_h,
            });
        }
    }
    ledges.push(Band {
        x0: 0.0,
        y0: cornice.0 as f32,
        x1: fw,
        y1: cornice.1 as f32,
    });
    let grain = Noise::new(seed.wrapping_add(1), w, h, 2.0, 3);
    let mottle = Noise::new(seed.wrapping_add(2), w, h, fw / 8.0, 3);
    let leaves = Noise::new(seed.wrapping_add(3), w, h, 4.0, 3);
    let mut labels = vec![WALL_LABEL; (w * h) as usize];
    let frame = (win_w * 0.06).max(2.0);
    let img = RgbImage::from_fn(w, h, |x, y| {
        let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
        let i = (y * w + x) as usize;
        let shade = |c: [f32; 3], k: f32| Rgb(c.map(|v| (v * (1.0 + k)).clamp(0.0, 255.0) as u8));
        let g = grain.at(px, py) - 0.5;
        if let Some((cx, cy, r)) = tree {
            let d = ((px - cx).powi(2) + (py - cy).powi(2)).sqrt();
            if d < r * (0.85 + 0.3 * leaves.at(px, py)) || (py > cy && (px - cx).abs() < r * 0.08) {
                labels[i] = NEGATIVE;
                let l = leaves.at(px * 3.0, py * 3.0);
                return shade([60.0, 110.0, 45.0], 0.6 * (l - 0.5));
            }
        }
        if y < roof {
            labels[i] = SKY;
            let t = py / roof as f32;
            return shade(sky_rgb, 0.1 * t + 0.01 * g);
        }
        if y >= ground {
            labels[i] = NEGATIVE;
            let t = (py - ground as f32) / (fh - ground as f32);
            return shade([road, road, road * 1.02], 0.15 * t + 0.06 * g);
        }
        if y >= cornice.0 && y < cornice.1 {
            return shade(wall_rgb.map(|v| (v * 1.2).min(250.0)), 0.05 * g);
        }
        if y >= cornice.1 && (y as f32) < cornice.1 as f32 + shadow * 1.5 {
            return shade(wall_rgb, -0.45 + 0.05 * g);
        }
        for s in &ledges[..ledges.len() - 1] {
            if px >= s.x0 && px < s.x1 {
                if py >= s.y0 && py < s.y1 {
                    return shade([235.0, 230.0, 220.0], 0.05 * g);
                }
                if py >= s.y1 && py < s.y1 + shadow {
                    return shade(wall_rgb, -0.4 + 0.05 * g);
                }
            }
        }
        for win in &windows {
            if px >= win[0] && px < win[2] && py >= win[1] && py < win[3] {
                let inner = px >= win[0] + frame
                    && px < win[2] - frame
                    && py >= win[1] + frame
                    && py < win[3] - frame;
                if !inner {
                    return shade([235.0, 235.0, 230.0], 0.03 * g);
                }
                labels[i] = super::eval::IGNORE;
                let refl = 0.3 * (1.0 - (py - win[1]) / (win[3] - win[1]));
                return shade([45.0, 55.0, 70.0], refl + 0.05 * g);
            }
        }
        let course = if brick && (y % 9 == 0 || (x + (y / 9) * 11) % 24 == 0) {
            0.12
        } else {
            0.0
        };
        shade(
            wall_rgb,
            0.15 * g + 0.12 * (mottle.at(px, py) - 0.5) + course,
        )
    });
    Scene {
        photo: Photo::new(DynamicImage::ImageRgb8(img)),
        truth: Truth {
            width: w,
            height: h,
            windows: Some(labels.iter().map(|&l| l == super::eval::IGNORE).collect()),
            labels: Some(labels),
            ledges,
            ledge_like: Vec::new(),
            storey_px: Some(storey),
            various: None,
        },
    }
}

/// What stands in front of the wall's foot in [`kerbside`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kerb {
    /// A grey car parked on the road in front of the wall: a body with
    /// window, trim and bumper bands across it and its shadow under it.
    ParkedCar,
    /// The left third of the wall in shade, as grey as the road, with the
    /// vertical joints of boarding (the ground fill climbs it by colour).
    ShadedBoards,
    /// A facade seen square on, as in CMP: a pavement strip along the
    /// bottom (from 93% of the height down) instead of the road, a grey
    /// plinth with horizontal grooves from 60% down, and a grey planked
    /// door in it down to the pavement (the ground fill climbs it).
    Plinth,
}

/// Sky over a plaster wall over a road (from 70% of the height down),
/// with `kerb` in front of or at the wall's foot. Labels: sky, wall,
/// ground, car (the door of [`Kerb::Plinth`] is not scored).
pub fn kerbside(kerb: Kerb, w: u32, h: u32) -> Scene {
    let (fw, fh) = (w as f32, h as f32);
    let grain = Noise::new(7, w, h, 2.0, 3);
    let mut labels = vec![WALL_LABEL; (w * h) as usize];
    let img = RgbImage::from_fn(w, h, |x, y| {
        let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
        let (u, v) = (px / fw, py / fh);
        let i = (y * w + x) as usize;
        let g = 12.0 * (grain.at(px, py) - 0.5);
        let grey = |l: f32| Rgb([l + g, l + g, l * 1.04 + g].map(|c| c.clamp(0.0, 255.0) as u8));
        if v < 0.15 {
            labels[i] = SKY;
            return Rgb([120, 170, 235]);
        }
        if kerb == Kerb::ParkedCar && (0.3..0.7).contains(&u) && (0.55..0.9).contains(&v) {
            labels[i] = CAR;
            return grey(match v {
                v if v < 0.66 => 55.0,
                v if (0.72..0.73).contains(&v) => 205.0,
                v if (0.84..0.86).contains(&v) => 70.0,
                v if v >= 0.86 => 25.0,
                _ => 145.0,
            });
        }
        if kerb == Kerb::Plinth && v >= 0.6 {
            if v >= 0.93 {
                labels[i] = GROUND;
                return grey(100.0);
            }
            if (0.45..0.55).contains(&u) {
                labels[i] = super::eval::IGNORE;
                return grey(if y % 10 == 0 { 95.0 } else { 100.0 });
            }
            return grey(if y % 12 < 2 { 125.0 } else { 150.0 });
        }
        if v >= 0.7 && kerb != Kerb::Plinth {
            labels[i] = GROUND;
            return grey(100.0);
        }
        if kerb == Kerb::ShadedBoards && u < 1.0 / 3.0 && v >= 0.2 {
            return grey(if x % 8 == 0 { 90.0 } else { 102.0 });
        }
        // Plaster, with a pilaster every sixth of the width.
        let l = if (u * 6.0).fract() < 0.1 {
            185.0
        } else {
            205.0
        };
        Rgb([l + g, l * 0.93 + g, l * 0.82 + g].map(|c| c.clamp(0.0, 255.0) as u8))
    });
    Scene {
        photo: Photo::new(DynamicImage::ImageRgb8(img)),
        truth: Truth {
            width: w,
            height: h,
            labels: Some(labels),
            ..Truth::default()
        },
    }
}

/// For unit tests: the analysis features of `img` (at its own size) and a
/// class map with sky over its first `sky_rows` rows and wall below.
#[cfg(test)]
pub(crate) fn sky_over_wall(
    img: RgbImage,
    sky_rows: u32,
) -> (super::features::Features, Vec<super::wall::Class>) {
    use super::wall::Class;
    let (w, h) = img.dimensions();
    let f = super::features::Features::new(&Photo::new(DynamicImage::ImageRgb8(img)), w.max(h));
    let class = (0..w * h)
        .map(|i| {
            if i < w * sky_rows {
                Class::Sky
            } else {
                Class::Wall
            }
        })
        .collect();
    (f, class)
}
