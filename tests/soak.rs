//! Thin dirt soaks into a brick wall's joints first; only thick dirt
//! covers the brick's face (`src/effects/rain/soak.rs`).

mod common;

use common::wall::{luma, rain_on_photo};
use image::{Rgb, RgbImage};

/// Whether (x, y) is a mortar joint of a stretcher bond at 1 cm a pixel:
/// bricks 20 x 6 px, joints 1 px, every other course offset by half.
fn joint(x: u32, y: u32) -> bool {
    let offset = if (y / 7).is_multiple_of(2) { 0 } else { 10 };
    y % 7 == 6 || (x + offset) % 21 == 20
}

/// Whether (x, y) is in the middle of a brick's face, 2 px from any joint.
fn face(x: u32, y: u32) -> bool {
    (-2i32..=2)
        .all(|d| !joint((x as i32 + d).max(0) as u32, y) && !joint(x, (y as i32 + d).max(0) as u32))
}

/// A brick wall with shadowed joints, 400 x 300 at 1 cm a pixel, aged by
/// `layers` rainfalls alone from one ledge across it at row 40 with stain
/// strength `strength`; the mean luma levels the rain took off the
/// joints and the faces below the ledge.
fn darkening(layers: u32, strength: f32) -> (f32, f32) {
    let photo = RgbImage::from_fn(400, 300, |x, y| match joint(x, y) {
        true => Rgb([92, 80, 74]),
        false => Rgb([158, 86, 64]),
    });
    let line = vec![[10.0, 40.0], [390.0, 40.0]];
    let out = rain_on_photo(photo.clone(), vec![line], None, (layers, 1), |p| {
        p.stain.washed_opacity = 0.0;
        p.stain.soot = 0.0;
        p.stain.strength = strength;
    });
    let aged = out.stack.composite().to_rgb8();
    let d: Vec<f32> = photo
        .pixels()
        .zip(aged.pixels())
        .map(|(a, b)| luma(&a.0) - luma(&b.0))
        .collect();
    // Where the stain is at its thickest: the mean darkening over 21 x 21
    // px (a brick and its joints) at least 0.6 of its most.
    let r = 10;
    let local = |x: u32, y: u32| {
        let mut sum = 0.0;
        for yy in y - r..=y + r {
            for xx in x - r..=x + r {
                sum += d[(yy * 400 + xx) as usize];
            }
        }
        sum / ((2 * r + 1) * (2 * r + 1)) as f32
    };
    let local: Vec<(u32, u32, f32)> = (45..250)
        .flat_map(|y| (20..380).map(move |x| (x, y)))
        .map(|(x, y)| (x, y, local(x, y)))
        .collect();
    let most = local.iter().map(|l| l.2).fold(0.0, f32::max);
    let (mut j, mut nj, mut f, mut nf) = (0.0, 0, 0.0, 0);
    for &(x, y, _) in local.iter().filter(|l| l.2 >= 0.6 * most) {
        let d = d[(y * 400 + x) as usize];
        if joint(x, y) {
            (j, nj) = (j + d, nj + 1);
        } else if face(x, y) {
            (f, nf) = (f + d, nf + 1);
        }
    }
    let (j, f) = (j / nj as f32, f / nf as f32);
    eprintln!("{layers} rainfalls of strength {strength}: joints {j}, faces {f}");
    (j, f)
}

/// A thin stain darkens the joints several times more than the brick's
/// face (the deposit "soaks into pores, mortar joints" instead of dimming
/// everything evenly, blind review); a full film darkens the face too.
#[test]
fn thin_dirt_fills_the_joints_first_thick_dirt_covers_the_face() {
    let (joints, faces) = darkening(2, 0.15);
    assert!(
        joints > 0.5,
        "thin stain: joints darken only {joints} levels"
    );
    assert!(
        joints > 3.0 * faces,
        "thin stain: joints {joints} levels, faces {faces}"
    );
    let (joints, faces) = darkening(40, 1.0);
    assert!(
        faces > 15.0 && faces > 0.5 * joints,
        "full film: joints {joints} levels, faces {faces}"
    );
}
