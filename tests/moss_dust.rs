//! Moss and dust as layers of the pipeline's stack (issue 3): particle
//! counts, curve continuity, where moss grows, the region, view angles and
//! determinism across thread counts.

use std::collections::HashSet;

use grime::effects::dust::{self, DustState, granules};
use grime::effects::moss;
use grime::effects::region::Region;
use grime::field::RowMajor;
use grime::pipeline::{self, Outcome, Scene};
use grime::preset::{DustEnvironment, Preset};
use grime::progress::Progress;
use grime::stack::{Layer, LayerPixels};
use grime::{demo, random};
use rand::Rng as _;

/// The papers' own models, as these tests check them: Santos' dust at its
/// 150 ppi over the whole wall, Chang's moss (eq. 18 alone, baseline 1/40
/// of the wall, a candidate per baseline^2 a year) and uniform, unfaded rain.
fn papers() -> Preset {
    let mut p = Preset::default();
    p.dust.ppi = 150.0;
    p.dust.open_wall = 1.0;
    p.moss.baseline = 1.0 / 40.0;
    p.moss.open_wall = 1.0;
    p.moss.seed_rate = 1.0;
    p.moss.spread = 0.8;
    p.rain.drip_spacing_m = 0.0;
    p.rain.end_share = 0.0;
    p.rain.fall_m = 0.0;
    p
}

fn facade(w: u32, h: u32) -> (Scene, Preset) {
    let d = demo::facade(w, h);
    let mut p = papers();
    p.rain.source_lines = d.source_lines;
    p.rain.layers = 3;
    (Scene::new(d.photo, d.region).unwrap(), p)
}

fn run(scene: &Scene, p: &Preset) -> Outcome {
    pipeline::run(scene, p, &Progress::none()).unwrap()
}

fn layer<'a>(out: &'a Outcome, name: &str) -> &'a Layer {
    out.stack
        .layers
        .iter()
        .find(|l| l.name == name)
        .unwrap_or_else(|| panic!("no layer {name}"))
}

fn alpha(l: &Layer) -> Vec<u8> {
    l.to_rgba().pixels().map(|p| p[3]).collect()
}

#[test]
fn layers_stack_as_rain_moss_film_granules() {
    let (scene, p) = facade(160, 120);
    let out = run(&scene, &p);
    let names: Vec<_> = out.stack.layers.iter().map(|l| l.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "rain 01",
            "rain 02",
            "rain 03",
            "rain washed",
            "moss",
            "dust film",
            "dust granules"
        ]
    );
    assert_eq!(out.report.layers.len(), 7);
    let mut q = p.clone();
    q.moss.enabled = false;
    q.dust.enabled = false;
    let out = run(&scene, &q);
    assert_eq!(out.stack.layers.len(), 4);
    assert!(out.report.moss().is_none() && out.report.dust().is_none());
}

#[test]
fn film_holds_exactly_eq_1_particles_after_t_days() {
    let (scene, mut p) = facade(320, 240);
    p.rain.layers = 0;
    p.moss.enabled = false;
    p.dust.environment = DustEnvironment::HighActivity;
    let (alpha_f, beta_f) = (2.8, 25.7);
    let wall = scene
        .region
        .as_ref()
        .unwrap()
        .pixels()
        .filter(|v| v[0] >= 128)
        .count() as f64;
    let area = wall / (p.dust.ppi * p.dust.ppi);
    for t in [1u32, 2, 37, 400] {
        p.dust.days = t;
        let want = (area * (alpha_f + beta_f) + area * alpha_f * (t - 1) as f64).round() as u64;
        let report = run(&scene, &p).report.dust().cloned().unwrap();
        assert_eq!(report.film_particles, want, "T = {t}");
        assert!((report.area_in2 - area).abs() < 1e-9);
        // The film itself holds them, one count per particle.
        let region = Region::new(320, 240, scene.region.as_deref()).unwrap();
        let mut state = DustState::new(&region, &p.dust, p.seed).unwrap();
        state
            .advance_to(&region, t, &p.dust, &Progress::none())
            .unwrap();
        assert_eq!(state.film.total(), want, "T = {t}");
    }
}

