//! Per-primitive bounds of the SCALIS density on a ray interval by skeleton
//! cells (Riemann sums), cheap and tight away from the surface.
//!
//! For a compact kernel, `f(p) = 1/N ∫₀ᴸ k(|p − q(s)|/τ(s))/τ(s) ds`
//! (thesis Part II eq. 1.14) with `k` decreasing in `h`. Cut `[0, L]` into
//! `n` cells `[s_j, s_{j+1}]`; on a cell the skeleton points lie on the
//! straight piece `q(s_j) q(s_{j+1})` and `τ` between `τ(s_j)` and
//! `τ(s_{j+1})`. For every point `p` of the ray piece `P = [p(a), p(b)]`:
//!
//! ```text
//! Δs_j · k(d_max/τ_min)/τ_max ≤ ∫_cell k(h)/τ ds ≤ Δs_j · k(d_min/τ_max)/τ_min
//! ```
//!
//! with `d_min` the distance between the skeleton piece and `P` (segment to
//! segment, closed form) and `d_max` the largest distance between their
//! end-points (the distance is convex on the product of the two segments,
//! so its maximum is at a pair of end-points). Summing over the cells gives
//! an enclosure of `f` on the whole ray interval, with an error of order
//! `L/n + |P|` times the integrand's slope. Distances are computed in
//! floats and widened by a relative slack of `64 ε` of the coordinates'
//! magnitude (as the crate's bounding volumes are); the sums run in
//! interval arithmetic.
//!
//! This is the role of the per-primitive interval bounds of ch. 2 §2.1 (a
//! sound range per primitive, combined by interval arithmetic); the closed
//! form's own interval extension ([`ScalisSegment::density_range`]) is much
//! wider on thin primitives (its derivative enclosure is of the order of
//! the global slope), which is why these sums are used first.

use boundtrace_fields::homothetic::SegmentKernel;
use boundtrace_fields::scalis::ScalisSegment;
use boundtrace_ia_core::{Interval, Real};
use boundtrace_inclusion::{ForwardQuadratic, Ray};

#[inline]
fn sub<T: Real>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline]
fn dot<T: Real>(a: [T; 3], b: [T; 3]) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline]
fn clamp01<T: Real>(x: T) -> T {
    if x > T::ONE {
        T::ONE
    } else if x >= T::ZERO {
        x
    } else {
        T::ZERO
    }
}

/// The distance between the segments `[p0, p1]` and `[q0, q1]` (closest
/// points by clamped parameters; degenerate segments allowed), in floats.
pub fn segment_distance<T: Real>(p0: [T; 3], p1: [T; 3], q0: [T; 3], q1: [T; 3]) -> T {
    let d1 = sub(p1, p0);
    let d2 = sub(q1, q0);
    let r = sub(p0, q0);
    let (a, e, f) = (dot(d1, d1), dot(d2, d2), dot(d2, r));
    let (s, t);
    if a <= T::ZERO && e <= T::ZERO {
        (s, t) = (T::ZERO, T::ZERO);
    } else if a <= T::ZERO {
        s = T::ZERO;
        t = clamp01(f / e);
    } else {
        let c = dot(d1, r);
        if e <= T::ZERO {
            t = T::ZERO;
            s = clamp01(-c / a);
        } else {
            let b = dot(d1, d2);
            let den = a * e - b * b;
            let s0 = if den > T::ZERO {
                clamp01((b * f - c * e) / den)
            } else {
                T::ZERO
            };
            let t0 = (b * s0 + f) / e;
            if t0 < T::ZERO {
                t = T::ZERO;
                s = clamp01(-c / a);
            } else if t0 > T::ONE {
                t = T::ONE;
                s = clamp01((b - c) / a);
            } else {
                (s, t) = (s0, t0);
            }
        }
    }
    let cp = [
        p0[0] + d1[0] * s - q0[0] - d2[0] * t,
        p0[1] + d1[1] * s - q0[1] - d2[1] * t,
        p0[2] + d1[2] * s - q0[2] - d2[2] * t,
    ];
    dot(cp, cp).sqrt()
}

