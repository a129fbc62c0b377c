//! Measuring the analysis against labelled photos (issue 11's targets):
//! wall IoU, spill of wall onto negatives and onto sky, recall and precision
//! of sills and cornices, and the scale estimate against storey heights
//! read from the labels. The `scene_eval` example runs it on the public
//! datasets; the tests run it on [`super::synthetic`] scenes.

use crate::analysis::neighbours;

mod foot;
pub use foot::{FootScore, true_foot};
use std::fmt::Write as _;

/// Storey height assumed by the scale estimate, metres.
pub use super::scale::STOREY_M;
use super::{Analysis, Class, LedgeKind};

/// Truth label: not scored (windows, doors, "various").
pub const IGNORE: u8 = 0;
/// Truth label: wall.
pub const WALL_LABEL: u8 = 1;
/// Truth label: sky (a negative, also counted on its own).
pub const SKY: u8 = 2;
/// Truth label: any other negative (vegetation, road, pavement, car).
pub const NEGATIVE: u8 = 3;
/// Truth label: vegetation (a negative, also counted on its own).
pub const VEGETATION: u8 = 4;
/// Truth label: road or pavement (a negative, also counted on its own).
pub const GROUND: u8 = 5;
/// Truth label: a vehicle (a negative, also counted on its own).
pub const CAR: u8 = 6;

/// Names of the negative labels, index = label.
const NEGATIVE_NAMES: [&str; 7] = ["", "", "sky", "other", "vegetation", "ground", "car"];

/// The classes a missed wall pixel can have, in the order
/// [`Metrics::report`] prints them, with the name it gives each (the
/// matte's soft edge for [`Class::Wall`]).
const MISS_NAMES: [(Class, &str); 6] = [
    (Class::Sky, "sky"),
    (Class::Vegetation, "vegetation"),
    (Class::Glass, "glass"),
    (Class::Ground, "ground"),
    (Class::Thing, "thing"),
    (Class::Wall, "edge"),
];

/// A labelled ledge: its box in photo pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Band {
    /// Left.
    pub x0: f32,
    /// Top.
    pub y0: f32,
    /// Right (exclusive).
    pub x1: f32,
    /// Bottom (exclusive).
    pub y1: f32,
}

/// What a photo really shows.
#[derive(Debug, Clone, Default)]
pub struct Truth {
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
    /// Per-pixel labels ([`IGNORE`], [`WALL_LABEL`], [`SKY`], [`NEGATIVE`]), if known.
    pub labels: Option<Vec<u8>>,
    /// Sills and cornices.
    pub ledges: Vec<Band>,
    /// Every labelled ledge-like element for the lenient precision (on CMP:
    /// sills, cornices, horizontal mouldings, balcony tops and feet);
    /// empty when the data has no such labels.
    pub ledge_like: Vec<Band>,
    /// Storey height in pixels, where it can be read.
    pub storey_px: Option<f32>,
    /// Per photo pixel: labelled window (glass and frame), where the data
    /// labels windows; for the glass measure, not the wall's IoU.
    pub windows: Option<Vec<bool>>,
    /// Per photo pixel: labelled "various" (LabelMeFacade's people,
    /// signs, umbrellas, street furniture: what stands before the wall),
    /// where the data labels it; ignored by the IoU, counted on its own
    /// ([`Metrics::various_spill`]).
    pub various: Option<Vec<bool>>,
}

