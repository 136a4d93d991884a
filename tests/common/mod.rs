//! Shared code of the containment property tests (`containment_interval`,
//! `containment_affine`).
//!
//! - [`reference`]: exact reals and proven enclosures of exact results in
//!   arbitrary precision (`astro-float`, directed rounding);
//! - [`strategies`]: proptest strategies for floats (infinities, signed
//!   zeros, subnormals, huge values, anchors such as `ln MAX` and `kπ/2`),
//!   intervals and affine forms;
//! - [`shapes`]: analytic fields with known roots (the tracer tests);
//! - [`interval_props`], [`affine_props`]: one containment check per
//!   operation on given operands (also called by the fuzz targets in `fuzz/`);
//! - [`forward`]: forward-bound checks on random expression trees (the
//!   `forward_bounds` tests and fuzz target);
//! - [`blobtree`]: random flat blobtrees and their property checks (the
//!   `blobtree` tests and fuzz targets);
//! - [`check`]: sample points of intervals and affine forms (endpoints,
//!   interior points, non-float reals next to endpoints and zero, reals beyond
//!   the float range in unbounded intervals, critical points of `sin`/`cos`)
//!   and the containment assertions.
//!
//! Not every test file uses every item.
#![allow(dead_code)]

pub mod affine_props;
pub mod blobtree;
pub mod check;
pub mod forward;
pub mod interval_props;
pub mod kernel_cases;
pub mod reference;
pub mod scalis_cases;
pub mod shapes;
pub mod strategies;

use std::fmt::{Debug, Display, LowerExp};

use boundtrace::ia_core::{Affine, Interval, Real};
use proptest::test_runner::{Config, FileFailurePersistence, contextualize_config};

/// Cases per property unless `PROPTEST_CASES` says otherwise.
pub const DEFAULT_CASES: u32 = 10_000;

/// The proptest configuration of every property: [`DEFAULT_CASES`] cases,
/// overridden by the `PROPTEST_CASES` environment variable (and the other
/// `PROPTEST_*` variables).
///
/// proptest 1.12 applies the environment in `Config::default()` and again in
/// the `proptest!` macro; an explicit `cases` would hide it from
/// `Config::default()`, so it is re-applied here with `contextualize_config`
/// (which does not rely on the macro doing it).
///
/// Failing cases are saved next to the test file
/// (`tests/<name>.proptest-regressions`) and replayed first on later runs.
pub fn config() -> Config {
    contextualize_config(Config {
        cases: DEFAULT_CASES,
        failure_persistence: Some(Box::new(FileFailurePersistence::WithSource(
            "proptest-regressions",
        ))),
        ..Config::default()
    })
}

/// The float types under test: [`Real`] plus what the tests need.
pub trait Flt: Real + Debug + Display + LowerExp + Send + Sync {
    /// `"f32"` or `"f64"`.
    const NAME: &'static str;
    /// The bit pattern, zero-extended.
    fn to_bits64(self) -> u64;
    /// From a bit pattern (truncated to the type's width).
    fn from_bits64(bits: u64) -> Self;
}

impl Flt for f32 {
    const NAME: &'static str = "f32";
    fn to_bits64(self) -> u64 {
        u64::from(self.to_bits())
    }
    fn from_bits64(bits: u64) -> Self {
        f32::from_bits(bits as u32)
    }
}

impl Flt for f64 {
    const NAME: &'static str = "f64";
    fn to_bits64(self) -> u64 {
        self.to_bits()
    }
    fn from_bits64(bits: u64) -> Self {
        f64::from_bits(bits)
    }
}

/// A float as `value (bits)`, e.g. `1e0 (0x3ff0000000000000)`.
pub fn show_f<T: Flt>(x: T) -> String {
    let digits = if T::MANTISSA_DIGITS == 24 { 8 } else { 16 };
    format!("{x:e} (0x{:0digits$x})", x.to_bits64())
}

/// An interval with its bit patterns.
pub fn show_iv<T: Flt>(x: Interval<T>) -> String {
    if x.is_empty() {
        return "EMPTY".into();
    }
    format!("[{}, {}]", show_f(x.lo()), show_f(x.hi()))
}

/// An affine form with its bit patterns.
pub fn show_af<T: Flt, const N: usize>(x: &Affine<T, N>) -> String {
    if x.is_empty() {
        return "EMPTY".into();
    }
    if x.is_entire() {
        return "ENTIRE".into();
    }
    let coeffs: Vec<String> = x.coeffs().iter().map(|&c| show_f(c)).collect();
    format!(
        "{{ center: {}, coeffs: [{}], err: {} }}",
        show_f(x.center()),
        coeffs.join(", "),
        show_f(x.err())
    )
}
