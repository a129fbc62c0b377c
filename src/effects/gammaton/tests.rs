use super::particle::{deteriorate, exchange};
use super::*;
use crate::preset::{GammaSource, Rule, RuleKind, Stop, Substance};

fn wall(w: usize, h: usize) -> (RowMajor<f32>, RowMajor<bool>) {
    // A rough wall: luminance varies, so flow wanders.
    let luma = RowMajor::from_fn(w, h, |x, y| ((x * 7 + y * 13) % 50) as f32 + 100.0);
    (luma, RowMajor::filled(w, h, true))
}

fn substance(name: &str, absorb: f32, deposit: f32, initial: f32) -> Substance {
    Substance {
        name: name.into(),
        filter: 0,
        absorb,
        deposit,
        initial,
        scale: 1.0,
        stops: vec![
            Stop::new(0.0, [0; 3], 0.0),
            Stop::new(1.0, [200, 80, 20], 1.0),
        ],
    }
}

fn params(consistent: bool) -> GammatonParams {
    GammatonParams {
        enabled: true,
        particles: 3000,
        consistent,
        sources: vec![
            GammaSource {
                share: 2.0,
                ..GammaSource::new(SourceKind::Sky, vec![1.0, 0.0])
            },
            GammaSource::new(SourceKind::Ground, vec![0.5, 0.2]),
        ],
        substances: vec![
            substance("water", 0.3, 0.5, 0.0),
            substance("salt", 0.2, 1.0, 0.4),
        ],
        ..GammatonParams::default()
    }
}

fn run(p: &GammatonParams) -> Outcome {
    let (luma, region) = wall(200, 120);
    simulate(&luma, &region, &Scenery::default(), p, 9, &Progress::none()).unwrap()
}

/// initial + emitted = on the wall + lost, per substance (no rules).
fn assert_conserved(out: &Outcome) {
    for s in &out.stats.substances {
        let before = s.initial + s.emitted;
        let after = s.on_wall + s.lost;
        assert!(
            (before - after).abs() <= 1e-3 * before.max(1.0),
            "{}: {before} in, {after} accounted for",
            s.name
        );
    }
}

#[test]
fn transport_conserves_every_substance_in_both_modes() {
    for consistent in [false, true] {
        let out = run(&params(consistent));
        assert_conserved(&out);
        assert_eq!(out.stats.emitted, 3000);
        assert!(
            out.stats.contacts > 3000,
            "every γ-ton touched the wall at least once"
        );
        let salt = &out.stats.substances[1];
        assert!(salt.on_wall > 0.0 && salt.lost > 0.0, "{salt:?}");
    }
}

#[test]
fn deterioration_follows_eq_3_21() {
    // The thesis's example of eq. 3.20's unsoundness, made sound by 3.21.
    let [ps, pp, pf] = deteriorate([0.0, 0.8, 0.2], [1.0, 0.1, 0.1]);
    assert_eq!(ps, 0.0);
    assert!((pp - 0.7).abs() < 1e-6);
    assert!(
        (pf - 0.3).abs() < 1e-6,
        "capped at 1 - p_s' - p_p', got {pf}"
    );
    // Plain case: p_f' = p_f + p_p' - Δ_f.
    let [ps, pp, pf] = deteriorate([0.3, 0.3, 0.2], [0.1, 0.1, 0.3]);
    assert!((ps - 0.2).abs() < 1e-6 && (pp - 0.2).abs() < 1e-6);
    assert!((pf - 0.1).abs() < 1e-6);
    // Probabilities only shrink to a settle: repeated hits end in zero.
    let mut p = [0.4, 0.3, 0.3];
    for _ in 0..50 {
        p = deteriorate(p, [0.1, 0.05, 0.05]);
    }
    assert_eq!(p, [0.0, 0.0, 0.0]);
}

