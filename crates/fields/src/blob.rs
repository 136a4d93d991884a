//! Point blobs (metaballs) and sums of them, with analytic Taylor bounds
//! along rays (forward-inclusion paper §4.4, §7 and App. A).
//!
//! # The field
//!
//! A [`PointBlob`] is a center `c`, a weight `w` and a [`Kernel`]; its
//! density at `p` is `w·k(|p − c|)`. A [`Blobs`] set sums them and exposes
//! the **iso-surface** `Σ wᵢ kᵢ(|p − cᵢ|) = iso` as a [`Field`] with the
//! tracer's sign convention (`f > 0` outside):
//!
//! ```text
//! f(p) = iso − Σᵢ wᵢ · kᵢ(|p − cᵢ|)
//! ```
//!
//! (the density's normalization `1/N` of the papers goes into `wᵢ`).
//! Evaluation is bottom-up in any [`FieldNum`] type, as a function of the
//! squared distance, so the compact and Cauchy kernels stay polynomial /
//! rational; a compact blob whose support the evaluation's enclosure does
//! not reach contributes exactly `0` and is skipped.
//!
//! # Taylor bounds along a ray (App. A)
//!
//! Along the ray `p(t) = o + t·v`, the normalized squared distance to a
//! center is a quadratic `u(t) = (|v|²t² + 2(o − c)·v t + |o − c|²)/σ²
//! = α(t − t_m)² + e`, with `α = |v|²/σ²` and `e = |(o − c) × v|²/(|v|²σ²)`
//! (the line's closest approach). Then, per blob,
//!
//! ```text
//! f'ᵢ(t)  = wᵢ · K'(u) · u'(t)
//! f''ᵢ(t) = wᵢ · (K''(u)·u'² + K'(u)·u'') = wᵢ · 2α · H_e(u),
//! H_e(u)  = 2(u − e)·K''(u) + K'(u)      (since u'² = 4α(u − e), u'' = 2α)
//! ```
//!
//! - the linear Taylor bound (paper §5.1) needs an enclosure of `f'` on
//!   `[t₀, t₁]`: `f'` is extremal at the ends or where `f'' = 0`, i.e.
//!   `H_e(u) = 0`, whose root `u*` is in closed form
//!   ([`Kernel::ray_slope_critical_u`]), at `t = t_m ± √((u* − e)/α)`;
//!   `f'` is evaluated in interval arithmetic at the ends and over
//!   enclosures of those points (the compact kernel of degree 2, whose `f'`
//!   jumps, uses the chain rule with intervals: `K'` over the `u` range
//!   times the range of the linear `u'`);
//! - the quadratic Taylor bound (§6.1) needs `f(t₀)`, `f'(t₀)` and `f''` on
//!   `[t₀, t₁]`: `f''` is a function of `u` alone, whose extrema are at the
//!   ends of the `u` range or at the closed-form critical point of `H_e`
//!   ([`Kernel::ray_curvature_range`]; the paper's eq. 23 for the Gaussian).
//!
//! Every quantity (the `u` range, `e`, the critical points) is enclosed in
//! outward-rounded interval arithmetic, so the bounds are sound. Blobs whose
//! compact support the ray interval misses contribute exactly `0` and are
//! skipped; infinite-support kernels are always summed.
//!
//! ```
//! use boundtrace_fields::blob::{Blobs, PointBlob};
//! use boundtrace_fields::kernel::Kernel;
//! use boundtrace_inclusion::{Field, ForwardQuadratic, Ray, value_at};
//!
//! let k = Kernel::compact(6, 1.0).unwrap();
//! let blobs = [
//!     PointBlob::new([-0.3, 0.0, 0.0], 1.0, k).unwrap(),
//!     PointBlob::new([0.3, 0.0, 0.0], 1.0, k).unwrap(),
//! ];
//! let field = Blobs::new(0.5, blobs).unwrap();
//! assert!(field.eval([0.0f64, 0.0, 0.0]) < 0.0); // inside
//! let ray = Ray::new([-3.0, 0.1, 0.0], [1.0, 0.0, 0.0]);
//! let q: ForwardQuadratic<f64> = field.taylor_quadratic(&ray, 1.5, 2.5).unwrap();
//! assert!(q.start().contains(value_at(&field, &ray, 1.5)));
//! assert!(q.bounds_at(0.5).contains(value_at(&field, &ray, 2.0)));
//! ```

