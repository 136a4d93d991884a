//! Sound helpers on one bounding polynomial `s + a·τ + b·τ²`, `τ ∈ [0, h]`.
//!
//! Every forward bound is a pair of such *sides* (paper eq. 18, Horner form
//! in the local parameter `τ = t − t₀ ≥ 0`). Because `τ ≥ 0` and `τ² ≥ 0`,
//! rounding each coefficient of a lower side down (of an upper side up) keeps
//! it a lower (upper) bound: that is how every rule here stays sound in
//! floating point without touching the rounding mode.
//!
//! The functions never panic and never return NaN: a product `0 · ∞` counts as
//! `0` (a zero coefficient contributes nothing on a bounded range), and any
//! NaN that `∞ − ∞` would produce becomes `−∞` in a lower and `+∞` in an upper
//! bound.

use boundtrace_ia_core::Real;
use boundtrace_ia_core::round::{add_down, add_up, div_down, div_up, mul_down, mul_up, sub_down};

/// `a · b` rounded down; `0 · x = 0`; NaN → `−∞`.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn mul_lo<T: Real>(a: T, b: T) -> T {
    if a == T::ZERO || b == T::ZERO {
        return T::ZERO;
    }
    let r = lo_nan(mul_down(a, b));
    // An underflow must not flip the known sign of the exact product.
    if r < T::ZERO && (a > T::ZERO) == (b > T::ZERO) {
        T::ZERO
    } else {
        r
    }
}

/// `a · b` rounded up; `0 · x = 0`; NaN → `+∞`.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn mul_hi<T: Real>(a: T, b: T) -> T {
    if a == T::ZERO || b == T::ZERO {
        return T::ZERO;
    }
    let r = hi_nan(mul_up(a, b));
    if r > T::ZERO && (a > T::ZERO) != (b > T::ZERO) {
        T::ZERO
    } else {
        r
    }
}

/// `a + b` rounded down; NaN → `−∞`.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn add_lo<T: Real>(a: T, b: T) -> T {
    lo_nan(add_down(a, b))
}

/// `a + b` rounded up; NaN → `+∞`.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn add_hi<T: Real>(a: T, b: T) -> T {
    hi_nan(add_up(a, b))
}

/// `a − b` rounded down.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn sub_lo<T: Real>(a: T, b: T) -> T {
    add_lo(a, -b)
}

/// `a − b` rounded up.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn sub_hi<T: Real>(a: T, b: T) -> T {
    add_hi(a, -b)
}

/// `a / b` rounded down; NaN → `−∞`.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn div_lo<T: Real>(a: T, b: T) -> T {
    if a == T::ZERO {
        return T::ZERO;
    }
    lo_nan(div_down(a, b))
}

/// `a / b` rounded up; NaN → `+∞`.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn div_hi<T: Real>(a: T, b: T) -> T {
    if a == T::ZERO {
        return T::ZERO;
    }
    hi_nan(div_up(a, b))
}

#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn lo_nan<T: Real>(x: T) -> T {
    if x.is_nan() { T::NEG_INFINITY } else { x }
}

#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn hi_nan<T: Real>(x: T) -> T {
    if x.is_nan() { T::INFINITY } else { x }
}

/// `min` that ignores nothing: a NaN operand gives `−∞` (used for lower bounds).
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn min_lo<T: Real>(a: T, b: T) -> T {
    if a.is_nan() || b.is_nan() {
        T::NEG_INFINITY
    } else if a < b {
        a
    } else {
        b
    }
}

/// `max` that gives `+∞` on a NaN operand (used for upper bounds).
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn max_hi<T: Real>(a: T, b: T) -> T {
    if a.is_nan() || b.is_nan() {
        T::INFINITY
    } else if a > b {
        a
    } else {
        b
    }
}

/// A lower bound of `num / (x_hi − x_lo)` for `x_hi > x_lo`, where `num` is
/// already a lower bound of the numerator.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn slope_lo<T: Real>(num: T, x_hi: T, x_lo: T) -> T {
    if num >= T::ZERO {
        div_lo(num, sub_hi(x_hi, x_lo))
    } else {
        div_lo(num, sub_lo(x_hi, x_lo))
    }
}

