//! Containment of every [`Affine`] operation, for `f32` and `f64`, with
//! `N = 1` and `N = 3` noise symbols.
//!
//! **What is proven** (per case, for random forms): for an operation
//! `z = f(x, y)` and each of three random noise assignments
//! `ε ∈ [−1, 1]^N` (`±1`, `±0`, dyadic, uniform, subnormal components), and
//! for actual values `x_v = x₀ + Σ xᵢεᵢ + δₓ` with `δₓ ∈ {−eₓ, eₓ, t·eₓ}`
//! (`t` a random dyadic in `(−1, 1)`; likewise `y_v`, independently), the
//! *exact* `f(x_v, y_v)` — when `x_v`, `y_v` are in `f`'s domain — lies
//!
//! - in the form `z` at the same `ε`, evaluated exactly:
//!   `z₀ + Σ zᵢεᵢ − e_z ≤ f ≤ z₀ + Σ zᵢεᵢ + e_z`;
//! - in `z.eval(ε)` and in `z.to_interval()`.
//!
//! `ENTIRE` (error term `+∞`) is accepted as containing every real; `EMPTY` is
//! a failure when some value is in the domain. An `ENTIRE` operand stands for
//! `0`, `±1`, `0.75`, `±2^3000` and `±2^-3000`. The exact values are
//! enclosed rigorously with `astro-float` (see `tests/common/reference.rs`).
//! Forms are built with arbitrary finite components (moderate, huge — so that
//! results overflow to `ENTIRE` — tiny, zero), from intervals, as variables,
//! or are `ENTIRE`/`EMPTY`. The constructors are checked to stand for every
//! real of their input, `to_interval`/`radius` and `eval` to enclose the
//! exact range. The plain `#[test]`s run all operations on fixed edge forms.
//!
//! Each property runs 10 000 cases; for more (or fewer) set `PROPTEST_CASES`:
//!
//! ```text
//! PROPTEST_CASES=200000 cargo test --release --test containment_affine
//! ```
//!
//! A failure prints the operation, the operand forms with bit patterns, `ε`,
//! the sample values, the exact enclosure and the result form.

mod common;

use boundtrace::ia_core::{Interval, Real};
use proptest::prelude::*;

use common::affine_props::*;
use common::check::{Fixed, Picks, affine_binary, picks};
use common::reference::{self as r};
use common::strategies::{eps, float, form, interval, raw_form};
use common::{Flt, config};

/// Every unary operation on `x` (for the fixed tests).
fn all_unary<T: Flt, const N: usize>(fx: &mut Fixed, x: A<T, N>, eps: &[[T; N]; 3], pk: &Picks) {
    fx.check(prop_neg(x, eps, pk));
    fx.check(prop_sqr(x, eps, pk));
    fx.check(prop_exp(x, eps, pk));
    fx.check(prop_sqrt(x, eps, pk));
    fx.check(prop_ln(x, eps, pk));
    fx.check(prop_recip(x, eps, pk));
    fx.check(prop_abs(x, eps, pk));
    fx.check(prop_to_interval(x));
    fx.check(prop_eval(x, eps));
}

/// Every binary operation on `x`, `y` (for the fixed tests).
fn all_binary<T: Flt, const N: usize>(
    fx: &mut Fixed,
    x: A<T, N>,
    y: A<T, N>,
    eps: &[[T; N]; 3],
    pk: &Picks,
) {
    fx.check(prop_add(x, y, eps, pk));
    fx.check(prop_sub(x, y, eps, pk));
    fx.check(prop_mul(x, y, eps, pk));
    fx.check(prop_div(x, y, eps, pk));
    fx.check(prop_min(x, y, eps, pk));
    fx.check(prop_max(x, y, eps, pk));
}

