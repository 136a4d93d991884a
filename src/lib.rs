//! boundtrace: sound, fast ray tracing of implicit surfaces.
//!
//! This facade re-exports the crates of the family; depend on it, or on a
//! single crate (e.g. `boundtrace-ia-core`) for a smaller build.
//!
//! ```
//! use boundtrace::ia_core::{Affine, Interval};
//!
//! let t = Interval::new(0.0f64, 1.0);
//! let f = t.sqr() - t; // t² − t on [0, 1]: exact range [−¼, 0]
//! assert!(f.contains(-0.25) && f.contains(0.0));
//! let fa = Affine::<f64, 1>::variable(t, 0);
//! assert!((fa.sqr() - fa).to_interval().contains(-0.25));
//! ```
//!
//! | module | crate | what |
//! | --- | --- | --- |
//! | [`ia_core`] | `boundtrace-ia-core` | [`Real`](ia_core::Real), [`Interval`](ia_core::Interval), [`Affine`](ia_core::Affine) with portable outward rounding |
//! | [`inclusion`] | `boundtrace-inclusion` | [`ForwardLinear`](inclusion::ForwardLinear), [`ForwardQuadratic`](inclusion::ForwardQuadratic), [`Jet`](inclusion::Jet), [`FieldNum`](inclusion::FieldNum), [`Field`](inclusion::Field) |
//! | [`fields`] | `boundtrace-fields` | kernels, blobs, SCALIS segments, HRBF, SDF primitives, operators, flat blobtrees |
//! | [`tracer`] | `boundtrace-tracer` | sphere/segment/forward marching, interval/affine bisection, opaque and transparent modes, statistics, cameras, images, standard scenes |
#![cfg_attr(not(feature = "std"), no_std)]

pub use boundtrace_fields as fields;
pub use boundtrace_ia_core as ia_core;
pub use boundtrace_inclusion as inclusion;
pub use boundtrace_tracer as tracer;

/// The README's code blocks, compiled and run as doc tests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
