//! Invariants of a whole rainfall: dirt conservation, where droplets start
//! and end, and that more water runs further.

use super::*;
use crate::field::RowMajor;
use crate::progress::Progress;

/// A textured wall, `w` x `h`, whole grid is region.
fn wall_input(w: usize, h: usize) -> (RowMajor<f32>, RowMajor<bool>) {
    let luma = RowMajor::from_fn(w, h, |x, y| {
        120.0
            + 30.0 * ((((y * w + x) * 7919) % 13) as f32 / 13.0)
            + 20.0 * y.is_multiple_of(9) as u8 as f32
    });
    (luma, RowMajor::filled(w, h, true))
}

fn one_layer() -> RainParams {
    RainParams {
        layers: 1,
        droplets: 80,
        reference_width: 0,
        ..RainParams::default()
    }
}

#[test]
fn dirt_is_conserved_between_droplets_and_wall() {
    let (luma, region) = wall_input(64, 96);
    let input = RainInput {
        luma: &luma,
        region: &region,
        source_lines: vec![],
        catch: vec![],
        release: Release::UNIFORM,
        washed: false,
    };
    // No fresh grime: all dirt comes off the ledges with the droplets.
    let p = RainParams {
        initial_dirt: 0.0,
        ..one_layer()
    };
    let out = simulate(&input, &p, 3, &Progress::none()).unwrap();
    let s = &out.layers[0].stats;
    let on_wall: f64 = out.dirt.data().iter().map(|&d| d as f64).sum();
    assert!(s.dirt_from_ledges > 1.0);
    let err = (on_wall + s.dirt_lost - s.dirt_from_ledges).abs();
    assert!(
        err < 1e-3 * s.dirt_from_ledges,
        "wall {on_wall} + lost {} != injected {}",
        s.dirt_lost,
        s.dirt_from_ledges
    );
}

#[test]
fn what_droplets_wash_off_and_deposit_balances_what_they_bring_and_lose() {
    // A grimy wall: droplets dissolve some of it (Chang eqs. 7-8) and leave
    // it lower down; the rest runs off. Per rainfall, the dirt the droplets
    // added minus what they washed off is what they brought off the ledges
    // minus what they lost.
    let (luma, region) = wall_input(64, 96);
    let input = RainInput {
        luma: &luma,
        region: &region,
        source_lines: vec![],
        catch: vec![],
        release: Release::UNIFORM,
        washed: true,
    };
    let p = RainParams {
        initial_dirt: 5.0,
        ledge_dirt: 0.5,
        ..one_layer()
    };
    let out = simulate(&input, &p, 3, &Progress::none()).unwrap();
    let s = &out.layers[0].stats;
    let sum = |f: &ColumnMajor<f32>| f.data().iter().map(|&v| v as f64).sum::<f64>();
    let net = out.washed.as_ref().unwrap();
    let cleaned: f64 = net.data().iter().map(|&v| v.max(0.0) as f64).sum();
    let deposit = sum(&out.layers[0].deposit);
    assert!(
        cleaned > 0.05 * deposit,
        "cleaned {cleaned} vs deposit {deposit}"
    );
    let err = (sum(net) + s.dirt_from_ledges - s.dirt_lost).abs();
    assert!(
        err < 1e-3 * (deposit + cleaned),
        "net washed {} != lost {} - brought {}",
        sum(net),
        s.dirt_lost,
        s.dirt_from_ledges
    );
    // Without droplets nothing is washed off, and the flag only adds the map.
    let dry = simulate(
        &input,
        &RainParams {
            droplets: 0,
            ..p.clone()
        },
        3,
        &Progress::none(),
    )
    .unwrap();
    assert_eq!(sum(dry.washed.as_ref().unwrap()), 0.0);
    let plain = simulate(
        &RainInput {
            washed: false,
            ..input.clone()
        },
        &p,
        3,
        &Progress::none(),
    )
    .unwrap();
    assert!(plain.washed.is_none());
    assert_eq!(plain.layers[0].deposit.data(), out.layers[0].deposit.data());
}

