//! [`Interval`]: closed real intervals with sound, portable outward rounding.

use core::ops::{Add, Div, Mul, Neg, Sub};

use crate::Real;
use crate::round::{
    add_down, add_up, div_down, div_up, mul_down, mul_up, powu_dir, sqrt_down, sqrt_up, sub_down,
    sub_up,
};

/// A closed interval `[lo, hi]` of real numbers, or the empty set.
///
/// Every operation returns an interval that **encloses** the exact set of
/// real results `{ f(x) : x ∈ self }` (the IEEE 1788 set-based flavour): each
/// bound is computed in round-to-nearest and then stepped outward with the
/// portable [`Real::next_down`] / [`Real::next_up`], so no rounding-mode
/// switch is needed and the same code is sound on CPUs, SPIR-V and WASM.
/// Operations never panic; points outside an operation's domain are ignored
/// (e.g. `sqrt([-4, 4]) = [0, 2]`), and an operation with no valid point
/// returns [`Interval::EMPTY`].
///
/// # Representation invariant
///
/// Exactly one of:
/// - **empty**: `lo = +∞` and `hi = −∞` ([`Interval::EMPTY`]);
/// - **non-empty**: `lo ≤ hi`, neither is NaN, `lo < +∞` and `hi > −∞`
///   (a bound may be infinite: `[−∞, 3]`, [`Interval::ENTIRE`]).
///
/// Only the constructors below build values, and all of them check this, so
/// `lo`/`hi` never hold NaN. The sign of a zero bound carries no meaning.
///
/// # Example
///
/// ```
/// use boundtrace_ia_core::Interval;
///
/// let x = Interval::new(-1.0f64, 2.0);
/// let y = x * x - x; // the dependency problem: x·x ignores that both are x
/// assert!(y.contains(0.0) && y.lo() <= -4.0);
/// assert!(x.sqr().lo() == 0.0); // sqr knows its argument
/// assert!(Interval::new(1.0f64, 2.0).recip().contains(0.75));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct Interval<T> {
    lo: T,
    hi: T,
}

/// `v^m` (odd `m`, or `v ≥ 0`) rounded down (`upper = false`) or up: the
/// magnitude's power rounded toward zero for the lower bound of a
/// non-negative value and for the upper bound of a negative one.
#[cfg_attr(not(target_arch = "spirv"), inline)]
fn pow_bound<T: Real>(v: T, m: u32, upper: bool) -> T {
    let p = powu_dir(v.abs(), m, upper == (v >= T::ZERO));
    if v < T::ZERO { -p } else { p }
}

impl<T: Real> Default for Interval<T> {
    /// The empty interval.
    fn default() -> Self {
        Self::EMPTY
    }
}

impl<T: Real> Interval<T> {
    /// The empty set, stored as `[+∞, −∞]`.
    pub const EMPTY: Self = Self {
        lo: T::INFINITY,
        hi: T::NEG_INFINITY,
    };

    /// The whole real line `[−∞, +∞]`.
    pub const ENTIRE: Self = Self {
        lo: T::NEG_INFINITY,
        hi: T::INFINITY,
    };

    /// `[lo, hi]`, or [`EMPTY`](Self::EMPTY) when that is not a valid interval.
    ///
    /// | input | result |
    /// | --- | --- |
    /// | `lo ≤ hi`, `lo < +∞`, `hi > −∞` | `[lo, hi]` |
    /// | `lo > hi` | `EMPTY` |
    /// | a NaN bound | `EMPTY` |
    /// | `[+∞, +∞]`, `[−∞, −∞]` (no real number) | `EMPTY` |
    ///
    /// ```
    /// use boundtrace_ia_core::Interval;
    /// assert_eq!(Interval::new(1.0, 2.0).hi(), 2.0);
    /// assert!(Interval::new(2.0, 1.0).is_empty());
    /// assert!(Interval::new(f32::NAN, 1.0).is_empty());
    /// ```
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn new(lo: T, hi: T) -> Self {
        // NaN fails both comparisons.
        if lo <= hi && lo < T::INFINITY && hi > T::NEG_INFINITY {
            Self { lo, hi }
        } else {
            Self::EMPTY
        }
    }

