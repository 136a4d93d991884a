//! Skeletons of homothetic-distance primitives blended by summation
//! (thesis Part II §1.1, eq. 1.13; used by Part III ch. 1 §1.8 for the
//! segment-tracing comparison of Fig. 1.19).
//!
//! # The field
//!
//! For segments `Sᵢ` ([`Segment`]: end-points with radii, the radius
//! varying linearly) and one [`SegmentKernel`] `k` written on the squared
//! homothetic distance `h²` ([`Segment::homothetic_sq`], eq. 1.12),
//!
//! ```text
//! f(p) = iso − c · Σᵢ k(h_{Sᵢ}(p)),      c = 1/k(1) (rounded to T)
//! ```
//!
//! positive outside, negative inside. The factor `c` normalizes the kernel
//! so that `k(1)·c = 1` up to rounding: with `iso = 1` an **isolated**
//! segment has its surface exactly on its sphere-cone (`h_S = 1`, the union
//! of the balls of the prescribed radii), and blending by summation grows
//! the shape where segments meet. The field is defined with the stored
//! `c`, so every bound below encloses exactly this function. A compact
//! kernel needs `σ > 1` (else `k(1) = 0`).
//!
//! # Bounds
//!
//! - **Interval, affine and forward bottom-up** bounds come from evaluating
//!   [`Field::eval`] in those number types (the closed form of `h_S` is
//!   branch-free, see [`homothetic`](crate::homothetic)).
//! - **Lipschitz.** `h(p, s) = |p − q(s)|/τ(s)` is `1/τ(s)`-Lipschitz in `p`
//!   for every `s`, so `h_S = min_s h(·, s)` is `1/τ_min`-Lipschitz with
//!   `τ_min = min(r_a, r_b)` (the radius is linear). Hence
//!   `|∇(k ∘ h_S)| ≤ max|k'| / τ_min` and
//!   [`lipschitz`](Field::lipschitz) is `c · Σᵢ max|k'| / τ_min,i`, rounded
//!   up. `max|k'|` is reached at `h*² = σ²/(2m − 1)` (compact, degree `2m`)
//!   or `h*² = σ²/(n + 1)` (Cauchy, degree `n`); `|k'|` increases before
//!   `h*` and decreases after it, so it is bounded by an interval
//!   evaluation of `|k'|` on a tiny interval certainly containing `h*`.
//! - **Directional (segment-tracing) bound.** On a ray window
//!   `o + [t₀, t₁]·d`, an interval evaluation of `h_{Sᵢ}` gives a range
//!   `Hᵢ`; `|k'|` on `Hᵢ` is bounded by the unimodality above (its value at
//!   the end of `Hᵢ` nearest to `h*`, or at `h*`), and `0` when
//!   `Hᵢ ≥ σ` for a compact kernel. [`Field::taylor_linear`] is the
//!   Lipschitz line `f(t₀) ± L·τ` with
//!   `L = c · |d| · Σᵢ max_{Hᵢ}|k'| / τ_min,i` (Galin et al.'s local
//!   Lipschitz bound, forward-inclusion paper eq. 11): it is what
//!   `segment` tracing and `linear-taylor` use. No quadratic Taylor bound
//!   is offered (`h_S` is only Lipschitz where the argmin switches
//!   between an end-point and the interior).
//! - **Fallback.** Where an affine or forward evaluation of a term is not
//!   finite (the division by the floored `τ_x` of the closed form), the
//!   term is replaced by its interval enclosure on the query's box
//!   intersected with the kernel's range `[0, 1]`.
//! - **Culling.** A compact kernel vanishes beyond `h_S ≥ σ`, i.e. outside
//!   the sphere-cone of the radii scaled by `σ`, whose box is the segment's
//!   box grown by `σ·max(r_a, r_b)` (rounded outward). Evaluation and the
//!   bounds skip the segments whose box the query's enclosure misses:
//!   their term is exactly `0` there.
//!
//! ```
//! use boundtrace_fields::homothetic::{Segment, SegmentKernel};
//! use boundtrace_fields::homothetic_skeleton::HomotheticSkeleton;
//! use boundtrace_ia_core::Interval;
//! use boundtrace_inclusion::{Field, Ray};
//!
//! let k = SegmentKernel::compact_polynomial(6, 2.0)?;
//! let segs = [
//!     Segment::new([-1.0, 0.0, 0.0], 0.3, [0.0, 0.0, 0.0], 0.4)?,
//!     Segment::new([0.0, 0.0, 0.0], 0.4, [0.0, 1.0, 0.0], 0.2)?,
//! ];
//! let sk = HomotheticSkeleton::new(segs, k, 1.0)?;
//! assert!(sk.eval([0.0f64, 0.0, 0.0]) < 0.0); // inside, at the joint
//! assert!(sk.eval([0.0f64, -2.0, 0.0]) > 0.0); // outside
//! // An interval over a ray window encloses every value on it.
//! let ray = Ray::new([0.5, -3.0, 0.0], [0.0, 1.0, 0.0]);
//! let range: Interval<f64> = sk.eval(ray.at(2.0, 3.0));
//! let v: f64 = sk.eval(ray.at(2.5, 2.5));
//! assert!(range.contains(v));
//! assert!(sk.lipschitz().unwrap() > 0.0);
//! # Ok::<(), boundtrace_fields::FieldError>(())
//! ```

