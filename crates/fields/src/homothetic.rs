//! Segment primitives with linearly varying radius and the homothetic
//! distance (thesis Part II §1.1, eqs. 1.10–1.13; Part III ch. 1 §1.3.2).
//!
//! A [`Segment`] is a line segment `q(s) = a + s·u`, `s ∈ [0, L]`, `u` the
//! unit axis, with the radius interpolated linearly between the end-points:
//! `τ(s) = r_a + Δ·s`, `Δ = (r_b − r_a)/L`.
//!
//! # Homothetic distance
//!
//! The homothetic distance of `p` to the skeleton point `q(s)` (eq. 1.11) is
//! `h(p, s) = |p − q(s)| / τ(s)`, and to the segment (eq. 1.12)
//! `h_S(p) = min_s h(p, s)`; `h_S ≤ 1` is exactly the sphere-cone (the union
//! of the balls `(q(s), τ(s))`).
//!
//! **Closed form.** Write `w = p − a`, `x = w·u` (axial coordinate) and
//! `d² = |w|² − x²`, so `|p − q(s)|² = Q(s) = (s − x)² + d²`. Then
//!
//! ```text
//! d/ds [Q/τ²] = 2·[(s − x)·τ(s) − Δ·Q(s)] / τ³ = 2·[(s − x)·τ_x − Δ·d²] / τ³,
//! ```
//!
//! with `τ_x = r_a + Δ·x` (the `s²` terms cancel). The numerator is *linear*
//! in `s` with slope `τ_x`: for `τ_x > 0` the unique stationary point
//! `s* = x + Δ·d²/τ_x` is the minimum, for `τ_x ≤ 0` it is a maximum and the
//! minimum is at an end-point. In both cases `h_S² = min(h²(0), h²(L),
//! h²(clamp(s*, 0, L)))`: every candidate is ≥ the minimum and the minimum
//! is one of them. This form needs no branch on `p`, so it is evaluated with
//! every [`FieldNum`] type (`τ_x` is floored at the smallest positive float
//! before the division, which only moves a candidate that is not the
//! minimum).
//!
//! # Argmin along a ray (Part III §1.3.2)
//!
//! For a ray `o + t·d` (unit `d̂ = d/|d|`), the squared distance of `q(s)` to
//! the ray's line is `D(s) = |M + s·U|²` with `M = (a − o)_⊥`, `U = u_⊥`
//! (components orthogonal to `d̂`). Minimising `D(s)/τ(s)²` over `s ∈ [0, L]`
//! exchanges the two minima (eq. 1.9); its derivative is
//! `2·(b·s + c)/τ³` with
//!
//! ```text
//! b = r_a·|U|² − Δ·(M·U),    c = r_a·(M·U) − Δ·|M|²
//! ```
//!
//! (the `s²` terms cancel again: the linear equation `b·x + c = 0` of the
//! thesis, here derived with our parametrisation). For `b > 0` the minimum
//! is at `s = −c/b` (clamped), otherwise at an end-point. The ray parameter
//! is the orthogonal projection of `q(s_min)` onto the ray. See
//! [`Segment::argmin_along_ray`].
//!
//! # Homothetic-distance primitives (eq. 1.13)
//!
//! [`HomotheticPrimitive`] is `k ∘ h_S` for a [`SegmentKernel`], exposed as
//! the field `k(1) − k(h_S(p))` (zero on the sphere-cone, positive outside).

// `!(x > 0)` is deliberate: it is true for NaN, which must be rejected.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::FieldError;
use crate::bounding::SphereCone;
use crate::error::{finite3, positive};
use boundtrace_ia_core::Real;
use boundtrace_inclusion::{Field, FieldNum, Ray};