#[inline]
fn dist<T: Real>(a: [T; 3], b: [T; 3]) -> T {
    let d = sub(a, b);
    dot(d, d).sqrt()
}

#[inline]
fn max_abs<T: Real>(p: [T; 3]) -> T {
    p[0].abs().max(p[1].abs()).max(p[2].abs())
}

/// An enclosure of the density of `seg` (compact kernel) on the ray
/// interval `[a, b]` by `cells` skeleton cells (module docs); `[0, +∞]`
/// for a Cauchy kernel, `cells = 0` or non-finite input.
pub fn density_bounds<T: Real>(
    seg: &ScalisSegment<T>,
    ray: &Ray<T>,
    a: T,
    b: T,
    cells: u32,
) -> Interval<T> {
    let unknown = Interval::new(T::ZERO, T::INFINITY);
    let (SegmentKernel::CompactPolynomial { .. }, true) = (seg.kernel(), cells > 0) else {
        return unknown;
    };
    let sk = seg.segment();
    let at = |t: T| {
        [
            ray.origin[0] + t * ray.dir[0],
            ray.origin[1] + t * ray.dir[1],
            ray.origin[2] + t * ray.dir[2],
        ]
    };
    let (p0, p1) = (at(a), at(b));
    let len = sk.length();
    let scale = max_abs(p0)
        .max(max_abs(p1))
        .max(max_abs(sk.a()))
        .max(max_abs(sk.b()))
        + len
        + sk.ra().max(sk.rb());
    let slack = scale * T::EPSILON * T::from_f64(64.0);
    if !slack.is_finite() {
        return unknown;
    }
    let (sigma, m) = match seg.kernel() {
        SegmentKernel::CompactPolynomial { degree, sigma } => (sigma, (degree / 2) as i32),
        SegmentKernel::Cauchy { .. } => return unknown,
    };
    let inv_s2 = T::ONE / (sigma * sigma);
    // k(h²) = (1 − h²/σ²)^m, 0 beyond σ (decreasing in h²). The base
    // `1 − h²/σ²` cancels near the support's edge: it is moved outward by
    // an absolute 8ε (it is ≤ 1 and `h`, `h²/σ²` carry a few ulps), so
    // that the relative widening below only has to cover the power and the
    // products.
    let slack_x = T::EPSILON * T::from_f64(8.0);
    // `powi_std`: the standard library's products in the same order on
    // every target, so that the widening covers the same roundings on a
    // GPU as on the CPU (no driver `Pow` involved).
    let k_up = |h2: T| {
        let x = T::ONE - h2 * inv_s2 + slack_x;
        if x > T::ZERO {
            x.min(T::ONE).powi_std(m)
        } else {
            T::ZERO
        }
    };
    let k_dn = |h2: T| {
        let x = T::ONE - h2 * inv_s2 - slack_x;
        if x > T::ZERO { x.powi_std(m) } else { T::ZERO }
    };
    let n = T::from_f64(f64::from(cells));
    let (mut lo, mut hi) = (T::ZERO, T::ZERO);
    let mut s0 = T::ZERO;
    let mut q0 = sk.point_at(s0);
    let mut tau0 = sk.radius_at(s0);
    let mut j = 1u32;
    while j <= cells {
        let s1 = if j == cells {
            len
        } else {
            len * T::from_f64(f64::from(j)) / n
        };
        let q1 = sk.point_at(s1);
        let tau1 = sk.radius_at(s1);
        let tmin = tau0.min(tau1) - slack;
        let tmax = tau0.max(tau1) + slack;
        if !(tmin > T::ZERO) {
            return unknown;
        }
        let dmin = (segment_distance(p0, p1, q0, q1) - slack).max(T::ZERO);
        let ds = s1 - s0 + slack;
        let hmin = dmin / tmax;
        if hmin * (T::ONE - slack_x) < sigma {
            hi = hi + ds * k_up(hmin * hmin) / tmin;
            let dmax = dist(p0, q0)
                .max(dist(p0, q1))
                .max(dist(p1, q0))
                .max(dist(p1, q1))
                + slack;
            let hmax = dmax / tmin;
            lo = lo + (s1 - s0 - slack).max(T::ZERO) * k_dn(hmax * hmax) / tmax;
        }
        s0 = s1;
        q0 = q1;
        tau0 = tau1;
        j += 1;
    }
    // Every term is ≥ 0 and computed with a relative error of a few ulps
    // (the powers, the quotients) and the sums add one ulp per term: a
    // relative widening of (cells + 64)·4ε covers the rounding.
    let rel = T::from_f64(f64::from(cells) + 64.0) * T::EPSILON * T::from_f64(4.0);
    let inv = seg.inv_normalization();
    let lo = lo * inv * (T::ONE - rel);
    let hi = hi * inv * (T::ONE + rel);
    if !(lo <= hi) || !hi.is_finite() {
        unknown
    } else {
        Interval::new(lo.max(T::ZERO), hi)
    }
}