/// An upper bound of `num / (x_hi − x_lo)` for `x_hi > x_lo`, where `num` is
/// already an upper bound of the numerator.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn slope_hi<T: Real>(num: T, x_hi: T, x_lo: T) -> T {
    if num >= T::ZERO {
        div_hi(num, sub_lo(x_hi, x_lo))
    } else {
        div_hi(num, sub_hi(x_hi, x_lo))
    }
}

/// One bounding polynomial `s + a·τ + b·τ²` of the local ray parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Side<T> {
    pub s: T,
    pub a: T,
    pub b: T,
}

impl<T: Real> Side<T> {
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn new(s: T, a: T, b: T) -> Self {
        Self { s, a, b }
    }

    /// The constant side `c`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn constant(c: T) -> Self {
        Self::new(c, T::ZERO, T::ZERO)
    }

    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn neg(self) -> Self {
        Self::new(-self.s, -self.a, -self.b)
    }

    /// `s + τ(a + bτ)` in round-to-nearest with a rigorous bound on its
    /// rounding error: Horner's error for degree 2 is at most
    /// `γ₄·(|s| + τ(|a| + |b|τ))`, `γ₄ ≈ 2ε`; taken as `4ε·(…)` plus
    /// `4·MIN_POSITIVE` for underflow (also with flush-to-zero). One directed
    /// operation per bound instead of four.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn eval_err(self, tau: T) -> (T, T) {
        let v = self.s + tau * (self.a + self.b * tau);
        let m = self.s.abs() + tau * (self.a.abs() + self.b.abs() * tau);
        let err = m * (T::from_f64(4.0) * T::EPSILON) + T::from_f64(4.0) * T::min_positive_value();
        (v, err)
    }

    /// `s + τ(a + bτ)` rounded down (`τ ≥ 0`).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn at_lo(self, tau: T) -> T {
        if tau == T::ZERO {
            return self.s;
        }
        let (v, err) = self.eval_err(tau);
        let r = sub_down(v, err);
        if r.is_nan() {
            // ∞·0 (an infinite τ or coefficient): directed evaluation, which
            // treats 0·∞ as 0.
            return add_lo(self.s, mul_lo(tau, add_lo(self.a, mul_lo(self.b, tau))));
        }
        r
    }

    /// `s + τ(a + bτ)` rounded up (`τ ≥ 0`).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn at_hi(self, tau: T) -> T {
        if tau == T::ZERO {
            return self.s;
        }
        let (v, err) = self.eval_err(tau);
        let r = add_up(v, err);
        if r.is_nan() {
            return add_hi(self.s, mul_hi(tau, add_hi(self.a, mul_hi(self.b, tau))));
        }
        r
    }

    /// The vertex `τv = −a/(2b)` when it may lie in `(0, h]` (a generous
    /// test: including it is always sound), with `b`'s sign.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn vertex_in(self, h: T) -> bool {
        let (a, b) = (self.a, self.b);
        if b == T::ZERO || a == T::ZERO || (a < T::ZERO) == (b < T::ZERO) {
            return false;
        }
        let tv = -a / (b + b);
        !(tv > h * (T::ONE + T::from_f64(1.0 / 1024.0)))
    }

    /// A lower bound of the side's minimum over `τ ∈ [0, h]`.
    pub fn range_lo(self, h: T) -> T {
        let lo = min_lo(self.s, self.at_lo(h));
        if self.b > T::ZERO && self.vertex_in(h) {
            let aa = mul_hi(self.a, self.a);
            let v = sub_lo(self.s, div_hi(aa, mul_lo(T::from_f64(4.0), self.b)));
            return min_lo(lo, v);
        }
        lo
    }

    /// An upper bound of the side's maximum over `τ ∈ [0, h]`.
    pub fn range_hi(self, h: T) -> T {
        let hi = max_hi(self.s, self.at_hi(h));
        if self.b < T::ZERO && self.vertex_in(h) {
            let aa = mul_hi(self.a, self.a);
            let v = add_hi(self.s, div_hi(aa, mul_lo(T::from_f64(4.0), -self.b)));
            return max_hi(hi, v);
        }
        hi
    }

    /// A sound enclosure `(lo, hi)` of the side's range over `τ ∈ [0, h]`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn range(self, h: T) -> (T, T) {
        (self.range_lo(h), self.range_hi(h))
    }

    /// Whether `u(τ) = τ(a + bτ)` may be positive / negative somewhere on
    /// `(0, h]` (a `false` is proven).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn may_rise_fall(self, h: T) -> (bool, bool) {
        let (a, b) = (self.a, self.b);
        let rise = !(a <= T::ZERO && add_hi(a, mul_hi(b, h)) <= T::ZERO);
        let fall = !(a >= T::ZERO && add_lo(a, mul_lo(b, h)) >= T::ZERO);
        (rise, fall)
    }

    /// Folds the `τ²` term into the slope over `[0, h]` (quadratic → linear):
    /// `bτ² ≥ min(0, b·h)·τ` for a lower side.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn to_linear_lo(self, h: T) -> Self {
        let bh = if self.b < T::ZERO {
            mul_lo(self.b, h)
        } else {
            T::ZERO
        };
        Self::new(self.s, add_lo(self.a, bh), T::ZERO)
    }

    /// Upper-side counterpart of [`to_linear_lo`](Self::to_linear_lo).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn to_linear_hi(self, h: T) -> Self {
        let bh = if self.b > T::ZERO {
            mul_hi(self.b, h)
        } else {
            T::ZERO
        };
        Self::new(self.s, add_hi(self.a, bh), T::ZERO)
    }
}