/// Sums over a set of photos.
#[derive(Debug, Clone, Default)]
pub struct Metrics {
    /// Photos.
    pub images: usize,
    /// Photos with pixel labels.
    pub labelled: usize,
    /// Sum of per-photo wall IoU.
    pub iou_sum: f64,
    /// Negative pixels.
    pub negatives: u64,
    /// Negative pixels called wall.
    pub negatives_wall: u64,
    /// Sky pixels.
    pub sky: u64,
    /// Sky pixels called wall.
    pub sky_wall: u64,
    /// Per negative label (index = label, [`SKY`] to [`CAR`]): pixels,
    /// and those called wall.
    pub spill_by: [(u64, u64); 7],
    /// Wall pixels.
    pub walls: u64,
    /// Wall pixels not called wall, by the class their analysis pixel
    /// has (index = [`Class`] as usize; at [`Class::Wall`]: the matte's
    /// soft edge fell under half there).
    pub miss_by: [u64; 6],
    /// Labelled ledges.
    pub bands: usize,
    /// Labelled ledges found.
    pub bands_found: usize,
    /// Detected sills, cornices and other ledges (not window heads or roof
    /// lines: CMP labels neither).
    pub detections: usize,
    /// Detections that lie on a labelled ledge.
    pub detections_ok: usize,
    /// Detections (as for the precision) on any labelled ledge-like element.
    pub detections_lenient_ok: usize,
    /// Photos with ledge-like labels (the lenient precision is reported).
    pub lenient_images: usize,
    /// Per kind (in [`LedgeKind`] order; window heads too, which the
    /// precisions leave out): detections, and those on a labelled ledge.
    pub by_kind: [(usize, usize); 7],
    /// Photos with a storey height to compare with.
    pub scale_n: usize,
    /// Of those, estimates within a factor 1.5.
    pub scale_ok: usize,
    /// Labelled window pixels.
    pub window_px: u64,
    /// Labelled window pixels called glass.
    pub window_glass: u64,
    /// Pixels called glass (in photos that label windows).
    pub glass_px: u64,
    /// Labelled "various" pixels ([`Truth::various`]).
    pub various: u64,
    /// Labelled "various" pixels called wall by the matte.
    pub various_wall: u64,
    /// Length of the detected ledges (not roof lines), in photo pixel
    /// columns, by the label under each column's drip line (index =
    /// label, [`IGNORE`] to [`CAR`]): water started on a car, a tree or
    /// the road is a tell.
    pub ledge_on: [u64; 7],
    /// Sum of analysis times, ms.
    pub ms: f64,
    /// The wall's foot against the labels.
    pub foot: FootScore,
}

/// The kinds, in declaration order (index = `kind as usize`).
const KINDS: [LedgeKind; 7] = [
    LedgeKind::Sill,
    LedgeKind::Cornice,
    LedgeKind::Coping,
    LedgeKind::WindowHead,
    LedgeKind::Balcony,
    LedgeKind::StringCourse,
    LedgeKind::RoofLine,
];

/// Share of pixels called wall by the matte.
fn is_wall(a: &Analysis, i: usize) -> bool {
    a.matte.as_raw()[i] >= crate::grid::WALL
}

