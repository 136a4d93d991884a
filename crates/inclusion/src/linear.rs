//! [`ForwardLinear`]: asymmetric linear forward inclusion functions
//! (forward-inclusion paper §5).

use crate::poly::{add_hi, add_lo, dot, max_hi, min_lo, mul_hi, mul_lo};
use crate::quadratic::ForwardQuadratic;
use boundtrace_ia_core::{Interval, Real};
use core::ops::{Add, Div, Mul, Neg, Sub};

/// A linear forward inclusion function: bounds of a function `f` of the ray
/// parameter on `[t₀, t₀ + h]` (forward-inclusion paper eq. 12)
///
/// ```text
/// f₋(t) = s₋ + m₋ τ  ≤  f(t)  ≤  f₊(t) = s₊ + m₊ τ,   τ = t − t₀ ∈ [0, h]
/// ```
///
/// exact at `t₀` up to the rounding margin `[s₋, s₊]` (see the crate docs),
/// with independent lower and upper slopes `m₋`, `m₊` and a validity length
/// `h` (paper §4.2).
///
/// Sums, scalar operations and products are computed directly on lines;
/// the other bottom-up rules of §5.2 are those of [`ForwardQuadratic`] with
/// the result folded back to lines over `[0, h]` (`bτ² ≥ min(0, b·h)·τ` for the
/// lower side): for the operations of the paper this *is* the linear rule —
/// a convex quadratic gets its tangent below and its chord above (eq. 17),
/// a product its four corner quadratics bounded by their extreme slopes,
/// `max` its chord above and the lower line with the higher start. A linear
/// input side is monotone, so compositions never need the
/// [`Composition`](crate::Composition) variants.
///
/// ```
/// use boundtrace_inclusion::ForwardLinear;
///
/// let t = ForwardLinear::<f64>::ray_param(0.0, 2.0);
/// let f = t.sqr() - t * 3.0 + 2.0; // (t − 1)(t − 2), roots 1 and 2
/// let [lo, hi] = f.slopes();
/// assert!(lo <= -3.0 && hi >= -1.0); // tangent −3 below, chord −1 above
/// assert!(f.safe_step() <= 1.0); // never passes the root at t = 1
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct ForwardLinear<T> {
    start: Interval<T>,
    lo: T,
    hi: T,
    h: T,
}

impl<T: Real> ForwardLinear<T> {
    /// The invalid bound (undefined at `t₀`).
    pub const INVALID: Self = Self {
        start: Interval::EMPTY,
        lo: T::ZERO,
        hi: T::ZERO,
        h: T::ZERO,
    };

    /// Builds a bound from its parts: start enclosure `[s₋, s₊]`, slopes
    /// `m₋`, `m₊`, validity length `h`. The caller vouches that they bound
    /// the function. A NaN part, negative `h` or empty start gives
    /// [`INVALID`](Self::INVALID).
    pub fn from_parts(start: Interval<T>, lo: T, hi: T, h: T) -> Self {
        if start.is_empty() || lo.is_nan() || hi.is_nan() || !(h >= T::ZERO) {
            return Self::INVALID;
        }
        Self { start, lo, hi, h }
    }

    /// The constant `c` (valid on any interval: `h = +∞`).
    pub fn constant(c: T) -> Self {
        Self::from_parts(Interval::point(c), T::ZERO, T::ZERO, T::INFINITY)
    }

    /// The ray parameter `t` on `[t0, t1]`: value `t₀`, slope `1`,
    /// `h = t1 − t0` rounded down. Non-finite bounds or `t1 < t0` give
    /// [`INVALID`](Self::INVALID).
    pub fn ray_param(t0: T, t1: T) -> Self {
        Self::from_quadratic(ForwardQuadratic::ray_param(t0, t1))
    }

    /// Linear Taylor inclusion (paper §5.1, eqs. 14–15): from an enclosure of
    /// `f(t₀)` and of `f'` over the whole interval, `f(t₀) + f'(ξ±)·τ`.
    pub fn taylor(value: Interval<T>, d1: Interval<T>, h: T) -> Self {
        if value.is_empty() || d1.is_empty() {
            return Self::INVALID;
        }
        Self::from_parts(value, d1.lo(), d1.hi(), h)
    }