    /// The point interval `[x, x]`; [`EMPTY`](Self::EMPTY) for NaN or `±∞`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn point(x: T) -> Self {
        Self::new(x, x)
    }

    /// Builds from bounds already known to satisfy the invariant, or fixes
    /// them up (a NaN bound, produced by no operation here, gives `ENTIRE`).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn raw(lo: T, hi: T) -> Self {
        debug_assert!(
            lo <= hi || lo.is_nan() || hi.is_nan(),
            "interval bounds out of order"
        );
        if lo.is_nan() || hi.is_nan() {
            return Self::ENTIRE;
        }
        Self { lo, hi }
    }

    /// Lower bound (`+∞` for the empty interval).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn lo(self) -> T {
        self.lo
    }

    /// Upper bound (`−∞` for the empty interval).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn hi(self) -> T {
        self.hi
    }

    /// Whether this is the empty set.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn is_empty(self) -> bool {
        self.lo > self.hi
    }

    /// Whether this is `[−∞, +∞]`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn is_entire(self) -> bool {
        self.lo == T::NEG_INFINITY && self.hi == T::INFINITY
    }

    /// Whether both bounds are finite (false for the empty interval).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn is_bounded(self) -> bool {
        self.lo.is_finite() && self.hi.is_finite()
    }

    /// Whether the real number `x` lies in the interval (false for NaN, `±∞`).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn contains(self, x: T) -> bool {
        self.lo <= x && x <= self.hi && x.is_finite()
    }

    /// Whether `self ⊆ other` (the empty set is a subset of everything).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn subset(self, other: Self) -> bool {
        self.is_empty() || (other.lo <= self.lo && self.hi <= other.hi)
    }

    /// The smallest interval containing both (the convex hull of the union).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn hull(self, other: Self) -> Self {
        // With EMPTY = [+∞, −∞] min/max ignore an empty operand.
        Self {
            lo: self.lo.min(other.lo),
            hi: self.hi.max(other.hi),
        }
    }

    /// The intersection; `EMPTY` when the intervals are disjoint.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn intersection(self, other: Self) -> Self {
        let lo = self.lo.max(other.lo);
        let hi = self.hi.min(other.hi);
        if lo <= hi {
            Self { lo, hi }
        } else {
            Self::EMPTY
        }
    }

    /// Width `hi − lo`, rounded up (`+∞` if unbounded, NaN if empty).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn width(self) -> T {
        if self.is_empty() {
            return T::nan();
        }
        sub_up(self.hi, self.lo)
    }

    /// A midpoint: a float inside the interval, near `(lo + hi)/2`.
    ///
    /// IEEE 1788 conventions: `mid(ENTIRE) = 0`, `mid([−∞, b]) = −MAX`,
    /// `mid([a, +∞]) = MAX`, `mid(EMPTY) = NaN`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn mid(self) -> T {
        let (a, b) = (self.lo, self.hi);
        if self.is_empty() {
            return T::nan();
        }
        match (a == T::NEG_INFINITY, b == T::INFINITY) {
            (true, true) => T::ZERO,
            (true, false) => -T::MAX,
            (false, true) => T::MAX,
            (false, false) => {
                let m = (a + b) * T::HALF;
                if m.is_finite() {
                    // Round-to-nearest of the exact midpoint stays in [a, b].
                    m
                } else {
                    // a + b overflowed.
                    a * T::HALF + b * T::HALF
                }
            }
        }
    }

    /// A radius `r` with `[mid − r, mid + r] ⊇ self`, rounded up
    /// (`+∞` if unbounded, NaN if empty).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn rad(self) -> T {
        if self.is_empty() {
            return T::nan();
        }
        let m = self.mid();
        sub_up(m, self.lo).max(sub_up(self.hi, m))
    }

    /// Magnitude `max |x|` over the interval (NaN if empty).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn mag(self) -> T {
        if self.is_empty() {
            return T::nan();
        }
        self.lo.abs().max(self.hi.abs())
    }

    /// Mignitude `min |x|` over the interval (NaN if empty).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn mig(self) -> T {
        if self.is_empty() {
            return T::nan();
        }
        if self.lo <= T::ZERO && T::ZERO <= self.hi {
            T::ZERO
        } else {
            self.lo.abs().min(self.hi.abs())
        }
    }

    /// The part of the interval at or above zero.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn nonneg(self) -> Self {
        self.intersection(Self {
            lo: T::ZERO,
            hi: T::INFINITY,
        })
    }

    /// `1 / x` (IEEE 1788 `recip`).
    ///
    /// | `x` | result |
    /// | --- | --- |
    /// | `[0, 0]`, empty | `EMPTY` |
    /// | `a < 0 < b` | `ENTIRE` |
    /// | `[0, b]`, `b > 0` | `[1/b, +∞]` |
    /// | `[a, 0]`, `a < 0` | `[−∞, 1/a]` |
    /// | `0 ∉ [a, b]` | `[1/b, 1/a]` |
    ///
    /// See also [`Div`].
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn recip(self) -> Self {
        Self::point(T::ONE) / self
    }

    /// `x²`: `[mig², mag²]` (tighter than `x * x`).
    ///
    /// ```
    /// use boundtrace_ia_core::Interval;
    /// let x = Interval::new(-3.0f64, 2.0).sqr();
    /// assert_eq!((x.lo(), x.hi()), (0.0, 9.0));
    /// ```
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn sqr(self) -> Self {
        if self.is_empty() {
            return self;
        }
        let (m, big) = (self.mig(), self.mag());
        Self::raw(mul_down(m, m), mul_up(big, big))
    }

    /// `x^n` for an integer `n` (IEEE 1788 `pown`).
    ///
    /// | `n` | result |
    /// | --- | --- |
    /// | `0` | `[1, 1]` (also for `x ∋ 0`) |
    /// | odd `> 0` | `[a^n, b^n]` (increasing) |
    /// | even `> 0` | `[mig^n, mag^n]` |
    /// | `< 0` | `recip(x^|n|)`; `EMPTY` for `x = [0, 0]` |
    ///
    /// Powers are computed by binary powering, each product stepped outward;
    /// a squaring doubles the relative error of its operand, so a bound is
    /// within a factor `(1 + ε_mach)^(|n|−1)` of the tightest one — about
    /// `|n| − 1` float steps, twice that near a power of two (ITF1788: at
    /// most 10 steps for `|n| ≤ 8`).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn powi(self, n: i32) -> Self {
        if self.is_empty() {
            return self;
        }
        if n == 0 {
            return Self::point(T::ONE);
        }
        let m = n.unsigned_abs();
        if n > 0 {
            return self.powu(m);
        }
        // Two sound enclosures of x^−m, intersected: 1/(x^m) is the right
        // shape when 0 ∈ x, (1/x)^m stays tight when x^m overflows (the
        // second only when 0 ∉ x). One power call site (see `mul`).
        let rounds = if self.mig() > T::ZERO { 2 } else { 1 };
        let mut r = self;
        let mut i = 0;
        while i < rounds {
            let base = if i == 0 { self } else { self.recip() };
            let p = base.powu(m);
            r = if i == 0 { p.recip() } else { r.intersection(p) };
            i += 1;
        }
        r
    }

    /// `x^m` for `m ≥ 1` by binary powering of the bounds.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn powu(self, m: u32) -> Self {
        // Even: |x|^m on [mig, mag]. Odd: increasing, x^m = −(|x|^m) for
        // x < 0.
        let (lo, hi) = if m % 2 == 0 {
            (self.mig(), self.mag())
        } else {
            (self.lo, self.hi)
        };
        Self::raw(pow_bound(lo, m, false), pow_bound(hi, m, true))
    }

    /// `x^p` for a real exponent `p` (IEEE 1788 `pow` with a point exponent).
    ///
    /// Domain `x ≥ 0` (and `x > 0` when `p ≤ 0`); points outside are ignored.
    /// `p = 0` gives `[1, 1]` on a non-empty domain. A NaN or infinite `p`
    /// is not a real exponent and gives `EMPTY`. When `p` is an integer
    /// that fits an `i32`, the bound is the one of [`powi`](Self::powi) on the
    /// domain; otherwise `libm`'s `pow` (error < 1 ulp) widened by two float
    /// steps per bound.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn pow(self, p: T) -> Self {
        if !p.is_finite() {
            return Self::EMPTY;
        }
        let x = self.nonneg();
        if x.is_empty() || (p <= T::ZERO && x.hi == T::ZERO) {
            // 0^p is undefined for p ≤ 0.
            return Self::EMPTY;
        }
        if p == T::ZERO {
            return Self::point(T::ONE);
        }
        if p.floor() == p {
            // Integer exponent representable as i32 (`to_i32` is `None` beyond,
            // e.g. for 2^31 as f32): x ≥ 0 here, so powi's bounds apply.
            if let Some(n) = p.to_i32() {
                return x.powi(n);
            }
        }
        let up = |v: T| {
            let r = v.m_pow(p);
            if v == T::ONE || v == T::ZERO || v.is_infinite() {
                r // exact: 1^p = 1, 0^p = 0, ∞^p ∈ {0, ∞}
            } else {
                r.next_up_n(T::TRANSCENDENTAL_STEPS)
            }
        };
        let down = |v: T| {
            let r = v.m_pow(p);
            if v == T::ONE || v == T::ZERO || v.is_infinite() {
                r
            } else {
                r.next_down_n(T::TRANSCENDENTAL_STEPS).max(T::ZERO)
            }
        };
        if p > T::ZERO {
            // Increasing on [0, ∞].
            Self::raw(down(x.lo), up(x.hi))
        } else {
            // Decreasing on (0, ∞]; unbounded as x → 0⁺ when 0 ∈ x.
            let hi = if x.lo == T::ZERO {
                T::INFINITY
            } else {
                up(x.lo)
            };
            Self::raw(down(x.hi), hi)
        }
    }

    /// `√x` on the domain `x ≥ 0` (`EMPTY` if `x < 0` everywhere).
    ///
    /// Correctly rounded `sqrt` stepped one float outward.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn sqrt(self) -> Self {
        let x = self.nonneg();
        if x.is_empty() {
            return x;
        }
        Self::raw(sqrt_down(x.lo), sqrt_up(x.hi))
    }

    /// `e^x`: increasing, range `[0, +∞]`; `exp(−∞) = 0`, `exp(0) = 1`
    /// exactly, other bounds widened by two float steps (libm error < 1 ulp).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn exp(self) -> Self {
        if self.is_empty() {
            return self;
        }
        // A point interval needs one libm call, not two.
        let rl = self.lo.m_exp();
        let rh = if self.hi == self.lo {
            rl
        } else {
            self.hi.m_exp()
        };
        let f = |v: T, r: T, up: bool| {
            if v == T::ZERO || v.is_infinite() {
                r // exact: e^0 = 1, e^−∞ = 0, e^+∞ = +∞
            } else if up {
                r.next_up_n(T::TRANSCENDENTAL_STEPS)
            } else {
                r.next_down_n(T::TRANSCENDENTAL_STEPS).max(T::ZERO)
            }
        };
        Self::raw(f(self.lo, rl, false), f(self.hi, rh, true))
    }

    /// Natural logarithm on the domain `x > 0`: `ln([0, b]) = [−∞, ln b]`,
    /// `EMPTY` for `x ≤ 0` everywhere; `ln(1) = 0` exactly, other bounds
    /// widened by two float steps (libm error < 1 ulp).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn ln(self) -> Self {
        let x = self.nonneg();
        if x.is_empty() || x.hi == T::ZERO {
            return Self::EMPTY;
        }
        let rl = x.lo.m_ln();
        let rh = if x.hi == x.lo { rl } else { x.hi.m_ln() };
        let f = |v: T, r: T, up: bool| {
            if v == T::ONE || v == T::ZERO || v.is_infinite() {
                r // exact: ln 1 = 0, ln 0 = −∞, ln ∞ = ∞
            } else if up {
                r.next_up_n(T::TRANSCENDENTAL_STEPS)
            } else {
                r.next_down_n(T::TRANSCENDENTAL_STEPS)
            }
        };
        Self::raw(f(x.lo, rl, false), f(x.hi, rh, true))
    }

    /// Sine. Bounds widened by two float steps (libm error < 1 ulp, full
    /// argument reduction), clamped to `[−1, 1]`; `sin(0) = 0` exactly.
    ///
    /// Extrema are located soundly: `[a, b]·2/π` is enclosed with outward
    /// rounding and the range includes `±1` whenever a critical point
    /// `π/2 + kπ` may lie inside. Non-point intervals beyond `|x| ≥ 2^(p−3)`
    /// (where floats are too sparse to place them) give `[−1, 1]`; on
    /// SPIR-V, so does an `f32` end with `|x| ≥ 2²⁸` (beyond the argument
    /// reduction of `ia-core`'s own GPU sine).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn sin(self) -> Self {
        self.trig(1)
    }

    /// Cosine; see [`sin`](Self::sin) for accuracy and extrema
    /// (`cos(0) = 1` exactly).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn cos(self) -> Self {
        self.trig(0)
    }

    /// Shared sin/cos: the maxima sit at `q ≡ phase (mod 4)` and the minima at
    /// `q ≡ phase + 2 (mod 4)`, for `q = x·2/π` (sin: phase 1, cos: phase 0).
    fn trig(self, phase: u32) -> Self {
        if self.is_empty() {
            return self;
        }
        let unit = Self::raw(-T::ONE, T::ONE);
        let f = |v: T| if phase == 1 { v.m_sin() } else { v.m_cos() };
        // Widens r = f(v) outward (exact at v = 0).
        let bound = |v: T, r: T, up: bool| {
            if v == T::ZERO {
                r // exact: sin 0 = 0, cos 0 = 1
            } else if up {
                r.next_up_n(T::TRANSCENDENTAL_STEPS).min(T::ONE)
            } else {
                r.next_down_n(T::TRANSCENDENTAL_STEPS).max(-T::ONE)
            }
        };
        let (a, b) = (self.lo, self.hi);
        let fa = f(a);
        if fa.is_nan() {
            // an infinite end, or beyond the reach of the GPU's own sine
            // (`|x| ≥ 2²⁸` on SPIR-V, `ia-core`'s `math`)
            return unit;
        }
        if a == b {
            return Self::raw(bound(a, fa, false), bound(a, fa, true));
        }
        // Beyond this, consecutive floats may be more than a quarter period
        // apart, so the critical points cannot be placed.
        let limit = T::from_f64((1u64 << (T::MANTISSA_DIGITS - 3)) as f64);
        if !(a.abs() < limit && b.abs() < limit) {
            return unit;
        }
        // [qa, qb] ⊇ [a, b]·2/π, with 2/π itself enclosed.
        let two_over_pi = Self::raw(T::FRAC_2_PI.next_down(), T::FRAC_2_PI.next_up());
        let qa = (Self::point(a) * two_over_pi).lo;
        let qb = (Self::point(b) * two_over_pi).hi;
        let four = T::from_f64(4.0);
        if qb - qa >= four {
            return unit;
        }
        // The critical points are the integers n in [qa, qb] (at most 5).
        let (mut has_max, mut has_min) = (false, false);
        let mut n = qa.ceil();
        while n <= qb {
            // n mod 4, exact: |n| < 2^(p−2).
            let r = (n - four * (n / four).floor()).to_u32().unwrap_or(0);
            has_max |= r == phase;
            has_min |= r == phase + 2;
            n = n + T::ONE;
        }
        let fb = f(b);
        if fb.is_nan() {
            return unit;
        }
        let lo = if has_min {
            -T::ONE
        } else {
            bound(a, fa, false).min(bound(b, fb, false))
        };
        let hi = if has_max {
            T::ONE
        } else {
            bound(a, fa, true).max(bound(b, fb, true))
        };
        Self::raw(lo, hi)
    }

    /// `|x|`: `[mig, mag]` (exact).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn abs(self) -> Self {
        if self.is_empty() {
            return self;
        }
        Self::raw(self.mig(), self.mag())
    }

    /// Pointwise minimum `{ min(x, y) }`: `[min(a, c), min(b, d)]` (exact).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn min(self, other: Self) -> Self {
        if self.is_empty() || other.is_empty() {
            return Self::EMPTY;
        }
        Self::raw(self.lo.min(other.lo), self.hi.min(other.hi))
    }

    /// Pointwise maximum `{ max(x, y) }`: `[max(a, c), max(b, d)]` (exact).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn max(self, other: Self) -> Self {
        if self.is_empty() || other.is_empty() {
            return Self::EMPTY;
        }
        Self::raw(self.lo.max(other.lo), self.hi.max(other.hi))
    }
}