impl Metrics {
    /// Adds one photo's analysis (or, with `None`, an analysis that found
    /// no wall: nothing called wall, no ledges).
    pub fn add(&mut self, a: Option<&Analysis>, t: &Truth) {
        self.images += 1;
        if let Some(a) = a {
            self.ms += a.timings.total_ms as f64;
        }
        if let Some(labels) = &t.labels {
            self.labelled += 1;
            let (mut inter, mut union) = (0u64, 0u64);
            for (i, &l) in labels.iter().enumerate() {
                if l == IGNORE {
                    continue;
                }
                let p = a.is_some_and(|a| is_wall(a, i));
                let truth = l == WALL_LABEL;
                inter += (p && truth) as u64;
                union += (p || truth) as u64;
                if truth {
                    self.walls += 1;
                    if let (Some(a), false) = (a, p) {
                        let w = t.width.max(1);
                        let c = a.class_at(i as u32 % w, i as u32 / w);
                        self.miss_by[c as usize] += 1;
                    }
                } else {
                    self.negatives += 1;
                    self.negatives_wall += p as u64;
                    let by = &mut self.spill_by[(l as usize).min(6)];
                    by.0 += 1;
                    by.1 += p as u64;
                    if l == SKY {
                        self.sky += 1;
                        self.sky_wall += p as u64;
                    }
                }
            }
            self.foot.add(a, labels, t.width, t.height);
            self.iou_sum += if union == 0 {
                1.0
            } else {
                inter as f64 / union as f64
            };
        }
        if let (Some(windows), Some(a)) = (&t.windows, a) {
            self.add_glass(a, windows, t.width as usize);
        }
        if let Some(various) = &t.various {
            self.various += various.iter().filter(|&&v| v).count() as u64;
            if let Some(a) = a {
                self.various_wall += (various.iter().enumerate())
                    .filter(|&(i, &v)| v && is_wall(a, i))
                    .count() as u64;
            }
        }
        let tol = 0.015 * t.height as f32;
        let ledges = a.map(|a| a.ledges.as_slice()).unwrap_or(&[]);
        let y_at = |poly: &[[f32; 2]], x: f32| -> Option<f32> {
            poly.windows(2).find_map(|s| {
                let (p, q) = (s[0], s[1]);
                (x >= p[0].min(q[0]) && x <= p[0].max(q[0])).then(|| {
                    if q[0] == p[0] {
                        p[1]
                    } else {
                        p[1] + (q[1] - p[1]) * (x - p[0]) / (q[0] - p[0])
                    }
                })
            })
        };
        let near = |b: &Band, y: f32| y >= b.y0 - tol && y <= b.y1 + tol;
        for b in &t.ledges {
            self.bands += 1;
            let (x0, x1) = (b.x0.max(0.0) as i64, b.x1 as i64);
            let cols = (x1 - x0).max(1);
            let hit = (x0..x1)
                .filter(|&x| {
                    ledges
                        .iter()
                        .any(|l| y_at(&l.polyline, x as f32 + 0.5).is_some_and(|y| near(b, y)))
                })
                .count() as i64;
            self.bands_found += (2 * hit >= cols) as usize;
        }
        // A detection is on `bands` when at least half its columns are.
        let on = |l: &super::Ledge, bands: &[Band]| {
            let (x0, x1) = (l.polyline[0][0], l.polyline[l.polyline.len() - 1][0]);
            let cols = ((x1 - x0) as i64).max(1);
            let hit = (0..cols)
                .filter(|&k| {
                    let x = x0 + k as f32 + 0.5;
                    y_at(&l.polyline, x)
                        .is_some_and(|y| bands.iter().any(|b| x >= b.x0 && x < b.x1 && near(b, y)))
                })
                .count() as i64;
            2 * hit >= cols
        };
        if let Some(labels) = &t.labels {
            self.add_ledges_on(ledges, labels, t.width as usize);
        }
        self.lenient_images += !t.ledge_like.is_empty() as usize;
        for l in ledges {
            if l.kind == LedgeKind::RoofLine {
                continue;
            }
            let ok = on(l, &t.ledges);
            let k = &mut self.by_kind[l.kind as usize];
            k.0 += 1;
            k.1 += ok as usize;
            if l.kind == LedgeKind::WindowHead {
                continue;
            }
            self.detections += 1;
            self.detections_ok += ok as usize;
            self.detections_lenient_ok += (ok || on(l, &t.ledge_like)) as usize;
        }
        if let (Some(storey), Some(a)) = (t.storey_px, a) {
            self.scale_n += 1;
            let truth = STOREY_M / storey;
            let r = a.scale.metres_per_pixel / truth;
            self.scale_ok += (1.0 / 1.5..=1.5).contains(&r) as usize;
        }
    }

    /// Adds each ledge's columns (not roof lines') to [`Self::ledge_on`]
    /// by the label (`labels`, `w` wide) at its drip line.
    fn add_ledges_on(&mut self, ledges: &[super::Ledge], labels: &[u8], w: usize) {
        let h = labels.len() / w.max(1);
        for l in ledges.iter().filter(|l| l.kind != LedgeKind::RoofLine) {
            for s in l.polyline.windows(2) {
                let (p, q) = (s[0], s[1]);
                let (x0, x1) = (p[0].max(0.0) as usize, (q[0].max(0.0) as usize).min(w));
                for x in x0..x1 {
                    let t = (x as f32 + 0.5 - p[0]) / (q[0] - p[0]).max(1e-3);
                    let y = (p[1] + t * (q[1] - p[1])).round().max(0.0) as usize;
                    if y < h {
                        self.ledge_on[(labels[y * w + x] as usize).min(6)] += 1;
                    }
                }
            }
        }
    }

