//! [`Affine`]: revised affine arithmetic (Fryazinov, Pasko and Comninos 2010).

use core::ops::{Add, Div, Mul, Neg, Sub};

use crate::Interval;
use crate::Real;
#[cfg(not(target_arch = "spirv"))]
use crate::round::sum_residual;
use crate::round::{add_down, add_up, mul_down, mul_up, product_is_exact, sub_down, sub_up};

/// A revised affine form `x̂ = x₀ + Σᵢ xᵢ·εᵢ + e·[−1, 1]` over `N` noise symbols.
///
/// Revised affine arithmetic (RAA; Fryazinov, Pasko and Comninos 2010, as
/// used in the thesis Part II §2.2.2 and the forward-inclusion paper §3)
/// keeps the first-order dependence on `N` shared noise symbols `εᵢ ∈ [−1, 1]`
/// and folds everything else — nonlinear terms, linearisation errors and
/// **every floating-point rounding error** — into one non-negative error term
/// `e`. For ray tracing `N = 1` and `ε₀` is the ray parameter mapped to
/// `[−1, 1]` ([`Affine::variable`]).
///
/// **Soundness**: for every assignment of the noise symbols that the operands
/// stand for, the exact real result of an operation lies in the result form
/// evaluated at the same symbols, widened by its error term. Rounding errors
/// of each computed coefficient are bounded by `ε_mach·|c| + MIN_SUBNORMAL`
/// (twice the true bound) and added to `e`; products with short significands
/// and, on CPUs, sums whose TwoSum residual is 0 are exact and add nothing.
///
/// # Representation invariant
///
/// Exactly one of:
/// - **bounded**: `x₀` and all `xᵢ` finite, `0 ≤ e < +∞`;
/// - **entire** ([`Affine::ENTIRE`]): `e = +∞`, `x₀ = xᵢ = 0` (any real);
/// - **empty** ([`Affine::EMPTY`]): `e = −∞`, `x₀ = xᵢ = 0` (no value, e.g.
///   `sqrt` of a negative form).
///
/// Any operation whose result would overflow becomes `ENTIRE`; NaN is never
/// stored.
///
/// ```
/// use boundtrace_ia_core::{Affine, Interval};
///
/// let t = Affine::<f64, 1>::variable(Interval::new(1.0, 3.0), 0); // 2 + ε₀
/// let f = (t - t).to_interval(); // dependencies cancel: exactly [0, 0]
/// assert_eq!((f.lo(), f.hi()), (0.0, 0.0));
/// let g = t.sqrt().to_interval();
/// assert!(g.contains(1.0) && g.contains(3f64.sqrt()) && g.width() < 0.8);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct Affine<T, const N: usize> {
    center: T,
    coeffs: [T; N],
    err: T,
}

/// Twice an upper bound of the rounding error of a round-to-nearest result
/// `c`: the error is at most `ε_mach/2·|c|` (normal `c`) or
/// `MIN_SUBNORMAL/2` (subnormal `c`), and this returns at least twice that.
#[cfg_attr(not(target_arch = "spirv"), inline)]
fn rnd<T: Real>(c: T) -> T {
    c.abs() * T::EPSILON + T::MIN_SUBNORMAL
}

/// Accumulates the error term of a result.
///
/// Sound terms (scaled input errors, linearisation errors) are summed with
/// upward rounding. Rounding errors are summed as [`rnd`] bounds with plain
/// round-to-nearest additions: each bound is twice the true error, and a
/// sum of `k` non-negative terms loses at most a factor `(1 − u)^(k−1)`, far
/// less than that slack — so one upward-rounded addition at the end is enough.
struct Errors<T> {
    sound: T,
    rounding: T,
}