#[test]
fn a_sheltered_ledge_sheds_less_water_than_an_open_one() {
    // Two equal ledges; the right one catches a quarter of the rain.
    let (luma, region) = wall_input(120, 80);
    let lines = vec![
        vec![(10.0, 20.0), (50.0, 20.0)],
        vec![(70.0, 20.0), (110.0, 20.0)],
    ];
    let starts = |catch: Vec<f32>| {
        let input = RainInput {
            luma: &luma,
            region: &region,
            source_lines: lines.clone(),
            catch,
            release: Release::UNIFORM,
            washed: false,
        };
        let p = RainParams {
            top_edge: false,
            droplets: 400,
            ..one_layer()
        };
        let out = simulate(&input, &p, 9, &Progress::none()).unwrap();
        let right = out.layers[0]
            .paths
            .iter()
            .filter(|q| q.start.0 > 60.0)
            .count();
        (out.layers[0].paths.len() - right, right)
    };
    let (left, right) = starts(vec![1.0, 0.25]);
    let ratio = right as f32 / left as f32;
    assert!((0.17..=0.33).contains(&ratio), "{right} vs {left}");
    // Open ledges share the rain by length; a fully sheltered one gets none.
    let (left, right) = starts(vec![]);
    assert!(
        (0.8..=1.25).contains(&(right as f32 / left as f32)),
        "{right} vs {left}"
    );
    assert_eq!(starts(vec![1.0, 0.0]).1, 0);
}

#[test]
fn droplets_start_on_the_source_line_and_end_lower() {
    let (luma, region) = wall_input(80, 120);
    let line = vec![(10.0, 30.0), (70.0, 30.0)];
    let input = RainInput {
        luma: &luma,
        region: &region,
        source_lines: vec![line],
        catch: vec![],
        release: Release::UNIFORM,
        washed: false,
    };
    let p = RainParams {
        top_edge: false,
        ..one_layer()
    };
    let out = simulate(&input, &p, 5, &Progress::none()).unwrap();
    let paths = &out.layers[0].paths;
    assert!(paths.len() > 40, "{} droplets ran", paths.len());
    for path in paths {
        assert!(
            (10.0..=70.0).contains(&path.start.0),
            "start x {}",
            path.start.0
        );
        assert!(
            (path.start.1 - 31.0).abs() < 1e-3,
            "start y {}",
            path.start.1
        );
        if path.steps > 5 {
            assert!(path.end.1 > path.start.1 + 2.0, "{path:?} did not run down");
        }
    }
    // Nothing well above the ledge gets dirt (diffusion spreads a few px).
    let reach = (p.diffusion_rounds * p.diffusion_iterations) as usize;
    let deposit = &out.layers[0].deposit;
    let above: f32 = (0..80)
        .flat_map(|x| (0..30 - reach).map(move |y| deposit.get(x, y)))
        .sum();
    assert_eq!(above, 0.0);
    assert!(
        deposit.data().iter().sum::<f32>() > 0.0,
        "but there is dirt below"
    );
}

#[test]
fn heavier_droplets_run_further() {
    // Eq. (5) drains a fixed fraction per step, so runs grow with log(mass);
    // the wall is tall enough that neither kind reaches the bottom.
    let (luma, region) = wall_input(64, 2000);
    let input = RainInput {
        luma: &luma,
        region: &region,
        source_lines: vec![],
        catch: vec![],
        release: Release::UNIFORM,
        washed: false,
    };
    let mean_run = |mass_max: f32| {
        let p = RainParams {
            mass_max,
            ..one_layer()
        };
        let out = simulate(&input, &p, 9, &Progress::none()).unwrap();
        let paths = &out.layers[0].paths;
        paths.iter().map(|p| p.end.1 - p.start.1).sum::<f32>() / paths.len() as f32
    };
    let (light, heavy) = (mean_run(20.0), mean_run(80.0));
    assert!(heavy > 1.15 * light, "light {light}, heavy {heavy}");
}

#[test]
fn droplet_count_scales_with_width() {
    let p = RainParams::default();
    assert_eq!(droplet_count(&p, 1000), 600);
    assert_eq!(droplet_count(&p, 2000), 1200);
    let fixed = RainParams {
        reference_width: 0,
        ..p
    };
    assert_eq!(droplet_count(&fixed, 2000), 600);
}

#[test]
fn cancel_stops_mid_layer() {
    use std::sync::atomic::AtomicBool;
    let (luma, region) = wall_input(64, 64);
    let input = RainInput {
        luma: &luma,
        region: &region,
        source_lines: vec![],
        catch: vec![],
        release: Release::UNIFORM,
        washed: false,
    };
    let cancel = AtomicBool::new(true);
    let r = simulate(
        &input,
        &RainParams::default(),
        1,
        &Progress::new(None, Some(&cancel)),
    );
    assert!(matches!(r, Err(crate::Error::Cancelled)));
}

#[test]
fn deposits_raise_streak_channels_but_keep_the_wall_rough() {
    // Eq. (15): after many rainfalls the surface keeps its texture; only
    // where dirt was deposited does it rise.
    let (luma, region) = wall_input(96, 128);
    let input = RainInput {
        luma: &luma,
        region: &region,
        source_lines: vec![],
        catch: vec![],
        release: Release::UNIFORM,
        washed: false,
    };
    let p = RainParams {
        layers: 12,
        droplets: 60,
        reference_width: 0,
        ..RainParams::default()
    };
    let out = simulate(&input, &p, 11, &Progress::none()).unwrap();
    let m_y = out.roughness_y.data();
    let rough = m_y.iter().filter(|&&m| m > 0.0).count() as f32 / m_y.len() as f32;
    assert!(
        rough > 0.5,
        "only {:.0}% of the wall is still rough",
        rough * 100.0
    );
}