    /// Counts glass against the labelled windows (`windows` per photo
    /// pixel, `w` wide), each photo pixel through its analysis pixel.
    fn add_glass(&mut self, a: &Analysis, windows: &[bool], w: usize) {
        let (aw, ah) = (a.analysis_width as usize, a.analysis_height as usize);
        let h = windows.len() / w.max(1);
        for (i, &win) in windows.iter().enumerate() {
            let (x, y) = ((i % w) * aw / w, (i / w) * ah / h.max(1));
            let glass = a.classes[y * aw + x] == super::Class::Glass;
            self.window_px += win as u64;
            self.window_glass += (win && glass) as u64;
            self.glass_px += glass as u64;
        }
    }

    /// Share of labelled window pixels called glass.
    pub fn glass_recall(&self) -> f64 {
        self.window_glass as f64 / self.window_px.max(1) as f64
    }

    /// Share of glass pixels on a labelled window.
    pub fn glass_precision(&self) -> f64 {
        self.window_glass as f64 / self.glass_px.max(1) as f64
    }

    /// Mean wall IoU over the labelled photos.
    pub fn mean_iou(&self) -> f64 {
        self.iou_sum / self.labelled.max(1) as f64
    }

    /// Share of negative pixels called wall.
    pub fn spill(&self) -> f64 {
        self.negatives_wall as f64 / self.negatives.max(1) as f64
    }

    /// Share of sky pixels called wall.
    pub fn sky_spill(&self) -> f64 {
        self.sky_wall as f64 / self.sky.max(1) as f64
    }

    /// Share of labelled "various" pixels called wall (a diagnostic: what
    /// stands before the wall and takes its grime; not in the IoU).
    pub fn various_spill(&self) -> f64 {
        self.various_wall as f64 / self.various.max(1) as f64
    }

    /// Share of labelled ledges found.
    pub fn recall(&self) -> f64 {
        self.bands_found as f64 / self.bands.max(1) as f64
    }

    /// Share of detections on a labelled ledge.
    pub fn precision(&self) -> f64 {
        self.detections_ok as f64 / self.detections.max(1) as f64
    }

    /// Share of detections on any labelled ledge-like element (see
    /// [`Truth::ledge_like`]): lenient, beside the strict [`Self::precision`].
    pub fn lenient_precision(&self) -> f64 {
        self.detections_lenient_ok as f64 / self.detections.max(1) as f64
    }

    /// Share of scale estimates within a factor 1.5.
    pub fn scale_within(&self) -> f64 {
        self.scale_ok as f64 / self.scale_n.max(1) as f64
    }

