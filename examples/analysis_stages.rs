//! Per-stage timings of the 12 MP analysis bench input (issue 11): runs
//! `analysis::analyse` on `synthetic::scene(3, 4000, 3000)` N times and
//! prints each stage's minimum and median in milliseconds.
//!
//! `target/release/examples/analysis_stages [RUNS]`

use grime::analysis::{self, Options, synthetic};

fn main() {
    let runs: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(15);
    let scene = synthetic::scene(3, 4000, 3000);
    let opts = Options::default();
    let mut t: Vec<[f32; 5]> = Vec::new();
    for _ in 0..runs {
        let a = analysis::analyse(&scene.photo, &opts).expect("analysis");
        let s = a.timings;
        t.push([
            s.features_ms,
            s.classes_ms,
            s.ledges_ms,
            s.matte_ms,
            s.total_ms,
        ]);
    }
    for (k, name) in ["features", "classes", "ledges", "matte", "total"]
        .iter()
        .enumerate()
    {
        let mut v: Vec<f32> = t.iter().map(|r| r[k]).collect();
        v.sort_by(f32::total_cmp);
        println!("{name:9} min {:7.1}  median {:7.1}", v[0], v[v.len() / 2]);
    }
}
