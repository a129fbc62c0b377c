//! Twin windows streak alike (blind review 30: "a comb of like drips under
//! one window and none under its twin"): a row of like sills drains alike
//! (`rain.twins`), each sill keeping its own drips.

mod common;

use common::wall::{self, luma, stains};
use grime::pipeline;
use image::RgbImage;

/// Photo size; the wall is 12 m wide (0.01 m a pixel).
const W: u32 = 1200;
const H: u32 = 400;
/// The sills' row, photo pixels.
const ROW: u32 = 80;
/// Six like sills 0.9 m wide, 1.9 m apart: their left ends.
const SILLS: [u32; 6] = [60, 250, 440, 630, 820, 1010];
const SILL_W: u32 = 90;
/// Rows below the sills looked at: 2.5 m, past the longest fall (2 m).
const BELOW: u32 = 250;
/// Columns either side of a sill looked at: its streaks' sides.
const SIDE: u32 = 20;

/// The wall's colour.
const WALL: [u8; 3] = [180, 170, 150];

/// The wall after `layers` rainfalls with `seed` under the six sills,
/// found by the analysis (sure), `rain.twins` at `twins`.
fn run(layers: u32, seed: u64, twins: bool) -> pipeline::Outcome {
    let lines: Vec<Vec<[f32; 2]>> = SILLS
        .iter()
        .map(|&x| vec![[x as f32, ROW as f32], [(x + SILL_W) as f32, ROW as f32]])
        .collect();
    wall::rain_on((W, H, WALL), lines, Some(1.0), (layers, seed), |p| {
        p.rain.twins = twins
    })
}

/// The ink under each sill: its box's summed darkening (1 - luma over the
/// clean wall's).
fn inks(image: &RgbImage) -> Vec<f32> {
    SILLS
        .iter()
        .map(|&x0| {
            let cols = (x0 - SIDE)..(x0 + SILL_W + SIDE);
            let rows = (ROW + 1)..(ROW + 1 + BELOW);
            rows.flat_map(|y| cols.clone().map(move |x| (x, y)))
                .map(|(x, y)| 1.0 - luma(&image.get_pixel(x, y).0) / luma(&WALL))
                .sum()
        })
        .collect()
}

/// The coefficient of variation of `v`.
fn cv(v: &[f32]) -> f32 {
    let n = v.len() as f32;
    let mean = v.iter().sum::<f32>() / n;
    (v.iter().map(|x| (x - mean).powi(2)).sum::<f32>() / n).sqrt() / mean
}

/// Six like sills in a row, forty rainfalls (`--years 50`), seeds 1-6:
/// the ink under each sill varies across the row by a coefficient of
/// variation (mean over the seeds) of 0.455 with `rain.twins` off (main:
/// each sill drains its own log-normal share, up to ~5x its twin's) and
/// 0.213 on (each keeps a small share of its own drain and its own drips).
#[test]
fn like_sills_in_a_row_streak_alike() {
    let seeds = 1..=6u64;
    let n = seeds.clone().count() as f32;
    let (mut off, mut on) = (0.0, 0.0);
    for seed in seeds {
        let (a, b) = (
            inks(&stains(run(40, seed, false))),
            inks(&stains(run(40, seed, true))),
        );
        eprintln!(
            "seed {seed}: off {a:.0?} cv {:.3}; on {b:.0?} cv {:.3}",
            cv(&a),
            cv(&b)
        );
        off += cv(&a) / n;
        on += cv(&b) / n;
    }
    eprintln!("the ink's CV across the row: off {off:.3}, on {on:.3}");
    assert!(on < 0.6 * off, "CV off {off:.3}, on {on:.3}");
}

/// Twin sills' stains are the same at any thread count.
#[test]
fn twin_sills_are_the_same_at_any_thread_count() {
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| stains(run(6, 4, true)))
    };
    assert!(run(1) == run(2), "1 and 2 threads differ");
}