impl<T: Real> Errors<T> {
    /// Starts from a sound (already upward-rounded) error term.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn new(sound: T) -> Self {
        Self {
            sound,
            rounding: T::ZERO,
        }
    }

    /// `fl(a + b)`, recording its rounding error (none when exact: an operand
    /// is 0, or on CPUs when the TwoSum residual is 0).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn sum(&mut self, a: T, b: T) -> T {
        let s = a + b;
        if a == T::ZERO || b == T::ZERO {
            return s;
        }
        #[cfg(not(target_arch = "spirv"))]
        if sum_residual(a, b, s) == T::ZERO {
            return s;
        }
        self.rounding = self.rounding + rnd(s);
        s
    }

    /// `fl(a · b)`, recording its rounding error (none when exact).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn prod(&mut self, a: T, b: T) -> T {
        let p = a * b;
        if a == T::ZERO || b == T::ZERO || product_is_exact(a, b, p) {
            return p;
        }
        self.rounding = self.rounding + rnd(p);
        p
    }

    /// Adds a sound non-negative error term.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn add(&mut self, e: T) {
        self.sound = add_up(self.sound, e);
    }

    /// The total error bound, rounded up.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn total(&self) -> T {
        add_up(self.sound, self.rounding)
    }
}

impl<T: Real, const N: usize> Default for Affine<T, N> {
    /// The empty form.
    fn default() -> Self {
        Self::EMPTY
    }
}

impl<T: Real, const N: usize> Affine<T, N> {
    /// The empty form (no value).
    pub const EMPTY: Self = Self {
        center: T::ZERO,
        coeffs: [T::ZERO; N],
        err: T::NEG_INFINITY,
    };

    /// The form that stands for any real number.
    pub const ENTIRE: Self = Self {
        center: T::ZERO,
        coeffs: [T::ZERO; N],
        err: T::INFINITY,
    };

