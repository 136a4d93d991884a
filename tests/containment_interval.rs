//! Containment of every [`Interval`] operation, for `f32` and `f64`.
//!
//! **What is proven** (per case, for random inputs): for every sample point
//! of the operands that lies in the operation's domain, the *exact* real
//! result lies in the computed interval (IEEE 1788 set-based semantics:
//! `out ⊇ { f(x) : x ∈ operands ∩ domain }`; for division `y = 0` is
//! excluded). Inputs include `±∞`, `EMPTY`, `ENTIRE`, half-unbounded and
//! zero-straddling intervals, signed zeros, subnormals, huge and tiny
//! magnitudes, and anchors such as `ln MAX`, `kπ/2` and `2^(p−3)`. Sample
//! points are the finite endpoints, interior points, reals just inside the
//! endpoints (mostly not floats), `0` and `±2^-3000` around zero, reals
//! beyond the float range in unbounded intervals, and for `sin`/`cos` the
//! critical points `kπ/2` inside the interval. The exact result is enclosed
//! rigorously with `astro-float` (directed rounding, see
//! `tests/common/reference.rs`) and compared exactly:
//! `out.lo ≤ r_lo && r_hi ≤ out.hi`. Set operations (`new`, `point`, `hull`,
//! `intersection`, `contains`, `subset`) and the numeric functions (`width`,
//! `mid`, `rad`, `mag`, `mig`) are checked for the corresponding enclosure
//! property. The plain `#[test]`s run the same checks on fixed edge cases.
//!
//! Each property runs 10 000 cases; for more (or fewer) set `PROPTEST_CASES`:
//!
//! ```text
//! PROPTEST_CASES=200000 cargo test --release --test containment_interval
//! ```
//!
//! A failure prints the operation, the inputs with their bit patterns, the
//! sample point, the exact enclosure and the computed interval; proptest then
//! shrinks it and records it in `tests/containment_interval.proptest-regressions`.

mod common;

use boundtrace::ia_core::{Interval, Real};
use proptest::prelude::*;

use common::check::{Fixed, PLAIN, Picks, binary, in_interval, picks, samples};
use common::interval_props::*;
use common::reference::{self as r};
use common::strategies::{
    float, half_ulp_of_max, interval, pow_exponent, powi_exponent, step, trig_interval,
};
use common::{Flt, config};

/// Intervals that touch or contain zero, with both signs of zero, and a few
/// others, for the fixed tests.
fn edge_intervals<T: Flt>() -> Vec<Interval<T>> {
    let f = T::from_f64;
    let (z, nz, inf, max, sub) = (T::ZERO, -T::ZERO, T::INFINITY, T::MAX, T::MIN_SUBNORMAL);
    let iv = Interval::new;
    vec![
        iv(z, z),
        iv(nz, nz),
        iv(nz, z),
        iv(z, nz),
        iv(z, f(2.0)),
        iv(nz, f(2.0)),
        iv(f(-3.0), z),
        iv(f(-3.0), nz),
        iv(f(-1.0), f(1.0)),
        iv(f(-2.0), f(3.0)),
        iv(f(1.0), f(2.0)),
        iv(f(-2.0), f(-0.5)),
        iv(f(0.5), f(4.0)),
        iv(sub, sub),
        iv(-sub, sub),
        iv(z, sub),
        iv(-sub, z),
        iv(sub, f(1.0)),
        iv(f(1.0), max),
        iv(-max, max),
        iv(max, max),
        iv(-inf, z),
        iv(z, inf),
        iv(-inf, f(-1.0)),
        iv(f(1.0), inf),
        Interval::ENTIRE,
        Interval::EMPTY,
    ]
}