/// Coefficient-wise sum of two lower sides (rounded down).
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn add_sides_lo<T: Real>(p: Side<T>, q: Side<T>) -> Side<T> {
    Side::new(add_lo(p.s, q.s), add_lo(p.a, q.a), add_lo(p.b, q.b))
}

/// Coefficient-wise sum of two upper sides (rounded up).
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn add_sides_hi<T: Real>(p: Side<T>, q: Side<T>) -> Side<T> {
    Side::new(add_hi(p.s, q.s), add_hi(p.a, q.a), add_hi(p.b, q.b))
}

/// Coefficient-wise minimum: a lower bound of both (`τ, τ² ≥ 0`).
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn min_sides<T: Real>(p: Side<T>, q: Side<T>) -> Side<T> {
    Side::new(min_lo(p.s, q.s), min_lo(p.a, q.a), min_lo(p.b, q.b))
}

/// Coefficient-wise maximum: an upper bound of both.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn max_sides<T: Real>(p: Side<T>, q: Side<T>) -> Side<T> {
    Side::new(max_hi(p.s, q.s), max_hi(p.a, q.a), max_hi(p.b, q.b))
}

/// `p · q` for scalars, both roundings.
#[cfg_attr(not(target_arch = "spirv"), inline)]
fn prod<T: Real>(p: T, q: T) -> (T, T) {
    (mul_lo(p, q), mul_hi(p, q))
}

/// `Σ xᵢ·yᵢ` (at most 3 terms) as `(lower, upper)` bounds: one pass in
/// round-to-nearest plus a rigorous a-posteriori error bound (Higham:
/// `|fl(Σ) − Σ| ≤ γₙ Σ|xᵢyᵢ|`, `γₙ = nu/(1 − nu)`, `u = ε/2`), taken
/// generously as `(n + 2)·ε·Σ|fl(xᵢyᵢ)| + (2n + 2)·MIN_POSITIVE` (the last
/// term covers underflow, also when a GPU flushes subnormals to zero; a
/// fused multiply-add only lowers the error). Much cheaper than directed
/// rounding of every product and sum, and as sound.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn dot<T: Real>(xs: [(T, T); 3]) -> (T, T) {
    // Three named terms, no index loop: a dynamic index is a bounds check,
    // i.e. a panic, which rust-gpu 0.11 can only handle by inlining every
    // caller up to the entry point (BENCHMARKS.md "GPU"). Callers pad with
    // `(0, 0)` terms, which are skipped below: the same sums as without.
    let [a, b, c] = xs;
    let acc = dot_term(dot_term(dot_term((T::ZERO, T::ZERO, 0), a), b), c);
    let (s, m, n) = acc;
    if n == 0 {
        return (T::ZERO, T::ZERO);
    }
    let nf = T::from_f64(f64::from(n));
    let err = m * (nf + T::TWO) * T::EPSILON + (nf + nf + T::TWO) * T::min_positive_value();
    (lo_nan(sub_down(s, err)), hi_nan(add_up(s, err)))
}

