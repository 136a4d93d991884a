//! Containment of the Taylor constructors ([`ForwardLinear::taylor`],
//! [`ForwardLinear::lipschitz`], [`ForwardQuadratic::taylor`]) and of the
//! "mixed" bounds ([`ForwardLinear::tighter`], [`ForwardQuadratic::tighter`])
//! for `f32` and `f64`.
//!
//! Each case draws a random polynomial of degree 4 (so `f`, `f'`, `f''` are
//! known exactly), a ray interval `[t0, t1]`, builds the Taylor bounds from
//! `Interval` enclosures of `f(t0)`, `f'(t0)`, `f'` and `f''` over the
//! interval, the bottom-up bounds from the generic evaluation, and their
//! mixes. At 33 points `τ = h·k/32` (exact reals) the exact value
//! `f(t0 + τ)` (computed without rounding) must lie between the bounds
//! (evaluated exactly), and the reference must keep the start's sign before
//! every bound's safe step. 10 000 cases per float type
//! (`PROPTEST_CASES` overrides).

mod common;

use astro_float::BigFloat;
use boundtrace::ia_core::Interval;
use boundtrace::inclusion::{FieldNum, ForwardLinear, ForwardQuadratic};
use proptest::prelude::*;
use proptest::test_runner::{TestCaseError, TestRunner};

use common::Flt;
use common::reference::{self as r, add_exact, big, mul_exact};

/// `Σ c_k t^k` by Horner's rule in any number type.
fn poly<T: Flt, N: FieldNum<T>>(c: &[T], t: N) -> N {
    let mut acc = N::constant(c[c.len() - 1]);
    for k in (0..c.len() - 1).rev() {
        acc = acc * t + c[k];
    }
    acc
}

/// The coefficients of the derivative.
fn deriv<T: Flt>(c: &[T]) -> Vec<T> {
    (1..c.len())
        .map(|k| c[k] * T::from_f64(k as f64)) // k ≤ 4: exact
        .collect()
}

/// The exact value `Σ c_k t^k` at an exact real `t`.
fn exact_poly<T: Flt>(c: &[T], t: &BigFloat) -> BigFloat {
    let mut acc = big(c[c.len() - 1]);
    for k in (0..c.len() - 1).rev() {
        acc = add_exact(&mul_exact(&acc, t), &big(c[k]));
    }
    acc
}

/// The exact value of `s + τ(a + bτ)` (the bounds' coefficients are finite
/// here: the polynomials are small).
fn side_exact(s: f64, a: f64, b: f64, tau: &BigFloat) -> BigFloat {
    let inner = add_exact(&r::from_f64(a), &mul_exact(&r::from_f64(b), tau));
    add_exact(&r::from_f64(s), &mul_exact(tau, &inner))
}

/// A bound seen through its parts: start, lower `(a, b)`, upper `(a, b)`,
/// validity, safe step.
struct Parts {
    name: &'static str,
    start: (f64, f64),
    lo: (f64, f64),
    hi: (f64, f64),
    h: f64,
    step: f64,
}

fn lin<T: Flt>(name: &'static str, b: ForwardLinear<T>) -> Parts {
    let [l, u] = b.slopes();
    Parts {
        name,
        start: (b.start().lo().as_f64(), b.start().hi().as_f64()),
        lo: (l.as_f64(), 0.0),
        hi: (u.as_f64(), 0.0),
        h: b.validity().as_f64(),
        step: b.safe_step().as_f64(),
    }
}

fn quad<T: Flt>(name: &'static str, b: ForwardQuadratic<T>) -> Parts {
    let [la, lb] = b.lower_coeffs();
    let [ua, ub] = b.upper_coeffs();
    Parts {
        name,
        start: (b.start().lo().as_f64(), b.start().hi().as_f64()),
        lo: (la.as_f64(), lb.as_f64()),
        hi: (ua.as_f64(), ub.as_f64()),
        h: b.validity().as_f64(),
        step: b.safe_step().as_f64(),
    }
}

/// `x · k / 32`, exactly.
fn frac32(x: &BigFloat, k: i64) -> BigFloat {
    let mut v = mul_exact(x, &r::int(k));
    if !v.is_zero() {
        let e = v.exponent().expect("finite");
        v.set_exponent(e - 5);
    }
    v
}