#[inline]
pub(crate) fn dot<T: Real>(a: [T; 3], b: [T; 3]) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline]
pub(crate) fn sub<T: Real>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// A line segment `a → b` with radius varying linearly from `ra` to `rb`
/// (thesis Part II §1.1: a skeleton edge with prescribed radii at its
/// vertices).
///
/// Invariants (checked by [`Segment::new`]): finite end-points and radii,
/// `ra > 0`, `rb > 0`, `|b − a| > 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct Segment<T> {
    a: [T; 3],
    ra: T,
    b: [T; 3],
    rb: T,
    /// Unit axis `(b − a)/L`.
    u: [T; 3],
    /// Length `L`.
    len: T,
    /// Radius slope `Δ = (rb − ra)/L`.
    slope: T,
}

/// The number of `T` words of a [`Segment`] as stored (`#[repr(C)]`, in
/// memory order: `a`, `r_a`, `b`, `r_b`, the unit axis, the length and the
/// radius slope): [`Segment::to_words`] and [`Segment::from_words_unchecked`],
/// the flat data of a GPU buffer.
pub const SEGMENT_WORDS: usize = 13;

impl<T: Copy> Segment<T> {
    /// The segment's [`SEGMENT_WORDS`] words in memory order (the derived
    /// axis, length and slope included, so that a segment rebuilt from them
    /// is this one bit for bit).
    pub fn to_words(&self) -> [T; SEGMENT_WORDS] {
        let (a, b, u) = (self.a, self.b, self.u);
        [
            a[0], a[1], a[2], self.ra, b[0], b[1], b[2], self.rb, u[0], u[1], u[2], self.len,
            self.slope,
        ]
    }

    /// The segment stored at `words[at..at + SEGMENT_WORDS]` (as
    /// [`to_words`](Self::to_words) writes it), without the checks of
    /// [`new`](Segment::new): for the GPU kernel, whose host wrote the words
    /// of valid segments. Indexes past `words` if it is too short (a panic
    /// on the CPU); invalid words give non-finite values, never a panic.
    #[inline]
    pub fn from_words_unchecked(words: &[T], at: usize) -> Self {
        let w = |k: usize| words[at + k];
        Self {
            a: [w(0), w(1), w(2)],
            ra: w(3),
            b: [w(4), w(5), w(6)],
            rb: w(7),
            u: [w(8), w(9), w(10)],
            len: w(11),
            slope: w(12),
        }
    }
}

impl<T: Real> Segment<T> {
    /// A segment from `a` (radius `ra`) to `b` (radius `rb`).
    ///
    /// # Errors
    ///
    /// [`FieldError::InvalidParameter`] for a NaN/infinite coordinate or
    /// radius, a radius `≤ 0`, or a zero-length (or non-finite-length)
    /// segment.
    ///
    /// ```
    /// use boundtrace_fields::homothetic::Segment;
    /// let s = Segment::new([0.0, 0.0, 0.0], 1.0, [2.0, 0.0, 0.0], 0.5).unwrap();
    /// assert_eq!(s.length(), 2.0);
    /// assert!(Segment::new([0.0; 3], 1.0, [0.0; 3], 1.0).is_err());
    /// assert!(Segment::new([0.0; 3], -1.0, [1.0, 0.0, 0.0], 1.0).is_err());
    /// ```
    pub fn new(a: [T; 3], ra: T, b: [T; 3], rb: T) -> Result<Self, FieldError> {
        let a = finite3("a", a)?;
        let b = finite3("b", b)?;
        let ra = positive("ra", ra)?;
        let rb = positive("rb", rb)?;
        let ab = sub(b, a);
        let len = dot(ab, ab).sqrt();
        if !len.is_finite() {
            return Err(FieldError::InvalidParameter {
                name: "b",
                reason: "segment length overflows",
            });
        }
        if len <= T::ZERO {
            return Err(FieldError::InvalidParameter {
                name: "b",
                reason: "zero-length segment (a == b)",
            });
        }
        let u = [ab[0] / len, ab[1] / len, ab[2] / len];
        Ok(Self {
            a,
            ra,
            b,
            rb,
            u,
            len,
            slope: (rb - ra) / len,
        })
    }