    /// The constant `x` (`EMPTY` for NaN or `±∞`, as [`Interval::point`]).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn constant(x: T) -> Self {
        if !x.is_finite() {
            return Self::EMPTY;
        }
        Self {
            center: x,
            coeffs: [T::ZERO; N],
            err: T::ZERO,
        }
    }

    /// A form covering `iv` with no dependence on the noise symbols:
    /// `mid ± rad` in the error term. Unbounded intervals give `ENTIRE`,
    /// the empty interval `EMPTY`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn from_interval(iv: Interval<T>) -> Self {
        if iv.is_empty() {
            return Self::EMPTY;
        }
        if !iv.is_bounded() {
            return Self::ENTIRE;
        }
        Self::finish(iv.mid(), [T::ZERO; N], iv.rad())
    }

    /// The input variable `x ∈ iv` as noise symbol `k`: `x̂ = mid + rad·ε_k`
    /// (`rad` rounded up, so every `x ∈ iv` has an `ε_k ∈ [−1, 1]`).
    ///
    /// If `k ≥ N` there is no such symbol and the interval goes into the error
    /// term instead (as [`from_interval`](Self::from_interval)).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn variable(iv: Interval<T>, k: usize) -> Self {
        let mut x = Self::from_interval(iv);
        if k < N && x.is_bounded() {
            x.coeffs[k] = x.err;
            x.err = T::ZERO;
        }
        x
    }

    /// Normalises a computed form: any non-finite part makes it `ENTIRE`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn finish(center: T, coeffs: [T; N], err: T) -> Self {
        let mut finite = center.is_finite() && err.is_finite();
        let mut i = 0;
        while i < N {
            finite &= coeffs[i].is_finite();
            i += 1;
        }
        if finite {
            Self {
                center,
                coeffs,
                err: err.max(T::ZERO),
            }
        } else {
            Self::ENTIRE
        }
    }

    /// The central value `x₀`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn center(&self) -> T {
        self.center
    }

    /// The noise-symbol coefficients `xᵢ`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn coeffs(&self) -> &[T; N] {
        &self.coeffs
    }

    /// The accumulated error term `e` (`+∞` for `ENTIRE`, `−∞` for `EMPTY`).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn err(&self) -> T {
        self.err
    }

    /// Whether this is the empty form.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn is_empty(&self) -> bool {
        self.err == T::NEG_INFINITY
    }

    /// Whether this is the form that stands for any real number.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn is_entire(&self) -> bool {
        self.err == T::INFINITY
    }

    /// Whether the form is bounded (neither empty nor entire).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn is_bounded(&self) -> bool {
        self.err.is_finite()
    }

    /// Total radius `Σ|xᵢ| + e`, rounded up.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn radius(&self) -> T {
        let mut r = self.err;
        let mut i = 0;
        while i < N {
            r = add_up(r, self.coeffs[i].abs());
            i += 1;
        }
        r
    }

    /// The range `[x₀ − r, x₀ + r]`, `r = Σ|xᵢ| + e`, rounded outward.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn to_interval(&self) -> Interval<T> {
        if self.is_empty() {
            return Interval::EMPTY;
        }
        if self.is_entire() {
            return Interval::ENTIRE;
        }
        let r = self.radius();
        Interval::new(sub_down(self.center, r), add_up(self.center, r))
    }

    /// The range at given noise-symbol values `eps` (each clamped to
    /// `[−1, 1]`): `x₀ + Σ xᵢ·epsᵢ ± e`, rounded outward.
    ///
    /// For a ray form built with [`variable`](Self::variable), `eps` is the
    /// ray parameter mapped to `[−1, 1]`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn eval(&self, eps: [T; N]) -> Interval<T> {
        if self.is_empty() {
            return Interval::EMPTY;
        }
        if self.is_entire() {
            return Interval::ENTIRE;
        }
        let mut v = Interval::point(self.center);
        let mut i = 0;
        while i < N {
            let e = if eps[i].is_nan() {
                T::ZERO
            } else {
                eps[i].max(-T::ONE).min(T::ONE)
            };
            v = v + Interval::point(self.coeffs[i]) * Interval::point(e);
            i += 1;
        }
        v + Interval::new(-self.err, self.err)
    }

    /// Shared empty/entire handling of binary operations; `None` when both
    /// operands are bounded.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn special2(self, rhs: Self) -> Option<Self> {
        if self.is_empty() || rhs.is_empty() {
            Some(Self::EMPTY)
        } else if self.is_entire() || rhs.is_entire() {
            Some(Self::ENTIRE)
        } else {
            None
        }
    }

    /// `self · s + t` for scalars: coefficients scaled by `s`, centre shifted
    /// by `t`, error term scaled by `|s|`; every rounding tracked.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn scale_shift(self, s: T, t: T) -> Self {
        if self.is_empty() || !s.is_finite() || !t.is_finite() {
            return Self::EMPTY;
        }
        if self.is_entire() {
            return if s == T::ZERO {
                Self::constant(t)
            } else {
                Self::ENTIRE
            };
        }
        let mut e = Errors::new(mul_up(self.err, s.abs()));
        let c = if s == T::ONE {
            self.center
        } else {
            e.prod(self.center, s)
        };
        let center = e.sum(c, t);
        let mut coeffs = self.coeffs;
        if s != T::ONE {
            let mut i = 0;
            while i < N {
                coeffs[i] = e.prod(coeffs[i], s);
                i += 1;
            }
        }
        Self::finish(center, coeffs, e.total())
    }

    /// `x²` (as `x · x`, which keeps the dependence: `x₀² + ½Σxᵢ²` centre).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn sqr(self) -> Self {
        self * self
    }

    /// Applies the linearisation `f(x) ∈ α·x + g` with `g ⊇ { f(x) − αx }`
    /// over the form's range: `α·x̂ + mid(g) ± rad(g)`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn linearized(self, alpha: T, g: Interval<T>) -> Self {
        if g.is_empty() {
            return Self::EMPTY;
        }
        if !g.is_bounded() {
            return Self::ENTIRE;
        }
        let z = self.scale_shift(alpha, g.mid());
        if !z.is_bounded() {
            return z;
        }
        let mut e = Errors::new(z.err);
        e.add(g.rad());
        Self::finish(z.center, z.coeffs, e.total())
    }

    /// Chebyshev linearisation of a monotone, convex (`convex = true`) or
    /// concave function `f` on `x ∈ [a, b]`:
    ///
    /// - slope `α` = the secant `(f(b) − f(a)) / (b − a)` (any float is sound);
    /// - `g = f − α·id` is convex (concave), so its maximum (minimum) over
    ///   `[a, b]` is at an endpoint, enclosed by interval evaluation;
    /// - its minimum (maximum) is bounded by the tangent at `c` (`f'(c) ≈ α`):
    ///   `f(x) ≥ f(c) + f'(c)(x − c)` (convex), evaluated as
    ///   `f(c) − α·c + (f'(c) − α)·([a, b] − c)` in interval arithmetic.
    ///
    /// `fi`/`dfi` enclose `f`/`f'` at a point, `tangent_at(α)` gives the
    /// point where `f' = α` (clamped to `[a, b]` here).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn chebyshev(
        self,
        range: Interval<T>,
        convex: bool,
        fi: impl Fn(T) -> Interval<T>,
        dfi: impl Fn(T) -> Interval<T>,
        tangent_at: impl Fn(T) -> T,
    ) -> Self {
        if !range.is_bounded() {
            // The form is bounded but its range overflowed (an infinite end
            // is no point to evaluate f at): give up soundly.
            return Self::ENTIRE;
        }
        let (a, b) = (range.lo(), range.hi());
        let (fa, fb) = (fi(a), fi(b));
        if a == b {
            return Self::from_interval(fa);
        }
        if !(fa.is_bounded() && fb.is_bounded()) {
            // f unbounded on the range (exp overflow, ln at 0).
            return Self::ENTIRE;
        }
        let alpha = (fb.mid() - fa.mid()) / (b - a);
        if !alpha.is_finite() {
            // b − a underflowed: f is monotone, so its image is the hull.
            return Self::from_interval(fa.hull(fb));
        }
        let g_end = |v: T, f: Interval<T>| f - Interval::point(v) * alpha;
        let ends = g_end(a, fa).hull(g_end(b, fb));
        let mut c = tangent_at(alpha);
        if !(c >= a && c <= b) {
            c = range.mid();
        }
        let tangent =
            fi(c) - Interval::point(c) * alpha + (dfi(c) - alpha) * (range - Interval::point(c));
        if !tangent.is_bounded() {
            // c or f'(c) out of range (e.g. the tangent point of √ on a tiny
            // range overflowed to 0, where f' is unbounded): monotone hull.
            return Self::from_interval(fa.hull(fb));
        }
        let g = if convex {
            Interval::new(tangent.lo().min(ends.lo()), ends.hi())
        } else {
            Interval::new(ends.lo(), tangent.hi().max(ends.hi()))
        };
        self.linearized(alpha, g)
    }

    /// `e^x` (convex): Chebyshev linearisation over the form's range.
    /// Overflowing ranges give `ENTIRE`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn exp(self) -> Self {
        if !self.is_bounded() {
            return self;
        }
        let r = self.to_interval();
        self.chebyshev(
            r,
            true,
            |v| Interval::point(v).exp(),
            |v| Interval::point(v).exp(),
            |alpha| alpha.m_ln(),
        )
    }

    /// `√x` (concave) on the domain `x ≥ 0`: Chebyshev linearisation over the
    /// form's range restricted to `[0, ∞)`; `EMPTY` if the range is negative.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn sqrt(self) -> Self {
        if !self.is_bounded() {
            return if self.is_entire() { self } else { Self::EMPTY };
        }
        let r = self
            .to_interval()
            .intersection(Interval::new(T::ZERO, T::INFINITY));
        if r.is_empty() {
            return Self::EMPTY;
        }
        let half = Interval::point(T::HALF);
        self.chebyshev(
            r,
            false,
            |v| Interval::point(v).sqrt(),
            |v| half / Interval::point(v).sqrt(),
            |alpha| T::ONE / (T::TWO * T::TWO * alpha * alpha),
        )
    }

    /// Natural logarithm (concave) on the domain `x > 0`; a range reaching 0
    /// is unbounded below and gives `ENTIRE`, a non-positive one `EMPTY`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn ln(self) -> Self {
        if !self.is_bounded() {
            return if self.is_entire() { self } else { Self::EMPTY };
        }
        let r = self
            .to_interval()
            .intersection(Interval::new(T::ZERO, T::INFINITY));
        if r.is_empty() || r.hi() == T::ZERO {
            return Self::EMPTY;
        }
        self.chebyshev(
            r,
            false,
            |v| Interval::point(v).ln(),
            |v| Interval::point(v).recip(),
            |alpha| T::ONE / alpha,
        )
    }

    /// `1/x`: convex for `x > 0`, concave for `x < 0`, Chebyshev-linearised;
    /// a range containing 0 gives `ENTIRE` (`EMPTY` if it is exactly `[0, 0]`).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn recip(self) -> Self {
        if !self.is_bounded() {
            return if self.is_entire() { self } else { Self::EMPTY };
        }
        let r = self.to_interval();
        if r.contains(T::ZERO) {
            return Self::from_interval(r.recip());
        }
        let positive = r.lo() > T::ZERO;
        self.chebyshev(
            r,
            positive,
            |v| Interval::point(v).recip(),
            |v| -Interval::point(v).sqr().recip(),
            |alpha| {
                let m = (-T::ONE / alpha).m_sqrt();
                if positive { m } else { -m }
            },
        )
    }

    /// `|x|`: the form itself (or its negation) when its range has one sign;
    /// otherwise the Chebyshev line through `(a, |a|)`, `(b, |b|)`, with
    /// `|x| − αx ∈ [0, max(−a(1+α), b(1−α))]` since `|α| ≤ 1`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn abs(self) -> Self {
        if !self.is_bounded() {
            return self;
        }
        let r = self.to_interval();
        if r.lo() >= T::ZERO {
            return self;
        }
        if r.hi() <= T::ZERO {
            return -self;
        }
        if !r.is_bounded() {
            // Bounded form whose range overflowed: no finite line fits.
            return Self::ENTIRE;
        }
        let (a, b) = (r.lo(), r.hi());
        let alpha = ((b + a) / (b - a)).max(-T::ONE).min(T::ONE);
        let ia = Interval::point(a);
        let ib = Interval::point(b);
        // g(a) = |a| − αa, g(b) = |b| − αb; g(x) = |x| − αx ≥ 0 as |α| ≤ 1.
        let ends = (-ia - ia * alpha).hull(ib - ib * alpha);
        self.linearized(alpha, Interval::new(T::ZERO, ends.hi()))
    }

    /// Pointwise minimum: `x` or `y` when `x − y` has one sign, otherwise
    /// `½(x + y − |x − y|)`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn min(self, rhs: Self) -> Self {
        if let Some(s) = self.special2(rhs) {
            return s;
        }
        let d = self - rhs;
        let r = d.to_interval();
        if r.hi() <= T::ZERO {
            self
        } else if r.lo() >= T::ZERO {
            rhs
        } else {
            (self + rhs - d.abs()) * T::HALF
        }
    }

    /// Pointwise maximum: `x` or `y` when `x − y` has one sign, otherwise
    /// `½(x + y + |x − y|)`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn max(self, rhs: Self) -> Self {
        if let Some(s) = self.special2(rhs) {
            return s;
        }
        let d = self - rhs;
        let r = d.to_interval();
        if r.lo() >= T::ZERO {
            self
        } else if r.hi() <= T::ZERO {
            rhs
        } else {
            (self + rhs + d.abs()) * T::HALF
        }
    }
}

