//! Scene analysis (issue 11): synthetic scenes with known sky, ground,
//! windows and ledges meet the targets; the close-up rule; determinism;
//! errors; the `grime scene` binary end to end.

mod common;

use common::{grime, s};

use std::path::Path;

use grime::analysis::eval::Metrics;
use grime::analysis::{self, LedgeKind, Options, synthetic};
use grime::photo::Photo;
use image::{DynamicImage, Rgb, RgbImage};

fn analyse(photo: &Photo) -> grime::Result<analysis::Analysis> {
    analysis::analyse(photo, &Options::default())
}

fn wall_share(a: &analysis::Analysis) -> f32 {
    a.matte.iter().filter(|&&v| v >= 128).count() as f32 / a.matte.len() as f32
}

#[test]
fn synthetic_scenes_meet_the_targets() {
    let mut m = Metrics::default();
    for seed in 0..6 {
        let s = synthetic::scene(seed, 480, 360);
        let a = analyse(&s.photo).unwrap();
        m.add(Some(&a), &s.truth);
    }
    let r = m.report();
    assert!(m.mean_iou() >= 0.8, "{r}");
    assert!(m.spill() <= 0.05, "{r}");
    assert!(m.sky_spill() <= 0.02, "{r}");
    assert!(m.recall() >= 0.8, "{r}");
    assert!(m.precision() >= 0.7, "{r}");
    assert_eq!(m.scale_ok, m.scale_n, "{r}");
    // Most of each window's panes are glass (0.68 measured), little else is.
    assert!(m.glass_recall() >= 0.6, "{r}");
    assert!(m.glass_precision() >= 0.9, "{r}");
}

#[test]
fn metrics_tell_a_bad_analysis_from_a_good_one() {
    // Nothing called wall: IoU 0, no spill, nothing found.
    let s = synthetic::scene(1, 240, 180);
    let mut m = Metrics::default();
    m.add(None, &s.truth);
    assert_eq!(m.mean_iou(), 0.0);
    assert_eq!(m.spill(), 0.0);
    assert_eq!(m.recall(), 0.0);
}

#[test]
fn a_close_up_is_all_wall() {
    let brick = grime::demo::load("brick").unwrap();
    let a = analyse(&brick.photo).unwrap();
    assert!(wall_share(&a) >= 0.98, "brick: {}", wall_share(&a));
    assert!(
        a.ledges
            .iter()
            .all(|l| l.polyline[1][0] - l.polyline[0][0] >= 0.25 * 512.0),
        "a texture has no short ledges: {:?}",
        a.ledges
    );
}

#[test]
fn the_demo_facade_wall_and_ledges_are_found() {
    let (w, h) = (480, 360);
    let d = grime::demo::facade(w, h);
    let l = grime::demo::layout(w, h);
    let a = analyse(&d.photo).unwrap();
    let region = d.region.unwrap();
    let (mut inter, mut union) = (0, 0);
    for (p, t) in a.matte.iter().zip(region.iter()) {
        inter += (*p >= 128 && *t >= 128) as u32;
        union += (*p >= 128 || *t >= 128) as u32;
    }
    // The demo region leaves whole windows out; the analysis keeps their
    // frames as wall (issue 11), so the IoU cannot reach 1.
    assert!(inter as f32 / union as f32 >= 0.8, "IoU {inter}/{union}");
    let near = |y: f32, x0: u32, x1: u32| {
        a.ledges.iter().any(|e| {
            (e.polyline[0][1] - y).abs() <= 4.0
                && e.polyline[0][0] < x1 as f32
                && e.polyline[1][0] > x0 as f32
        })
    };
    for s in &l.sills {
        assert!(
            near(s.3 as f32 + 1.0, s.0, s.2),
            "sill {s:?}: {:?}",
            a.ledges
        );
    }
    assert!(
        near(l.cornice.1 as f32 + 1.0, 0, w),
        "cornice: {:?}",
        a.ledges
    );
    // Under the cornice the wall is sheltered; mid-wall far from ledges it is not.
    let yc = l.cornice.1 as f32 + 4.0;
    assert!(a.shelter_at(w as f32 / 2.0, yc) > 0.5);
    let lines = a.source_lines();
    assert_eq!(lines.len(), a.ledges.len());
    assert!(
        lines
            .iter()
            .all(|p| p.len() >= 2 && p.iter().flatten().all(|v| v.is_finite()))
    );
    let mut preset = grime::preset::Preset::default();
    preset.rain.source_lines = lines;
    preset.validate().unwrap();
}