    /// First end-point `a`.
    #[inline]
    pub fn a(&self) -> [T; 3] {
        self.a
    }
    /// Second end-point `b`.
    #[inline]
    pub fn b(&self) -> [T; 3] {
        self.b
    }
    /// Radius at `a`.
    #[inline]
    pub fn ra(&self) -> T {
        self.ra
    }
    /// Radius at `b`.
    #[inline]
    pub fn rb(&self) -> T {
        self.rb
    }
    /// Unit axis `u = (b − a)/L`.
    #[inline]
    pub fn axis(&self) -> [T; 3] {
        self.u
    }
    /// Length `L`.
    #[inline]
    pub fn length(&self) -> T {
        self.len
    }
    /// Radius slope `Δ = (rb − ra)/L`.
    #[inline]
    pub fn radius_slope(&self) -> T {
        self.slope
    }
    /// The skeleton point `q(s) = a + s·u` (`s` is an arc length).
    #[inline]
    pub fn point_at(&self, s: T) -> [T; 3] {
        [
            self.a[0] + s * self.u[0],
            self.a[1] + s * self.u[1],
            self.a[2] + s * self.u[2],
        ]
    }
    /// The radius `τ(s) = ra + Δ·s`.
    #[inline]
    pub fn radius_at(&self, s: T) -> T {
        self.ra + self.slope * s
    }

    /// `(x, d²)`: the axial coordinate `(p − a)·u` and the squared distance
    /// to the segment's *line*, in any number type.
    #[inline]
    pub fn axial<N: FieldNum<T>>(&self, p: [N; 3]) -> (N, N) {
        let w = [p[0] - self.a[0], p[1] - self.a[1], p[2] - self.a[2]];
        let x = w[0] * self.u[0] + w[1] * self.u[1] + w[2] * self.u[2];
        // d² = |w × u|², free of the cancellation of |w|² − x².
        let c0 = w[1] * self.u[2] - w[2] * self.u[1];
        let c1 = w[2] * self.u[0] - w[0] * self.u[2];
        let c2 = w[0] * self.u[1] - w[1] * self.u[0];
        if !N::IS_FORM {
            return (x, c0.sqr() + c1.sqr() + c2.sqr());
        }
        // For the forms, `c0² + c1² + c2²` (the same sums) in a loop: one
        // `sqr` call site, since the shader inlines every call and a form's
        // `sqr` is large (BENCHMARKS.md "GPU", session 36). Not for the
        // other types: llvmpipe counts every loop iteration against one
        // budget per invocation, and the SCALIS normals ran out of it.
        let mut d2 = c0;
        let mut k = 0;
        while k < 3 {
            let c = if k == 0 {
                c0
            } else if k == 1 {
                c1
            } else {
                c2
            };
            let q = c.sqr();
            d2 = if k == 0 { q } else { d2 + q };
            k += 1;
        }
        (x, d2)
    }

    /// The squared homothetic distance to the skeleton point `q(s)`
    /// (eq. 1.11 squared): `|p − q(s)|² / τ(s)²`.
    #[inline]
    pub fn homothetic_sq_to_point<N: FieldNum<T>>(&self, p: [N; 3], s: T) -> N {
        let (x, d2) = self.axial(p);
        let tau = self.radius_at(s);
        ((-x + s).sqr() + d2) / (tau * tau)
    }