impl<T: Real, const N: usize> Neg for Affine<T, N> {
    type Output = Self;
    /// `−x̂`: all coefficients negated (exact).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn neg(self) -> Self {
        if !self.is_bounded() {
            return self;
        }
        let mut coeffs = self.coeffs;
        let mut i = 0;
        while i < N {
            coeffs[i] = -coeffs[i];
            i += 1;
        }
        Self {
            center: -self.center,
            coeffs,
            err: self.err,
        }
    }
}

impl<T: Real, const N: usize> Add for Affine<T, N> {
    type Output = Self;
    /// `(x₀ + y₀) + Σ(xᵢ + yᵢ)εᵢ ± (eₓ + e_y)`, plus the rounding errors.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn add(self, rhs: Self) -> Self {
        if let Some(s) = self.special2(rhs) {
            return s;
        }
        let mut e = Errors::new(add_up(self.err, rhs.err));
        let center = e.sum(self.center, rhs.center);
        let mut coeffs = self.coeffs;
        let mut i = 0;
        while i < N {
            coeffs[i] = e.sum(coeffs[i], rhs.coeffs[i]);
            i += 1;
        }
        Self::finish(center, coeffs, e.total())
    }
}

impl<T: Real, const N: usize> Sub for Affine<T, N> {
    type Output = Self;
    /// `x̂ + (−ŷ)`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn sub(self, rhs: Self) -> Self {
        self + (-rhs)
    }
}