#[test]
fn the_same_rain_at_any_thread_count() {
    // Wide enough for several patches per phase, so that droplets run on
    // different threads and some cross patch borders.
    let (luma, region) = wall_input(700, 90);
    let input = RainInput {
        luma: &luma,
        region: &region,
        source_lines: vec![],
        catch: vec![],
        release: Release::UNIFORM,
        washed: false,
    };
    let p = RainParams {
        layers: 3,
        droplets: 500,
        reference_width: 0,
        b: 0.1,
        ..RainParams::default()
    };
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| simulate(&input, &p, 21, &Progress::none()).unwrap())
    };
    let one = run(1);
    for threads in [2, 3] {
        let many = run(threads);
        for (a, b) in one.layers.iter().zip(&many.layers) {
            assert_eq!(a.deposit, b.deposit, "{threads} threads");
            assert_eq!(a.stats.droplet_steps, b.stats.droplet_steps);
        }
        assert_eq!(one.water, many.water, "{threads} threads");
        assert_eq!(one.dirt, many.dirt, "{threads} threads");
    }
}

#[test]
fn an_in_range_preset_that_asks_too_much_is_refused_before_it_starts() {
    // Issue 13: every value is in range, but 100000 droplets per grid column
    // make 4e8 droplet runs on this grid.
    let (luma, region) = wall_input(400, 300);
    let input = RainInput {
        luma: &luma,
        region: &region,
        source_lines: vec![],
        catch: vec![],
        release: Release::UNIFORM,
        washed: false,
    };
    let p = RainParams {
        droplets: 100_000,
        reference_width: 1,
        ..RainParams::default()
    };
    let cost = Cost::of(&p, 400, 300);
    assert_eq!(cost.runs, 12 * 40_000_000);
    assert!(cost.steps > MAX_STEPS && cost.bytes > MAX_BYTES);
    let e = simulate(&input, &p, 1, &Progress::none()).unwrap_err();
    let Error::TooMuchWork { fix, .. } = &e else {
        panic!("{e}");
    };
    assert!(fix.contains("rain.droplets") && fix.contains("rain.reference_width"));
    // Far more than the default fits.
    let default = Cost::of(&RainParams::default(), 1024, 1024);
    assert!(default.steps * 100 < MAX_STEPS && default.bytes * 50 < MAX_BYTES);
    assert!(default.check().is_ok());
    // So does a memory bound alone: many rainfalls on a huge grid.
    let layers = RainParams {
        layers: 200,
        droplets: 1,
        ..RainParams::default()
    };
    let e = Cost::of(&layers, 8000, 8000).check().unwrap_err();
    assert!(e.to_string().contains("memory"), "{e}");
}

#[test]
fn droplets_in_several_schedules_are_the_same_at_any_thread_count() {
    // More droplets than one schedule holds: they run SCHEDULE at a time.
    let (luma, region) = wall_input(300, 12);
    let input = RainInput {
        luma: &luma,
        region: &region,
        source_lines: vec![],
        catch: vec![],
        release: Release::UNIFORM,
        washed: false,
    };
    let p = RainParams {
        layers: 1,
        droplets: SCHEDULE as u32 + 5000,
        reference_width: 0,
        max_steps: 40,
        ..RainParams::default()
    };
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| simulate(&input, &p, 4, &Progress::none()).unwrap())
    };
    let (one, two) = (run(1), run(2));
    let stats = &one.layers[0].stats;
    assert!(stats.droplets as usize > SCHEDULE, "{}", stats.droplets);
    assert_eq!(one.layers[0].paths.len(), stats.droplets as usize);
    assert_eq!(one.layers[0].deposit, two.layers[0].deposit);
    assert_eq!(one.dirt, two.dirt);
}

