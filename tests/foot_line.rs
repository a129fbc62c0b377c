//! The wall's foot seen in the photo (`analysis::foot_line`): found along
//! a street's wall, cut where a car or a walker stands in front of it,
//! absent from a close-up of a wall. What the effects place by it
//! (`Site::ground_at`: the splash zone's soiling, moss, climate) follows.

use grime::analysis::synthetic::{self, Kerb};
use grime::analysis::{self, Options};
use grime::photo::Photo;
use grime::pipeline::Site;
use image::{DynamicImage, Rgb, RgbImage};

const W: u32 = 480;
const H: u32 = 360;
/// The wall's foot, row.
const FOOT: u32 = 250;

/// A plaster wall with pilasters and jambs (vertical edges) over a road
/// seen from eye level (paving joints across the view), the sky above;
/// `front(x, y)` drawn over it where it is `Some`.
fn street(front: impl Fn(u32, u32) -> Option<[u8; 3]>) -> Site {
    let img = RgbImage::from_fn(W, H, |x, y| {
        let g = ((x.wrapping_mul(73_856_093) ^ y.wrapping_mul(19_349_663)) % 13) as u8;
        if let Some(c) = front(x, y) {
            return Rgb(c.map(|v| v.saturating_add(g / 2)));
        }
        street_pixel(x, y, g)
    });
    site_of(img)
}

/// The street's pixel at (x, y) with grain `g`: sky, the wall, the road.
fn street_pixel(x: u32, y: u32, g: u8) -> Rgb<u8> {
    {
        if y < 40 {
            return Rgb([120, 170, 235]);
        }
        if y >= FOOT {
            // Joints across the view, closer together further off.
            let d = (y - FOOT) as f32;
            let joint = (d.sqrt() * 3.0).fract() < 0.15;
            let v = if joint { 80 } else { 104 } + g;
            return Rgb([v, v, v + 3]);
        }
        let pilaster = x % 60 < 6;
        let jamb = x.is_multiple_of(10);
        let l = if pilaster {
            180
        } else if jamb {
            150
        } else {
            205
        } + g;
        Rgb([l, (l as f32 * 0.7) as u8, (l as f32 * 0.55) as u8])
    }
}

fn site_of(img: RgbImage) -> Site {
    let photo = Photo::new(DynamicImage::ImageRgb8(img));
    let a = analysis::analyse(&photo, &Options::default()).unwrap();
    Site::seen(&a)
}

/// Columns in `xs` whose foot is within 2% of the height of `row`.
fn on_row(site: &Site, xs: std::ops::Range<u32>, row: f32) -> usize {
    xs.filter(|&x| {
        site.ground_at(x)
            .is_some_and(|g| (g - row).abs() <= 0.02 * H as f32)
    })
    .count()
}

/// Columns in `xs` with any foot.
fn claimed(site: &Site, xs: std::ops::Range<u32>) -> usize {
    xs.filter(|&x| site.ground_at(x).is_some()).count()
}

#[test]
fn the_foot_of_a_street_wall_is_found_on_its_line() {
    let site = street(|_, _| None);
    let on = on_row(&site, 0..W, FOOT as f32);
    assert!(
        on as f32 > 0.8 * W as f32,
        "{on} of {W} columns on the foot"
    );
    assert_eq!(
        claimed(&site, 0..W),
        on,
        "a foot claimed off the wall's foot"
    );
}

/// Per column of a `W` x `H` kerbside scene: its foot's rows and the
/// labelled foot.
fn kerbside(kerb: Kerb) -> (Vec<f32>, Vec<Option<f32>>, analysis::Analysis) {
    let sc = synthetic::kerbside(kerb, W, H);
    let a = analysis::analyse(&sc.photo, &Options::default()).unwrap();
    let truth = analysis::eval::true_foot(sc.truth.labels.as_ref().unwrap(), W as usize);
    (a.foot_rows(W, H), truth, a)
}

#[test]
fn the_foot_of_a_synthetic_street_scene_is_found_and_nothing_else() {
    // The left third is shaded boards the ground's fill climbs.
    let (rows, truth, a) = kerbside(Kerb::ShadedBoards);
    let (mut claimed, mut right, mut found) = (0, 0, 0);
    for (t, y) in truth.iter().zip(&rows) {
        let near = t.is_some_and(|t| (t - y).abs() <= 0.015 * H as f32);
        claimed += y.is_finite() as usize;
        right += (y.is_finite() && near) as usize;
        found += near as usize;
    }
    // Under the boards (upright joints) and under the plain plaster
    // beyond, where the colour step alone decides.
    assert!(found * 3 > W as usize, "{found} of {W} columns found");
    assert_eq!(right, claimed, "claimed off the true foot");
    // The polylines are straight, left to right.
    assert!(a.foot.iter().all(|l| l.len() == 2 && l[0][0] < l[1][0]));
}

/// A car body standing on the road over the foot, its wheels below it.
fn car(x: u32, y: u32) -> Option<[u8; 3]> {
    ((170..330).contains(&x) && (200..275).contains(&y)).then_some(match y {
        200..225 => [50, 55, 60],
        225..228 => [200, 200, 205],
        262.. => [25, 25, 25],
        _ => [150, 40, 40],
    })
}

