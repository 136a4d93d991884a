//! Composition of a monotone convex/concave function with a forward bound
//! (forward-inclusion paper §5.2 "Convex/Concave functions" and App. B).
//!
//! For a function `φ` that is monotone and convex or concave on the range of
//! the input band, a bound of `φ ∘ f` is built side by side from a *line in
//! `x`* through the input side's start value `x₀`, composed with that side
//! `q(τ) = x₀ + u(τ)`:
//!
//! - the **tangent** at `x₀` bounds a convex function from below (a concave
//!   one from above) on its whole domain;
//! - the **chord** over the side's range `[I₀, I₁]` bounds it from above
//!   (below), but a single line through `(x₀, φ(x₀))` can only do so when
//!   `x₀` is an end of the range. When the quadratic side turns back past
//!   `x₀` inside `[0, h]`, App. B offers three ways out, all implemented
//!   ([`Composition`]).
//!
//! Lines are allowed a different slope left and right of `x₀` (`dL`, `dR`):
//! this absorbs the rounding of derivatives and makes the "relax at maxima"
//! variant exact at `t₀`. The composed side is `ℓ₀ + d(u)·u(τ)` with
//! `u = aτ + bτ²`, bounded by taking the extreme of `dL·a, dR·a` and of
//! `dL·b, dR·b` (valid because `τ, τ² ≥ 0`).

use crate::poly::{
    Side, add_hi, add_lo, max_hi, min_lo, mul_hi, mul_lo, slope_hi, slope_lo, sub_hi, sub_lo,
};
use boundtrace_ia_core::round::div_down;
use boundtrace_ia_core::{Interval, Real};

/// How a quadratic bound is composed with a convex/concave function when the
/// chord side cannot be exact at `t₀` (forward-inclusion paper App. B,
/// Fig. 21 a–c). Only [`ForwardQuadratic`](crate::ForwardQuadratic) is
/// affected: a linear side is monotone, so its start is always an end of its
/// range.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum Composition {
    /// Fig. 21 (a): shorten the validity interval to the point where the
    /// input side returns to its start value (the paper's main variant).
    #[default]
    ValidityInterval = 0,
    /// Fig. 21 (b): one chord over the whole range; the bound is no longer
    /// exact at `t₀` on that side (its start value is raised/lowered to the
    /// chord), but the interval keeps its length.
    RelaxStart = 1,
    /// Fig. 21 (c): keep the bound exact at `t₀` and the interval length;
    /// use the left chord before the input returns past `x₀` and the right
    /// chord after, merged into one quadratic that over-estimates the
    /// extremum.
    RelaxMax = 2,
}

impl Composition {
    /// The variant of a `#[repr(u32)]` code (an unknown code reads as the
    /// default).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub(crate) fn from_code(code: u32) -> Self {
        match code {
            1 => Self::RelaxStart,
            2 => Self::RelaxMax,
            _ => Self::ValidityInterval,
        }
    }

    /// Combines the modes of two operands: the non-default one wins (so a
    /// constant, built with the default, never overrides a ray parameter
    /// built with another mode).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub(crate) fn join(self, other: Self) -> Self {
        if self == Self::ValidityInterval {
            other
        } else {
            self
        }
    }
}

/// A monotone function composed by the rules here: one zero-sized type per
/// function ([`Exp`], [`Ln`], [`Sqrt`], [`Recip`], [`Pow`], [`Sin`],
/// [`Cos`]), so that a composition instantiates its own function only. (A
/// run-time choice among them put every function's enclosure at every call
/// site; a GPU driver inlines each call, and the `ForwardQuadratic` bottom-up
/// bounds of a blob scene came to 36 million SPIR-V instructions, most of
/// them sines, cosines and integer powers no blob evaluates: BENCHMARKS.md
/// "GPU".)
pub(crate) trait Unary<T: Real>: Copy {
    /// `sin` (for `sin`/`cos`: which quarter periods are convex).
    const IS_SIN: bool = false;

    /// A sound enclosure of `φ(x)` (IEEE 1788 domain semantics).
    fn eval(self, x: Interval<T>) -> Interval<T>;

    /// A sound enclosure of `φ'(x)` at a point of the open domain.
    fn deriv(self, x: T) -> Interval<T>;

    /// Defined for `x ≥ 0` only, bounded as `φ(max(x, 0))` (√ and positive
    /// powers).
    fn nonneg_domain(self) -> bool {
        false
    }

