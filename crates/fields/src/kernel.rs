//! Radial kernels (fall-off functions) of skeleton-based implicit surfaces
//! and the analytic extrema of their derivatives.
//!
//! # The four families
//!
//! Every kernel is a decreasing function of the distance `d` to a skeleton
//! point with a scale `σ > 0`; all are written here as functions of the
//! **normalized squared distance** `u = d²/σ²`, which keeps the compact and
//! Cauchy kernels polynomial/rational (and tight in interval arithmetic):
//!
//! | kind | `k(d)` | `K(u)` | source |
//! | --- | --- | --- | --- |
//! | [`Compact`](KernelKind::Compact) | `(1 − (d/σ)²)^{n/2}` for `d < σ`, else `0` | `max(1 − u, 0)^{n/2}` | thesis eq. 1.7, paper eq. 7 |
//! | [`Cauchy`](KernelKind::Cauchy) | `(1 + (d/σ)²)^{−n/2}` | `(1 + u)^{−n/2}` | thesis eq. 1.8 |
//! | [`Gaussian`](KernelKind::Gaussian) | `e^{−(d/σ)²}` | `e^{−u}` | thesis eq. 1.6, paper eq. 6 with `σ = r/√s` |
//! | [`Inverse`](KernelKind::Inverse) | `(d/σ)^{−n}` | `u^{−n/2}` | thesis eq. 1.9 |
//!
//! The normalization factor `1/N` of the papers (chosen to reach a
//! prescribed radius at a given iso-value) is **not** part of the kernel:
//! `k(0) = 1` (`+∞` for the inverse kernel), and a primitive's weight
//! carries the normalization (see [`crate::blob::PointBlob`]). In the
//! forward-inclusion paper's eq. 7 the support radius is `σ·r`; here it is
//! the single scale `σ`.
//!
//! # Derivatives
//!
//! Two sets of derivatives are offered:
//!
//! - with respect to `u` (the normalized squared distance):
//!   [`d_u`](Kernel::d_u), [`d2_u`](Kernel::d2_u), generic over
//!   [`FieldNum`]. For all four families `K` is **convex and decreasing**
//!   in `u` (`K' ≤ 0 ≤ K''`), and `K''` is monotone too (decreasing, except
//!   the compact kernel of degree 3, whose `K''` grows to `+∞` at the
//!   support boundary), so interval evaluations of `K'` and `K''` over a
//!   `u` range are tight. The derivative with respect to the un-normalized
//!   squared distance `D = d²` is `K'(u)/σ²`.
//! - with respect to the distance `d`: [`derivative`](Kernel::derivative)
//!   `k'(d) = (2d/σ²)·K'(u)` and
//!   [`second_derivative`](Kernel::second_derivative)
//!   `k''(d) = (2/σ²)·(2u·K''(u) + K'(u))`, with sound enclosures of their
//!   ranges over `[d₀, d₁]`: [`derivative_range`](Kernel::derivative_range),
//!   [`second_derivative_range`](Kernel::second_derivative_range)
//!   (forward-inclusion paper App. A: extrema at the ends or at the
//!   closed-form critical points below).
//!
//! # Closed-form critical points
//!
//! With `m = n/2`, the extrema of `k'(d)` (roots of `k''`) and of `k''(d)`
//! (roots of `k'''`, cf. paper eq. 23 for the Gaussian) for `d > 0` are at
//!
//! | kind | `k'` extremum at `u =` | `k''` extremum at `u =` |
//! | --- | --- | --- |
//! | compact | `1/(n − 1)` | `3/(n − 1)` (when `< 1`) and the support boundary `u = 1` |
//! | Cauchy | `1/(n + 1)` | `3/(n + 1)` |
//! | Gaussian | `1/2` | `3/2` |
//! | inverse | none (monotone) | none (monotone) |
//!
//! More generally, along a ray the squared distance is a quadratic
//! `u(t) = α(t − t_m)² + e` (with `e` the value at its minimum), so
//! `u'² = 4α(u − e)`, `u'' = 2α` and the field's second derivative along the
//! ray is `2α·H_e(u)` with `H_e(u) = 2(u − e)·K''(u) + K'(u)`, a function of
//! `u` alone. [`ray_curvature_range`](Kernel::ray_curvature_range) encloses
//! `H_e` over a `u` range; its one interior critical point (root of
//! `H_e' = 3K'' + 2(u − e)K'''`) is, in closed form,
//!
//! | kind | `H_e` extremum at `u =` |
//! | --- | --- |
//! | compact | `(3 + (n − 4)e)/(n − 1)` |
//! | Cauchy | `(3 + (n + 4)e)/(n + 1)` |
//! | Gaussian | `e + 3/2` |
//! | inverse | `(n + 4)e/(n + 1)` |
//!
//! (for `e = 0` these are the `k''` critical points above). The field's
//! first derivative along the ray, `u'·K'(u)`, has its interior extrema
//! where `f'' = 0`, i.e. at the root of `H_e` itself
//! ([`ray_slope_critical_u`](Kernel::ray_slope_critical_u)):
//!
//! | kind | `H_e = 0` at `u =` |
//! | --- | --- |
//! | compact (`n ≥ 3`) | `(1 + (n − 2)e)/(n − 1)` (and the support boundary) |
//! | Cauchy | `(1 + (n + 2)e)/(n + 1)` |
//! | Gaussian | `e + 1/2` |
//! | inverse | `(n + 2)e/(n + 1)` |
//!
//! # Soundness
//!
//! Every `*_range` method returns an [`Interval`] that encloses the exact
//! range: the critical points are computed in interval arithmetic (an
//! enclosure of the exact critical point), and the derivative formulas are
//! evaluated with outward-rounded intervals at the ends and over those
//! enclosures. The scale is applied as `D/σ/σ` (two divisions by the exact
//! parameter `σ`), never through a rounded `1/σ²`.
//!
//! ```
//! use boundtrace_fields::kernel::Kernel;
//!
//! let k = Kernel::<f64>::compact(6, 2.0).unwrap();
//! assert_eq!(k.value(0.0), 1.0);
//! assert_eq!(k.value(2.5), 0.0); // outside the support
//! // |k'| is largest at d = σ/√(n − 1) = 2/√5.
//! let r = k.derivative_range(0.0, 2.0);
//! let peak = k.derivative(2.0 / 5f64.sqrt());
//! assert!(r.contains(peak) && r.lo() > peak - 1e-12);
//! assert!(Kernel::<f64>::compact(1, 1.0).is_err()); // degree below 2
//! ```