#[test]
fn exchange_matches_the_transport_equations() {
    let cells = [0, 1];
    // Classic stop, eq. 3.23-3.24: absorb a c_j / n from each.
    let mut map = [2.0, 4.0];
    let (s, b) = exchange(1.0, &mut map, &cells, (0.5, 1.0), false, false);
    assert_eq!(map, [1.5, 3.0]);
    assert_eq!((s, b), (2.5, 0.0));
    // Classic settle, eq. 3.25: each gets k s / n; with k < 1 the rest is lost.
    let mut map = [0.0, 0.0];
    let (s, b) = exchange(2.0, &mut map, &cells, (0.5, 0.5), false, true);
    assert_eq!(map, [0.5, 0.5]);
    assert_eq!((s, b), (0.0, 1.0));
    // Consistent, d = k - a >= 0: the γ-ton gives d s in all.
    let mut map = [1.0, 1.0];
    let (s, _) = exchange(2.0, &mut map, &cells, (0.25, 0.75), true, false);
    assert_eq!(map, [1.5, 1.5]);
    assert_eq!(s, 1.0);
    // Consistent, d < 0: each cell gives -d c_j.
    let mut map = [1.0, 3.0];
    let (s, _) = exchange(0.0, &mut map, &cells, (0.75, 0.25), true, false);
    assert_eq!(map, [0.5, 1.5]);
    assert_eq!(s, 2.0);
    // Negative absorption gives at most what the γ-ton holds.
    let mut map = [4.0, 4.0];
    let (s, _) = exchange(1.0, &mut map, &cells, (-1.0, 1.0), false, false);
    assert_eq!(s, 0.0);
    assert_eq!(map, [4.5, 4.5]);
}

#[test]
fn rules_match_plain_references() {
    let mut p = params(true);
    p.rules = vec![
        Rule {
            kind: RuleKind::Transfer,
            from: "water".into(),
            to: "salt".into(),
            rate: 0.25,
            only_where: String::new(),
        },
        Rule {
            kind: RuleKind::Deteriorate,
            from: "water".into(),
            to: String::new(),
            rate: -0.5,
            only_where: "salt".into(),
        },
    ];
    let water = vec![4.0, 8.0, 0.0];
    let salt = vec![0.0, 1.0, 0.0];
    let mut maps = vec![water.clone(), salt.clone()];
    rules::apply(&mut maps, &p);
    // Transfer (eq. 3.28): water 3, 6, 0; salt 1, 3, 0. Then deteriorate
    // (eq. 3.29) where salt > 0: water 1.5, 3, 0.
    assert_eq!(maps[0], vec![1.5, 3.0, 0.0]);
    assert_eq!(maps[1], vec![1.0, 3.0, 0.0]);
}

#[test]
fn settle_only_gammatons_leave_everything_where_they_stop() {
    let mut p = params(false);
    (p.p_straight, p.p_parabolic, p.p_flow) = (0.0, 0.0, 0.0);
    p.radius = 0.0;
    p.sources.truncate(1);
    p.substances[1].initial = 0.0;
    p.substances[0].deposit = 1.0;
    let out = run(&p);
    assert_eq!(out.stats.left, 0);
    assert_eq!(out.stats.contacts, out.stats.emitted, "one contact each");
    let water = &out.stats.substances[0];
    assert!((water.on_wall - water.emitted).abs() < 1e-2, "{water:?}");
    assert!(water.lost.abs() < 1e-6);
    // Each γ-ton carried 1: every wetted pixel holds a whole number of them.
    assert!(
        out.maps[0]
            .data()
            .iter()
            .all(|&v| (v - v.round()).abs() < 1e-4)
    );
}

#[test]
fn same_result_at_one_two_and_three_threads() {
    // Sky and ground, and slanted rain under a ledge.
    let mut slanted = params(true);
    (slanted.sources[0].direction, slanted.sources[0].spread) = (25.0, 15.0);
    for (p, scenery) in [(params(true), Scenery::default()), (slanted, sill())] {
        let runs: Vec<Vec<Vec<f32>>> = [1, 2, 3]
            .into_iter()
            .map(|n| {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(n)
                    .build()
                    .unwrap();
                pool.install(|| {
                    run_on(&p, &scenery)
                        .maps
                        .into_iter()
                        .map(|m| m.data().to_vec())
                        .collect()
                })
            })
            .collect();
        assert_eq!(runs[0], runs[1]);
        assert_eq!(runs[0], runs[2]);
    }
}

/// A ledge's drip line at y = 40 from x = 60 to 140 on the 200 x 120 wall,
/// its shelter reaching 10 px per metre.
fn sill() -> Scenery {
    Scenery {
        overhangs: vec![sky::Overhang::new(vec![(60.0, 40.0), (140.0, 40.0)], 10.0)],
        ..Scenery::default()
    }
}

fn run_on(p: &GammatonParams, scenery: &Scenery) -> Outcome {
    let (luma, region) = wall(200, 120);
    simulate(&luma, &region, scenery, p, 9, &Progress::none()).unwrap()
}

