//! Implicit-surface fields for boundtrace, each written once and generic
//! over the number type ([`FieldNum`](boundtrace_inclusion::FieldNum)), so
//! the same code gives values, jets, interval/affine ranges and forward
//! linear/quadratic bounds, on the CPU and (compiled to SPIR-V) the GPU.
//!
//! Sign convention (the tracer's): **`f > 0` outside, `f < 0` inside**;
//! density fields are exposed as `iso − density`.
//!
//! ```
//! use boundtrace_fields::blobtree::{FlatBlobtree, Node};
//! use boundtrace_fields::{Operator, Primitive};
//! use boundtrace_ia_core::Interval;
//! use boundtrace_inclusion::{Field, ForwardQuadratic, Ray};
//!
//! // Two spheres blended by the compact smooth union G∪ (β = 0.2).
//! let a = Primitive::sphere([-0.5, 0.0, 0.0], 0.6)?;
//! let b = Primitive::sphere([0.5, 0.0, 0.0], 0.6)?;
//! let op = Operator::compact_union(0.2, Operator::default_r_o(0.2))?;
//! let tree = Node::op(op, Node::primitive(a), Node::primitive(b));
//!
//! // The flat post-order encoding is what CPU and GPU evaluate.
//! let flat = FlatBlobtree::from_node(&tree)?;
//! let scene = flat.as_ref();
//!
//! // A ray along x: a value, a sound range, a forward bound and its step.
//! let ray = Ray::new([-3.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
//! let f0: f64 = scene.eval(ray.at(0.0, 0.0));
//! assert!((f0 - 1.9).abs() < 1e-6); // 3 − 0.5 − 0.6, the blend is local
//! let range: Interval<f64> = scene.eval(ray.at(0.0, 1.0));
//! assert!(range.lo() > 0.0); // no surface for t ∈ [0, 1]
//! let bound: ForwardQuadratic<f64> = scene.eval(ray.at(0.0, 3.0));
//! assert!(bound.safe_step() <= 1.9 + 1e-9); // never passes the surface at t = 1.9
//! # Ok::<(), boundtrace_fields::FieldError>(())
//! ```
//!
//! | module | contents | source |
//! | --- | --- | --- |
//! | [`kernel`] | compact polynomial, Cauchy, Gaussian, inverse kernels and the extrema of their derivatives | thesis Part II §1.1; forward-inclusion paper App. A |
//! | [`blob`] | point blobs with Taylor bounds | forward-inclusion paper App. A |
//! | [`homothetic`] | segment primitives with linearly varying radius, homothetic distance and its argmin along a ray | thesis eq. 1.11–1.13, Part III §1.3.2 |
//! | [`homothetic_skeleton`] | sums of homothetic-distance primitives `k ∘ h_S` over a skeleton, with Lipschitz and directional bounds | thesis eq. 1.13, Part III §1.8 |
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
pub mod homothetic_skeleton;
pub mod hrbf;
pub mod kernel;
pub mod operator;
pub mod scalis;
pub mod sdf;
pub mod transform;

pub use blob::{Blobs, PointBlob};

/// `0` in the number type of `x`, with `x`'s validity interval for the
/// forward types (`x·0`); a plain constant when `x` is unbounded (where
/// `x·0` would be NaN for floats).
#[inline]
pub(crate) fn zero_like<T: boundtrace_ia_core::Real, N: boundtrace_inclusion::FieldNum<T>>(
    x: &N,
) -> N {
    if x.enclosure().is_bounded() {
        *x * T::ZERO
    } else {
        N::constant(T::ZERO)
    }
}
pub use error::FieldError;
pub use kernel::{Kernel, KernelKind};
pub use operator::{Operator, OperatorClass, OperatorKind};
pub use sdf::{AlgebraicPrimitives, AllPrimitives, Primitive, PrimitiveKind, PrimitiveKinds};
pub use transform::Rigid;