    /// The sphere-tracing bound `f(t₀) ± L·τ` (paper eq. 10) for a global
    /// Lipschitz bound `L` of `f` along a unit-speed ray.
    pub fn lipschitz(value: Interval<T>, l: T, h: T) -> Self {
        Self::taylor(value, Interval::new(-l, l), h)
    }

    /// Folds a quadratic bound to lines over its validity interval.
    pub fn from_quadratic(q: ForwardQuadratic<T>) -> Self {
        if !q.is_valid() {
            let mut r = Self::INVALID;
            r.start = q.start();
            if !r.start.is_empty() {
                r.lo = T::NEG_INFINITY;
                r.hi = T::INFINITY;
            }
            return r;
        }
        let h = q.validity();
        let l = q.lower_side().to_linear_lo(h);
        let u = q.upper_side().to_linear_hi(h);
        Self::from_parts(q.start(), l.a, u.a, h)
    }

    /// The same bound as a [`ForwardQuadratic`] (zero curvature).
    pub fn to_quadratic(self) -> ForwardQuadratic<T> {
        if !self.is_valid() {
            return ForwardQuadratic::INVALID;
        }
        ForwardQuadratic::from_parts(self.start, [self.lo, T::ZERO], [self.hi, T::ZERO], self.h)
    }

    /// Whether the bound is defined (its start enclosure is non-empty).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn is_valid(&self) -> bool {
        !self.start.is_empty()
    }

    /// The enclosure `[s₋, s₊]` of `f(t₀)`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn start(&self) -> Interval<T> {
        self.start
    }

    /// The slopes `[m₋, m₊]`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn slopes(&self) -> [T; 2] {
        [self.lo, self.hi]
    }

    /// The validity length `h`: the bounds hold for `τ = t − t₀ ∈ [0, h]`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn validity(&self) -> T {
        self.h
    }

    /// The validity end `t₁' = t₀ + h`, rounded down.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn validity_end(&self, t0: T) -> T {
        boundtrace_ia_core::round::add_down(t0, self.h)
    }

    /// A sound enclosure `[f₋(τ), f₊(τ)]` at `τ = t − t₀` (rounded outward).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn bounds_at(&self, tau: T) -> Interval<T> {
        self.to_quadratic().bounds_at(tau)
    }

    /// A sound enclosure of `f` over the whole validity interval.
    pub fn range(&self) -> Interval<T> {
        self.to_quadratic().range()
    }

    /// The first `τ ∈ [0, h]` where the relevant bounding line reaches `0`
    /// (never past the first root of `f`), or `None`; see
    /// [`ForwardQuadratic::first_root`].
    pub fn first_root(&self) -> Option<T> {
        self.to_quadratic().first_root()
    }

    /// The safe marching step: [`first_root`](Self::first_root) or `h`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn safe_step(&self) -> T {
        self.first_root().unwrap_or(self.h)
    }

    /// "Mixed" bounds: per side, the tighter of two bounds of the same
    /// function (see [`ForwardQuadratic::tighter`]).
    pub fn tighter(self, other: Self) -> Self {
        Self::from_quadratic(self.to_quadratic().tighter(other.to_quadratic()))
    }

    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn lift2(
        self,
        other: Self,
        f: impl Fn(ForwardQuadratic<T>, ForwardQuadratic<T>) -> ForwardQuadratic<T>,
    ) -> Self {
        Self::from_quadratic(f(self.to_quadratic(), other.to_quadratic()))
    }

    /// `x²`: tangent below, chord above where the input keeps its sign.
    pub fn sqr(self) -> Self {
        Self::from_quadratic(self.to_quadratic().sqr())
    }

    /// `xⁿ` (see [`ForwardQuadratic::powi`]).
    pub fn powi(self, n: i32) -> Self {
        Self::from_quadratic(self.to_quadratic().powi(n))
    }

    /// `x^p` (see [`ForwardQuadratic::powf`]).
    pub fn powf(self, p: T) -> Self {
        Self::from_quadratic(self.to_quadratic().powf(p))
    }

    /// `1/x`, shortened before the pole (see [`ForwardQuadratic::recip`]).
    pub fn recip(self) -> Self {
        Self::from_quadratic(self.to_quadratic().recip())
    }

    /// `eˣ`.
    pub fn exp(self) -> Self {
        Self::from_quadratic(self.to_quadratic().exp())
    }

    /// `ln x` (see [`ForwardQuadratic::ln`]).
    pub fn ln(self) -> Self {
        Self::from_quadratic(self.to_quadratic().ln())
    }

    /// `√x` (see [`ForwardQuadratic::sqrt`]).
    pub fn sqrt(self) -> Self {
        Self::from_quadratic(self.to_quadratic().sqrt())
    }

    /// `sin x` (the quadratic rule, folded; see
    /// [`ForwardQuadratic::sin`]).
    pub fn sin(self) -> Self {
        Self::from_quadratic(self.to_quadratic().sin())
    }

    /// `cos x` (the quadratic rule, folded).
    pub fn cos(self) -> Self {
        Self::from_quadratic(self.to_quadratic().cos())
    }

    /// `max(f, g)` (paper §5.2): chord of the upper lines' maximum, the lower
    /// line with the higher start.
    pub fn max(self, other: Self) -> Self {
        self.lift2(other, |a, b| a.max(b))
    }

    /// A bound enclosing both `self` and `other` (their hull): the lower
    /// side of `min(self, other)`, the upper side of `max(self, other)`, the
    /// shorter validity. Used where a field's branch cannot be decided on
    /// the interval, so both branches are kept.
    pub fn join(self, other: Self) -> Self {
        if !self.is_valid() || !other.is_valid() {
            return Self::INVALID;
        }
        let lo = self.min(other);
        let hi = self.max(other);
        if !lo.is_valid() || !hi.is_valid() {
            return Self::INVALID;
        }
        let h = if lo.h < hi.h { lo.h } else { hi.h };
        Self::from_parts(Interval::new(lo.start.lo(), hi.start.hi()), lo.lo, hi.hi, h)
    }

    /// `min(f, g)`.
    pub fn min(self, other: Self) -> Self {
        self.lift2(other, |a, b| a.min(b))
    }

    /// `|x|`.
    pub fn abs(self) -> Self {
        Self::from_quadratic(self.to_quadratic().abs())
    }
}

