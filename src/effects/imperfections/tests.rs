use super::placement::{self, AREA};
use super::*;
use crate::effects::testing;
use crate::field::RowMajor;
use crate::preset::{
    BlotchParams, CorrosionParams, Placement, RustParams, ScratchParams, SmudgeParams,
};
use crate::say::{ADVERBS, NO_ADVERB};

fn alpha_of(layer: &Layer) -> Vec<u8> {
    let img = layer.to_rgba();
    img.pixels().map(|p| p[3]).collect()
}

#[test]
fn scratches_spread_around_the_dominant_axis_and_are_centimetres() {
    testing::facade(320, 240, |ctx| {
        let p = ScratchParams {
            enabled: true,
            coverage: 0.3,
            angle: 30.0,
            angle_spread: 10.0,
            ..ScratchParams::default()
        };
        let placed = placement::place(ctx, p.place());
        let drawn = scratches::draw(ctx, &p, &placed, 5);
        let n = drawn.scratches.len() as f32;
        assert!(n > 200.0, "{n} scratches");
        let mean = drawn.scratches.iter().map(|s| s.angle).sum::<f32>() / n;
        let sd = (drawn
            .scratches
            .iter()
            .map(|s| (s.angle - mean).powi(2))
            .sum::<f32>()
            / n)
            .sqrt();
        assert!((mean - 30.0).abs() < 1.5, "mean angle {mean}");
        assert!((sd - 10.0).abs() < 1.5, "angle spread {sd}");
        // 8 cm on a 10 m wide photo of 320 px: about 2.6 px, not a tenth of it.
        let len = drawn.scratches.iter().map(|s| s.length).sum::<f32>() / n;
        assert!((len - 0.08 * 32.0).abs() < 0.3, "mean length {len} px");
        // No spread: one direction.
        let narrow = scratches::draw(
            ctx,
            &ScratchParams {
                angle_spread: 0.0,
                ..p
            },
            &placed,
            5,
        );
        assert!(narrow.scratches.iter().all(|s| s.angle == 30.0));
    });
}

#[test]
fn a_higher_splotch_threshold_leaves_sparser_splotches_inside_the_lower_ones() {
    testing::facade(320, 240, |ctx| {
        let p = |coverage| BlotchParams {
            enabled: true,
            coverage,
            placement: Placement::Everywhere,
            ..BlotchParams::splotches()
        };
        let (sparse, dense) = (p(0.1), p(0.4));
        let placed = placement::place(ctx, sparse.place());
        let (_, _, a) = blots::draw(ctx, &sparse, &placed, 3, Gen::Splotches);
        let (_, _, b) = blots::draw(ctx, &dense, &placed, 3, Gen::Splotches);
        let (ca, cb) = (measured(&a, &placed), measured(&b, &placed));
        assert!(
            (ca - 0.1).abs() < 0.005 && (cb - 0.4).abs() < 0.005,
            "{ca} {cb}"
        );
        // The field is the same: a higher threshold n keeps a subset.
        assert!(
            a.pixels()
                .zip(b.pixels())
                .all(|(x, y)| x[0] == 0 || y[0] > 0)
        );
        // [n, 1] interpolates: dry splotch alpha grows away from the edge.
        let g = blots::field(ctx, &dense, &placed, 3, Gen::Splotches);
        let t = threshold(&g, &placed, 0.4);
        assert!(
            g.iter()
                .zip(b.pixels())
                .all(|(v, a)| (*v > t) == (a[0] > 0))
        );
    });
}

fn rusted_connected_to_seeds(agg: &rust::Aggregate, seeds: &[(usize, usize)]) -> bool {
    let (w, h) = (agg.age.width(), agg.age.height());
    let mut seen = vec![false; w * h];
    let mut stack: Vec<(usize, usize)> = seeds.to_vec();
    while let Some((x, y)) = stack.pop() {
        if seen[y * w + x] || !agg.age.get(x, y).is_finite() {
            continue;
        }
        seen[y * w + x] = true;
        for (dx, dy) in [
            (-1, -1),
            (0, -1),
            (1, -1),
            (-1, 0),
            (1, 0),
            (-1, 1),
            (0, 1),
            (1, 1),
        ] {
            let (xx, yy) = (x as isize + dx, y as isize + dy);
            if xx >= 0 && yy >= 0 && (xx as usize) < w && (yy as usize) < h {
                stack.push((xx as usize, yy as usize));
            }
        }
    }
    (0..w * h).all(|i| seen[i] || !agg.age.data()[i].is_finite())
}

