//! [`ForwardQuadratic`]: asymmetric quadratic forward inclusion functions
//! (forward-inclusion paper §6, App. B–C).

use crate::compose::{self, Composition, Line, Unary};
use crate::poly::{
    self, Side, add_hi, add_lo, add_sides_hi, add_sides_lo, div_hi, div_lo, max_hi, max_sides,
    min_sides, mul_hi, mul_lo, sub_hi, sub_lo,
};
use boundtrace_ia_core::round::sub_down;
use boundtrace_ia_core::{Interval, Real};
use core::ops::{Add, Div, Mul, Neg, Sub};

/// A quadratic forward inclusion function: bounds of a function `f` of the
/// ray parameter on `[t₀, t₀ + h]` (forward-inclusion paper eq. 18)
///
/// ```text
/// f₋(t) = s₋ + τ (a₋ + b₋ τ)  ≤  f(t)  ≤  f₊(t) = s₊ + τ (a₊ + b₊ τ),   τ = t − t₀ ∈ [0, h]
/// ```
///
/// **Exact at `t₀`** (paper eq. 5) up to rounding: `[s₋, s₊]` is the
/// enclosure of `f(t₀)` that [`Interval`] arithmetic computes at the point
/// `t₀` (its width is the *margin*, a few float steps; see the crate docs),
/// and the lower and upper quadratics are independent (asymmetric).
///
/// `h` is the **validity length**: an operation that is only valid on part
/// of the interval (a pole of `1/x` or `ln x`, a chord that cannot stay exact
/// at `t₀`, see [`Composition`]) shortens it instead of returning an infinite
/// bound (paper §4.2); [`validity`](Self::validity) reports it.
///
/// Arithmetic follows the bottom-up rules of §6.2: sums and scalar products
/// coefficient-wise; products as the four corner quartics reduced to
/// quadratics that keep value and slope at `t₀`; monotone convex/concave
/// functions by tangent and chord lines in the argument (App. B);
/// `max`/`min` by Bézier control points (App. C). Every coefficient is
/// rounded outward, so the bounds are sound in floating point.
///
/// Functions are evaluated with IEEE 1788 domain semantics: `sqrt` and a
/// non-integer [`powf`](Self::powf) bound `φ(max(x, 0))`, so they hold
/// wherever the exact expression is defined. An operation that is undefined
/// at `t₀` itself (`1/x` with `0` in the start enclosure, `ln` of a
/// non-positive start) makes the result *invalid*: [`is_valid`](Self::is_valid)
/// is `false` and its validity length `0`.
///
/// ```
/// use boundtrace_inclusion::ForwardQuadratic;
///
/// // f(t) = (t − 1)² − 0.25 on [0, 3]: a root at t = 0.5.
/// let t = ForwardQuadratic::<f64>::ray_param(0.0, 3.0);
/// let f = (t - 1.0).sqr() - 0.25;
/// assert!(f.start().contains(0.75)); // exact at t₀ = 0
/// let step = f.safe_step(); // never passes the root
/// assert!(step <= 0.5 && step > 0.5 - 1e-12);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct ForwardQuadratic<T> {
    start: Interval<T>,
    lo: [T; 2],
    hi: [T; 2],
    h: T,
    mode: ModeCode,
}

/// A [`Composition`] stored as its `u32` code, so that
/// `Option<ForwardQuadratic>` has a tag rather than a niche in this field:
/// rust-gpu 0.11 cannot move a value out of a niche-encoded enum ("cannot
/// memcpy dynamically sized data").
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(transparent)]
pub(crate) struct ModeCode(u32);

impl ModeCode {
    const DEFAULT: Self = Self(Composition::ValidityInterval as u32);

    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn get(self) -> Composition {
        Composition::from_code(self.0)
    }

    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn join(self, other: Self) -> Self {
        self.get().join(other.get()).into()
    }
}

impl From<Composition> for ModeCode {
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn from(c: Composition) -> Self {
        Self(c as u32)
    }
}

impl<T: Real> ForwardQuadratic<T> {
    /// The invalid bound (undefined at `t₀`).
    pub const INVALID: Self = Self {
        start: Interval::EMPTY,
        lo: [T::ZERO; 2],
        hi: [T::ZERO; 2],
        h: T::ZERO,
        mode: ModeCode::DEFAULT,
    };

    /// Builds a bound from its parts: start enclosure `[s₋, s₊]`, lower
    /// coefficients `(a₋, b₋)`, upper `(a₊, b₊)` and validity length `h`.
    ///
    /// The caller vouches that these bound the function; use the operators
    /// or [`taylor`](Self::taylor) to derive sound ones. A NaN part, a
    /// negative `h` or an empty start gives [`INVALID`](Self::INVALID).
    pub fn from_parts(start: Interval<T>, lo: [T; 2], hi: [T; 2], h: T) -> Self {
        let nan = lo[0].is_nan() || lo[1].is_nan() || hi[0].is_nan() || hi[1].is_nan();
        if start.is_empty() || nan || !(h >= T::ZERO) {
            return Self::INVALID;
        }
        Self {
            start,
            lo,
            hi,
            h,
            mode: ModeCode::DEFAULT,
        }
    }

    /// The constant `c` (valid on any interval: `h = +∞`).
    pub fn constant(c: T) -> Self {
        Self::from_parts(Interval::point(c), [T::ZERO; 2], [T::ZERO; 2], T::INFINITY)
    }