    /// `φ'(x)` given `v ⊇ φ(x)`, where the derivative is a function of the
    /// value (reused by the tangent rule); otherwise [`deriv`](Self::deriv).
    fn deriv_from(self, x: T, v: Interval<T>) -> Interval<T> {
        let _ = v;
        self.deriv(x)
    }

    /// `φ` at a point, clamping the argument into the closed domain for the
    /// `x ≥ 0` functions (their bounds use `φ(max(x, 0))`).
    fn at(self, x: T) -> Interval<T> {
        let x = if self.nonneg_domain() {
            x.max(T::ZERO)
        } else {
            x
        };
        self.eval(Interval::point(x))
    }
}

/// `eˣ` as a [`Unary`] function.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Exp;
/// `ln x` as a [`Unary`] function.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Ln;
/// `√x` as a [`Unary`] function.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Sqrt;
/// `1/x` as a [`Unary`] function.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Recip;
/// `max(x, 0)^p` for a non-integer `p` (`x > 0` for `p < 0`) as a
/// [`Unary`] function.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Pow<T>(pub T);
/// `sin x` as a [`Unary`] function.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Sin;
/// `cos x` as a [`Unary`] function.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Cos;

impl<T: Real> Unary<T> for Exp {
    fn eval(self, x: Interval<T>) -> Interval<T> {
        x.exp()
    }
    fn deriv(self, x: T) -> Interval<T> {
        Interval::point(x).exp()
    }
    fn deriv_from(self, _x: T, v: Interval<T>) -> Interval<T> {
        v
    }
}

impl<T: Real> Unary<T> for Ln {
    fn eval(self, x: Interval<T>) -> Interval<T> {
        x.ln()
    }
    fn deriv(self, x: T) -> Interval<T> {
        Interval::point(x).recip()
    }
}

impl<T: Real> Unary<T> for Sqrt {
    fn nonneg_domain(self) -> bool {
        true
    }
    fn eval(self, x: Interval<T>) -> Interval<T> {
        x.sqrt()
    }
    fn deriv(self, x: T) -> Interval<T> {
        (Interval::point(x).sqrt() * T::TWO).recip()
    }
    fn deriv_from(self, x: T, v: Interval<T>) -> Interval<T> {
        if x > T::ZERO {
            (v * T::TWO).recip()
        } else {
            self.deriv(x)
        }
    }
}

impl<T: Real> Unary<T> for Recip {
    fn eval(self, x: Interval<T>) -> Interval<T> {
        x.recip()
    }
    fn deriv(self, x: T) -> Interval<T> {
        -(Interval::point(x).sqr().recip())
    }
    fn deriv_from(self, _x: T, v: Interval<T>) -> Interval<T> {
        -v.sqr()
    }
}

impl<T: Real> Unary<T> for Pow<T> {
    fn eval(self, x: Interval<T>) -> Interval<T> {
        x.pow(self.0)
    }
    fn deriv(self, x: T) -> Interval<T> {
        Interval::point(x).pow(self.0 - T::ONE) * self.0
    }
    fn nonneg_domain(self) -> bool {
        self.0 > T::ZERO
    }
}

impl<T: Real> Unary<T> for Sin {
    const IS_SIN: bool = true;
    fn eval(self, x: Interval<T>) -> Interval<T> {
        x.sin()
    }
    fn deriv(self, x: T) -> Interval<T> {
        Interval::point(x).cos()
    }
}

impl<T: Real> Unary<T> for Cos {
    fn eval(self, x: Interval<T>) -> Interval<T> {
        x.cos()
    }
    fn deriv(self, x: T) -> Interval<T> {
        -Interval::point(x).sin()
    }
}

/// A line in `x` through `(x₀, ℓ₀)` with slope `dl` left of `x₀` and `dr`
/// right of it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Line<T> {
    pub l0: T,
    pub dl: T,
    pub dr: T,
}

/// Composes `line ∘ q` into a lower (`upper = false`) or upper side.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn compose_line<T: Real>(line: Line<T>, q: Side<T>, upper: bool) -> Side<T> {
    if upper {
        Side::new(
            line.l0,
            max_hi(mul_hi(line.dl, q.a), mul_hi(line.dr, q.a)),
            max_hi(mul_hi(line.dl, q.b), mul_hi(line.dr, q.b)),
        )
    } else {
        Side::new(
            line.l0,
            min_lo(mul_lo(line.dl, q.a), mul_lo(line.dr, q.a)),
            min_lo(mul_lo(line.dl, q.b), mul_lo(line.dr, q.b)),
        )
    }
}