#[test]
fn a_car_in_front_cuts_the_foot() {
    let site = street(car);
    assert_eq!(claimed(&site, 172..328), 0, "a foot claimed on the car");
    let beside = on_row(&site, 0..150, FOOT as f32) + on_row(&site, 350..W, FOOT as f32);
    assert!(beside > 200, "{beside} columns found beside the car");
}

#[test]
fn a_walker_in_front_cuts_the_foot() {
    // Dark legs and a coat from row 160 down to the feet on row 262.
    let walker = |x: u32, y: u32| {
        let legs = ((230..238).contains(&x) || (242..250).contains(&x)) && (215..262).contains(&y);
        let coat = (226..254).contains(&x) && (160..215).contains(&y);
        (legs || coat).then_some([40, 35, 45])
    };
    let site = street(walker);
    // Under the coat, between and beside the legs, the wall's foot is seen.
    let at_legs = claimed(&site, 230..238) + claimed(&site, 242..250);
    assert_eq!(at_legs, 0, "a foot claimed at the walker's feet");
    assert!(on_row(&site, 0..200, FOOT as f32) > 150);
}

#[test]
fn a_close_up_of_a_wall_has_no_foot() {
    // Brick courses and perpend joints over the whole frame, the lowest
    // course in shade (smooth and grey, like a pavement).
    let img = RgbImage::from_fn(W, H, |x, y| {
        let course = y / 24;
        let offset = if course % 2 == 0 { 0 } else { 25 };
        let joint = y % 24 < 3 || (x + offset) % 50 < 3;
        let g = ((x.wrapping_mul(73_856_093) ^ y.wrapping_mul(19_349_663)) % 17) as u8;
        Rgb(if y >= 320 {
            [100 + g / 3, 100 + g / 3, 104 + g / 3]
        } else if joint {
            [190, 185, 175]
        } else {
            [150 + g, 70 + g / 2, 50 + g / 2]
        })
    });
    let site = site_of(img);
    assert_eq!(claimed(&site, 0..W), 0, "a foot on a close-up");
}

/// Rows of the grey plinth at the street wall's foot, which the ground's
/// fill climbs (as grey and smooth as the road, no colour step between).
const PLINTH: u32 = 14;

/// [`street`] with a grey plinth, grooved upright every 8 columns, along
/// the wall's foot; `front(x, y)` drawn over it where it is `Some`.
fn plinth_street(front: impl Fn(u32, u32) -> Option<[u8; 3]>) -> (Site, analysis::Analysis) {
    let img = RgbImage::from_fn(W, H, |x, y| {
        let g = ((x.wrapping_mul(73_856_093) ^ y.wrapping_mul(19_349_663)) % 13) as u8;
        if let Some(c) = front(x, y) {
            return Rgb(c.map(|v| v.saturating_add(g / 2)));
        }
        if (FOOT - PLINTH..FOOT).contains(&y) {
            let v = if x.is_multiple_of(8) { 88 } else { 108 } + g;
            return Rgb([v, v, v + 3]);
        }
        street_pixel(x, y, g)
    });
    let photo = Photo::new(DynamicImage::ImageRgb8(img));
    let a = analysis::analyse(&photo, &Options::default()).unwrap();
    (Site::seen(&a), a)
}

#[test]
fn the_foot_is_found_where_the_ground_fill_climbs_the_wall() {
    let (site, a) = plinth_street(|_, _| None);
    // The class map's lowest wall row is on the plinth's top.
    let class_rows = a.class_foot_rows(W, H);
    let climbed = class_rows
        .iter()
        .filter(|&&y| y <= (FOOT - PLINTH / 2) as f32)
        .count();
    assert!(climbed as u32 > W / 2, "the fill climbed {climbed} columns");
    let on = on_row(&site, 0..W, FOOT as f32);
    assert!(on as u32 > W / 2, "{on} of {W} columns on the foot");
    assert_eq!(
        claimed(&site, 0..W),
        on,
        "a foot claimed off the wall's foot"
    );
}

#[test]
fn a_car_in_front_cuts_the_foot_the_fill_climbed() {
    let (site, _) = plinth_street(car);
    assert_eq!(claimed(&site, 172..328), 0, "a foot claimed on the car");
    let beside = on_row(&site, 0..150, FOOT as f32) + on_row(&site, 350..W, FOOT as f32);
    assert!(beside > 150, "{beside} columns found beside the car");
}

/// The demo facade (`grime run --demo`, the GUI's sample: plain plaster
/// over a pavement, no upright texture) keeps its seen foot: most of its
/// width on the pavement's top row. Moss's splash zone and the climate's
/// wet foot follow it (`tests/gui.rs`'s seen site has ground).
#[test]
fn the_demo_facades_plain_wall_keeps_its_foot() {
    let demo = grime::demo::load("facade").unwrap();
    let (w, h) = (demo.photo.width(), demo.photo.height());
    let foot = grime::demo::layout(w, h).ground as f32;
    let a = analysis::analyse(&demo.photo, &Options::default()).unwrap();
    let rows = a.foot_rows(w, h);
    let on = rows
        .iter()
        .filter(|&&y| y.is_finite() && (y - foot).abs() <= 4.0)
        .count();
    let off = rows
        .iter()
        .filter(|&&y| y.is_finite() && (y - foot).abs() > 4.0)
        .count();
    assert!(
        on as f32 > 0.7 * w as f32,
        "{on} of {w} columns on the foot"
    );
    assert!(off * 20 < w as usize, "{off} columns off the foot");
}
