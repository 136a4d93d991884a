//! Containment checks of every [`Affine`] operation on given operand forms
//! and noise values (one function per operation), shared by the
//! `containment_affine` property tests and the `affine_ops` fuzz target
//! (`fuzz/`). See `tests/containment_affine.rs` for what is proven.

use boundtrace::ia_core::{Affine, Interval};
use proptest::prelude::*;

use super::check::{PLAIN, Picks, Res, affine_binary, affine_unary, affine_values, samples};
use super::reference::{self as r, Enc, add_exact, big, le, sub_exact};
use super::{Flt, show_af, show_f, show_iv};

pub type A<T, const N: usize> = Affine<T, N>;

/// `constant(c)` stands for `c` (and is `EMPTY` for NaN, `±∞`).
pub fn prop_constant<T: Flt, const N: usize>(c: T, eps: &[[T; N]; 3]) -> Res {
    let z = A::<T, N>::constant(c);
    if !c.is_finite() {
        prop_assert!(z.is_empty(), "constant({}) = {}", show_f(c), show_af(&z));
        return Ok(());
    }
    affine_values("constant", &show_f(c), &z, eps, &[big(c)])
}

/// `from_interval(iv)` stands for every real of `iv`, at every `ε`.
pub fn prop_from_interval<T: Flt, const N: usize>(
    iv: Interval<T>,
    eps: &[[T; N]; 3],
    pk: &Picks,
) -> Res {
    let z = A::<T, N>::from_interval(iv);
    affine_values(
        "from_interval",
        &show_iv(iv),
        &z,
        eps,
        &samples(iv, pk, PLAIN),
    )
}

/// `variable(iv, k)` covers `iv` over `ε_k ∈ [−1, 1]` (`k < N`, bounded `iv`),
/// otherwise stands for every real of `iv` at every `ε`.
pub fn prop_variable<T: Flt, const N: usize>(
    iv: Interval<T>,
    k: usize,
    eps: &[[T; N]; 3],
    pk: &Picks,
) -> Res {
    let z = A::<T, N>::variable(iv, k);
    if k >= N || !iv.is_bounded() {
        let input = format!("{} as symbol {k}", show_iv(iv));
        return affine_values("variable", &input, &z, eps, &samples(iv, pk, PLAIN));
    }
    prop_assert!(
        z.is_bounded(),
        "variable({}, {k}) = {}",
        show_iv(iv),
        show_af(&z)
    );
    let c = big(z.center());
    let mut rad = big(z.err());
    for &zi in z.coeffs() {
        rad = add_exact(&rad, &big(zi.abs()));
    }
    prop_assert!(
        le(&sub_exact(&c, &rad), &big(iv.lo())) && le(&big(iv.hi()), &add_exact(&c, &rad)),
        "variable({}, {k}) = {} does not cover the interval",
        show_iv(iv),
        show_af(&z)
    );
    Ok(())
}

/// `to_interval ⊇ [x₀ − r, x₀ + r]` and `radius ≥ r`, `r = Σ|xᵢ| + e` (exact).
pub fn prop_to_interval<T: Flt, const N: usize>(x: A<T, N>) -> Res {
    let iv = x.to_interval();
    if x.is_empty() {
        prop_assert!(iv.is_empty(), "{} → {}", show_af(&x), show_iv(iv));
        return Ok(());
    }
    if x.is_entire() {
        prop_assert!(iv.is_entire(), "{} → {}", show_af(&x), show_iv(iv));
        return Ok(());
    }
    let mut rad = big(x.err());
    for &xi in x.coeffs() {
        rad = add_exact(&rad, &big(xi.abs()));
    }
    let c = big(x.center());
    prop_assert!(
        !iv.is_empty()
            && le(&big(iv.lo()), &sub_exact(&c, &rad))
            && le(&add_exact(&c, &rad), &big(iv.hi())),
        "to_interval({}) = {}",
        show_af(&x),
        show_iv(iv)
    );
    let radius = x.radius();
    prop_assert!(
        le(&rad, &big(radius)),
        "radius({}) = {}",
        show_af(&x),
        show_f(radius)
    );
    Ok(())
}

/// `eval(ε) ⊇ [x₀ + Σxᵢεᵢ − e, x₀ + Σxᵢεᵢ + e]` (exact).
pub fn prop_eval<T: Flt, const N: usize>(x: A<T, N>, eps: &[[T; N]; 3]) -> Res {
    for e in eps {
        let iv = x.eval(*e);
        if x.is_empty() {
            prop_assert!(iv.is_empty());
            continue;
        }
        if x.is_entire() {
            prop_assert!(iv.is_entire());
            continue;
        }
        let c = super::check::center_at(&x, e);
        let err = big(x.err());
        prop_assert!(
            !iv.is_empty()
                && le(&big(iv.lo()), &sub_exact(&c, &err))
                && le(&add_exact(&c, &err), &big(iv.hi())),
            "eval({}, {:?}) = {}",
            show_af(&x),
            e,
            show_iv(iv)
        );
    }
    Ok(())
}

pub fn prop_neg<T: Flt, const N: usize>(x: A<T, N>, eps: &[[T; N]; 3], pk: &Picks) -> Res {
    affine_unary("neg", &x, &(-x), eps, pk, |v, _| Some(Enc::exact(v.neg())))
}

pub fn prop_add<T: Flt, const N: usize>(
    x: A<T, N>,
    y: A<T, N>,
    eps: &[[T; N]; 3],
    pk: &Picks,
) -> Res {
    affine_binary("x + y", &x, &y, &(x + y), eps, pk, |a, b, p| {
        Some(r::add(a, b, p))
    })
}

