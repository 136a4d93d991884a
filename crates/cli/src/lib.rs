//! The `boundtrace` command's library: the versioned JSON scene format
//! ([`scene_format`]), reachable without the binary (the fuzz target
//! `scene_parse` uses it), and the pieces of the command that are worth
//! testing on their own ([`output`]: atomic writes and the heatmap legend).
//!
//! ```
//! use boundtrace_cli::scene_format::SceneFile;
//! use boundtrace_tracer::scenes::{DEFAULT_SEED, Scene};
//!
//! // Export a standard scene to the file format and read it back.
//! let scene = Scene::<f64>::build("hrbf-8", DEFAULT_SEED)?;
//! let json = SceneFile::from_scene(&scene)?.to_json();
//! let back = SceneFile::parse(&json)?.build::<f64>()?;
//! assert_eq!(format!("{:?}", back.field()), format!("{:?}", scene.field()));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

// `!(a < b)` is deliberate: it is also true when a value is NaN, which
// must take the rejecting branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod output;
pub mod report;
pub mod scene_format;