#[test]
fn rust_grows_from_its_seeds_and_with_iterations() {
    let allowed = RowMajor::filled(120, 90, 1.0);
    let sources = RowMajor::filled(120, 90, false);
    let seeds = [(20, 20), (90, 60)];
    let ground = rust::Ground {
        allowed: &allowed,
        sources: &sources,
        seeds: &seeds,
    };
    let p = |iterations| RustParams {
        iterations,
        p_edge: 0.0,
        p_interior: 0.0,
        ..RustParams::default()
    };
    let counts: Vec<usize> = [5, 15, 40]
        .into_iter()
        .map(|n| {
            let agg = rust::aggregate(&ground, &p(n), 0, 7);
            assert_eq!(agg.iterations, n);
            assert!(
                rusted_connected_to_seeds(&agg, &seeds),
                "rust away from its seeds at {n}"
            );
            // Older rust sits nearer its seed.
            agg.rusted
        })
        .collect();
    assert!(counts[0] < counts[1] && counts[1] < counts[2], "{counts:?}");
    // Metal cells start rust of their own: a row of sources rusts along it.
    let mut row = RowMajor::filled(120, 90, false);
    (0..120).for_each(|x| row.data_mut()[45 * 120 + x] = true);
    let metal = rust::Ground {
        allowed: &allowed,
        sources: &row,
        seeds: &[],
    };
    let agg = rust::aggregate(
        &metal,
        &RustParams {
            p_edge: 0.1,
            p_interior: 0.0,
            ..p(10)
        },
        0,
        7,
    );
    let near = (0..120 * 90)
        .filter(|&i| agg.age.data()[i].is_finite())
        .all(|i| (i / 120).abs_diff(45) <= 10);
    assert!(agg.rusted > 100 && near, "{} rusted", agg.rusted);
}

fn adverbs() -> Vec<f32> {
    let mut c: Vec<f32> = ADVERBS.iter().map(|a| a.1).collect();
    c.push(NO_ADVERB);
    c.sort_by(f32::total_cmp);
    c.dedup();
    c
}

#[test]
fn the_coverage_table_holds_for_every_adverb_generator_and_placement() {
    testing::facade(240, 180, |ctx| {
        for placement in ["everywhere", "ground", "sills", "edges", "railings"] {
            for c in adverbs() {
                for what in [
                    "scratches",
                    "splotches",
                    "stains",
                    "mould",
                    "rust",
                    "smudges",
                    "corrosion",
                ] {
                    let mut preset = Preset::default();
                    preset.set(&format!("{what}.enabled=true")).unwrap();
                    preset.set(&format!("{what}.coverage={c}")).unwrap();
                    preset
                        .set(&format!("{what}.placement=\"{placement}\""))
                        .unwrap();
                    let made =
                        stage(ctx, &mut Products::default(), &preset, &Progress::none()).unwrap();
                    let layer = made.layers.iter().find(|l| l.name == what).unwrap();
                    let place = match what {
                        "scratches" => preset.scratches.place(),
                        "splotches" => preset.splotches.place(),
                        "stains" => preset.stains.place(),
                        "mould" => preset.mould.place(),
                        "smudges" => preset.smudges.place(),
                        "corrosion" => preset.corrosion.place(),
                        _ => preset.rust.place(),
                    };
                    let placed = placement::place(ctx, place);
                    let covered = alpha_of(layer).iter().filter(|&&a| a > 0).count();
                    let got = covered as f32 / placed.area as f32;
                    assert!(
                        (got - c).abs() <= 0.02,
                        "{what} near {placement} at {c}: covered {got}"
                    );
                }
            }
        }
    });
}