#[test]
fn slanted_ledges_are_followed() {
    // A lit band over a shadow, sloping 6 px over 200 px, on plain wall.
    let img = RgbImage::from_fn(240, 160, |x, y| {
        let edge = 80.0 + 0.03 * x as f32;
        let v = if (y as f32) < edge && (y as f32) > edge - 6.0 {
            235
        } else if (y as f32) >= edge && (y as f32) < edge + 4.0 {
            90
        } else {
            180
        };
        Rgb([v, (v as f32 * 0.95) as u8, (v as f32 * 0.85) as u8])
    });
    let a = analyse(&Photo::new(DynamicImage::ImageRgb8(img))).unwrap();
    let e = a
        .ledges
        .iter()
        .find(|e| e.polyline[1][0] - e.polyline[0][0] > 150.0)
        .expect("the ledge");
    let slope = (e.polyline[1][1] - e.polyline[0][1]) / (e.polyline[1][0] - e.polyline[0][0]);
    assert!((slope - 0.03).abs() < 0.01, "{e:?}");
    assert_ne!(e.kind, LedgeKind::RoofLine);
}

#[test]
fn determinism_at_one_and_two_threads() {
    let s = synthetic::scene(4, 640, 480);
    let run = |n: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
            .install(|| analyse(&s.photo).unwrap())
    };
    let (a, b) = (run(1), run(2));
    assert_eq!(a.matte, b.matte);
    assert_eq!(a.classes, b.classes);
    assert_eq!(a.ledges, b.ledges);
    assert_eq!(a.shelter, b.shelter);
    assert_eq!(a.scale, b.scale);
}

#[test]
fn no_wall_is_a_clear_error() {
    let sky = RgbImage::from_pixel(200, 100, Rgb([120, 170, 235]));
    let err = analysis::analyse(
        &Photo::new(DynamicImage::ImageRgb8(sky)),
        &Options {
            name: "sky.png".into(),
            ..Options::default()
        },
    )
    .unwrap_err();
    let msg = err.to_string();
    assert!(
        msg.contains("no wall found in sky.png") && msg.contains("--region full"),
        "{msg}"
    );
}

#[test]
fn user_wall_width_sets_the_scale() {
    let d = grime::demo::facade(400, 300);
    let a = analysis::analyse(
        &d.photo,
        &Options {
            wall_width_m: Some(8.0),
            ..Options::default()
        },
    )
    .unwrap();
    assert_eq!(a.scale.source, analysis::ScaleSource::UserWidth);
    assert!((a.scale.metres_per_pixel - 8.0 / 400.0).abs() < 1e-4);
    assert_eq!(analysis::parse_metres("14m").unwrap(), 14.0);
    assert_eq!(analysis::parse_metres("1400cm").unwrap(), 14.0);
    assert!(analysis::parse_metres("-3m").is_err());
}