// `!(x > 0)` is deliberate: it is true for NaN, which must be rejected.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::FieldError;
use crate::homothetic::{KERNEL_COMPACT, Plain, SEGMENT_WORDS, Segment, SegmentKernel, kernel_sq};
use boundtrace_ia_core::{Interval, Real};
use boundtrace_inclusion::{Field, FieldNum, ForwardLinear, Ray};

/// Storage of [`Segment`]s that a [`HomotheticSkeleton`] reads one by one
/// (its `S`): every `AsRef<[Segment<T>]>` (an array, a slice, a `Vec`) and
/// [`FlatSegments`], the segments as plain words (the GPU's buffers).
pub trait HomotheticSegments<T> {
    /// The number of segments.
    fn count(&self) -> usize;
    /// Segment `i` (`i < count()`).
    fn segment(&self, i: usize) -> Segment<T>;
}

impl<T: Copy, S: AsRef<[Segment<T>]>> HomotheticSegments<T> for S {
    #[inline]
    fn count(&self) -> usize {
        self.as_ref().len()
    }
    #[inline]
    fn segment(&self, i: usize) -> Segment<T> {
        self.as_ref()[i]
    }
}

/// Segments stored as plain words, [`SEGMENT_WORDS`] per segment in
/// [`Segment::to_words`]' order: the flat data that the GPU kernel reads
/// from a `f32` buffer. A skeleton over it is the skeleton over the same
/// segments as structs, bit for bit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlatSegments<'a, T> {
    words: &'a [T],
    count: usize,
}

impl<'a, T> FlatSegments<'a, T> {
    /// The first `count` segments of `words`; `None` when `words` holds
    /// fewer than `count ·` [`SEGMENT_WORDS`] words. Extra words are left
    /// out.
    pub fn new(words: &'a [T], count: usize) -> Option<Self> {
        let needed = count.checked_mul(SEGMENT_WORDS)?;
        (needed <= words.len()).then_some(Self { words, count })
    }

    /// [`new`](Self::new) without the length check, for the GPU kernel
    /// (no `Option` to move): `count ·` [`SEGMENT_WORDS`] `≤ words.len()`
    /// is the caller's to check, else the field's evaluation indexes past
    /// the words (a panic on the CPU).
    pub const fn new_unchecked(words: &'a [T], count: usize) -> Self {
        Self { words, count }
    }
}

impl<T: Copy> HomotheticSegments<T> for FlatSegments<'_, T> {
    #[inline]
    fn count(&self) -> usize {
        self.count
    }
    #[inline]
    fn segment(&self, i: usize) -> Segment<T> {
        Segment::from_words_unchecked(self.words, i * SEGMENT_WORDS)
    }
}

/// The number of `T` words of a skeleton's parameters
/// ([`HomotheticSkeleton::parameter_words`]): `σ`, the iso-value, the
/// normalization `c`, the two ends of the interval around `h*` and the
/// slope bound.
pub const PARAMETER_WORDS: usize = 6;

/// A sum of homothetic-distance primitives `k ∘ h_{Sᵢ}` over segments
/// sharing one kernel, as the field `iso − c·Σᵢ k(h_{Sᵢ}(p))` (module
/// docs).
///
/// `S` is any storage of [`Segment`]s ([`HomotheticSegments`]): an array,
/// a slice, a `Vec`, or [`FlatSegments`].
/// Evaluation is allocation- and recursion-free.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HomotheticSkeleton<T, S> {
    segments: S,
    /// The kernel as plain data ([`SegmentKernel::code`] and `σ`): the
    /// field's evaluation matches no enum, so that the GPU runs it.
    code: [u32; 2],
    sigma: T,
    iso: T,
    /// `c ≈ 1/k(1)`: the field's normalization (exact by definition).
    scale: T,
    /// An interval certainly containing the maximiser `h*` of `|k'|`.
    h_star: Interval<T>,
    /// An upper bound of `max_h |k'(h)|`.
    slope_max: T,
}

impl<T: Real, S> HomotheticSkeleton<T, S> {
    /// The skeleton of [`new`](Self::new) from its parts as
    /// [`parameter_words`](Self::parameter_words) gives them, without
    /// checks or derivations: for the GPU kernel, whose host took the
    /// words from a skeleton built by [`new`](Self::new) (the same field
    /// then, bit for bit). Invalid words give non-finite values, never a
    /// panic.
    pub fn from_parameter_words_unchecked(
        segments: S,
        code: [u32; 2],
        words: [T; PARAMETER_WORDS],
    ) -> Self {
        Self {
            segments,
            code,
            sigma: words[0],
            iso: words[1],
            scale: words[2],
            h_star: Interval::new(words[3], words[4]),
            slope_max: words[5],
        }
    }