    /// The metrics as a few lines of text.
    pub fn report(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "images          {}", self.images);
        if self.labelled > 0 {
            let _ = writeln!(s, "wall IoU (mean) {:.3}", self.mean_iou());
            let _ = writeln!(s, "spill           {:.3}", self.spill());
            let _ = writeln!(s, "sky spill       {:.3}", self.sky_spill());
            for (name, &(n, wall)) in NEGATIVE_NAMES.iter().zip(&self.spill_by).skip(3) {
                if n > 0 {
                    let _ = writeln!(
                        s,
                        "  spill {name:10} {:.3} ({wall}/{n} px)",
                        wall as f64 / n as f64
                    );
                }
            }
            if self.various > 0 {
                let _ = writeln!(
                    s,
                    "  spill various    {:.3} ({}/{} px; not in the IoU)",
                    self.various_spill(),
                    self.various_wall,
                    self.various
                );
            }
            // The other half of the IoU: wall called something else.
            for (class, name) in MISS_NAMES {
                let n = self.miss_by[class as usize];
                let _ = writeln!(
                    s,
                    "  miss {name:11} {:.3} ({n}/{} wall px)",
                    n as f64 / self.walls.max(1) as f64,
                    self.walls
                );
            }
        }
        let on: u64 = self.ledge_on.iter().sum();
        if on > 0 {
            let share = |l: u8| self.ledge_on[l as usize] as f64 / on as f64;
            let _ = writeln!(
                s,
                "ledge px on car {:.3} ({}/{on} px; wall {:.3}, vegetation {:.3}, sky {:.3}, ground {:.3})",
                share(CAR),
                self.ledge_on[CAR as usize],
                share(WALL_LABEL),
                share(VEGETATION),
                share(SKY),
                share(GROUND)
            );
        }
        if self.foot.truth > 0 {
            s.push_str(&self.foot.report());
        }
        if self.window_px > 0 {
            let _ = writeln!(
                s,
                "glass recall    {:.3} precision {:.3} (of {} window px)",
                self.glass_recall(),
                self.glass_precision(),
                self.window_px
            );
        }
        if self.bands > 0 {
            let _ = writeln!(
                s,
                "ledge recall    {:.3} ({}/{})",
                self.recall(),
                self.bands_found,
                self.bands
            );
            let _ = writeln!(
                s,
                "ledge precision {:.3} ({}/{})",
                self.precision(),
                self.detections_ok,
                self.detections
            );
            if self.lenient_images > 0 {
                let _ = writeln!(
                    s,
                    "  lenient       {:.3} ({}/{}: on any labelled ledge-like element)",
                    self.lenient_precision(),
                    self.detections_lenient_ok,
                    self.detections
                );
            }
            for kind in KINDS {
                let (n, ok) = self.by_kind[kind as usize];
                if n > 0 {
                    let aside = if kind == LedgeKind::WindowHead {
                        " not in the precisions"
                    } else {
                        ""
                    };
                    let _ = writeln!(
                        s,
                        "  {:14} {:.3} ({ok}/{n}){aside}",
                        kind.label(),
                        ok as f64 / n as f64
                    );
                }
            }
        }
        if self.scale_n > 0 {
            let _ = writeln!(
                s,
                "scale within 1.5x {:.3} ({}/{})",
                self.scale_within(),
                self.scale_ok,
                self.scale_n
            );
        }
        let _ = writeln!(
            s,
            "mean analysis   {:.1} ms",
            self.ms / self.images.max(1) as f64
        );
        s
    }
}

