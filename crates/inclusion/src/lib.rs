//! Forward linear and quadratic inclusion functions for ray tracing implicit
//! surfaces (Aydinlilar and Zanni, *Forward inclusion functions for
//! ray-tracing implicit surfaces*, 2023), second-order jets, and the generic
//! [`Field`] trait that every field of boundtrace implements once for all
//! number types.
//!
//! ```
//! use boundtrace_inclusion::{Field, FieldNum, ForwardLinear, ForwardQuadratic, Ray};
//!
//! /// A Gaussian blob: f = 0.5 − e^{−|p|²} (positive outside).
//! struct Blob;
//! impl Field<f64> for Blob {
//!     fn eval<N: FieldNum<f64>>(&self, p: [N; 3]) -> N {
//!         -(-(p[0].sqr() + p[1].sqr() + p[2].sqr())).exp() + 0.5
//!     }
//! }
//!
//! // March a ray with quadratic bounds (paper Alg. 1, k = 2).
//! let ray = Ray::new([-3.0, 0.2, 0.0], [1.0, 0.0, 0.0]);
//! let (mut t, mut len) = (0.0, 0.5);
//! let hit = loop {
//!     let b: ForwardQuadratic<f64> = Blob.eval(ray.at(t, t + len));
//!     if b.start().hi() < 1e-9 { break Some(t); } // within ε of the surface
//!     let step = b.safe_step(); // never passes the first root
//!     t += step;
//!     len = 2.0 * step.max(1e-9);
//!     if t > 6.0 { break None; }
//! };
//! let t_hit = hit.unwrap();
//! let exact = 3.0 - (2f64.ln() - 0.04).sqrt();
//! assert!(t_hit <= exact && exact - t_hit < 1e-8);
//!
//! // The same field as a linear bound and as plain floats.
//! let l: ForwardLinear<f64> = Blob.eval(ray.at(0.0, 1.0));
//! assert!(l.start().contains(Blob.eval(ray.at::<f64>(0.0, 0.0))));
//! ```
//!
//! # What is here
//!
//! - [`ForwardLinear`], [`ForwardQuadratic`]: bounds `f₋ ≤ f ≤ f₊` on
//!   `[t₀, t₀ + h]` that are exact at `t₀`, asymmetric, with a validity
//!   length `h` (paper §4–6); bottom-up rules for `+ − × ÷`, `sqr`, `powi`,
//!   `powf`, `sqrt`, `recip`, `exp`, `ln`, `sin`, `cos`, `abs`, `min`,
//!   `max`, and `join` (the hull of two bounds, for undecided branches); Taylor
//!   constructors (§5.1, §6.1); "mixed" ([`ForwardQuadratic::tighter`]);
//!   root finding for safe marching steps ([`ForwardQuadratic::safe_step`]).
//! - [`Composition`]: the three App. B variants (Fig. 21 a–c).
//! - [`Jet`]: value, first and second derivative (forward mode).
//! - [`FieldNum`]: the one arithmetic trait implemented by `f32`/`f64`,
//!   [`Jet`], [`Interval`](boundtrace_ia_core::Interval),
//!   [`Affine`](boundtrace_ia_core::Affine) and the forward types, with
//!   [`enclosure`](FieldNum::enclosure) and [`join`](FieldNum::join) so
//!   fields can decide (or keep both of) piecewise branches soundly.
//! - [`Field`], [`Ray`], and helpers ([`gradient`], [`linear_bound`],
//!   [`quadratic_bound`]).
//!
//! # Soundness and the margin at `t₀`
//!
//! In exact arithmetic a forward bound satisfies `f₋(t₀) = f(t₀) = f₊(t₀)`.
//! In floating point, `f(t₀)` itself is not representable, so each bound
//! carries a start *enclosure* `[s₋, s₊] ∋ f(t₀)`: the **margin** is its
//! width. The start values are computed with the same outward-rounded rules
//! as [`Interval`](boundtrace_ia_core::Interval) at the point `t₀` (sums and
//! products of the sides' start values, `φ` of the start values), so the
//! margin is the rounding error of interval arithmetic at `t₀`: a few float
//! steps per operation. The property tests enforce
//! `s₊ − s₋ ≤ 4·w + 2·n·ε·M`, with `w` the width of the `Interval`
//! evaluation at `[t₀, t₀]`, `n` the number of operations and `M` the
//! largest intermediate magnitude — or, where the point enclosure is itself
//! wide and a later operation amplifies a one-step difference past that
//! (`exp` of a width-100 argument), that every operation's start is within
//! `8·ε·M` of the `Interval` rule applied to its arguments' starts. Two
//! documented relaxations are exempt:
//! [`Composition::RelaxStart`] (the chord side starts at the chord) and
//! `sqrt`/`powf(p < 1)` of an input whose upper start is exactly `0` (no
//! finite slope is exact there). Coefficients are rounded outward (lower
//! side down, upper side up — valid because `τ = t − t₀ ≥ 0`), so the
//! bounds `[s₋ + τ(a₋ + b₋τ), s₊ + τ(a₊ + b₊τ)]` contain `f(t₀ + τ)` for all
//! real `τ ∈ [0, h]` where `f` is defined, and
//! [`bounds_at`](ForwardQuadratic::bounds_at) rounds their evaluation
//! outward too. The property tests in `tests/forward_bounds.rs` check all of
//! this against a higher-precision reference on random expression trees.
//!
//! `h > 0` whenever the bound is defined at `t₀` and no coefficient
//! overflowed (e.g. `f32` values beyond `10³⁸`; an infinite slope cannot be
//! marched on); `h = +∞` for an expression that does not use the ray
//! parameter.
//!
//! # Cost
//!
//! Forward bounds do much more work per operation than intervals (measured
//! with `cargo bench --bench inclusion_fields`: a Gaussian blob is about 10×
//! the interval cost, a compact blob about 40×); the papers' point is that
//! far fewer marching steps are needed. [`ForwardLinear`] computes sums,
//! scalar operations and products on lines directly and reuses the quadratic
//! rules (folded back to lines) for the others.
//!
//! # Features
//!
//! - `std` (default) / `libm`: where transcendental functions come from
//!   (see `boundtrace-ia-core`); one of them is required.
#![cfg_attr(not(feature = "std"), no_std)]
// `!(x >= 0)` is deliberate throughout: it is true for NaN, which must take
// the conservative branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod compose;
mod field;
mod jet;
mod linear;
mod num;
mod poly;
mod quadratic;

pub use compose::Composition;
pub use field::{BoundKind, Field, Ray, gradient, jet_at, linear_bound, quadratic_bound, value_at};
pub use jet::Jet;
pub use linear::ForwardLinear;
pub use num::FieldNum;
pub use quadratic::ForwardQuadratic;