    /// The ray parameter `t` itself on `[t0, t1]`: value `t₀`, slope `1`.
    ///
    /// `h = t1 − t0` rounded down, so `t₀ + h ≤ t1`. Non-finite bounds or
    /// `t1 < t0` give [`INVALID`](Self::INVALID).
    pub fn ray_param(t0: T, t1: T) -> Self {
        Self::ray_param_with(t0, t1, Composition::default())
    }

    /// [`ray_param`](Self::ray_param) with a choice of [`Composition`]
    /// variant, which every bound computed from it inherits.
    pub fn ray_param_with(t0: T, t1: T, mode: Composition) -> Self {
        if !t0.is_finite() || !t1.is_finite() || t1 < t0 {
            return Self::INVALID;
        }
        let mut r = Self::from_parts(
            Interval::point(t0),
            [T::ONE, T::ZERO],
            [T::ONE, T::ZERO],
            sub_down(t1, t0),
        );
        r.mode = mode.into();
        r
    }

    /// Quadratic Taylor inclusion (paper §6.1, eq. 19): from an enclosure of
    /// `f(t₀)`, of `f'(t₀)` and of `f''` over the whole interval,
    /// `f(t₀) + τ (f'(t₀) + ½ f''(ξ±) τ)`. Sound when the inputs are
    /// enclosures; an empty input gives [`INVALID`](Self::INVALID).
    pub fn taylor(value: Interval<T>, d1: Interval<T>, d2: Interval<T>, h: T) -> Self {
        if value.is_empty() || d1.is_empty() || d2.is_empty() {
            return Self::INVALID;
        }
        Self::from_parts(
            value,
            [d1.lo(), mul_lo(d2.lo(), T::HALF)],
            [d1.hi(), mul_hi(d2.hi(), T::HALF)],
            h,
        )
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

    /// Lower coefficients `(a₋, b₋)`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn lower_coeffs(&self) -> [T; 2] {
        self.lo
    }