impl<T: Real> Neg for ForwardLinear<T> {
    type Output = Self;
    /// Swaps and negates the lines (exact).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn neg(self) -> Self {
        if !self.is_valid() {
            return self;
        }
        Self::from_parts(-self.start, -self.hi, -self.lo, self.h)
    }
}

impl<T: Real> Add for ForwardLinear<T> {
    type Output = Self;
    /// Paper eq. 16, rounded outward.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn add(self, rhs: Self) -> Self {
        if !self.is_valid() || !rhs.is_valid() {
            return Self::INVALID;
        }
        Self::from_parts(
            self.start + rhs.start,
            add_lo(self.lo, rhs.lo),
            add_hi(self.hi, rhs.hi),
            min_h(self.h, rhs.h),
        )
    }
}

impl<T: Real> Sub for ForwardLinear<T> {
    type Output = Self;
    /// `self + (−rhs)`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn sub(self, rhs: Self) -> Self {
        self + (-rhs)
    }
}

impl<T: Real> Mul for ForwardLinear<T> {
    type Output = Self;
    /// The four corner products (quadratics sharing `t₀`), each bounded by
    /// its tangent/chord; extreme slopes (paper §5.2 "Multiplication").
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn mul(self, rhs: Self) -> Self {
        if !self.is_valid() || !rhs.is_valid() {
            return Self::INVALID;
        }
        let h = min_h(self.h, rhs.h);
        let fs = [(self.start.lo(), self.lo), (self.start.hi(), self.hi)];
        let gs = [(rhs.start.lo(), rhs.lo), (rhs.start.hi(), rhs.hi)];
        let (mut s_lo, mut s_hi) = (T::INFINITY, T::NEG_INFINITY);
        let (mut m_lo, mut m_hi) = (T::INFINITY, T::NEG_INFINITY);
        // Index loops (an array's `IntoIter` does not compile to SPIR-V).
        let mut i = 0;
        while i < 2 {
            let (f0, f1) = fs[i];
            i += 1;
            let mut j = 0;
            while j < 2 {
                let (g0, g1) = gs[j];
                j += 1;
                // (f0 + f1τ)(g0 + g1τ) = c0 + c1τ + c2τ²; over [0, h] its
                // tangent is below and its chord above when c2 ≥ 0 (and the
                // reverse when c2 < 0): slopes c1 + min/max(0, c2·h).
                s_lo = min_lo(s_lo, mul_lo(f0, g0));
                s_hi = max_hi(s_hi, mul_hi(f0, g0));
                let (c1_lo, c1_hi) = dot([(f0, g1), (f1, g0), (T::ZERO, T::ZERO)]);
                let (c2_lo, c2_hi) = (mul_lo(f1, g1), mul_hi(f1, g1));
                let dl = if c2_lo < T::ZERO {
                    mul_lo(c2_lo, h)
                } else {
                    T::ZERO
                };
                let dh = if c2_hi > T::ZERO {
                    mul_hi(c2_hi, h)
                } else {
                    T::ZERO
                };
                m_lo = min_lo(m_lo, add_lo(c1_lo, dl));
                m_hi = max_hi(m_hi, add_hi(c1_hi, dh));
            }
        }
        Self::from_parts(Interval::new(s_lo, s_hi), m_lo, m_hi, h)
    }
}

