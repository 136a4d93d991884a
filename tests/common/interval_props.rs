//! Containment checks of every [`Interval`] operation on given operands
//! (one function per operation), shared by the `containment_interval`
//! property tests and the `interval_ops` fuzz target (`fuzz/`). See
//! `tests/containment_interval.rs` for what is proven.

use boundtrace::ia_core::Interval;
use proptest::prelude::*;

use super::check::{PLAIN, Picks, Res, TRIG, binary, in_interval, unary};
use super::reference::{self as r, Enc, big, le, sub_exact};
use super::{Flt, show_f, show_iv};

/// `Interval::new(a, b)` holds `[a, b]` when that is a set of reals, else `EMPTY`.
pub fn prop_new<T: Flt>(a: T, b: T) -> Res {
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
pub fn prop_point<T: Flt>(x: T) -> Res {
    let out = Interval::point(x);
    if x.is_finite() {
        prop_assert!(out.contains(x), "point({}) = {}", show_f(x), show_iv(out));
    } else {
        prop_assert!(out.is_empty(), "point({}) = {}", show_f(x), show_iv(out));
    }
    Ok(())
}

pub fn identity(s: &r::BigFloat, _p: usize) -> Option<Enc> {
    Some(Enc::exact(s.clone()))
}

pub fn prop_hull<T: Flt>(x: Interval<T>, y: Interval<T>, pk: &Picks) -> Res {
    let out = x.hull(y);
    unary("hull (x part)", x, out, pk, PLAIN, identity)?;
    unary("hull (y part)", y, out, &pk.rotate(), PLAIN, identity)
}

pub fn prop_intersection<T: Flt>(x: Interval<T>, y: Interval<T>, pk: &Picks) -> Res {
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
pub fn prop_contains<T: Flt>(x: Interval<T>) -> Res {
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

pub fn prop_subset<T: Flt>(x: Interval<T>, y: Interval<T>) -> Res {
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
pub fn prop_width<T: Flt>(x: Interval<T>) -> Res {
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
pub fn prop_mid<T: Flt>(x: Interval<T>) -> Res {
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
pub fn prop_rad<T: Flt>(x: Interval<T>) -> Res {
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
pub fn prop_mag<T: Flt>(x: Interval<T>, pk: &Picks) -> Res {
    let out = Interval::new(T::NEG_INFINITY, x.mag());
    unary("mag (as [−∞, mag])", x, out, pk, PLAIN, |s, _| {
        Some(r::abs(s))
    })
}

/// `mig ≤ |x|` for every sample.
pub fn prop_mig<T: Flt>(x: Interval<T>, pk: &Picks) -> Res {
    let out = Interval::new(x.mig(), T::INFINITY);
    unary("mig (as [mig, +∞])", x, out, pk, PLAIN, |s, _| {
        Some(r::abs(s))
    })
}

pub fn prop_neg<T: Flt>(x: Interval<T>, pk: &Picks) -> Res {
    unary("neg", x, -x, pk, PLAIN, |s, _| Some(Enc::exact(s.neg())))
}

pub fn prop_add<T: Flt>(x: Interval<T>, y: Interval<T>, pk: &Picks) -> Res {
    binary("x + y", x, y, x + y, pk, |a, b, p| Some(r::add(a, b, p)))
}

pub fn prop_sub<T: Flt>(x: Interval<T>, y: Interval<T>, pk: &Picks) -> Res {
    binary("x - y", x, y, x - y, pk, |a, b, p| Some(r::sub(a, b, p)))
}

pub fn prop_mul<T: Flt>(x: Interval<T>, y: Interval<T>, pk: &Picks) -> Res {
    binary("x * y", x, y, x * y, pk, |a, b, p| Some(r::mul(a, b, p)))
}

pub fn prop_div<T: Flt>(x: Interval<T>, y: Interval<T>, pk: &Picks) -> Res {
    binary("x / y", x, y, x / y, pk, r::div)
}

pub fn prop_scalar_rhs<T: Flt>(x: Interval<T>, s: T, pk: &Picks) -> Res {
    let y = Interval::point(s);
    binary("x + s", x, y, x + s, pk, |a, b, p| Some(r::add(a, b, p)))?;
    binary("x - s", x, y, x - s, pk, |a, b, p| Some(r::sub(a, b, p)))?;
    binary("x * s", x, y, x * s, pk, |a, b, p| Some(r::mul(a, b, p)))?;
    binary("x / s", x, y, x / s, pk, r::div)
}

/// `s + x`, `s − x`, `s · x`, `s / x` with a scalar left operand.
pub fn prop_scalar_lhs<T>(x: Interval<T>, s: T, pk: &Picks) -> Res
where
    T: Flt
        + std::ops::Add<Interval<T>, Output = Interval<T>>
        + std::ops::Sub<Interval<T>, Output = Interval<T>>
        + std::ops::Mul<Interval<T>, Output = Interval<T>>
        + std::ops::Div<Interval<T>, Output = Interval<T>>,
{
    let y = Interval::point(s);
    binary("s + x", y, x, s + x, pk, |a, b, p| Some(r::add(a, b, p)))?;
    binary("s - x", y, x, s - x, pk, |a, b, p| Some(r::sub(a, b, p)))?;
    binary("s * x", y, x, s * x, pk, |a, b, p| Some(r::mul(a, b, p)))?;
    binary("s / x", y, x, s / x, pk, r::div)
}

pub fn prop_recip<T: Flt>(x: Interval<T>, pk: &Picks) -> Res {
    unary("recip", x, x.recip(), pk, PLAIN, r::recip)
}

pub fn prop_sqr<T: Flt>(x: Interval<T>, pk: &Picks) -> Res {
    unary("sqr", x, x.sqr(), pk, PLAIN, |s, p| Some(r::sqr(s, p)))
}

pub fn prop_powi<T: Flt>(x: Interval<T>, n: i32, pk: &Picks) -> Res {
    let op = format!("powi({n})");
    unary(&op, x, x.powi(n), pk, PLAIN, |s, p| {
        r::powi(s, i64::from(n), p)
    })
}

pub fn prop_pow<T: Flt>(x: Interval<T>, e: T, pk: &Picks) -> Res {
    let op = format!("pow({})", show_f(e));
    unary(&op, x, x.pow(e), pk, PLAIN, |s, p| r::pow(s, e.as_f64(), p))
}

pub fn prop_sqrt<T: Flt>(x: Interval<T>, pk: &Picks) -> Res {
    unary("sqrt", x, x.sqrt(), pk, PLAIN, r::sqrt)
}

pub fn prop_exp<T: Flt>(x: Interval<T>, pk: &Picks) -> Res {
    unary("exp", x, x.exp(), pk, PLAIN, |s, p| Some(r::exp(s, p)))
}

pub fn prop_ln<T: Flt>(x: Interval<T>, pk: &Picks) -> Res {
    unary("ln", x, x.ln(), pk, PLAIN, r::ln)
}

pub fn prop_sin<T: Flt>(x: Interval<T>, pk: &Picks) -> Res {
    unary("sin", x, x.sin(), pk, TRIG, |s, p| Some(r::sin(s, p)))
}

pub fn prop_cos<T: Flt>(x: Interval<T>, pk: &Picks) -> Res {
    unary("cos", x, x.cos(), pk, TRIG, |s, p| Some(r::cos(s, p)))
}

pub fn prop_abs<T: Flt>(x: Interval<T>, pk: &Picks) -> Res {
    unary("abs", x, x.abs(), pk, PLAIN, |s, _| Some(r::abs(s)))
}

pub fn prop_min<T: Flt>(x: Interval<T>, y: Interval<T>, pk: &Picks) -> Res {
    binary("min", x, y, x.min(y), pk, |a, b, _| {
        Some(Enc::exact(r::min(a.clone(), b.clone())))
    })
}

pub fn prop_max<T: Flt>(x: Interval<T>, y: Interval<T>, pk: &Picks) -> Res {
    binary("max", x, y, x.max(y), pk, |a, b, _| {
        Some(Enc::exact(r::max(a.clone(), b.clone())))
    })
}