    /// Upper coefficients `(a₊, b₊)`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn upper_coeffs(&self) -> [T; 2] {
        self.hi
    }

    /// The validity length `h`: the bounds hold for `τ = t − t₀ ∈ [0, h]`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn validity(&self) -> T {
        self.h
    }

    /// The validity end `t₁' = t₀ + h`, rounded down (so `≤` the exact end).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn validity_end(&self, t0: T) -> T {
        boundtrace_ia_core::round::add_down(t0, self.h)
    }

    /// The [`Composition`] variant this bound was computed with.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn composition(&self) -> Composition {
        self.mode.get()
    }

    /// A sound enclosure `[f₋(τ), f₊(τ)]` at `τ = t − t₀` (rounded outward).
    /// Meaningful for `τ ∈ [0, h]`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn bounds_at(&self, tau: T) -> Interval<T> {
        if !self.is_valid() {
            return Interval::EMPTY;
        }
        let (l, u) = (self.lower_side().at_lo(tau), self.upper_side().at_hi(tau));
        if l <= u {
            Interval::new(l, u)
        } else {
            Interval::new(u, l)
        }
    }

    /// A sound enclosure of `f` over the whole validity interval.
    pub fn range(&self) -> Interval<T> {
        if !self.is_valid() {
            return Interval::EMPTY;
        }
        Interval::new(
            self.lower_side().range_lo(self.h),
            self.upper_side().range_hi(self.h),
        )
    }

    /// The first `τ ∈ [0, h]` where the bound on the relevant side reaches
    /// `0`, or `None` if it provably does not (paper Alg. 1
    /// `CalcNextRoot`).
    ///
    /// Outside (`s₋ > 0`) the lower bound is used, inside (`s₊ < 0`) the
    /// upper one; if the start enclosure contains `0` the answer is
    /// `Some(0)`, as it is for an invalid bound. The returned `τ` **never
    /// passes the first root of `f`**: the side is proven nonzero on
    /// `[0, τ)` in outward-rounded arithmetic. Quadratic roots use the
    /// cancellation-free formula and are then backed off, if needed, by a few
    /// float steps until that proof succeeds.
    pub fn first_root(&self) -> Option<T> {
        if !self.is_valid() {
            return Some(T::ZERO);
        }
        if self.start.lo() > T::ZERO {
            poly::safe_root_pos(self.lower_side(), self.h)
        } else if self.start.hi() < T::ZERO {
            poly::safe_root_pos(self.upper_side().neg(), self.h)
        } else {
            Some(T::ZERO)
        }
    }

    /// The safe marching step: [`first_root`](Self::first_root), or the
    /// whole validity length `h` when the bound has no root.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn safe_step(&self) -> T {
        self.first_root().unwrap_or(self.h)
    }

    /// "Mixed" bounds (paper §7): of two bounds of the same function on the
    /// same ray interval (e.g. Taylor and bottom-up), keep on each side the
    /// one that is tighter at the end of their common validity interval.
    pub fn tighter(self, other: Self) -> Self {
        if !self.is_valid() {
            return other;
        }
        if !other.is_valid() {
            return self;
        }
        let h = if self.h < other.h { self.h } else { other.h };
        let (l1, l2) = (self.lower_side(), other.lower_side());
        let (u1, u2) = (self.upper_side(), other.upper_side());
        let pick_l1 = l1.at_lo(h) >= l2.at_lo(h);
        let pick_u1 = u1.at_hi(h) <= u2.at_hi(h);
        let lo = if pick_l1 { l1 } else { l2 };
        let hi = if pick_u1 { u1 } else { u2 };
        let hh = match (pick_l1, pick_u1) {
            (true, true) => self.h,
            (false, false) => other.h,
            _ => h,
        };
        Self::from_sides(lo, hi, hh, self.mode.join(other.mode))
    }

    // ----- internals -------------------------------------------------------

    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub(crate) fn lower_side(&self) -> Side<T> {
        Side::new(self.start.lo(), self.lo[0], self.lo[1])
    }

    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub(crate) fn upper_side(&self) -> Side<T> {
        Side::new(self.start.hi(), self.hi[0], self.hi[1])
    }

    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub(crate) fn from_sides(lo: Side<T>, hi: Side<T>, h: T, mode: impl Into<ModeCode>) -> Self {
        let start = Interval::new(lo.s, hi.s);
        let mut r = Self::from_parts(start, [lo.a, lo.b], [hi.a, hi.b], h);
        r.mode = mode.into();
        r
    }

    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn min_h(&self, other: &Self) -> T {
        if self.h < other.h { self.h } else { other.h }
    }

    /// Length up to which the side `q` (with `q.s > 0`) stays `≥ q.s / 2`,
    /// and the floor it provably stays above there.
    fn half_way(q: Side<T>, h: T) -> (T, T) {
        let half = mul_hi(q.s, T::HALF);
        let shifted = Side::new(sub_lo(q.s, half), q.a, q.b);
        if !(shifted.s > T::ZERO) {
            // q.s is the least subnormal: half of it is not representable.
            // Stop half way to the side's root instead (it is still > 0).
            let hh = match poly::safe_root_pos(q, h) {
                Some(r) => r * T::HALF,
                None => h,
            };
            return (hh, T::ZERO);
        }
        // shifted ≥ 0 on [0, h'] means q = shifted + (q.s − shifted.s) ≥ half.
        (poly::safe_root_pos(shifted, h).unwrap_or(h), half)
    }

    /// `x²` (tighter than `x · x`): exact polynomial squares of the sides
    /// where they keep their sign, the tangent `2x*·x − x*²` otherwise.
    pub fn sqr(self) -> Self {
        if !self.is_valid() {
            return self;
        }
        let (fl, fu) = (self.lower_side(), self.upper_side());
        let h = self.h;
        let (qll, quu) = (poly::quartic(fl, fl), poly::quartic(fu, fu));
        let lower = if fl.range_lo(h) >= T::ZERO {
            poly::reduce_lo(qll, h)
        } else if fu.range_hi(h) <= T::ZERO {
            poly::reduce_lo(quu, h)
        } else if fl.s > T::ZERO {
            let d = fl.s + fl.s;
            compose::compose_line(
                Line {
                    l0: mul_lo(fl.s, fl.s),
                    dl: d,
                    dr: d,
                },
                fl,
                false,
            )
        } else if fu.s < T::ZERO {
            let d = fu.s + fu.s;
            compose::compose_line(
                Line {
                    l0: mul_lo(fu.s, fu.s),
                    dl: d,
                    dr: d,
                },
                fu,
                false,
            )
        } else {
            Side::constant(T::ZERO)
        };
        // The side may cross zero: the corner products also bound x² from
        // below (x² ≥ min(f₋², f₊², f₋f₊) for f₋ ≤ x ≤ f₊), which is nearly
        // exact for a thin band (e.g. the square of a coordinate).
        let corners = min_sides(
            min_sides(poly::reduce_lo(qll, h), poly::reduce_lo(quu, h)),
            poly::reduce_lo(poly::quartic(fl, fu), h),
        );
        let lower = better_lower(lower, corners, h);
        let upper = max_sides(poly::reduce_hi(qll, h), poly::reduce_hi(quu, h));
        Self::from_sides(lower, upper, h, self.mode)
    }

    /// `xⁿ` for an integer `n`: `sqr` and products by binary powering;
    /// negative `n` as `1 / x^|n|`; `x⁰ = 1`.
    pub fn powi(self, n: i32) -> Self {
        if !self.is_valid() {
            return self;
        }
        // One call of `powi_pos` for both signs (a GPU driver inlines each
        // call site: BENCHMARKS.md "GPU").
        let p = self.powi_pos(n.unsigned_abs());
        if n < 0 { p.recip() } else { p }
    }

    fn powi_pos(self, n: u32) -> Self {
        if n == 0 {
            let mut one = Self::constant(T::ONE);
            one.h = self.h;
            one.mode = self.mode;
            return one;
        }
        // Binary powering, iterative (no recursion: runs on the GPU).
        let mut result: Option<Self> = None;
        let mut base = self;
        let mut e = n;
        loop {
            if e & 1 == 1 {
                result = Some(match result {
                    None => base,
                    Some(r) => r * base,
                });
            }
            e >>= 1;
            if e == 0 {
                break;
            }
            base = base.sqr();
        }
        match result {
            Some(r) => r,
            None => self,
        }
    }

    /// `1/x`: convex decreasing for `x > 0`, concave decreasing for `x < 0`.
    /// The interval is shortened so that the input stays at least half way
    /// from `0` (its start value halved), keeping the chord slopes finite.
    pub fn recip(self) -> Self {
        if !self.is_valid() {
            return self;
        }
        // Convex for x > 0, concave for x < 0.
        let convex = self.start.lo() > T::ZERO;
        match self.away_from_pole(true) {
            Some((h, known)) => self.tangent_chord(compose::Recip, h, false, convex, known, false),
            None => Self::INVALID,
        }
    }

    /// `eˣ`: convex increasing. The interval is shortened where the upper
    /// argument would exceed its start value by 16 (a growth by
    /// `e¹⁶ ≈ 9·10⁶`), which keeps the chord finite and meaningful.
    pub fn exp(self) -> Self {
        if !self.is_valid() {
            return self;
        }
        // Stop where the upper argument has grown by EXP_GROWTH: the chord
        // stays finite (no overflow) and meaningful.
        let fu = self.upper_side();
        let mut h = self.h;
        let cap = add_lo(fu.s, T::from_f64(EXP_GROWTH));
        if cap > fu.s && fu.range_hi(h) > cap {
            let room = Side::new(sub_lo(cap, fu.s), -fu.a, -fu.b);
            if let Some(r) = poly::safe_root_pos(room, h) {
                h = r;
            }
        }
        let all = (T::NEG_INFINITY, T::INFINITY);
        self.tangent_chord(compose::Exp, h, true, true, all, false)
    }

    /// `ln x`: concave increasing; needs a positive start, shortened like
    /// [`recip`](Self::recip).
    pub fn ln(self) -> Self {
        if !self.is_valid() {
            return self;
        }
        match self.away_from_pole(false) {
            Some((h, known)) => self.tangent_chord(compose::Ln, h, true, false, known, false),
            None => Self::INVALID,
        }
    }

    /// `√x` (bounded as `√max(x, 0)`): concave increasing. When the upper
    /// input starts exactly at `0` no finite slope is exact at `t₀` (the
    /// derivative is infinite): that side is then the constant `√max f₊`, a
    /// relaxed start (the one case where the start enclosure is wider than
    /// the rounding margin).
    pub fn sqrt(self) -> Self {
        self.concave_power(compose::Sqrt)
    }

    /// `x^p` for a real `p`: an integer `p` uses [`powi`](Self::powi);
    /// otherwise `max(x, 0)^p` for `p > 0` (convex for `p > 1`, concave and
    /// sqrt-like for `p < 1`), and for `p < 0` convex decreasing on `x > 0`,
    /// shortened like [`recip`](Self::recip).
    pub fn powf(self, p: T) -> Self {
        if p.is_nan() {
            return Self::INVALID;
        }
        if p == p.round() && p.abs() < T::from_f64(2147483647.0) {
            return self.powi(p.to_i32().unwrap_or(0));
        }
        if !self.is_valid() {
            return self;
        }
        let phi = compose::Pow(p);
        if p < T::ZERO {
            // Convex decreasing for x > 0.
            return match self.away_from_pole(false) {
                Some((h, known)) => self.tangent_chord(phi, h, false, true, known, false),
                None => Self::INVALID,
            };
        }
        if p < T::ONE {
            return self.concave_power(phi);
        }
        if self.start.hi() < T::ZERO {
            return Self::INVALID;
        }
        // max(x, 0)^p is convex increasing on all of ℝ; below 0 it has no
        // tangent, and its lower bound is 0 unless the input starts positive.
        let nonneg = (T::ZERO, T::INFINITY);
        let zero_below = !(self.start.lo() > T::ZERO);
        self.tangent_chord(phi, self.h, true, true, nonneg, zero_below)
    }

    /// `sin x`: on a quarter period `[kπ/2, (k+1)π/2]` containing the input's
    /// range, sine is monotone and convex or concave, and the tangent/chord
    /// rules of [`exp`](Self::exp) apply (exact at `t₀`). When the range
    /// spans a critical or inflection point, the 1-Lipschitz rule
    /// `sin x(τ) ≤ sup sin(S) + dist(x(τ), S)` (`S` the start enclosure)
    /// gives both sides, with the distance bounded by the Bézier maximum
    /// (App. C) of the input's sides and 0.
    pub fn sin(self) -> Self {
        self.trig(compose::Sin)
    }

    /// `cos x`; see [`sin`](Self::sin).
    pub fn cos(self) -> Self {
        self.trig(compose::Cos)
    }

    fn trig<P: Unary<T>>(self, phi: P) -> Self {
        if !self.is_valid() {
            return self;
        }
        let (fl, fu) = (self.lower_side(), self.upper_side());
        let (h, mode) = (self.h, self.mode.get());
        let all = (T::NEG_INFINITY, T::INFINITY);
        let (r0, r1) = (fl.range_lo(h), fu.range_hi(h));
        // Beyond 2^(p−3) floats are too sparse to place quarter periods.
        let limit = T::from_f64((1u64 << (T::MANTISSA_DIGITS - 3)) as f64);
        if r0.abs() < limit && r1.abs() < limit {
            // [qa, qb] ⊇ range·2/π, with 2/π itself enclosed.
            let two_over_pi = Interval::new(T::FRAC_2_PI.next_down(), T::FRAC_2_PI.next_up());
            let qa = (Interval::point(r0) * two_over_pi).lo();
            let qb = (Interval::point(r1) * two_over_pi).hi();
            let k = qa.floor();
            if qb <= k + T::ONE {
                // The range lies in [kπ/2, (k+1)π/2]; k mod 4 (exact, |k| < 2^(p−2)).
                let four = T::from_f64(4.0);
                let r = (k - four * (k / four).floor()).to_u32().unwrap_or(0);
                // (increasing, convex) on the quarter.
                let (inc, convex) = match (P::IS_SIN, r) {
                    (true, 0) => (true, false),
                    (true, 1) => (false, false),
                    (true, 2) => (false, true),
                    (true, _) => (true, true),
                    (false, 0) => (false, false),
                    (false, 1) => (false, true),
                    (false, 2) => (true, true),
                    (false, _) => (true, false),
                };
                return self.tangent_chord(phi, h, inc, convex, all, false);
            }
        }
        // 1-Lipschitz: with z the point of the start S nearest to x(τ),
        // φ(x(τ)) ≤ φ(z) + |x(τ) − z| ≤ sup φ(S) + dist(x(τ), S), and
        // dist(x(τ), S) ≤ max(0, u(τ), −ℓ(τ)) for the sides without their
        // starts (u = a₊τ + b₊τ², ℓ = a₋τ + b₋τ²); symmetrically below.
        let v = phi.eval(self.start);
        let up = Side::new(T::ZERO, fu.a, fu.b);
        let dn = Side::new(T::ZERO, -fl.a, -fl.b);
        let d = bezier_max(bezier_max(up, dn, h), Side::constant(T::ZERO), h);
        let upper = Side::new(v.hi(), d.a, d.b);
        let lower = Side::new(v.lo(), -d.a, -d.b);
        Self::from_sides(lower, upper, h, mode)
    }

    /// For the functions with a pole at 0 (`1/x`, `ln x`, `x^p` for
    /// `p < 0`): `None` unless the input starts positive (or negative, with
    /// `negative_ok`); otherwise the validity length shortened so that the
    /// input stays at least half way from 0, and the range it is then known
    /// to stay in (for [`compose::chord`]).
    fn away_from_pole(&self, negative_ok: bool) -> Option<(T, (T, T))> {
        let pos = self.start.lo() > T::ZERO;
        let neg = self.start.hi() < T::ZERO;
        if !(pos || (neg && negative_ok)) {
            return None;
        }
        let q = if pos {
            self.lower_side()
        } else {
            self.upper_side().neg()
        };
        let (h, floor) = Self::half_way(q, self.h);
        Some(if pos {
            (h, (floor, T::INFINITY))
        } else {
            (h, (T::NEG_INFINITY, -floor))
        })
    }

    /// `φ ∘ self` for `φ` increasing (`inc`) or decreasing and convex or
    /// concave on the input's range (on `[0, h]`, `known`: the range the
    /// input is known to stay in): the tangent bounds a convex function
    /// from below (a concave one from above), the chord from the other side,
    /// each taking the input side that is extreme in its direction. With
    /// `zero_tangent` the tangent side is the constant 0 (`max(x, 0)^p`
    /// for an input not starting positive). One call of each rule, for all
    /// functions: a GPU driver inlines every call site (BENCHMARKS.md "GPU").
    fn tangent_chord<P: Unary<T>>(
        self,
        phi: P,
        h: T,
        inc: bool,
        convex: bool,
        known: (T, T),
        zero_tangent: bool,
    ) -> Self {
        let (fl, fu) = (self.lower_side(), self.upper_side());
        let mode = self.mode.get();
        let (t_in, c_in) = if inc == convex { (fl, fu) } else { (fu, fl) };
        let (chord_side, h2) = compose::chord(phi, c_in, h, convex, mode, known);
        let tangent_side = if zero_tangent {
            Side::constant(T::ZERO)
        } else {
            compose::tangent(phi, t_in, !convex)
        };
        if convex {
            Self::from_sides(tangent_side, chord_side, h2, mode)
        } else {
            Self::from_sides(chord_side, tangent_side, h2, mode)
        }
    }

    /// `√x` and `max(x, 0)^p` for `0 < p < 1`: concave increasing on
    /// `x ≥ 0`, `φ(0) = 0`, bounded as `φ(max(x, 0))`; undefined when the
    /// input starts below 0.
    fn concave_power<P: Unary<T>>(self, phi: P) -> Self {
        if !self.is_valid() {
            return self;
        }
        if self.start.hi() < T::ZERO {
            return Self::INVALID;
        }
        let (fl, fu) = (self.lower_side(), self.upper_side());
        let (h, mode) = (self.h, self.mode.get());
        let (lower, h2) = if self.start.lo() > T::ZERO {
            compose::chord(phi, fl, h, false, mode, (T::ZERO, T::INFINITY))
        } else {
            (Side::constant(T::ZERO), h)
        };
        let upper = Self::concave_power_upper(phi, fu, h2);
        Self::from_sides(lower, upper, h2, mode)
    }

    /// The upper side of a concave power (`√x`, `max(x, 0)^p` for
    /// `0 < p < 1`) of the input's upper side `fu` on `[0, h]`: the tangent
    /// at a positive start, kept `≥ 0` down to the input's lowest value
    /// (the function is 0 there); the constant `φ(max I₁, 0)` otherwise
    /// (no finite slope is exact at a start of 0).
    fn concave_power_upper<P: Unary<T>>(phi: P, fu: Side<T>, h: T) -> Side<T> {
        let x0 = fu.s;
        if x0 > T::ZERO {
            let v = phi.eval(Interval::point(x0));
            let d = phi.deriv_from(x0, v);
            let i0 = fu.range_lo(h);
            let mut dl = d.lo();
            if i0 < T::ZERO {
                // Stay ≥ 0 down to I₀ (the function is 0 there).
                let cap = div_lo(v.hi(), sub_hi(x0, i0));
                if cap < dl {
                    dl = cap;
                }
            }
            compose::compose_line(
                Line {
                    l0: v.hi(),
                    dl,
                    dr: d.hi(),
                },
                fu,
                true,
            )
        } else {
            let i1 = fu.range_hi(h);
            let top = phi.eval(Interval::point(if i1 > T::ZERO { i1 } else { T::ZERO }));
            if top.is_empty() {
                compose::unbounded(T::INFINITY, true)
            } else {
                Side::constant(top.hi())
            }
        }
    }

    /// `max(f, g)` (paper §5.2 and App. C): the upper bound is the quadratic
    /// whose Bézier control points are the maxima of the operands' control
    /// points (exact at `t₀`); the lower bound is the operand's lower bound
    /// with the higher start value (ties: higher at the end).
    pub fn max(self, other: Self) -> Self {
        if !self.is_valid() || !other.is_valid() {
            return Self::INVALID;
        }
        let h = self.min_h(&other);
        let mode = self.mode.join(other.mode);
        let (l1, l2) = (self.lower_side(), other.lower_side());
        let lower = if l1.s > l2.s || (l1.s == l2.s && l1.at_lo(h) >= l2.at_lo(h)) {
            l1
        } else {
            l2
        };
        let upper = bezier_max(self.upper_side(), other.upper_side(), h);
        Self::from_sides(lower, upper, h, mode)
    }

    /// A bound enclosing both `self` and `other` (their hull): the lower
    /// side of `min(self, other)` below, the upper side of
    /// `max(self, other)` above (App. C), the shorter validity. Used where a
    /// field's branch cannot be decided on the interval, so both branches
    /// are kept.
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
        Self {
            start: Interval::new(lo.start.lo(), hi.start.hi()),
            lo: lo.lo,
            hi: hi.hi,
            h,
            mode: self.mode.join(other.mode),
        }
    }

    /// `min(f, g) = −max(−f, −g)`.
    pub fn min(self, other: Self) -> Self {
        -((-self).max(-other))
    }

    /// `|x| = max(x, −x)`.
    pub fn abs(self) -> Self {
        if !self.is_valid() {
            return self;
        }
        if self.start.lo() >= T::ZERO && self.lower_side().range_lo(self.h) >= T::ZERO {
            return self;
        }
        if self.start.hi() <= T::ZERO && self.upper_side().range_hi(self.h) <= T::ZERO {
            return -self;
        }
        let m = self.max(-self);
        // |x| ≥ 0: a zero lower start may use the constant 0 instead.
        let lower = m.lower_side();
        if lower.s <= T::ZERO {
            let zero = Side::constant(T::ZERO);
            return Self::from_sides(zero, m.upper_side(), m.h, m.mode);
        }
        m
    }
}