/// Bounding boxes of the 4-connected components of pixels whose label is
/// in `wanted` (e.g. the sills of a label image), ignoring specks under
/// `min_px` pixels.
pub fn components(labels: &[u8], w: usize, h: usize, wanted: &[u8], min_px: usize) -> Vec<Band> {
    let mut seen = vec![false; w * h];
    let mut out = Vec::new();
    let mut stack = Vec::new();
    for s in 0..w * h {
        if seen[s] || !wanted.contains(&labels[s]) {
            continue;
        }
        seen[s] = true;
        stack.push(s);
        let (mut x0, mut y0, mut x1, mut y1, mut n) = (w, h, 0, 0, 0);
        while let Some(i) = stack.pop() {
            let (x, y) = (i % w, i / w);
            (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
            n += 1;
            let mut visit = |j: usize| {
                if !seen[j] && wanted.contains(&labels[j]) {
                    seen[j] = true;
                    stack.push(j);
                }
            };
            neighbours(i, w, h).for_each(&mut visit);
        }
        if n >= min_px {
            out.push(Band {
                x0: x0 as f32,
                y0: y0 as f32,
                x1: x1 as f32 + 1.0,
                y1: y1 as f32 + 1.0,
            });
        }
    }
    out
}

/// Storey height (pixels) from window boxes: for each window, the rise
/// of its top to the nearest window above it that covers at least half
/// the narrower one's width (its column of windows), more than 1.5% of
/// the height up; the median rise, weighted by the windows' widths.
/// [choice: rather than the spacing of all the windows' rows, which
/// halves the storey where two rows of windows interleave: a neighbour's
/// facade at other heights (CMP b0143, b0262), tall and short windows
/// side by side (b0303). On CMP the two differ by more than 1.23x on 68
/// photos; of those looked at, the column rise was the storey seen.
/// Weighted so that a tower's grid of small windows behind (b0103) does
/// not outvote the facade's.]
pub fn storey_from_windows(windows: &[Band], height: f32) -> Option<f32> {
    let mut rises: Vec<(f32, f32)> = windows
        .iter()
        .filter_map(|a| {
            windows
                .iter()
                .filter(|b| {
                    let overlap = a.x1.min(b.x1) - a.x0.max(b.x0);
                    b.y0 < a.y0 - 0.015 * height && overlap >= 0.5 * (a.x1 - a.x0).min(b.x1 - b.x0)
                })
                .map(|b| a.y0 - b.y0)
                .min_by(f32::total_cmp)
                .map(|rise| (rise, a.x1 - a.x0))
        })
        .collect();
    if rises.len() < 2 {
        return None;
    }
    rises.sort_by(|a, b| a.0.total_cmp(&b.0));
    let half = rises.iter().map(|r| r.1).sum::<f32>() / 2.0;
    let mut seen = 0.0;
    rises
        .iter()
        .find(|r| {
            seen += r.1;
            seen >= half
        })
        .map(|r| r.0)
}

#[cfg(test)]
mod tests {
    use super::super::{Ledge, Scale, ScaleSource, Timings};
    use super::*;

    fn analysis(ledges: Vec<Ledge>) -> Analysis {
        Analysis {
            width: 100,
            height: 100,
            analysis_width: 100,
            analysis_height: 100,
            matte: image::GrayImage::new(100, 100),
            classes: Vec::new(),
            wall_fraction: 1.0,
            ledges,
            foot: Vec::new(),
            foot_sure: Vec::new(),
            shelter: Vec::new(),
            scale: Scale {
                metres_per_pixel: 0.01,
                source: ScaleSource::Default,
            },
            timings: Timings::default(),
        }
    }

    #[test]
    fn wall_called_something_else_is_counted_by_its_class() {
        // All wall; the matte takes the left half; on the right the top
        // is called glass, the bottom ground.
        let mut a = analysis(Vec::new());
        a.matte = image::GrayImage::from_fn(100, 100, |x, _| image::Luma([255 * (x < 50) as u8]));
        a.classes = (0..100 * 100)
            .map(|i| match (i % 100 < 50, i / 100 < 50) {
                (true, _) => Class::Wall,
                (false, true) => Class::Glass,
                (false, false) => Class::Ground,
            })
            .collect();
        let t = Truth {
            width: 100,
            height: 100,
            labels: Some(vec![WALL_LABEL; 100 * 100]),
            ..Truth::default()
        };
        let mut m = Metrics::default();
        m.add(Some(&a), &t);
        assert_eq!(m.walls, 10000);
        assert_eq!(m.miss_by, [0, 0, 0, 2500, 2500, 0]);
        let r = m.report();
        assert!(
            r.contains("  miss glass       0.250 (2500/10000 wall px)"),
            "{r}"
        );
        assert!(r.contains("  miss sky         0.000"), "{r}");
    }

    #[test]
    fn various_pixels_called_wall_are_counted_apart_from_the_iou() {
        // All wall by the labels except a "various" block (a person, a
        // sign) over the left quarter; the matte takes the left half.
        let mut a = analysis(Vec::new());
        a.matte = image::GrayImage::from_fn(100, 100, |x, _| image::Luma([255 * (x < 50) as u8]));
        a.classes = vec![Class::Wall; 100 * 100];
        let various: Vec<bool> = (0..100 * 100).map(|i| i % 100 < 25).collect();
        let labels = various
            .iter()
            .map(|&v| if v { IGNORE } else { WALL_LABEL })
            .collect();
        let t = Truth {
            width: 100,
            height: 100,
            labels: Some(labels),
            various: Some(various),
            ..Truth::default()
        };
        let mut m = Metrics::default();
        m.add(Some(&a), &t);
        assert_eq!((m.various, m.various_wall), (2500, 2500));
        assert!((m.mean_iou() - 25.0 / 75.0).abs() < 1e-9);
        let r = m.report();
        assert!(r.contains("  spill various    1.000 (2500/2500 px"), "{r}");
    }

    #[test]
    fn the_lenient_precision_also_counts_other_ledge_like_elements() {
        let at = |y: f32, kind| Ledge {
            kind,
            polyline: vec![[10.0, y], [50.0, y]],
            confidence: 1.0,
        };
        let sill = Band {
            x0: 10.0,
            y0: 20.0,
            x1: 50.0,
            y1: 22.0,
        };
        let moulding = Band {
            y0: 60.0,
            y1: 62.0,
            ..sill
        };
        let t = Truth {
            width: 100,
            height: 100,
            ledges: vec![sill],
            ledge_like: vec![sill, moulding],
            ..Truth::default()
        };
        let a = analysis(vec![
            at(21.0, LedgeKind::Sill),
            at(61.0, LedgeKind::StringCourse),
            at(90.0, LedgeKind::Sill),
            at(61.0, LedgeKind::WindowHead),
        ]);
        let mut m = Metrics::default();
        m.add(Some(&a), &t);
        assert_eq!((m.detections, m.detections_ok), (3, 1));
        assert_eq!(m.detections_lenient_ok, 2);
        assert_eq!(m.by_kind[LedgeKind::WindowHead as usize], (1, 0));
        assert!(m.report().contains("lenient       0.667"), "{}", m.report());
    }

    #[test]
    fn ledges_are_measured_by_the_label_under_their_drip_line() {
        // Wall above row 50, a car below; a ledge at row 30 (40 columns)
        // and one at row 70 (20 columns), a roof line on the car (not
        // counted).
        let at = |y: f32, x1: f32, kind| Ledge {
            kind,
            polyline: vec![[10.0, y], [x1, y]],
            confidence: 1.0,
        };
        let mut a = analysis(vec![
            at(30.0, 50.0, LedgeKind::Sill),
            at(70.0, 30.0, LedgeKind::WindowHead),
            at(80.0, 90.0, LedgeKind::RoofLine),
        ]);
        a.classes = vec![Class::Wall; 100 * 100];
        let t = Truth {
            width: 100,
            height: 100,
            labels: Some(
                (0..100 * 100)
                    .map(|i| if i < 5000 { WALL_LABEL } else { CAR })
                    .collect(),
            ),
            ..Truth::default()
        };
        let mut m = Metrics::default();
        m.add(Some(&a), &t);
        assert_eq!(
            (m.ledge_on[WALL_LABEL as usize], m.ledge_on[CAR as usize]),
            (40, 20)
        );
        assert!(
            m.report().contains("ledge px on car 0.333 (20/60 px"),
            "{}",
            m.report()
        );
    }

    #[test]
    fn the_storey_is_the_rise_within_a_column_of_windows() {
        // Two columns of windows 100 px apart in height, the right one
        // 50 px lower: all the windows' rows are 50 px apart.
        let window = |x0: f32, y0: f32| Band {
            x0,
            y0,
            x1: x0 + 40.0,
            y1: y0 + 60.0,
        };
        let mut windows: Vec<Band> = (0..4)
            .map(|k| window(20.0, 20.0 + 100.0 * k as f32))
            .collect();
        windows.extend((0..4).map(|k| window(200.0, 70.0 + 100.0 * k as f32)));
        assert_eq!(storey_from_windows(&windows, 500.0), Some(100.0));
        // One window alone in its column: no rise.
        assert_eq!(storey_from_windows(&windows[..1], 500.0), None);
    }
}