/// The density `f` of `seg` and its derivative `f'` along the ray at `t`,
/// as sound enclosures (the closed form in interval arithmetic).
fn value_and_slope<T: Real>(
    seg: &ScalisSegment<T>,
    ray: &Ray<T>,
    t: T,
) -> (Interval<T>, Interval<T>) {
    let p = ray.at::<Interval<T>>(t, t);
    let f: Interval<T> = seg.density(p);
    let g = seg.gradient_generic(p);
    let d = ray.dir;
    (f, g[0] * d[0] + g[1] * d[1] + g[2] * d[2])
}

/// Whether [`log_concave_range`] applies to `seg`: a compact kernel and a
/// constant radius (`r_a = r_b > 0`).
pub fn is_log_concave<T: Real>(seg: &ScalisSegment<T>) -> bool {
    let sk = seg.segment();
    matches!(seg.kernel(), SegmentKernel::CompactPolynomial { degree, .. } if degree >= 2)
        && sk.ra() == sk.rb()
        && sk.ra() > T::ZERO
}

/// A sound enclosure of the density of a constant-radius compact segment
/// ([`is_log_concave`]) on the ray interval `[a, b]` from its values and
/// derivatives at the two ends, or `None` when it does not apply.
///
/// Such a density is log-concave along every line (proof in the module
/// docs of the `slice` module, "Log-concavity": the kernel
/// `(1 − u/σ²)₊^m` is log-concave and non-increasing in `u`, `u` is convex
/// in `(t, s)` for a constant radius, Prékopa–Leindler), hence unimodal —
/// `f ≥ min(f(a), f(b))` on `[a, b]` — and `ln f` lies below its tangents
/// at `a` and `b`: `f(t) ≤ f(a)·e^{s_a (t − a)}` with `s_a = f'(a)/f(a)`,
/// likewise at `b`. Unlike the column classifier of the `slice` module, which
/// trusts the `f64` closed form to a relative accuracy, everything here is
/// in interval arithmetic: the end values and slopes are enclosures, the
/// exponentials are outward rounded, and the crossing of the two tangents
/// only needs to be approximate (for any `t'`, `max(A(t'), B(t'))` bounds
/// `min(A, B)` on `[a, b]` when `A` increases and `B` decreases). The
/// error is of order `(b − a)²` times the curvature of `ln f`, much
/// smaller than the cell sums' ([`density_bounds`]) on short intervals.
pub fn log_concave_range<T: Real>(
    seg: &ScalisSegment<T>,
    ray: &Ray<T>,
    a: T,
    b: T,
) -> Option<Interval<T>> {
    let r = log_concave_range_or_empty(seg, ray, a, b);
    (!r.is_empty()).then_some(r)
}