/// How far the argument of `exp` may grow over a bound's interval.
const EXP_GROWTH: f64 = 16.0;

/// Of two valid lower sides, the one to keep: the higher at `τ = h` unless
/// that would give up more than a rounding margin at `τ = 0`.
fn better_lower<T: Real>(a: Side<T>, b: Side<T>, h: T) -> Side<T> {
    let slack = T::from_f64(64.0) * T::EPSILON * (a.s.abs() + b.s.abs()) + T::MIN_SUBNORMAL;
    let end = if h.is_finite() { h } else { T::ONE };
    if b.s + slack >= a.s && b.at_lo(end) > a.at_lo(end) {
        b
    } else if a.s + slack >= b.s || a.at_lo(end) >= b.at_lo(end) {
        a
    } else {
        b
    }
}

/// The Fig. 8 reduction `f8` of a corner instead of the exact-slope one `ex`
/// (same start) only when it is higher both half way and at the end: its
/// slope at `t₀` is lower, so it is only worth it when it pays off over most
/// of the interval. Measured on the `bound_widths` report: choosing by the
/// end value alone, or by the mean over `[0, h]`, made ranges and folded
/// linear bounds wider.
fn fig8_if_tighter<T: Real>(ex: Side<T>, f8: Side<T>, h: T) -> Side<T> {
    let m = h * T::HALF;
    if f8.s >= ex.s && f8.at_lo(m) > ex.at_lo(m) && f8.at_lo(h) > ex.at_lo(h) {
        f8
    } else {
        ex
    }
}