/// The unbounded side in the given direction, keeping a start value.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn unbounded<T: Real>(start: T, upper: bool) -> Side<T> {
    if upper {
        Side::new(start, T::INFINITY, T::INFINITY)
    } else {
        Side::new(start, T::NEG_INFINITY, T::NEG_INFINITY)
    }
}

/// The tangent side: a lower bound of convex `φ ∘ q` (`upper = false`) or an
/// upper bound of concave `φ ∘ q` (`upper = true`), valid for every `τ` where
/// `q(τ)` lies in the region of convexity.
pub(crate) fn tangent<T: Real, P: Unary<T>>(phi: P, q: Side<T>, upper: bool) -> Side<T> {
    let v = phi.at(q.s);
    // Reuse the value where the derivative is a function of it.
    let d = phi.deriv_from(q.s, v);
    if v.is_empty() || d.is_empty() {
        let s = if upper { T::INFINITY } else { T::NEG_INFINITY };
        return unbounded(s, upper);
    }
    let line = if upper {
        // Concave: right of x₀ the slope may only grow, left only shrink.
        Line {
            l0: v.hi(),
            dl: d.lo(),
            dr: d.hi(),
        }
    } else {
        Line {
            l0: v.lo(),
            dl: d.hi(),
            dr: d.lo(),
        }
    };
    compose_line(line, q, upper)
}

/// The chord side: an upper bound of convex `φ ∘ q` (`upper = true`) or a
/// lower bound of concave `φ ∘ q` (`upper = false`) on `τ ∈ [0, h]`.
///
/// Returns the side and the (possibly shortened) validity length.
/// `known`: a range the argument is known to stay in on `[0, h]` (proven by
/// the caller's domain shortening, e.g. `x ≥ x₀/2` before a pole), which
/// the computed range is intersected with: near the float range's bottom the
/// outward-rounded range is wider than the truth and could otherwise reach
/// across the pole. For sqrt-like functions bounded as `φ(max(x, 0))` it is
/// `[0, ∞]`, which keeps the chord to `(0, φ(0))` valid for negative `x` too.
pub(crate) fn chord<T: Real, P: Unary<T>>(
    phi: P,
    q: Side<T>,
    h: T,
    upper: bool,
    mode: Composition,
    known: (T, T),
) -> (Side<T>, T) {
    let x0 = q.s;
    let v0 = phi.at(x0);
    if v0.is_empty() || !x0.is_finite() {
        let s = if upper { T::INFINITY } else { T::NEG_INFINITY };
        return (unbounded(s, upper), h);
    }
    let (mut rise, mut fall) = q.may_rise_fall(h);
    let mut h = h;
    if rise && fall && mode == Composition::ValidityInterval && q.b != T::ZERO {
        // u(τ) = τ(a + bτ) changes sign at τs = −a/b: stop there (rounded
        // down, so u keeps the sign of a on [0, τs]).
        let ts = div_down(-q.a, q.b);
        if ts > T::ZERO && ts < h {
            h = ts;
            if q.a > T::ZERO {
                fall = false;
            } else {
                rise = false;
            }
        }
    }
    let (mut i0, mut i1) = q.range(h);
    if i0 < known.0 {
        i0 = known.0;
    }
    if i1 > known.1 {
        i1 = known.1;
    }
    if i0 > x0 {
        i0 = x0;
    }
    if i1 < x0 {
        i1 = x0;
    }
    if !i0.is_finite() || !i1.is_finite() {
        return (unbounded(if upper { v0.hi() } else { v0.lo() }, upper), h);
    }
    let l0 = if upper { v0.hi() } else { v0.lo() };
    let relax = rise && fall && mode == Composition::RelaxStart;
    // φ at the range's ends where a slope needs it, each evaluated at one
    // call site (a GPU driver inlines every call).
    let p0 = if relax || (fall && i0 < x0) {
        phi.at(i0)
    } else {
        Interval::EMPTY
    };
    let p1 = if relax || (rise && i1 > x0) {
        phi.at(i1)
    } else {
        Interval::EMPTY
    };
    if relax {
        // One chord over [I₀, I₁]; its value at x₀ replaces the start.
        if p0.is_empty() || p1.is_empty() || !(i1 > i0) {
            return (unbounded(l0, upper), h);
        }
        let side = if upper {
            let s = slope_hi(sub_hi(p1.hi(), p0.hi()), i1, i0);
            let start = add_hi(p0.hi(), mul_hi(s, sub_hi(x0, i0)));
            Side::new(max_hi(start, l0), mul_hi(s, q.a), mul_hi(s, q.b))
        } else {
            let s = slope_lo(sub_lo(p1.lo(), p0.lo()), i1, i0);
            let start = add_lo(p0.lo(), mul_lo(s, sub_lo(x0, i0)));
            Side::new(min_lo(start, l0), mul_lo(s, q.a), mul_lo(s, q.b))
        };
        // The chord at x₀ is at least as far out as φ(x₀) (convexity), so the
        // start above is ≥ (≤) l0 up to rounding; `max_hi`/`min_lo` make sure.
        return (side, h);
    }
    // Left slope (x ∈ [I₀, x₀]) and right slope (x ∈ [x₀, I₁]).
    let left = if fall && i0 < x0 {
        let p = p0;
        if p.is_empty() || !p.is_bounded() {
            return (unbounded(l0, upper), h);
        } else if upper {
            // ℓ₀ + sL(I₀ − x₀) ≥ φ(I₀)  ⇔  sL ≤ (ℓ₀ − φ(I₀)) / (x₀ − I₀)
            Some(slope_lo(sub_lo(l0, p.hi()), x0, i0))
        } else {
            Some(slope_hi(sub_hi(l0, p.lo()), x0, i0))
        }
    } else {
        None
    };
    let right = if rise && i1 > x0 {
        let p = p1;
        if p.is_empty() || !p.is_bounded() {
            return (unbounded(l0, upper), h);
        } else if upper {
            Some(slope_hi(sub_hi(p.hi(), l0), i1, x0))
        } else {
            Some(slope_lo(sub_lo(p.lo(), l0), i1, x0))
        }
    } else {
        None
    };
    let (dl, dr) = match (left, right) {
        (Some(l), Some(r)) => (l, r),
        (Some(l), None) => (l, l),
        (None, Some(r)) => (r, r),
        (None, None) => (T::ZERO, T::ZERO),
    };
    (compose_line(Line { l0, dl, dr }, q, upper), h)
}

