use super::placement::{self, AREA};
use super::*;
use crate::effects::testing;
use crate::field::RowMajor;
use crate::preset::{BlotchParams, Placement, RustParams, ScratchParams};
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
                for what in ["scratches", "splotches", "stains", "mould", "rust"] {
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