/// [`log_concave_range`] with [`Interval::EMPTY`] for `None` (the range is
/// never empty where it applies): the tracer's per-ray form, without an
/// `Option` of an interval (rust-gpu).
pub fn log_concave_range_or_empty<T: Real>(
    seg: &ScalisSegment<T>,
    ray: &Ray<T>,
    a: T,
    b: T,
) -> Interval<T> {
    if !is_log_concave(seg) || !(a <= b) {
        return Interval::EMPTY;
    }
    // both ends from one call (one inlined copy on a GPU)
    let ts = [a, b];
    let mut ends = [(Interval::EMPTY, Interval::EMPTY); 2];
    let mut k = 0;
    while k < 2 {
        ends[k] = value_and_slope(seg, ray, ts[k]);
        k += 1;
    }
    let [(fa, da), (fb, db)] = ends;
    if fa.is_empty() || fb.is_empty() || !fa.hi().is_finite() || !fb.hi().is_finite() {
        return Interval::EMPTY;
    }
    let lo = fa.lo().min(fb.lo()).max(T::ZERO);
    let ia = Interval::point(a);
    let ib = Interval::point(b);
    // ln f(t) ≤ ln f(a) + s_a·(t − a) for t ≥ a: the largest slope (NaN:
    // none)
    let sa = if fa.lo() > T::ZERO && !da.is_empty() {
        (da / fa).hi()
    } else {
        T::nan()
    };
    // ln f(t) ≤ ln f(b) + s_b·(t − b) for t ≤ b: the smallest slope
    let sb = if fb.lo() > T::ZERO && !db.is_empty() {
        (db / fb).lo()
    } else {
        T::nan()
    };
    let tangent_a = |t: T, s: T| {
        (Interval::point(fa.hi()) * (Interval::point(s) * (Interval::point(t) - ia)).exp()).hi()
    };
    let tangent_b = |t: T, s: T| {
        (Interval::point(fb.hi()) * (Interval::point(s) * (Interval::point(t) - ib)).exp()).hi()
    };
    let sup_a = if sa.is_nan() {
        T::INFINITY
    } else if sa <= T::ZERO {
        fa.hi()
    } else {
        tangent_a(b, sa)
    };
    let sup_b = if sb.is_nan() {
        T::INFINITY
    } else if sb >= T::ZERO {
        fb.hi()
    } else {
        tangent_b(a, sb)
    };
    let mut hi = sup_a.min(sup_b);
    if !sa.is_nan() && !sb.is_nan() {
        let (al, be) = (sa, sb);
        if al > T::ZERO && be < T::ZERO {
            // approximately where the two tangents cross (any point is sound)
            let t = (fb.hi().ln_ia() - fa.hi().ln_ia() + al * a - be * b) / (al - be);
            if t.is_finite() {
                let t = t.max(a).min(b);
                hi = hi.min(tangent_a(t, al).max(tangent_b(t, be)));
            }
        }
    }
    // the segment's values at the ends bound it from above too
    let hi = hi.max(fa.hi()).max(fb.hi());
    if lo <= hi && !hi.is_nan() {
        Interval::new(lo, hi)
    } else {
        Interval::EMPTY
    }
}

/// The quadratic Taylor model of the density of `seg` on the ray interval
/// `[a, b]`: enclosures of `f(a)`, `f'(a)` and of `f''` on `[a, b]` (the
/// closed forms of [`ScalisSegment::density`],
/// [`ScalisSegment::gradient_generic`] and
/// [`ScalisSegment::second_derivative_generic`] in interval arithmetic), so
/// that `f(a + τ) ∈ f(a) + f'(a)·τ + f''·τ²/2` for `τ ∈ [0, b − a]`
/// (forward-inclusion paper §6.1). `None` where the second derivative has
/// no closed form (degree 2, Cauchy kernel). These models add: a sum of
/// primitives' models bounds the sum of their densities, with cancellations
/// between primitives taken into account. [`taylor_model_at`] with `c = a`.
pub fn taylor_model<T: Real>(
    seg: &ScalisSegment<T>,
    ray: &Ray<T>,
    a: T,
    b: T,
) -> Option<[Interval<T>; 3]> {
    taylor_model_at(seg, ray, a, a, b, 1)
}