/// Settle-only rain from the sky: each γ-ton leaves its 1 of water where
/// it first meets the wall.
fn rain(direction: f32, spread: f32, shelter: f32) -> GammatonParams {
    let mut p = params(false);
    (p.p_straight, p.p_parabolic, p.p_flow) = (0.0, 0.0, 0.0);
    p.radius = 0.0;
    p.particles = 60_000;
    p.substances[0].deposit = 1.0;
    p.substances[1].initial = 0.0;
    p.sources = vec![GammaSource {
        direction,
        spread,
        shelter,
        ..GammaSource::new(SourceKind::Sky, vec![1.0, 0.0])
    }];
    p
}

/// Water per pixel in columns `xs`, rows `ys`.
fn density(out: &Outcome, xs: std::ops::Range<usize>, ys: std::ops::Range<usize>) -> f32 {
    let n = (xs.len() * ys.len()) as f32;
    let water = &out.maps[0];
    xs.flat_map(|x| ys.clone().map(move |y| water.get(x, y)))
        .sum::<f32>()
        / n
}

#[test]
fn slanted_rain_leaves_the_lee_side_of_a_ledge_dry() {
    // 60000 drops on 24000 pixels: 2.5 a pixel in the open.
    for (direction, lee, windward) in [(45.0, 141..150, 60..69), (-45.0, 50..59, 131..140)] {
        let out = run_on(&rain(direction, 0.0, 3.0), &sill());
        assert_conserved(&out);
        assert_eq!(out.stats.left, 0);
        let (lee, windward) = (density(&out, lee, 50..60), density(&out, windward, 50..60));
        // Above the ledge nothing shelters the wall.
        let open = density(&out, 0..200, 0..38);
        assert!((open - 2.5).abs() < 0.25, "open wall: {open}");
        assert!(
            (windward - open).abs() < 0.4,
            "windward {windward}, open {open}"
        );
        assert!(
            lee < 0.6 * windward,
            "direction {direction}: lee {lee}, windward {windward}"
        );
        // What the ledge caught runs off its drip line.
        assert!(density(&out, 60..140, 40..41) > 5.0 * open);
    }
}

#[test]
fn a_spread_blurs_the_sides_of_a_ledges_shelter() {
    // Just beyond the ledge's right end: straight rain reaches it, rain
    // spread over +-60 degrees partly comes through the ledge.
    let beside = |spread| density(&run_on(&rain(0.0, spread, 3.0), &sill()), 141..147, 45..55);
    let (straight, spread) = (beside(0.0), beside(60.0));
    assert!((straight - 2.5).abs() < 0.5, "straight: {straight}");
    assert!(
        spread < 0.85 * straight,
        "spread {spread}, straight {straight}"
    );
    // Right under its middle, rain is sheltered either way.
    for spread in [0.0, 60.0] {
        let under = density(&run_on(&rain(0.0, spread, 3.0), &sill()), 95..105, 45..55);
        assert!(under < 0.5 * 2.5, "spread {spread}: {under}");
    }
}

#[test]
fn without_ledges_or_shelter_the_sky_falls_anywhere() {
    // Direction and spread act through the ledges only: without them (or
    // with no shelter) the first contacts are the old uniform ones.
    let plain = run_on(&rain(0.0, 0.0, 0.0), &Scenery::default()).maps;
    let slanted = run_on(&rain(30.0, 20.0, 3.0), &Scenery::default()).maps;
    let unsheltered = run_on(&rain(30.0, 20.0, 0.0), &sill()).maps;
    assert!(plain == slanted && plain == unsheltered);
}

#[test]
fn direction_spread_and_shelter_belong_to_the_sky() {
    let mut p = rain(30.0, 10.0, 1.0);
    assert!(p.validate().is_ok());
    p.sources[0].kind = SourceKind::Ground;
    let e = p.validate().unwrap_err().to_string();
    assert!(e.contains("gammaton.sources[0].direction"), "{e}");
    p.sources[0] = GammaSource::new(SourceKind::Ground, vec![1.0]);
    assert!(p.validate().is_ok());
    // Out of range, through the preset's PARAMS rows.
    let mut preset = Preset::default();
    preset.gammaton.sources[0].direction = 95.0;
    let e = preset.validate().unwrap_err().to_string();
    assert!(e.contains("gammaton.sources.direction"), "{e}");
}

