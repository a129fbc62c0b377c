//! Time-lapse benchmark (issue 15): "30 frames of a 12 MP photo cost little
//! more than the run itself". The procedural facade at 4000 x 3000 (JPEG,
//! region and ledges found by the scene analysis), aged 30 years to a PNG:
//! alone, and with a 31-frame GIF (frames 1024 px, captioned) written
//! beside it, both through `age::age` as `grime run` does. Results:
//! BENCHMARKS.md. `cargo bench --bench timelapse`.

use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use grime::age::{self, Inputs, Outputs};
use grime::clock::{self, Pins};
use grime::preset::Preset;
use grime::progress::Progress;
use grime::timelapse::{self, Timelapse};

fn bench(c: &mut Criterion) {
    let dir = tempfile::tempdir().unwrap();
    let photo = dir.path().join("facade.jpg");
    grime::demo::facade(4000, 3000)
        .photo
        .image()
        .to_rgb8()
        .save(&photo)
        .unwrap();
    let mut preset = Preset::default();
    preset.age.years = Some(30);
    let preset = clock::at(&preset, 30, Pins::none()).unwrap();
    let inputs = Inputs::file(&photo);
    let outputs = |timelapse: Option<Timelapse>| Outputs {
        images: vec![dir.path().join("aged.png")],
        layers_dir: None,
        report: None,
        create_dirs: false,
        timelapse,
    };
    let mut gif = Timelapse::new(dir.path().join("ageing.gif"));
    gif.caption = true;
    gif.years = timelapse::default_years(30);
    let mut group = c.benchmark_group("timelapse");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(60));
    group.bench_function("run_4000x3000_30_years", |b| {
        b.iter(|| age::age(&inputs, &preset, &outputs(None), &Progress::none()).unwrap())
    });
    group.bench_function("run_and_gif_31_frames_4000x3000", |b| {
        b.iter(|| {
            age::age(
                &inputs,
                &preset,
                &outputs(Some(gif.clone())),
                &Progress::none(),
            )
            .unwrap()
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