impl<T: Real, const N: usize> Mul for Affine<T, N> {
    type Output = Self;
    /// RAA product (Fryazinov et al. 2010, eq. for `z = xy`):
    ///
    /// - `z₀ = x₀y₀ + ½ Σ xᵢyᵢ` (the mean of `xᵢyᵢεᵢ² ∈ [0, xᵢyᵢ]`),
    /// - `zᵢ = x₀yᵢ + y₀xᵢ`,
    /// - `e_z = |x₀|e_y + |y₀|eₓ + rₓr_y − ½ Σ|xᵢyᵢ|`, `r = Σ|xᵢ| + e`,
    ///
    /// plus all rounding errors, with `e_z` computed with upward rounding.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn mul(self, rhs: Self) -> Self {
        if let Some(s) = self.special2(rhs) {
            return s;
        }
        let (x0, y0) = (self.center, rhs.center);
        let mut e = Errors::new(T::ZERO);
        let mut diag = T::ZERO; // Σ xᵢyᵢ (rounding tracked)
        let mut diag_abs = T::ZERO; // Σ |xᵢyᵢ| rounded down
        let mut coeffs = [T::ZERO; N];
        let mut i = 0;
        while i < N {
            let (xi, yi) = (self.coeffs[i], rhs.coeffs[i]);
            let p = e.prod(xi, yi);
            diag = e.sum(diag, p);
            diag_abs = add_down(diag_abs, mul_down(xi.abs(), yi.abs()));
            let a = e.prod(x0, yi);
            let b = e.prod(y0, xi);
            coeffs[i] = e.sum(a, b);
            i += 1;
        }
        let p0 = e.prod(x0, y0);
        let half_diag = e.prod(diag, T::HALF);
        let center = e.sum(p0, half_diag);
        let cross = add_up(
            add_up(mul_up(x0.abs(), rhs.err), mul_up(y0.abs(), self.err)),
            mul_up(self.radius(), rhs.radius()),
        );
        let nonlinear = sub_up(cross, mul_down(diag_abs, T::HALF)).max(T::ZERO);
        e.add(nonlinear);
        Self::finish(center, coeffs, e.total())
    }
}