use crate::FieldError;
use crate::bounding::Sphere;
use crate::error::finite3;
use crate::kernel::{Kernel, KernelKind};
use boundtrace_ia_core::{Interval, Real};
use boundtrace_inclusion::{Field, FieldNum, ForwardLinear, ForwardQuadratic, Ray};

/// A point primitive: density `w·k(|p − c|)`.
///
/// Invariant (checked by [`new`](Self::new)): finite center and weight; the
/// kernel is valid by construction.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct PointBlob<T> {
    center: [T; 3],
    weight: T,
    kernel: Kernel<T>,
}

impl<T: Real> PointBlob<T> {
    /// A blob at `center` with weight `w` (any finite value; negative
    /// weights subtract density) and kernel `kernel`.
    ///
    /// # Errors
    /// [`FieldError::InvalidParameter`] for a non-finite center or weight.
    pub fn new(center: [T; 3], weight: T, kernel: Kernel<T>) -> Result<Self, FieldError> {
        let center = finite3("center", center)?;
        if !weight.is_finite() {
            return Err(FieldError::InvalidParameter {
                name: "weight",
                reason: "must be finite",
            });
        }
        Ok(Self {
            center,
            weight,
            kernel,
        })
    }

    /// The center.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn center(&self) -> [T; 3] {
        self.center
    }

    /// The weight `w`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn weight(&self) -> T {
        self.weight
    }

    /// The kernel.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn kernel(&self) -> Kernel<T> {
        self.kernel
    }

    /// The density `w·k(|p − c|)` in any number type.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn density<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        let c = self.center;
        let d2 = (p[0] - c[0]).sqr() + (p[1] - c[1]).sqr() + (p[2] - c[2]).sqr();
        self.kernel.eval_sq(d2) * self.weight
    }

    /// Whether an enclosure of the squared distance proves the point(s)
    /// outside the compact support (so the density is exactly `0`).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn outside_support(&self, d2: Interval<T>) -> bool {
        self.kernel.kind() == KernelKind::Compact
            && !d2.is_empty()
            && (Interval::point(d2.lo()) / self.kernel.sigma() / self.kernel.sigma()).lo() >= T::ONE
    }

    /// The support sphere: radius `σ` for the compact kernel (the density
    /// is exactly `0` outside); for infinite-support kernels the clipping
    /// radius beyond which `|w|·k ≤ eps` ([`Kernel::clip_radius`]). `None`
    /// for a NaN, zero or negative `eps`.
    ///
    /// # Warning
    /// For the Cauchy, Gaussian and inverse kernels the density outside
    /// this sphere is not zero, only at most `eps`.
    pub fn support(&self, eps: T) -> Option<Sphere<T>> {
        Some(Sphere {
            center: self.center,
            radius: self.kernel.clip_radius(self.weight, eps)?,
        })
    }
}

/// A blob set: the field `f(p) = iso − Σ wᵢ kᵢ(|p − cᵢ|)` (positive
/// outside, where the density is below `iso`).
///
/// `S` is any storage of blobs: a fixed array `[PointBlob<T>; K]`, a slice
/// `&[PointBlob<T>]` (`no_std`, no allocation) or a `Vec`.
///
/// The field sums the blobs `start..end` of the storage (all of them unless
/// built by [`window_unchecked`](Blobs::window_unchecked)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Blobs<T, S> {
    iso: T,
    blobs: S,
    start: usize,
    end: usize,
}

/// Per-blob ray data: enclosures of `u(t₀)`, `u'(t₀)`, the `u` range ends,
/// the range of `u'`, and `e`, `2α`.
struct RayData<T> {
    q: [Interval<T>; 3],
    a: Interval<T>,
    tm: Interval<T>,
    u_t0: Interval<T>,
    du_t0: Interval<T>,
    u_min: Interval<T>,
    u_max: Interval<T>,
    du: Interval<T>,
    e: Interval<T>,
    two_alpha: Interval<T>,
}

