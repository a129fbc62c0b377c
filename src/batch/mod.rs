//! Ageing a whole folder: discovery, output paths, shards, per-image seeds,
//! and a parallel runner that keeps going when one file is bad.
//!
//! The pieces, in the order `grime batch` uses them:
//!
//! 1. [`plan`] lists the input folder (sorted, extensions matched without
//!    regard to case, optionally recursive), maps every image to its outputs
//!    under the output folder (mirroring sub-folders), keeps the images of
//!    one [`Shard`], and marks those whose outputs all exist as skipped.
//! 2. [`run`] ages the planned images on a rayon pool, at most one image per
//!    pool thread at a time (so memory is bounded by jobs x one image),
//!    and returns a [`Summary`] (serialisable, for `--json`).
//!
//! Every image gets its own seed, [`derive_seed`]`(preset seed, relative
//! path)`, so its output does not depend on which other files run, in what
//! order, or in which shard: `grime run IMAGE --seed <derived>` gives the
//! same bytes.
//!
//! ```
//! use std::path::Path;
//! use grime::batch::{derive_seed, Shard};
//! let s = derive_seed(1, Path::new("north/door.jpg"));
//! assert_eq!(s, derive_seed(1, Path::new("north/door.jpg")));
//! assert_ne!(s, derive_seed(2, Path::new("north/door.jpg")));
//! let shard: Shard = "3/8".parse().unwrap();
//! assert!(shard.contains(2) && shard.contains(10) && !shard.contains(3));
//! ```

mod plan;
mod runner;

pub use plan::{
    Job, ListingError, Options, OutputFormat, Plan, Seeing, Shard, derive_seed, discover,
    is_temp_file, plan, rel_string,
};
pub use runner::{FileReport, Status, Summary, run, sidecar_quad};