/// One term of [`dot`]: `(Σ, Σ|·|, count)` plus `x·y`, unless `x` or `y`
/// is zero.
#[cfg_attr(not(target_arch = "spirv"), inline)]
fn dot_term<T: Real>((s, m, n): (T, T, u32), (x, y): (T, T)) -> (T, T, u32) {
    if x == T::ZERO || y == T::ZERO {
        return (s, m, n);
    }
    let p = x * y;
    (s + p, m + p.abs(), n + 1)
}

/// The quartic `p·q = c₀ + c₁τ + c₂τ² + c₃τ³ + c₄τ⁴`, each coefficient as
/// `(lower, upper)` bounds (`c₀`, the start value, with directed rounding;
/// the others with [`dot`]).
pub(crate) fn quartic<T: Real>(p: Side<T>, q: Side<T>) -> [(T, T); 5] {
    [
        prod(p.s, q.s),
        dot([(p.s, q.a), (p.a, q.s), (T::ZERO, T::ZERO)]),
        dot([(p.s, q.b), (p.a, q.a), (p.b, q.s)]),
        dot([(p.a, q.b), (p.b, q.a), (T::ZERO, T::ZERO)]),
        dot([(p.b, q.b), (T::ZERO, T::ZERO), (T::ZERO, T::ZERO)]),
    ]
}

/// A lower bound of `min_{τ∈[0,h]} (c₂ + c₃τ + c₄τ²)` from lower coefficients.
fn min_tail<T: Real>(c2: T, c3: T, c4: T, h: T) -> T {
    let r = Side::new(c2, c3, c4);
    r.range_lo(h)
}

/// Degree reduction of a quartic (given by coefficient bounds) to a lower
/// quadratic side exact in value and slope at `τ = 0`:
/// `c₀ + c₁τ + β τ²` with `β = min_{[0,h]} (c₂ + c₃τ + c₄τ²)`, the tightest
/// curvature that keeps `c₀`, `c₁`.
pub(crate) fn reduce_lo<T: Real>(c: [(T, T); 5], h: T) -> Side<T> {
    Side::new(c[0].0, c[1].0, min_tail(c[2].0, c[3].0, c[4].0, h))
}

/// Upper counterpart of [`reduce_lo`].
pub(crate) fn reduce_hi<T: Real>(c: [(T, T); 5], h: T) -> Side<T> {
    let r = Side::new(c[2].1, c[3].1, c[4].1);
    Side::new(c[0].1, c[1].1, r.range_hi(h))
}