use crate::FieldError;
use crate::error::positive;
use boundtrace_ia_core::{Interval, Real};
use boundtrace_inclusion::FieldNum;

/// The largest kernel degree accepted (powers stay exact small integers).
pub const MAX_DEGREE: u32 = 64;

/// The kernel family (the `#[repr(u32)]` tag stored in flat scene data).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum KernelKind {
    /// Compact polynomial `max(1 − u, 0)^{n/2}` (thesis eq. 1.7).
    Compact = 0,
    /// Cauchy `(1 + u)^{−n/2}` (thesis eq. 1.8).
    Cauchy = 1,
    /// Gaussian `e^{−u}` (thesis eq. 1.6).
    Gaussian = 2,
    /// Inverse `u^{−n/2}` (thesis eq. 1.9), singular at the center.
    Inverse = 3,
}

impl KernelKind {
    /// The kind of a tag word, or `None` for an unknown tag.
    pub fn from_u32(tag: u32) -> Option<Self> {
        match tag {
            0 => Some(Self::Compact),
            1 => Some(Self::Cauchy),
            2 => Some(Self::Gaussian),
            3 => Some(Self::Inverse),
            _ => None,
        }
    }
}

/// A radial kernel: family, degree `n` and scale `σ` (plain data, `Copy`).
///
/// Invariant (checked by the constructors): `σ` finite and `> 0`; `2 ≤ n ≤`
/// [`MAX_DEGREE`] for the compact, Cauchy and inverse kernels, `n = 0` for
/// the Gaussian.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct Kernel<T> {
    kind: KernelKind,
    degree: u32,
    sigma: T,
}

fn check_degree(n: u32) -> Result<u32, FieldError> {
    if n < 2 {
        Err(FieldError::InvalidParameter {
            name: "n",
            reason: "kernel degree must be >= 2",
        })
    } else if n > MAX_DEGREE {
        Err(FieldError::InvalidParameter {
            name: "n",
            reason: "kernel degree must be <= 64",
        })
    } else {
        Ok(n)
    }
}

/// `x^{e/2}` for `x ≥ 0` and an integer `e ≥ 0`: `x^{e/2}` by `powi` for even
/// `e`, `(√x)^e` for odd `e`.
#[cfg_attr(not(target_arch = "spirv"), inline)]
fn half_pow<T: Real, N: FieldNum<T>>(x: N, e: u32) -> N {
    if e == 0 {
        return N::constant(T::ONE);
    }
    // x^{e/2} = x^{e/2} (even e) or (√x)^e (odd e); one `powi` call site
    // (a GPU driver inlines every call: BENCHMARKS.md "GPU").
    let (base, k) = if e % 2 == 0 {
        (x, e / 2)
    } else {
        (x.sqrt(), e)
    };
    if k == 1 { base } else { base.powi(k as i32) }
}

/// Which side of the compact support boundary `u = 1` a number lies on.
enum Side {
    Inside,
    Outside,
    Both,
}

#[cfg_attr(not(target_arch = "spirv"), inline)]
fn side<T: Real, N: FieldNum<T>>(u: &N) -> Side {
    let e = u.enclosure();
    if e.hi() < T::ONE {
        Side::Inside
    } else if e.lo() >= T::ONE {
        Side::Outside
    } else {
        Side::Both
    }
}

impl<T: Real> Kernel<T> {
    /// The compact polynomial kernel `k_{n,σ}` (thesis eq. 1.7): support
    /// radius `σ`, class `C^{⌈n/2⌉−1}` (`n = 6` gives `C²`).
    ///
    /// # Errors
    /// [`FieldError::InvalidParameter`] when `σ` is not finite and `> 0` or
    /// `n ∉ [2, 64]`.
    pub fn compact(n: u32, sigma: T) -> Result<Self, FieldError> {
        Ok(Self {
            kind: KernelKind::Compact,
            degree: check_degree(n)?,
            sigma: positive("sigma", sigma)?,
        })
    }

