//! Undo and redo. Each edit stores what it changed, before and after: a
//! mask edit only the pixels inside the box it touched, a line, quad or
//! preset edit the small values themselves.

use image::GrayImage;

use super::tools::PixelRect;
use crate::perspective::Quad;
use crate::preset::{Preset, SourceLine};

use super::state::Document;

/// The mask pixels inside a box, before and after an edit.
#[derive(Debug, Clone, PartialEq)]
pub struct MaskPatch {
    /// The box.
    pub rect: PixelRect,
    /// Pixels before, row-major.
    pub before: Vec<u8>,
    /// Pixels after, row-major.
    pub after: Vec<u8>,
}

impl MaskPatch {
    /// The patch between two masks of the same size; `None` if they are equal.
    pub fn diff(before: &GrayImage, after: &GrayImage) -> Option<MaskPatch> {
        let (w, h) = before.dimensions();
        if after.dimensions() != (w, h) {
            return None;
        }
        let (a, b) = (before.as_raw(), after.as_raw());
        let mut rect: Option<PixelRect> = None;
        for y in 0..h as usize {
            let row = y * w as usize..(y + 1) * w as usize;
            let (ra, rb) = (&a[row.clone()], &b[row]);
            let first = ra.iter().zip(rb).position(|(p, q)| p != q);
            let Some(first) = first else { continue };
            let last = ra
                .iter()
                .zip(rb)
                .rposition(|(p, q)| p != q)
                .unwrap_or(first);
            let r = PixelRect {
                x0: first as u32,
                y0: y as u32,
                x1: last as u32 + 1,
                y1: y as u32 + 1,
            };
            rect = Some(rect.map_or(r, |q| q.union(&r)));
        }
        let rect = rect?;
        Some(MaskPatch {
            rect,
            before: crop(before, rect),
            after: crop(after, rect),
        })
    }

    /// Writes the before (`undo`) or after pixels into `mask`.
    pub fn apply(&self, mask: &mut GrayImage, undo: bool) {
        let src = if undo { &self.before } else { &self.after };
        let w = mask.width() as usize;
        let rw = self.rect.width() as usize;
        let raw: &mut [u8] = mask;
        for (i, y) in (self.rect.y0..self.rect.y1).enumerate() {
            let start = y as usize * w + self.rect.x0 as usize;
            raw[start..start + rw].copy_from_slice(&src[i * rw..(i + 1) * rw]);
        }
    }

    fn bytes(&self) -> usize {
        self.before.len() + self.after.len()
    }
}

fn crop(img: &GrayImage, r: PixelRect) -> Vec<u8> {
    let w = img.width() as usize;
    let mut out = Vec::with_capacity((r.width() * r.height()) as usize);
    for y in r.y0..r.y1 {
        let s = y as usize * w + r.x0 as usize;
        out.extend_from_slice(&img.as_raw()[s..s + r.width() as usize]);
    }
    out
}

/// One undoable change to the document.
#[derive(Debug, Clone, PartialEq)]
pub enum Edit {
    /// The wall mask.
    Mask(MaskPatch),
    /// The source lines.
    Lines {
        /// Before.
        before: Vec<SourceLine>,
        /// After.
        after: Vec<SourceLine>,
    },
    /// The perspective quad.
    Quad {
        /// Before.
        before: Option<Quad>,
        /// After.
        after: Option<Quad>,
    },
    /// Parameters. Consecutive edits of the same `key` (one slider drag) can
    /// merge into one.
    Preset {
        /// What was changed, e.g. `rain.k_a`.
        key: String,
        /// Before.
        before: Box<Preset>,
        /// After.
        after: Box<Preset>,
    },
}

/// What an undo or redo touched, so the app knows what to refresh.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Touched {
    /// The mask, inside this box.
    Mask(PixelRect),
    /// The source lines.
    Lines,
    /// The quad.
    Quad,
    /// The preset.
    Preset,
}

impl Edit {
    /// Puts the before (`undo`) or after state into the document.
    pub fn apply(&self, doc: &mut Document, undo: bool) -> Touched {
        match self {
            Edit::Mask(p) => {
                p.apply(&mut doc.mask, undo);
                Touched::Mask(p.rect)
            }
            Edit::Lines { before, after } => {
                doc.lines = if undo { before } else { after }.clone();
                Touched::Lines
            }
            Edit::Quad { before, after } => {
                doc.quad = if undo { *before } else { *after };
                Touched::Quad
            }
            Edit::Preset { before, after, .. } => {
                doc.preset = if undo { before } else { after }.as_ref().clone();
                Touched::Preset
            }
        }
    }