/// The paper's quadratic multiplication (forward-inclusion §6.2, Fig. 8):
/// a lower quadratic for the quartic `P` from a line below its derivative
/// `P′ = c₁ + 2c₂τ + 3c₃τ² + 4c₄τ³`, integrated from `τ = 0`.
///
/// `P′` is split at its inflection `τᵢ = −c₃/(4c₄)` into convex and concave
/// parts; a convex part is bounded below by its tangent at the midpoint (a
/// concave-kinked pair of half-lines absorbs the derivative's rounding), a
/// concave part by its chord. Each part's line is extended to `[0, h]`, the
/// lowest values at `0` and `h` define one line `L` below `P′` on all of
/// `[0, h]`, and `P(τ) ≥ c₀ + L(0)τ + (L(h) − L(0))τ²/(2h)`. Everything is
/// evaluated in interval arithmetic, so the result is sound. Unlike
/// [`reduce_lo`] its slope at `τ = 0` may be below `c₁`; the callers keep
/// whichever of the two is tighter at `h`.
pub(crate) fn reduce_lo_fig8<T: Real>(c: [(T, T); 5], h: T) -> Option<Side<T>> {
    use boundtrace_ia_core::Interval;
    if !(h > T::ZERO) || !h.is_finite() {
        return None;
    }
    // Constant indices only: a dynamic index is a panic path, which
    // rust-gpu 0.11 handles by inlining every caller (BENCHMARKS.md "GPU").
    let (c1, c2) = (Interval::new(c[1].0, c[1].1), Interval::new(c[2].0, c[2].1));
    let (c3, c4) = (Interval::new(c[3].0, c[3].1), Interval::new(c[4].0, c[4].1));
    if c1.is_empty() || c2.is_empty() || c3.is_empty() || c4.is_empty() {
        return None;
    }
    let d = [
        c1,
        c2 * T::TWO,
        c3 * T::from_f64(3.0),
        c4 * T::from_f64(4.0),
    ];
    // Split point: the inflection, if inside (0, h).
    let mut split = None;
    let mid4 = c4.mid();
    if mid4 != T::ZERO {
        let ti = -c3.mid() / (mid4 * T::from_f64(4.0));
        if ti > T::ZERO && ti < h {
            split = Some(ti);
        }
    }
    // Lowest values at 0 and at h of the extended lines (one part, or two
    // split at the inflection). A loop, so that the part's bound has one
    // call site: the shader inlines every call, and this function is in
    // every forward quadratic product (BENCHMARKS.md "GPU", session 36).
    let (parts, mid) = match split {
        Some(ti) => (2, ti),
        None => (1, h),
    };
    let (mut at0, mut ath) = (T::INFINITY, T::INFINITY);
    let mut k = 0;
    let mut lines = true;
    while k < parts {
        let (u, v) = if k == 0 { (T::ZERO, mid) } else { (mid, h) };
        match fig8_part(d, u, v, h) {
            Some((l0, lh)) => {
                at0 = min_lo(at0, l0);
                ath = min_lo(ath, lh);
                k += 1;
            }
            None => {
                lines = false;
                k = parts;
            }
        }
    }
    if !lines {
        return None;
    }
    if !(at0.is_finite() && ath.is_finite()) {
        return None;
    }
    let b = div_lo(sub_lo(ath, at0), h + h);
    Some(Side::new(c[0].0, at0, b))
}

/// [`reduce_lo_fig8`]'s line below `P′` on the part `[u, v]` of `[0, h]`,
/// extended: its values at `0` and `h` (`None` when degenerate). `d` holds
/// `P′`'s coefficients `[c₁, 2c₂, 3c₃, 4c₄]` as intervals.
fn fig8_part<T: Real>(d: [boundtrace_ia_core::Interval<T>; 4], u: T, v: T, h: T) -> Option<(T, T)> {
    use boundtrace_ia_core::Interval;
    let [c1, d1, d2, d3] = d;
    // P′ and P″ as enclosures at a point or over an interval of τ ≥ 0.
    let dp = |t: Interval<T>| c1 + t * (d1 + t * (d2 + t * d3));
    let ddp = |t: Interval<T>| d1 + t * (d2 * T::TWO + t * (d3 * T::from_f64(3.0)));
    // P‴ decides the convexity of P′.
    let dddp = |t: Interval<T>| d2 * T::TWO + t * (d3 * T::from_f64(6.0));
    if !(v > u) {
        return None;
    }
    let (ui, vi) = (Interval::point(u), Interval::point(v));
    let mi = Interval::point(u + (v - u) * T::HALF);
    // Convexity of P′ on [u, v] from the sign of P‴ over the part.
    let curv = dddp(Interval::new(u, v));
    let (yu, yv) = if curv.lo() >= T::ZERO {
        // Tangent at m with slope S: left of m use S.hi, right S.lo.
        let y = Interval::point(dp(mi).lo());
        let sl = ddp(mi);
        let yu = y + Interval::point(sl.hi()) * (ui - mi);
        let yv = y + Interval::point(sl.lo()) * (vi - mi);
        (yu.lo(), yv.lo())
    } else if curv.hi() <= T::ZERO {
        (dp(ui).lo(), dp(vi).lo())
    } else {
        // Neither provably convex nor concave (rounding at the
        // inflection): a constant below the range of P′ on the part.
        let r = dp(Interval::new(u, v)).lo();
        (r, r)
    };
    if !(yu.is_finite() && yv.is_finite()) {
        return None;
    }
    // The line through (u, yu), (v, yv), extended to 0 and h.
    let slope = (Interval::point(yv) - Interval::point(yu)) / (vi - ui);
    let l0 = (Interval::point(yu) + slope * (Interval::point(T::ZERO) - ui)).lo();
    let lh = (Interval::point(yu) + slope * (Interval::point(h) - ui)).lo();
    Some((l0, lh))
}