/// Intervals for `sin`/`cos`: wide, huge, around `kπ/2`, at `2^(p−3)`.
fn trig_edges<T: Flt>() -> Vec<Interval<T>> {
    let f = T::from_f64;
    let limit = f(2f64.powi(T::MANTISSA_DIGITS as i32 - 3));
    let mut v = vec![
        Interval::new(f(0.0), f(1e6)),
        Interval::new(f(-1e300), f(1e300)),
        Interval::point(f(1e300)),
        Interval::point(f(1e22)),
        Interval::point(T::MAX),
        Interval::new(-T::MAX, T::MAX),
        Interval::new(limit.next_down(), limit),
        Interval::new(limit, limit.next_up()),
        Interval::new(limit - f(4.0), limit),
        Interval::new(f(0.0), T::PI),
        Interval::new(T::PI, T::PI.next_up()),
        Interval::new(f(1.0), f(2.0)),
        Interval::new(f(-7.0), f(-1.0)),
    ];
    for k in -8..=8 {
        let c = f(f64::from(k) * std::f64::consts::FRAC_PI_2);
        v.push(Interval::new(c.next_down(), c.next_up()));
        v.push(Interval::new(step(c, -3), c));
        v.push(Interval::new(c, step(c, 3)));
        v.push(Interval::point(c));
    }
    for k in [1i64 << 20, (1 << 40) + 1, (1 << 49) - 1] {
        let c = f(k as f64 * std::f64::consts::FRAC_PI_2);
        v.push(Interval::new(c.next_down(), c.next_up()));
        v.push(Interval::new(c - f(1.0), c + f(1.0)));
    }
    v
}