#[test]
fn stops_interpolate_and_clamp() {
    let stops = [
        Stop::new(0.2, [0, 0, 0], 0.0),
        Stop::new(0.6, [200, 100, 0], 1.0),
    ];
    assert_eq!(rules::sample(&stops, 0.0), ([0.0; 3], 0.0));
    let (c, a) = rules::sample(&stops, 0.4);
    assert!((c[0] - 100.0).abs() < 1e-3 && (c[1] - 50.0).abs() < 1e-3 && (a - 0.5).abs() < 1e-6);
    assert_eq!(rules::sample(&stops, 1.0), ([200.0, 100.0, 0.0], 1.0));
}

#[test]
fn a_line_source_off_the_grid_does_not_panic() {
    // Points above and below the grid: the γ-tons start off it and leave.
    let mut p = params(true);
    p.p_flow = 0.9;
    p.p_straight = 0.0;
    p.p_parabolic = 0.0;
    p.sources = vec![GammaSource {
        points: vec![[20.0, -40.0], [180.0, -30.0], [150.0, 400.0]],
        ..GammaSource::new(SourceKind::Line, vec![1.0])
    }];
    let out = run(&p);
    assert_eq!(out.stats.emitted, 3000);
    assert_conserved(&out);
}

fn mask_source() -> GammaSource {
    GammaSource {
        mask: "painted.png".into(),
        ..GammaSource::new(SourceKind::Mask, vec![1.0, 0.0])
    }
}

#[test]
fn a_painted_mask_emits_only_where_it_is_white() {
    // Settle-only γ-tons: each leaves its water where it starts.
    let mut p = params(false);
    (p.p_straight, p.p_parabolic, p.p_flow) = (0.0, 0.0, 0.0);
    p.radius = 0.0;
    p.substances[0].deposit = 1.0;
    p.substances[1].initial = 0.0;
    p.sources = vec![mask_source()];
    let (luma, region) = wall(200, 120);
    // White square at x 50..60, y 30..40; grey (half as likely) at 100..110.
    let mask = RowMajor::from_fn(200, 120, |x, y| match (x, y) {
        (50..60, 30..40) => 1.0,
        (100..110, 30..40) => 0.5,
        _ => 0.0,
    });
    let scenery = Scenery {
        masks: vec![Some(mask)],
        ..Scenery::default()
    };
    let out = simulate(&luma, &region, &scenery, &p, 9, &Progress::none()).unwrap();
    let water = &out.maps[0];
    let sum = |x0: usize, x1: usize| -> f32 {
        (x0..x1)
            .flat_map(|x| (30..40).map(move |y| (x, y)))
            .map(|(x, y)| water.get(x, y))
            .sum()
    };
    let (white, grey) = (sum(50, 60), sum(100, 110));
    assert!(
        (white + grey - 3000.0).abs() < 0.5,
        "all water in the squares"
    );
    assert!(
        (grey / white - 0.5).abs() < 0.1,
        "grey emits half: {grey} vs {white}"
    );
}

#[test]
fn a_mask_source_needs_its_mask_the_photos_size() {
    use crate::grid::Grid;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("painted.png");
    let mut p = params(true);
    p.sources = vec![GammaSource {
        mask: path.to_string_lossy().into_owned(),
        ..mask_source()
    }];
    // The preset names a mask exactly for mask sources.
    assert!(p.validate().is_ok());
    p.sources[0].mask.clear();
    assert!(p.validate().is_err(), "a mask source without a mask");
    p.sources[0].kind = SourceKind::Sky;
    assert!(p.validate().is_ok());
    p.sources[0].mask = "painted.png".into();
    assert!(p.validate().is_err(), "a sky source with a mask");
    p.sources[0] = GammaSource {
        mask: path.to_string_lossy().into_owned(),
        ..mask_source()
    };
    let grid = Grid::new(40, 30, None, 0).unwrap();
    // Missing.
    let e = load_masks(&p, &grid, (40, 30)).unwrap_err().to_string();
    assert!(
        e.contains("gammaton.sources[0].mask") && e.contains("painted.png"),
        "{e}"
    );
    // Wrong size.
    image::GrayImage::from_pixel(20, 30, image::Luma([255]))
        .save(&path)
        .unwrap();
    let e = load_masks(&p, &grid, (40, 30)).unwrap_err().to_string();
    assert!(e.contains("20x30") && e.contains("40x30"), "{e}");
    // Right size, on a grid half the photo's size: white on the left half.
    image::GrayImage::from_fn(40, 30, |x, _| image::Luma([if x < 20 { 255 } else { 0 }]))
        .save(&path)
        .unwrap();
    let grid = Grid::new(40, 30, None, 20).unwrap();
    let masks = load_masks(&p, &grid, (40, 30)).unwrap();
    let m = masks[0].as_ref().unwrap();
    assert_eq!((m.width(), m.height()), (20, 15));
    assert_eq!((m.get(9, 7), m.get(10, 7)), (1.0, 0.0));
    // A mask source with nothing white on the wall is refused.
    let (luma, region) = wall(20, 15);
    let scenery = Scenery {
        masks: vec![Some(RowMajor::filled(20, 15, 0.0))],
        ..Scenery::default()
    };
    let e = simulate(&luma, &region, &scenery, &p, 1, &Progress::none());
    assert!(matches!(e, Err(Error::Preset(m)) if m.contains("paints no wall pixel")));
}