#[test]
fn a_time_sequence_is_incremental() {
    let region = Region::new(200, 150, None).unwrap();
    let mut p = papers().dust;
    p.environment = DustEnvironment::HighActivity;
    let mut stepped = DustState::new(&region, &p, 4).unwrap();
    stepped
        .advance_to(&region, 100, &p, &Progress::none())
        .unwrap();
    let (film100, gran100, stats100) = stepped.render(&region, &p, None).unwrap();
    stepped
        .advance_to(&region, 200, &p, &Progress::none())
        .unwrap();
    let (film200, gran200, stats200) = stepped.render(&region, &p, None).unwrap();
    let mut direct = DustState::new(&region, &p, 4).unwrap();
    direct
        .advance_to(&region, 200, &p, &Progress::none())
        .unwrap();
    let (film_d, gran_d, stats_d) = direct.render(&region, &p, None).unwrap();
    assert_eq!(film200, film_d, "day 100 + days 101-200 = day 200");
    assert_eq!(gran200, gran_d);
    assert_eq!(stats200, stats_d);
    let added = dust::total(&p.segments().0, stats100.area_in2, 200)
        - dust::total(&p.segments().0, stats100.area_in2, 100);
    assert_eq!(stats200.film_particles - stats100.film_particles, added);
    for (a, b) in film100.pixels().zip(film200.pixels()) {
        assert!(b[3] >= a[3], "film never thins");
    }
    for (a, b) in gran100.pixels().zip(gran200.pixels()) {
        assert!(a[0] == 0 || b[0] == a[0], "granules stay");
    }
}

/// Plain reference: flood fill over 8-neighbours.
fn components(pixels: &HashSet<(i64, i64)>) -> usize {
    let mut seen = HashSet::new();
    let mut n = 0;
    for &start in pixels {
        if !seen.insert(start) {
            continue;
        }
        n += 1;
        let mut stack = vec![start];
        while let Some((x, y)) = stack.pop() {
            for dx in -1..=1 {
                for dy in -1..=1 {
                    let q = (x + dx, y + dy);
                    if pixels.contains(&q) && seen.insert(q) {
                        stack.push(q);
                    }
                }
            }
        }
    }
    n
}

#[test]
fn hairs_are_8_connected_curves() {
    let mut rng = random::rng(11, random::Stream::DustGranules, 0, 0);
    for w in [12.0f32, 36.0, 200.0] {
        for _ in 0..300 {
            let pts = std::array::from_fn(|_| (rng.random::<f32>() * w, rng.random::<f32>() * w));
            let mut pixels = HashSet::new();
            granules::hair(pts, &mut |x, y| {
                pixels.insert((x, y));
            });
            assert_eq!(components(&pixels), 1, "hair through {pts:?} has gaps");
            // A curve, not a filled area: about as many pixels as it is long.
            let span = pts.iter().map(|p| p.0).fold(f32::MIN, f32::max)
                - pts.iter().map(|p| p.0).fold(f32::MAX, f32::min);
            let tall = pts.iter().map(|p| p.1).fold(f32::MIN, f32::max)
                - pts.iter().map(|p| p.1).fold(f32::MAX, f32::min);
            assert!(
                pixels.len() as f32 <= 3.0 * (span + tall + 2.0),
                "{} pixels",
                pixels.len()
            );
        }
    }
    // The same holds in a rendered mask of hairs only.
    let region = Region::new(120, 90, None).unwrap();
    let mut p = papers().dust;
    (p.arc_share, p.clump_share, p.hair_share) = (0.0, 0.0, 1.0);
    p.environment = DustEnvironment::Custom;
    p.film_segments = vec![grime::preset::Segment::new(0, 0.0, 0.0)];
    p.mask_segments = vec![grime::preset::Segment::new(0, 0.0, 0.6)];
    p.ppi = 10.0;
    let (_, gran, stats) = dust::accumulate(&region, None, &p, 3, &Progress::none()).unwrap();
    assert_eq!((stats.hairs, stats.arcs, stats.clumps), (65, 0, 0));
    let covered: HashSet<(i64, i64)> = gran
        .enumerate_pixels()
        .filter(|(_, _, v)| v[0] > 0)
        .map(|(x, y, _)| (x as i64, y as i64))
        .collect();
    assert!(
        components(&covered) <= 65,
        "each hair is one piece (touching hairs merge)"
    );
}