/// The coefficient bounds of `−P`.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn neg_quartic<T: Real>(c: [(T, T); 5]) -> [(T, T); 5] {
    [
        (-c[0].1, -c[0].0),
        (-c[1].1, -c[1].0),
        (-c[2].1, -c[2].0),
        (-c[3].1, -c[3].0),
        (-c[4].1, -c[4].0),
    ]
}

/// Upper counterpart of [`reduce_lo_fig8`] (via `−P`).
#[cfg(test)]
pub(crate) fn reduce_hi_fig8<T: Real>(c: [(T, T); 5], h: T) -> Option<Side<T>> {
    reduce_lo_fig8(neg_quartic(c), h).map(Side::neg)
}

/// A float estimate (no rounding control) of the values at `τ = h/2` and
/// `τ = h` of the
/// [`reduce_lo_fig8`] side, used to skip that (costlier, rigorous)
/// construction when it cannot beat [`reduce_lo`]. `None` when degenerate.
pub(crate) fn fig8_lo_estimate<T: Real>(c: [(T, T); 5], h: T) -> Option<(T, T)> {
    let (c0, c1, c2, c3, c4) = (c[0].0, c[1].0, c[2].0, c[3].0, c[4].0);
    let dp =
        |t: T| c1 + t * (T::TWO * c2 + t * (T::from_f64(3.0) * c3 + t * T::from_f64(4.0) * c4));
    let ddp = |t: T| T::TWO * c2 + t * (T::from_f64(6.0) * c3 + t * T::from_f64(12.0) * c4);
    let mut split = None;
    if c4 != T::ZERO {
        let ti = -c3 / (T::from_f64(4.0) * c4);
        if ti > T::ZERO && ti < h {
            split = Some(ti);
        }
    }
    // The line of the part [u, v] at 0 and h (no index loop: see
    // [`reduce_lo_fig8`]).
    let part = |u: T, v: T| {
        let m = u + (v - u) * T::HALF;
        let convex = T::from_f64(6.0) * c3 + T::from_f64(24.0) * c4 * m >= T::ZERO;
        let (yu, yv) = if convex {
            let (y, s) = (dp(m), ddp(m));
            (y + s * (u - m), y + s * (v - m))
        } else {
            (dp(u), dp(v))
        };
        let slope = (yv - yu) / (v - u);
        (yu - slope * u, yu + slope * (h - u))
    };
    let (l0, lh) = part(T::ZERO, split.unwrap_or(h));
    let (mut at0, mut ath) = (T::INFINITY.min(l0), T::INFINITY.min(lh));
    if let Some(ti) = split {
        let (l0, lh) = part(ti, h);
        at0 = at0.min(l0);
        ath = ath.min(lh);
    }
    // ∫₀^τ of the line through (0, at0), (h, ath), at τ = h/2 and τ = h.
    let mid = c0 + h * T::HALF * (at0 + (at0 + ath) * T::HALF) * T::HALF;
    let end = c0 + h * (at0 + ath) * T::HALF;
    if mid.is_finite() && end.is_finite() {
        Some((mid, end))
    } else {
        None
    }
}