/// An upper side above both `p` and `q` on `[0, h]`: control points
/// `max(Pᵢ, Qᵢ)` (App. C), computed relative to the common start so the
/// rounding error stays relative to the differences.
fn bezier_max<T: Real>(p: Side<T>, q: Side<T>, h: T) -> Side<T> {
    if !(h > T::ZERO) || !h.is_finite() {
        return max_sides(p, q);
    }
    let u0 = max_hi(p.s, q.s);
    // α = 2(s − U₀)/h + a (middle control point, scaled);
    // β = (s − U₀)/h + a + b·h (end control point, scaled).
    let ab = |r: Side<T>| {
        let d = div_hi(sub_hi(r.s, u0), h);
        let alpha = add_hi(add_hi(d, d), r.a);
        let beta = add_hi(add_hi(d, r.a), mul_hi(r.b, h));
        (alpha, beta)
    };
    let (ap, bp) = ab(p);
    let (aq, bq) = ab(q);
    let a = max_hi(ap, aq);
    let beta = max_hi(bp, bq);
    let b = div_hi(sub_hi(beta, a), h);
    let bez = Side::new(u0, a, b);
    // Keep the plain coefficient-wise maximum if it is tighter at the end.
    let plain = max_sides(p, q);
    if plain.at_hi(h) < bez.at_hi(h) && plain.s <= u0 {
        plain
    } else {
        bez
    }
}