    /// The squared homothetic distance `h_S(p)²` to the segment (eq. 1.12,
    /// squared), by the closed form of the module docs.
    ///
    /// ```
    /// use boundtrace_fields::homothetic::Segment;
    /// let s = Segment::new([0.0, 0.0, 0.0], 1.0, [4.0, 0.0, 0.0], 1.0).unwrap();
    /// // constant radius: the Euclidean distance to the segment over the radius
    /// assert!((s.homothetic_sq([2.0, 3.0, 0.0]) - 9.0f64).abs() < 1e-12);
    /// ```
    pub fn homothetic_sq<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        let (x, d2) = self.axial(p);
        let tau_x = (x * self.slope + self.ra).max(N::constant(T::MIN_SUBNORMAL));
        if !N::IS_FORM {
            // Straight-line for points, intervals and jets (no loop: see
            // `axial`); the loop below computes the same for the forms.
            let h2_at = |s: N| {
                // τ(s) > 0 for s ∈ [0, L]
                let tau = s * self.slope + self.ra;
                ((x - s).sqr() + d2) / tau.sqr()
            };
            let s_star = (x + d2 * self.slope / tau_x)
                .max(N::constant(T::ZERO))
                .min(N::constant(self.len));
            let e0 = (x.sqr() + d2) / (self.ra * self.ra);
            let e1 = ((-x + self.len).sqr() + d2) / (self.rb * self.rb);
            return e0.min(e1).min(h2_at(s_star));
        }
        // Step 0: the clamped stationary point s* = clamp(x + d²·Δ/τ(x), 0,
        // L). Steps 1-3: min(e0, e1, h²(s*)) with e0 = (x² + d²)/ra², e1 =
        // ((L − x)² + d²)/rb² (the end-points) and h²(s) = ((x − s)² +
        // d²)/τ(s)², τ(s) > 0 for s ∈ [0, L]. A loop, so that the division
        // of two forms, `sqr` and `min` have one call site each (the shader
        // inlines every call: BENCHMARKS.md "GPU", session 36), for the
        // forms only (see `axial`).
        let mut s_star = x;
        let mut h2 = x;
        let mut k = 0;
        while k < 4 {
            let num = if k == 0 {
                d2 * self.slope
            } else {
                let a = if k == 1 {
                    x
                } else if k == 2 {
                    -x + self.len
                } else {
                    x - s_star
                };
                a.sqr() + d2
            };
            let e = if k == 1 {
                num / (self.ra * self.ra)
            } else if k == 2 {
                num / (self.rb * self.rb)
            } else {
                let den = if k == 0 {
                    tau_x
                } else {
                    (s_star * self.slope + self.ra).sqr()
                };
                num / den
            };
            if k == 0 {
                s_star = (x + e).max(N::constant(T::ZERO)).min(N::constant(self.len));
            } else {
                h2 = if k == 1 { e } else { h2.min(e) };
            }
            k += 1;
        }
        h2
    }

    /// The homothetic distance `h_S(p)` (eq. 1.12).
    #[inline]
    pub fn homothetic_distance<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        self.homothetic_sq(p).sqrt()
    }

    /// The skeleton parameter `s ∈ [0, L]` where `h(p, s)` is minimal (a
    /// point query in plain floats; see the module docs).
    pub fn closest_homothetic_param(&self, p: [T; 3]) -> T {
        let (Plain(x), Plain(d2)) = self.axial(p.map(Plain));
        let tau_x = self.ra + self.slope * x;
        let h2 = |s: T| ((s - x) * (s - x) + d2) / (self.radius_at(s) * self.radius_at(s));
        let (h0, h1) = (h2(T::ZERO), h2(self.len));
        let end = if h0 <= h1 { T::ZERO } else { self.len };
        if tau_x > T::ZERO {
            let s = (x + self.slope * d2 / tau_x).max(T::ZERO).min(self.len);
            if h2(s) <= h2(end) {
                return s;
            }
        }
        end
    }

    /// The argmin of the homothetic distance along a ray (Part III §1.3.2,
    /// eq. 1.6): `(t, s, h²)` with `t` the ray parameter, `s ∈ [0, L]` the
    /// skeleton parameter and `h²` the squared homothetic distance of the
    /// skeleton point `q(s)` to the ray's *line* (`t` ranges over ℝ; clamp it
    /// to the ray's interval yourself). `None` for a zero or non-finite
    /// direction.
    ///
    /// ```
    /// use boundtrace_fields::homothetic::Segment;
    /// use boundtrace_inclusion::Ray;
    /// let s = Segment::new([0.0, 0.0, 0.0], 0.5, [2.0, 0.0, 0.0], 1.0).unwrap();
    /// let ray = Ray::new([1.0, 5.0, 0.5], [0.0, -1.0, 0.0]);
    /// let (t, s_min, h2) = s.argmin_along_ray(&ray).unwrap();
    /// assert!((t - 5.0f64).abs() < 1e-12); // the ray passes through y = 0
    /// assert!(h2 <= 1.0);
    /// # let _ = s_min;
    /// ```
    pub fn argmin_along_ray(&self, ray: &Ray<T>) -> Option<(T, T, T)> {
        let dd = dot(ray.dir, ray.dir);
        if !(dd > T::ZERO) || !dd.is_finite() {
            return None;
        }
        let inv = T::ONE / dd.sqrt();
        let dh = [ray.dir[0] * inv, ray.dir[1] * inv, ray.dir[2] * inv];
        let perp = |v: [T; 3]| {
            let k = dot(v, dh);
            [v[0] - k * dh[0], v[1] - k * dh[1], v[2] - k * dh[2]]
        };
        let m = perp(sub(self.a, ray.origin));
        let uu = perp(self.u);
        let (mm, mu, u2) = (dot(m, m), dot(m, uu), dot(uu, uu));
        let phi = |s: T| {
            let tau = self.radius_at(s);
            (mm + s * (T::TWO * mu + s * u2)).max(T::ZERO) / (tau * tau)
        };
        let b = self.ra * u2 - self.slope * mu;
        let c = self.ra * mu - self.slope * mm;
        let (p0, p1) = (phi(T::ZERO), phi(self.len));
        let (mut s, mut h2) = if p0 <= p1 {
            (T::ZERO, p0)
        } else {
            (self.len, p1)
        };
        if b > T::ZERO {
            let sc = (-c / b).max(T::ZERO).min(self.len);
            let pc = phi(sc);
            if pc <= h2 {
                s = sc;
                h2 = pc;
            }
        }
        let q = self.point_at(s);
        let t = dot(sub(q, ray.origin), ray.dir) / dd;
        Some((t, s, h2))
    }

    /// The sphere-cone of the radii scaled by `scale` (`scale = 1`: the
    /// union of balls `h_S ≤ 1`; `scale = σ`: the support of a compact
    /// kernel, thesis Fig. 1.6).
    #[inline]
    pub fn sphere_cone(&self, scale: T) -> SphereCone<T> {
        SphereCone {
            a: self.a,
            ra: self.ra * scale,
            b: self.b,
            rb: self.rb * scale,
        }
    }
}

