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
    /// A `--say` sentence has a word grime does not know.
    #[error("--say: {0}")]
    Say(String),
    /// The output would overwrite an input.
    #[error("{path}: refusing to overwrite an input file; choose another output path")]
    WouldOverwriteInput {
        /// The file involved.
        path: PathBuf,
    },
    /// A preset asks for more work or memory than grime will start, though
    /// each of its values is in range.
    #[error("preset: {need}, over the limit of {limit}; {fix}")]
    TooMuchWork {
        /// What the run would need, e.g. "about 9.4e11 droplet steps".
        need: String,
        /// The limit, in the same unit.
        limit: String,
        /// Which preset fields to change, and how.
        fix: String,
    },
    /// A file named as a photo or mask holds no PNG, JPEG, TIFF or WebP data.
    #[error("{path}: not a PNG, JPEG, TIFF or WebP file ({found}); grime reads only those")]
    NotAnImage {
        /// The file involved.
        path: PathBuf,
        /// What its first bytes look like, e.g. `text` or `unrecognised bytes`.
        found: String,
    },
    /// A real image, but in a format grime does not take as input (GIF, BMP, ...).
    #[error("{path}: {kind} is not a supported input; convert it to PNG, JPEG, TIFF or WebP first")]
    UnsupportedInput {
        /// The file involved.
        path: PathBuf,
        /// The format found, e.g. `a GIF image`.
        kind: String,
    },
    /// The photo's embedded ICC colour profile is too large or not a profile.
    #[error(
        "{path}: its ICC colour profile {reason}; remove the profile (e.g. `exiftool -icc_profile= FILE`) or re-save the photo"
    )]
    BadIcc {
        /// The file involved.
        path: PathBuf,
        /// What is wrong with the profile.
        reason: String,
    },
    /// Ageing the photo would need more memory than the limit allows.
    #[error(
        "{path}: a {width}x{height} photo needs about {needed} of memory to age, over the {limit} limit; raise it with --max-memory {suggest} (or GRIME_MAX_MEMORY={suggest}) or scale the photo down"
    )]
    MemoryLimit {
        /// The photo.
        path: PathBuf,
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
        /// Estimated peak memory, human-readable (e.g. `9.5 GB`).
        needed: String,
        /// The limit, human-readable.
        limit: String,
        /// A limit that would allow this run, e.g. `10G`.
        suggest: String,
    },
    /// An image's region mask (`batch --masks`) does not exist.
    #[error("{image}: its mask {mask} is missing; add the mask there or run without --masks")]
    MaskMissing {
        /// The photo whose mask is missing.
        image: PathBuf,
        /// Where its mask was expected.
        mask: PathBuf,
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
    /// A recipe's input files are not the ones given (`--recipe-from`).
    #[error("{0}")]
    RecipeMismatch(String),
    /// A file holds no grime recipe.
    #[error("{path}: no grime recipe in this file ({reason})")]
    NoRecipe {
        /// The file involved.
        path: PathBuf,
        /// Why none was found.
        reason: String,
    },
    /// Two outputs of one run would be the same file.
    #[error("{path}: both {first} and {second} would write this file; give each its own path")]
    OutputClash {
        /// The file involved.
        path: PathBuf,
        /// What writes it first (e.g. `-o`).
        first: String,
        /// What writes it again (e.g. `--report`).
        second: String,
    },
    /// An output's folder does not exist (checked before any work).
    #[error("{path}: the output folder does not exist; create it or choose another output path")]
    OutputFolderMissing {
        /// The folder.
        path: PathBuf,
    },
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
