//! Moss in the photo's light and the wall's relief (`effects::surface::light`):
//! a colony takes the colour of the light on the wall and keeps the wall's
//! joints (`how-facades-age.md`, "Living growth").

use grime::photo::Photo;
use grime::pipeline::{self, Outcome, Scene};
use grime::preset::Preset;
use grime::progress::Progress;
use grime::random;
use image::{DynamicImage, RgbImage, RgbaImage};

const LUMA: [f32; 3] = [0.299, 0.587, 0.114];

/// Moss alone over the whole wall (no rain, no dust), colonies of
/// `baseline_px` pixels.
fn moss_only(w: u32, baseline_px: f32) -> Preset {
    let mut p = Preset::default();
    p.rain.layers = 0;
    p.dust.enabled = false;
    p.moss.open_wall = 1.0;
    p.moss.humidity = 1.0;
    p.moss.seed_rate = 2.0;
    p.moss.years = 20;
    p.moss.baseline = baseline_px / w as f32;
    p.seed = 3;
    p
}

fn moss_layer(img: RgbImage, p: &Preset) -> RgbaImage {
    let scene = Scene::new(Photo::new(DynamicImage::ImageRgb8(img)), None).unwrap();
    let out: Outcome = pipeline::run(&scene, p, &Progress::none()).unwrap();
    out.stack
        .layers
        .iter()
        .find(|l| l.name == "moss")
        .expect("a moss layer")
        .to_rgba()
}

/// Mean `(R - B) / luma` of the layer's pixels with alpha over 0.2.
fn warmth(layer: &RgbaImage) -> f32 {
    let (mut sum, mut n) = (0.0, 0);
    for px in layer.pixels().filter(|p| p[3] > 51) {
        let c = [px[0], px[1], px[2]].map(f32::from);
        let y: f32 = c.iter().zip(LUMA).map(|(v, k)| v * k).sum();
        sum += (c[0] - c[2]) / y.max(1.0);
        n += 1;
    }
    assert!(n > 500, "moss shows ({n} px)");
    sum / n as f32
}

/// A rough render of grain `v` in 150..190, each channel times `light`
/// (luma 1).
fn render(w: u32, h: u32, light: [f32; 3]) -> RgbImage {
    RgbImage::from_fn(w, h, |x, y| {
        let v = 150.0 + (random::mix((y as u64) << 32 | x as u64) % 40) as f32;
        image::Rgb(light.map(|k| (v * k).round().min(255.0) as u8))
    })
}

#[test]
fn moss_on_a_wall_in_warm_light_is_warmer_than_in_neutral_light() {
    let (w, h) = (320, 240);
    let p = moss_only(w, 6.0);
    // An evening sun's cast: the render's neutrals go orange, luma kept.
    let orange = [1.22, 0.94, 0.70];
    let y: f32 = orange.iter().zip(LUMA).map(|(v, k)| v * k).sum();
    let warm = warmth(&moss_layer(render(w, h, orange.map(|v| v / y)), &p));
    let neutral = warmth(&moss_layer(render(w, h, [1.0; 3]), &p));
    eprintln!("moss (R - B) / Y: warm light {warm:.3}, neutral {neutral:.3}");
    assert!(warm > neutral + 0.1, "warm {warm} vs neutral {neutral}");
}

/// A brick wall: 24 x 8 px bricks (luma about 190) in 1 px dark joints
/// (60), stretcher bond.
fn brick(w: u32, h: u32) -> (RgbImage, Vec<bool>) {
    let joint = |x: u32, y: u32| y.is_multiple_of(8) || (x + 12 * ((y / 8) % 2)).is_multiple_of(24);
    let img = RgbImage::from_fn(w, h, |x, y| {
        let g = (random::mix((y as u64) << 32 | x as u64) % 12) as u8;
        match joint(x, y) {
            true => image::Rgb([60 + g, 60 + g, 60 + g]),
            false => image::Rgb([185 + g, 185 + g, 185 + g]),
        }
    });
    let joints = (0..h)
        .flat_map(|y| (0..w).map(move |x| joint(x, y)))
        .collect();
    (img, joints)
}

#[test]
fn a_brick_walls_joints_show_through_a_colony() {
    let (w, h) = (320, 240);
    // Colonies 3 px across, as on a street photo (softened to the photo's
    // blur).
    let p = moss_only(w, 3.0);
    let (img, joints) = brick(w, h);
    let layer = moss_layer(img, &p);
    let (mut on_joint, mut on_brick) = ((0.0, 0), (0.0, 0));
    for (px, j) in layer.pixels().zip(&joints) {
        if px[3] <= 76 {
            continue;
        }
        let y: f32 = [px[0], px[1], px[2]]
            .iter()
            .zip(LUMA)
            .map(|(v, k)| f32::from(*v) * k)
            .sum();
        let acc = if *j { &mut on_joint } else { &mut on_brick };
        acc.0 += y;
        acc.1 += 1;
    }
    assert!(
        on_joint.1 > 200 && on_brick.1 > 1000,
        "{on_joint:?} {on_brick:?}"
    );
    let (jm, bm) = (
        on_joint.0 / on_joint.1 as f32,
        on_brick.0 / on_brick.1 as f32,
    );
    eprintln!("moss luma on joints {jm:.1}, on bricks {bm:.1}");
    // The joints are at a third of the bricks' luma: the colony over them
    // keeps most of that step.
    assert!(jm < 0.55 * bm, "joints {jm} vs bricks {bm}");
}