/// A plain float as a [`FieldNum`], so the generic code of this crate can
/// run on any `T: Real` (the crate's `f32`/`f64` impls need `T` concrete).
#[derive(Clone, Copy, Debug, PartialEq, PartialOrd)]
pub(crate) struct Plain<T>(pub(crate) T);

macro_rules! wrap_binop {
    ($tr:ident, $f:ident, $op:tt) => {
        impl<T: Real> core::ops::$tr for Plain<T> {
            type Output = Self;
            #[inline]
            fn $f(self, o: Self) -> Self {
                Plain(self.0 $op o.0)
            }
        }
        impl<T: Real> core::ops::$tr<T> for Plain<T> {
            type Output = Self;
            #[inline]
            fn $f(self, o: T) -> Self {
                Plain(self.0 $op o)
            }
        }
    };
}
wrap_binop!(Add, add, +);
wrap_binop!(Sub, sub, -);
wrap_binop!(Mul, mul, *);
wrap_binop!(Div, div, /);

impl<T: Real> core::ops::Neg for Plain<T> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Plain(-self.0)
    }
}

impl<T: Real> FieldNum<T> for Plain<T> {
    fn constant(c: T) -> Self {
        Plain(c)
    }
    fn ray_param(t0: T, _t1: T) -> Self {
        Plain(t0)
    }
    fn sqr(self) -> Self {
        Plain(self.0 * self.0)
    }
    fn powi(self, n: i32) -> Self {
        Plain(self.0.powi(n))
    }
    fn powf(self, p: T) -> Self {
        Plain(self.0.powf_ia(p))
    }
    fn sqrt(self) -> Self {
        Plain(self.0.sqrt())
    }
    fn recip(self) -> Self {
        Plain(self.0.recip())
    }
    fn exp(self) -> Self {
        Plain(self.0.exp_ia())
    }
    fn ln(self) -> Self {
        Plain(self.0.ln_ia())
    }
    fn sin(self) -> Self {
        Plain(self.0.sin())
    }
    fn cos(self) -> Self {
        Plain(self.0.cos())
    }
    fn abs(self) -> Self {
        Plain(self.0.abs())
    }
    fn min(self, o: Self) -> Self {
        Plain(self.0.min(o.0))
    }
    fn max(self, o: Self) -> Self {
        Plain(self.0.max(o.0))
    }
    fn enclosure(&self) -> boundtrace_ia_core::Interval<T> {
        boundtrace_ia_core::Interval::point(self.0)
    }
    fn join(self, _o: Self) -> Self {
        self
    }
}