#[test]
fn a_cached_run_sees_a_repainted_mask() {
    use crate::pipeline::{Cache, Scene, run, run_cached};
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("painted.png");
    let paint = |left: bool| {
        image::GrayImage::from_fn(40, 30, |x, _| {
            image::Luma([255 * u8::from((x < 20) == left)])
        })
        .save(&path)
        .unwrap()
    };
    let photo = image::RgbImage::from_pixel(40, 30, image::Rgb([150, 140, 130]));
    let scene = Scene::new(crate::photo::Photo::new(photo.into()), None).unwrap();
    let mut preset = Preset::default();
    preset.gammaton.enabled = true;
    preset.gammaton.particles = 2000;
    preset.gammaton.sources = vec![GammaSource {
        mask: path.to_string_lossy().into_owned(),
        ..GammaSource::new(SourceKind::Mask, vec![1.0])
    }];
    let gamma = |out: crate::pipeline::Outcome| -> Vec<u8> {
        let layer = out.stack.layers.into_iter();
        match layer.last().map(|l| (l.kind, l.pixels)) {
            Some((Some(Effect::Gammaton), LayerPixels::Rgba(img))) => img.into_raw(),
            _ => panic!("the γ-ton layer comes last"),
        }
    };
    let none = Progress::none();
    let mut cache = Cache::default();
    paint(true);
    let left = gamma(run_cached(&scene, &preset, &none, &mut cache).unwrap());
    // The same preset, the mask repainted (as in the GUI): the γ-tons run again.
    paint(false);
    let right = gamma(run_cached(&scene, &preset, &none, &mut cache).unwrap());
    assert!(
        left != right,
        "the kept γ-tons were shown for a repainted mask"
    );
    assert!(right == gamma(run(&scene, &preset, &none).unwrap()));
    // Unchanged, the kept output is used (and equals a fresh run).
    assert!(right == gamma(run_cached(&scene, &preset, &none, &mut cache).unwrap()));
}

#[test]
fn the_filter_spreads_a_substance_over_the_near_wall() {
    use crate::pipeline::{Scene, run};
    // Settle-only γ-tons from one painted pixel: all the dirt sits there;
    // a filter of 2 shows it as the mean over a 5 x 5 window.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("dot.png");
    image::GrayImage::from_fn(40, 30, |x, y| {
        image::Luma([255 * u8::from((x, y) == (20, 15))])
    })
    .save(&path)
    .unwrap();
    let photo = image::RgbImage::from_pixel(40, 30, image::Rgb([150, 140, 130]));
    let scene = Scene::new(crate::photo::Photo::new(photo.into()), None).unwrap();
    let mut preset = Preset::default();
    let g = &mut preset.gammaton;
    g.enabled = true;
    g.particles = 500;
    (g.p_straight, g.p_parabolic, g.p_flow, g.radius) = (0.0, 0.0, 0.0, 0.0);
    g.substances[0].scale = 1e-3;
    g.sources = vec![GammaSource {
        mask: path.to_string_lossy().into_owned(),
        ..GammaSource::new(SourceKind::Mask, vec![1.0])
    }];
    let covered = |preset: &Preset| -> usize {
        let out = run(&scene, preset, &Progress::none()).unwrap();
        match &out.stack.layers.last().unwrap().pixels {
            LayerPixels::Rgba(img) => img.pixels().filter(|p| p[3] > 0).count(),
            _ => panic!("an RGBA layer"),
        }
    };
    assert_eq!(covered(&preset), 1);
    preset.gammaton.substances[0].filter = 2;
    assert_eq!(covered(&preset), 25);
}