macro_rules! interval_suite {
    ($name:ident, $t:ty) => {
        mod $name {
            use super::*;

            type T = $t;
            type I = Interval<T>;

            proptest! {
                #![proptest_config(config())]

                #[test]
                fn new(a in float::<T>(), b in float::<T>()) {
                    prop_new(a, b)?;
                }

                #[test]
                fn point(x in float::<T>()) {
                    prop_point(x)?;
                }

                #[test]
                fn hull(x in interval::<T>(), y in interval::<T>(), pk in picks()) {
                    prop_hull(x, y, &pk)?;
                }

                #[test]
                fn intersection(x in interval::<T>(), y in interval::<T>(), pk in picks()) {
                    prop_intersection(x, y, &pk)?;
                }

                #[test]
                fn contains(x in interval::<T>()) {
                    prop_contains(x)?;
                }

                #[test]
                fn subset(x in interval::<T>(), y in interval::<T>()) {
                    prop_subset(x, y)?;
                }

                #[test]
                fn width(x in interval::<T>()) {
                    prop_width(x)?;
                }

                #[test]
                fn mid(x in interval::<T>()) {
                    prop_mid(x)?;
                }

                #[test]
                fn rad(x in interval::<T>()) {
                    prop_rad(x)?;
                }

                #[test]
                fn mag(x in interval::<T>(), pk in picks()) {
                    prop_mag(x, &pk)?;
                }

                #[test]
                fn mig(x in interval::<T>(), pk in picks()) {
                    prop_mig(x, &pk)?;
                }

                #[test]
                fn neg(x in interval::<T>(), pk in picks()) {
                    prop_neg(x, &pk)?;
                }

                #[test]
                fn add(x in interval::<T>(), y in interval::<T>(), pk in picks()) {
                    prop_add(x, y, &pk)?;
                }

                #[test]
                fn sub(x in interval::<T>(), y in interval::<T>(), pk in picks()) {
                    prop_sub(x, y, &pk)?;
                }

                #[test]
                fn mul(x in interval::<T>(), y in interval::<T>(), pk in picks()) {
                    prop_mul(x, y, &pk)?;
                }

                #[test]
                fn div(x in interval::<T>(), y in interval::<T>(), pk in picks()) {
                    prop_div(x, y, &pk)?;
                }

                #[test]
                fn scalar_rhs(x in interval::<T>(), s in float::<T>(), pk in picks()) {
                    prop_scalar_rhs(x, s, &pk)?;
                }

                #[test]
                fn scalar_lhs(x in interval::<T>(), s in float::<T>(), pk in picks()) {
                    prop_scalar_lhs(x, s, &pk)?;
                }

                #[test]
                fn recip(x in interval::<T>(), pk in picks()) {
                    prop_recip(x, &pk)?;
                }

                #[test]
                fn sqr(x in interval::<T>(), pk in picks()) {
                    prop_sqr(x, &pk)?;
                }

                #[test]
                fn powi(x in interval::<T>(), n in powi_exponent(), pk in picks()) {
                    prop_powi(x, n, &pk)?;
                }

                #[test]
                fn pow(x in interval::<T>(), e in pow_exponent::<T>(), pk in picks()) {
                    prop_pow(x, e, &pk)?;
                }

                #[test]
                fn sqrt(x in interval::<T>(), pk in picks()) {
                    prop_sqrt(x, &pk)?;
                }

                #[test]
                fn exp(x in interval::<T>(), pk in picks()) {
                    prop_exp(x, &pk)?;
                }

                #[test]
                fn ln(x in interval::<T>(), pk in picks()) {
                    prop_ln(x, &pk)?;
                }

                #[test]
                fn sin(x in trig_interval::<T>(), pk in picks()) {
                    prop_sin(x, &pk)?;
                }

                #[test]
                fn cos(x in trig_interval::<T>(), pk in picks()) {
                    prop_cos(x, &pk)?;
                }

                #[test]
                fn abs(x in interval::<T>(), pk in picks()) {
                    prop_abs(x, &pk)?;
                }

                #[test]
                fn min(x in interval::<T>(), y in interval::<T>(), pk in picks()) {
                    prop_min(x, y, &pk)?;
                }

                #[test]
                fn max(x in interval::<T>(), y in interval::<T>(), pk in picks()) {
                    prop_max(x, y, &pk)?;
                }
            }

            /// Division and `recip` by intervals touching or containing 0.
            #[test]
            fn edge_division_by_zero() {
                let mut fx = Fixed::default();
                let edges = edge_intervals::<T>();
                for pk in &Picks::FIXED {
                    for &y in &edges {
                        fx.check(prop_recip(y, pk));
                        for &x in &edges {
                            fx.check(prop_div(x, y, pk));
                            fx.check(prop_mul(x, y, pk));
                        }
                        for s in [0.0, -0.0, 1.0, -2.5] {
                            fx.check(prop_scalar_rhs(y, s as T, pk));
                            let x = I::point(s as T);
                            fx.check(binary("s / x", x, y, (s as T) / y, pk, r::div));
                        }
                    }
                }
                fx.finish();
            }

            /// `powi` with negative, even and odd exponents, `i32::MIN`,
            /// `i32::MAX` and large ones.
            #[test]
            fn edge_powi() {
                let mut fx = Fixed::default();
                let ns = [
                    i32::MIN,
                    i32::MIN + 1,
                    -(1 << 30),
                    -1001,
                    -100,
                    -4,
                    -3,
                    -2,
                    -1,
                    0,
                    1,
                    2,
                    3,
                    4,
                    100,
                    1001,
                    1 << 30,
                    i32::MAX - 1,
                    i32::MAX,
                ];
                let mut xs = edge_intervals::<T>();
                xs.push(I::new(1.0 - T::EPSILON, 1.0 + T::EPSILON));
                xs.push(I::new(-1.0 - T::EPSILON, -1.0));
                xs.push(I::new(0.999, 1.001));
                for pk in &Picks::FIXED {
                    for &x in &xs {
                        for n in ns {
                            fx.check(prop_powi(x, n, pk));
                        }
                    }
                }
                fx.finish();
            }

            /// `pow` with fractional exponents on intervals touching 0.
            #[test]
            fn edge_pow() {
                let mut fx = Fixed::default();
                let es = [
                    0.5,
                    -0.5,
                    1.5,
                    -1.5,
                    1.0 / 3.0,
                    -1.0 / 3.0,
                    1e-3,
                    -1e-3,
                    2.0,
                    -2.0,
                    0.0,
                    -0.0,
                    2147483647.0,
                    2147483648.0,
                    -2147483649.0,
                    1e10,
                    -1e10,
                    1e30,
                    -1e30,
                    f64::NAN,
                    f64::INFINITY,
                    f64::NEG_INFINITY,
                    1e-40,
                    -1e-300,
                ];
                let mut xs = edge_intervals::<T>();
                xs.push(I::new(0.25, 4.0));
                xs.push(I::new(0.0, 1.0));
                xs.push(I::new(1.0, 1.0));
                xs.push(I::new(1.0 - T::EPSILON, 1.0 + T::EPSILON));
                for pk in &Picks::FIXED {
                    for &x in &xs {
                        for e in es {
                            fx.check(prop_pow(x, e as T, pk));
                        }
                        fx.check(prop_pow(x, T::MIN_SUBNORMAL, pk));
                        fx.check(prop_pow(x, T::MAX, pk));
                        fx.check(prop_sqrt(x, pk));
                    }
                }
                fx.finish();
            }

            /// `sin`/`cos` on wide intervals, huge arguments, around `kπ/2`.
            #[test]
            fn edge_trig() {
                let mut fx = Fixed::default();
                for pk in &Picks::FIXED {
                    for x in trig_edges::<T>().into_iter().chain(edge_intervals::<T>()) {
                        fx.check(prop_sin(x, pk));
                        fx.check(prop_cos(x, pk));
                    }
                }
                // Wide intervals contain both extrema.
                let w = I::new(0.0, 1e6 as T);
                assert!(w.sin().lo() <= -1.0 && w.sin().hi() >= 1.0);
                fx.finish();
            }

            /// `exp` around overflow and underflow, `ln` near 0 and 1.
            #[test]
            fn edge_exp_ln() {
                let mut fx = Fixed::default();
                let big_arg = T::MAX.ln();
                let small_arg = T::MIN_SUBNORMAL.ln();
                let mut xs = edge_intervals::<T>();
                for c in [big_arg, small_arg, T::MIN_POSITIVE.ln(), 1.0, 0.0] {
                    xs.push(I::new(c.next_down(), c.next_up()));
                    xs.push(I::new(c - 1.0, c + 1.0));
                    xs.push(I::point(c));
                }
                xs.push(I::new(1e30 as T, T::INFINITY));
                xs.push(I::new(T::NEG_INFINITY, -1e30 as T));
                xs.push(I::new(1.0 - T::EPSILON, 1.0 + T::EPSILON));
                xs.push(I::new(1.0, 1.0 + T::EPSILON));
                xs.push(I::new(T::ZERO, T::MIN_SUBNORMAL));
                xs.push(I::new(T::ZERO, T::MIN_POSITIVE));
                for pk in &Picks::FIXED {
                    for &x in &xs {
                        fx.check(prop_exp(x, pk));
                        fx.check(prop_ln(x, pk));
                    }
                }
                fx.finish();
            }

            /// Every unary and binary operation on signed zeros and the
            /// other edge intervals.
            #[test]
            fn edge_all_ops() {
                let mut fx = Fixed::default();
                let edges = edge_intervals::<T>();
                for pk in &Picks::FIXED {
                    for &x in &edges {
                        fx.check(prop_neg(x, pk));
                        fx.check(prop_sqr(x, pk));
                        fx.check(prop_sqrt(x, pk));
                        fx.check(prop_abs(x, pk));
                        fx.check(prop_mag(x, pk));
                        fx.check(prop_mig(x, pk));
                        fx.check(prop_width(x));
                        fx.check(prop_mid(x));
                        fx.check(prop_rad(x));
                        fx.check(prop_contains(x));
                        for &y in &edges {
                            fx.check(prop_add(x, y, pk));
                            fx.check(prop_sub(x, y, pk));
                            fx.check(prop_min(x, y, pk));
                            fx.check(prop_max(x, y, pk));
                            fx.check(prop_hull(x, y, pk));
                            fx.check(prop_intersection(x, y, pk));
                            fx.check(prop_subset(x, y));
                        }
                    }
                }
                fx.finish();
            }

            /// Sums and differences whose exact value is a tie just below
            /// the overflow threshold (`MAX − k·ulp/2`, odd `k`): the rounded
            /// sum must still be stepped when needed.
            #[test]
            fn edge_sums_near_overflow() {
                let mut fx = Fixed::default();
                let half = half_ulp_of_max::<T>();
                for pk in &Picks::FIXED {
                    for k in 1..=15 {
                        let a = (k as T) * half;
                        for j in 0..4 {
                            let m = step(T::MAX, -j);
                            for (x, y) in [
                                (I::point(-a), I::point(m)),
                                (I::point(a), I::point(-m)),
                                (I::new(-a, 0.0), I::point(m)),
                                (I::new(0.0, a), I::point(-m)),
                            ] {
                                fx.check(prop_add(x, y, pk));
                                fx.check(prop_add(y, x, pk));
                                fx.check(prop_sub(x, -y, pk));
                                fx.check(prop_sub(-y, x, pk));
                                fx.check(prop_scalar_rhs(x, y.lo(), pk));
                            }
                        }
                    }
                }
                fx.finish();
            }

            /// The sample points of a bounded interval include its ends and
            /// reals strictly inside (a check of the test itself).
            #[test]
            fn samples_cover_the_interval() {
                let x = I::new(1.0, 2.0);
                let s = samples(x, &Picks::FIXED[1], PLAIN);
                assert!(s.len() >= 5);
                assert!(s.iter().all(|v| in_interval(x, v)));
            }
        }
    };
}

interval_suite!(f32_interval, f32);
interval_suite!(f64_interval, f64);