/// `h_S(p) − 1`: zero on the sphere-cone of the segment, negative inside,
/// positive outside (not a distance: no Lipschitz bound is claimed).
impl<T: Real> Field<T> for Segment<T> {
    fn eval<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        self.homothetic_distance(p) - T::ONE
    }
}

/// A kernel of a segment primitive, written on the squared homothetic
/// distance `h²` (thesis Part II eqs. 1.7–1.8).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SegmentKernel<T> {
    /// `(1 − h²/σ²)^{n/2}` for `h < σ`, `0` beyond (eq. 1.7); `n` even.
    CompactPolynomial {
        /// Even degree `n ≥ 2`.
        degree: u32,
        /// Scale `σ > 0`.
        sigma: T,
    },
    /// `(1 + h²/σ²)^{−n/2}` (eq. 1.8).
    Cauchy {
        /// Degree `n ≥ 2`.
        degree: u32,
        /// Scale `σ > 0`.
        sigma: T,
    },
}

impl<T: Real> SegmentKernel<T> {
    /// The compact polynomial kernel of even degree `n ≥ 2` and scale `σ`.
    ///
    /// # Errors
    ///
    /// [`FieldError::InvalidParameter`] for `n < 2`, odd `n`, `n > 64`, or a
    /// NaN/infinite/non-positive `σ`.
    pub fn compact_polynomial(degree: u32, sigma: T) -> Result<Self, FieldError> {
        check_degree(degree)?;
        if degree % 2 != 0 {
            return Err(FieldError::InvalidParameter {
                name: "degree",
                reason: "the compact polynomial kernel needs an even degree",
            });
        }
        Ok(Self::CompactPolynomial {
            degree,
            sigma: positive("sigma", sigma)?,
        })
    }

    /// The Cauchy kernel of degree `n ≥ 2` and scale `σ`.
    ///
    /// # Errors
    ///
    /// [`FieldError::InvalidParameter`] for `n < 2`, `n > 64`, or a
    /// NaN/infinite/non-positive `σ`.
    pub fn cauchy(degree: u32, sigma: T) -> Result<Self, FieldError> {
        check_degree(degree)?;
        Ok(Self::Cauchy {
            degree,
            sigma: positive("sigma", sigma)?,
        })
    }

    /// `k` at the squared distance `h2 ≥ 0`, in any number type.
    pub fn eval_sq<N: FieldNum<T>>(&self, h2: N) -> N {
        let [kind, degree] = self.code();
        kernel_sq(kind, degree, self.sigma(), h2)
    }

