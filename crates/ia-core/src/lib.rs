//! Sound interval and revised affine arithmetic for ray tracing implicit
//! surfaces, with **portable outward rounding**: no FPU rounding-mode
//! switches, so the very same code is sound on CPUs, on the GPU (SPIR-V via
//! rust-gpu) and in WASM.
//!
//! ```
//! use boundtrace_ia_core::{Affine, Interval};
//!
//! // f(t) = t² − 2t on t ∈ [0, 2]; the exact range is [−1, 0].
//! let t = Interval::new(0.0f64, 2.0);
//! let ia = t.sqr() - t * 2.0;
//! assert!(ia.lo() <= -1.0 && ia.hi() >= 0.0); // sound, but [−4, 4]: wide
//!
//! let ta = Affine::<f64, 1>::variable(t, 0); // t = 1 + 1·ε₀
//! let aa = (ta.sqr() - ta * 2.0).to_interval();
//! assert!(aa.lo() <= -1.0 && aa.hi() >= 0.0); // sound, and tighter:
//! assert!(aa.width() < ia.width());
//! ```
//!
//! # What is here
//!
//! - [`Real`]: `f32` / `f64` with portable [`Real::next_up`] /
//!   [`Real::next_down`] (bit manipulation).
//! - [`Interval`]: closed intervals, IEEE 1788 set-based semantics
//!   (domain restriction, `EMPTY`, `ENTIRE`, the division case table).
//! - [`Affine`]: revised affine arithmetic (Fryazinov, Pasko and Comninos
//!   2010): a centre, `N` noise-symbol coefficients and one accumulated error
//!   term; rounding errors are added to that term, so forms stay sound.
//! - [`round`]: the outward-rounded basic operations themselves (`add_down`,
//!   `mul_up`, …), for code that builds its own sound bounds (the forward
//!   inclusion functions of `boundtrace-inclusion` do).
//!
//! # Conventions
//!
//! - **Soundness**: every operation encloses the exact real result for all
//!   real inputs in its operands. Basic operations (`+ − × ÷`, `sqr`,
//!   `sqrt`) are at most one float step wider per bound than the tightest
//!   enclosure (on CPUs); `exp`, `ln`, `sin`, `cos`, `pow` are widened by two
//!   steps to cover libm's error (< 1 ulp). Each op's docs state its margin.
//! - **Never panics**: out-of-domain parts are dropped (`sqrt([−1, 4]) =
//!   [0, 2]`); nothing valid left gives `EMPTY`; unbounded results are
//!   `±∞` bounds.
//! - **GPU**: on `target_arch = "spirv"` the division, `sqrt` and libm
//!   margins are widened to the Vulkan precision requirements.
//!
//! # Features
//!
//! - `std` (default): transcendental functions from the standard library.
//! - `libm`: transcendental functions from the `libm` crate (required without
//!   `std`; takes precedence over `std` when both are on).
//!
//! With neither feature the crate refuses to compile, saying which to enable.
#![cfg_attr(not(feature = "std"), no_std)]

#[cfg(not(any(feature = "std", feature = "libm")))]
compile_error!(
    "boundtrace-ia-core needs a source of transcendental functions: enable the `std` feature \
     (default) or, for no_std targets, the `libm` feature"
);

mod affine;
mod interval;
mod math;
mod real;
pub mod round;

pub use affine::Affine;
pub use interval::Interval;
pub use real::Real;
