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
    match Format::from_path(path)? {
        Format::Psd => psd::write(stack, path),
        Format::Ora => ora::write(stack, path),
        _ => io::save_image(&stack.composite(), stack.base.icc.as_deref(), path),
    }
}