    /// [`compact`](Self::compact) for parameters it accepts (a validated
    /// primitive's), without building its error values (a GPU shader
    /// cannot): the same kernel. A degree outside `[2, 64]` is clamped
    /// into it; a `σ` that is not finite and `> 0` gives NaN values.
    #[inline]
    pub(crate) fn compact_trusted(n: u32, sigma: T) -> Self {
        Self {
            kind: KernelKind::Compact,
            degree: n.clamp(2, MAX_DEGREE),
            sigma,
        }
    }

    /// The Cauchy kernel (thesis eq. 1.8).
    ///
    /// # Errors
    /// As [`compact`](Self::compact).
    pub fn cauchy(n: u32, sigma: T) -> Result<Self, FieldError> {
        Ok(Self {
            kind: KernelKind::Cauchy,
            degree: check_degree(n)?,
            sigma: positive("sigma", sigma)?,
        })
    }

    /// The Gaussian kernel `e^{−(d/σ)²}`.
    ///
    /// # Errors
    /// [`FieldError::InvalidParameter`] when `σ` is not finite and `> 0`.
    pub fn gaussian(sigma: T) -> Result<Self, FieldError> {
        Ok(Self {
            kind: KernelKind::Gaussian,
            degree: 0,
            sigma: positive("sigma", sigma)?,
        })
    }

    /// The Gaussian kernel in the papers' form `e^{−s(d/r)²}` (thesis eq.
    /// 1.6, forward-inclusion paper eq. 6): `σ = r/√s`, rounded to nearest
    /// (the kernel is then exactly `e^{−(d/σ)²}` with that `σ`).
    ///
    /// # Errors
    /// [`FieldError::InvalidParameter`] when `s` or `r` is not finite and
    /// `> 0`, or `σ` leaves the float range.
    pub fn gaussian_scaled(s: T, r: T) -> Result<Self, FieldError> {
        let s = positive("s", s)?;
        let r = positive("r", r)?;
        Self::gaussian(r / s.sqrt())
    }

    /// The inverse kernel `(d/σ)^{−n}` (thesis eq. 1.9); `+∞` at the center.
    ///
    /// # Errors
    /// As [`compact`](Self::compact).
    pub fn inverse(n: u32, sigma: T) -> Result<Self, FieldError> {
        Ok(Self {
            kind: KernelKind::Inverse,
            degree: check_degree(n)?,
            sigma: positive("sigma", sigma)?,
        })
    }