/// `[f(a₀), f(a₁), f(a₂)]`: `<[_; 3]>::map`, which rust-gpu 0.11 cannot
/// compile (it drains the array through pointer offsets).
#[cfg_attr(not(target_arch = "spirv"), inline)]
fn map3<A: Copy, B>(a: [A; 3], f: impl Fn(A) -> B) -> [B; 3] {
    [f(a[0]), f(a[1]), f(a[2])]
}

/// `[f(a₀, b₀), f(a₁, b₁), f(a₂, b₂)]`: constant indices only (a closure
/// indexing an array with a variable is a bounds check, i.e. a panic path,
/// which rust-gpu 0.11 handles by inlining every caller; BENCHMARKS.md "GPU").
#[cfg_attr(not(target_arch = "spirv"), inline)]
fn zip3<A: Copy, B: Copy, C>(a: [A; 3], b: [B; 3], f: impl Fn(A, B) -> C) -> [C; 3] {
    [f(a[0], b[0]), f(a[1], b[1]), f(a[2], b[2])]
}

fn dot3<T: Real>(a: [Interval<T>; 3], b: [Interval<T>; 3]) -> Interval<T> {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl<T: Real, S: AsRef<[PointBlob<T>]>> Blobs<T, S> {
    /// The field `iso − Σ densities`.
    ///
    /// # Errors
    /// [`FieldError::InvalidParameter`] for a non-finite `iso`.
    pub fn new(iso: T, blobs: S) -> Result<Self, FieldError> {
        if !iso.is_finite() {
            return Err(FieldError::InvalidParameter {
                name: "iso",
                reason: "must be finite",
            });
        }
        Ok(Self::new_unchecked(iso, blobs))
    }

    /// [`new`](Self::new) without the check, for the GPU shader (rust-gpu
    /// cannot build a [`FieldError`] there): a non-finite `iso` gives a
    /// non-finite field instead of an error.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn new_unchecked(iso: T, blobs: S) -> Self {
        let end = blobs.as_ref().len();
        Self::window_unchecked(iso, blobs, 0, end)
    }

    /// The field of the blobs `start..end` of `blobs` (ends past the
    /// storage are clipped), without sub-slicing the storage — a SPIR-V
    /// shader cannot sub-slice a storage buffer — and without checking
    /// `iso` (as [`new_unchecked`](Self::new_unchecked)).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn window_unchecked(iso: T, blobs: S, start: usize, end: usize) -> Self {
        Self {
            iso,
            blobs,
            start,
            end,
        }
    }

    /// The iso-value.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn iso(&self) -> T {
        self.iso
    }

    /// The blobs.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn blobs(&self) -> &[PointBlob<T>] {
        let all = self.blobs.as_ref();
        let end = self.end.min(all.len());
        all.get(self.start.min(end)..end).unwrap_or(&[])
    }

    /// The summed density `Σ wᵢ kᵢ(|p − cᵢ|)` in any number type (compact
    /// blobs proven out of reach are skipped: their density is exactly 0).
    pub fn density<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        // `0` carrying the query's validity: a bound where every primitive is
        // culled must not claim validity beyond the interval the culling
        // was decided on (a constant's is infinite).
        let mut acc = crate::zero_like::<T, N>(&p[0]);
        let all = self.blobs.as_ref();
        let end = self.end.min(all.len());
        let mut i = self.start;
        while i < end {
            let blob = all[i]; // a local copy: no storage-buffer pointer below
            let b = &blob;
            i += 1;
            let c = b.center;
            let d2 = (p[0] - c[0]).sqr() + (p[1] - c[1]).sqr() + (p[2] - c[2]).sqr();
            if b.outside_support(d2.enclosure()) {
                continue;
            }
            acc = acc + b.kernel.eval_sq(d2) * b.weight;
        }
        acc
    }

    /// A sphere containing every blob's [`support`](PointBlob::support)
    /// (rounded up); `None` for an empty set or an invalid `eps`.
    ///
    /// # Warning
    /// As [`PointBlob::support`]: for infinite-support kernels the field
    /// outside differs from `iso` by at most `eps` per blob.
    pub fn bounding_sphere(&self, eps: T) -> Option<Sphere<T>> {
        let blobs = self.blobs();
        let first = blobs.first()?;
        let (mut lo, mut hi) = (first.center, first.center);
        for b in blobs {
            for k in 0..3 {
                lo[k] = lo[k].min(b.center[k]);
                hi[k] = hi[k].max(b.center[k]);
            }
        }
        let center = [
            (lo[0] + hi[0]) * T::HALF,
            (lo[1] + hi[1]) * T::HALF,
            (lo[2] + hi[2]) * T::HALF,
        ];
        let mut radius = T::ZERO;
        for b in blobs {
            let s = b.support(eps)?;
            let q = [0, 1, 2].map(|k| Interval::point(s.center[k]) - center[k]);
            let r = (dot3(q, q).sqrt() + s.radius).hi();
            radius = radius.max(r);
        }
        Some(Sphere { center, radius })
    }

    /// Enclosures of the per-blob quantities along the ray on `[t0, t1]`.
    fn ray_data(b: &PointBlob<T>, ray: &Ray<T>, t0: T, t1: T) -> RayData<T> {
        let sigma = b.kernel.sigma();
        let q = zip3(ray.origin, b.center, |o, c| Interval::point(o) - c);
        let v = map3(ray.dir, Interval::point);
        let at = |t: T| zip3(v, q, |vk, qk| vk * t + qk);
        let (r0, r1) = (at(t0), at(t1));
        let d0 = dot3(r0, r0);
        let d1 = dot3(r1, r1);
        let dp0 = dot3(v, r0) * T::TWO;
        let dp1 = dot3(v, r1) * T::TWO;
        let a = dot3(v, v);
        // Closest approach of the line: |q × v|² / |v|², at t_m = −q·v/|v|².
        let cross = [
            q[1] * v[2] - q[2] * v[1],
            q[2] * v[0] - q[0] * v[2],
            q[0] * v[1] - q[1] * v[0],
        ];
        let (e_line, tm) = if a.lo() > T::ZERO {
            (
                (dot3(cross, cross) / a).max(Interval::point(T::ZERO)),
                -dot3(q, v) / a,
            )
        } else {
            // (Nearly) zero direction: bound through the ends only.
            (Interval::new(T::ZERO, d0.hi()), Interval::ENTIRE)
        };
        let tr = Interval::new(t0, t1);
        let inside = tm.intersection(tr);
        let mut min_lo = d0.lo().min(d1.lo());
        let mut min_hi = d0.hi().min(d1.hi());
        if !inside.is_empty() {
            min_lo = min_lo.min(e_line.lo());
            if tm.subset(tr) {
                min_hi = min_hi.min(e_line.hi()).max(e_line.lo());
            }
        }
        let d_min = Interval::new(min_lo.max(T::ZERO), min_hi);
        let d_max = Interval::new(d0.lo().max(d1.lo()), d0.hi().max(d1.hi()));
        let norm = |x: Interval<T>| x / sigma / sigma;
        RayData {
            q,
            a,
            tm,
            u_t0: norm(d0),
            du_t0: norm(dp0),
            u_min: norm(d_min),
            u_max: norm(d_max),
            du: norm(dp0.hull(dp1)),
            e: norm(e_line),
            two_alpha: norm(a) * T::TWO,
        }
    }

    /// `u'(t)·K'(u(t))` over enclosures `t ∈ T` (sound; tight for thin `T`).
    fn slope_at(b: &PointBlob<T>, ray: &Ray<T>, r: &RayData<T>, t: Interval<T>) -> Interval<T> {
        let sigma = b.kernel.sigma();
        let v = map3(ray.dir, Interval::point);
        let x = zip3(v, r.q, |vk, qk| vk * t + qk);
        let u = dot3(x, x) / sigma / sigma;
        let du = dot3(v, x) * T::TWO / sigma / sigma;
        b.kernel.d_u(u) * du
    }

    /// Enclosure of `u'·K'(u)` (the blob's `f'/w`) over `[t0, t1]`: hull of
    /// the ends and of the two critical points `t_m ± √((u* − e)/α)` of
    /// [`Kernel::ray_slope_critical_u`] (`f'` is continuous there and
    /// `f'' = 0` only at them), plus `0` when a compact support boundary
    /// may be crossed (where `f'' ` is not defined, `f' = 0`). The compact
    /// kernel of degree 2 (jumping `f'`) and a zero direction use the chain
    /// rule with intervals, `K'(u range) · u' range`.
    fn slope_range(
        b: &PointBlob<T>,
        ray: &Ray<T>,
        r: &RayData<T>,
        t0: T,
        t1: T,
        u_range: Interval<T>,
    ) -> Interval<T> {
        let k = b.kernel;
        let crit = k.ray_slope_critical_u(r.e);
        let Some(crit) = crit.filter(|_| r.a.lo() > T::ZERO) else {
            return k.d_u(u_range) * r.du;
        };
        let sigma = b.kernel.sigma();
        let mut s = Self::slope_at(b, ray, r, Interval::point(t0)).hull(Self::slope_at(
            b,
            ray,
            r,
            Interval::point(t1),
        ));
        let zero = Interval::point(T::ZERO);
        let dt = ((crit - r.e).max(zero) * sigma * sigma / r.a).sqrt();
        let tr = Interval::new(t0, t1);
        // An index loop: a shader cannot iterate an array by value.
        let tcs = [r.tm - dt, r.tm + dt];
        let mut i = 0;
        while i < tcs.len() {
            let tc = tcs[i].intersection(tr);
            i += 1;
            if !tc.is_empty() {
                s = s.hull(Self::slope_at(b, ray, r, tc));
            }
        }
        if k.kind() == KernelKind::Compact && r.u_max.hi() >= T::ONE {
            s = s.hull(zero);
        }
        s
    }

    /// The per-primitive extension of the forward-inclusion paper §6.2.1
    /// (Fig. 9) for a compact blob that the ray enters at `t_e ∈ (t₀, t₁)`:
    /// its density and slope are `0` at `t₀` and at `t_e` (degree ≥ 4, so
    /// `k` is C¹ at the support boundary), hence with `f'' ∈ [m, M]` on the
    /// support part, `½·m·(t − t_e)₊² ≤ f ≤ ½·M·(t − t_e)₊²`, and both
    /// sides are bounded by the parabolas through `0` at `t₀` with the same
    /// value at `t₁`: `½·[m, M]·s·(t − t₀)²` with
    /// `s = ((t₁ − t_e)/(t₁ − t₀))² ≤ 1` (`(τ−δ)₊ ≤ τ(h−δ)/h` for
    /// `0 ≤ τ ≤ h`). Returns `s` (rounded up, with `t_e` rounded down), or
    /// `1` when the blob does not qualify.
    #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN takes the `1` branch
    fn entry_scale(b: &PointBlob<T>, r: &RayData<T>, t0: T, t1: T) -> Interval<T> {
        let one = Interval::point(T::ONE);
        let k = b.kernel;
        if k.kind() != KernelKind::Compact
            || k.degree() < 4
            || r.u_t0.lo() < T::ONE
            || !(r.a.lo() > T::ZERO)
            || !(t1 > t0)
        {
            return one;
        }
        // Entry: u(t) = 1, i.e. t = t_m − √((1 − e)·σ²/|d|²) (e = closest u).
        let sigma = k.sigma();
        let half = ((one - r.e).max(Interval::point(T::ZERO)) * sigma * sigma / r.a).sqrt();
        let te = (r.tm - half).lo();
        if !(te > t0) || !(te < t1) {
            return one;
        }
        let frac = (Interval::point(t1) - te) / (Interval::point(t1) - t0);
        Interval::new(T::ZERO, frac.sqr().hi().min(T::ONE))
    }

    /// Enclosures of `f(t₀)`, `f'(t₀)`, and `f'` on `[t₀, t₁]` (when not
    /// `SECOND`; else `0`) or `f''` on `[t₀, t₁]` (when `SECOND`; else `0`);
    /// `None` for an invalid interval. `SECOND` is a constant so that the
    /// linear bound's code holds no curvature code (a GPU driver inlines
    /// every call: BENCHMARKS.md "GPU").
    fn taylor_parts<const SECOND: bool>(
        &self,
        ray: &Ray<T>,
        t0: T,
        t1: T,
    ) -> Option<[Interval<T>; 4]> {
        if !t0.is_finite() || !t1.is_finite() || t1 < t0 {
            return None;
        }
        let zero = Interval::point(T::ZERO);
        let (mut f0, mut df0, mut df, mut d2f) = (zero, zero, zero, zero);
        let all = self.blobs.as_ref();
        let end = self.end.min(all.len());
        let mut i = self.start;
        while i < end {
            let blob = all[i]; // a local copy: no storage-buffer pointer below
            let b = &blob;
            i += 1;
            let r = Self::ray_data(b, ray, t0, t1);
            if b.kernel.kind() == KernelKind::Compact && r.u_min.lo() >= T::ONE {
                // The ray interval misses the support: exactly 0.
                continue;
            }
            let k = b.kernel;
            let w = b.weight;
            let u_range = Interval::new(r.u_min.lo(), r.u_max.hi());
            f0 = f0 + k.eval_u(r.u_t0) * w;
            df0 = df0 + k.d_u(r.u_t0) * r.du_t0 * w;
            if SECOND {
                let h = k.ray_curvature_range(r.u_min, r.u_max, r.e) * r.two_alpha;
                d2f = d2f + h * Self::entry_scale(b, &r, t0, t1) * w;
            } else {
                df = df + Self::slope_range(b, ray, &r, t0, t1, u_range) * w;
            }
        }
        // f = iso − Σ.
        Some([-f0 + self.iso, -df0, -df, -d2f])
    }
}