/// The quadratic Taylor model of the density of `seg` on the ray interval
/// `[a, b]` built at `c ∈ [a, b]`: enclosures of `f(c)`, `f'(c)` and of
/// `f''` on `[a, b]`, so that `f(c + τ) ∈ f(c) + f'(c)·τ + f''·τ²/2` for
/// `c + τ ∈ [a, b]`. Built at the midpoint, its quadratic term is a quarter
/// of [`taylor_model`]'s ([`taylor_model_range_at`],
/// [`taylor_model_slope`]).
///
/// `f''` is enclosed as the hull of the closed form's interval enclosures
/// on `pieces` consecutive pieces of `[a, b]` (equal lengths, the first
/// starting at `a`, the last ending at `b`, each starting where the
/// previous one ends): the closed form's interval extension overestimates
/// faster than linearly in the length on grazing rays, so the hull of
/// pieces is much narrower than one enclosure of the whole (at `pieces`
/// times the cost). `None` as for [`taylor_model`], when `c` is not in
/// `[a, b]` or `pieces` is `0`.
pub fn taylor_model_at<T: Real>(
    seg: &ScalisSegment<T>,
    ray: &Ray<T>,
    c: T,
    a: T,
    b: T,
    pieces: u32,
) -> Option<[Interval<T>; 3]> {
    let m = taylor_model_at_or_empty(seg, ray, c, a, b, pieces);
    (!m[0].is_empty()).then_some(m)
}

/// [`taylor_model_at`] with three [`Interval::EMPTY`]s for `None` (a model
/// has no empty part): the tracer's per-ray form, without an `Option` of
/// intervals (rust-gpu).
pub fn taylor_model_at_or_empty<T: Real>(
    seg: &ScalisSegment<T>,
    ray: &Ray<T>,
    c: T,
    a: T,
    b: T,
    pieces: u32,
) -> [Interval<T>; 3] {
    let none = [Interval::EMPTY; 3];
    if !(a <= c && c <= b) || pieces == 0 || !seg.has_second_derivative() {
        return none;
    }
    let mut d2 = Interval::EMPTY;
    let mut lo = a;
    let mut k = 1u32;
    while k <= pieces {
        let hi = if k == pieces {
            b
        } else {
            a + (b - a) * T::from_f64(f64::from(k) / f64::from(pieces))
        };
        let hi = hi.max(lo);
        d2 = d2.hull(seg.second_derivative_closed_form(ray.at::<Interval<T>>(lo, hi), ray.dir));
        lo = hi;
        k += 1;
    }
    let (f0, d1) = value_and_slope(seg, ray, c);
    if f0.is_empty() || d1.is_empty() || d2.is_empty() {
        return none;
    }
    [f0, d1, d2]
}

/// The range on the ray interval `[a, b]` of a (summed) quadratic Taylor
/// model `[f0, d1, d2]` built at `a` ([`taylor_model`]), sound (outward
/// rounded; the polynomial is bounded on `τ ∈ [0, h]` with `h` the length
/// rounded up).
pub fn taylor_model_range<T: Real>(model: [Interval<T>; 3], a: T, b: T) -> Interval<T> {
    taylor_model_range_at(model, a, a, b)
}

