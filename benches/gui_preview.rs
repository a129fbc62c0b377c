//! GUI preview latency (issue 6): time from a parameter change to the
//! updated preview on a 1 MP proxy with the default preset. This runs the
//! preview worker's code path: proxy scene → pipeline → composite → egui
//! image ([`Previewer`], which the worker owns, so each effect's output is
//! kept between runs in a `pipeline::Cache` as in the GUI, and only the
//! effects a change makes stale re-run). Three cases:
//!
//! - a simulation parameter (`rain.k_a`) to the first updated preview: the
//!   quick pass on a coarse grid ([`render::QUICK_MAX_SIDE`]);
//! - the same change to the refined preview: quick pass, then full pass;
//! - a change that only re-composites (stain opacity, like layer
//!   visibility/opacity and scrubbing the time slider back).
//!
//! Before the benchmarks it prints where the time goes (median of a few
//! runs per stage) for the quick pass at a few grid sizes and for the full
//! pass. Results: BENCHMARKS.md.

use std::collections::BTreeMap;
use std::sync::Arc;

use criterion::{Criterion, criterion_group, criterion_main};
use grime::gui::render::{self, PROXY_PIXELS, Previewer, Proxy};
use grime::preset::Preset;
use grime::progress::Progress;

/// Median ms per stage over `runs` runs of `max_side`, printed on one line.
/// Each run changes `rain.k_a` (the dust is kept) or, with `dust_change`,
/// `dust.days` (only the dust is made again; rain and moss are kept).
fn breakdown(proxy: &Proxy, preset: &Preset, max_side: u32, runs: usize, dust_change: bool) {
    let layers = BTreeMap::new();
    let mut previewer = Previewer::default();
    let mut preset = preset.clone();
    preset.sim.max_side = max_side;
    // One run to fill the cache, as after the first preview.
    previewer
        .full(
            &proxy.job(&preset, None, &layers).unwrap(),
            &Progress::none(),
        )
        .unwrap();
    let mut per_stage: Vec<(String, Vec<f64>)> = Vec::new();
    let mut totals = Vec::new();
    for i in 0..runs {
        if dust_change {
            preset.dust.days += 1;
        } else {
            preset.rain.k_a = 0.51 + 0.01 * i as f32; // never the default 0.5
        }
        let start = std::time::Instant::now();
        let job = proxy.job(&preset, None, &layers).unwrap();
        let p = previewer.full(&job, &Progress::none()).unwrap();
        totals.push(start.elapsed().as_secs_f64() * 1000.0);
        for t in p.timings {
            match per_stage.iter_mut().find(|(s, _)| *s == t.stage) {
                Some((_, v)) => v.push(t.ms),
                None => per_stage.push((t.stage, vec![t.ms])),
            }
        }
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let stages: Vec<String> = per_stage
        .iter_mut()
        .map(|(s, v)| format!("{s} {:.1}", median(v)))
        .collect();
    println!(
        "breakdown max_side {max_side}{}: total {:.1} ms = {}",
        if dust_change { " (dust change)" } else { "" },
        median(&mut totals),
        stages.join(", ")
    );
}

fn preview(c: &mut Criterion) {
    // 1155 x 866 = 1.0 MP, the proxy size; the proxy is the photo itself.
    let demo = grime::demo::facade(1155, 866);
    let mask = demo.region.clone().expect("the sample has a region");
    let photo = Arc::new(demo.photo);
    let proxy = Proxy::new(&photo, &mask, PROXY_PIXELS);
    let mut preset = Preset::default();
    preset.rain.source_lines = demo.source_lines;
    let layers = BTreeMap::new();

    for side in [128, render::QUICK_MAX_SIDE, 256] {
        breakdown(&proxy, &preset, side, 5, false);
    }
    breakdown(&proxy, &preset, render::QUICK_MAX_SIDE, 5, true);
    breakdown(&proxy, &preset, preset.sim.max_side, 3, false);

    let mut g = c.benchmark_group("gui_preview");
    g.sample_size(10);
    let mut previewer = Previewer::default();
    let mut k_a = 0.5;
    g.bench_function("slider_change_first_preview_1mp", |b| {
        b.iter(|| {
            // A slider moves: a new job from the document, its quick pass.
            k_a = if k_a == 0.5 { 0.55 } else { 0.5 };
            preset.rain.k_a = k_a;
            let job = proxy.job(&preset, None, &layers).expect("job");
            let quick = previewer.quick(&job, &Progress::none());
            quick.expect("a quick pass").expect("preview").image
        })
    });
    g.bench_function("slider_change_refined_preview_1mp", |b| {
        b.iter(|| {
            // The same, to the full pass (the quick pass runs first).
            k_a = if k_a == 0.5 { 0.55 } else { 0.5 };
            preset.rain.k_a = k_a;
            let job = proxy.job(&preset, None, &layers).expect("job");
            previewer
                .run(job, &Progress::none(), &|quick| {
                    std::hint::black_box(quick);
                })
                .expect("preview")
                .image
        })
    });
    let job = proxy.job(&preset, None, &layers).expect("job");
    let mut done = render::simulate(job, &Progress::none()).expect("preview");
    let mut opacity = 0.8;
    g.bench_function("slider_change_recomposite_1mp", |b| {
        b.iter(|| {
            opacity = if opacity == 0.8 { 0.6 } else { 0.8 };
            preset.stain.opacity = opacity;
            assert!(render::restyles(&done.sim_preset, &preset));
            done.restyle(&preset, &layers);
            done.image.size
        })
    });
    g.finish();
}

criterion_group!(benches, preview);
criterion_main!(benches);