    /// The parameters as plain data: the kernel's
    /// [`code`](SegmentKernel::code) and the [`PARAMETER_WORDS`] words `σ`,
    /// iso-value, normalization `c`, `h*`'s interval (two words) and the
    /// slope bound, what
    /// [`from_parameter_words_unchecked`](Self::from_parameter_words_unchecked)
    /// takes.
    pub fn parameter_words(&self) -> ([u32; 2], [T; PARAMETER_WORDS]) {
        (
            self.code,
            [
                self.sigma,
                self.iso,
                self.scale,
                self.h_star.lo(),
                self.h_star.hi(),
                self.slope_max,
            ],
        )
    }
}

impl<T: Real, S: AsRef<[Segment<T>]>> HomotheticSkeleton<T, S> {
    /// The segments.
    #[inline]
    pub fn segments(&self) -> &[Segment<T>] {
        self.segments.as_ref()
    }
}

#[cfg(feature = "alloc")]
impl<T: Real, S: HomotheticSegments<T>> HomotheticSkeleton<T, S> {
    /// The segments as flat words, [`SEGMENT_WORDS`] per segment
    /// ([`FlatSegments`]' data, the GPU's buffer).
    pub fn segment_words(&self) -> alloc::vec::Vec<T> {
        let n = self.segments.count();
        let mut w = alloc::vec::Vec::with_capacity(n * SEGMENT_WORDS);
        for i in 0..n {
            w.extend_from_slice(&self.segments.segment(i).to_words());
        }
        w
    }
}

impl<T: Real, S: HomotheticSegments<T>> HomotheticSkeleton<T, S> {
    /// The skeleton of `segments` with `kernel`, for the iso-value `iso`
    /// (`iso = 1`: an isolated segment's surface is its sphere-cone).
    ///
    /// # Errors
    ///
    /// [`FieldError::InvalidParameter`] when there is no segment, `iso` is
    /// not finite and `> 0`, a compact kernel has `σ ≤ 1` (then `k(1) = 0`),
    /// or `1/k(1)` overflows `T`.
    pub fn new(segments: S, kernel: SegmentKernel<T>, iso: T) -> Result<Self, FieldError> {
        if segments.count() == 0 {
            return Err(FieldError::InvalidParameter {
                name: "segments",
                reason: "a skeleton needs at least one segment",
            });
        }
        let iso = crate::error::positive("iso", iso)?;
        let sigma = kernel.sigma();
        if let SegmentKernel::CompactPolynomial { .. } = kernel {
            if !(sigma > T::ONE) {
                return Err(FieldError::InvalidParameter {
                    name: "sigma",
                    reason: "a compact homothetic kernel needs σ > 1 (k(1) = 0 otherwise)",
                });
            }
        }
        let k1 = kernel.eval_sq(Plain(T::ONE)).0;
        let scale = T::ONE / k1;
        if !(k1 > T::ZERO) || !scale.is_finite() {
            return Err(FieldError::InvalidParameter {
                name: "sigma",
                reason: "the kernel value at h = 1 is too small to normalize (σ too close to 1)",
            });
        }
        // h*² = σ²/(2m − 1) (compact, n = 2m) or σ²/(n + 1) (Cauchy).
        let denom = match kernel {
            SegmentKernel::CompactPolynomial { degree, .. } => degree - 1,
            SegmentKernel::Cauchy { degree, .. } => degree + 1,
        };
        let h_star = Interval::point(sigma) / Interval::point(T::from_f64(f64::from(denom))).sqrt();
        let mut out = Self {
            segments,
            code: kernel.code(),
            sigma,
            iso,
            scale,
            h_star,
            slope_max: T::ZERO,
        };
        out.slope_max = out.slope_enclosure(h_star).hi();
        if !out.slope_max.is_finite() {
            return Err(FieldError::InvalidParameter {
                name: "sigma",
                reason: "the kernel's slope bound overflows",
            });
        }
        Ok(out)
    }

    /// The number of segments.
    #[inline]
    pub fn segment_count(&self) -> usize {
        self.segments.count()
    }

    /// The shared kernel.
    #[inline]
    pub fn kernel(&self) -> SegmentKernel<T> {
        SegmentKernel::from_code_unchecked(self.code, self.sigma)
    }

    /// `k(h)` at the squared distance `h2` (the kernel's plain data, no
    /// enum).
    #[inline]
    fn kernel_sq<N: FieldNum<T>>(&self, h2: N) -> N {
        kernel_sq(self.code[0], self.code[1], self.sigma, h2)
    }