impl<T: Real> Neg for Interval<T> {
    type Output = Self;
    /// `−x = [−b, −a]` (exact; the empty set stays empty).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn neg(self) -> Self {
        Self {
            lo: -self.hi,
            hi: -self.lo,
        }
    }
}

impl<T: Real> Add for Interval<T> {
    type Output = Self;
    /// `[a + c, b + d]`, each bound rounded outward.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn add(self, rhs: Self) -> Self {
        if self.is_empty() || rhs.is_empty() {
            return Self::EMPTY;
        }
        // −∞ + ∞ cannot occur: lo < +∞ and hi > −∞.
        Self::raw(add_down(self.lo, rhs.lo), add_up(self.hi, rhs.hi))
    }
}

impl<T: Real> Sub for Interval<T> {
    type Output = Self;
    /// `[a − d, b − c]`, each bound rounded outward.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn sub(self, rhs: Self) -> Self {
        if self.is_empty() || rhs.is_empty() {
            return Self::EMPTY;
        }
        Self::raw(sub_down(self.lo, rhs.hi), sub_up(self.hi, rhs.lo))
    }
}

/// Sign class of a non-empty interval for the product and quotient tables.
#[derive(Clone, Copy, PartialEq)]
enum Class {
    /// `[0, 0]`.
    Z,
    /// `a = 0 < b`.
    P0,
    /// `a > 0`.
    P1,
    /// `a < 0 = b`.
    N0,
    /// `b < 0`.
    N1,
    /// `a < 0 < b`.
    M,
}