impl<T: Real, const N: usize> Div for Affine<T, N> {
    type Output = Self;
    /// `x̂ · recip(ŷ)`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    #[allow(clippy::suspicious_arithmetic_impl)] // x / y = x · (1/y) by design
    fn div(self, rhs: Self) -> Self {
        self * rhs.recip()
    }
}

impl<T: Real, const N: usize> Add<T> for Affine<T, N> {
    type Output = Self;
    /// Shifts the centre (a NaN or infinite scalar gives `EMPTY`).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn add(self, rhs: T) -> Self {
        self.scale_shift(T::ONE, rhs)
    }
}

impl<T: Real, const N: usize> Sub<T> for Affine<T, N> {
    type Output = Self;
    /// Shifts the centre (a NaN or infinite scalar gives `EMPTY`).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn sub(self, rhs: T) -> Self {
        self.scale_shift(T::ONE, -rhs)
    }
}

impl<T: Real, const N: usize> Mul<T> for Affine<T, N> {
    type Output = Self;
    /// Scales every term (a NaN or infinite scalar gives `EMPTY`).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn mul(self, rhs: T) -> Self {
        self.scale_shift(rhs, T::ZERO)
    }
}

impl<T: Real, const N: usize> Div<T> for Affine<T, N> {
    type Output = Self;
    /// `x̂ · recip([rhs])`; division by zero gives `EMPTY` (as for intervals).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    #[allow(clippy::suspicious_arithmetic_impl)] // x / s = x · (1/s) by design
    fn div(self, rhs: T) -> Self {
        self * Self::constant(rhs).recip()
    }
}