    /// Whether the kernel is compact (else Cauchy).
    #[inline]
    fn compact(&self) -> bool {
        self.code[0] == KERNEL_COMPACT
    }

    /// The iso-value.
    #[inline]
    pub fn iso(&self) -> T {
        self.iso
    }

    /// The normalization `c ≈ 1/k(1)` of the density.
    #[inline]
    pub fn scale(&self) -> T {
        self.scale
    }

    /// An upper bound of `max_h |k'(h)|` over all `h ≥ 0` (module docs).
    #[inline]
    pub fn kernel_slope_bound(&self) -> T {
        self.slope_max
    }

    /// An enclosure of `|k'(h)|` for `h ∈ hs` (`hs ⊂ [0, ∞)`), by interval
    /// arithmetic on `|k'(h)| = 2m·h/σ²·(1 − h²/σ²)₊^{m−1}` (compact) or
    /// `n·h/σ²·(1 + h²/σ²)^{−(n+2)/2}` (Cauchy); for the compact kernel of
    /// degree 2 it over-estimates beyond `σ` (where `k' = 0`), which is
    /// sound.
    fn slope_enclosure(&self, hs: Interval<T>) -> Interval<T> {
        let sigma = Interval::point(self.sigma);
        let s2 = sigma.sqr();
        let u = hs.sqr() / s2;
        let degree = self.code[1];
        let lead = hs * Interval::point(T::from_f64(f64::from(degree))) / s2;
        if self.compact() {
            let m = degree / 2;
            if m == 1 {
                lead
            } else {
                lead * u.one_minus_clamped().powi((m - 1) as i32)
            }
        } else {
            let b = u + Interval::point(T::ONE);
            let e = degree + 2;
            let den = if e % 2 == 0 {
                b.powi((e / 2) as i32)
            } else {
                b.powi(e as i32).sqrt()
            };
            lead / den
        }
    }

    /// An upper bound of `|k'(h)|` over `h ∈ hs` (an enclosure of `h_S` on
    /// some region): `0` beyond a compact support, else by the unimodality
    /// of `|k'|` around `h*` (module docs).
    pub fn kernel_slope_on(&self, hs: Interval<T>) -> T {
        if hs.is_empty() || hs.lo().is_nan() || hs.hi().is_nan() {
            return self.slope_max;
        }
        let lo = hs.lo().max(T::ZERO);
        let hi = hs.hi();
        if self.compact() && lo >= self.sigma {
            return T::ZERO;
        }
        let at = if hi <= self.h_star.lo() {
            Interval::point(hi)
        } else if lo >= self.h_star.hi() {
            Interval::point(lo)
        } else {
            return self.slope_max;
        };
        self.slope_enclosure(at).hi().min(self.slope_max)
    }

    /// The box outside of which segment `s`'s term is exactly `0` (compact
    /// kernels: the segment's box grown by `σ·max(r_a, r_b)`); `None` for
    /// the Cauchy kernel.
    ///
    /// Computed in plain floats (it is on the evaluation path) and widened
    /// by `4ε·(|x| + σ·r) + 4·MIN_SUBNORMAL` per side, more than the at most
    /// three roundings of `x ∓ σ·r` (each `≤ ε/2` relative, or half a
    /// subnormal), so the box contains the exact one.
    pub fn support_box(&self, s: &Segment<T>) -> Option<[[T; 3]; 2]> {
        self.compact().then(|| self.compact_support_box(s))
    }

    /// [`support_box`](Self::support_box) of a compact kernel, with no
    /// `Option` (the evaluation path, which the GPU runs).
    fn compact_support_box(&self, s: &Segment<T>) -> [[T; 3]; 2] {
        let grow = self.sigma * s.ra().max(s.rb());
        let four = T::TWO * T::TWO;
        let tiny = four * T::MIN_SUBNORMAL;
        let (a, b) = (s.a(), s.b());
        let mut lo = [T::ZERO; 3];
        let mut hi = [T::ZERO; 3];
        let mut k = 0;
        while k < 3 {
            let (mn, mx) = (a[k].min(b[k]), a[k].max(b[k]));
            lo[k] = mn - grow - ((mn.abs() + grow) * four * T::EPSILON + tiny);
            hi[k] = mx + grow + ((mx.abs() + grow) * four * T::EPSILON + tiny);
            k += 1;
        }
        [lo, hi]
    }

    /// Whether the enclosure `e` of the query certainly misses segment
    /// `s`'s support box (always `false` for the Cauchy kernel).
    #[inline]
    fn misses(&self, s: &Segment<T>, e: &[Interval<T>; 3]) -> bool {
        if !self.compact() {
            return false;
        }
        let [lo, hi] = self.compact_support_box(s);
        let mut out = false;
        let mut k = 0;
        while k < 3 {
            out |= !e[k].is_empty() && (e[k].hi() < lo[k] || e[k].lo() > hi[k]);
            k += 1;
        }
        out
    }