/// The range on the ray interval `[a, b]` of a (summed) quadratic Taylor
/// model `[f0, d1, d2]` built at `c ∈ [a, b]` ([`taylor_model_at`]), sound:
/// the hull of the ranges of the two halves `τ ∈ [0, b − c]` and
/// `τ ∈ [−(c − a), 0]` (each length rounded up), the second as the model
/// of `σ = −τ` (`d1` negated).
pub fn taylor_model_range_at<T: Real>(model: [Interval<T>; 3], c: T, a: T, b: T) -> Interval<T> {
    let [f0, d1, d2] = model;
    let (left, right) = reach(c, a, b);
    let r = ForwardQuadratic::taylor(f0, d1, d2, right).range();
    if left > T::ZERO {
        r.hull(ForwardQuadratic::taylor(f0, -d1, d2, left).range())
    } else {
        r
    }
}

/// An enclosure of the derivative `f'` on the ray interval `[a, b]` of a
/// (summed) quadratic Taylor model `[f0, d1, d2]` built at `c ∈ [a, b]`:
/// `f'(c + τ) = f'(c) + f''(ξ)·τ ∈ d1 + d2·[−(c − a), b − c]` (mean value
/// theorem on `f'`, `ξ` between `c` and `c + τ`). Summed over primitives
/// it keeps their cancellations, so it can prove a sum monotone where the
/// sum of per-primitive derivative enclosures cannot.
pub fn taylor_model_slope<T: Real>(model: [Interval<T>; 3], c: T, a: T, b: T) -> Interval<T> {
    let (left, right) = reach(c, a, b);
    model[1] + model[2] * Interval::new(-left, right)
}

/// `(c − a, b − c)`, each rounded up and at least `0`: how far a model
/// built at `c` reaches on `[a, b]`.
fn reach<T: Real>(c: T, a: T, b: T) -> (T, T) {
    let left = (Interval::point(c) - Interval::point(a)).hi().max(T::ZERO);
    let right = (Interval::point(b) - Interval::point(c)).hi().max(T::ZERO);
    (left, right)
}

#[cfg(test)]
mod tests {
    use super::*;
    use boundtrace_fields::homothetic::Segment;

    #[test]
    fn segment_distance_cases() {
        let d = segment_distance(
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.5, 1.0, -1.0],
            [0.5, 1.0, 1.0],
        );
        assert!((d - 1.0f64).abs() < 1e-15);
        let d = segment_distance(
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [3.0, 0.0, 0.0],
        );
        assert!((d - 1.0f64).abs() < 1e-15);
        let d = segment_distance(
            [0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [1.0, -1.0, 0.0],
        );
        assert!((d - 1.0f64).abs() < 1e-15);
    }

    #[test]
    fn bounds_contain_sampled_values_and_tighten_with_cells() {
        let k = SegmentKernel::compact_polynomial(6, 2.0).unwrap();
        let s = ScalisSegment::new(
            Segment::new([0.0, 0.0, 0.0], 0.1, [1.0, 0.3, 0.0], 0.2).unwrap(),
            k,
            1.0,
        )
        .unwrap();
        let ray = Ray::new([0.4, -1.0, 0.05], [0.1, 1.0, 0.02]);
        let mut prev = f64::INFINITY;
        for cells in [4, 16, 64, 256] {
            for (a, b) in [(0.6, 1.0), (0.9, 1.2), (1.1, 1.11), (0.0, 2.0)] {
                let r = density_bounds(&s, &ray, a, b, cells);
                for i in 0..=100 {
                    let t = a + (b - a) * f64::from(i) / 100.0;
                    let f: f64 = s.density(ray.at::<f64>(t, t));
                    assert!(r.contains(f), "{cells} cells, [{a}, {b}]: {r:?} misses {f}");
                }
            }
            let w = density_bounds(&s, &ray, 1.1, 1.11, cells).width();
            assert!(w < prev, "{cells}: {w} !< {prev}");
            prev = w;
        }
        // far from the support: exactly zero
        let far = density_bounds(&s, &Ray::new([5.0, 5.0, 5.0], [1.0, 0.0, 0.0]), 0.0, 1.0, 8);
        assert_eq!((far.lo(), far.hi()), (0.0, 0.0));
    }

