//! The splash zone's soiling at the wall's foot (`how-facades-age.md`,
//! "Near the ground"): only where the wall stands on the ground, inside
//! the region, growing with the rainfalls, the same at any thread count.

use grime::effects::foot::LAYER;
use grime::photo::Photo;
use grime::pipeline::{self, Outcome, Scene, Site};
use grime::preset::Preset;
use grime::progress::Progress;
use image::{DynamicImage, GrayImage, Luma, Rgb, RgbImage};

/// Photo size; the wall's foot is on row `FOOT` in the left half, and the
/// right half's wall ends on that row at the frame's cut (no ground).
const W: u32 = 400;
const H: u32 = 300;
const FOOT: u32 = 250;
/// Metres per pixel: 1 cm.
const MPP: f32 = 0.01;

/// A grained wall with a window (not wall) in the middle of the left
/// half, the ground below row `FOOT` in the left half only.
fn scene() -> Scene {
    let photo = RgbImage::from_fn(W, H, |x, y| {
        let g = ((x.wrapping_mul(73_856_093) ^ y.wrapping_mul(19_349_663)) % 31) as u8;
        Rgb([160 + g, 150 + g, 135 + g])
    });
    let region = GrayImage::from_fn(W, H, |x, y| {
        let window = (60..120).contains(&x) && (100..180).contains(&y);
        Luma([if y < FOOT && !window { 255 } else { 0 }])
    });
    let ground = (0..W)
        .map(|x| if x < W / 2 { FOOT as f32 } else { f32::NAN })
        .collect();
    Scene::new(Photo::new(DynamicImage::ImageRgb8(photo)), Some(region))
        .unwrap()
        .with_site(Site {
            metres_per_pixel: MPP,
            ground,
            ..Site::assumed(W)
        })
        .unwrap()
}

/// The scene with the ground on row `FOOT` under the whole width, the
/// site `sure(x)` sure of it per column (the left half's wall stands on
/// it; the right half's line may be a car's roof taken for the foot).
fn scene_sure(sure: impl Fn(u32) -> f32) -> Scene {
    let s = scene();
    let site = Site {
        ground: vec![FOOT as f32; W as usize],
        ground_sure: (0..W).map(sure).collect(),
        ..s.site.clone()
    };
    s.with_site(site).unwrap()
}

/// The preset: `rainfalls` light rainfalls, no moss or dust.
fn preset(rainfalls: u32) -> Preset {
    let mut p = Preset {
        seed: 5,
        ..Preset::default()
    };
    p.rain.layers = rainfalls;
    p.rain.droplets = 20;
    p.foot.enabled = true;
    p.moss.enabled = false;
    p.dust.enabled = false;
    p
}

fn run(p: &Preset) -> Outcome {
    pipeline::run(&scene(), p, &Progress::none()).unwrap()
}

/// The soiling's alpha (0..255) per pixel, with its opacity; all 0 when
/// there is no such layer (nothing soiled).
fn soiling(out: &Outcome) -> Vec<f32> {
    let Some(layer) = out.stack.layers.iter().find(|l| l.name == LAYER) else {
        return vec![0.0; (W * H) as usize];
    };
    (0..H)
        .flat_map(|y| (0..W).map(move |x| (x, y)))
        .map(|(x, y)| layer.rgba(x, y)[3] as f32 * layer.opacity)
        .collect()
}

/// Mean alpha over the pixels of `rows` x `cols`.
fn mean(a: &[f32], rows: std::ops::Range<u32>, cols: std::ops::Range<u32>) -> f32 {
    let n = (rows.len() * cols.len()) as f32;
    rows.flat_map(|y| cols.clone().map(move |x| a[(y * W + x) as usize]))
        .sum::<f32>()
        / n
}

