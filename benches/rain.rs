//! Rain benchmarks (issue 2): Chang Table 1 on a 1024x1024 wall, and a
//! 4000x3000 photo with the default preset (rain, moss, dust). Results: BENCHMARKS.md.

use criterion::{Criterion, criterion_group, criterion_main};
use grime::pipeline::{self, Scene};
use grime::preset::{self, Preset};
use grime::progress::Progress;

fn facade_scene(w: u32, h: u32) -> (Scene, Vec<grime::preset::SourceLine>) {
    let demo = grime::demo::facade(w, h);
    (
        Scene::new(demo.photo, demo.region).expect("scene"),
        demo.source_lines,
    )
}

fn chang_table1(c: &mut Criterion) {
    // Whole image is the wall; water from the top edge (Chang's setting).
    let demo = grime::demo::facade(1024, 1024);
    let scene = Scene::new(demo.photo, None).expect("scene");
    // Table 1 is the rain workload alone.
    let mut preset = preset::builtin("chang-table1").expect("preset");
    preset.moss.enabled = false;
    preset.dust.enabled = false;
    let mut g = c.benchmark_group("rain");
    g.sample_size(10);
    g.bench_function("chang_table1_1024x1024", |b| {
        b.iter(|| pipeline::run(&scene, &preset, &Progress::none()).expect("run"))
    });
    g.finish();
}

fn photo_4000x3000(c: &mut Criterion) {
    let (scene, lines) = facade_scene(4000, 3000);
    let mut preset = Preset::default();
    preset.rain.source_lines = lines;
    let mut g = c.benchmark_group("rain");
    g.sample_size(10);
    g.bench_function("default_4000x3000", |b| {
        b.iter(|| pipeline::run(&scene, &preset, &Progress::none()).expect("run"))
    });
    g.finish();
}

criterion_group!(benches, chang_table1, photo_4000x3000);
criterion_main!(benches);