    #[test]
    fn tight_ranges_contain_sampled_values_and_beat_the_cell_sums() {
        let k = SegmentKernel::compact_polynomial(6, 2.0).unwrap();
        let constant = ScalisSegment::new(
            Segment::new([0.0, 0.0, 0.0], 0.15, [1.0, 0.3, 0.0], 0.15).unwrap(),
            k,
            1.0,
        )
        .unwrap();
        let varying = ScalisSegment::new(
            Segment::new([0.0, 0.0, 0.0], 0.1, [1.0, 0.3, 0.0], 0.2).unwrap(),
            k,
            1.0,
        )
        .unwrap();
        assert!(is_log_concave(&constant) && !is_log_concave(&varying));
        assert!(
            log_concave_range(&varying, &Ray::new([0.0; 3], [1.0, 0.0, 0.0]), 0.0, 1.0).is_none()
        );
        // grazing rays, across the support's boundary, through the middle
        let rays = [
            Ray::new([-0.5, 0.25, 0.0], [1.0, 0.28, 0.0]),
            Ray::new([0.4, -1.0, 0.05], [0.1, 1.0, 0.02]),
            Ray::new([0.5, 0.15, -1.0], [0.0, 0.0, 1.0]),
        ];
        let mut tighter = 0;
        for s in [&constant, &varying] {
            for ray in &rays {
                for (a, b) in [
                    (0.0, 2.0),
                    (0.6, 1.0),
                    (0.9, 1.05),
                    (1.0, 1.002),
                    (0.5, 0.5),
                ] {
                    let lc = log_concave_range(s, ray, a, b);
                    let tm = taylor_model(s, ray, a, b).map(|m| taylor_model_range(m, a, b));
                    assert_eq!(lc.is_some(), is_log_concave(s));
                    let tm = tm.expect("degree 6 has a second derivative");
                    for i in 0..=200 {
                        let t = a + (b - a) * f64::from(i) / 200.0;
                        let f: f64 = s.density(ray.at::<f64>(t, t));
                        if let Some(r) = lc {
                            assert!(r.contains(f), "log-concave [{a}, {b}]: {r:?} misses {f}");
                        }
                        assert!(tm.contains(f), "Taylor [{a}, {b}]: {tm:?} misses {f}");
                    }
                    let cells = density_bounds(s, ray, a, b, 64);
                    let best = lc.map_or(tm.width(), |r| r.width().min(tm.width()));
                    if b - a < 0.01 && cells.width() > 0.0 {
                        assert!(
                            best < cells.width(),
                            "[{a}, {b}]: {best} !< {}",
                            cells.width()
                        );
                        tighter += 1;
                    }
                }
            }
        }
        assert!(tighter > 0);
    }