/// Edge forms: huge coefficients (overflow), tiny ones, ranges touching or
/// straddling zero, `exp` overflow and underflow, `ENTIRE`, `EMPTY`.
fn edge_forms<T: Flt, const N: usize>() -> Vec<A<T, N>> {
    let f = T::from_f64;
    let iv = Interval::new;
    let huge = T::MAX * f(0.25);
    let tiny = T::MIN_SUBNORMAL;
    let mut v = vec![
        A::constant(T::ZERO),
        A::constant(-T::ZERO),
        A::constant(T::ONE),
        A::constant(T::MAX),
        A::constant(tiny),
        A::constant(-f(2.5)),
        A::variable(iv(T::ZERO, T::ONE), 0),
        A::variable(iv(-T::ONE, T::ONE), 0),
        A::variable(iv(f(1.0), f(800.0)), 0),
        A::variable(iv(f(-800.0), f(-700.0)), 0),
        A::variable(iv(f(80.0), f(90.0)), N - 1),
        A::variable(iv(f(-3.0), f(-1.0)), 0),
        A::variable(iv(f(1.0), f(3.0)), N),
        A::variable(iv(T::ZERO, tiny), 0),
        A::variable(iv(-huge, huge), 0),
        A::from_interval(iv(T::ZERO, f(2.0))),
        A::from_interval(iv(-tiny, tiny)),
        raw_form(T::ONE, [T::ONE; N], T::ZERO),
        raw_form(T::ZERO, [T::ONE; N], T::ZERO),
        raw_form(f(N as f64), [T::ONE; N], T::ZERO),
        raw_form(huge, [huge; N], huge),
        raw_form(huge, [-huge; N], T::ZERO),
        raw_form(-huge, [huge; N], f(1.0)),
        raw_form(f(1e-3), [tiny; N], tiny),
        raw_form(f(2.0), [f(-0.5); N], f(0.25)),
        raw_form(T::MAX, [T::MAX; N], T::MAX),
        A::ENTIRE,
        A::EMPTY,
    ];
    let mut c = [T::ZERO; N];
    c[N - 1] = f(1e30);
    v.push(raw_form(f(1e30), c, f(1e20)));
    v
}

/// Fixed noise assignments: all `+1`, all `−1`, and interior values.
fn edge_eps<T: Flt, const N: usize>() -> [[T; N]; 3] {
    let mut inner = [T::HALF; N];
    inner[0] = T::from_f64(0.0625);
    [[T::ONE; N], [-T::ONE; N], inner]
}