/// A plain wall of uniform roughness (i.i.d. grain, so M_y has no pattern of
/// its own), rained on from its top edge and from one short ledge.
fn plain_wall(w: u32, h: u32) -> (Scene, Preset) {
    let img = image::RgbImage::from_fn(w, h, |x, y| {
        let v = 170 + (random::mix((y as u64) << 32 | x as u64) % 16) as u8;
        image::Rgb([v, v - 10, v - 25])
    });
    let scene = Scene::new(
        grime::photo::Photo::new(image::DynamicImage::ImageRgb8(img)),
        None,
    )
    .unwrap();
    let mut p = papers();
    p.rain.layers = 6;
    // No fresh grime: water and dirt come from the rain alone, so they vary.
    p.rain.initial_dirt = 0.0;
    p.rain.source_lines = vec![vec![
        [w as f32 * 0.55, h as f32 * 0.5],
        [w as f32 * 0.85, h as f32 * 0.5],
    ]];
    p.dust.enabled = false;
    (scene, p)
}

#[test]
fn moss_density_correlates_with_wetness() {
    let (scene, mut p) = plain_wall(480, 360);
    p.moss.years = 12;
    for seed in [1, 2, 3] {
        p.seed = seed;
        let out = run(&scene, &p);
        let (gw, gh) = (out.grid.width, out.grid.height);
        assert_eq!((gw, gh, out.grid.scale), (480, 360, 1.0));
        let region = RowMajor::filled(gw, gh, true);
        let d_max = moss::d_max(&out.rain.dirt, &region, p.stain.percentile);
        let moss_alpha = alpha(layer(&out, "moss"));
        // Blocks of 40 x 40 pixels: mean (w/a + D/D_max) against mean moss alpha.
        let (bs, mut xs, mut ys) = (40usize, Vec::new(), Vec::new());
        for by in (0..gh / bs).map(|b| b * bs) {
            for bx in (0..gw / bs).map(|b| b * bs) {
                let (mut wet, mut moss_sum) = (0.0, 0.0);
                for y in by..by + bs {
                    for x in bx..bx + bs {
                        let i = y * gw + x;
                        let wa = (out.rain.water.get(x, y) / p.rain.saturation).min(1.0);
                        wet += (wa + (out.rain.dirt.get(x, y) / d_max).min(1.0)) as f64;
                        moss_sum += moss_alpha[i] as f64 / 255.0;
                    }
                }
                xs.push(wet / (bs * bs) as f64);
                ys.push(moss_sum / (bs * bs) as f64);
            }
        }
        let r = pearson(&xs, &ys);
        let report = out.report.moss().cloned().unwrap();
        eprintln!(
            "seed {seed}: {} colonies, coverage {:.4}, r = {r:.3}",
            report.colonies, report.coverage
        );
        assert!(report.colonies > 20);
        assert!(
            r > 0.35,
            "seed {seed}: moss density vs w/a + D/D_max: r = {r}"
        );
    }
}

#[test]
fn moss_sits_high_on_the_facade_and_grows_with_the_years() {
    let (scene, mut p) = facade(320, 240);
    p.dust.enabled = false;
    let mut last = 0.0;
    for years in [5, 15, 30] {
        p.moss.years = years;
        let out = run(&scene, &p);
        let a = alpha(layer(&out, "moss"));
        let band =
            |y0: usize, y1: usize| a[y0 * 320..y1 * 320].iter().map(|&v| v as f64).sum::<f64>();
        assert!(
            band(0, 80) > band(160, 240),
            "{years} years: more moss on the top third"
        );
        let coverage = out.report.moss().unwrap().coverage;
        assert!(
            coverage > last,
            "{years} years: coverage {coverage} <= {last}"
        );
        last = coverage;
    }
}