#[test]
fn the_foot_is_soiled_only_where_the_wall_stands_on_the_ground() {
    let out = run(&preset(40));
    assert!(out.stack.layers.iter().any(|l| l.name == LAYER));
    let a = soiling(&out);
    let scene = scene();
    let region = scene.region.as_deref().unwrap();
    for y in 0..H {
        for x in 0..W {
            let v = a[(y * W + x) as usize];
            if region.get_pixel(x, y)[0] == 0 {
                assert_eq!(v, 0.0, "soiling outside the region at ({x}, {y})");
            }
            // The right half's wall ends at the frame's cut, not on ground.
            if x >= W / 2 {
                assert_eq!(v, 0.0, "soiling with no ground below at ({x}, {y})");
            }
            // Nothing above 0.4 m, 1.35 (the top's rises) x 1.3 (specks).
            if (y as f32) < FOOT as f32 - 0.4 * 1.35 * 1.3 / MPP - 1.0 {
                assert_eq!(v, 0.0, "soiling {v} far above the foot at ({x}, {y})");
            }
        }
    }
    // The bottom 10 cm are soiled, more than the 20 cm above them.
    let cols = 10..W / 2 - 20;
    let low = mean(&a, FOOT - 10..FOOT, cols.clone());
    let mid = mean(&a, FOOT - 30..FOOT - 10, cols);
    assert!(low > 60.0, "the foot's mean alpha {low}");
    assert!(mid < low, "{mid} above, {low} at the foot");
}

#[test]
fn the_soiling_grows_with_the_rainfalls() {
    let foot = |n: u32| {
        let a = soiling(&run(&preset(n)));
        mean(&a, FOOT - 40..FOOT, 10..W / 2 - 20)
    };
    let (young, old, older) = (foot(2), foot(12), foot(40));
    assert!(young > 0.0, "{young}");
    assert!(young < old && old < older, "{young} {old} {older}");
    // No rainfall, no splashed soil.
    assert_eq!(foot(0), 0.0);
}

#[test]
fn the_soiling_darkens_the_foot_and_keeps_its_grain() {
    let out = run(&preset(40));
    let aged = out.stack.composite().to_rgb8();
    let photo = scene().photo.image().to_rgb8();
    let (mut before, mut after) = (Vec::new(), Vec::new());
    for x in 10..W / 2 - 20 {
        let y = FOOT - 3;
        before.push(photo.get_pixel(x, y)[1] as f32);
        after.push(aged.get_pixel(x, y)[1] as f32);
    }
    let m = |v: &[f32]| v.iter().sum::<f32>() / v.len() as f32;
    assert!(
        m(&after) < 0.85 * m(&before),
        "{} -> {}",
        m(&before),
        m(&after)
    );
    // Multiplied in: the grain's pixel-to-pixel steps go on, smaller.
    let steps = |v: &[f32]| v.windows(2).filter(|w| w[0] != w[1]).count();
    assert!(steps(&after) > steps(&before) / 2);
}

#[test]
fn the_soiling_is_byte_identical_at_one_and_two_threads() {
    let in_pool = |n: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
            .install(|| soiling(&run(&preset(12))))
    };
    let (one, two) = (in_pool(1), in_pool(2));
    assert!(one.iter().any(|v| *v > 0.0));
    assert!(one == two, "the soiling differs between 1 and 2 threads");
}

#[test]
fn the_foot_is_soiled_only_where_the_scene_is_sure_of_it() {
    let soiled = |sure: f32| {
        let sc = scene_sure(|x| if x < W / 2 { 1.0 } else { sure });
        let a = soiling(&pipeline::run(&sc, &preset(40), &Progress::none()).unwrap());
        let bottom = FOOT - (0.1 / MPP) as u32..FOOT;
        (
            mean(&a, bottom.clone(), 10..W / 2 - 20),
            mean(&a, bottom, W / 2 + 20..W - 10),
        )
    };
    // Sure on the left: soiled within its 10 cm; unsure on the right: not.
    let (sure, unsure) = soiled(0.3);
    assert!(sure > 60.0, "the sure foot's mean alpha {sure}");
    assert_eq!(unsure, 0.0, "soiling on a foot the scene is not sure of");
    // Half sure: soiled, less than where sure.
    let (_, half) = soiled(0.7);
    assert!(
        half > 0.3 * sure && half < 0.85 * sure,
        "{half} against {sure}"
    );
}
