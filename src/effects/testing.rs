//! A [`Context`] for effect tests, built as the pipeline builds it.

use image::{GrayImage, RgbImage};

use super::Context;
use super::region::Region;
use crate::grid::Grid;
use crate::photo::Photo;
use crate::pipeline::Site;

/// Runs `f` with a context over `photo` (whole photo when `mask` is
/// `None`), the site given, an optional normal map and a grid as large as
/// the photo up to `max_side`.
pub fn with<R>(
    photo: &Photo,
    mask: Option<&GrayImage>,
    site: &Site,
    normals: Option<&RgbImage>,
    max_side: u32,
    f: impl FnOnce(&Context) -> R,
) -> R {
    let (w, h) = (photo.width(), photo.height());
    let grid = Grid::new(w, h, mask, max_side).unwrap();
    let luma = grid.luma(photo);
    let region = grid.region(mask);
    let wall = Region::new(w, h, mask).unwrap();
    let ctx = Context {
        grid: &grid,
        luma: &luma,
        region: &region,
        mask,
        wall: &wall,
        normals,
        site,
        photo,
    };
    f(&ctx)
}

/// The demo facade at `w` x `h`, with its site.
pub fn facade<R>(w: u32, h: u32, f: impl FnOnce(&Context) -> R) -> R {
    let d = crate::demo::facade(w, h);
    with(&d.photo, d.region.as_ref(), &d.site, None, 0, f)
}