fn pearson(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let cov: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let vx: f64 = x.iter().map(|a| (a - mx).powi(2)).sum();
    let vy: f64 = y.iter().map(|b| (b - my).powi(2)).sum();
    cov / (vx * vy).sqrt()
}

#[test]
fn moss_and_dust_never_touch_pixels_outside_the_region() {
    let (scene, mut p) = facade(320, 240);
    p.moss.years = 25;
    p.moss.seed_rate = 3.0;
    p.dust.environment = DustEnvironment::HighActivity;
    p.dust.theta_v = 85.0;
    let out = run(&scene, &p);
    let mask = scene.region.as_deref().unwrap();
    for name in ["moss", "dust film", "dust granules"] {
        let a = alpha(layer(&out, name));
        let inside = a
            .iter()
            .zip(mask.as_raw())
            .filter(|(a, m)| **a > 0 && **m > 0)
            .count();
        assert!(inside > 100, "{name} is drawn at all ({inside} px)");
        let outside = a
            .iter()
            .zip(mask.as_raw())
            .filter(|(a, m)| **a > 0 && **m == 0)
            .count();
        assert_eq!(outside, 0, "{name} has {outside} pixels outside the region");
    }
    let before = scene.photo.image().to_rgb8();
    let after = out.stack.composite().to_rgb8();
    for ((b, a), m) in before.pixels().zip(after.pixels()).zip(mask.as_raw()) {
        if *m == 0 {
            assert_eq!(a, b);
        }
    }
}

#[test]
fn dust_film_shows_more_at_grazing_views_and_not_head_on() {
    let (scene, mut p) = facade(240, 180);
    p.rain.layers = 0;
    p.moss.enabled = false;
    p.dust.environment = DustEnvironment::Desktop;
    let mut last = -1.0;
    for theta_v in [0.0, 20.0, 45.0, 70.0, 90.0] {
        p.dust.theta_v = theta_v;
        let out = run(&scene, &p);
        let film = layer(&out, "dust film");
        let visibility: f64 = alpha(film).iter().map(|&a| a as f64).sum();
        if theta_v == 0.0 {
            assert_eq!(visibility, 0.0, "theta_v = 0 gives no film");
        }
        assert!(
            visibility > last,
            "theta_v = {theta_v}: {visibility} <= {last}"
        );
        last = visibility;
        // The granules do not depend on the view (Santos eq. 10).
        assert!(layer(&out, "dust granules").coverage() > 0.0);
    }
}

#[test]
fn same_seed_gives_byte_identical_layers_at_1_and_2_threads() {
    let (scene, mut p) = facade(320, 240);
    p.moss.years = 15;
    p.dust.environment = DustEnvironment::HighActivity;
    let at = |threads: usize, p: &Preset| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| run(&scene, p))
    };
    let (one, two) = (at(1, &p), at(2, &p));
    assert_eq!(one.stack.layers.len(), two.stack.layers.len());
    for (a, b) in one.stack.layers.iter().zip(&two.stack.layers) {
        assert_eq!(a.name, b.name);
        assert!(
            a.to_rgba().as_raw() == b.to_rgba().as_raw(),
            "layer {} differs",
            a.name
        );
        if let (LayerPixels::Tint { color: ca, .. }, LayerPixels::Tint { color: cb, .. }) =
            (&a.pixels, &b.pixels)
        {
            assert_eq!(ca, cb);
        }
    }
    assert_eq!(one.report.moss(), two.report.moss());
    assert_eq!(one.report.dust(), two.report.dust());
    assert!(one.stack.composite().as_bytes() == two.stack.composite().as_bytes());
    // And another seed gives other moss and dust.
    p.seed += 1;
    let other = at(2, &p);
    assert!(alpha(layer(&other, "moss")) != alpha(layer(&one, "moss")));
    assert!(alpha(layer(&other, "dust granules")) != alpha(layer(&one, "dust granules")));
}