macro_rules! scalar_lhs_ops {
    ($($t:ty),*) => {$(
        impl<const N: usize> Add<Affine<$t, N>> for $t {
            type Output = Affine<$t, N>;
            /// `rhs + self`.
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn add(self, rhs: Affine<$t, N>) -> Affine<$t, N> {
                rhs + self
            }
        }
        impl<const N: usize> Sub<Affine<$t, N>> for $t {
            type Output = Affine<$t, N>;
            /// `(−rhs) + self`.
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn sub(self, rhs: Affine<$t, N>) -> Affine<$t, N> {
                -rhs + self
            }
        }
        impl<const N: usize> Mul<Affine<$t, N>> for $t {
            type Output = Affine<$t, N>;
            /// `rhs · self`.
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn mul(self, rhs: Affine<$t, N>) -> Affine<$t, N> {
                rhs * self
            }
        }
        impl<const N: usize> Div<Affine<$t, N>> for $t {
            type Output = Affine<$t, N>;
            /// `recip(rhs) · self`.
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            #[allow(clippy::suspicious_arithmetic_impl)] // s / y = (1/y) · s
            fn div(self, rhs: Affine<$t, N>) -> Affine<$t, N> {
                rhs.recip() * self
            }
        }
    )*};
}
scalar_lhs_ops!(f32, f64);

impl<T: Real, const N: usize> From<Interval<T>> for Affine<T, N> {
    /// [`Affine::from_interval`].
    fn from(iv: Interval<T>) -> Self {
        Self::from_interval(iv)
    }
}