pub fn prop_sub<T: Flt, const N: usize>(
    x: A<T, N>,
    y: A<T, N>,
    eps: &[[T; N]; 3],
    pk: &Picks,
) -> Res {
    affine_binary("x - y", &x, &y, &(x - y), eps, pk, |a, b, p| {
        Some(r::sub(a, b, p))
    })
}

pub fn prop_mul<T: Flt, const N: usize>(
    x: A<T, N>,
    y: A<T, N>,
    eps: &[[T; N]; 3],
    pk: &Picks,
) -> Res {
    affine_binary("x * y", &x, &y, &(x * y), eps, pk, |a, b, p| {
        Some(r::mul(a, b, p))
    })
}

pub fn prop_div<T: Flt, const N: usize>(
    x: A<T, N>,
    y: A<T, N>,
    eps: &[[T; N]; 3],
    pk: &Picks,
) -> Res {
    affine_binary("x / y", &x, &y, &(x / y), eps, pk, r::div)
}

pub fn prop_min<T: Flt, const N: usize>(
    x: A<T, N>,
    y: A<T, N>,
    eps: &[[T; N]; 3],
    pk: &Picks,
) -> Res {
    affine_binary("min", &x, &y, &x.min(y), eps, pk, |a, b, _| {
        Some(Enc::exact(r::min(a.clone(), b.clone())))
    })
}

pub fn prop_max<T: Flt, const N: usize>(
    x: A<T, N>,
    y: A<T, N>,
    eps: &[[T; N]; 3],
    pk: &Picks,
) -> Res {
    affine_binary("max", &x, &y, &x.max(y), eps, pk, |a, b, _| {
        Some(Enc::exact(r::max(a.clone(), b.clone())))
    })
}

/// `x + s`, `x − s`, `x · s`, `x / s` against the constant `s`.
pub fn prop_scalar_rhs<T: Flt, const N: usize>(
    x: A<T, N>,
    s: T,
    eps: &[[T; N]; 3],
    pk: &Picks,
) -> Res {
    let c = A::<T, N>::constant(s);
    affine_binary("x + s", &x, &c, &(x + s), eps, pk, |a, b, p| {
        Some(r::add(a, b, p))
    })?;
    affine_binary("x - s", &x, &c, &(x - s), eps, pk, |a, b, p| {
        Some(r::sub(a, b, p))
    })?;
    affine_binary("x * s", &x, &c, &(x * s), eps, pk, |a, b, p| {
        Some(r::mul(a, b, p))
    })?;
    affine_binary("x / s", &x, &c, &(x / s), eps, pk, r::div)
}

/// `s + x`, `s − x`, `s · x`, `s / x` with a scalar left operand.
pub fn prop_scalar_lhs<T, const N: usize>(x: A<T, N>, s: T, eps: &[[T; N]; 3], pk: &Picks) -> Res
where
    T: Flt
        + std::ops::Add<A<T, N>, Output = A<T, N>>
        + std::ops::Sub<A<T, N>, Output = A<T, N>>
        + std::ops::Mul<A<T, N>, Output = A<T, N>>
        + std::ops::Div<A<T, N>, Output = A<T, N>>,
{
    let c = A::<T, N>::constant(s);
    let add = |a: &r::BigFloat, b: &r::BigFloat, p| Some(r::add(a, b, p));
    let sub = |a: &r::BigFloat, b: &r::BigFloat, p| Some(r::sub(a, b, p));
    let mul = |a: &r::BigFloat, b: &r::BigFloat, p| Some(r::mul(a, b, p));
    affine_binary("s + x", &c, &x, &(s + x), eps, pk, add)?;
    affine_binary("s - x", &c, &x, &(s - x), eps, pk, sub)?;
    affine_binary("s * x", &c, &x, &(s * x), eps, pk, mul)?;
    affine_binary("s / x", &c, &x, &(s / x), eps, pk, r::div)
}

pub fn prop_sqr<T: Flt, const N: usize>(x: A<T, N>, eps: &[[T; N]; 3], pk: &Picks) -> Res {
    affine_unary("sqr", &x, &x.sqr(), eps, pk, |v, p| Some(r::sqr(v, p)))
}

pub fn prop_exp<T: Flt, const N: usize>(x: A<T, N>, eps: &[[T; N]; 3], pk: &Picks) -> Res {
    affine_unary("exp", &x, &x.exp(), eps, pk, |v, p| Some(r::exp(v, p)))
}

pub fn prop_sqrt<T: Flt, const N: usize>(x: A<T, N>, eps: &[[T; N]; 3], pk: &Picks) -> Res {
    affine_unary("sqrt", &x, &x.sqrt(), eps, pk, r::sqrt)
}

pub fn prop_ln<T: Flt, const N: usize>(x: A<T, N>, eps: &[[T; N]; 3], pk: &Picks) -> Res {
    affine_unary("ln", &x, &x.ln(), eps, pk, r::ln)
}

pub fn prop_recip<T: Flt, const N: usize>(x: A<T, N>, eps: &[[T; N]; 3], pk: &Picks) -> Res {
    affine_unary("recip", &x, &x.recip(), eps, pk, r::recip)
}

pub fn prop_abs<T: Flt, const N: usize>(x: A<T, N>, eps: &[[T; N]; 3], pk: &Picks) -> Res {
    affine_unary("abs", &x, &x.abs(), eps, pk, |v, _| Some(r::abs(v)))
}