#[test]
fn placements_put_the_area_where_they_say() {
    testing::facade(240, 180, |ctx| {
        let rows = |p: Placement| {
            let placed = placement::place(
                ctx,
                crate::preset::Place {
                    placement: p,
                    band: 1.0,
                    around: [120.0, 90.0],
                    area: &[],
                },
            );
            let (mut sum, mut n) = (0.0, 0.0);
            for (i, w) in placed.weight.iter().enumerate() {
                if *w >= AREA {
                    sum += (i / 240) as f32;
                    n += 1.0;
                }
            }
            sum / n
        };
        assert!(rows(Placement::Ground) > rows(Placement::Everywhere));
        assert!(rows(Placement::Top) < rows(Placement::Everywhere));
        assert!((rows(Placement::Point) - 90.0).abs() < 2.0);
    });
}

/// Covered pixels next to an uncovered one of the placement area.
fn boundary(alpha: &image::GrayImage, placed: &placement::Placed) -> Vec<usize> {
    let (w, h) = (placed.width, placed.height);
    (0..w * h)
        .filter(|&i| {
            let (x, y) = (i % w, i / w);
            alpha.as_raw()[i] > 0
                && x > 0
                && y > 0
                && x + 1 < w
                && y + 1 < h
                && [i - 1, i + 1, i - w, i + w]
                    .iter()
                    .any(|&j| alpha.as_raw()[j] == 0 && placed.in_area(j))
        })
        .collect()
}

#[test]
fn smudges_weigh_a_greasy_blur_by_the_fbm_and_fade_in_at_their_edge() {
    testing::facade(320, 240, |ctx| {
        let p = SmudgeParams {
            enabled: true,
            coverage: 0.4,
            placement: Placement::Everywhere,
            ..SmudgeParams::default()
        };
        let placed = placement::place(ctx, p.place());
        let (img, alpha) = smudges::smudges(ctx, &p, &placed, 4);
        assert!((measured(&alpha, &placed) - 0.4).abs() < 0.005);
        // The fBm is the weight: alpha never falls as the field rises.
        let f = fractal::Fractal::new(
            4,
            Gen::Smudges.stream(0),
            320,
            240,
            ctx.photo_px(p.size),
            p.roughness,
        );
        let wt = smudges::weight(&f, &placed, p.coverage, p.stretch);
        let mut covered: Vec<(f32, u8)> = wt
            .field
            .iter()
            .zip(alpha.as_raw())
            .filter(|(_, a)| **a > 0)
            .map(|(g, a)| (*g, *a))
            .collect();
        covered.sort_by(|a, b| a.0.total_cmp(&b.0));
        assert!(covered.windows(2).all(|p| p[0].1 <= p[1].1));
        // No hard edge (a splotch starts at half its alpha): soft at the rim.
        let rim = boundary(&alpha, &placed);
        assert!(rim.len() > 50);
        let mean = rim.iter().map(|&i| alpha.as_raw()[i] as f32).sum::<f32>() / rim.len() as f32;
        assert!(mean < 0.1 * 255.0, "rim alpha {mean}");
        let top = *alpha.as_raw().iter().max().unwrap();
        assert!(top > 240, "strongest smudge alpha {top}");
        // Darker than the wall under it, on the whole.
        let photo = ctx.photo.image().to_rgb8();
        let luma = |c: &[u8]| c[0] as f32 * 0.3 + c[1] as f32 * 0.59 + c[2] as f32 * 0.11;
        let (mut under, mut over) = (0.0, 0.0);
        for (q, s) in photo.pixels().zip(img.pixels()) {
            if s[3] > 128 {
                under += luma(&q.0);
                over += luma(&s.0);
            }
        }
        assert!(over < under * 0.85, "smudge {over} wall {under}");
    });
}