/// Proves `s + aτ + bτ² ≥ 0` on `[0, r]` (given `s > 0`, `r ≥ 0`).
fn nonneg_on<T: Real>(q: Side<T>, r: T) -> bool {
    if r.is_nan() || q.at_lo(r) < T::ZERO {
        return false;
    }
    let (s, a, b) = (q.s, q.a, q.b);
    if b <= T::ZERO || a >= T::ZERO {
        // Concave (or linear), or convex and increasing from τ = 0: nonnegative
        // at both ends means nonnegative in between.
        return true;
    }
    // Convex and decreasing at 0: fine while r is before the vertex −a/(2b),
    // or if the vertex value itself is nonnegative.
    if mul_hi(b + b, r) <= -a {
        return true;
    }
    sub_lo(s, div_hi(mul_hi(a, a), mul_lo(T::from_f64(4.0), b))) >= T::ZERO
}

/// A float estimate of the least positive root of `s + aτ + bτ²` (`s > 0`),
/// or `h` when there is none (numerically stable: no cancellation).
fn root_estimate<T: Real>(q: Side<T>, h: T) -> T {
    let (s, a, b) = (q.s, q.a, q.b);
    if b == T::ZERO {
        return if a < T::ZERO { s / -a } else { h };
    }
    let disc = a * a - T::from_f64(4.0) * b * s;
    if !(disc >= T::ZERO) {
        // No real root in floats: the closest approach is the vertex.
        let tv = -a / (b + b);
        return if tv > T::ZERO { tv } else { h };
    }
    let sq = disc.sqrt();
    let qq = if a >= T::ZERO {
        -(a + sq) * T::HALF
    } else {
        (sq - a) * T::HALF
    };
    let r1 = qq / b;
    let r2 = if qq != T::ZERO { s / qq } else { T::INFINITY };
    let mut best = h;
    if r1 > T::ZERO && r1 < best {
        best = r1;
    }
    if r2 > T::ZERO && r2 < best {
        best = r2;
    }
    best
}