fn check_case<T: Flt + FieldNum<T>>(seed: u64) -> Result<(), TestCaseError> {
    let mut s = seed | 1;
    let mut unit = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    let c: Vec<T> = (0..5)
        .map(|_| T::from_f64(f64::from((unit() * 4.0 - 2.0) as f32)))
        .collect();
    let t0 = T::from_f64(f64::from((unit() * 4.0 - 2.0) as f32));
    let len = (1e-3f64.ln() + unit() * (2f64.ln() - 1e-3f64.ln())).exp();
    let t1 = T::from_f64(f64::from((t0.as_f64() + len) as f32));
    if t1 <= t0 {
        return Ok(());
    }
    let (d1, d2) = (deriv(&c), deriv(&deriv(&c)));
    let whole = Interval::new(t0, t1);
    let at0 = Interval::point(t0);
    let value = poly(&c, at0);
    let h = ForwardLinear::ray_param(t0, t1).validity();
    let slope_range = poly(&d1, whole);
    let lt = ForwardLinear::taylor(value, slope_range, h);
    let lip = ForwardLinear::lipschitz(value, slope_range.mag(), h);
    let qt = ForwardQuadratic::taylor(value, poly(&d1, at0), poly(&d2, whole), h);
    let lb: ForwardLinear<T> = poly(&c, ForwardLinear::ray_param(t0, t1));
    let qb: ForwardQuadratic<T> = poly(&c, ForwardQuadratic::ray_param(t0, t1));
    let bounds = [
        lin("linear taylor", lt),
        lin("lipschitz", lip),
        quad("quadratic taylor", qt),
        lin("linear mixed", lb.tighter(lt)),
        quad("quadratic mixed", qb.tighter(qt)),
    ];
    let bt0 = big(t0);
    let f0 = exact_poly(&c, &bt0);
    for b in &bounds {
        let ctx = || {
            format!(
                "{} {}: seed={seed:#x} c={c:?} t0={t0:e} t1={t1:e}",
                T::NAME,
                b.name
            )
        };
        if b.h.is_nan() || b.h <= 0.0 || r::lt(&big(t1), &add_exact(&bt0, &r::from_f64(b.h))) {
            return Err(TestCaseError::fail(format!(
                "validity h={:e}; {}",
                b.h,
                ctx()
            )));
        }
        let bh = r::from_f64(b.h);
        for k in 0..=32 {
            let tau = frac32(&bh, k);
            let y = exact_poly(&c, &add_exact(&bt0, &tau));
            let lo = side_exact(b.start.0, b.lo.0, b.lo.1, &tau);
            let hi = side_exact(b.start.1, b.hi.0, b.hi.1, &tau);
            if !(r::le(&lo, &y) && r::le(&y, &hi)) {
                return Err(TestCaseError::fail(format!(
                    "f(t0+τ) = {} not in [{}, {}] at τ = {}; {}",
                    r::show(&y),
                    r::show(&lo),
                    r::show(&hi),
                    r::show(&tau),
                    ctx()
                )));
            }
        }
        // The safe step never passes the first root.
        let outside = b.start.0 > 0.0;
        let inside = b.start.1 < 0.0;
        if (outside || inside) && b.step > 0.0 {
            let step = r::from_f64(b.step);
            for k in 0..32 {
                let y = exact_poly(&c, &add_exact(&bt0, &frac32(&step, k)));
                let crossed = if outside {
                    r::sign(&y) == std::cmp::Ordering::Less
                } else {
                    r::sign(&y) == std::cmp::Ordering::Greater
                };
                if crossed {
                    return Err(TestCaseError::fail(format!(
                        "step {:e} passes a root (f(t0) = {}); {}",
                        b.step,
                        r::show(&f0),
                        ctx()
                    )));
                }
            }
        }
    }
    Ok(())
}

fn run<T: Flt + FieldNum<T>>() {
    let mut config = common::config();
    config.failure_persistence = None;
    let mut runner = TestRunner::new(config);
    if let Err(e) = runner.run(&any::<u64>(), |seed| check_case::<T>(seed)) {
        panic!("{e}");
    }
}

#[test]
fn taylor_and_mixed_f32() {
    run::<f32>();
}

#[test]
fn taylor_and_mixed_f64() {
    run::<f64>();
}