    /// The kernel's plain-data code `[kind, degree]`: kind
    /// [`KERNEL_COMPACT`] or [`KERNEL_CAUCHY`] (with
    /// [`sigma`](Self::sigma), what
    /// [`from_code_unchecked`](Self::from_code_unchecked) rebuilds it
    /// from: an enum with data is not GPU buffer data).
    pub fn code(&self) -> [u32; 2] {
        match *self {
            Self::CompactPolynomial { degree, .. } => [KERNEL_COMPACT, degree],
            Self::Cauchy { degree, .. } => [KERNEL_CAUCHY, degree],
        }
    }

    /// The kernel of [`code`](Self::code) `[kind, degree]` and scale
    /// `sigma`, without the checks of the constructors (any kind but
    /// [`KERNEL_COMPACT`] is Cauchy).
    pub fn from_code_unchecked(code: [u32; 2], sigma: T) -> Self {
        let [kind, degree] = code;
        if kind == KERNEL_COMPACT {
            Self::CompactPolynomial { degree, sigma }
        } else {
            Self::Cauchy { degree, sigma }
        }
    }

    /// The kernel scale `σ`.
    pub fn sigma(&self) -> T {
        match *self {
            Self::CompactPolynomial { sigma, .. } | Self::Cauchy { sigma, .. } => sigma,
        }
    }
}

/// [`SegmentKernel::code`]'s kind of a compact polynomial kernel.
pub const KERNEL_COMPACT: u32 = 0;
/// [`SegmentKernel::code`]'s kind of a Cauchy kernel.
pub const KERNEL_CAUCHY: u32 = 1;

/// [`SegmentKernel::eval_sq`] from the kernel's plain data (its
/// [`code`](SegmentKernel::code) and `σ`), with no enum: the form that the
/// GPU's fields evaluate (any kind but [`KERNEL_COMPACT`] is Cauchy).
#[inline]
pub(crate) fn kernel_sq<T: Real, N: FieldNum<T>>(kind: u32, degree: u32, sigma: T, h2: N) -> N {
    // One call site per operation (the kernels' bases first, then a single
    // `powi` and a single `recip`): the shader's forward forms inline every
    // call, and three `powi`s made the homothetic bottom-up pipeline too
    // large for lavapipe (BENCHMARKS.md "GPU", session 36). The same
    // operations as `(1 − u)₊^{d/2}` and `1/(1 + u)^{d/2}` or
    // `1/√((1 + u)^d)`, so the same results.
    let u = h2 / (sigma * sigma);
    let compact = kind == KERNEL_COMPACT;
    let odd = degree % 2 != 0;
    let n = if compact || !odd { degree / 2 } else { degree };
    let base = if compact {
        u.one_minus_clamped()
    } else {
        u + T::ONE
    };
    let p = base.powi(n as i32);
    if compact {
        p
    } else {
        (if odd { p.sqrt() } else { p }).recip()
    }
}

fn check_degree(degree: u32) -> Result<(), FieldError> {
    if degree < 2 {
        return Err(FieldError::InvalidParameter {
            name: "degree",
            reason: "kernel degree must be ≥ 2",
        });
    }
    if degree > 64 {
        return Err(FieldError::InvalidParameter {
            name: "degree",
            reason: "kernel degree must be ≤ 64",
        });
    }
    Ok(())
}

/// A homothetic-distance primitive `k ∘ h_S` (thesis eq. 1.13), as the
/// field `k(1) − k(h_S(p))`: zero on the sphere-cone, positive outside,
/// negative inside (kernels are decreasing).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HomotheticPrimitive<T> {
    /// The skeleton segment.
    pub segment: Segment<T>,
    /// The kernel.
    pub kernel: SegmentKernel<T>,
}

