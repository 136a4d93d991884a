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

use common::check::{Fixed, PLAIN, Picks, Res, TRIG, binary, in_interval, picks, samples, unary};
use common::reference::{self as r, Enc, big, le, sub_exact};
use common::strategies::{
    float, half_ulp_of_max, interval, pow_exponent, powi_exponent, step, trig_interval,
};
use common::{Flt, config, show_f, show_iv};

/// `Interval::new(a, b)` holds `[a, b]` when that is a set of reals, else `EMPTY`.
fn prop_new<T: Flt>(a: T, b: T) -> Res {
    let out = Interval::new(a, b);
    if a <= b && a < T::INFINITY && b > T::NEG_INFINITY {
        prop_assert!(
            !out.is_empty() && out.lo() <= a && b <= out.hi(),
            "new({}, {}) = {}",
            show_f(a),
            show_f(b),
            show_iv(out)
        );
    } else {
        prop_assert!(
            out.is_empty(),
            "new({}, {}) = {}",
            show_f(a),
            show_f(b),
            show_iv(out)
        );
    }
    Ok(())
}

/// `Interval::point(x)` contains `x` (a real) or is `EMPTY` (NaN, `±∞`).
fn prop_point<T: Flt>(x: T) -> Res {
    let out = Interval::point(x);
    if x.is_finite() {
        prop_assert!(out.contains(x), "point({}) = {}", show_f(x), show_iv(out));
    } else {
        prop_assert!(out.is_empty(), "point({}) = {}", show_f(x), show_iv(out));
    }
    Ok(())
}

fn identity(s: &r::BigFloat, _p: usize) -> Option<Enc> {
    Some(Enc::exact(s.clone()))
}

fn prop_hull<T: Flt>(x: Interval<T>, y: Interval<T>, pk: &Picks) -> Res {
    let out = x.hull(y);
    unary("hull (x part)", x, out, pk, PLAIN, identity)?;
    unary("hull (y part)", y, out, &pk.rotate(), PLAIN, identity)
}

fn prop_intersection<T: Flt>(x: Interval<T>, y: Interval<T>, pk: &Picks) -> Res {
    let out = x.intersection(y);
    let in_y = |s: &r::BigFloat, _p: usize| in_interval(y, s).then(|| Enc::exact(s.clone()));
    let in_x = |s: &r::BigFloat, _p: usize| in_interval(x, s).then(|| Enc::exact(s.clone()));
    unary("intersection (x part)", x, out, pk, PLAIN, in_y)?;
    unary("intersection (y part)", y, out, &pk.rotate(), PLAIN, in_x)?;
    // The exact intersection's endpoints.
    if !x.is_empty() && !y.is_empty() {
        let lo = x.lo().max(y.lo());
        let hi = x.hi().min(y.hi());
        for e in [lo, hi] {
            if lo <= hi && e.is_finite() {
                prop_assert!(
                    out.contains(e),
                    "{} ∩ {} = {} misses {}",
                    show_iv(x),
                    show_iv(y),
                    show_iv(out),
                    show_f(e)
                );
            }
        }
    }
    Ok(())
}

/// `contains` is true for floats of the interval.
fn prop_contains<T: Flt>(x: Interval<T>) -> Res {
    if x.is_empty() {
        prop_assert!(!x.contains(T::ZERO));
        return Ok(());
    }
    let (a, b) = (x.lo(), x.hi());
    let mut members = vec![x.mid(), a.next_up(), b.next_down(), a, b, T::ZERO, -T::ZERO];
    members.retain(|&m| m.is_finite() && a <= m && m <= b);
    for m in members {
        prop_assert!(
            x.contains(m),
            "{} does not contain {}",
            show_iv(x),
            show_f(m)
        );
    }
    Ok(())
}

fn prop_subset<T: Flt>(x: Interval<T>, y: Interval<T>) -> Res {
    let h = x.hull(y);
    prop_assert!(
        x.subset(h) && y.subset(h),
        "{} ∪ {} ⊄ {}",
        show_iv(x),
        show_iv(y),
        show_iv(h)
    );
    let i = x.intersection(y);
    prop_assert!(
        i.subset(x) && i.subset(y),
        "{} ⊄ {} or {}",
        show_iv(i),
        show_iv(x),
        show_iv(y)
    );
    prop_assert!(x.subset(x) && Interval::EMPTY.subset(x));
    Ok(())
}

/// `width ≥ hi − lo` (exact), `+∞` when unbounded.
fn prop_width<T: Flt>(x: Interval<T>) -> Res {
    if x.is_empty() {
        return Ok(());
    }
    let w = x.width();
    let ok = if x.is_bounded() {
        !w.is_nan() && le(&sub_exact(&big(x.hi()), &big(x.lo())), &big(w))
    } else {
        w == T::INFINITY
    };
    prop_assert!(ok, "width({}) = {}", show_iv(x), show_f(w));
    Ok(())
}

/// `mid` is a float of the interval.
fn prop_mid<T: Flt>(x: Interval<T>) -> Res {
    if x.is_empty() {
        return Ok(());
    }
    let m = x.mid();
    prop_assert!(
        m.is_finite() && x.lo() <= m && m <= x.hi(),
        "mid({}) = {}",
        show_iv(x),
        show_f(m)
    );
    Ok(())
}

/// `[mid − rad, mid + rad] ⊇ x` (exact).
fn prop_rad<T: Flt>(x: Interval<T>) -> Res {
    if x.is_empty() {
        return Ok(());
    }
    let (m, rd) = (x.mid(), x.rad());
    let ok = if x.is_bounded() {
        let (bm, br) = (big(m), big(rd));
        !rd.is_nan()
            && le(&sub_exact(&bm, &br), &big(x.lo()))
            && le(&big(x.hi()), &r::add_exact(&bm, &br))
    } else {
        rd == T::INFINITY
    };
    prop_assert!(
        ok,
        "mid({0}) = {1}, rad({0}) = {2}",
        show_iv(x),
        show_f(m),
        show_f(rd)
    );
    Ok(())
}