    /// The normalized density `c·Σᵢ k(h_{Sᵢ}(p))` (segments whose support
    /// the query cannot reach are skipped).
    pub fn density<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        let e = [p[0].enclosure(), p[1].enclosure(), p[2].enclosure()];
        // `0` carrying the query's validity (see `crate::zero_like`).
        let mut acc = crate::zero_like::<T, N>(&p[0]);
        // An index loop over the storage (`FlatSegments` on the GPU).
        let mut i = 0;
        while i < self.segments.count() {
            let s = self.segments.segment(i);
            i += 1;
            if self.misses(&s, &e) {
                continue;
            }
            let mut term = self.kernel_sq(s.homothetic_sq(p));
            let enc = term.enclosure();
            if N::IS_FORM && !enc.is_empty() && !enc.is_bounded() {
                // Affine and forward forms of the closed form can blow up
                // (division by the floored `τ_x`, then clamps that cannot
                // recover an infinite form) where intervals stay tight:
                // replace the term by its interval enclosure on the query's
                // box, within the kernel's range [0, 1] (sound: every value
                // of the term on the query lies in both). A point, jet or
                // interval term is never unbounded (the kernel's clamp or
                // reciprocal keeps it in [0, 1], or NaN), so other types
                // compile this out (`FieldNum::IS_FORM`).
                let r: Interval<T> = self.kernel_sq(s.homothetic_sq(e));
                let (lo, hi) = if r.is_empty() {
                    (T::ZERO, T::ONE)
                } else {
                    (r.lo().max(T::ZERO), r.hi().min(T::ONE))
                };
                let z = crate::zero_like::<T, N>(&p[0]);
                term = (z + lo).join(z + hi);
            }
            acc = acc + term;
        }
        acc * self.scale
    }

    /// A bound of `|d f(o + t·d)/dt|` on `[t0, t1]` (module docs), rounded
    /// up; `+∞` for a non-finite ray.
    pub fn directional_lipschitz(&self, ray: &Ray<T>, t0: T, t1: T) -> T {
        let e: [Interval<T>; 3] = ray.at(t0, t1);
        let iv = Interval::point;
        let speed = (iv(ray.dir[0]).sqr() + iv(ray.dir[1]).sqr() + iv(ray.dir[2]).sqr()).sqrt();
        let mut acc = iv(T::ZERO);
        let mut i = 0;
        while i < self.segments.count() {
            let s = self.segments.segment(i);
            i += 1;
            if self.misses(&s, &e) {
                continue;
            }
            let hs = s.homothetic_sq(e).sqrt();
            let slope = self.kernel_slope_on(hs);
            if slope > T::ZERO {
                acc = acc + iv(slope) / iv(s.ra().min(s.rb()));
            }
        }
        let l = (acc * speed * iv(self.scale)).hi();
        if l.is_nan() { T::INFINITY } else { l }
    }
}