impl<T: Real> Interval<T> {
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn class(self) -> Class {
        let (a, b) = (self.lo, self.hi);
        if a > T::ZERO {
            Class::P1
        } else if b < T::ZERO {
            Class::N1
        } else if a == T::ZERO {
            if b == T::ZERO { Class::Z } else { Class::P0 }
        } else if b == T::ZERO {
            Class::N0
        } else {
            Class::M
        }
    }
}

impl<T: Real> Mul for Interval<T> {
    type Output = Self;
    /// Product by sign classes (`P`: `a ≥ 0`, `N`: `b ≤ 0`, `M`: `a < 0 < b`,
    /// `Z`: `[0, 0]`), `x = [a, b]`, `y = [c, d]`:
    ///
    /// | `x \ y` | P | M | N |
    /// | --- | --- | --- | --- |
    /// | **P** | `[ac, bd]` | `[bc, bd]` | `[bc, ad]` |
    /// | **M** | `[ad, bd]` | `[min(ad, bc), max(ac, bd)]` | `[bc, ac]` |
    /// | **N** | `[ad, bc]` | `[ad, ac]` | `[bd, ac]` |
    ///
    /// and `Z · y = [0, 0]` for any non-empty `y` (also unbounded). In each
    /// cell, `0 · ∞` cannot arise; products are rounded outward.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn mul(self, rhs: Self) -> Self {
        use Class::*;
        if self.is_empty() || rhs.is_empty() {
            return Self::EMPTY;
        }
        let (a, b, c, d) = (self.lo, self.hi, rhs.lo, rhs.hi);
        let (x, y) = (self.class(), rhs.class());
        if x == Z || y == Z {
            return Self::point(T::ZERO);
        }
        let pos = |k: Class| k == P0 || k == P1;
        let neg = |k: Class| k == N0 || k == N1;
        // The operands of the lower and the upper bound by cell; each
        // product is written once (a GPU driver inlines every call, so the
        // number of call sites is the shader's size: BENCHMARKS.md "GPU").
        let (lo_ops, hi_ops) = if pos(x) {
            if pos(y) {
                ((a, c), (b, d)) // P * P => [a*c, b*d]
            } else if neg(y) {
                ((b, c), (a, d)) // P * N => [b*c, a*d]
            } else {
                ((b, c), (b, d)) // P * M => [b*c, b*d]
            }
        } else if neg(x) {
            if pos(y) {
                ((a, d), (b, c)) // N * P => [a*d, b*c]
            } else if neg(y) {
                ((b, d), (a, c)) // N * N => [b*d, a*c]
            } else {
                ((a, d), (a, c)) // N * M => [a*d, a*c]
            }
        } else if pos(y) {
            ((a, d), (b, d)) // M * P => [a*d, b*d]
        } else if neg(y) {
            ((b, c), (a, c)) // M * N => [b*c, a*c]
        } else {
            ((a, d), (a, c)) // M * M => [min(a*d, b*c), max(a*c, b*d)]
        };
        let mut lo = mul_down(lo_ops.0, lo_ops.1);
        let mut hi = mul_up(hi_ops.0, hi_ops.1);
        if !pos(x) && !neg(x) && !pos(y) && !neg(y) {
            lo = lo.min(mul_down(b, c));
            hi = hi.max(mul_up(b, d));
        }
        Self::raw(lo, hi)
    }
}

