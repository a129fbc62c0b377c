use std::collections::BTreeMap;
use std::sync::Arc;
use std::time::Instant;
use grime::gui::render::{self, PROXY_PIXELS, Proxy};
use grime::preset::Preset;
use grime::progress::Progress;

fn main() {
    let demo = grime::demo::facade(1155, 866);
    let mask = demo.region.clone().expect("the sample has a region");
    let photo = Arc::new(demo.photo);
    let proxy = Proxy::new(&photo, &mask, PROXY_PIXELS);
    let mut preset = Preset::default();
    preset.rain.source_lines = demo.source_lines;
    let layers = BTreeMap::new();
    for side in [128u32, 192, 256, 384, 1024] {
        for _ in 0..3 {
            preset.sim.max_side = side;
            let t = Instant::now();
            let job = proxy.job(&preset, None, &layers).unwrap();
            let tj = t.elapsed();
            let out = grime::perspective::pipeline_with_quad(&job.scene, None, &job.preset, &Progress::none()).unwrap();
            let tp = t.elapsed();
            let img = out.stack.composite();
            let tc = t.elapsed();
            let ci = render::to_color_image(&img);
            let te = t.elapsed();
            std::hint::black_box(ci);
            println!("side {side}: job {:.1} pipeline {:.1} composite {:.1} color {:.1} total {:.1} | {}", tj.as_secs_f64()*1e3, (tp-tj).as_secs_f64()*1e3, (tc-tp).as_secs_f64()*1e3, (te-tc).as_secs_f64()*1e3, te.as_secs_f64()*1e3,
              out.report.timings.iter().map(|t| format!("{} {:.1}", t.stage, t.ms)).collect::<Vec<_>>().join(", "));
        }
    }
}