/// Whether every enclosure is bounded and non-empty (an index loop over
/// an array: a shader can neither iterate a slice nor make one of an
/// array).
fn usable<T: Real, const N: usize>(xs: [Interval<T>; N]) -> bool {
    let mut i = 0;
    while i < N {
        if xs[i].is_empty() || !xs[i].is_bounded() {
            return false;
        }
        i += 1;
    }
    true
}

impl<T: Real, S: AsRef<[PointBlob<T>]>> Field<T> for Blobs<T, S> {
    fn eval<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        -self.density(p) + self.iso
    }

    /// `Σ |wᵢ|·max|kᵢ'|` (rounded up); `None` when a blob uses the inverse
    /// kernel (unbounded slope).
    fn lipschitz(&self) -> Option<T> {
        let mut l = Interval::point(T::ZERO);
        let all = self.blobs.as_ref();
        let end = self.end.min(all.len());
        let mut i = self.start;
        while i < end {
            let blob = all[i]; // a local copy: no storage-buffer pointer below
            let b = &blob;
            i += 1;
            l = l + Interval::point(b.kernel.max_slope()?) * b.weight.abs();
        }
        Some(l.hi())
    }

    /// Linear Taylor bound (paper §5.1, App. A): `f(t₀)` and `f'` over
    /// `[t₀, t₁]` from the chain rule with intervals. `None` for an invalid
    /// interval or when `f'` is unbounded (inverse kernel near a center).
    fn taylor_linear(&self, ray: &Ray<T>, t0: T, t1: T) -> Option<ForwardLinear<T>> {
        let [f0, _, df, _] = self.taylor_parts::<false>(ray, t0, t1)?;
        if !usable([f0, df]) {
            return None;
        }
        let h = (Interval::point(t1) - t0).lo().max(T::ZERO);
        Some(ForwardLinear::taylor(f0, df, h))
    }

    /// Quadratic Taylor bound (paper §6.1, App. A): `f(t₀)`, `f'(t₀)`, and
    /// `f'' = −Σ wᵢ·2αᵢ·H(u)` over `[t₀, t₁]` from the closed-form extrema
    /// of [`Kernel::ray_curvature_range`]. `None` for an invalid interval or
    /// when `f''` is unbounded there (compact kernel of degree 2 or 3
    /// crossing its support boundary, inverse kernel near a center).
    fn taylor_quadratic(&self, ray: &Ray<T>, t0: T, t1: T) -> Option<ForwardQuadratic<T>> {
        let [f0, df0, _, d2f] = self.taylor_parts::<true>(ray, t0, t1)?;
        if !usable([f0, df0, d2f]) {
            return None;
        }
        let h = (Interval::point(t1) - t0).lo().max(T::ZERO);
        Some(ForwardQuadratic::taylor(f0, df0, d2f, h))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use boundtrace_inclusion::{jet_at, value_at};

    fn scene() -> Blobs<f64, [PointBlob<f64>; 4]> {
        let blobs = [
            PointBlob::new([0.0, 0.0, 0.0], 1.0, Kernel::compact(6, 1.0).unwrap()).unwrap(),
            PointBlob::new([0.7, 0.2, 0.0], 0.8, Kernel::cauchy(4, 0.5).unwrap()).unwrap(),
            PointBlob::new([-0.4, 0.5, 0.1], 1.2, Kernel::gaussian(0.6).unwrap()).unwrap(),
            PointBlob::new([0.1, -0.6, 0.3], 0.5, Kernel::compact(4, 0.8).unwrap()).unwrap(),
        ];
        Blobs::new(0.4, blobs).unwrap()
    }

    #[test]
    fn a_window_is_the_field_of_the_sub_slice() {
        let all = scene();
        let blobs = all.blobs();
        let ray = Ray::new([-1.5, 0.1, 0.05], [1.0, 0.05, 0.0]);
        for (start, end) in [(0, 4), (1, 3), (2, 2), (3, 9)] {
            let win = Blobs::window_unchecked(0.4, blobs, start, end);
            let sub = Blobs::new(0.4, &blobs[start.min(4)..end.min(4)]).unwrap();
            assert_eq!(win.blobs(), sub.blobs());
            for i in 0..20 {
                let p = [-1.0 + 0.1 * i as f64, 0.05 * i as f64 - 0.4, 0.1];
                let (a, b): (f64, f64) = (win.eval(p), sub.eval(p));
                assert_eq!(a, b);
            }
            assert_eq!(win.lipschitz(), sub.lipschitz());
            for (t0, t1) in [(0.0, 0.4), (1.0, 1.3), (1.4, 2.6)] {
                assert_eq!(
                    win.taylor_linear(&ray, t0, t1),
                    sub.taylor_linear(&ray, t0, t1)
                );
                assert_eq!(
                    win.taylor_quadratic(&ray, t0, t1),
                    sub.taylor_quadratic(&ray, t0, t1)
                );
            }
        }
        // The whole set equals `new`.
        assert_eq!(
            Blobs::window_unchecked(0.4, blobs, 0, 4),
            Blobs::new(0.4, blobs).unwrap()
        );
    }

    #[test]
    fn rejects_bad_parameters() {
        let k = Kernel::gaussian(1.0f64).unwrap();
        assert!(PointBlob::new([f64::NAN, 0.0, 0.0], 1.0, k).is_err());
        assert!(PointBlob::new([0.0; 3], f64::INFINITY, k).is_err());
        assert!(Blobs::new(f64::NAN, [PointBlob::new([0.0; 3], 1.0, k).unwrap()]).is_err());
    }

    #[test]
    fn culled_bounds_keep_the_window_validity() {
        // Every blob out of reach: the bound is the constant iso, valid on
        // the queried window only (the culling was decided on it).
        let k = Kernel::compact(6, 0.5).unwrap();
        let f = Blobs::new(0.3, [PointBlob::new([5.0, 5.0, 5.0], 1.0, k).unwrap()]).unwrap();
        let ray = Ray::new([0.0; 3], [1.0, 0.0, 0.0]);
        let q: ForwardQuadratic<f64> = f.eval(ray.at(0.0, 1.0));
        let l: ForwardLinear<f64> = f.eval(ray.at(0.0, 1.0));
        assert!(q.validity() <= 1.0 && l.validity() <= 1.0, "{q:?} {l:?}");
        assert!(q.start().contains(0.3) && q.range().contains(0.3));
        let v: f64 = f.eval(ray.at(0.5, 0.5));
        assert_eq!(v, 0.3);
    }

    #[test]
    fn entry_extension_is_tighter_and_contains_samples() {
        // Windows that start outside a compact support and enter it (§6.2.1).
        for n in [4u32, 6, 8] {
            let k = Kernel::compact(n, 1.0).unwrap();
            let f = Blobs::new(0.3, [PointBlob::new([0.0, 0.0, 0.0], 1.0, k).unwrap()]).unwrap();
            for (y, t0, len) in [
                (0.0, 0.0, 2.5),
                (0.4, 1.0, 1.5),
                (0.9, 1.5, 2.0),
                (0.2, 0.5, 0.8),
            ] {
                let ray = Ray::new([-3.0, y, 0.1], [1.0, 0.0, 0.0]);
                let q = f.taylor_quadratic(&ray, t0, t0 + len).unwrap();
                let mut tightened = false;
                for i in 0..=400 {
                    let tau = len * i as f64 / 400.0;
                    let v: f64 = f.eval(ray.at(t0 + tau, t0 + tau));
                    let b = q.bounds_at(tau);
                    assert!(
                        b.lo() <= v && v <= b.hi(),
                        "n {n} y {y} t0 {t0} tau {tau}: {v} ∉ {b:?}"
                    );
                    // The unscaled bound would be iso − ½·M·τ² at the lower side.
                    tightened |= b.lo() > 0.3 - 1e-9 - 0.5 * tau * tau;
                }
                assert!(tightened || t0 + len <= 2.0, "n {n}: no tightening");
            }
        }
    }

    #[test]
    fn taylor_bounds_contain_samples() {
        let f = scene();
        let ray = Ray::new([-2.0, 0.1, 0.05], [1.0, 0.05, 0.0]);
        for i in 0..40 {
            let t0 = 0.1 * i as f64;
            let t1 = t0 + 0.35;
            let l = f.taylor_linear(&ray, t0, t1).unwrap();
            let q = f.taylor_quadratic(&ray, t0, t1).unwrap();
            for j in 0..=16 {
                let tau = 0.35 * j as f64 / 16.0;
                let v = value_at(&f, &ray, t0 + tau);
                assert!(l.bounds_at(tau).contains(v), "linear t0={t0} τ={tau}");
                assert!(q.bounds_at(tau).contains(v), "quadratic t0={t0} τ={tau}");
            }
        }
    }

    #[test]
    fn taylor_start_derivative_matches_jet() {
        let f = scene();
        let ray = Ray::new([-2.0, 0.1, 0.05], [0.8, 0.1, -0.05]);
        let [_, df0, _, _] = f.taylor_parts::<false>(&ray, 1.7, 1.8).unwrap();
        let j = jet_at(&f, &ray, 1.7);
        assert!(df0.contains(j.d1) && df0.width() < 1e-12);
    }

    #[test]
    fn skips_far_compact_blobs_and_bounds() {
        let k = Kernel::compact(6, 1.0f64).unwrap();
        let f = Blobs::new(0.5, [PointBlob::new([0.0, 5.0, 0.0], 1.0, k).unwrap()]).unwrap();
        let ray = Ray::new([-3.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
        let q = f.taylor_quadratic(&ray, 0.0, 6.0).unwrap();
        assert_eq!(q.start(), Interval::point(0.5));
        assert_eq!(q.lower_coeffs(), [0.0, 0.0]);
        let s = f.bounding_sphere(1e-3).unwrap();
        assert!(s.radius >= 1.0);
        assert!(f.lipschitz().unwrap() > 0.0);
    }
}