impl<T: Real> Div for Interval<T> {
    type Output = Self;
    /// Quotient, IEEE 1788 semantics: `x / y = hull{ ξ/η : ξ ∈ x, η ∈ y, η ≠ 0 }`.
    ///
    /// Classes: `P1`: `a > 0`; `P0`: `a = 0 < b`; `N1`: `b < 0`;
    /// `N0`: `a < 0 = b`; `M`: `a < 0 < b`; `Z`: `[0, 0]`;
    /// `x = [a, b]`, `y = [c, d]`:
    ///
    /// | `x \ y` | P1 | N1 | P0 | N0 | M |
    /// | --- | --- | --- | --- | --- | --- |
    /// | **P1** | `[a/d, b/c]` | `[b/d, a/c]` | `[a/d, +∞]` | `[−∞, a/c]` | ENTIRE |
    /// | **P0** | `[a/d, b/c]` | `[b/d, a/c]` | `[0, +∞]` | `[−∞, 0]` | ENTIRE |
    /// | **M** | `[a/c, b/c]` | `[b/d, a/d]` | ENTIRE | ENTIRE | ENTIRE |
    /// | **N0** | `[a/c, b/d]` | `[b/c, a/d]` | `[−∞, 0]` | `[0, +∞]` | ENTIRE |
    /// | **N1** | `[a/c, b/d]` | `[b/c, a/d]` | `[−∞, b/d]` | `[b/c, +∞]` | ENTIRE |
    ///
    /// `x / [0, 0] = EMPTY`, `[0, 0] / y = [0, 0]` otherwise; an empty operand
    /// gives `EMPTY`. No cell divides `∞/∞` or `0/0`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn div(self, rhs: Self) -> Self {
        use Class::*;
        if self.is_empty() || rhs.is_empty() {
            return Self::EMPTY;
        }
        let (a, b, c, d) = (self.lo, self.hi, rhs.lo, rhs.hi);
        let (x, y) = (self.class(), rhs.class());
        if y == Z {
            return Self::EMPTY;
        }
        if x == Z {
            return Self::point(T::ZERO);
        }
        // Each bound is a quotient `n / m` or a constant; the quotients are
        // written once (see `mul`).
        let (inf, ninf, zero) = (T::INFINITY, T::NEG_INFINITY, T::ZERO);
        let q = |n: T, m: T| (n, m, None);
        let k = |v: T| (zero, T::ONE, Some(v));
        let (lo, hi) = match (x, y) {
            // y > 0
            (P0 | P1, P1) => (q(a, d), q(b, c)),
            (M, P1) => (q(a, c), q(b, c)),
            (N0 | N1, P1) => (q(a, c), q(b, d)),
            // y < 0
            (P0 | P1, N1) => (q(b, d), q(a, c)),
            (M, N1) => (q(b, d), q(a, d)),
            (N0 | N1, N1) => (q(b, c), q(a, d)),
            // y = [0, d]
            (P1, P0) => (q(a, d), k(inf)),
            (P0, P0) => (k(zero), k(inf)),
            (N0, P0) => (k(ninf), k(zero)),
            (N1, P0) => (k(ninf), q(b, d)),
            // y = [c, 0]
            (P1, N0) => (k(ninf), q(a, c)),
            (P0, N0) => (k(ninf), k(zero)),
            (N0, N0) => (k(zero), k(inf)),
            (N1, N0) => (q(b, c), k(inf)),
            // y straddles 0, or x straddles 0 and y touches it
            _ => (k(ninf), k(inf)),
        };
        let lo = match lo.2 {
            Some(v) => v,
            None => div_down(lo.0, lo.1),
        };
        let hi = match hi.2 {
            Some(v) => v,
            None => div_up(hi.0, hi.1),
        };
        Self::raw(lo, hi)
    }
}

