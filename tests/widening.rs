//! Streaks widen as they fall (`how-facades-age.md`: "narrow at the
//! release point, wider and fainter over a fall of about 0.5 to 2 m"):
//! under one ledge, a streak's visible width grows down its length rather
//! than closing to an icicle's tip (blind reviews p44 and later: "icicle-
//! tipped daggers under the sills").

use grime::photo::Photo;
use grime::pipeline::{self, Scene, Site};
use grime::preset::Preset;
use grime::progress::Progress;
use image::{DynamicImage, Rgb, RgbImage};

/// Photo size; the wall is 8 m wide (0.01 m a pixel), as in `streaks.rs`.
const W: u32 = 800;
const H: u32 = 600;
/// The ledge: row and ends, photo pixels.
const ROW: u32 = 100;
const ENDS: (u32, u32) = (100, 700);
/// Rows below the ledge looked at: 3 m, past the longest fall.
const BELOW: u32 = 300;
/// Columns either side of a streak's peak it is looked for in, per row
/// (runs wander sideways).
const HALF: usize = 12;

/// The ink (sum of the rain layers' alphas) below the ledge after forty
/// rainfalls with `seed`, row-major, rows ROW+1..ROW+BELOW.
fn ink(seed: u64) -> Vec<f32> {
    let photo = RgbImage::from_pixel(W, H, Rgb([180, 170, 150]));
    let (a, b) = (ENDS.0 as f32, ENDS.1 as f32);
    let scene = Scene::new(Photo::new(DynamicImage::ImageRgb8(photo)), None)
        .unwrap()
        .with_site(Site {
            metres_per_pixel: 0.01,
            ..Site::assumed(W)
        })
        .unwrap();
    let mut p = Preset::default();
    p.moss.enabled = false;
    p.dust.enabled = false;
    p.rain.top_edge = false;
    p.rain.layers = 40;
    p.seed = seed;
    p.rain.source_lines = vec![vec![[a, ROW as f32], [b, ROW as f32]]];
    let out = pipeline::run(&scene, &p, &Progress::none()).unwrap();
    let rain: Vec<_> = out
        .stack
        .layers
        .iter()
        .filter(|l| l.name.starts_with("rain ") && l.name != "rain washed")
        .collect();
    let mut ink = vec![0.0; (W * BELOW) as usize];
    for y in 0..BELOW {
        for x in 0..W {
            ink[(y * W + x) as usize] = rain
                .iter()
                .map(|l| l.rgba(x, ROW + 1 + y)[3] as f32 / 255.0)
                .sum();
        }
    }
    ink
}

/// A streak's visible widths, columns, at 20, 50 and 80% of its length,
/// where its ink passes 0.3 and 0.1 of the darkest under the ledge.
#[derive(Debug, Clone)]
struct Widths {
    at_03: [f32; 3],
    at_01: [f32; 3],
    /// Over half the row's own darkest near the streak.
    half: [f32; 3],
}

/// The streaks under the ledge of `ink`: the columns holding the most
/// mean ink within 0.15 m either side, with a fifth of the darkest's; a
/// streak's length is the last row where its ink across ([`HALF`] either
/// side of it) is at least a fifth of its most.
fn widths(ink: &[f32]) -> Vec<Widths> {
    let (w, rows) = (W as usize, BELOW as usize);
    let at = |x: usize, y: usize| ink[y * w + x];
    let profile: Vec<f32> = (0..w)
        .map(|x| (0..rows).map(|y| at(x, y)).sum::<f32>())
        .collect();
    let top = profile.iter().copied().fold(0.0, f32::max);
    let darkest = ink.iter().copied().fold(0.0, f32::max);
    let peaks = (HALF + 15..w - HALF - 15).filter(|&x| {
        let around = profile[x - 15..=x + 15].iter().copied().fold(0.0, f32::max);
        profile[x] >= around && profile[x] > 0.2 * top
    });
    peaks
        .map(|x| {
            let across: Vec<f32> = (0..rows)
                .map(|y| (x - HALF..=x + HALF).map(|c| at(c, y)).sum())
                .collect();
            let most = across.iter().copied().fold(0.0, f32::max);
            let length = across.iter().rposition(|&v| v >= 0.2 * most).unwrap_or(0) as f32;
            // The run of columns above `k` of the darkest around the row's
            // darkest near the streak.
            let width = |y: usize, k: f32| {
                let c = (x - HALF..=x + HALF)
                    .max_by(|&a, &b| at(a, y).total_cmp(&at(b, y)))
                    .unwrap();
                let level = match k < 0.0 {
                    true => -k * at(c, y),
                    false => k * darkest,
                };
                if at(c, y) < level {
                    return 0.0;
                }
                let left = (0..c).rev().take_while(|&i| at(i, y) >= level).count();
                let right = (c + 1..w).take_while(|&i| at(i, y) >= level).count();
                (1 + left + right) as f32
            };
            let rows_at = [0.2, 0.5, 0.8].map(|f| (f * length) as usize);
            Widths {
                at_03: rows_at.map(|y| width(y, 0.3)),
                at_01: rows_at.map(|y| width(y, 0.1)),
                half: rows_at.map(|y| width(y, -0.5)),
            }
        })
        .collect()
}

/// The mean of each of three positions over `all`.
fn means(all: &[[f32; 3]]) -> [f32; 3] {
    let n = all.len().max(1) as f32;
    [0, 1, 2].map(|i| all.iter().map(|a| a[i]).sum::<f32>() / n)
}

/// Three seeds' streaks pooled, their mean widths at 20 / 50 / 80% of
/// their length (columns, 0.01 m): over half their row's darkest, main at
/// b796688 22.6 / 20.8 / 20.6 (narrowing down, to an icicle's tip), now
/// 23.1 / 37.2 / 42.8; over a tenth of the darkest under the ledge (the
/// dirt film saturates the band under it, so its top is wide) 80.6 / 67.6
/// / 35.5, now 103.2 / 95.3 / 56.4; over 0.3 of it 34.2 / 27.7 / 14.9, now
/// 41.2 / 40.7 / 8.0 (the end fainter: the same ink over a wider wash).
#[test]
fn streaks_widen_downward_not_to_a_tip() {
    let inks: Vec<Vec<f32>> = [1, 2, 3].into_iter().map(ink).collect();
    let total: f32 = inks.iter().flatten().sum();
    let all: Vec<Widths> = inks.iter().flat_map(|i| widths(i)).collect();
    let a03 = means(&all.iter().map(|w| w.at_03).collect::<Vec<_>>());
    let a01 = means(&all.iter().map(|w| w.at_01).collect::<Vec<_>>());
    let half = means(&all.iter().map(|w| w.half).collect::<Vec<_>>());
    eprintln!(
        "ink {total:.0}, {} streaks; width at 20/50/80% of the length, columns: > 0.3 of the darkest \
         {a03:.1?}, > 0.1 {a01:.1?}, > half the row's darkest {half:.1?}",
        all.len()
    );
    assert!(
        half[2] > 1.4 * half[0],
        "widths over half a row's darkest {half:.1?}"
    );
    assert!(
        half[1] > 1.2 * half[0],
        "widths over half a row's darkest {half:.1?}"
    );
    assert!(a01[2] > 45.0, "widths over 0.1 of the darkest {a01:.1?}");
}