    fn bytes(&self) -> usize {
        match self {
            Edit::Mask(p) => p.bytes(),
            _ => 1024,
        }
    }
}

/// The undo and redo stacks.
#[derive(Debug, Default)]
pub struct History {
    undo: Vec<Edit>,
    redo: Vec<Edit>,
}

/// Mask patches are kept up to this many bytes in total; older edits are
/// forgotten first.
const BUDGET: usize = 512 << 20;
/// At most this many steps.
const MAX_STEPS: usize = 200;

impl History {
    /// Records an edit that has already been applied. With `merge`, a preset
    /// edit of the same key as the last one extends it instead (a slider
    /// being dragged).
    pub fn push(&mut self, edit: Edit, merge: bool) {
        self.redo.clear();
        if merge
            && let (
                Some(Edit::Preset {
                    key: k0, after: a0, ..
                }),
                Edit::Preset { key, after, .. },
            ) = (self.undo.last_mut(), &edit)
            && k0 == key
        {
            *a0 = after.clone();
            return;
        }
        self.undo.push(edit);
        let mut total: usize = self.undo.iter().map(Edit::bytes).sum();
        while (total > BUDGET || self.undo.len() > MAX_STEPS) && self.undo.len() > 1 {
            total -= self.undo.remove(0).bytes();
        }
    }

    /// Undoes the last edit.
    pub fn undo(&mut self, doc: &mut Document) -> Option<Touched> {
        let edit = self.undo.pop()?;
        let t = edit.apply(doc, true);
        self.redo.push(edit);
        Some(t)
    }

    /// Redoes the last undone edit.
    pub fn redo(&mut self, doc: &mut Document) -> Option<Touched> {
        let edit = self.redo.pop()?;
        let t = edit.apply(doc, false);
        self.undo.push(edit);
        Some(t)
    }

    /// True when there is something to undo.
    pub fn can_undo(&self) -> bool {
        !self.undo.is_empty()
    }

    /// True when there is something to redo.
    pub fn can_redo(&self) -> bool {
        !self.redo.is_empty()
    }

    /// Forgets everything (a new document).
    pub fn clear(&mut self) {
        self.undo.clear();
        self.redo.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gui::state::ImageSource;

    fn doc() -> Document {
        Document::new(ImageSource::Demo("facade".into()), 8, 6, Preset::default())
    }

    #[test]
    fn mask_patch_covers_only_the_changed_box_and_round_trips() {
        let mut d = doc();
        let before = d.mask.clone();
        d.mask.put_pixel(2, 1, image::Luma([0]));
        d.mask.put_pixel(4, 3, image::Luma([7]));
        let p = MaskPatch::diff(&before, &d.mask).unwrap();
        assert_eq!(
            p.rect,
            PixelRect {
                x0: 2,
                y0: 1,
                x1: 5,
                y1: 4
            }
        );
        assert_eq!(p.before.len(), 9);
        let after = d.mask.clone();
        let mut h = History::default();
        h.push(Edit::Mask(p), false);
        assert!(matches!(h.undo(&mut d), Some(Touched::Mask(_))));
        assert_eq!(d.mask, before);
        h.redo(&mut d);
        assert_eq!(d.mask, after);
        assert!(MaskPatch::diff(&after, &after).is_none());
    }

    #[test]
    fn slider_drags_merge_and_new_edits_clear_redo() {
        let mut d = doc();
        let mut h = History::default();
        let p0 = d.preset.clone();
        for (i, v) in [0.1, 0.2, 0.3].iter().enumerate() {
            let before = d.preset.clone();
            d.preset.rain.k_a = *v;
            h.push(
                Edit::Preset {
                    key: "rain.k_a".into(),
                    before: Box::new(before),
                    after: Box::new(d.preset.clone()),
                },
                i > 0,
            );
        }
        h.undo(&mut d);
        assert_eq!(d.preset, p0, "one drag is one undo step");
        assert!(h.can_redo());
        h.push(
            Edit::Lines {
                before: vec![],
                after: vec![vec![[0.0, 0.0], [1.0, 0.0]]],
            },
            false,
        );
        assert!(!h.can_redo());
    }
}