macro_rules! scalar_ops {
    ($($op:ident $f:ident),*) => {$(
        impl<T: Real> $op<T> for Interval<T> {
            type Output = Self;
            /// The interval operation with the point interval `[rhs, rhs]`
            /// (a NaN or infinite scalar is no real number: `EMPTY`).
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn $f(self, rhs: T) -> Self {
                self.$f(Self::point(rhs))
            }
        }
    )*};
}
scalar_ops!(Add add, Sub sub, Mul mul, Div div);

macro_rules! scalar_lhs_ops {
    ($($t:ty),*) => {$(
        impl Add<Interval<$t>> for $t {
            type Output = Interval<$t>;
            /// `[self, self] + rhs`.
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn add(self, rhs: Interval<$t>) -> Interval<$t> {
                Interval::point(self) + rhs
            }
        }
        impl Sub<Interval<$t>> for $t {
            type Output = Interval<$t>;
            /// `[self, self] − rhs`.
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn sub(self, rhs: Interval<$t>) -> Interval<$t> {
                Interval::point(self) - rhs
            }
        }
        impl Mul<Interval<$t>> for $t {
            type Output = Interval<$t>;
            /// `[self, self] · rhs`.
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn mul(self, rhs: Interval<$t>) -> Interval<$t> {
                Interval::point(self) * rhs
            }
        }
        impl Div<Interval<$t>> for $t {
            type Output = Interval<$t>;
            /// `[self, self] / rhs`.
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn div(self, rhs: Interval<$t>) -> Interval<$t> {
                Interval::point(self) / rhs
            }
        }
    )*};
}
scalar_lhs_ops!(f32, f64);

#[cfg(test)]
mod tests {
    use super::*;

    type I = Interval<f64>;

    fn iv(a: f64, b: f64) -> I {
        I::new(a, b)
    }

    const INF: f64 = f64::INFINITY;

    #[test]
    fn constructor_case_table() {
        assert_eq!(iv(1.0, 2.0).lo(), 1.0);
        assert!(iv(2.0, 1.0).is_empty());
        assert!(iv(f64::NAN, 1.0).is_empty());
        assert!(iv(1.0, f64::NAN).is_empty());
        assert!(iv(INF, INF).is_empty());
        assert!(iv(-INF, -INF).is_empty());
        assert!(iv(-INF, INF).is_entire());
        assert!(I::point(INF).is_empty());
        assert!(I::default().is_empty());
    }

    #[test]
    fn set_operations() {
        assert_eq!(iv(1.0, 2.0).hull(iv(4.0, 5.0)), iv(1.0, 5.0));
        assert_eq!(I::EMPTY.hull(iv(4.0, 5.0)), iv(4.0, 5.0));
        assert!(iv(1.0, 2.0).intersection(iv(3.0, 4.0)).is_empty());
        assert_eq!(iv(1.0, 3.0).intersection(iv(2.0, 4.0)), iv(2.0, 3.0));
        assert!(iv(1.0, 2.0).subset(iv(0.0, 2.0)));
        assert!(I::EMPTY.subset(iv(0.0, 0.0)));
        assert!(!iv(-1.0, 2.0).subset(iv(0.0, 2.0)));
    }

