//! The library's typed errors. Every message says what was wrong and, where
//! it can, how to fix it; the binary prints it on one line.

use std::path::PathBuf;

/// Everything that can go wrong in grime's library code.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file involved.
        path: PathBuf,
        /// What the operating system said.
        source: std::io::Error,
    },
    /// A file exists but is not an image grime can decode.
    #[error("{path}: cannot decode image ({reason})")]
    Decode {
        /// The file involved.
        path: PathBuf,
        /// What the decoder said.
        reason: String,
    },
    /// The file's extension names no format grime reads or writes.
    #[error(
        "{path}: unknown image extension; use .png, .jpg, .jpeg, .tif, .tiff or .webp (or .psd/.ora for layered output)"
    )]
    UnknownFormat {
        /// The file involved.
        path: PathBuf,
    },
    /// An image is larger than the decoding limits allow.
    #[error(
        "{path}: image is too large to decode safely ({reason}); grime refuses images over {max_pixels} pixels"
    )]
    TooLarge {
        /// The file involved.
        path: PathBuf,
        /// What the decoder said.
        reason: String,
        /// The limit in pixels.
        max_pixels: u64,
    },
    /// Encoding an output image failed.
    #[error("{path}: cannot encode image ({reason})")]
    Encode {
        /// The file involved.
        path: PathBuf,
        /// What the encoder said.
        reason: String,
    },
    /// The region mask does not match the photo.
    #[error(
        "mask is {mask_w}x{mask_h} but the image is {img_w}x{img_h}; the mask must have the image's size"
    )]
    MaskSize {
        /// Mask width.
        mask_w: u32,
        /// Mask height.
        mask_h: u32,
        /// Image width.
        img_w: u32,
        /// Image height.
        img_h: u32,
    },
    /// The normal map does not match the photo.
    #[error(
        "normal map is {map_w}x{map_h} but the image is {img_w}x{img_h}; the normal map must have the image's size"
    )]
    NormalMapSize {
        /// Map width.
        map_w: u32,
        /// Map height.
        map_h: u32,
        /// Image width.
        img_w: u32,
        /// Image height.
        img_h: u32,
    },
    /// The region mask selects no pixel.
    #[error("the region mask is empty: paint some wall (white) into it")]
    EmptyRegion,
    /// A preset value is out of range or of the wrong type.
    #[error("preset: {field} = {value} is out of range; allowed: {range}")]
    OutOfRange {
        /// Dotted field name, e.g. `rain.k_a`.
        field: String,
        /// The offending value.
        value: String,
        /// The allowed range, e.g. `0 ..= 1`.
        range: String,
    },
    /// A preset could not be parsed.
    #[error("preset: {0}")]
    Preset(String),
    /// The output would overwrite an input.
    #[error("{path}: refusing to overwrite an input file; choose another output path")]
    WouldOverwriteInput {
        /// The file involved.
        path: PathBuf,
    },
    /// Scene analysis found (almost) no wall in the photo.
    #[error("no wall found in {name}: use --mask FILE or --region full")]
    NoWall {
        /// The photo's name.
        name: String,
    },
    /// The caller cancelled the run.
    #[error("cancelled")]
    Cancelled,
}

/// Shorthand for results with grime's [`Error`].
pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// Wraps an I/O error with the path it concerns.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            source,
        }
    }
}
