//! Rain shelter: the wall just under a projecting ledge, balcony or roof
//! overhang gets less rain. Driving rain reaches behind a projection of
//! depth p down to about p / tan(angle) below it; with rain angles spread
//! over a storm, the shelter fades roughly exponentially with the distance
//! below the ledge (how-facades-age.md, "Rain shelter") [choice: an
//! exponential with a reach set by the ledge's kind].

use super::features::Features;
use super::{Ledge, LedgeKind};

/// How far below a ledge its shelter reaches, in image heights (1/e).
pub fn reach(kind: LedgeKind) -> f32 {
    match kind {
        LedgeKind::RoofLine | LedgeKind::Cornice | LedgeKind::Coping => 0.04,
        LedgeKind::Balcony => 0.03,
        LedgeKind::Sill | LedgeKind::WindowHead | LedgeKind::StringCourse => 0.012,
    }
}

/// Shelter 0..1 per analysis pixel (1 = fully sheltered) under `ledges`
/// (analysis pixels).
pub fn map(f: &Features, ledges: &[Ledge]) -> Vec<f32> {
    let (w, h) = (f.w, f.h);
    let mut out = vec![0f32; w * h];
    for l in ledges {
        let d = reach(l.kind) * h as f32;
        for seg in l.polyline.windows(2) {
            let (a, b) = (seg[0], seg[1]);
            let (x0, x1) = (
                a[0].min(b[0]).max(0.0) as usize,
                (a[0].max(b[0]) as usize).min(w),
            );
            for x in x0..x1 {
                let t = if b[0] != a[0] {
                    (x as f32 - a[0]) / (b[0] - a[0])
                } else {
                    0.0
                };
                let yl = a[1] + (b[1] - a[1]) * t;
                let y0 = yl.max(0.0).ceil() as usize;
                let y1 = ((yl + 4.0 * d).ceil() as usize).min(h);
                for y in y0..y1 {
                    let s = l.confidence.max(0.5) * (-(y as f32 - yl) / d).exp();
                    let o = &mut out[y * w + x];
                    *o = o.max(s);
                }
            }
        }
    }
    out
}