impl<T: Real> Neg for ForwardQuadratic<T> {
    type Output = Self;
    /// Swaps and negates the sides (exact).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn neg(self) -> Self {
        if !self.is_valid() {
            return self;
        }
        Self::from_sides(
            self.upper_side().neg(),
            self.lower_side().neg(),
            self.h,
            self.mode,
        )
    }
}

impl<T: Real> Add for ForwardQuadratic<T> {
    type Output = Self;
    /// Coefficient-wise sum (paper eq. 16), rounded outward.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn add(self, rhs: Self) -> Self {
        if !self.is_valid() || !rhs.is_valid() {
            return Self::INVALID;
        }
        Self::from_sides(
            add_sides_lo(self.lower_side(), rhs.lower_side()),
            add_sides_hi(self.upper_side(), rhs.upper_side()),
            self.min_h(&rhs),
            self.mode.join(rhs.mode),
        )
    }
}

impl<T: Real> Sub for ForwardQuadratic<T> {
    type Output = Self;
    /// `self + (−rhs)`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn sub(self, rhs: Self) -> Self {
        self + (-rhs)
    }
}

impl<T: Real> Mul for ForwardQuadratic<T> {
    type Output = Self;
    /// Products of the four corner pairs of sides (quartics, paper §6.2).
    /// Each is reduced to a quadratic in two ways and the tighter at `h` is
    /// kept: the paper's Fig. 8 rule (a line below the cubic derivative,
    /// split at its inflection into convex/concave parts, integrated), and
    /// the quadratic keeping value and slope at `t₀` with the tightest
    /// curvature `min/max_{[0,h]} (c₂ + c₃τ + c₄τ²)`. The result takes the
    /// extreme coefficients of the four.
    fn mul(self, rhs: Self) -> Self {
        if !self.is_valid() || !rhs.is_valid() {
            return Self::INVALID;
        }
        let h = self.min_h(&rhs);
        let mode = self.mode.join(rhs.mode);
        let (f0, f1) = (self.lower_side(), self.upper_side());
        let (g0, g1) = (rhs.lower_side(), rhs.upper_side());
        // The four corners (f0 g0, f0 g1, f1 g0, f1 g1, combined in that
        // order) in a loop with one call of `corner_product`: a GPU driver
        // inlines every call site, and four of them made a product 1.3
        // million SPIR-V instructions (BENCHMARKS.md "GPU"). The operands
        // are chosen by branches, not by index: a dynamic index is a panic
        // path, which rust-gpu 0.11 handles by inlining every caller up to
        // the entry point.
        let (mut lower, mut upper) = (Side::constant(T::ZERO), Side::constant(T::ZERO));
        let mut k = 0u32;
        while k < 4 {
            let f = if k < 2 { f0 } else { f1 };
            let g = if k % 2 == 0 { g0 } else { g1 };
            let (l, u) = corner_product(f, g, h);
            if k == 0 {
                (lower, upper) = (l, u);
            } else {
                lower = min_sides(lower, l);
                upper = max_sides(upper, u);
            }
            k += 1;
        }
        Self::from_sides(lower, upper, h, mode)
    }
}

