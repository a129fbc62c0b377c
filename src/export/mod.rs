//! Writing a layer stack: flattened images, a folder of layer PNGs with a
//! manifest, and (see the submodules) layered documents.

pub mod layers_dir;
pub mod ora;
pub mod psd;

use std::path::Path;

use crate::error::Result;
use crate::io::{self, Format};
use crate::stack::Stack;

/// Saves the stack to `path` in the format its extension names: flattened
/// for PNG/JPEG/TIFF/WebP, layered for PSD/ORA. Written atomically.
///
/// # Errors
/// [`crate::Error::UnknownFormat`], I/O and encoding errors.
pub fn save(stack: &Stack, path: &Path) -> Result<()> {
    save_with(stack, path, None)
}

/// [`save`], with `recipe` stored in the file ([`crate::recipe`]).
///
/// # Errors
/// As [`save`].
pub fn save_with(stack: &Stack, path: &Path, recipe: Option<&str>) -> Result<()> {
    let xmp = recipe.map(crate::recipe::embed::xmp);
    match Format::from_path(path)? {
        Format::Psd => psd::write_with(stack, path, xmp.as_deref().map(str::as_bytes)),
        Format::Ora => ora::write_with(stack, path, recipe),
        _ => io::save_image_with(&stack.composite(), stack.base.icc.as_deref(), path, recipe),
    }
}
