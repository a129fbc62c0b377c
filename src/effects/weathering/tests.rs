use image::{Rgb, RgbImage};

use super::*;
use crate::effects::testing;
use crate::photo::Photo;
use crate::pipeline::Site;
use crate::preset::ClimateParams;
use crate::stack::Stack;

/// A red wall whose left half faces the sun (normals tilted toward it)
/// and whose right half faces away.
fn half_lit() -> (Photo, RgbImage) {
    let photo = Photo::new(image::DynamicImage::ImageRgb8(RgbImage::from_pixel(
        160,
        120,
        Rgb([200, 70, 50]),
    )));
    // Tangent space, 127.5 = 0: left tilts right (toward a sun at +60°),
    // right tilts left.
    let normals = RgbImage::from_fn(160, 120, |x, _| {
        if x < 80 {
            Rgb([230, 128, 200])
        } else {
            Rgb([25, 128, 200])
        }
    });
    (photo, normals)
}

fn saturation([r, g, b]: [u8; 3]) -> f32 {
    let (mx, mn) = (r.max(g).max(b) as f32, r.min(g).min(b) as f32);
    if mx == 0.0 { 0.0 } else { (mx - mn) / mx }
}

#[test]
fn desaturaty_fades_most_where_the_light_is_strongest() {
    let (photo, normals) = half_lit();
    let site = Site::assumed(160);
    let mut preset = Preset::default();
    preset.desaturate.enabled = true;
    preset.climate.sun_azimuth = 60.0;
    preset.climate.sun_elevation = 10.0;
    testing::with(&photo, None, &site, Some(&normals), 0, |ctx| {
        let light = climate::light(ctx, &preset.climate);
        assert!(
            light.get(40, 60) > light.get(120, 60) + 0.2,
            "{} {}",
            light.get(40, 60),
            light.get(120, 60)
        );
        let made = stage(ctx, &mut Products::default(), &preset, &Progress::none()).unwrap();
        let stack = Stack {
            base: std::sync::Arc::new(photo.clone()),
            layers: made.layers,
            region: None,
        };
        let out = stack.composite().to_rgb8();
        let drop = |x| saturation([200, 70, 50]) - saturation(out.get_pixel(x, 60).0);
        assert!(
            drop(40) > drop(120) + 0.1,
            "sunny {} shaded {}",
            drop(40),
            drop(120)
        );
        assert!(drop(120) >= 0.0);
    });
}

#[test]
fn spotty_spots_grow_in_place() {
    testing::facade(200, 150, |ctx| {
        let p = GeneratorParams {
            enabled: true,
            ..GeneratorParams::spotty()
        };
        let c = climate::maps(ctx, &ClimateParams::default());
        let m = musgrave(ctx, &p, 4);
        let e = environment(&c, &p);
        let spots: Vec<RowMajor<f32>> =
            [0.3, 0.6, 1.2].iter().map(|&t| spotty(&m, &e, t)).collect();
        let area = |s: &RowMajor<f32>| s.data().iter().filter(|&&v| v > 0.0).count();
        for pair in spots.windows(2) {
            // Every spot of the earlier time is still there, at least as strong.
            assert!(
                pair[0]
                    .data()
                    .iter()
                    .zip(pair[1].data())
                    .all(|(a, b)| b >= a)
            );
            assert!(
                area(&pair[1]) > area(&pair[0]),
                "{} {}",
                area(&pair[0]),
                area(&pair[1])
            );
        }
        assert!(area(&spots[0]) > 0);
    });
}

#[test]
fn humidity_is_higher_near_the_ground_and_light_dries_it() {
    testing::facade(200, 150, |ctx| {
        let p = ClimateParams::default();
        let c = climate::maps(ctx, &p);
        let row_mean = |m: &RowMajor<f32>, y: usize| {
            (0..m.width()).map(|x| m.get(x, y)).sum::<f32>() / m.width() as f32
        };
        let (gh, top) = (c.humidity.height(), 40);
        assert!(row_mean(&c.humidity, gh - 3) > row_mean(&c.humidity, top) + 0.1);
        let dry = climate::maps(ctx, &ClimateParams { c2: 1.5, ..p });
        assert!(row_mean(&dry.humidity, gh - 3) < row_mean(&c.humidity, gh - 3));
    });
}