/// The lower and upper quadratic sides of the quartic `f·g` on `[0, h]`
/// (one corner of [`ForwardQuadratic`]'s product): [`poly::reduce_lo`] /
/// [`poly::reduce_hi`], replaced by the Fig. 8 rule where it is tighter.
fn corner_product<T: Real>(f: Side<T>, g: Side<T>, h: T) -> (Side<T>, Side<T>) {
    let c = poly::quartic(f, g);
    let mut l = poly::reduce_lo(c, h);
    let mut u = poly::reduce_hi(c, h);
    // The Fig. 8 rule only matters with cubic/quartic terms, and
    // is only computed (rigorously) when a float estimate says it
    // is tighter half way and at the end (see `fig8_if_tighter`).
    let cubic = c[3] != (T::ZERO, T::ZERO) || c[4] != (T::ZERO, T::ZERO);
    if cubic && h.is_finite() {
        let m = h * T::HALF;
        // The lower side (of `c`), then the upper one (the negated lower
        // side of `−c`), with one call of the Fig. 8 rule (GPU size, as in
        // `mul`).
        let mut upper = false;
        loop {
            let (q, ex) = if upper {
                (poly::neg_quartic(c), u.neg())
            } else {
                (c, l)
            };
            let promising = poly::fig8_lo_estimate(q, h)
                .is_some_and(|(em, eh)| em > ex.at_lo(m) && eh > ex.at_lo(h));
            if promising {
                if let Some(r8) = poly::reduce_lo_fig8(q, h) {
                    let t = fig8_if_tighter(ex, r8, h);
                    if upper {
                        u = t.neg();
                    } else {
                        l = t;
                    }
                }
            }
            if upper {
                break;
            }
            upper = true;
        }
    }
    (l, u)
}

impl<T: Real> Div for ForwardQuadratic<T> {
    type Output = Self;
    /// `self · recip(rhs)`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    #[allow(clippy::suspicious_arithmetic_impl)] // x / y = x · (1/y) by design
    fn div(self, rhs: Self) -> Self {
        self * rhs.recip()
    }
}

impl<T: Real> Add<T> for ForwardQuadratic<T> {
    type Output = Self;
    /// Shifts the start values (rounded outward); a non-finite scalar gives
    /// [`INVALID`](Self::INVALID).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn add(self, c: T) -> Self {
        if !self.is_valid() || !c.is_finite() {
            return Self::INVALID;
        }
        let (mut l, mut u) = (self.lower_side(), self.upper_side());
        l.s = add_lo(l.s, c);
        u.s = add_hi(u.s, c);
        Self::from_sides(l, u, self.h, self.mode)
    }
}

impl<T: Real> Sub<T> for ForwardQuadratic<T> {
    type Output = Self;
    /// `self + (−c)`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn sub(self, c: T) -> Self {
        self + (-c)
    }
}

