//! γ-tons: 1 million on a 1024 x 1024 grid (issue 16's target: < 0.5 s on
//! 2 cores; aitios needs about 32 s per iteration for 8 entities on a mesh).

use criterion::{Criterion, criterion_group, criterion_main};
use grime::effects::gammaton;
use grime::field::RowMajor;
use grime::preset::GammatonParams;
use grime::progress::Progress;

fn million(c: &mut Criterion) {
    let (w, h) = (1024, 1024);
    let luma = RowMajor::from_fn(w, h, |x, y| ((x * 7 + y * 13) % 64) as f32 + 96.0);
    let region = RowMajor::filled(w, h, true);
    let p = GammatonParams {
        enabled: true,
        particles: 1_000_000,
        // The default source: rain from the sky carrying one unit of dirt.
        ..GammatonParams::default()
    };
    let mut group = c.benchmark_group("gammaton");
    group.sample_size(10);
    group.bench_function("1M gamma-tons, 1024x1024, default motion", |b| {
        b.iter(|| {
            gammaton::simulate(
                &luma,
                &region,
                &Default::default(),
                &p,
                1,
                &Progress::none(),
            )
            .expect("run")
        })
    });
    group.finish();
}

criterion_group!(benches, million);
criterion_main!(benches);
