//! Robust ray tracing of implicit surfaces: every method of the papers,
//! generic over the [`Field`](boundtrace_inclusion::Field) it traces,
//! allocation- and recursion-free per ray so the GPU runs the same code.
//!
//! Conventions: a ray is `o + t·d` ([`Ray`](boundtrace_inclusion::Ray)),
//! traced on a span `[t0, t1]`; the field is **positive outside, negative
//! inside**; a root is reported within `eps` (in `t`) of a true root.
//!
//! ```
//! use boundtrace_fields::{Blobs, Kernel, PointBlob};
//! use boundtrace_inclusion::Ray;
//! use boundtrace_tracer::{Method, Params, first_root};
//!
//! // Two compact blobs blended by summation: f = ½ − Σ k.
//! let k = Kernel::<f64>::compact(6, 1.0)?;
//! let blobs = [
//!     PointBlob::new([-0.4, 0.0, 0.0], 1.0, k)?,
//!     PointBlob::new([0.4, 0.0, 0.0], 1.0, k)?,
//! ];
//! let field = Blobs::new(0.5, blobs)?;
//! let ray = Ray::new([0.0, -3.0, 0.0], [0.0, 1.0, 0.0]);
//! let params = Params::new();
//! let (seg, seg_trace) = first_root(&field, &ray, [0.0, 6.0], Method::Segment, &params);
//! let (quad, quad_trace) = first_root(&field, &ray, [0.0, 6.0], Method::QuadraticTaylor, &params);
//! let (seg, quad) = (seg.unwrap(), quad.unwrap());
//! assert!((seg.t - quad.t).abs() <= 2.0 * params.eps); // the same surface point
//! assert!(quad_trace.stats.steps <= seg_trace.stats.steps); // in fewer steps
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! | module | contents | source |
//! | --- | --- | --- |
//! | [`method`] | [`Method`] (by name), [`Mode`], [`Params`] | — |
//! | [`trace`](mod@trace) | [`trace`](fn@trace), [`first_root`], [`Root`], [`RayStats`], [`normal`] | forward-inclusion paper Alg. 1 |
//! | [`march`] | sphere, segment, forward linear and quadratic marching | Hart 1996; Galin et al. 2020; forward-inclusion paper §4–6 |
//! | [`bisect`] | interval and revised-affine bisection with a fixed stack | Mitchell 1990; Fryazinov et al. 2010 |
//! | [`scalis`] | per-ray primitive lists, `scalis-quadratic`, per-ray Lipschitz sphere tracing, per-primitive interval bisection of SCALIS skeletons | thesis Part III ch. 1–2 |
//! | `slice` (`std`) | inside/outside slice stacks of SCALIS skeletons from all roots along `z` | thesis Part III ch. 2 §2.2 |
//! | [`camera`] | perspective look-at and orthographic cameras | — |
//! | [`pixel`] | one pixel's ray clipped and traced (shared by the CPU renderer and the GPU shader) | — |
//! | `image`, `render` (`alloc`/`std`) | depth, normal, shaded and steps-heatmap images, PNG; (parallel) rendering | forward-inclusion paper Fig. 10 |
//! | `scenes` (`std`) | the standard procedural scenes of the papers | forward-inclusion paper §7; thesis Part III; synchronized-tracing paper Fig. 16 |
//! | `stats` (`std`) | the statistics harness and the dense reference | thesis §1.8 |
//! | [`tiles`] | the tile A-buffer (builder: `alloc`) of blobtree ABVs | synchronized-tracing paper §6.1 |
//! | [`sync`] | synchronized per-tile ray processing with pruned views (no_std, caller buffers) | synchronized-tracing paper §6.2, Alg. 3 |
//! | `sync_render` (`std`) | rendering a blobtree by synchronized tracing, timings | synchronized-tracing paper §6, Fig. 20 |
//! | `tile_programs` (`std`) | one pruned blobtree program per 8 × 8 tile from the A-buffer's tile lists (the GPU's tiled dispatch) and its CPU twin | synchronized-tracing paper §6 |
//!
//! # Features
//! - `std` (default): images, PNG, standard scenes, statistics (implies `alloc`).
//! - `alloc`: heap-allocated helpers; per-ray tracing never allocates.
//! - `libm`: math from the `libm` crate (required without `std`).
//! - `parallel`: multi-threaded rendering and statistics (rayon), with the
//!   same output as single-threaded.
#![cfg_attr(not(feature = "std"), no_std)]
#![cfg_attr(docsrs, feature(doc_cfg))]
// `!(a < b)` is deliberate throughout: it is also true when a value is NaN,
// which must take the safe branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

#[cfg(all(not(feature = "std"), not(feature = "libm")))]
compile_error!("boundtrace-tracer needs the `std` or the `libm` feature for its math");

#[cfg(feature = "alloc")]
extern crate alloc;

// Not used on the GPU (`trace_in` answers `Unsupported` for the bisection
// methods there).
#[cfg_attr(target_arch = "spirv", allow(dead_code))]
pub mod bisect;
pub mod camera;
#[cfg(feature = "alloc")]
pub mod image;
pub mod march;
pub mod method;
pub mod pixel;
#[cfg(feature = "std")]
pub mod render;
pub mod scalis;
#[cfg(feature = "std")]
pub mod scenes;
#[cfg(feature = "std")]
pub mod slice;
#[cfg(feature = "std")]
pub mod stats;
pub mod sync;
#[cfg(feature = "std")]
pub mod sync_render;
#[cfg(feature = "std")]
pub mod tile_programs;
pub mod tiles;
pub mod trace;

pub use camera::Camera;
pub use method::{InvalidParams, Method, Mode, Params, UnknownMethod};
pub use trace::{
    Leg, RayStats, Root, Side, Status, Trace, fill_taylor_cache, first_root, normal, trace,
    trace_in, trace_linear_bottom_up_resume_in, trace_linear_mixed_cached_resume_in,
    trace_linear_mixed_resume_in, trace_linear_taylor_resume_in,
    trace_quadratic_bottom_up_resume_in, trace_quadratic_mixed_cached_resume_in,
    trace_quadratic_mixed_resume_in, trace_quadratic_taylor_resume_in, trace_resume_in,
    trace_segment_lines_resume_in, trace_segment_resume_in, trace_sphere_in,
    trace_sphere_resume_in,
};