    /// Models built at the midpoint, summed over two primitives, with the
    /// second derivative on one piece and on eight: their ranges contain
    /// the sampled densities and their slopes the sampled derivatives; on
    /// short intervals they are no wider than the models built at the start
    /// (narrower on some), and eight pieces halve the slope's width on
    /// some interval.
    #[test]
    fn centered_models_contain_values_and_slopes() {
        let k = SegmentKernel::compact_polynomial(6, 2.0).unwrap();
        let segs = [
            ScalisSegment::new(
                Segment::new([0.0, 0.0, 0.0], 0.1, [1.0, 0.3, 0.0], 0.25).unwrap(),
                k,
                1.0,
            )
            .unwrap(),
            ScalisSegment::new(
                Segment::new([0.2, 0.4, 0.0], 0.3, [0.9, 0.1, 0.1], 0.12).unwrap(),
                k,
                1.0,
            )
            .unwrap(),
        ];
        let rays = [
            Ray::new([-0.5, 0.25, 0.0], [1.0, 0.28, 0.0]),
            Ray::new([0.4, -1.0, 0.05], [0.1, 1.0, 0.02]),
            Ray::new([0.5, 0.15, -1.0], [0.0, 0.0, 1.0]),
        ];
        let density = |ray: &Ray<f64>, t: f64| -> (f64, f64) {
            let p = ray.at::<f64>(t, t);
            let mut f = 0.0;
            let mut d = 0.0;
            for s in &segs {
                f += s.density(p);
                let g = s.gradient_generic(p);
                d += g[0] * ray.dir[0] + g[1] * ray.dir[1] + g[2] * ray.dir[2];
            }
            (f, d)
        };
        let (mut checked, mut narrower, mut finer) = (0, 0, 0);
        for ray in &rays {
            for (a, b) in [
                (0.0, 2.0),
                (0.6, 1.0),
                (0.9, 1.05),
                (1.0, 1.002),
                (0.7, 0.7),
            ] {
                let c = a + (b - a) * 0.5;
                let zero = Interval::point(0.0);
                let (mut at_c, mut at_a) = ([zero; 3], [zero; 3]);
                for s in &segs {
                    let m = taylor_model_at(s, ray, c, a, b, 1).expect("degree 6");
                    let m0 = taylor_model(s, ray, a, b).expect("degree 6");
                    for i in 0..3 {
                        at_c[i] = at_c[i] + m[i];
                        at_a[i] = at_a[i] + m0[i];
                    }
                }
                // the second derivative on 8 pieces: inside the one of the
                // whole interval (each piece's box is inside the whole's),
                // and its model contains the samples too
                let mut fine = [zero; 3];
                for s in &segs {
                    let m = taylor_model_at(s, ray, c, a, b, 8).expect("degree 6");
                    let whole = taylor_model_at(s, ray, c, a, b, 1).expect("degree 6");
                    let slack = 1e-9 * whole[2].width().max(1.0);
                    assert!(m[2].lo() >= whole[2].lo() - slack, "{m:?} {whole:?}");
                    assert!(m[2].hi() <= whole[2].hi() + slack, "{m:?} {whole:?}");
                    for i in 0..3 {
                        fine[i] = fine[i] + m[i];
                    }
                }
                let fine_range = taylor_model_range_at(fine, c, a, b);
                let fine_slope = taylor_model_slope(fine, c, a, b);
                let coarse_slope = taylor_model_slope(at_c, c, a, b);
                finer += usize::from(fine_slope.width() < 0.5 * coarse_slope.width());
                let range = taylor_model_range_at(at_c, c, a, b);
                let slope = taylor_model_slope(at_c, c, a, b);
                let start_slope = taylor_model_slope(at_a, a, a, b);
                for i in 0..=400 {
                    let t = a + (b - a) * f64::from(i) / 400.0;
                    let (f, d) = density(ray, t);
                    assert!(range.contains(f), "[{a}, {b}]: {range:?} misses {f} at {t}");
                    assert!(
                        slope.contains(d),
                        "[{a}, {b}]: {slope:?} misses f' = {d} at {t}"
                    );
                    assert!(
                        start_slope.contains(d),
                        "[{a}, {b}]: {start_slope:?} misses {d}"
                    );
                    assert!(fine_range.contains(f), "8 pieces [{a}, {b}]: misses {f}");
                    assert!(fine_slope.contains(d), "8 pieces [{a}, {b}]: misses {d}");
                    checked += 1;
                }
                let start = taylor_model_range(at_a, a, b);
                if b - a < 0.2 && b > a {
                    assert!(range.width() <= start.width(), "{range:?} vs {start:?}");
                    narrower += usize::from(range.width() < start.width());
                }
            }
        }
        assert!(
            checked > 0 && narrower > 0 && finer > 0,
            "{narrower} {finer}"
        );
        // a model built outside the interval is refused
        assert!(taylor_model_at(&segs[0], &rays[0], 2.0, 0.0, 1.0, 1).is_none());
    }
}