impl<T: Real> Mul<T> for ForwardQuadratic<T> {
    type Output = Self;
    /// Scales every coefficient (rounded outward), swapping the sides for a
    /// negative scalar; a non-finite scalar gives [`INVALID`](Self::INVALID).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn mul(self, c: T) -> Self {
        if !self.is_valid() || !c.is_finite() {
            return Self::INVALID;
        }
        let (l, u) = (self.lower_side(), self.upper_side());
        let (l, u) = if c >= T::ZERO { (l, u) } else { (u, l) };
        let lo = Side::new(mul_lo(l.s, c), mul_lo(l.a, c), mul_lo(l.b, c));
        let hi = Side::new(mul_hi(u.s, c), mul_hi(u.a, c), mul_hi(u.b, c));
        Self::from_sides(lo, hi, self.h, self.mode)
    }
}

impl<T: Real> Div<T> for ForwardQuadratic<T> {
    type Output = Self;
    /// Divides every coefficient (rounded outward); a zero or non-finite
    /// divisor gives [`INVALID`](Self::INVALID).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn div(self, c: T) -> Self {
        if !self.is_valid() || !c.is_finite() || c == T::ZERO {
            return Self::INVALID;
        }
        let (l, u) = (self.lower_side(), self.upper_side());
        let (l, u) = if c > T::ZERO { (l, u) } else { (u, l) };
        let lo = Side::new(div_lo(l.s, c), div_lo(l.a, c), div_lo(l.b, c));
        let hi = Side::new(div_hi(u.s, c), div_hi(u.a, c), div_hi(u.b, c));
        Self::from_sides(lo, hi, self.h, self.mode)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ForwardLinear;

    fn contains_on(b: ForwardQuadratic<f64>, t0: f64, f: impl Fn(f64) -> f64) {
        let h = b.validity();
        assert!(h > 0.0);
        for i in 0..=400 {
            let tau = h * i as f64 / 400.0;
            let y = f(t0 + tau);
            let iv = b.bounds_at(tau);
            let tol = 1e-9 * (1.0 + y.abs());
            assert!(
                iv.lo() <= y + tol && y - tol <= iv.hi(),
                "{y} not in {iv:?} at τ={tau}"
            );
        }
    }

    #[test]
    fn join_encloses_both_operands() {
        let cases: [(f64, f64); 4] = [(0.0, 1.0), (-1.0, 0.5), (0.2, 3.0), (1.0, 1.25)];
        for (t0, t1) in cases {
            let t = ForwardQuadratic::ray_param(t0, t1);
            let a = (t - 0.3).sqr() - 0.2;
            let b = (-t).exp() * 0.5;
            let j = a.join(b);
            let fa = |x: f64| (x - 0.3) * (x - 0.3) - 0.2;
            let fb = |x: f64| (-x).exp() * 0.5;
            contains_on(j, t0, fa);
            contains_on(j, t0, fb);
            assert!(j.validity() <= a.validity().min(b.validity()));
            let l = ForwardLinear::from_quadratic(a).join(ForwardLinear::from_quadratic(b));
            contains_on(l.to_quadratic(), t0, fa);
            contains_on(l.to_quadratic(), t0, fb);
        }
        assert!(
            !ForwardQuadratic::<f64>::INVALID
                .join(ForwardQuadratic::constant(1.0))
                .is_valid()
        );
    }

    #[test]
    fn sin_cos_on_quarters_and_across_extrema() {
        // Short intervals stay in one quarter period (tangent/chord rule),
        // long ones cross extrema (Lipschitz rule).
        for (t0, t1) in [
            (0.1f64, 0.4),
            (2.0, 2.5),
            (-1.2, -0.9),
            (0.0, 7.0),
            (1.0, 2.2),
        ] {
            let t = ForwardQuadratic::ray_param(t0, t1);
            let s = (t * 1.5).sin();
            let c = (t.sqr() * 0.5).cos();
            contains_on(s, t0, |x| (1.5 * x).sin());
            contains_on(c, t0, |x| (0.5 * x * x).cos());
            assert!(s.start().contains((1.5 * t0).sin()));
        }
    }

    #[test]
    fn blob_like_expression() {
        let t = ForwardQuadratic::<f64>::ray_param(-2.0, 2.0);
        let d2 = (t - 0.3).sqr() + 0.2;
        let f = (-d2).exp() * 2.0 - 0.5;
        contains_on(f, -2.0, |t| {
            2.0 * (-((t - 0.3f64).powi(2) + 0.2)).exp() - 0.5
        });
        let g = d2.recip() + d2.sqrt() - d2.ln();
        let gf = |t: f64| {
            let d = (t - 0.3f64).powi(2) + 0.2;
            1.0 / d + d.sqrt() - d.ln()
        };
        contains_on(g, -2.0, gf);
        let m = f.max(t * 0.1).min(-t + 1.0).abs();
        contains_on(m, -2.0, |t| {
            let f = 2.0 * (-((t - 0.3f64).powi(2) + 0.2)).exp() - 0.5;
            f.max(0.1 * t).min(1.0 - t).abs()
        });
    }

    #[test]
    fn recip_shortens_before_pole() {
        let t = ForwardQuadratic::<f64>::ray_param(0.0, 4.0);
        let r = (-t + 1.0).recip(); // pole at t = 1
        assert!(r.validity() > 0.0 && r.validity() <= 0.5 + 1e-12);
        contains_on(r, 0.0, |t| 1.0 / (1.0 - t));
    }
}
