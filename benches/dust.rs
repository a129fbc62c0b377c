//! Dust and moss benchmarks (issue 3). Results: BENCHMARKS.md.
//!
//! - `dust/santos_largest_1500x1500`: the paper's largest scene, 1,187,200
//!   fine particles and 551,200 coarse elements (w = 14, the sphere scene) on
//!   a 1500x1500 texture, placed over 100 days and shaded into both layers.
//!   Santos & Baranoski's C++ took 70 s.
//! - `dust/default_4000x3000`: the default preset's dust on a 4000x3000 photo.
//! - `moss/facade_960x720_15y`: 15 years of moss on the demo facade's rain.

use criterion::{Criterion, criterion_group, criterion_main};
use grime::effects::dust;
use grime::effects::moss::{self, MossInput, Wet};
use grime::effects::region::Region;
use grime::pipeline::{self, Scene};
use grime::preset::{DustEnvironment, DustParams, Preset, Segment};
use grime::progress::Progress;

fn santos_largest(c: &mut Criterion) {
    let region = Region::new(1500, 1500, None).expect("region");
    // A = 1500^2 / 150^2 = 100 in^2; 100 days at these rates give exactly
    // 1,187,200 fine particles and 551,200 coarse elements.
    let p = DustParams {
        days: 100,
        environment: DustEnvironment::Custom,
        film_segments: vec![Segment::new(0, 118.72, 0.0)],
        mask_segments: vec![Segment::new(0, 55.12, 0.0)],
        granule_size: 14.0,
        ..DustParams::default()
    };
    let (_, _, stats) = dust::accumulate(&region, None, &p, 1, &Progress::none()).expect("dust");
    assert_eq!((stats.film_particles, stats.granules), (1_187_200, 551_200));
    let mut g = c.benchmark_group("dust");
    g.sample_size(10);
    g.bench_function("santos_largest_1500x1500", |b| {
        b.iter(|| dust::accumulate(&region, None, &p, 1, &Progress::none()).expect("dust"))
    });
    g.finish();
}

fn default_4000x3000(c: &mut Criterion) {
    let demo = grime::demo::facade(4000, 3000);
    let mask = demo.region.expect("facade has a region");
    let region = Region::new(4000, 3000, Some(&mask)).expect("region");
    let p = Preset::default().dust;
    let mut g = c.benchmark_group("dust");
    g.sample_size(10);
    g.bench_function("default_4000x3000", |b| {
        b.iter(|| dust::accumulate(&region, None, &p, 1, &Progress::none()).expect("dust"))
    });
    g.finish();
}

fn moss_facade(c: &mut Criterion) {
    let demo = grime::demo::facade(960, 720);
    let mut preset = Preset::default();
    preset.rain.source_lines = demo.source_lines.clone();
    preset.moss.enabled = false;
    preset.dust.enabled = false;
    let scene = Scene::new(demo.photo, demo.region).expect("scene");
    let out = pipeline::run(&scene, &preset, &Progress::none()).expect("rain");
    let mask = scene.region.as_deref();
    let grid_region = out.grid.region(mask);
    let luma = out.grid.luma(&scene.photo);
    let region = Region::new(960, 720, mask).expect("region");
    let input = MossInput {
        luma: &luma,
        region: &grid_region,
        wet: Some(Wet {
            water: &out.rain.water,
            saturation: preset.rain.saturation,
            dirt: &out.rain.dirt,
            d_max: moss::d_max(&out.rain.dirt, &grid_region, preset.stain.percentile),
        }),
        habitat: None,
        baseline: demo.site.px(preset.moss.colony_m),
    };
    let p = Preset::default().moss;
    let mut g = c.benchmark_group("moss");
    g.sample_size(10);
    g.bench_function("facade_960x720_15y", |b| {
        b.iter(|| moss::grow(&input, &out.grid, &region, &p, 1, &Progress::none()).expect("moss"))
    });
    g.finish();
}

criterion_group!(benches, santos_largest, default_4000x3000, moss_facade);
criterion_main!(benches);