impl<T: Real, const N: usize> From<Affine<T, N>> for Interval<T> {
    /// [`Affine::to_interval`].
    fn from(x: Affine<T, N>) -> Self {
        x.to_interval()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    type A = Affine<f64, 1>;
    type I = Interval<f64>;

    fn var(a: f64, b: f64) -> A {
        A::variable(I::new(a, b), 0)
    }

    #[test]
    fn construction() {
        let x = var(1.0, 3.0);
        assert_eq!((x.center(), x.coeffs()[0], x.err()), (2.0, 1.0, 0.0));
        assert!(A::constant(f64::NAN).is_empty());
        assert!(A::from_interval(I::ENTIRE).is_entire());
        assert!(A::from_interval(I::EMPTY).is_empty());
        let y = A::variable(I::new(1.0, 3.0), 5); // no symbol 5: error term
        assert_eq!((y.coeffs()[0], y.err()), (0.0, 1.0));
        assert_eq!(x.to_interval(), I::new(1.0, 3.0));
        assert!(A::default().is_empty());
    }

    #[test]
    fn linear_ops_cancel_dependencies() {
        let x = var(1.0, 3.0);
        assert_eq!((x - x).to_interval(), I::new(0.0, 0.0));
        let y = (x * 2.0 - x).to_interval();
        assert_eq!(y, I::new(1.0, 3.0));
        let z = (x * 0.1 - x * 0.1).to_interval(); // inexact products: tiny error
        assert!(z.contains(0.0) && z.width() < 1e-15);
        assert!((x + f64::NAN).is_empty());
        assert!((x + A::ENTIRE).is_entire());
        assert!((x + A::EMPTY).is_empty());
    }

    #[test]
    fn raa_product() {
        // (2 + ε)(2 + ε) = 4 + 4ε + ε²: centre 4.5, coeff 4, err 0.5 → [0, 9]
        let x = var(1.0, 3.0);
        let s = x.sqr();
        assert!(s.center() >= 4.5 && s.center() <= 4.5 + 1e-14);
        assert_eq!(s.coeffs()[0], 4.0);
        assert!(s.err() >= 0.5 && s.err() < 0.5 + 1e-14);
        let r = s.to_interval();
        assert!(r.lo() <= 0.0 && r.lo() > -1e-13 && r.hi() >= 9.0);
        // t² − 2t on [0, 2] in RAA: [−1.5, 0.5]-ish, tighter than IA's [−4, 4].
        let t = var(0.0, 2.0);
        let f = (t.sqr() - t * 2.0).to_interval();
        assert!(f.lo() <= -1.0 && f.hi() >= 0.0 && f.width() <= 2.0 + 1e-12);
    }

    #[test]
    fn nonlinear_ops_enclose_samples() {
        let x = var(0.5, 2.0);
        type Case = (fn(A) -> A, fn(f64) -> f64);
        let ops: [Case; 5] = [
            (A::exp, f64::exp),
            (A::sqrt, f64::sqrt),
            (A::ln, f64::ln),
            (A::recip, |v| 1.0 / v),
            (A::abs, f64::abs),
        ];
        for (op, f) in ops {
            let z = op(x);
            for k in 0..=20 {
                let eps = -1.0 + 0.1 * k as f64;
                let v = 1.25 + 0.75 * eps;
                assert!(z.eval([eps]).contains(f(v)), "{z:?} at {v}");
            }
        }
    }

    #[test]
    fn domains() {
        assert!(var(-2.0, -1.0).sqrt().is_empty());
        assert!(var(-2.0, -1.0).ln().is_empty());
        assert!(var(-1.0, 1.0).recip().is_entire());
        assert!(var(0.0, 1.0).ln().is_entire());
        assert!(var(-1.0, 4.0).sqrt().eval([1.0]).contains(2.0));
        assert!(var(1.0, 800.0).exp().is_entire());
        let n = var(-3.0, -1.0).recip();
        assert!(n.eval([-1.0]).contains(-1.0 / 3.0) && n.eval([1.0]).contains(-1.0));
    }

    #[test]
    fn min_max_abs() {
        let x = var(-1.0, 3.0);
        let c = A::constant(1.0);
        for k in 0..=20 {
            let eps = -1.0 + 0.1 * k as f64;
            let v = 1.0 + 2.0 * eps;
            assert!(x.abs().eval([eps]).contains(v.abs()));
            assert!(x.min(c).eval([eps]).contains(v.min(1.0)));
            assert!(x.max(c).eval([eps]).contains(v.max(1.0)));
        }
        assert_eq!(x.min(A::constant(5.0)), x);
        assert_eq!(x.max(A::constant(5.0)), A::constant(5.0));
    }

    #[test]
    fn regressions_from_the_property_tests() {
        // sqrt on [0, b] with tiny b: the tangent point overflowed to 0.
        let m = f64::MIN_POSITIVE;
        let x = var(-m, m);
        let eps = 1.0 / 16.0;
        let exact = (m * eps).sqrt();
        assert!(x.sqrt().eval([eps]).contains(exact));
        // abs/min/max of bounded forms whose range overflows.
        let big = A::variable(I::new(-f64::MAX, f64::MAX), 0);
        let shifted = big + 1.0; // range [−MAX, +∞]
        assert!(shifted.abs().eval([1.0]).hi() == f64::INFINITY);
        let y = var(0.0, 1.0);
        assert!(big.min(y).eval([1.0]).contains(1.0));
        assert!(big.max(y).eval([1.0]).contains(f64::MAX));
    }

    #[test]
    fn overflow_becomes_entire() {
        let x = A::variable(I::new(1e300, 1.1e300), 0);
        assert!((x * x).is_entire());
        assert!((x * f64::MAX).is_entire());
    }
}