#[test]
fn scene_subcommand_writes_json_mask_and_overlay() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("street.png");
    synthetic::scene(2, 320, 240)
        .photo
        .image()
        .save(&input)
        .unwrap();
    let (json, mask, seen) = (
        dir.path().join("scene.json"),
        dir.path().join("wall.png"),
        dir.path().join("seen.png"),
    );
    let o = grime(&[
        "scene",
        s(&input),
        "-o",
        s(&json),
        "--mask-out",
        s(&mask),
        "--overlay",
        s(&seen),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(v["width"], 320);
    assert!(v["wall_fraction"].as_f64().unwrap() > 0.3);
    assert!(v["scale"]["metres_per_pixel"].as_f64().unwrap() > 0.0);
    assert!(
        v["ledges"]
            .as_array()
            .unwrap()
            .iter()
            .any(|l| l["kind"] == "sill")
    );
    let m = image::open(&mask).unwrap();
    assert_eq!((m.width(), m.height()), (320, 240));
    let ov = image::open(&seen).unwrap().to_rgb8();
    let orig = image::open(&input).unwrap().to_rgb8();
    assert_eq!(ov.dimensions(), orig.dimensions());
    assert_ne!(ov, orig, "the overlay draws on the photo");
}

#[test]
fn scene_subcommand_errors_are_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("sky.png");
    RgbImage::from_pixel(64, 48, Rgb([120, 170, 235]))
        .save(&input)
        .unwrap();
    let before = std::fs::read(&input).unwrap();
    for (args, needle) in [
        (
            vec!["scene", s(&input), "--overlay", s(&input)],
            "refusing to overwrite",
        ),
        (vec!["scene", s(&input)], "no wall found"),
        (
            vec!["scene", s(&input), "--wall-width", "wide"],
            "wall width",
        ),
    ] {
        let o = grime(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            !o.status.success() && err.trim_end().lines().count() == 1,
            "{err}"
        );
        assert!(err.contains(needle), "{needle}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    assert_eq!(std::fs::read(&input).unwrap(), before);
    let help = grime(&["scene", "--help"]);
    let text = String::from_utf8_lossy(&help.stdout);
    assert!(text.contains("--mask-out") && text.contains("--overlay") && text.contains("ledges"));
}

/// A synthetic street photo saved as PNG, and which of its pixels are sky.
fn street(dir: &Path) -> (std::path::PathBuf, Vec<bool>) {
    let scene = synthetic::scene(3, 320, 240);
    let path = dir.join("street.png");
    scene.photo.image().to_rgb8().save(&path).unwrap();
    let labels = scene.truth.labels.expect("synthetic scenes are labelled");
    (
        path,
        labels
            .iter()
            .map(|&l| l == grime::analysis::eval::SKY)
            .collect(),
    )
}

fn sky_changed(input: &Path, output: &Path, sky: &[bool]) -> usize {
    let a = image::open(input).unwrap().to_rgb8();
    let b = image::open(output).unwrap().to_rgb8();
    a.pixels()
        .zip(b.pixels())
        .zip(sky)
        .filter(|((p, q), s)| **s && p != q)
        .count()
}

#[test]
fn run_leaves_the_sky_alone_unless_told_every_pixel_is_wall() {
    let dir = tempfile::tempdir().unwrap();
    let (input, sky) = street(dir.path());
    assert!(
        sky.iter().filter(|s| **s).count() > 1000,
        "the scene has sky"
    );
    let auto = dir.path().join("auto.png");
    let full = dir.path().join("full.png");
    let fast = ["--layers", "3", "--set", "sim.max_side=160", "-q"];
    for (out, extra) in [(&auto, vec![]), (&full, vec!["--region", "full"])] {
        let mut args = vec!["run", s(&input), "-o", s(out)];
        args.extend_from_slice(&fast);
        args.extend(extra);
        let o = grime(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let (in_auto, in_full) = (
        sky_changed(&input, &auto, &sky),
        sky_changed(&input, &full, &sky),
    );
    // 320 of the 5120 sky pixels (0 found automatically); over 500 until
    // the thirty-third pass, when the roof line under this scene's sky
    // began to shed into the coping a few rows below it and its stain no
    // longer reached up into the sky.
    assert!(
        in_full > 200,
        "every pixel is wall: the sky ages too ({in_full})"
    );
    assert!(
        (in_auto as f32) < 0.05 * sky.iter().filter(|s| **s).count() as f32,
        "found automatically, the sky stays as it was ({in_auto} sky pixels changed)"
    );
}

#[test]
fn run_and_batch_say_when_there_is_no_wall() {
    let dir = tempfile::tempdir().unwrap();
    let photos = dir.path().join("in");
    std::fs::create_dir(&photos).unwrap();
    let sky = photos.join("sky.png");
    RgbImage::from_pixel(200, 100, Rgb([120, 170, 235]))
        .save(&sky)
        .unwrap();
    let (street_png, _) = street(&photos);
    let out = dir.path().join("out.png");
    let o = grime(&["run", s(&sky), "-o", s(&out), "-q"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(
        err.contains("no wall found") && err.contains("--region full"),
        "{err}"
    );
    // In a batch the sky is reported and the street is aged.
    let aged = dir.path().join("aged");
    let o = grime(&[
        "batch",
        s(&photos),
        "-o",
        s(&aged),
        "-q",
        "--layers",
        "2",
        "--set",
        "sim.max_side=128",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(err.contains("1 succeeded, 1 failed"), "{err}");
    assert!(aged.join(street_png.file_name().unwrap()).is_file());
}

#[test]
fn scene_refuses_two_outputs_on_one_file_and_a_missing_folder_up_front() {
    let dir = tempfile::tempdir().unwrap();
    let (input, _) = street(dir.path());
    let same = dir.path().join("x.png");
    let o = grime(&[
        "scene",
        s(&input),
        "--mask-out",
        s(&same),
        "--overlay",
        s(&same),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(
        err.contains("--mask-out") && err.contains("--overlay"),
        "{err}"
    );
    assert!(!same.exists(), "nothing written");
    let o = grime(&[
        "scene",
        s(&input),
        "-o",
        s(&dir.path().join("no/scene.json")),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("output folder does not exist"), "{err}");
}

/// The share of coarse asphalt called wall in a 240 x 200 street: an
/// orange storey over a grey plinth of the road's colour and a dark foot
/// at 55% of the height; below it, the left 100 columns a grey road
/// marked with white lines `slope` off level (0.577: 30 degrees, in
/// perspective), the rest coarse grain (blocks of 3 x 3 pixels of the two
/// `levels` at random: it runs every way, as wet asphalt seen close).
fn coarse_street(slope: f32, levels: [u8; 2]) -> f32 {
    let (w, h) = (240usize, 200usize);
    let img = RgbImage::from_fn(w as u32, h as u32, |x, y| {
        let (x, y) = (x as usize, y as usize);
        let mut hash = ((x / 3) * 1000 + y / 3) as u64;
        hash = hash.wrapping_mul(0x9E37_79B9_7F4A_7C15);
        hash ^= hash >> 29;
        Rgb(match y {
            0..60 => [204, 128, 76],
            60..106 => [100; 3],
            106..112 => [30; 3],
            _ if x >= 100 && hash % 5 < 2 => [levels[0]; 3],
            _ if x >= 100 => [levels[1]; 3],
            _ if (x as f32 * slope + y as f32) % 24.0 < 3.0 => [230; 3],
            _ => [100; 3],
        })
    });
    let a = analyse(&Photo::new(DynamicImage::ImageRgb8(img))).unwrap();
    let wall = |x0: usize, y0: usize, y1: usize| {
        let n = (y0..y1)
            .flat_map(|y| (x0..w).map(move |x| y * w + x))
            .filter(|&i| a.classes[i] == analysis::Class::Wall)
            .count();
        n as f32 / ((w - x0) * (y1 - y0)) as f32
    };
    assert!(wall(0, 0, 56) > 0.95, "the storey is wall");
    wall(110, 125, 190)
}

#[test]
fn a_street_mostly_of_coarse_asphalt_is_ground() {
    // The marked road is 0.37 of the bottom fifth, short of a street; with
    // the grain of its colour it is one.
    let asphalt = coarse_street(0.577, [94, 108]);
    assert!(asphalt < 0.5, "{asphalt} of the coarse asphalt is wall");
}