impl<T: Real, S: HomotheticSegments<T>> Field<T> for HomotheticSkeleton<T, S> {
    fn eval<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        -self.density(p) + self.iso
    }

    /// `c · Σᵢ max|k'| / min(r_a, r_b)`, rounded up (module docs): sound
    /// everywhere, loose for large skeletons.
    fn lipschitz(&self) -> Option<T> {
        let iv = Interval::point;
        let mut acc = iv(T::ZERO);
        let mut i = 0;
        while i < self.segments.count() {
            let s = self.segments.segment(i);
            acc = acc + iv(self.slope_max) / iv(s.ra().min(s.rb()));
            i += 1;
        }
        Some((acc * iv(self.scale)).hi())
    }

    /// The local Lipschitz line `f(t₀) ± L·τ` with
    /// [`directional_lipschitz`](Self::directional_lipschitz) `L` (module
    /// docs).
    fn taylor_linear(&self, ray: &Ray<T>, t0: T, t1: T) -> Option<ForwardLinear<T>> {
        let p0: [Interval<T>; 3] = ray.at(t0, t0);
        let f0: Interval<T> = self.eval(p0);
        let l = self.directional_lipschitz(ray, t0, t1);
        let h = (Interval::point(t1) - Interval::point(t0))
            .lo()
            .max(T::ZERO);
        Some(ForwardLinear::lipschitz(f0, l, h))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::homothetic::HomotheticPrimitive;
    use alloc::vec;

    fn seg(a: [f64; 3], ra: f64, b: [f64; 3], rb: f64) -> Segment<f64> {
        Segment::new(a, ra, b, rb).unwrap()
    }

    /// `FieldNum::IS_FORM`: the closed form in intervals (and points) is
    /// never unbounded, however wide or narrow the query box, so
    /// [`HomotheticSkeleton::density`] may leave the forms' interval
    /// fallback out for them.
    #[test]
    fn interval_densities_are_bounded() {
        let segs = vec![
            seg([-1.0, 0.0, 0.0], 0.3, [0.0, 0.0, 0.0], 0.4),
            seg([0.0, 0.0, 0.0], 1e-6, [0.0, 1.0, 0.2], 0.2),
            seg([0.1, 0.9, 0.3], 0.1, [0.1, 0.9, 0.31], 0.5),
        ];
        let centers = [
            [0.0, 0.0, 0.0],
            [-1.2, 0.0, 0.0],
            [0.0, 0.5, 0.1],
            [0.1, 0.9, 0.3],
            [3.0, -2.0, 1.0],
        ];
        let halves = [0.0, 1e-300, 1e-8, 0.05, 0.7, 10.0, 1e30, f64::INFINITY];
        for k in [
            SegmentKernel::compact_polynomial(4, 1.6).unwrap(),
            SegmentKernel::cauchy(3, 1.2).unwrap(),
        ] {
            let sk = HomotheticSkeleton::new(segs.clone(), k, 1.0).unwrap();
            for c in centers {
                for h in halves {
                    let b = c.map(|x| Interval::new(x - h, x + h));
                    let d: Interval<f64> = sk.density(b);
                    assert!(!d.is_empty() && d.is_bounded(), "{k:?} {c:?} ± {h}: {d:?}");
                    let p: f64 = sk.density(c);
                    assert!(
                        p.is_finite() && d.contains(p),
                        "{k:?} {c:?} ± {h}: {p} ∉ {d:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn validation() {
        let s = [seg([0.0; 3], 0.5, [1.0, 0.0, 0.0], 0.5)];
        let k = SegmentKernel::compact_polynomial(4, 2.0).unwrap();
        assert!(HomotheticSkeleton::new(s, k, 1.0).is_ok());
        assert!(HomotheticSkeleton::new(s, k, 0.0).is_err());
        assert!(HomotheticSkeleton::new(s, k, f64::NAN).is_err());
        let none: [Segment<f64>; 0] = [];
        assert!(HomotheticSkeleton::new(none, k, 1.0).is_err());
        let k1 = SegmentKernel::compact_polynomial(4, 1.0).unwrap();
        assert!(HomotheticSkeleton::new(s, k1, 1.0).is_err());
        // σ barely above 1 with a high degree: 1/k(1) overflows f32
        let k64 = SegmentKernel::compact_polynomial(64, 1.0001f32).unwrap();
        let s32 = [Segment::new([0.0f32; 3], 0.5, [1.0, 0.0, 0.0], 0.5).unwrap()];
        assert!(HomotheticSkeleton::new(s32, k64, 1.0).is_err());
    }

    /// One segment with `iso = 1` has the surface of the homothetic
    /// primitive `k(1) − k(h_S)`: the sphere-cone.
    #[test]
    fn isolated_segment_surface_is_the_sphere_cone() {
        for k in [
            SegmentKernel::compact_polynomial(6, 2.0).unwrap(),
            SegmentKernel::cauchy(3, 1.0).unwrap(),
        ] {
            let s = seg([0.0; 3], 0.5, [3.0, 1.0, 0.0], 1.2);
            let sk = HomotheticSkeleton::new([s], k, 1.0).unwrap();
            let prim = HomotheticPrimitive::new(s, k).unwrap();
            for p in [
                [1.0, 2.0, 0.3],
                [-0.4, -0.3, 0.0],
                [1.5, 0.5, 0.0],
                [5.0, 1.0, 1.0],
            ] {
                let a: f64 = sk.eval(p);
                let b: f64 = prim.eval(p);
                assert_eq!(a > 0.0, b > 0.0, "{p:?}: {a} vs {b}");
            }
            // on the ball around a, opposite to the segment: f = 0
            let d = [-3.0 / 10f64.sqrt(), -1.0 / 10f64.sqrt(), 0.0];
            let f: f64 = sk.eval([0.5 * d[0], 0.5 * d[1], 0.0]);
            assert!(f.abs() < 1e-12, "{f}");
        }
    }

    /// The sum blends: the joint of two segments is more inside than
    /// either primitive alone, and the far segment is culled exactly.
    #[test]
    fn sum_blends_and_culls() {
        let k = SegmentKernel::compact_polynomial(6, 2.0).unwrap();
        let a = seg([0.0; 3], 0.3, [1.0, 0.0, 0.0], 0.3);
        let b = seg([1.0, 0.0, 0.0], 0.3, [1.0, 1.0, 0.0], 0.3);
        let far = seg([20.0, 0.0, 0.0], 0.3, [21.0, 0.0, 0.0], 0.3);
        let one = HomotheticSkeleton::new([a], k, 1.0).unwrap();
        let two = HomotheticSkeleton::new([a, b], k, 1.0).unwrap();
        let three = HomotheticSkeleton::new([a, far, b], k, 1.0).unwrap();
        let p = [1.0, 0.4, 0.0];
        let (f1, f2): (f64, f64) = (one.eval(p), two.eval(p));
        assert!(f2 < f1);
        assert_eq!(f2, three.eval(p));
        let [lo, _] = three.support_box(&far).unwrap();
        assert!(lo[0] <= 20.0 - 0.6 && lo[0] > 19.0);
        assert!(one.support_box(&a).is_some());
        let c = HomotheticSkeleton::new([a], SegmentKernel::cauchy(3, 1.0).unwrap(), 1.0).unwrap();
        assert!(c.support_box(&a).is_none());
    }

    /// The global and directional Lipschitz bounds hold between dense
    /// samples along rays (finite differences never exceed them).
    #[test]
    fn lipschitz_bounds_hold_on_samples() {
        let kernels = [
            SegmentKernel::compact_polynomial(2, 1.5).unwrap(),
            SegmentKernel::compact_polynomial(8, 2.5).unwrap(),
            SegmentKernel::cauchy(3, 1.0).unwrap(),
            SegmentKernel::cauchy(4, 0.7).unwrap(),
        ];
        let segs = [
            seg([-1.0, 0.0, 0.0], 0.2, [0.0, 0.1, 0.0], 0.5),
            seg([0.0, 0.1, 0.0], 0.5, [0.3, 1.0, 0.2], 0.1),
        ];
        for k in kernels {
            let sk = HomotheticSkeleton::new(segs, k, 0.8).unwrap();
            let global = sk.lipschitz().unwrap();
            assert!(global.is_finite() && global > 0.0);
            for ray in [
                Ray::new([-2.0, -1.0, 0.05], [1.0, 0.6, 0.0]),
                Ray::new([0.2, 3.0, 0.1], [0.0, -1.5, 0.0]),
            ] {
                for w in 0..8 {
                    let (t0, t1) = (0.5 * f64::from(w), 0.5 * f64::from(w) + 0.5);
                    let local = sk.directional_lipschitz(&ray, t0, t1);
                    assert!(local <= global * ray.speed() * (1.0 + 1e-9) + 1e-12);
                    let lin = sk.taylor_linear(&ray, t0, t1).unwrap();
                    let n = 200;
                    let mut prev: Option<f64> = None;
                    for i in 0..=n {
                        let t = t0 + (t1 - t0) * f64::from(i) / f64::from(n);
                        let v: f64 = sk.eval(ray.at(t, t));
                        assert!(lin.bounds_at(t - t0).contains(v), "{k:?} t={t}");
                        if let Some(pv) = prev {
                            let dt = (t1 - t0) / f64::from(n);
                            assert!((v - pv).abs() <= local * dt + 1e-12, "{k:?} t={t}");
                        }
                        prev = Some(v);
                    }
                }
            }
        }
    }

    /// At the edge of a support box the affine form of the closed form is
    /// infinite; the interval fallback keeps it finite and tight (this
    /// window of the shipped `skeleton-homothetic` scene was reported as a
    /// spurious root by affine bisection before the fallback).
    #[test]
    fn affine_fallback_keeps_support_edges_tight() {
        use boundtrace_ia_core::Affine;
        let v = [
            ([0.0, -0.8, 0.0], 0.16),
            ([0.0, 0.0, 0.0], 0.12),
            ([-0.5, 0.45, 0.1], 0.06),
            ([0.45, 0.5, -0.1], 0.08),
            ([0.05, 0.75, 0.3], 0.05),
            ([-0.6, -0.75, 0.2], 0.04),
        ];
        let segs: [Segment<f64>; 5] = [(0, 1), (1, 2), (1, 3), (1, 4), (0, 5)]
            .map(|(i, j)| seg(v[i].0, v[i].1, v[j].0, v[j].1));
        let k = SegmentKernel::compact_polynomial(4, 1.6).unwrap();
        let sk = HomotheticSkeleton::new(segs, k, 1.0).unwrap();
        let ray = Ray::new(
            [
                -0.898_708_443_344_732_4,
                -1.027_847_890_502_219_3,
                0.455_304_024_271_052_7,
            ],
            [1.0, 0.0, 0.0],
        );
        for i in 0..4 {
            let t = 0.042_708 + 1e-4 * f64::from(i);
            let af: Affine<f64, 1> = sk.eval(ray.at(t - 5e-5, t + 5e-5));
            let r = af.to_interval();
            let v: f64 = sk.eval(ray.at(t, t));
            assert!(
                r.is_bounded() && r.contains(v) && r.lo() > 0.0,
                "{t}: {r:?} {v}"
            );
        }
    }

    /// `|k'|` bounds: the maximum over `h` matches a dense scan, and the
    /// per-range bound is never below a sampled `|k'|` in the range.
    #[test]
    fn kernel_slope_bounds() {
        for k in [
            SegmentKernel::compact_polynomial(2, 1.5).unwrap(),
            SegmentKernel::compact_polynomial(6, 2.0).unwrap(),
            SegmentKernel::cauchy(3, 1.0).unwrap(),
            SegmentKernel::cauchy(6, 2.0).unwrap(),
        ] {
            let sk = HomotheticSkeleton::new([seg([0.0; 3], 1.0, [1.0, 0.0, 0.0], 1.0)], k, 1.0)
                .unwrap();
            let slope = |h: f64| {
                let e = 1e-6;
                let (a, b): (f64, f64) =
                    (k.eval_sq((h + e) * (h + e)), k.eval_sq((h - e) * (h - e)));
                ((a - b) / (2.0 * e)).abs()
            };
            let mut best: f64 = 0.0;
            for i in 1..4000 {
                let h = 5.0 * f64::from(i) / 4000.0;
                best = best.max(slope(h));
            }
            let m = sk.kernel_slope_bound();
            assert!(
                m >= best * (1.0 - 1e-6) && m <= best * 1.01,
                "{k:?}: {m} vs {best}"
            );
            for (lo, hi) in [(0.0, 0.1), (0.2, 0.5), (0.9, 1.4), (1.6, 4.0), (0.0, 9.0)] {
                let b = sk.kernel_slope_on(Interval::new(lo, hi));
                for i in 1..100 {
                    let h = lo + (hi - lo) * f64::from(i) / 100.0;
                    assert!(slope(h) <= b * (1.0 + 1e-6) + 1e-9, "{k:?} h={h}: {b}");
                }
            }
        }
    }

    /// The skeleton over [`FlatSegments`] with its parameter words (the
    /// GPU's data) is the skeleton it came from, bit for bit, in every
    /// number type and in its bounds, for both kernels; a short buffer is
    /// refused.
    #[test]
    fn flat_segments_are_the_same_field() {
        use boundtrace_ia_core::Affine;
        use boundtrace_inclusion::ForwardQuadratic;
        let segs = vec![
            seg([-1.0, 0.0, 0.0], 0.3, [0.0, 0.0, 0.0], 0.4),
            seg([0.0, 0.0, 0.0], 0.4, [0.0, 1.0, 0.2], 0.2),
            seg([0.1, 0.9, 0.3], 0.1, [0.6, 1.2, -0.3], 0.15),
        ];
        for k in [
            SegmentKernel::compact_polynomial(4, 1.6).unwrap(),
            SegmentKernel::cauchy(3, 1.2).unwrap(),
        ] {
            let sk = HomotheticSkeleton::new(segs.clone(), k, 1.0).unwrap();
            let mut words = sk.segment_words();
            let n = sk.segment_count();
            assert_eq!(words.len(), n * SEGMENT_WORDS);
            assert_eq!(words[SEGMENT_WORDS + 3], segs[1].ra());
            words.push(99.0); // a word past the last segment, left out
            assert!(FlatSegments::new(&words, n + 1).is_none());
            assert!(FlatSegments::new(&words, usize::MAX).is_none());
            let (code, params) = sk.parameter_words();
            let flat = HomotheticSkeleton::from_parameter_words_unchecked(
                FlatSegments::new(&words, n).unwrap(),
                code,
                params,
            );
            assert_eq!(flat.kernel(), k);
            assert_eq!(flat.parameter_words(), (code, params));
            assert_eq!(flat.segment_words(), words[..n * SEGMENT_WORDS]);
            assert_eq!(flat.lipschitz(), sk.lipschitz());
            for i in 0..60 {
                let t = f64::from(i) * 0.05 - 1.5;
                let x = [0.3 * t + 0.1, t, 0.2 - 0.4 * t];
                assert_eq!(flat.eval(x).to_bits(), sk.eval(x).to_bits(), "{x:?}");
                let b = x.map(|c| Interval::new(c - 0.05, c + 0.03));
                let (fb, sb): (Interval<f64>, Interval<f64>) = (flat.eval(b), sk.eval(b));
                assert_eq!(
                    (fb.lo().to_bits(), fb.hi().to_bits()),
                    (sb.lo().to_bits(), sb.hi().to_bits())
                );
                let ray = Ray::new([x[0], x[1], x[2]], [0.2, 1.0, -0.3]);
                let pa: [Affine<f64, 1>; 3] = ray.at(0.0, 0.2);
                let (fa, sa): (Affine<f64, 1>, Affine<f64, 1>) = (flat.eval(pa), sk.eval(pa));
                assert_eq!(fa, sa);
                let pq: [ForwardQuadratic<f64>; 3] = ray.at(0.0, 0.2);
                let (fq, sq): (ForwardQuadratic<f64>, ForwardQuadratic<f64>) =
                    (flat.eval(pq), sk.eval(pq));
                assert_eq!(fq, sq);
                assert_eq!(
                    flat.taylor_linear(&ray, 0.0, 0.2),
                    sk.taylor_linear(&ray, 0.0, 0.2)
                );
            }
        }
    }
}