/// The safe step for a side that starts positive (`s > 0`): `None` when the
/// side is proven `≥ 0` on all of `[0, h]`, otherwise `Some(r)` with
/// `0 ≤ r ≤ h` and the side proven `≥ 0` on `[0, r]` (so a function bounded
/// below by it has no root in `[0, r)`). `r` is within a few float steps below
/// the side's exact first root, except in rare ill-conditioned cases where the
/// crude bound `s / (|a| + |b|·h)` is returned instead.
pub(crate) fn safe_root_pos<T: Real>(q: Side<T>, h: T) -> Option<T> {
    if q.a.is_nan() || q.b.is_nan() {
        return Some(T::ZERO);
    }
    if q.a == T::NEG_INFINITY || q.b == T::NEG_INFINITY {
        return Some(T::ZERO);
    }
    if nonneg_on(q, h) {
        return None;
    }
    let mut r = root_estimate(q, h);
    if !(r <= h) {
        r = h;
    }
    if !(r >= T::ZERO) {
        r = T::ZERO;
    }
    let mut k = 0u32;
    while k < 12 {
        if nonneg_on(q, r) {
            return Some(r);
        }
        r = r.next_down_n(1u32 << k).max(T::ZERO);
        k += 1;
    }
    let slope = add_hi(q.a.abs(), mul_hi(q.b.abs(), h));
    let crude = div_lo(q.s, slope);
    Some(if crude < h { crude.max(T::ZERO) } else { h })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `dot` takes three named terms (no index loop, for the GPU build);
    /// the `(0, 0)` padding must be neutral: the same bounds as summing
    /// only the real terms, and those bounds must contain the exact sum.
    #[test]
    fn dot_padding_is_neutral_and_sound() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed % 2001) as f64 / 100.0 - 10.0
        };
        for _ in 0..200 {
            let terms = [(next(), next()), (next(), next()), (next(), next())];
            for n in 1..=3 {
                let z = (0.0, 0.0);
                let padded = match n {
                    1 => [terms[0], z, z],
                    2 => [terms[0], terms[1], z],
                    _ => terms,
                };
                let moved = match n {
                    1 => [z, z, terms[0]],
                    2 => [terms[0], z, terms[1]],
                    _ => terms,
                };
                let (lo, hi) = dot(padded);
                assert_eq!((lo, hi), dot(moved), "padding position matters, n = {n}");
                // Exact sum of the products of these small decimals: each
                // product and the sum are within 1e-9 of the f64 values.
                let exact: f64 = terms[..n].iter().map(|&(x, y)| x * y).sum();
                assert!(
                    lo <= exact + 1e-9 && exact - 1e-9 <= hi,
                    "{lo} {exact} {hi}"
                );
                assert!(lo <= hi);
            }
        }
        assert_eq!(dot([(0.0f64, 0.0), (0.0, 0.0), (0.0, 0.0)]), (0.0, 0.0));
    }

    #[test]
    fn range_includes_vertex() {
        let q = Side::new(1.0f64, -2.0, 1.0); // (τ−1)², min 0 at τ=1
        let (lo, hi) = q.range(3.0);
        assert!(lo <= 0.0 && lo > -1e-12);
        assert!((4.0..4.0 + 1e-12).contains(&hi));
    }

    #[test]
    fn safe_root_never_passes() {
        // 1 − 3τ + 2τ² = (1 − τ)(1 − 2τ): roots 0.5 and 1.
        let q = Side::new(1.0f64, -3.0, 2.0);
        let r = safe_root_pos(q, 2.0).unwrap();
        assert!(r <= 0.5 && r > 0.5 - 1e-12);
        // Touching parabola (τ − 1)² + tiny: no root.
        let q = Side::new(1.0f64 + 1e-9, -2.0, 1.0);
        assert_eq!(safe_root_pos(q, 0.5), None);
        // Concave: 1 + τ − τ², root (1+√5)/2.
        let q = Side::new(1.0f64, 1.0, -1.0);
        let r = safe_root_pos(q, 10.0).unwrap();
        let exact = (1.0 + 5f64.sqrt()) / 2.0;
        assert!(r <= exact && r > exact - 1e-12);
    }

    /// Both reductions of random products bound the product (f64 reference
    /// with a relative slack far above its rounding).
    #[test]
    fn reductions_contain_random_products() {
        let mut s = 12345u64;
        let mut r = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64 * 4.0 - 2.0
        };
        for _ in 0..20_000 {
            let p = Side::new(r(), r() * 3.0, r() * 3.0);
            let q = Side::new(r(), r() * 3.0, r() * 3.0);
            let h = (r() + 2.0) / 2.0;
            let c = quartic(p, q);
            let sides = [
                (Some(reduce_lo(c, h)), false),
                (Some(reduce_hi(c, h)), true),
                (reduce_lo_fig8(c, h), false),
                (reduce_hi_fig8(c, h), true),
            ];
            for i in 0..=50 {
                let t = h * i as f64 / 50.0;
                let e = (p.s + t * (p.a + p.b * t)) * (q.s + t * (q.a + q.b * t));
                let tol = 1e-12 * (1.0 + e.abs());
                for (side, upper) in sides {
                    let Some(side) = side else { continue };
                    if upper {
                        assert!(side.at_hi(t) >= e - tol, "{p:?} {q:?} h={h} t={t}");
                    } else {
                        assert!(side.at_lo(t) <= e + tol, "{p:?} {q:?} h={h} t={t}");
                    }
                }
            }
        }
    }

    #[test]
    fn quartic_reduction_bounds_product() {
        let p = Side::new(1.0f64, -1.0, 0.5);
        let q = Side::new(2.0f64, 0.5, -0.25);
        let h = 2.0;
        let c = quartic(p, q);
        let lo = reduce_lo(c, h);
        let hi = reduce_hi(c, h);
        let lo8 = reduce_lo_fig8(c, h).unwrap();
        let hi8 = reduce_hi_fig8(c, h).unwrap();
        assert_eq!((lo8.s, hi8.s), (2.0, 2.0));
        for i in 0..=100 {
            let t = h * i as f64 / 100.0;
            let exact = (1.0 - t + 0.5 * t * t) * (2.0 + 0.5 * t - 0.25 * t * t);
            assert!(lo.at_lo(t) <= exact + 1e-12 && hi.at_hi(t) >= exact - 1e-12);
            assert!(lo8.at_lo(t) <= exact + 1e-12 && hi8.at_hi(t) >= exact - 1e-12);
        }
    }
}
