//! Window glass found from the window's frame (issue 11; the blind
//! critics' grime on window glass): panes no darker than the wall, in a
//! frame under a head and over a sill, are glass; the frame and the sill
//! stay wall.

use grime::analysis::{self, Class, Options};
use grime::photo::Photo;
use image::{DynamicImage, Rgb, RgbImage};

/// Left edges of the windows' frames (60 px wide) and the tops of the
/// panes of each storey (100 px tall).
const COLUMNS: [u32; 3] = [120, 290, 460];
const STOREYS: [u32; 2] = [130, 290];
const FRAME: u32 = 4;

/// What lies at (x, y) of the facade: sky over a brick-red wall with
/// two storeys of three windows, each a white frame round two light,
/// bluish panes (lighter than the wall) split by a meeting rail, under a
/// projecting head (lit stone over its shadow) and over a lit sill with
/// its shadow.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Part {
    Sky,
    Wall,
    Stone,
    Shadow,
    Frame,
    Pane,
}

fn part(x: u32, y: u32) -> Part {
    if y < 70 {
        return Part::Sky;
    }
    for &x0 in &COLUMNS {
        for &y0 in &STOREYS {
            let (x1, y1) = (x0 + 60, y0 + 100);
            let wide = (x0 - 6..x1 + 6).contains(&x);
            if wide && ((y0 - 14..y0 - 8).contains(&y) || (y1..y1 + 6).contains(&y)) {
                return Part::Stone;
            }
            if wide && ((y0 - 8..y0 - 5).contains(&y) || (y1 + 6..y1 + 9).contains(&y)) {
                return Part::Shadow;
            }
            if (x0..x1).contains(&x) && (y0 - 5..y1).contains(&y) {
                let inner = (x0 + FRAME..x1 - FRAME).contains(&x)
                    && (y0 - 5 + FRAME..y1 - FRAME).contains(&y)
                    && !(y0 + 48..y0 + 52).contains(&y);
                return if inner { Part::Pane } else { Part::Frame };
            }
        }
    }
    Part::Wall
}

fn facade() -> Photo {
    let img = RgbImage::from_fn(640, 480, |x, y| {
        // A faint brick course pattern on the wall.
        let course = if y % 8 == 0 { 0.93 } else { 1.0 };
        let c = match part(x, y) {
            Part::Sky => [0.55, 0.72, 0.95],
            Part::Wall => [0.62 * course, 0.36 * course, 0.30 * course],
            Part::Stone => [0.88, 0.86, 0.82],
            Part::Shadow => [0.22, 0.17, 0.15],
            Part::Frame => [0.92, 0.92, 0.90],
            Part::Pane => [0.64, 0.70, 0.78],
        };
        Rgb(c.map(|v| (v * 255.0) as u8))
    });
    Photo::new(DynamicImage::ImageRgb8(img))
}

/// The share of the pixels of `which` (within the wall's rows) whose class
/// is `class`.
fn share(a: &analysis::Analysis, which: Part, class: Class) -> f32 {
    let (mut n, mut k) = (0, 0);
    for y in 70..480 {
        for x in 0..640 {
            if part(x, y) == which {
                n += 1;
                k += (a.class_at(x, y) == class) as usize;
            }
        }
    }
    k as f32 / n.max(1) as f32
}

#[test]
fn light_panes_are_glass_and_their_frame_and_sill_stay_wall() {
    let a = analysis::analyse(&facade(), &Options::default()).unwrap();
    let panes = share(&a, Part::Pane, Class::Glass);
    assert!(panes > 0.6, "panes called glass: {panes}");
    for (which, least) in [(Part::Frame, 0.6), (Part::Stone, 0.8), (Part::Wall, 0.95)] {
        let wall = share(&a, which, Class::Wall);
        assert!(wall > least, "{which:?} called wall: {wall}");
    }
}

#[test]
fn the_panes_leave_the_walls_matte_and_the_sills_do_not() {
    // No grime is drawn over the panes; the sill under each, at its
    // middle, stays in the matte (its rain streaks start there).
    let a = analysis::analyse(&facade(), &Options::default()).unwrap();
    for &x0 in &COLUMNS {
        for &y0 in &STOREYS {
            let pane = a.matte.get_pixel(x0 + 30, y0 + 25)[0];
            let sill = a.matte.get_pixel(x0 + 30, y0 + 103)[0];
            assert!(
                pane < 128,
                "matte {pane} over the pane at ({}, {})",
                x0 + 30,
                y0 + 25
            );
            assert!(
                sill >= 128,
                "matte {sill} over the sill at ({}, {})",
                x0 + 30,
                y0 + 103
            );
        }
    }
}