    #[test]
    fn numeric_functions() {
        assert_eq!(iv(-3.0, 1.0).mag(), 3.0);
        assert_eq!(iv(-3.0, 1.0).mig(), 0.0);
        assert_eq!(iv(-3.0, -1.0).mig(), 1.0);
        assert_eq!(iv(1.0, 3.0).mid(), 2.0);
        assert_eq!(I::ENTIRE.mid(), 0.0);
        assert_eq!(iv(-INF, 0.0).mid(), -f64::MAX);
        assert_eq!(iv(0.0, INF).mid(), f64::MAX);
        assert_eq!(iv(-f64::MAX, f64::MAX).mid(), 0.0);
        assert_eq!(iv(f64::MAX / 2.0, f64::MAX).mid(), 0.75 * f64::MAX);
        assert_eq!(iv(1.0, 3.0).rad(), 1.0);
        assert_eq!(iv(1.0, 3.0).width(), 2.0);
        assert!(I::EMPTY.width().is_nan() && I::EMPTY.mag().is_nan());
        assert_eq!(iv(0.0, INF).width(), INF);
    }

    #[test]
    fn multiplication_case_table() {
        // One case per cell of the table, with exact products.
        let near = |x: I, a: f64, b: f64| {
            assert!(
                x.lo() <= a && x.lo() >= a.next_down(),
                "{x:?} vs [{a}, {b}]"
            );
            assert!(x.hi() >= b && x.hi() <= b.next_up(), "{x:?} vs [{a}, {b}]");
        };
        near(iv(1.0, 2.0) * iv(3.0, 4.0), 3.0, 8.0); // P P
        near(iv(1.0, 2.0) * iv(-3.0, 4.0), -6.0, 8.0); // P M
        near(iv(1.0, 2.0) * iv(-4.0, -3.0), -8.0, -3.0); // P N
        near(iv(-1.0, 2.0) * iv(3.0, 4.0), -4.0, 8.0); // M P
        near(iv(-1.0, 2.0) * iv(-3.0, 4.0), -6.0, 8.0); // M M
        near(iv(-1.0, 2.0) * iv(-4.0, -3.0), -8.0, 4.0); // M N
        near(iv(-2.0, -1.0) * iv(3.0, 4.0), -8.0, -3.0); // N P
        near(iv(-2.0, -1.0) * iv(-3.0, 4.0), -8.0, 6.0); // N M
        near(iv(-2.0, -1.0) * iv(-4.0, -3.0), 3.0, 8.0); // N N
        // Z * anything, also unbounded.
        assert_eq!(iv(0.0, 0.0) * I::ENTIRE, iv(0.0, 0.0));
        // 0 at an endpoint times an unbounded interval.
        assert_eq!(iv(0.0, 1.0) * iv(2.0, INF), iv(0.0, INF));
        assert_eq!(iv(0.0, 1.0) * I::ENTIRE, I::ENTIRE);
        assert!((I::EMPTY * iv(1.0, 2.0)).is_empty());
    }

    #[test]
    fn division_case_table() {
        let near = |x: I, a: f64, b: f64| {
            let ok_lo = x.lo() == a || (x.lo() < a && x.lo() >= a.next_down());
            let ok_hi = x.hi() == b || (x.hi() > b && x.hi() <= b.next_up());
            assert!(ok_lo && ok_hi, "{x:?} vs [{a}, {b}]");
        };
        near(iv(1.0, 2.0) / iv(4.0, 8.0), 0.125, 0.5); // P1 / P1
        near(iv(0.0, 2.0) / iv(4.0, 8.0), 0.0, 0.5); // P0 / P1
        near(iv(-1.0, 2.0) / iv(4.0, 8.0), -0.25, 0.5); // M / P1
        near(iv(-2.0, -1.0) / iv(4.0, 8.0), -0.5, -0.125); // N1 / P1
        near(iv(1.0, 2.0) / iv(-8.0, -4.0), -0.5, -0.125); // P1 / N1
        near(iv(-1.0, 2.0) / iv(-8.0, -4.0), -0.5, 0.25); // M / N1
        near(iv(-2.0, -1.0) / iv(-8.0, -4.0), 0.125, 0.5); // N1 / N1
        near(iv(1.0, 2.0) / iv(0.0, 4.0), 0.25, INF); // P1 / P0
        near(iv(0.0, 2.0) / iv(0.0, 4.0), 0.0, INF); // P0 / P0
        near(iv(-2.0, 0.0) / iv(0.0, 4.0), -INF, 0.0); // N0 / P0
        near(iv(-2.0, -1.0) / iv(0.0, 4.0), -INF, -0.25); // N1 / P0
        near(iv(1.0, 2.0) / iv(-4.0, 0.0), -INF, -0.25); // P1 / N0
        near(iv(0.0, 2.0) / iv(-4.0, 0.0), -INF, 0.0); // P0 / N0
        near(iv(-2.0, 0.0) / iv(-4.0, 0.0), 0.0, INF); // N0 / N0
        near(iv(-2.0, -1.0) / iv(-4.0, 0.0), 0.25, INF); // N1 / N0
        assert!((iv(1.0, 2.0) / iv(-1.0, 1.0)).is_entire()); // P1 / M
        assert!((iv(-1.0, 2.0) / iv(0.0, 1.0)).is_entire()); // M / P0
        assert!((iv(1.0, 2.0) / iv(0.0, 0.0)).is_empty()); // x / Z
        assert_eq!(iv(0.0, 0.0) / iv(-1.0, 1.0), iv(0.0, 0.0)); // Z / y
        near(iv(1.0, INF) / iv(1.0, INF), 0.0, INF);
        near(iv(1.0, 2.0) / 4.0, 0.25, 0.5);
        near(1.0 / iv(2.0, 4.0), 0.25, 0.5);
    }