#[cfg(test)]
mod tests {
    use super::*;

    const ALL: (f64, f64) = (f64::NEG_INFINITY, f64::INFINITY);

    fn check(phi: impl Fn(f64) -> f64, q: Side<f64>, side: Side<f64>, h: f64, upper: bool) {
        for i in 0..=200 {
            let t = h * i as f64 / 200.0;
            let x = q.s + t * (q.a + q.b * t);
            let y = phi(x);
            if upper {
                assert!(side.at_hi(t) >= y - 1e-12, "upper fails at {t}: {y}");
            } else {
                assert!(side.at_lo(t) <= y + 1e-12, "lower fails at {t}: {y}");
            }
        }
    }

    #[test]
    fn exp_of_quadratic_all_modes() {
        // q dips below its start and comes back: x₀ not an extremum.
        let q = Side::new(0.0f64, -2.0, 1.0);
        for mode in [
            Composition::ValidityInterval,
            Composition::RelaxStart,
            Composition::RelaxMax,
        ] {
            let (up, h) = chord(Exp, q, 3.0, true, mode, ALL);
            assert!(h > 0.0 && h <= 3.0);
            if mode == Composition::ValidityInterval {
                assert!(h <= 2.0);
            } else {
                assert_eq!(h, 3.0);
            }
            check(f64::exp, q, up, h, true);
            let lo = tangent(Exp, q, false);
            check(f64::exp, q, lo, h, false);
            if mode != Composition::RelaxStart {
                assert_eq!(up.s, 1.0);
            }
        }
    }

    #[test]
    fn sqrt_lower_chord_through_zero() {
        let q = Side::new(4.0f64, -3.0, 0.0); // goes negative at τ = 4/3
        let (lo, h) = chord(
            Sqrt,
            q,
            2.0,
            false,
            Composition::RelaxMax,
            (0.0, f64::INFINITY),
        );
        check(|x| x.max(0.0).sqrt(), q, lo, h, false);
    }
}