#[test]
fn corrosion_pits_densest_where_its_fbm_weight_is_strongest() {
    testing::facade(320, 240, |ctx| {
        let p = CorrosionParams {
            enabled: true,
            coverage: 0.5,
            placement: Placement::Everywhere,
            ..CorrosionParams::default()
        };
        let placed = placement::place(ctx, p.place());
        let (img, alpha) = smudges::corrosion(ctx, &p, &placed, 9);
        assert!((measured(&alpha, &placed) - 0.5).abs() < 0.005);
        let f = fractal::Fractal::new(
            9,
            Gen::Corrosion.stream(0),
            320,
            240,
            ctx.photo_px(p.size),
            p.roughness,
        );
        let wt = smudges::weight(&f, &placed, p.coverage, 1.0);
        let pitted = smudges::pits(ctx, &p, &wt.weight, 320, 9);
        // Pits are only inside the corrosion, and in the layer.
        for (i, px) in img.pixels().enumerate() {
            let a = alpha_byte(
                smudges::pit_alpha(ctx.photo_px(p.pit_size)).max(p.discolour * wt.weight[i]),
            );
            assert!(!pitted[i] || (wt.weight[i] > 0.0 && px[3] == a));
        }
        let share = |lo: f32, hi: f32| {
            let inside: Vec<usize> = (0..wt.weight.len())
                .filter(|&i| wt.weight[i] > lo && wt.weight[i] <= hi)
                .collect();
            inside.iter().filter(|&&i| pitted[i]).count() as f32 / inside.len().max(1) as f32
        };
        let (weak, strong) = (share(0.0, 0.33), share(0.66, 1.0));
        assert!(
            strong > 2.0 * weak && strong > 0.15,
            "pits: weak {weak} strong {strong}"
        );
        // Overall: about pits x mean weight of the covered pixels.
        let n = wt.weight.iter().filter(|&&v| v > 0.0).count() as f32;
        let mean = wt.weight.iter().sum::<f32>() / n;
        let all = pitted.iter().filter(|&&b| b).count() as f32 / n;
        assert!(
            (all - p.pits * mean).abs() < 0.05,
            "{all} vs {}",
            p.pits * mean
        );
        // No pits at all: only the discolouration, its alpha the weight's.
        let clean = smudges::corrosion(
            ctx,
            &CorrosionParams {
                pits: 0.0,
                ..p.clone()
            },
            &placed,
            9,
        )
        .1;
        for (a, v) in clean.as_raw().iter().zip(&wt.weight) {
            let want = if *v > 0.0 {
                alpha_byte(p.discolour * v)
            } else {
                0
            };
            assert_eq!(*a, want);
        }
    });
}

#[test]
fn colour_layers_take_the_walls_light() {
    // A wall dark on its left half and light on its right: the same rust
    // is darker over the dark half (modulated, not painted over).
    let photo = crate::photo::Photo::new(image::DynamicImage::ImageLuma8(
        image::GrayImage::from_fn(200, 100, |x, _| {
            image::Luma([if x < 100 { 60 } else { 180 }])
        }),
    ));
    let site = crate::pipeline::Site::assumed(200);
    testing::with(&photo, None, &site, None, 0, |ctx| {
        let mut preset = Preset::default();
        for s in [
            "rust.enabled=true",
            "rust.coverage=0.5",
            "rust.placement=\"everywhere\"",
        ] {
            preset.set(s).unwrap();
        }
        let made = stage(ctx, &mut Products::default(), &preset, &Progress::none()).unwrap();
        let rust = made
            .layers
            .iter()
            .find(|l| l.name == "rust")
            .unwrap()
            .to_rgba();
        let mean_red = |xs: std::ops::Range<u32>| {
            let (sum, n) = rust
                .enumerate_pixels()
                .filter(|(x, _, p)| xs.contains(x) && p[3] > 0)
                .fold((0u64, 0u64), |(s, n), (_, _, p)| (s + p[0] as u64, n + 1));
            assert!(n > 100, "{n} rust pixels");
            sum as f32 / n as f32
        };
        let (dark, light) = (mean_red(0..100), mean_red(100..200));
        assert!(
            dark < 0.7 * light,
            "rust red {dark} over the dark half, {light} over the light"
        );
    });
}

#[test]
fn stains_fade_in_at_their_edge_and_are_darkest_just_inside_it() {
    testing::facade(320, 240, |ctx| {
        let p = BlotchParams {
            enabled: true,
            coverage: 0.3,
            placement: Placement::Everywhere,
            wet: 1.0,
            ..BlotchParams::stains()
        };
        let placed = placement::place(ctx, p.place());
        let (_, _, alpha) = blots::draw(ctx, &p, &placed, 8, Gen::Stains);
        let rim = boundary(&alpha, &placed);
        assert!(rim.len() > 50);
        let mean = rim.iter().map(|&i| alpha.as_raw()[i] as f32).sum::<f32>() / rim.len() as f32;
        let top = *alpha.as_raw().iter().max().unwrap() as f32;
        assert!(mean < 0.5 * top, "rim alpha {mean}, strongest {top}");
    });
}