    #[test]
    fn recip_and_powers() {
        assert!(iv(0.0, 0.0).recip().is_empty());
        assert!(iv(-1.0, 1.0).recip().is_entire());
        assert_eq!(iv(0.0, 2.0).recip().hi(), INF);
        assert_eq!(iv(-2.0, 3.0).powi(0), iv(1.0, 1.0));
        assert_eq!(iv(-2.0, 3.0).powi(2).lo(), 0.0);
        assert!(iv(-2.0, 3.0).powi(2).contains(9.0));
        assert!(iv(-2.0, 3.0).powi(3).contains(-8.0));
        assert!(iv(-2.0, 3.0).powi(3).contains(27.0));
        assert!(iv(0.0, 0.0).powi(-2).is_empty());
        assert!(iv(-1.0, 1.0).powi(-1).is_entire());
        let r = iv(-1.0, 1.0).powi(-2);
        assert!(r.lo() <= 1.0 && r.hi() == INF);
        assert!(iv(2.0, 3.0).powi(i32::MIN).contains(0.0));
        // (1/x)^m keeps negative powers of huge numbers tight.
        let big = I::point(f64::MAX).powi(-2);
        assert_eq!((big.lo(), big.hi()), (0.0, f64::from_bits(1)));
        assert!(iv(-4.0, 4.0).sqrt().contains(2.0));
        assert_eq!(iv(-4.0, 4.0).sqrt().lo(), 0.0);
        assert!(iv(-4.0, -1.0).sqrt().is_empty());
        assert!(iv(4.0, 9.0).pow(0.5).contains(2.0));
        assert!(iv(4.0, 9.0).pow(-0.5).contains(1.0 / 3.0));
        assert!(iv(-4.0, 0.0).pow(-1.0).is_empty());
        assert_eq!(iv(0.0, 2.0).pow(0.0), iv(1.0, 1.0));
        assert!(iv(0.0, 2.0).pow(f64::NAN).is_empty());
        assert!(iv(0.0, 2.0).pow(-1.0).hi() == INF);
        // 2^31 does not fit an i32: libm's pow, not a silent powi(0).
        assert_eq!(
            Interval::new(0.0f32, 0.0).pow(2147483600.0),
            Interval::new(0.0, 0.0)
        );
        assert!(Interval::new(1.0f32, 2.0).pow(2147483600.0).hi() == f32::INFINITY);
        // Reals in (0, MIN_SUBNORMAL) are in [0, 2]: x^−0.001 is unbounded.
        assert_eq!(iv(0.0, 2.0).pow(-0.001).hi(), INF);
        assert!(iv(0.0, 0.0).pow(-0.5).is_empty());
        assert_eq!(iv(0.0, 0.0).pow(0.5), iv(0.0, 0.0));
    }

    #[test]
    fn transcendental_exact_points() {
        assert_eq!(iv(0.0, 0.0).exp(), iv(1.0, 1.0));
        assert_eq!(iv(-INF, 0.0).exp(), iv(0.0, 1.0));
        assert_eq!(iv(1.0, 1.0).ln(), iv(0.0, 0.0));
        assert_eq!(iv(0.0, 1.0).ln(), iv(-INF, 0.0));
        assert!(iv(-2.0, 0.0).ln().is_empty());
        assert_eq!(iv(0.0, 0.0).sin(), iv(0.0, 0.0));
        assert_eq!(iv(0.0, 0.0).cos(), iv(1.0, 1.0));
        assert!(iv(1.0, 2.0).exp().contains(1f64.exp()));
        assert!(iv(1.0, 2.0).ln().contains(2f64.ln()));
    }

    #[test]
    fn trig_extrema() {
        let s = iv(0.0, 2.0).sin(); // contains π/2
        assert_eq!(s.hi(), 1.0);
        assert!(s.lo() <= 0.0 && s.lo() > -1e-15);
        let c = iv(3.0, 3.5).cos(); // contains π
        assert_eq!(c.lo(), -1.0);
        assert!(iv(-INF, 0.0).sin() == iv(-1.0, 1.0));
        assert_eq!(iv(0.0, 10.0).cos(), iv(-1.0, 1.0));
        // Monotone piece: no extremum inside.
        let m = iv(0.1, 0.2).sin();
        assert!(m.contains(0.1f64.sin()) && m.contains(0.2f64.sin()) && m.hi() < 0.2);
        // A huge point is evaluated, not widened to [-1, 1].
        let p = I::point(1e300).sin();
        assert!(p.width() < 1e-15 && p.contains(1e300f64.sin()));
    }

    #[test]
    fn abs_min_max() {
        assert_eq!(iv(-3.0, 1.0).abs(), iv(0.0, 3.0));
        assert_eq!(iv(-3.0, -1.0).abs(), iv(1.0, 3.0));
        assert_eq!(iv(1.0, 5.0).min(iv(2.0, 3.0)), iv(1.0, 3.0));
        assert_eq!(iv(1.0, 5.0).max(iv(2.0, 3.0)), iv(2.0, 5.0));
        assert!(iv(1.0, 5.0).max(I::EMPTY).is_empty());
        assert_eq!(-iv(1.0, 2.0), iv(-2.0, -1.0));
        assert!((-I::EMPTY).is_empty());
    }

    #[test]
    fn f32_works_too() {
        let x = Interval::new(1.0f32, 2.0);
        let y = (x * x + 1.0).sqrt().exp().ln();
        assert!(y.contains(2.0f32.sqrt()) && y.contains(5.0f32.sqrt()));
    }
}
