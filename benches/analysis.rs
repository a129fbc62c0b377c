//! Scene analysis benchmark (issue 11). Results: BENCHMARKS.md "Scene analysis".
//!
//! - `analysis/street_4000x3000`: a 12 MP synthetic street scene (sky,
//!   facade with windows, sills and cornice, road, tree), decoded already:
//!   the whole of `analysis::analyse`, matte upsampled to 12 MP included.
//!   Target: at most 150 ms on 2 cores.

use criterion::{Criterion, criterion_group, criterion_main};
use grime::analysis::{self, Options, synthetic};

fn street_12mp(c: &mut Criterion) {
    let scene = synthetic::scene(3, 4000, 3000);
    let opts = Options::default();
    let mut g = c.benchmark_group("analysis");
    g.sample_size(10);
    g.bench_function("street_4000x3000", |b| {
        b.iter(|| analysis::analyse(&scene.photo, &opts).expect("analysis"))
    });
    g.finish();
}

criterion_group!(benches, street_12mp);
criterion_main!(benches);