    /// The family.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn kind(&self) -> KernelKind {
        self.kind
    }

    /// The degree `n` (`0` for the Gaussian).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn degree(&self) -> u32 {
        self.degree
    }

    /// The scale `σ` (the support radius of the compact kernel).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn sigma(&self) -> T {
        self.sigma
    }

    /// `Some(σ)` for the compact kernel (`k = 0` for `d ≥ σ`), `None` for
    /// the infinite-support kernels.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn support_radius(&self) -> Option<T> {
        match self.kind {
            KernelKind::Compact => Some(self.sigma),
            _ => None,
        }
    }

    /// `u = D/σ²` from the squared distance `D`, as `D/σ/σ` (sound for the
    /// enclosure types: two divisions by the exact `σ`).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn normalize_sq<N: FieldNum<T>>(&self, d2: N) -> N {
        d2 / self.sigma / self.sigma
    }

    /// The `j`-th derivative (`j ≤ 2`) of `K` with respect to `u`, inside
    /// the compact support (for the compact kernel: the polynomial branch,
    /// continued by the clamp `max(1 − u, 0)` beyond `u = 1`).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn profile_inside<N: FieldNum<T>>(&self, u: N, j: u32) -> N {
        let n = self.degree;
        // Coefficients m, m(m−1), m(m+1) with m = n/2: exact (n ≤ 64).
        let nf = T::from_f64(f64::from(n));
        let two = T::TWO;
        let four = T::from_f64(4.0);
        // Every family but the Gaussian is `c · base^{e/2}`; the power and
        // the product are written once (a GPU driver inlines every call:
        // BENCHMARKS.md "GPU").
        let (base, e2, c) = match self.kind {
            KernelKind::Gaussian => {
                let p = (-u).exp();
                return if j == 1 { -p } else { p };
            }
            KernelKind::Compact => {
                // K^{(j)} = (−1)^j m(m−1)…(m−j+1) (1−u)^{m−j}.
                let (c, e2) = match j {
                    0 => (T::ONE, n as i64),
                    1 => (-(nf / two), n as i64 - 2),
                    _ => (nf * (nf - two) / four, n as i64 - 4),
                };
                (u.one_minus_clamped(), e2, c)
            }
            // Cauchy: K^{(j)} = (−1)^j m(m+1)…(m+j−1) (1+u)^{−m−j};
            // inverse: the same with u^{−m−j}.
            KernelKind::Cauchy | KernelKind::Inverse => {
                let c = match j {
                    0 => T::ONE,
                    1 => -(nf / two),
                    _ => nf * (nf + two) / four,
                };
                let v = if self.kind == KernelKind::Cauchy {
                    u + T::ONE
                } else {
                    u
                };
                (v.recip(), i64::from(n + 2 * j), c)
            }
        };
        let p = match e2 {
            e if e >= 0 => half_pow::<T, N>(base, e as u32),
            // Compact, n = 3, j = 2: (1 − u)^{−1/2}.
            -1 => base.sqrt().recip(),
            // Compact, n = 2, j = 2: K'' = 0 inside (m(m − 1) = 0).
            _ => return N::constant(T::ZERO),
        };
        if j == 0 { p } else { p * c }
    }

    /// `K^{(j)}(u)` with the compact support handled: `0` for `u ≥ 1`, the
    /// join of both branches when the enclosure of `u` straddles `1` and
    /// the clamped polynomial is not already `0` there.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn profile<N: FieldNum<T>>(&self, u: N, j: u32) -> N {
        let compact = self.kind == KernelKind::Compact;
        if compact && matches!(side::<T, N>(&u), Side::Outside) {
            // Exactly 0 (also keeps jets of √ at 0 from producing NaN).
            return N::constant(T::ZERO);
        }
        // (1 − u)^{m − j} with m − j ≤ 0: a jump or a pole at u = 1, so an
        // enclosure straddling it also takes the outside value 0. (One call
        // of `profile_inside`: see `half_pow`.)
        let jump = compact && self.degree < 2 * j + 1;
        let straddles = jump && matches!(side::<T, N>(&u), Side::Both);
        let p = self.profile_inside(u, j);
        if straddles {
            p.join(N::constant(T::ZERO))
        } else {
            p
        }
    }

    /// `K(u)`, the kernel as a function of the normalized squared distance
    /// `u = d²/σ²` (`u ≥ 0`), in any number type.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn eval_u<N: FieldNum<T>>(&self, u: N) -> N {
        self.profile(u, 0)
    }

    /// `K'(u) = dK/du` (`≤ 0`).
    ///
    /// For the compact kernel of degree 2 it is `−1` inside the support and
    /// `0` outside (both, joined, on an enclosure that straddles `u = 1`).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn d_u<N: FieldNum<T>>(&self, u: N) -> N {
        self.profile(u, 1)
    }

    /// `K''(u) = d²K/du²` (`≥ 0`; `0` outside a compact support, `+∞` at
    /// the boundary for the compact kernel of degree 3).
    ///
    /// # Warning
    /// For the compact kernel of degree 2 `K'` jumps at `u = 1`, so `K''`
    /// has a Dirac mass there that this function does not represent (it is
    /// `0` on both sides); [`ray_curvature_range`](Self::ray_curvature_range)
    /// accounts for it.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn d2_u<N: FieldNum<T>>(&self, u: N) -> N {
        self.profile(u, 2)
    }

    /// The kernel at the squared distance `D = d²` (not normalized), in any
    /// number type: `K(D/σ²)`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn eval_sq<N: FieldNum<T>>(&self, d2: N) -> N {
        self.eval_u(self.normalize_sq(d2))
    }

    /// `k(d)` at a distance `d ≥ 0`, in plain floats.
    pub fn value(&self, d: T) -> T
    where
        T: FieldNum<T>,
    {
        self.eval_sq(d * d)
    }

    /// `k'(d) = dk/dd = (2d/σ²)·K'(d²/σ²)` in plain floats.
    pub fn derivative(&self, d: T) -> T
    where
        T: FieldNum<T>,
    {
        let s = d / self.sigma;
        self.d_u(s * s) * (T::TWO * s / self.sigma)
    }

    /// `k''(d) = (2/σ²)·(2u·K''(u) + K'(u))`, `u = d²/σ²`, in plain floats.
    pub fn second_derivative(&self, d: T) -> T
    where
        T: FieldNum<T>,
    {
        let s = d / self.sigma;
        let u = s * s;
        (T::TWO * u * self.d2_u(u) + self.d_u(u)) * T::TWO / self.sigma / self.sigma
    }

    /// A sound enclosure of `k'(d)` for a distance interval `D` (`≥ 0`).
    fn derivative_iv(&self, d: Interval<T>) -> Interval<T> {
        let s = d / self.sigma;
        self.d_u(s.sqr()) * (s * T::TWO / self.sigma)
    }

    /// A sound enclosure of `k''(d)` over a distance interval `D` (`≥ 0`).
    fn second_derivative_iv(&self, d: Interval<T>) -> Interval<T> {
        let u = (d / self.sigma).sqr();
        self.ray_curvature_iv(u, Interval::point(T::ZERO)) * T::TWO / self.sigma / self.sigma
    }

    /// The critical point `u*` (an enclosure) of `k'`, if the family has one.
    fn d1_critical_u(&self) -> Option<Interval<T>> {
        let n = Interval::point(T::from_f64(f64::from(self.degree)));
        match self.kind {
            KernelKind::Compact => Some((n - T::ONE).recip()),
            KernelKind::Cauchy => Some((n + T::ONE).recip()),
            KernelKind::Gaussian => Some(Interval::point(T::HALF)),
            KernelKind::Inverse => None,
        }
    }

    /// Sound enclosure of the range of `k'(d)` for `d ∈ [d0, d1]`
    /// (`0 ≤ d0 ≤ d1`; `d1` may be `+∞`): the hull of `k'` at the ends,
    /// over an enclosure of the critical point `σ·√u*` (module docs) when it
    /// lies in the range, and, for the compact kernel, of the limit from
    /// inside at the support boundary `d = σ` (where `k'` jumps for
    /// `n = 2`: the closure of the range). [`Interval::EMPTY`] for an
    /// invalid range.
    pub fn derivative_range(&self, d0: T, d1: T) -> Interval<T> {
        let range = Interval::new(d0, d1);
        if range.is_empty() || d0 < T::ZERO {
            return Interval::EMPTY;
        }
        let mut r = self
            .derivative_iv(Interval::point(d0))
            .hull(self.end_derivative(d1));
        if self.kind == KernelKind::Compact && range.contains(self.sigma) {
            // The limit from inside at the support boundary: k'(σ⁻) =
            // (2/σ)·K'(1⁻), −2/σ for n = 2 (where k' jumps to 0), 0 else.
            let one = Interval::point(T::ONE);
            let edge = self.profile_inside(one, 1) * (Interval::point(T::TWO) / self.sigma);
            r = r.hull(edge);
        }
        if let Some(u) = self.d1_critical_u() {
            let dc = u.sqrt() * self.sigma;
            let dc = dc.intersection(range);
            if !dc.is_empty() {
                r = r.hull(self.derivative_iv(dc));
            }
        }
        r
    }

    /// `k'` at the upper end of a range (`0` at `+∞`).
    fn end_derivative(&self, d1: T) -> Interval<T> {
        if d1 == T::INFINITY {
            // Every family decays to 0 (the inverse kernel's k' too).
            Interval::point(T::ZERO)
        } else {
            self.derivative_iv(Interval::point(d1))
        }
    }

    /// Sound enclosure of the range of `k''(d)` for `d ∈ [d0, d1]`
    /// (`0 ≤ d0 ≤ d1 < +∞`): the hull of `k''` at the ends, at the critical
    /// point `σ·√(3/(n ∓ 1))` (module docs) and, for the compact kernel, at
    /// the support boundary `d = σ` (where `k''` may jump). For the compact
    /// kernel of degree 2 the Dirac mass of `k''` at `d = σ` is not a value
    /// and is ignored here (the values are `−2/σ²` inside, `0` outside).
    pub fn second_derivative_range(&self, d0: T, d1: T) -> Interval<T> {
        let range = Interval::new(d0, d1);
        if range.is_empty() || d0 < T::ZERO || d1 == T::INFINITY {
            return Interval::EMPTY;
        }
        let u0 = (Interval::point(d0) / self.sigma).sqr();
        let u1 = (Interval::point(d1) / self.sigma).sqr();
        let mut r = self.curvature_candidates(u0, u1, Interval::point(T::ZERO), false);
        if r.is_empty() {
            r = self
                .second_derivative_iv(Interval::point(d0))
                .hull(self.second_derivative_iv(Interval::point(d1)));
        }
        r * T::TWO / self.sigma / self.sigma
    }

    /// `H_e(u) = 2(u − e)·K''(u) + K'(u)` over intervals (sound, with the
    /// support branches of [`d_u`](Self::d_u)/[`d2_u`](Self::d2_u)).
    fn ray_curvature_iv(&self, u: Interval<T>, e: Interval<T>) -> Interval<T> {
        (u - e) * T::TWO * self.d2_u(u) + self.d_u(u)
    }

    /// `H_e` with the inside (polynomial) branch only.
    fn ray_curvature_inside(&self, u: Interval<T>, e: Interval<T>) -> Interval<T> {
        (u - e) * T::TWO * self.profile_inside(u, 2) + self.profile_inside(u, 1)
    }

    /// An enclosure of the root `u*` of `H_e(u) = 2(u − e)·K''(u) + K'(u)`
    /// (module docs), where the field's derivative along a ray whose
    /// squared normalized distance has minimum `e` (given as an enclosure)
    /// is extremal; the points are `t = t_m ± √((u* − e)/α)`. `None` for
    /// the compact kernel of degree 2 (`H_e = K' = −1`: no root; its `f'`
    /// jumps at the support boundary instead).
    pub fn ray_slope_critical_u(&self, e: Interval<T>) -> Option<Interval<T>> {
        let n = Interval::point(T::from_f64(f64::from(self.degree)));
        let two = T::TWO;
        match self.kind {
            KernelKind::Compact if self.degree == 2 => None,
            KernelKind::Compact => Some(((n - two) * e + T::ONE) / (n - T::ONE)),
            KernelKind::Cauchy => Some(((n + two) * e + T::ONE) / (n + T::ONE)),
            KernelKind::Gaussian => Some(e + T::HALF),
            KernelKind::Inverse => Some((n + two) * e / (n + T::ONE)),
        }
    }

    /// The enclosure of the interior critical point of `H_e`.
    fn curvature_critical_u(&self, e: Interval<T>) -> Interval<T> {
        let n = Interval::point(T::from_f64(f64::from(self.degree)));
        let three = T::from_f64(3.0);
        let four = T::from_f64(4.0);
        match self.kind {
            KernelKind::Compact => ((n - four) * e + three) / (n - T::ONE),
            KernelKind::Cauchy => ((n + four) * e + three) / (n + T::ONE),
            KernelKind::Gaussian => e + T::from_f64(1.5),
            KernelKind::Inverse => (n + four) * e / (n + T::ONE),
        }
    }

    /// Hull of `H_e` over the candidates of `[u0, u1]` (enclosures of the
    /// range ends). `dirac`: report `ENTIRE` when the compact kernel of
    /// degree 2 may cross its support boundary (a Dirac mass in the ray's
    /// second derivative); the degree 3 pole gives an unbounded side.
    fn curvature_candidates(
        &self,
        u0: Interval<T>,
        u1: Interval<T>,
        e: Interval<T>,
        dirac: bool,
    ) -> Interval<T> {
        if u0.is_empty() || u1.is_empty() || e.is_empty() {
            return Interval::EMPTY;
        }
        let whole = Interval::new(u0.lo(), u1.hi());
        let crit = self.curvature_critical_u(e).intersection(whole);
        if self.kind != KernelKind::Compact {
            let mut r = self
                .ray_curvature_iv(u0, e)
                .hull(self.ray_curvature_iv(u1, e));
            if !crit.is_empty() {
                r = r.hull(self.ray_curvature_iv(crit, e));
            }
            return r;
        }
        let one = T::ONE;
        if u0.lo() >= one {
            // Entirely outside the support.
            return Interval::point(T::ZERO);
        }
        let crosses = u1.hi() >= one;
        if crosses && dirac && self.degree == 2 {
            return Interval::ENTIRE;
        }
        // Inside part [u0, min(u1, 1)]: ends and critical point.
        let clip = |x: Interval<T>| Interval::new(x.lo().min(one), x.hi().min(one));
        let mut r = self
            .ray_curvature_inside(clip(u0), e)
            .hull(self.ray_curvature_inside(clip(u1), e));
        let crit = crit.intersection(Interval::new(T::ZERO, one));
        if !crit.is_empty() {
            r = r.hull(self.ray_curvature_inside(crit, e));
        }
        if self.degree == 3 && crosses {
            // K'' → +∞ at the boundary (2(u − e) ≥ 0 there).
            r = Interval::new(r.lo(), T::INFINITY);
        }
        if crosses || u0.hi() >= one {
            r = r.hull(Interval::point(T::ZERO));
        }
        r
    }

    /// Sound enclosure of `H_e(u) = 2(u − e)·K''(u) + K'(u)` over the `u`
    /// range `[u0, u1]` (given as enclosures of its two ends), where `e ≤ u`
    /// is the minimum of the quadratic `u(t) = α(t − t_m)² + e` along a ray
    /// (given as an enclosure). The field's second derivative along the ray
    /// is `2α·H_e(u(t))` (module docs), so this is the `f''` range that
    /// quadratic Taylor bounds need (forward-inclusion paper App. A).
    ///
    /// Candidates: both ends, the closed-form critical point (module docs)
    /// and, for the compact kernel, the support boundary `u = 1`. Where `f'`
    /// jumps (compact kernel of degree 2 crossing `u = 1`) `f''` has a Dirac
    /// mass and the result is [`Interval::ENTIRE`]; for degree 3 `K''` has a
    /// pole there and the upper side is `+∞`. [`Interval::EMPTY`] for an
    /// empty input.
    pub fn ray_curvature_range(
        &self,
        u0: Interval<T>,
        u1: Interval<T>,
        e: Interval<T>,
    ) -> Interval<T> {
        self.curvature_candidates(u0, u1, e, true)
    }

    /// Sound enclosure of `|k'(d)|` over all `d ≥ 0`: a Lipschitz bound of
    /// the kernel as a function of the point (`None` for the inverse
    /// kernel, which is unbounded). Rounded up.
    pub fn max_slope(&self) -> Option<T> {
        if self.kind == KernelKind::Inverse {
            return None;
        }
        let end = match self.kind {
            KernelKind::Compact => self.sigma,
            _ => T::INFINITY,
        };
        let r = self.derivative_range(T::ZERO, end);
        if r.is_empty() { None } else { Some(r.mag()) }
    }

    /// The radius beyond which `|w|·k(d) ≤ ε` (so a sum of such kernels can
    /// be clipped there with an error of at most `ε` per kernel): `σ` for
    /// the compact kernel (exact: `k = 0` beyond), otherwise from
    /// `K(u) = ε/|w|`: Cauchy `u = (|w|/ε)^{2/n} − 1`, Gaussian
    /// `u = ln(|w|/ε)`, inverse `u = (|w|/ε)^{2/n}`, radius `σ√u` (rounded
    /// up; `0` when `|w| ≤ ε`). `None` for a NaN, zero or negative `ε`.
    ///
    /// # Warning
    /// For the infinite-support kernels the field beyond this radius is not
    /// zero: clipping there is an approximation of at most `ε` per kernel.
    pub fn clip_radius(&self, weight: T, eps: T) -> Option<T> {
        if eps.is_nan() || eps <= T::ZERO || weight.is_nan() {
            return None;
        }
        if self.kind == KernelKind::Compact {
            return Some(self.sigma);
        }
        let ratio = Interval::point(weight.abs()) / eps;
        if ratio.hi() <= T::ONE {
            return Some(T::ZERO);
        }
        let inv_m = Interval::point(T::TWO) / T::from_f64(f64::from(self.degree.max(1)));
        let u = match self.kind {
            // exponent rounded up keeps the power an upper bound (ratio ≥ 1)
            KernelKind::Cauchy => ratio.pow(inv_m.hi()) - T::ONE,
            KernelKind::Inverse => ratio.pow(inv_m.hi()),
            _ => ratio.ln(),
        };
        let r = u.max(Interval::point(T::ZERO)).sqrt() * self.sigma;
        Some(r.hi())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn kernels() -> [Kernel<f64>; 10] {
        [
            Kernel::compact(2, 1.5).unwrap(),
            Kernel::compact(3, 1.5).unwrap(),
            Kernel::compact(4, 0.7).unwrap(),
            Kernel::compact(6, 2.0).unwrap(),
            Kernel::compact(9, 1.0).unwrap(),
            Kernel::cauchy(2, 1.0).unwrap(),
            Kernel::cauchy(5, 0.8).unwrap(),
            Kernel::gaussian(1.3).unwrap(),
            Kernel::inverse(2, 1.0).unwrap(),
            Kernel::inverse(3, 0.5).unwrap(),
        ]
    }

    #[test]
    fn rejects_bad_parameters() {
        assert!(Kernel::<f64>::compact(1, 1.0).is_err());
        assert!(Kernel::<f64>::compact(0, 1.0).is_err());
        assert!(Kernel::<f64>::compact(65, 1.0).is_err());
        assert!(Kernel::<f64>::cauchy(2, 0.0).is_err());
        assert!(Kernel::<f64>::cauchy(2, -1.0).is_err());
        assert!(Kernel::<f32>::gaussian(f32::NAN).is_err());
        assert!(Kernel::<f64>::gaussian(f64::INFINITY).is_err());
        assert!(Kernel::<f64>::inverse(1, 1.0).is_err());
        assert!(Kernel::<f64>::gaussian_scaled(0.0, 1.0).is_err());
        assert_eq!(
            Kernel::<f64>::compact(1, 1.0),
            Err(FieldError::InvalidParameter {
                name: "n",
                reason: "kernel degree must be >= 2"
            })
        );
    }

    #[test]
    fn values_match_definitions() {
        let d = 0.6f64;
        let c = Kernel::compact(6, 2.0).unwrap();
        assert_relative_eq!(c.value(d), (1.0 - 0.09f64).powi(3), epsilon = 1e-15);
        let c3 = Kernel::compact(3, 2.0).unwrap();
        assert_relative_eq!(c3.value(d), (1.0 - 0.09f64).powf(1.5), epsilon = 1e-15);
        let y = Kernel::cauchy(3, 2.0).unwrap();
        assert_relative_eq!(y.value(d), (1.09f64).powf(-1.5), epsilon = 1e-15);
        let g = Kernel::gaussian_scaled(2.0, 1.0).unwrap();
        assert_relative_eq!(g.value(d), (-2.0 * 0.36f64).exp(), epsilon = 1e-15);
        let i = Kernel::inverse(3, 2.0).unwrap();
        assert_relative_eq!(i.value(d), (0.3f64).powi(-3), epsilon = 1e-12);
        assert_eq!(c.value(2.0), 0.0);
        assert_eq!(c.value(7.0), 0.0);
    }

    #[test]
    fn derivatives_match_finite_differences() {
        for k in kernels() {
            for i in 1..40 {
                let d = 0.05 * i as f64;
                if let Some(s) = k.support_radius() {
                    if (d - s).abs() < 0.02 {
                        continue;
                    }
                }
                let h = 1e-5;
                let fd1 = (k.value(d + h) - k.value(d - h)) / (2.0 * h);
                let fd2 = (k.derivative(d + h) - k.derivative(d - h)) / (2.0 * h);
                let scale = 1.0 + k.derivative(d).abs();
                assert_relative_eq!(k.derivative(d), fd1, epsilon = 1e-6 * scale);
                let scale2 = 1.0 + k.second_derivative(d).abs();
                assert_relative_eq!(k.second_derivative(d), fd2, epsilon = 1e-5 * scale2);
            }
        }
    }

    #[test]
    fn extrema_contain_dense_samples_and_are_tight() {
        for k in kernels() {
            for &(d0, d1) in &[(0.0, 3.0), (0.1, 0.4), (0.3, 1.2), (0.5, 0.51), (1.0, 2.5)] {
                if k.kind() == KernelKind::Inverse && d0 == 0.0 {
                    continue;
                }
                let r1 = k.derivative_range(d0, d1);
                let r2 = k.second_derivative_range(d0, d1);
                let (mut lo1, mut hi1, mut lo2, mut hi2) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
                for i in 0..=4000 {
                    let d = d0 + (d1 - d0) * i as f64 / 4000.0;
                    let (a, b) = (k.derivative(d), k.second_derivative(d));
                    // float samples carry their own rounding error
                    let near = |r: Interval<f64>, x: f64| {
                        let tol = 1e-12 * (1.0 + x.abs());
                        r.lo() <= x + tol && x - tol <= r.hi()
                    };
                    assert!(near(r1, a), "{k:?} k'({d}) = {a} not in {r1:?}");
                    if b.is_finite() {
                        assert!(near(r2, b), "{k:?} k''({d}) = {b} not in {r2:?}");
                    }
                    lo1 = lo1.min(a);
                    hi1 = hi1.max(a);
                    if b.is_finite() {
                        lo2 = lo2.min(b);
                        hi2 = hi2.max(b);
                    }
                }
                // Tight: within a small fraction of the sampled spread.
                let tol1 = 1e-3 * (1.0 + hi1.abs().max(lo1.abs()));
                assert!(
                    r1.lo() >= lo1 - tol1 && r1.hi() <= hi1 + tol1,
                    "{k:?} {r1:?}"
                );
                if k.degree() != 3 && !(k.kind() == KernelKind::Compact && d1 >= k.sigma()) {
                    let tol2 = 1e-2 * (1.0 + hi2.abs().max(lo2.abs()));
                    assert!(
                        r2.lo() >= lo2 - tol2 && r2.hi() <= hi2 + tol2,
                        "{k:?} [{d0}, {d1}] {r2:?} vs [{lo2}, {hi2}]"
                    );
                }
            }
        }
    }

    #[test]
    fn compact_degree_two_slope_reaches_the_boundary_limit() {
        let k = Kernel::compact(2, 1.0f64).unwrap();
        let r = k.derivative_range(0.5, 2.0);
        assert!(r.lo() <= -2.0 && r.hi() >= 0.0, "{r:?}");
        assert!(k.derivative_range(0.5, 1.0).contains(-1.999));
        assert!(k.max_slope().unwrap() >= 2.0);
        let k3 = Kernel::compact(3, 2.0f64).unwrap();
        let (m, d) = (k3.max_slope().unwrap(), 2.0 / 2f64.sqrt());
        assert!(m >= k3.derivative(d).abs() && m < k3.derivative(d).abs() + 1e-12);
    }

    #[test]
    fn ray_slope_root_zeroes_curvature() {
        for k in kernels() {
            for &e in &[0.0, 0.1, 0.3] {
                let Some(u) = k.ray_slope_critical_u(Interval::point(e)) else {
                    assert_eq!(k.degree(), 2);
                    continue;
                };
                let u = u.mid();
                if k.kind() == KernelKind::Inverse && e == 0.0 {
                    continue;
                }
                let h = 2.0 * (u - e) * k.d2_u(u) + k.d_u(u);
                assert!(h.abs() < 1e-12 * (1.0 + k.d_u(u).abs()), "{k:?} e={e}: {h}");
            }
        }
    }

    #[test]
    fn max_slope_and_clip_radius() {
        let g = Kernel::gaussian(1.0f64).unwrap();
        let m = g.max_slope().unwrap();
        // max |2d e^{−d²}| = √2 e^{−1/2}
        assert!(m >= 2f64.sqrt() * (-0.5f64).exp() && m < 0.8578);
        assert!(Kernel::inverse(2, 1.0f64).unwrap().max_slope().is_none());
        let r = g.clip_radius(1.0, 1e-3).unwrap();
        assert!(g.value(r) <= 1e-3 && g.value(r * 0.99) > 1e-3);
        let c = Kernel::cauchy(4, 1.0f64).unwrap();
        let r = c.clip_radius(2.0, 1e-2).unwrap();
        assert!(2.0 * c.value(r) <= 1e-2 + 1e-15 && 2.0 * c.value(r * 0.99) > 1e-2);
        assert_eq!(c.clip_radius(1e-3, 1e-2), Some(0.0));
        assert_eq!(
            Kernel::compact(6, 3.0f64).unwrap().clip_radius(1.0, 1e-9),
            Some(3.0)
        );
        assert!(c.clip_radius(1.0, 0.0).is_none());
    }

    #[test]
    fn generic_over_number_types() {
        use boundtrace_inclusion::Jet;
        for k in kernels() {
            let d2 = Jet::variable(0.49f64);
            let j = k.eval_sq(d2);
            let u = 0.49 / k.sigma() / k.sigma();
            assert_relative_eq!(j.d1, k.d_u(u) / k.sigma() / k.sigma(), epsilon = 1e-12);
            let iv = k.eval_sq(Interval::new(0.25, 0.81));
            assert!(iv.contains(k.value(0.7)) && iv.contains(k.value(0.5)));
        }
    }
}