/// `mag ≥ |x|` for every sample.
fn prop_mag<T: Flt>(x: Interval<T>, pk: &Picks) -> Res {
    let out = Interval::new(T::NEG_INFINITY, x.mag());
    unary("mag (as [−∞, mag])", x, out, pk, PLAIN, |s, _| {
        Some(r::abs(s))
    })
}

/// `mig ≤ |x|` for every sample.
fn prop_mig<T: Flt>(x: Interval<T>, pk: &Picks) -> Res {
    let out = Interval::new(x.mig(), T::INFINITY);
    unary("mig (as [mig, +∞])", x, out, pk, PLAIN, |s, _| {
        Some(r::abs(s))
    })
}

fn prop_neg<T: Flt>(x: Interval<T>, pk: &Picks) -> Res {
    unary("neg", x, -x, pk, PLAIN, |s, _| Some(Enc::exact(s.neg())))
}

fn prop_add<T: Flt>(x: Interval<T>, y: Interval<T>, pk: &Picks) -> Res {
    binary("x + y", x, y, x + y, pk, |a, b, p| Some(r::add(a, b, p)))
}

fn prop_sub<T: Flt>(x: Interval<T>, y: Interval<T>, pk: &Picks) -> Res {
    binary("x - y", x, y, x - y, pk, |a, b, p| Some(r::sub(a, b, p)))
}

fn prop_mul<T: Flt>(x: Interval<T>, y: Interval<T>, pk: &Picks) -> Res {
    binary("x * y", x, y, x * y, pk, |a, b, p| Some(r::mul(a, b, p)))
}

fn prop_div<T: Flt>(x: Interval<T>, y: Interval<T>, pk: &Picks) -> Res {
    binary("x / y", x, y, x / y, pk, r::div)
}

fn prop_scalar_rhs<T: Flt>(x: Interval<T>, s: T, pk: &Picks) -> Res {
    let y = Interval::point(s);
    binary("x + s", x, y, x + s, pk, |a, b, p| Some(r::add(a, b, p)))?;
    binary("x - s", x, y, x - s, pk, |a, b, p| Some(r::sub(a, b, p)))?;
    binary("x * s", x, y, x * s, pk, |a, b, p| Some(r::mul(a, b, p)))?;
    binary("x / s", x, y, x / s, pk, r::div)
}

fn prop_recip<T: Flt>(x: Interval<T>, pk: &Picks) -> Res {
    unary("recip", x, x.recip(), pk, PLAIN, r::recip)
}

fn prop_sqr<T: Flt>(x: Interval<T>, pk: &Picks) -> Res {
    unary("sqr", x, x.sqr(), pk, PLAIN, |s, p| Some(r::sqr(s, p)))
}

fn prop_powi<T: Flt>(x: Interval<T>, n: i32, pk: &Picks) -> Res {
    let op = format!("powi({n})");
    unary(&op, x, x.powi(n), pk, PLAIN, |s, p| {
        r::powi(s, i64::from(n), p)
    })
}

fn prop_pow<T: Flt>(x: Interval<T>, e: T, pk: &Picks) -> Res {
    let op = format!("pow({})", show_f(e));
    unary(&op, x, x.pow(e), pk, PLAIN, |s, p| r::pow(s, e.as_f64(), p))
}

fn prop_sqrt<T: Flt>(x: Interval<T>, pk: &Picks) -> Res {
    unary("sqrt", x, x.sqrt(), pk, PLAIN, r::sqrt)
}

fn prop_exp<T: Flt>(x: Interval<T>, pk: &Picks) -> Res {
    unary("exp", x, x.exp(), pk, PLAIN, |s, p| Some(r::exp(s, p)))
}

fn prop_ln<T: Flt>(x: Interval<T>, pk: &Picks) -> Res {
    unary("ln", x, x.ln(), pk, PLAIN, r::ln)
}

fn prop_sin<T: Flt>(x: Interval<T>, pk: &Picks) -> Res {
    unary("sin", x, x.sin(), pk, TRIG, |s, p| Some(r::sin(s, p)))
}

fn prop_cos<T: Flt>(x: Interval<T>, pk: &Picks) -> Res {
    unary("cos", x, x.cos(), pk, TRIG, |s, p| Some(r::cos(s, p)))
}

fn prop_abs<T: Flt>(x: Interval<T>, pk: &Picks) -> Res {
    unary("abs", x, x.abs(), pk, PLAIN, |s, _| Some(r::abs(s)))
}

fn prop_min<T: Flt>(x: Interval<T>, y: Interval<T>, pk: &Picks) -> Res {
    binary("min", x, y, x.min(y), pk, |a, b, _| {
        Some(Enc::exact(r::min(a.clone(), b.clone())))
    })
}

fn prop_max<T: Flt>(x: Interval<T>, y: Interval<T>, pk: &Picks) -> Res {
    binary("max", x, y, x.max(y), pk, |a, b, _| {
        Some(Enc::exact(r::max(a.clone(), b.clone())))
    })
}

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
                    let y = I::point(s);
                    binary("s + x", y, x, s + x, &pk, |a, b, p| Some(r::add(a, b, p)))?;
                    binary("s - x", y, x, s - x, &pk, |a, b, p| Some(r::sub(a, b, p)))?;
                    binary("s * x", y, x, s * x, &pk, |a, b, p| Some(r::mul(a, b, p)))?;
                    binary("s / x", y, x, s / x, &pk, r::div)?;
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