impl<T: Real> HomotheticPrimitive<T> {
    /// The primitive of `segment` with `kernel`.
    ///
    /// # Errors
    ///
    /// [`FieldError::InvalidParameter`] for a compact kernel with `σ ≤ 1`
    /// (the surface `h_S = 1` would be outside the support).
    pub fn new(segment: Segment<T>, kernel: SegmentKernel<T>) -> Result<Self, FieldError> {
        if let SegmentKernel::CompactPolynomial { sigma, .. } = kernel {
            if !(sigma > T::ONE) {
                return Err(FieldError::InvalidParameter {
                    name: "sigma",
                    reason: "a compact kernel needs σ > 1 for the surface to be in its support",
                });
            }
        }
        Ok(Self { segment, kernel })
    }

    /// The density `k(h_S(p))`.
    #[inline]
    pub fn density<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        self.kernel.eval_sq(self.segment.homothetic_sq(p))
    }
}

impl<T: Real> Field<T> for HomotheticPrimitive<T> {
    fn eval<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        let iso = self.kernel.eval_sq(Plain(T::ONE)).0;
        -self.density(p) + iso
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use boundtrace_ia_core::Interval;

    fn seg() -> Segment<f64> {
        Segment::new([0.0, 0.0, 0.0], 0.5, [3.0, 1.0, 0.0], 1.2).unwrap()
    }

    #[test]
    fn rejects_bad_parameters() {
        let o = [0.0; 3];
        let x = [1.0, 0.0, 0.0];
        assert!(Segment::new(o, 0.0, x, 1.0).is_err());
        assert!(Segment::new(o, 1.0, x, -1.0).is_err());
        assert!(Segment::new(o, f64::NAN, x, 1.0).is_err());
        assert!(Segment::new([f64::NAN, 0.0, 0.0], 1.0, x, 1.0).is_err());
        assert!(Segment::new(o, 1.0, o, 1.0).is_err());
        assert!(SegmentKernel::compact_polynomial(1, 2.0).is_err());
        assert!(SegmentKernel::compact_polynomial(3, 2.0).is_err());
        assert!(SegmentKernel::cauchy(0, 2.0).is_err());
        assert!(SegmentKernel::compact_polynomial(4, -2.0).is_err());
    }

    #[test]
    fn homothetic_matches_dense_minimum() {
        let s = seg();
        let pts = [
            [1.0, 2.0, 0.3],
            [-1.0, 0.2, 0.0],
            [5.0, 2.0, -1.0],
            [1.5, 0.5, 0.0],
        ];
        for p in pts {
            let h2: f64 = s.homothetic_sq(p);
            let mut best = f64::INFINITY;
            for i in 0..=20000 {
                let si = s.length() * i as f64 / 20000.0;
                best = best.min(s.homothetic_sq_to_point(p, si));
            }
            assert!(h2 <= best + 1e-12 && best - h2 < 1e-6, "{h2} {best}");
            let sm = s.closest_homothetic_param(p);
            assert!((s.homothetic_sq_to_point(p, sm) - h2).abs() < 1e-12);
            let iv: Interval<f64> = s.homothetic_sq(p.map(Interval::point));
            assert!(iv.contains(h2));
        }
    }

    #[test]
    fn primitive_is_zero_on_the_sphere_cone() {
        let k = SegmentKernel::compact_polynomial(6, 2.0).unwrap();
        let prim = HomotheticPrimitive::new(seg(), k).unwrap();
        // on the ball around a, opposite to the segment
        let d = [-3.0 / 10f64.sqrt(), -1.0 / 10f64.sqrt(), 0.0];
        let p = [0.5 * d[0], 0.5 * d[1], 0.0];
        assert!(prim.eval(p).abs() < 1e-12);
        assert!(prim.eval([0.0, 0.0, 2.0]) > 0.0);
        assert!(prim.eval([1.5, 0.5, 0.0]) < 0.0);
    }
}