macro_rules! affine_suite {
    ($name:ident, $t:ty, $n:literal) => {
        mod $name {
            use super::*;

            type T = $t;
            const N: usize = $n;

            /// Any form.
            fn f() -> BoxedStrategy<A<T, N>> {
                form::<T, N>()
            }

            /// Three noise assignments.
            fn ep() -> BoxedStrategy<[[T; N]; 3]> {
                eps::<T, N>()
            }

            proptest! {
                #![proptest_config(config())]

                #[test]
                fn constant(c in float::<T>(), e in ep()) {
                    prop_constant::<T, N>(c, &e)?;
                }

                #[test]
                fn from_interval(iv in interval::<T>(), e in ep(), pk in picks()) {
                    prop_from_interval::<T, N>(iv, &e, &pk)?;
                }

                #[test]
                fn variable(
                    iv in interval::<T>(),
                    k in 0..=N,
                    e in ep(),
                    pk in picks(),
                ) {
                    prop_variable::<T, N>(iv, k, &e, &pk)?;
                }

                #[test]
                fn to_interval(x in f()) {
                    prop_to_interval(x)?;
                }

                #[test]
                fn eval(x in f(), e in ep()) {
                    prop_eval(x, &e)?;
                }

                #[test]
                fn neg(x in f(), e in ep(), pk in picks()) {
                    prop_neg(x, &e, &pk)?;
                }

                #[test]
                fn add(x in f(), y in f(), e in ep(), pk in picks()) {
                    prop_add(x, y, &e, &pk)?;
                }

                #[test]
                fn sub(x in f(), y in f(), e in ep(), pk in picks()) {
                    prop_sub(x, y, &e, &pk)?;
                }

                #[test]
                fn mul(x in f(), y in f(), e in ep(), pk in picks()) {
                    prop_mul(x, y, &e, &pk)?;
                }

                #[test]
                fn div(x in f(), y in f(), e in ep(), pk in picks()) {
                    prop_div(x, y, &e, &pk)?;
                }

                #[test]
                fn min(x in f(), y in f(), e in ep(), pk in picks()) {
                    prop_min(x, y, &e, &pk)?;
                }

                #[test]
                fn max(x in f(), y in f(), e in ep(), pk in picks()) {
                    prop_max(x, y, &e, &pk)?;
                }

                #[test]
                fn scalar_rhs(x in f(), s in float::<T>(), e in ep(), pk in picks()) {
                    prop_scalar_rhs(x, s, &e, &pk)?;
                }

                #[test]
                fn scalar_lhs(x in f(), s in float::<T>(), e in ep(), pk in picks()) {
                    prop_scalar_lhs(x, s, &e, &pk)?;
                }

                #[test]
                fn sqr(x in f(), e in ep(), pk in picks()) {
                    prop_sqr(x, &e, &pk)?;
                }

                #[test]
                fn exp(x in f(), e in ep(), pk in picks()) {
                    prop_exp(x, &e, &pk)?;
                }

                #[test]
                fn sqrt(x in f(), e in ep(), pk in picks()) {
                    prop_sqrt(x, &e, &pk)?;
                }

                #[test]
                fn ln(x in f(), e in ep(), pk in picks()) {
                    prop_ln(x, &e, &pk)?;
                }

                #[test]
                fn recip(x in f(), e in ep(), pk in picks()) {
                    prop_recip(x, &e, &pk)?;
                }

                #[test]
                fn abs(x in f(), e in ep(), pk in picks()) {
                    prop_abs(x, &e, &pk)?;
                }
            }

            /// All operations on the edge forms (huge coefficients that
            /// overflow to `ENTIRE`, ranges touching zero, ...), pairwise.
            #[test]
            fn edge_forms_all_ops() {
                let mut fx = Fixed::default();
                let forms = edge_forms::<T, N>();
                let e = edge_eps::<T, N>();
                for pk in &Picks::FIXED {
                    for &x in &forms {
                        all_unary(&mut fx, x, &e, pk);
                        for s in [0.0, -0.0, 1.0, -2.5, 1e30, f64::INFINITY, f64::NAN] {
                            let s = s as T;
                            fx.check(prop_scalar_rhs(x, s, &e, pk));
                            let c = A::<T, N>::constant(s);
                            fx.check(affine_binary("s / x", &c, &x, &(s / x), &e, pk, r::div));
                            fx.check(affine_binary(
                                "s - x",
                                &c,
                                &x,
                                &(s - x),
                                &e,
                                pk,
                                |a, b, p| Some(r::sub(a, b, p)),
                            ));
                        }
                        for &y in &forms {
                            all_binary(&mut fx, x, y, &e, pk);
                        }
                    }
                }
                fx.finish();
            }

            /// Constructors on edge intervals.
            #[test]
            fn edge_constructors() {
                let mut fx = Fixed::default();
                let e = edge_eps::<T, N>();
                let f = <T as Real>::from_f64;
                let ivs = [
                    Interval::new(T::ZERO, T::ZERO),
                    Interval::new(-T::MAX, T::MAX),
                    Interval::new(T::MAX, T::MAX),
                    Interval::new(T::MIN_SUBNORMAL, f(1.0)),
                    Interval::new(f(-1e30), f(1e-30)),
                    Interval::new(f(1.0), T::INFINITY),
                    Interval::ENTIRE,
                    Interval::EMPTY,
                ];
                for pk in &Picks::FIXED {
                    for iv in ivs {
                        fx.check(prop_from_interval::<T, N>(iv, &e, pk));
                        for k in 0..=N {
                            fx.check(prop_variable::<T, N>(iv, k, &e, pk));
                        }
                        fx.check(prop_constant::<T, N>(iv.lo(), &e));
                    }
                }
                fx.finish();
            }

            /// Huge coefficients overflow to `ENTIRE`, which contains everything.
            #[test]
            fn overflow_gives_entire() {
                let big_form = raw_form::<T, N>(T::MAX * 0.5, [T::MAX * 0.5; N], T::ZERO);
                assert!((big_form * big_form).is_entire());
                assert!((big_form * 4.0).is_entire());
                let mut fx = Fixed::default();
                let e = edge_eps::<T, N>();
                for pk in &Picks::FIXED {
                    all_unary(&mut fx, big_form, &e, pk);
                    all_binary(&mut fx, big_form, big_form, &e, pk);
                }
                fx.finish();
            }
        }
    };
}

affine_suite!(f32_n1, f32, 1);
affine_suite!(f32_n3, f32, 3);
affine_suite!(f64_n1, f64, 1);
affine_suite!(f64_n3, f64, 3);