impl<T: Real> Div for ForwardLinear<T> {
    type Output = Self;
    /// `self · recip(rhs)`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn div(self, rhs: Self) -> Self {
        self.lift2(rhs, |a, b| a / b)
    }
}

impl<T: Real> Add<T> for ForwardLinear<T> {
    type Output = Self;
    /// Shifts the start (rounded outward).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn add(self, c: T) -> Self {
        if !self.is_valid() || !c.is_finite() {
            return Self::INVALID;
        }
        Self::from_parts(self.start + c, self.lo, self.hi, self.h)
    }
}

impl<T: Real> Sub<T> for ForwardLinear<T> {
    type Output = Self;
    /// `self + (−c)`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn sub(self, c: T) -> Self {
        self + (-c)
    }
}

impl<T: Real> Mul<T> for ForwardLinear<T> {
    type Output = Self;
    /// Scales start and slopes (rounded outward; sides swap for `c < 0`).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn mul(self, c: T) -> Self {
        if !self.is_valid() || !c.is_finite() {
            return Self::INVALID;
        }
        let (l, u) = if c >= T::ZERO {
            (self.lo, self.hi)
        } else {
            (self.hi, self.lo)
        };
        let s = self.start * c;
        Self::from_parts(s, mul_lo(l, c), mul_hi(u, c), self.h)
    }
}

impl<T: Real> Div<T> for ForwardLinear<T> {
    type Output = Self;
    /// Divides start and slopes (rounded outward); `c = 0` or non-finite
    /// gives [`INVALID`](Self::INVALID).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn div(self, c: T) -> Self {
        Self::from_quadratic(self.to_quadratic() / c)
    }
}

/// The shorter of two validity lengths.
#[cfg_attr(not(target_arch = "spirv"), inline)]
fn min_h<T: Real>(a: T, b: T) -> T {
    if a < b { a } else { b }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn convex_rule_eq17() {
        let t = ForwardLinear::<f64>::ray_param(1.0, 3.0);
        let f = t.sqr(); // tangent 2 below, chord (9 − 1)/2 = 4 above
        let [lo, hi] = f.slopes();
        assert!((lo - 2.0).abs() < 1e-12 && (hi - 4.0).abs() < 1e-12);
        assert!(f.start().contains(1.0));
    }

    #[test]
    fn max_rule() {
        let t = ForwardLinear::<f64>::ray_param(0.0, 1.0);
        let m = (t * 2.0).max(-t + 1.0);
        // lower: −t + 1 (higher start), upper: chord from 1 to 2.
        let [lo, hi] = m.slopes();
        assert!((lo + 1.0).abs() < 1e-12 && (hi - 1.0).abs() < 1e-12);
    }
}