#[test]
fn kept_walls_are_the_shorter_runs() {
    let (luma, region) = wall_input(64, 96);
    let input = RainInput {
        luma: &luma,
        region: &region,
        source_lines: vec![],
        catch: vec![],
        release: Release::UNIFORM,
        washed: false,
    };
    let p = |layers| RainParams {
        layers,
        ..one_layer()
    };
    let none = Progress::none();
    let (full, kept) = simulate_keeping(&input, &p(4), 5, &none, &[0, 2, 4]).unwrap();
    let alone = simulate(&input, &p(4), 5, &none).unwrap();
    assert_eq!(
        (full.water.data(), full.dirt.data()),
        (alone.water.data(), alone.dirt.data())
    );
    assert_eq!(
        kept.iter().map(|k| k.rainfalls).collect::<Vec<_>>(),
        [0, 2, 4]
    );
    for k in &kept {
        let short = simulate(&input, &p(k.rainfalls), 5, &none).unwrap();
        let prefix = full.prefix(k);
        assert_eq!(
            prefix.water.data(),
            short.water.data(),
            "{} rainfalls",
            k.rainfalls
        );
        assert_eq!(prefix.dirt.data(), short.dirt.data());
        assert_eq!(prefix.roughness_y.data(), short.roughness_y.data());
        for (a, b) in prefix.layers.iter().zip(&short.layers) {
            assert_eq!(a.deposit.data(), b.deposit.data());
        }
    }
}

#[test]
fn a_ledge_found_elsewhere_leaves_the_other_ledges_streaks_where_they_were() {
    // Two ledges on the left half; then a third on the right half. The
    // streaks under the first two keep their starts: the third takes its
    // share of the droplets (50 of 140 pixels of ledge) from the end of
    // each one's own list.
    let (luma, region) = wall_input(160, 80);
    let left = vec![
        vec![(10.0, 20.0), (50.0, 20.0)],
        vec![(10.0, 45.0), (60.0, 45.0)],
    ];
    let run = |lines: Vec<Vec<(f32, f32)>>| {
        let input = RainInput {
            luma: &luma,
            region: &region,
            source_lines: lines,
            catch: vec![],
            release: Release::UNIFORM,
            washed: false,
        };
        let p = RainParams {
            top_edge: false,
            droplets: 300,
            ..one_layer()
        };
        let out = simulate(&input, &p, 4, &Progress::none()).unwrap();
        let mut starts: Vec<(i64, i64)> = out.layers[0]
            .paths
            .iter()
            .filter(|q| q.start.0 < 80.0)
            .map(|q| ((q.start.0 * 100.0) as i64, (q.start.1 * 100.0) as i64))
            .collect();
        starts.sort_unstable();
        starts
    };
    let before = run(left.clone());
    let mut more = left.clone();
    more.push(vec![(100.0, 30.0), (150.0, 30.0)]);
    let after = run(more);
    let kept = after
        .iter()
        .filter(|s| before.binary_search(s).is_ok())
        .count();
    assert!(
        kept as f32 >= 0.95 * after.len() as f32 && after.len() * 5 >= before.len() * 3,
        "{kept} of {} starts on the left kept ({} before)",
        after.len(),
        before.len()
    );
}

#[test]
fn each_source_gets_its_share_of_the_droplets_and_keeps_their_numbers() {
    let count = |o: &[(usize, u64)], i: usize| o.iter().filter(|d| d.0 == i).count();
    let two = owners(7, &[10.0, 30.0], &[5, 9], 40);
    assert_eq!((count(&two, 0), count(&two, 1)), (10, 30));
    // A sheltered source (no span) gets none.
    let sheltered = owners(7, &[0.0, 30.0, 10.0], &[3, 5, 9], 41);
    assert_eq!(count(&sheltered, 0), 0);
    assert_eq!(sheltered.len(), 41);
    // A third source: the first two keep droplets 0.. of their own lists.
    let three = owners(7, &[10.0, 30.0, 40.0], &[5, 9, 11], 40);
    for i in 0..2 {
        let mut js: Vec<u64> = three.iter().filter(|d| d.0 == i).map(|d| d.1).collect();
        js.sort_unstable();
        assert_eq!(js, (0..js.len() as u64).collect::<Vec<_>>());
    }
}

/// A droplet's walk turns back at its source's ends: it stays on the
/// source, a step past an end lands as far inside, and a uniform spread
/// of starts stays uniform after many steps (no pile-up at the ends).
#[test]
fn a_droplets_walk_turns_back_at_its_sources_ends() {
    assert_eq!(reflect(-3.0, 10.0), 3.0);
    assert_eq!(reflect(12.0, 10.0), 8.0);
    assert_eq!(reflect(25.0, 10.0), 5.0);
    assert_eq!(reflect(4.0, 0.0), 0.0);
    let mut rng = crate::random::rng(1, Stream::Droplet, 0, 0);
    let mut bins = [0usize; 10];
    for _ in 0..20_000 {
        let mut x = rng.random::<f32>() * 10.0;
        for _ in 0..8 {
            x = reflect(x + 6.0 * crate::random::box_muller(&mut rng).0, 10.0);
        }
        assert!((0.0..=10.0).contains(&x), "{x} left the source");
        bins[(x as usize).min(9)] += 1;
    }
    for b in bins {
        assert!((1_800..2_200).contains(&b), "{bins:?}: not uniform");
    }
}
