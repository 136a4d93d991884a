//! Implicit-surface fields for boundtrace, each written once and generic
//! over the number type ([`FieldNum`](boundtrace_inclusion::FieldNum)), so
//! the same code gives values, jets, interval/affine ranges and forward
//! linear/quadratic bounds, on the CPU and (compiled to SPIR-V) the GPU.
//!
//! Sign convention (the tracer's): **`f > 0` outside, `f < 0` inside**.
//!
//! | module | contents | source |
//! | --- | --- | --- |
//! | [`kernel`] | compact polynomial, Cauchy, Gaussian, inverse kernels and the extrema of their derivatives | thesis Part II §1.1; forward-inclusion paper App. A |
//! | [`blob`] | point blobs with Taylor bounds | forward-inclusion paper App. A |
//! | [`homothetic`] | segment primitives with linearly varying radius, homothetic distance and its argmin along a ray | thesis eq. 1.11–1.13, Part III §1.3.2 |
//! | [`scalis`] | SCALIS segments in closed form, normalization `g(f) − 1`, per-primitive bounds | thesis eq. 1.14, Part III §1.2, ch. 2 §2.1 |
//! | [`hrbf`] | Hermite RBF (`φ(x) = x³`) evaluation and fitting | thesis eq. 3.17 |
//! | [`density`] | n-ary sum, max/min, Ricci blend of density fields | thesis Part II |
//! | [`sdf`], [`transform`] | approximate SDF primitives with rigid transforms | synchronized-tracing paper §3 |
//! | [`operator`] | CSG, smooth and compact operators with their ranges | synchronized-tracing paper §3–4 |
//! | [`bounding`] | spheres, boxes, sphere-cones | synchronized-tracing paper §4.3 |
//! | [`blobtree`] | flat post-order blobtree, ROI/ABV, sparse traversal, pruned views | synchronized-tracing paper §4–5, §7 |
#![cfg_attr(not(feature = "std"), no_std)]
#![cfg_attr(docsrs, feature(doc_cfg))]

#[cfg(all(not(feature = "std"), not(feature = "libm")))]
compile_error!("boundtrace-fields needs the `std` or the `libm` feature for its math");

#[cfg(feature = "alloc")]
extern crate alloc;

pub mod blob;
pub mod blobtree;
pub mod bounding;
pub mod density;
mod error;
pub mod homothetic;
pub mod hrbf;
pub mod kernel;
pub mod operator;
pub mod scalis;
pub mod sdf;
pub mod transform;

pub use error::FieldError;
