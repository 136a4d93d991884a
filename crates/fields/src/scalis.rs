//! SCALIS segments: scale-invariant integral surfaces of line segments with
//! linearly varying radius (thesis Part II eq. 1.14), in closed form, their
//! normalization `g(f) − 1` (Part III ch. 1 §1.2) and per-primitive bounds
//! (Part III ch. 2 §2.1).
//!
//! # The field
//!
//! For a [`Segment`] `q(s) = a + s·u`, `τ(s) = r_a + Δ·s`, `s ∈ [0, L]`, and
//! a kernel `k` of the homothetic distance `h = |p − q|/τ`,
//!
//! ```text
//! f(p) = 1/N_{k,c} · ∫₀ᴸ k(|p − q(s)| / τ(s)) / τ(s) ds          (eq. 1.14)
//! ```
//!
//! We centre the parameter on the segment's midpoint: `y = s − L/2 ∈ [−ℓ, ℓ]`
//! (`ℓ = L/2`), `τ(y) = τ_c + Δ·y` with `τ_c = (r_a + r_b)/2`. With
//! `x_c` the axial coordinate of `p` from the midpoint and `d²` its squared
//! distance to the segment's line, `|p − q(y)|² = (y − x_c)² + d²`.
//!
//! ## Compact polynomial kernel, even degree `n = 2m ∈ {2, 4, 6, 8}`
//!
//! `k(h) = (1 − h²/σ²)^m` for `h < σ`. Then
//! `k(h)/τ = P(y)^m / (σ^{2m} τ^{2m+1})` with the **quadratic**
//!
//! ```text
//! P(y) = σ²τ(y)² − (y − x_c)² − d² = A·y² + B·y + C,
//! A = σ²Δ² − 1,  B = 2σ²τ_cΔ + 2x_c,  C = σ²τ_c² − x_c² − d².
//! ```
//!
//! *Clipping.* The integrand is non-zero where `P > 0`. Since
//! `στ(y) − |p − q(y)|` is concave in `y` and `τ > 0` on the segment, the set
//! `{P ≥ 0} ∩ [−ℓ, ℓ]` is one interval. We require `σ·|Δ| < 1` (the support
//! ball of one end-point does not swallow the other: the thesis' "bounded
//! radius variation", Part III §1.5), so `A < 0` and that interval is
//! `[y₀, y₁] = [max(r₋, −ℓ), max(min(r₊, ℓ), y₀)]` with the roots
//! `r∓ = (−B ± √max(B² − 4AC, 0)) / (2A)`; an empty support gives `y₀ = y₁`
//! and a zero integral, with no branch on `p`. (Root accuracy barely matters:
//! the integrand vanishes to order `m` at the roots.)
//!
//! *Integration.* `I = ∫_{y₀}^{y₁} P(y)^m / τ(y)^{2m+1} dy`, a rational
//! integrand with its only pole at the apex `τ = 0`, outside the segment.
//! We centre on the clipped range: `y = y_m + z`, `z ∈ [−w, w]`,
//! `τ_m = τ(y_m)`, and re-centre the *quadratic* `P` on `y_m` before raising
//! it to the power `m` (expanding `P^m` about a far point cancels
//! catastrophically). Two evaluations, exact in real arithmetic, are chosen
//! per point by `|q|`, `q = Δw/τ_m` (the relative radius variation over the
//! clipped range), against `ρ* = 1/4` (`f64`; `2/5` for `f32`):
//!
//! - **`|q| ≤ ρ*` — centred binomial series.**
//!   `τ^{−e} = τ_m^{−e} Σ_k C(k+e−1, e−1) (−Δz/τ_m)^k` (`e = 2m+1`) and
//!   `∫_{−w}^{w} z^n dz = 2w^{n+1}/(n+1)` for even `n`, `0` for odd `n`:
//!   `I = 2τ_m^{−e} Σ_j π_j w^{j+1} Σ_{k ≡ j (mod 2)} C(k+e−1, e−1) (−q)^k/(j+k+1)`,
//!   `π_j` the coefficients of `P^m` in `z`. The series is truncated at the
//!   first `K` (≤ 63) whose tail `Σ_{k>K} C(k+e−1,e−1) ρ^k` times
//!   `(1+ρ)^e` is below `10⁻³ ε_mach`, for the smallest of the precomputed
//!   tiers `ρ ∈ ρ*·{0, 1/64, 1/16, 1/4, 1/2, 1}` that bounds `|q|` (a
//!   constant radius needs one term, `|q| ≤ ρ*/64` about ten); since
//!   `P^m ≥ 0` and `τ ≤ (1+ρ)τ_m`,
//!   this (plus the rounding of the constant coefficients) bounds the
//!   relative error `δ`, and the result is widened by `±2δ` relative with
//!   [`FieldNum::join`] so that bottom-up bounds stay sound (point types are
//!   not widened).
//! - **`|q| > ρ*` — partial fractions in `τ`.** Substituting
//!   `z = (τ − τ_m)/Δ` turns the polynomial into `Σᵢ cᵢ τⁱ` (`i ≤ 2m`) and
//!   `I = 1/Δ · [Σ_{i<2m} cᵢ τ^{i−2m}/(i−2m) + c_{2m} ln τ]_{τ_m−Δw}^{τ_m+Δw}`.
//!   The coefficients grow like `Δ^{−i}` and cancel by about
//!   `(1/(2|q|))^{2m}`, which is why this form is kept for `|q| > ρ*`.
//!
//! When an enclosure of `|q|` straddles `ρ*`, both are computed and joined.
//! Measured against adaptive quadrature (`tests/fields_scalis.rs`): relative
//! error ≤ 10⁻⁹ in `f64`; in `f32` about `10⁻⁴`–`10⁻³` where the partial
//! fractions are used. The switch between the two forms and the rounding
//! of the partial fractions make the `f64` value noisy at about `10⁻¹⁰`
//! relative (degree 8, strongly varying radius): finite differences of
//! values with tiny steps are meaningless there, use the closed-form
//! derivatives.
//!
//! The gradient differentiates under the integral (the boundary terms vanish:
//! `P = 0` at a clipped end, the segment ends are fixed):
//! `∇f = −2m/(N σ^{2m}) · [(p − q(y_m))·∫P^{m−1}/τ^e − u·∫z P^{m−1}/τ^e]` —
//! two more integrals of the same kind.
//!
//! *Normalization.* For an infinite line of constant radius `τ₀`,
//! `∫ k/τ₀ ds = σ·c_m·(1 − D²/σ²)^{m+½}` with `D = d/τ₀` and
//! `c_m = ∫₋₁¹(1 − v²)^m dv = 2^{2m+1}(m!)²/(2m+1)!` (`32/35` for `m = 3`),
//! i.e. a compact kernel of degree `n + 1` (Part III eq. 1.1). Choosing
//! `N_{k,c} = σ c_m (1 − 1/σ²)^{m+½} / c` puts the iso-value `c` at `D = 1`
//! (needs `σ > 1`), and inverting gives Part III eq. 1.3:
//! `g(f) = σ²(1 − (1 − 1/σ²)(f/c)^{2/(n+1)})`, `g = σ²` for `f ≤ 0`.
//!
//! ## Cauchy kernel, degree 3
//!
//! `k(h) = (1 + h²/σ²)^{−3/2}`, so `k/τ = σ³τ² / R(y)^{3/2}` with
//! `R = σ²τ² + (y − x_c)² + d² = a(v² + e²)`, `a = σ²Δ² + 1`,
//! `v = y + b/(2a)`, `b = 2σ²τ_cΔ − 2x_c`, and — without cancellation —
//! `a²e² = σ²τ_x² + a·d²`, `τ_x = τ_c + Δx_c` the radius at the projection
//! of `p`. With `τ = τ_v + Δv` (`τ_v = τ_c − Δb/(2a)`) and
//! `r = √(v² + e²)`, the three primitives
//!
//! ```text
//! ∫ dv/r³ = v/(e²r),   ∫ v dv/r³ = −1/r,   ∫ v² dv/r³ = asinh(v/e) − v/r
//! ```
//!
//! are evaluated as differences in stable forms: `[−1/r] = (v₁² − v₀²) /
//! (r₀r₁(r₀ + r₁))`; `[v/(e²r)] = (v₁² − v₀²)/(r₀r₁(v₁r₀ + v₀r₁))` when `v₀`,
//! `v₁` have the same sign (the direct form otherwise, where no cancellation
//! occurs); `[asinh(v/e)] = ln((v₁ + r₁)/(v₀ + r₀))` for `v ≥ 0`, its mirror
//! for `v ≤ 0` and `ln((v₁ + r₁)(r₀ − v₀)/e²)` across `0`. The branch is
//! decided from [`FieldNum::enclosure`]; when undecided both (equal)
//! expressions are [`FieldNum::join`]ed. Only degree 3 is offered: even
//! degrees need `atan`, which [`FieldNum`] lacks. For an infinite line
//! `∫ k/τ₀ ds = 2σ/(1 + D²/σ²)` (a Cauchy kernel of degree 2), so
//! `N = 2σ³/((1 + σ²)c)` and `g(f) = (1 + σ²)c/f − σ²` (eq. 1.4).
//!
//! # Per-primitive bounds (ch. 2 §2.1)
//!
//! [`ScalisSegment::directional_lipschitz`] bounds `|d f(o + t·d)/dt|` on
//! `[t₀, t₁]` by `|d|/N · max|k'| · ∫_{s₀}^{s₁} ds/τ(s)²` (`|∂h/∂t| ≤
//! |d|/τ`), where `[s₀, s₁]` are the skeleton points whose support can reach
//! the ray segment (all of `[0, L]` for Cauchy) and
//! `∫ ds/τ² = (s₁ − s₀)/(τ(s₀)τ(s₁))` exactly. `max|k'|` is
//! `2m·h*(1 − h*²/σ²)^{m−1}/σ²` at `h*² = σ²/(2m−1)` (compact) and
//! `3·(1/(2σ))·(4/5)^{5/2}` at `h* = σ/2` (Cauchy, thesis §2.1.1); when a
//! lower bound `h_min` of `h_S` on the ray segment (interval evaluation of
//! [`Segment::homothetic_sq`]) exceeds `h*`, `|k'(h_min)|` replaces it
//! (`|k'|` decreases beyond `h*` and every skeleton point is at least
//! `h_min` away), and the bound is `0` beyond a compact support. This is
//! simpler than the thesis' split of the integral by the sign of
//! `(p − q)·u`, and looser where the ray passes close to the skeleton.
//! [`ScalisSegment::density_range`] combines sound end-point values
//! (interval evaluation at the points), a sound enclosure of the derivative
//! on the whole interval (the closed-form gradient evaluated in interval
//! arithmetic, compact kernel) — a fixed sign is a *monotone interval* — and
//! the two Lipschitz lines of Fig. 2.2 for ambiguous intervals.
//! The thesis detects monotony from the derivative signs at the interval
//! end-points alone, relying on the observation that the field is
//! unimodal along rays; that is not proven for varying radii (no
//! counter-example was found in the tests), so it is offered separately as
//! [`ScalisSegment::density_range_unimodal`] with a warning.
//!
//! [`Field::taylor_linear`] of [`ScalisSegment`] and [`ScalisSkeleton`] is
//! [`ForwardLinear::taylor`] from the point enclosure at `t₀` and that
//! derivative enclosure; [`Field::taylor_quadratic`] (compact kernels of
//! degree ≥ 4) is [`ForwardQuadratic::taylor`] from point enclosures of `f`
//! and `f'` at `t₀` and an interval enclosure of the closed-form `f''`
//! ([`ScalisSegment::second_derivative_generic`]) on `[t₀, t₁]`.

//!
//! # Cost
//!
//! Measured once (release, x86-64, one segment of length 3, compact degree
//! 6 / Cauchy degree 3): `f64` density about 120 ns (constant radius), 330 ns
//! (radius 0.3 → 0.7), 40 ns (Cauchy); `Interval` at a point 2.5–10 µs
//! (compact), 0.8 µs (Cauchy); a bottom-up [`ForwardQuadratic`] of the
//! closed form 0.3–0.6 ms (compact), 40 µs (Cauchy) — the series is a long
//! polynomial in forward arithmetic. For forward bounds prefer the Taylor
//! bounds ([`BoundKind::Taylor`](boundtrace_inclusion::BoundKind::Taylor)),
//! built from interval evaluations of the closed-form derivatives.

// `!(x > 0)` is deliberate: it is true for NaN, which must be rejected.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::FieldError;
use crate::bounding::SphereCone;
use crate::homothetic::{Plain, Segment, SegmentKernel};
use boundtrace_ia_core::{Interval, Real};
use boundtrace_inclusion::{Field, FieldNum, ForwardLinear, ForwardQuadratic, Ray};

/// Highest supported compact half-degree `m` (degree `n = 2m ≤ 8`).
const MAX_M: usize = 4;
/// Coefficients of polynomials of degree ≤ 2·MAX_M.
const NC: usize = 2 * MAX_M + 1;
/// Most series terms.
const MAX_TERMS: usize = 64;
/// The bound `ρ*` on `|q| = |Δ|w/τ_m` below which the centred series is
/// used (partial fractions above): `1/4` for `f64`, `2/5` for `f32` (whose
/// partial fractions lose `~(1/(2ρ))^{2m}` ulps).
fn series_limit<T: Real>() -> f64 {
    if T::EPSILON.as_f64() > 1e-10 {
        0.4
    } else {
        0.25
    }
}

/// A SCALIS segment primitive (thesis eq. 1.14) with a compact polynomial
/// (even degree 2–8) or Cauchy (degree 3) kernel, normalized so that an
/// isolated long segment of constant radius `r` has its iso-surface
/// `f = iso` at distance `r` from the skeleton.
///
/// As a [`Field`] it is `iso − f(p)` (positive outside). The density itself
/// is [`density`](Self::density); the normalized field `g(f) − 1` is
/// [`ScalisSegment::normalized`] / [`Normalized`].
///
/// ```
/// use boundtrace_fields::homothetic::{Segment, SegmentKernel};
/// use boundtrace_fields::scalis::ScalisSegment;
/// use boundtrace_inclusion::{Field, FieldNum};
///
/// let seg = Segment::new([-50.0, 0.0, 0.0], 1.0, [50.0, 0.0, 0.0], 1.0).unwrap();
/// let k = SegmentKernel::compact_polynomial(6, 2.0).unwrap();
/// let s = ScalisSegment::new(seg, k, 1.0).unwrap();
/// // on the prescribed radius in the middle of a long segment: f = iso
/// assert!((s.density([0.0, 1.0, 0.0]) - 1.0f64).abs() < 1e-12);
/// assert!(s.eval([0.0, 1.5, 0.0]) > 0.0); // outside
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct ScalisSegment<T> {
    seg: Segment<T>,
    /// The kernel's kind: [`KIND_COMPACT`] or [`KIND_CAUCHY`] (an enum
    /// with data cannot live in a GPU storage buffer; [`kernel`](Self::kernel)
    /// rebuilds it from this, `degree` and `sigma`).
    kind: u32,
    /// The kernel's degree `n`.
    degree: u32,
    iso: T,
    /// Half-degree `m` (compact) or `0` (Cauchy).
    m: u32,
    /// The kernel's scale `σ`.
    sigma: T,
    half: T,
    tc: T,
    delta: T,
    /// Density scale: `1/(N σ^{2m})` (compact), `(1 + σ²)c/2` (Cauchy).
    scale: T,
    /// Series tiers, increasing bounds up to `ρ*` (compact kernels only):
    /// the `|q|` bound of each,
    tier_bound: [T; TIERS],
    /// its number of terms `K + 1`,
    tier_terms: [u32; TIERS],
    /// and its relative widening `2δ`.
    tier_widen: [T; TIERS],
    /// `τ_c^{−e} C(k+e−1, e−1) (−Δ/τ_c)^k`.
    beta: [T; MAX_TERMS],
    /// `max |k'|`.
    kprime_max: T,
    /// `1/N`.
    inv_norm: T,
    /// The support box `[lo, hi]` (compact kernels; infinite for Cauchy).
    support_box: [[T; 3]; 2],
}

/// [`ScalisSegment`]'s kernel kind code of a compact polynomial kernel.
const KIND_COMPACT: u32 = 0;
/// [`ScalisSegment`]'s kernel kind code of a Cauchy kernel.
const KIND_CAUCHY: u32 = 1;

/// The number of 32-bit words of a [`ScalisSegment<f32>`] as stored
/// (`#[repr(C)]`, every field a 4-byte word or an array of them):
/// [`ScalisSegment::to_words`] writes them in memory order, the layout a
/// GPU storage buffer of segments holds.
pub const SCALIS_SEGMENT_WORDS: usize = 13 + 9 + 3 * TIERS + MAX_TERMS + 2 + 6;

fn binom(n: u32, k: u32) -> f64 {
    let mut r = 1.0f64;
    let mut i = 0;
    while i < k {
        r = r * f64::from(n - i) / f64::from(i + 1);
        i += 1;
    }
    r
}

/// Number of series tiers.
const TIERS: usize = 6;
/// Tier bounds as fractions of `ρ*`; the first tier is `q = 0` (constant
/// radius).
const TIER_FRACTIONS: [f64; TIERS] = [0.0, 1.0 / 64.0, 1.0 / 16.0, 1.0 / 4.0, 1.0 / 2.0, 1.0];

/// `(K + 1, 2δ)` for the binomial series of `(1 + x)^{−e}`, `|x| ≤ ρ`: the
/// first `K` whose tail `Σ_{k>K} C(k+e−1, e−1) ρ^k` (bounded by the next
/// term over `1 − ratio`, the term ratios `ρ(k+e)/(k+1)` decreasing) times
/// `(1+ρ)^e` is below `10⁻³ ε`, and the relative error `δ` it leaves with the
/// rounding of the coefficients (module docs).
fn series_tier(rho: f64, e: u32, eps: f64) -> (u32, f64) {
    let target = eps * 1e-3;
    let grow_e = (1.0 + rho).powi(e as i32);
    let mut k = 0u32;
    loop {
        let next = binom(k + e, e - 1) * rho.powi(k as i32 + 1);
        let ratio = rho * f64::from(k + 1 + e) / f64::from(k + 2);
        let tail = if ratio < 1.0 {
            next / (1.0 - ratio)
        } else {
            f64::INFINITY
        };
        if (ratio < 1.0 && tail * grow_e <= target) || k as usize + 1 >= MAX_TERMS {
            let round = 8.0 * f64::from(k + 3 + e) * eps;
            let delta_rel = (tail + round * (1.0 - rho).powi(-(e as i32))) * grow_e;
            return (k + 1, 2.0 * delta_rel * 1.01);
        }
        k += 1;
    }
}

impl ScalisSegment<f32> {
    /// The segment's [`SCALIS_SEGMENT_WORDS`] words in memory order (`f32`s
    /// as their bits): the bytes of a GPU storage buffer of segments, which
    /// a shader reads as `&[ScalisSegment<f32>]`.
    pub fn to_words(&self) -> [u32; SCALIS_SEGMENT_WORDS] {
        let mut w = [0u32; SCALIS_SEGMENT_WORDS];
        let mut n = 0;
        let mut put = |x: u32| {
            w[n] = x;
            n += 1;
        };
        let s = &self.seg;
        for k in 0..3 {
            put(s.a()[k].to_bits());
        }
        put(s.ra().to_bits());
        for k in 0..3 {
            put(s.b()[k].to_bits());
        }
        put(s.rb().to_bits());
        for k in 0..3 {
            put(s.axis()[k].to_bits());
        }
        put(s.length().to_bits());
        put(s.radius_slope().to_bits());
        put(self.kind);
        put(self.degree);
        put(self.iso.to_bits());
        put(self.m);
        for x in [self.sigma, self.half, self.tc, self.delta, self.scale] {
            put(x.to_bits());
        }
        for x in self.tier_bound {
            put(x.to_bits());
        }
        for x in self.tier_terms {
            put(x);
        }
        for x in self.tier_widen {
            put(x.to_bits());
        }
        for x in self.beta {
            put(x.to_bits());
        }
        put(self.kprime_max.to_bits());
        put(self.inv_norm.to_bits());
        for corner in self.support_box {
            for x in corner {
                put(x.to_bits());
            }
        }
        w
    }
}

impl<T: Real> ScalisSegment<T> {
    /// The SCALIS primitive of `segment` with `kernel`, normalized for the
    /// iso-value `iso > 0`.
    ///
    /// # Errors
    ///
    /// [`FieldError::InvalidParameter`] for: a compact kernel of degree
    /// other than 2, 4, 6, 8, or with `σ ≤ 1` (the iso-surface would leave
    /// the support), or with `σ·|r_b − r_a| ≥ L` (one end's support swallows
    /// the other's); a Cauchy kernel of degree other than 3 (the others need
    /// `atan`); a NaN/infinite/non-positive `iso`.
    pub fn new(segment: Segment<T>, kernel: SegmentKernel<T>, iso: T) -> Result<Self, FieldError> {
        let iso = crate::error::positive("iso", iso)?;
        let sigma = kernel.sigma();
        let half = segment.length() * T::HALF;
        let tc = (segment.ra() + segment.rb()) * T::HALF;
        let delta = segment.radius_slope();
        let (sf, isof, tcf, df, hf) = (
            sigma.as_f64(),
            iso.as_f64(),
            tc.as_f64(),
            delta.as_f64(),
            half.as_f64(),
        );
        let (kind, degree) = match kernel {
            SegmentKernel::CompactPolynomial { degree, .. } => (KIND_COMPACT, degree),
            SegmentKernel::Cauchy { degree, .. } => (KIND_CAUCHY, degree),
        };
        let mut out = Self {
            seg: segment,
            kind,
            degree,
            iso,
            m: 0,
            sigma,
            half,
            tc,
            delta,
            scale: T::ZERO,
            tier_bound: [T::ZERO; TIERS],
            tier_terms: [0; TIERS],
            tier_widen: [T::ZERO; TIERS],
            beta: [T::ZERO; MAX_TERMS],
            kprime_max: T::ZERO,
            inv_norm: T::ZERO,
            support_box: [[T::NEG_INFINITY; 3], [T::INFINITY; 3]],
        };
        match kernel {
            SegmentKernel::CompactPolynomial { degree, .. } => {
                if degree % 2 != 0 || degree < 2 || degree as usize > 2 * MAX_M {
                    return Err(FieldError::InvalidParameter {
                        name: "degree",
                        reason: "SCALIS compact kernels support the even degrees 2, 4, 6, 8",
                    });
                }
                if !(sigma > T::ONE) {
                    return Err(FieldError::InvalidParameter {
                        name: "sigma",
                        reason: "a compact SCALIS kernel needs σ > 1",
                    });
                }
                if !(sigma * delta.abs() < T::ONE) || !(sf * df.abs() < 1.0 - 1e-9) {
                    return Err(FieldError::InvalidParameter {
                        name: "rb",
                        reason: "radius variation too steep for the kernel scale: need σ·|rb − ra| < L",
                    });
                }
                let m = degree / 2;
                out.m = m;
                let mf = f64::from(m);
                let mut cm = 2f64.powi(2 * m as i32 + 1);
                let mut i = 1;
                while i <= m {
                    cm *= f64::from(i) * f64::from(i);
                    i += 1;
                }
                let mut i = 1;
                while i <= 2 * m + 1 {
                    cm /= f64::from(i);
                    i += 1;
                }
                let norm = sf * cm * (1.0 - 1.0 / (sf * sf)).powf(mf + 0.5) / isof;
                out.inv_norm = T::from_f64(1.0 / norm);
                out.scale = T::from_f64(1.0 / (norm * sf.powi(2 * m as i32)));
                // max |k'(h)| = 2m h (1 − h²/σ²)^{m−1} / σ² at h² = σ²/(2m − 1)
                let h2 = sf * sf / (2.0 * mf - 1.0);
                out.kprime_max = T::from_f64(
                    2.0 * mf * h2.sqrt() * (1.0 - h2 / (sf * sf)).powf(mf - 1.0) / (sf * sf)
                        * (1.0 + 1e-12),
                );
                // series terms per tier of |q| ≤ ρ* (module docs)
                let e = 2 * m + 1;
                let rho_max = series_limit::<T>();
                let mut i = 0;
                let mut kmax = 0;
                while i < TIERS {
                    let rho = rho_max * TIER_FRACTIONS[i];
                    let (terms, tol) = series_tier(rho, e, T::EPSILON.as_f64());
                    out.tier_bound[i] = T::from_f64(rho);
                    out.tier_terms[i] = terms;
                    out.tier_widen[i] = T::from_f64(tol);
                    kmax = kmax.max(terms);
                    i += 1;
                }
                let mut j = 0u32;
                while j < kmax {
                    out.beta[j as usize] = T::from_f64(binom(j + e - 1, e - 1));
                    j += 1;
                }
                let _ = (tcf, df, hf);
                let reach = Interval::point(sigma) * segment.ra().max(segment.rb());
                let (a, b) = (segment.a(), segment.b());
                out.support_box = [
                    [0, 1, 2].map(|k| (Interval::point(a[k].min(b[k])) - reach).lo()),
                    [0, 1, 2].map(|k| (Interval::point(a[k].max(b[k])) + reach).hi()),
                ];
            }
            SegmentKernel::Cauchy { degree, .. } => {
                if degree != 3 {
                    return Err(FieldError::InvalidParameter {
                        name: "degree",
                        reason: "SCALIS Cauchy kernels support degree 3 only (others need atan)",
                    });
                }
                let norm = 2.0 * sf * sf * sf / ((1.0 + sf * sf) * isof);
                out.inv_norm = T::from_f64(1.0 / norm);
                out.scale = T::from_f64((1.0 + sf * sf) * isof / 2.0);
                out.kprime_max = T::from_f64(1.5 / sf * 0.8f64.powf(2.5) * (1.0 + 1e-12));
            }
        }
        Ok(out)
    }

    /// The skeleton segment.
    #[inline]
    pub fn segment(&self) -> &Segment<T> {
        &self.seg
    }
    /// The kernel.
    #[inline]
    pub fn kernel(&self) -> SegmentKernel<T> {
        if self.kind == KIND_CAUCHY {
            SegmentKernel::Cauchy {
                degree: self.degree,
                sigma: self.sigma,
            }
        } else {
            SegmentKernel::CompactPolynomial {
                degree: self.degree,
                sigma: self.sigma,
            }
        }
    }
    /// The iso-value `c`.
    #[inline]
    pub fn iso(&self) -> T {
        self.iso
    }
    /// `1/N_{k,c}` (eq. 1.14).
    #[inline]
    pub fn inv_normalization(&self) -> T {
        self.inv_norm
    }
    /// The density `f(p)` of eq. 1.14 (≥ 0), in any number type.
    pub fn density<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        let (x, d2) = self.seg.axial(p);
        let xc = x - self.half;
        if self.m == 0 {
            self.cauchy(xc, d2)
        } else {
            match self.clip(xc, d2) {
                Ok((poly, y0, y1)) => self.integrate(&poly, self.m, 0, y0, y1) * self.scale,
                Err(zero) => zero,
            }
        }
    }

    /// `P(y)` as coefficients `[C, B, A]` and the clipped support `[y₀, y₁]`.
    /// `Err(zero)` when the support certainly misses the segment (decided
    /// on [`FieldNum::enclosure`]; this also keeps `√0` out of jets and
    /// forward bounds). The zero is `disc·0`, which keeps the validity
    /// interval of the forward bound the decision was made on.
    fn clip<N: FieldNum<T>>(&self, xc: N, d2: N) -> Result<([N; 3], N, N), N> {
        let s2 = self.sigma * self.sigma;
        let a = s2 * self.delta * self.delta - T::ONE;
        let b = xc * T::TWO + T::TWO * s2 * self.tc * self.delta;
        let c = -(xc.sqr() + d2) + s2 * self.tc * self.tc;
        let disc = b.sqr() - c * (T::from_f64(4.0) * a);
        if disc.enclosure().hi() <= T::ZERO {
            return Err(disc * T::ZERO);
        }
        let sq = disc.max(N::constant(T::ZERO)).sqrt();
        let lo = (-b + sq) / (T::TWO * a);
        let hi = (-b - sq) / (T::TWO * a);
        if lo.enclosure().lo() >= self.half || hi.enclosure().hi() <= -self.half {
            return Err((lo + hi) * T::ZERO);
        }
        let (mh, h) = (N::constant(-self.half), N::constant(self.half));
        let y0 = lo.max(mh).min(h);
        let y1 = hi.min(h).max(y0);
        Ok(([c, b, N::constant(a)], y0, y1))
    }

    /// `∫_{y₀}^{y₁} z^{zp}·P(y)^{pw} / τ(y)^{2m+1} dy` with `z = y − y_m`,
    /// `y_m = (y₀ + y₁)/2`, `P` the quadratic `[C, B, A]` in `y`: the
    /// centred binomial series when `|q| = |Δ|·w/τ_m ≤ ρ*`, partial
    /// fractions otherwise (both, joined, when the enclosure of `|q|`
    /// straddles `ρ*`). `P` is re-centred on `y_m` *before* it is raised to
    /// the power, which avoids the cancellation of expanding `P^m` far from
    /// its support.
    fn integrate<N: FieldNum<T>>(&self, base: &[N; 3], pw: u32, zp: u32, y0: N, y1: N) -> N {
        let zero = N::constant(T::ZERO);
        let ym = (y0 + y1) * T::HALF;
        let w = (y1 - y0) * T::HALF;
        let tm = ym * self.delta + self.tc;
        // P(y_m + z) = A z² + (2A y_m + B) z + P(y_m)
        let a = base[2];
        let shifted = [
            (a * ym + base[1]) * ym + base[0],
            a * ym * T::TWO + base[1],
            a,
        ];
        let mut poly = [zero; NC];
        let mut deg = power(&shifted, pw, &mut poly);
        let mut r = 0;
        while r < zp && deg + 1 < NC {
            let mut i = deg + 1;
            while i > 0 {
                if i < NC {
                    poly[i] = poly[i - 1];
                }
                i -= 1;
            }
            poly[0] = zero;
            deg += 1;
            r += 1;
        }
        let q = w * self.delta / tm;
        let qa = q.abs().enclosure();
        let lim = T::from_f64(series_limit::<T>());
        // The series where |q| ≤ ρ*, the fractions where |q| > ρ*, both
        // (joined, the series up to ρ*) when |q| straddles ρ*: each called
        // from one place, since a GPU driver inlines every call.
        let only_series = qa.hi() <= lim;
        let only_fractions = !only_series && qa.lo() > lim;
        let mut out = zero;
        if !only_fractions {
            let qmax = if only_series { qa.hi() } else { lim };
            out = self.integrate_series(&poly, deg, w, tm, q, qmax);
        }
        if !only_series {
            let f = self.integrate_fractions(&poly, deg, w, tm);
            out = if only_fractions { f } else { out.join(f) };
        }
        out
    }

    /// Centred series (`poly` in `z = y − y_m ∈ [−w, w]`):
    /// `τ^{−e} = τ_m^{−e} Σ_k C(k+e−1, e−1) (−Δz/τ_m)^k`, and
    /// `∫_{−w}^{w} z^n dz = 2w^{n+1}/(n+1)` for even `n` (0 for odd):
    /// `I = 2τ_m^{−e} Σ_j π_j w^{j+1} Σ_{k ≡ j (2)} C(k+e−1,e−1) q^k/(j+k+1)`
    /// with `q = −Δw/τ_m`.
    fn integrate_series<N: FieldNum<T>>(
        &self,
        pi: &[N; NC],
        deg: usize,
        w: N,
        tm: N,
        q: N,
        qmax: T,
    ) -> N {
        let zero = N::constant(T::ZERO);
        let e = 2 * self.m as i32 + 1;
        let q = -q;
        let q2 = q.sqr();
        // the first tier whose bound covers |q| (the last one is ρ* ≥ qmax)
        let mut tier = TIERS - 1;
        let mut ti = 0;
        while ti < TIERS {
            if qmax <= self.tier_bound[ti] {
                tier = ti;
                break;
            }
            ti += 1;
        }
        let (kmax, tol) = (self.tier_terms[tier] as usize, self.tier_widen[tier]); // k < kmax
        let mut acc = zero;
        let mut wp = w; // w^{j+1}
        let mut j = 0usize;
        while j <= deg {
            // S_j = Σ_{k ≡ j mod 2, k < kmax} β_k q^k / (j+k+1), Horner in q²
            let par = (j % 2) as isize;
            let mut k = kmax as isize - 1;
            if k.rem_euclid(2) != par {
                k -= 1;
            }
            let mut s = zero;
            while k >= 0 {
                let ku = k as usize;
                s = s * q2 + self.beta[ku] / T::from_f64((j + ku + 1) as f64);
                k -= 2;
            }
            if par == 1 {
                s = s * q;
            }
            acc = acc + pi[j] * wp * s;
            wp = wp * w;
            j += 1;
        }
        let r = acc * tm.recip().powi(e) * T::TWO;
        // point types keep `r` (`join` returns `self` for them)
        r.join(r * (-tol + T::ONE)).join(r * (T::ONE + tol))
    }

    /// Partial fractions in `τ = τ_m + Δz` (module docs; `poly` in `z`).
    fn integrate_fractions<N: FieldNum<T>>(&self, poly: &[N; NC], deg: usize, w: N, tm: N) -> N {
        let zero = N::constant(T::ZERO);
        let e = 2 * self.m as usize + 1;
        let dw = w * self.delta;
        let tau0 = tm - dw;
        let tau1 = tm + dw;
        // poly(z) = Σ_j a_j ((τ − τ_m)/Δ)^j = Σ_i c_i τ^i
        let mut ntm = [zero; NC]; // (−τ_m)^k
        ntm[0] = N::constant(T::ONE);
        let mut k = 1;
        while k < NC {
            ntm[k] = ntm[k - 1] * (-tm);
            k += 1;
        }
        let mut c = [zero; NC];
        let inv_d = T::ONE / self.delta;
        let mut j = 0usize;
        let mut dpow = T::ONE; // Δ^{-j}
        while j <= deg {
            let aj = poly[j] * dpow;
            let mut i = 0usize;
            while i <= j {
                c[i] = c[i] + aj * ntm[j - i] * T::from_f64(binom(j as u32, i as u32));
                i += 1;
            }
            dpow = dpow * inv_d;
            j += 1;
        }
        let mut acc = zero;
        let r0 = tau0.recip();
        let r1 = tau1.recip();
        let mut i = 0usize;
        while i <= deg {
            let pw = e as i32 - 1 - i as i32; // ∫τ^{i−e} = τ^{−pw}/(−pw)
            if pw == 0 {
                acc = acc + c[i] * (tau1 * r0).ln();
            } else if pw > 0 {
                // both powers from one `powi` call (one inlined copy)
                let rr = [r0, r1];
                let mut pp = [zero; 2];
                let mut q = 0;
                while q < 2 {
                    pp[q] = rr[q].powi(pw);
                    q += 1;
                }
                acc = acc + c[i] * (pp[1] - pp[0]) / T::from_f64(-f64::from(pw));
            }
            i += 1;
        }
        acc / self.delta
    }

    /// The Cauchy (degree 3) density at axial coordinate `xc` (from the
    /// midpoint) and squared line distance `d2`.
    fn cauchy<N: FieldNum<T>>(&self, xc: N, d2: N) -> N {
        let s2 = self.sigma * self.sigma;
        let a = s2 * self.delta * self.delta + T::ONE;
        let b = -(xc * T::TWO) + T::TWO * s2 * self.tc * self.delta;
        let tau_x = xc * self.delta + self.tc;
        let e2 = (tau_x.sqr() * s2 + d2 * a) / (a * a);
        let vc = b / (T::TWO * a);
        let v0 = vc - self.half;
        let v1 = vc + self.half;
        let tau_v = -(vc * self.delta) + self.tc;
        let r0 = (v0.sqr() + e2).sqrt();
        let r1 = (v1.sqr() + e2).sqrt();
        let dv2 = (v1 - v0) * (v1 + v0);
        // [−1/r]
        let k1 = dv2 / (r0 * r1 * (r0 + r1));
        // [v/(e² r)] and [asinh(v/e)]
        let (e0, e1) = (v0.enclosure(), v1.enclosure());
        let same_pos = e0.lo() >= T::ZERO;
        let same_neg = e1.hi() <= T::ZERO;
        let across = e0.hi() < T::ZERO && e1.lo() > T::ZERO;
        // The case (the first that holds), or all of them joined when none
        // is certain; each formula is written once and computed only when
        // needed (a GPU driver inlines every call site).
        let case_pos = same_pos;
        let case_neg = !same_pos && same_neg;
        let case_across = !same_pos && !same_neg && across;
        let mixed = !case_pos && !case_neg && !case_across;
        let zero = N::constant(T::ZERO);
        let stable_k0 = if case_across {
            zero
        } else {
            dv2 / (r0 * r1 * (v1 * r0 + v0 * r1))
        };
        let direct_k0 = if case_across || mixed {
            (v1 / r1 - v0 / r0) / e2
        } else {
            zero
        };
        let pos_as = if case_pos || mixed {
            ((v1 + r1) / (v0 + r0)).ln()
        } else {
            zero
        };
        let neg_as = if case_neg || mixed {
            ((r0 - v0) / (r1 - v1)).ln()
        } else {
            zero
        };
        let across_as = if case_across || mixed {
            ((v1 + r1) * (r0 - v0) / e2).ln()
        } else {
            zero
        };
        let (k0, ash) = if case_pos {
            (stable_k0, pos_as)
        } else if case_neg {
            (stable_k0, neg_as)
        } else if case_across {
            (direct_k0, across_as)
        } else {
            (
                stable_k0.join(direct_k0),
                pos_as.join(neg_as).join(across_as),
            )
        };
        let k2 = ash - k0 * e2;
        let integral =
            k2 * (self.delta * self.delta) + k1 * tau_v * (T::TWO * self.delta) + k0 * tau_v.sqr();
        integral * self.scale / (a * a.sqrt())
    }

    /// The density and its gradient in closed form, in plain floats
    /// (compact kernel: differentiated under the integral, see the module
    /// docs; Cauchy: forward-mode differentiation of the closed form).
    pub fn density_gradient(&self, p: [T; 3]) -> (T, [T; 3]) {
        if self.m == 0 {
            let f = self.density(p.map(Plain)).0;
            let mut g = [T::ZERO; 3];
            let mut k = 0;
            while k < 3 {
                let mut q = p.map(|v| boundtrace_inclusion::Jet::constant(v));
                q[k] = boundtrace_inclusion::Jet::variable(p[k]);
                g[k] = self.density(q).d1;
                k += 1;
            }
            return (f, g);
        }
        let g = self.gradient_generic(p.map(Plain));
        (self.density(p.map(Plain)).0, [g[0].0, g[1].0, g[2].0])
    }

    /// The closed-form gradient of the compact density in any number type
    /// (`[0; 3]` for the Cauchy kernel, which has no closed form here).
    pub fn gradient_generic<N: FieldNum<T>>(&self, p: [N; 3]) -> [N; 3] {
        let zero = N::constant(T::ZERO);
        if self.m == 0 {
            return [zero; 3];
        }
        let (x, d2) = self.seg.axial(p);
        let xc = x - self.half;
        let (poly, y0, y1) = match self.clip(xc, d2) {
            Ok(c) => c,
            Err(z) => return [z; 3],
        };
        // ∇f = −2m·scale·[(p − q(y_m))·J0 − u·J1], J0 = ∫P^{m−1}/τ^e,
        // J1 = ∫(y − y_m)P^{m−1}/τ^e
        // (one `integrate` call in a loop: one inlined copy on a GPU)
        let mut jj = [zero; 2];
        let mut r = 0;
        while r < 2 {
            jj[r] = self.integrate(&poly, self.m - 1, r as u32, y0, y1);
            r += 1;
        }
        let [j0, j1] = jj;
        let ym = (y0 + y1) * T::HALF;
        let mid = self.seg.point_at(self.half);
        let u = self.seg.axis();
        let k = self.scale * T::from_f64(-2.0 * f64::from(self.m));
        [
            ((p[0] - mid[0] - ym * u[0]) * j0 - j1 * u[0]) * k,
            ((p[1] - mid[1] - ym * u[1]) * j0 - j1 * u[1]) * k,
            ((p[2] - mid[2] - ym * u[2]) * j0 - j1 * u[2]) * k,
        ]
    }

    /// The second derivative of the compact density along the direction
    /// `d`, `∂²f(p + t·d)/∂t²` at `t = 0`, in closed form and any number type
    /// (`None` for the Cauchy kernel and for degree 2, whose density is only
    /// `C¹`). Differentiating twice under the integral (the boundary terms
    /// vanish for `m ≥ 2`, `P^{m−1} = 0` at a clipped end):
    /// `f'' = 1/(Nσ^{2m}) ∫ [4m(m−1)P^{m−2}((p − q)·d)² − 2m|d|²P^{m−1}]/τ^e`,
    /// with `(p − q(y))·d = (p − q(y_m))·d − z·(u·d)`.
    pub fn second_derivative_generic<N: FieldNum<T>>(&self, p: [N; 3], d: [T; 3]) -> Option<N> {
        if self.has_second_derivative() {
            Some(self.second_derivative_closed_form(p, d))
        } else {
            None
        }
    }

    /// Whether [`second_derivative_generic`](Self::second_derivative_generic)
    /// has a closed form (a compact kernel of degree ≥ 4).
    #[inline]
    pub fn has_second_derivative(&self) -> bool {
        self.m >= 2
    }

    /// [`second_derivative_generic`](Self::second_derivative_generic)
    /// without the `Option` (a GPU shader's form): the closed form where
    /// [`has_second_derivative`](Self::has_second_derivative), a NaN
    /// constant otherwise.
    pub fn second_derivative_closed_form<N: FieldNum<T>>(&self, p: [N; 3], d: [T; 3]) -> N {
        if self.m < 2 {
            return N::constant(T::nan());
        }
        let (x, d2) = self.seg.axial(p);
        let xc = x - self.half;
        let (poly, y0, y1) = match self.clip(xc, d2) {
            Ok(c) => c,
            Err(z) => return z,
        };
        // `∫P^{m−2}z^r/τ^e` for r = 0, 1, 2 and `∫P^{m−1}/τ^e`, from one
        // `integrate` call in a loop (one inlined copy on a GPU)
        let mut ii = [N::constant(T::ZERO); 4];
        let mut r = 0;
        while r < 4 {
            let (pw, zp) = if r < 3 {
                (self.m - 2, r as u32)
            } else {
                (self.m - 1, 0)
            };
            ii[r] = self.integrate(&poly, pw, zp, y0, y1);
            r += 1;
        }
        let [i0, i1, i2, j] = ii;
        let ym = (y0 + y1) * T::HALF;
        let mid = self.seg.point_at(self.half);
        let u = self.seg.axis();
        let ud = u[0] * d[0] + u[1] * d[1] + u[2] * d[2];
        let dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        let w0 = (p[0] - mid[0] - ym * u[0]) * d[0]
            + (p[1] - mid[1] - ym * u[1]) * d[1]
            + (p[2] - mid[2] - ym * u[2]) * d[2];
        let mf = f64::from(self.m);
        let sq = w0.sqr() * i0 - w0 * i1 * (T::TWO * ud) + i2 * (ud * ud);
        (sq * T::from_f64(4.0 * mf * (mf - 1.0)) - j * (T::from_f64(2.0 * mf) * dd)) * self.scale
    }

    /// A quadratic Taylor bound of the field `iso − f` along `ray` on
    /// `[t0, t1]` (forward-inclusion paper §6.1): point enclosures of `f` and
    /// `f'` at `t0` and an interval enclosure of `f''` on the whole interval,
    /// all in closed form (`None` where
    /// [`second_derivative_generic`](Self::second_derivative_generic) is).
    pub fn field_taylor_quadratic(
        &self,
        ray: &Ray<T>,
        t0: T,
        t1: T,
    ) -> Option<ForwardQuadratic<T>> {
        let (f0, d1, d2) = self.taylor_parts(ray, t0, t1)?;
        let h = (Interval::point(t1) - Interval::point(t0))
            .lo()
            .max(T::ZERO);
        Some(ForwardQuadratic::taylor(
            Interval::point(self.iso) - f0,
            -d1,
            -d2,
            h,
        ))
    }

    /// `(f(t0), f'(t0), f''([t0, t1]))` of the density as enclosures.
    fn taylor_parts(
        &self,
        ray: &Ray<T>,
        t0: T,
        t1: T,
    ) -> Option<(Interval<T>, Interval<T>, Interval<T>)> {
        let d2 = self.second_derivative_generic(ray.at::<Interval<T>>(t0, t1), ray.dir)?;
        let p0 = ray.at::<Interval<T>>(t0, t0);
        let f0: Interval<T> = self.density(p0);
        let g = self.gradient_generic(p0);
        let d = ray.dir;
        let d1 = g[0] * d[0] + g[1] * d[1] + g[2] * d[2];
        Some((f0, d1, d2))
    }

    /// The normalization `g(f)` of Part III eq. 1.3 (compact) / 1.4
    /// (Cauchy): the squared homothetic distance to an infinite line of
    /// constant radius whose field is `f`. `g(iso) = 1`, decreasing.
    pub fn g<N: FieldNum<T>>(&self, f: N) -> N {
        let s2 = self.sigma * self.sigma;
        if self.m == 0 {
            f.recip() * ((T::ONE + s2) * self.iso) - s2
        } else {
            let expo = T::TWO / T::from_f64(f64::from(2 * self.m + 1));
            let r = (f / self.iso).max(N::constant(T::ZERO)).powf(expo);
            (-(r * (T::ONE - T::ONE / s2)) + T::ONE) * s2
        }
    }

    /// The normalized field `g(f(p)) − 1` of this primitive alone (Part III
    /// eq. 1.5): positive outside, zero on the surface.
    pub fn normalized<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        self.g(self.density(p)) - T::ONE
    }

    /// The support of the primitive as a sphere-cone: radii scaled by `σ`
    /// (compact: exactly where the density is non-zero, thesis Fig. 1.6),
    /// or, for the Cauchy kernel, by the clipping scale
    /// [`cauchy_clip_scale`](Self::cauchy_clip_scale)`(eps)` outside of
    /// which the density is `< eps` (Part III §1.5). `eps` is ignored for
    /// compact kernels.
    pub fn support(&self, eps: T) -> SphereCone<T> {
        if self.m == 0 {
            self.seg.sphere_cone(self.cauchy_clip_scale(eps))
        } else {
            self.seg.sphere_cone(self.sigma)
        }
    }

    /// The scale `S` such that the Cauchy density is `< eps` wherever
    /// `h_S(p) > S` (outside the sphere-cone of radii `S·r`). Derivation:
    /// there every skeleton point has `h ≥ S`, so
    /// `f ≤ k(S)/N · ∫₀ᴸ ds/τ = k(S)/N · Λ`, `Λ = ln(r_b/r_a)/Δ` (`L/r` for
    /// constant radius); solving `k(S)Λ/N = eps` for `k(S) =
    /// (1 + S²/σ²)^{−3/2}` gives `S = σ·√((Λ/(N·eps))^{2/3} − 1)` (`0` when
    /// the bracket is negative). Returns `σ` for compact kernels and `+∞`
    /// for `eps ≤ 0` or NaN.
    pub fn cauchy_clip_scale(&self, eps: T) -> T {
        if self.m != 0 {
            return self.sigma;
        }
        if !(eps > T::ZERO) {
            return T::INFINITY;
        }
        let ra = self.seg.ra().as_f64();
        let rb = self.seg.rb().as_f64();
        let l = self.seg.length().as_f64();
        let lam = if (rb - ra).abs() <= 1e-12 * ra {
            l / ra.min(rb)
        } else {
            (rb / ra).ln() / ((rb - ra) / l)
        };
        let q = (lam * self.inv_norm.as_f64() / eps.as_f64()).powf(2.0 / 3.0) - 1.0;
        let s = self.sigma.as_f64() * q.max(0.0).sqrt();
        T::from_f64(s * (1.0 + 1e-9) + 1e-300)
    }

    /// A directional Lipschitz bound (Part III ch. 2 §2.1.1): an upper
    /// bound of `|d f(o + t·d)/dt|` for `t ∈ [t0, t1]` (see the module
    /// docs), `+∞` for invalid input.
    pub fn directional_lipschitz(&self, ray: &Ray<T>, t0: T, t1: T) -> T {
        let iv = |v: T| Interval::point(v);
        let (s0, s1) = if self.m == 0 {
            (T::ZERO, self.seg.length())
        } else {
            // skeleton points whose support ball can reach the ray segment:
            // |s − x(p)| ≤ σ τ_max for some p on it
            let tmax = self.seg.ra().max(self.seg.rb());
            let x_at = |t: T| -> Interval<T> {
                let p = ray.at::<Interval<T>>(t, t);
                self.seg.axial(p).0
            };
            let (xa, xb) = (x_at(t0), x_at(t1));
            let reach = (iv(self.sigma) * iv(tmax)).hi();
            let lo = (xa.min(xb) - iv(reach)).lo().max(T::ZERO);
            let hi = (xa.max(xb) + iv(reach)).hi().min(self.seg.length());
            if !(lo <= hi) {
                return T::ZERO;
            }
            (lo, hi)
        };
        let tau = |s: T| iv(self.seg.ra()) + iv(self.seg.radius_slope()) * iv(s);
        let integral = (iv(s1) - iv(s0)) / (tau(s0) * tau(s1));
        let kp = self.kprime_bound(ray, t0, t1);
        if kp == T::ZERO {
            return T::ZERO;
        }
        let l = iv(self.inv_norm) * iv(kp) * iv(ray.speed()) * integral;
        let r = l.hi();
        if r.is_nan() { T::INFINITY } else { r }
    }

    /// An upper bound of `|k'(h)|` over the homothetic distances `h ≥ h_S(p)`
    /// of the points `p` of the ray segment: `max |k'|` when the segment can
    /// come closer than the maximiser `h*`, else `|k'(h_min)|` (`|k'|`
    /// decreases beyond `h*`), `0` beyond a compact support. `h_min` is a
    /// lower bound of `h_S` on the ray segment from interval arithmetic.
    fn kprime_bound(&self, ray: &Ray<T>, t0: T, t1: T) -> T {
        let hmin2: Interval<T> = self.seg.homothetic_sq(ray.at(t0, t1));
        let h2 = hmin2.lo().as_f64();
        if !(h2 > 0.0) {
            return self.kprime_max;
        }
        let h = h2.sqrt() * (1.0 - 1e-12);
        let sf = self.sigma.as_f64();
        // Powers by products and one square root: no `powf` in `f64`,
        // which a GPU has no instruction for (`(1 + u)^{−5/2}` to a few
        // ulps, far inside the `1e-9` margin below).
        let (hstar, k) = if self.m == 0 {
            let u = h * h / (sf * sf);
            let v = 1.0 + u;
            (sf * 0.5, 3.0 * h / (sf * sf) / (v * v * v.sqrt()))
        } else {
            if h >= sf {
                return T::ZERO;
            }
            let mf = f64::from(self.m);
            let u = h * h / (sf * sf);
            // (1 − u)^{m−1}
            let mut pw = 1.0;
            let mut i = 1;
            while i < self.m {
                pw *= 1.0 - u;
                i += 1;
            }
            (sf / (2.0 * mf - 1.0).sqrt(), 2.0 * mf * h / (sf * sf) * pw)
        };
        if h <= hstar {
            return self.kprime_max;
        }
        let k = T::from_f64(k * (1.0 + 1e-9)).next_up();
        if k.is_finite() {
            k.min(self.kprime_max)
        } else {
            self.kprime_max
        }
    }

    /// A sound enclosure of the density's derivative along the ray on
    /// `[t0, t1]`: the closed-form gradient in interval arithmetic (compact
    /// kernel), intersected with `±`[`directional_lipschitz`](Self::directional_lipschitz).
    pub fn derivative_range(&self, ray: &Ray<T>, t0: T, t1: T) -> Interval<T> {
        let l = self.directional_lipschitz(ray, t0, t1);
        let lip = Interval::new(-l, l);
        if self.m == 0 {
            return lip;
        }
        let p = ray.at::<Interval<T>>(t0, t1);
        let g = self.gradient_generic(p);
        let d = ray.dir;
        let dd = g[0] * d[0] + g[1] * d[1] + g[2] * d[2];
        let r = dd.intersection(lip);
        if r.is_empty() { lip } else { r }
    }

    /// A sound enclosure of the density on the ray interval `[t0, t1]`
    /// (Part III ch. 2 §2.1): end-point values, monotone intervals detected
    /// from the sign of a sound derivative enclosure on the whole interval,
    /// and the two Lipschitz lines (Fig. 2.2 right) otherwise.
    pub fn density_range(&self, ray: &Ray<T>, t0: T, t1: T) -> Interval<T> {
        // both ends from one `density` call (one inlined copy on a GPU)
        let ts = [t0, t1];
        let mut fs = [Interval::point(T::ZERO); 2];
        let mut k = 0;
        while k < 2 {
            fs[k] = self.density(ray.at(ts[k], ts[k]));
            k += 1;
        }
        let [f0, f1] = fs;
        let d = self.derivative_range(ray, t0, t1);
        let h = Interval::point(t1) - Interval::point(t0);
        let zero = Interval::point(T::ZERO);
        let r = if d.lo() >= T::ZERO {
            Interval::new(f0.lo(), f1.hi())
        } else if d.hi() <= T::ZERO {
            Interval::new(f1.lo(), f0.hi())
        } else {
            // f ≤ f0 + d₊(t − t0) and f ≤ f1 + |d₋|(t1 − t): the two lines
            // meet at (f0|d₋| + f1 d₊ + d₊|d₋| h)/(d₊ + |d₋|); likewise below.
            let (dm, dp) = (Interval::point(-d.lo()), Interval::point(d.hi()));
            let span = dp + dm;
            let up = (f0 * dm + f1 * dp + dp * dm * h) / span;
            let lo = (f0 * dp + f1 * dm - dp * dm * h) / span;
            Interval::new(lo.lo(), up.hi())
        };
        let r = r.hull(f0).hull(f1);
        Interval::new(r.lo().max(zero.lo()), r.hi())
    }

    /// A sound enclosure of the field `iso − f` on `[t0, t1]` (from
    /// [`density_range`](Self::density_range)).
    pub fn field_range(&self, ray: &Ray<T>, t0: T, t1: T) -> Interval<T> {
        Interval::point(self.iso) - self.density_range(ray, t0, t1)
    }

    /// The thesis' per-primitive range (Part III ch. 2 §2.1): monotony
    /// decided from the derivative signs at the two end-points only, the
    /// lower end `min(f(t0), f(t1))` on ambiguous intervals.
    ///
    /// # Warning
    ///
    /// Sound only if the density is unimodal along the ray (increasing then
    /// decreasing), which the thesis observes but which is not proven for
    /// varying radii; prefer [`density_range`](Self::density_range).
    pub fn density_range_unimodal(&self, ray: &Ray<T>, t0: T, t1: T) -> Interval<T> {
        let f0: Interval<T> = self.density(ray.at(t0, t0));
        let f1: Interval<T> = self.density(ray.at(t1, t1));
        let dir = |t: T| {
            let g = self.gradient_generic(ray.at::<Interval<T>>(t, t));
            g[0] * ray.dir[0] + g[1] * ray.dir[1] + g[2] * ray.dir[2]
        };
        if self.m != 0 {
            // unimodal: f'(t1) > 0 ⇒ increasing on [t0, t1]; f'(t0) < 0 ⇒
            // decreasing (a zero derivative may be outside the support)
            if dir(t1).lo() > T::ZERO {
                return Interval::new(f0.lo(), f1.hi());
            }
            if dir(t0).hi() < T::ZERO {
                return Interval::new(f1.lo(), f0.hi());
            }
        }
        let full = self.density_range(ray, t0, t1);
        Interval::new(f0.lo().min(f1.lo()).max(full.lo()), full.hi())
    }
}

/// `poly^m` into `out`; returns the degree `2m`.
fn power<T: Real, N: FieldNum<T>>(poly: &[N; 3], m: u32, out: &mut [N; NC]) -> usize {
    let zero = N::constant(T::ZERO);
    *out = [zero; NC];
    out[0] = N::constant(T::ONE);
    let mut deg = 0usize;
    let mut k = 0;
    while k < m {
        let mut next = [zero; NC];
        let mut i = 0;
        while i <= deg {
            let mut j = 0;
            while j < 3 {
                if i + j < NC {
                    next[i + j] = next[i + j] + out[i] * poly[j];
                }
                j += 1;
            }
            i += 1;
        }
        *out = next;
        deg += 2;
        k += 1;
    }
    deg
}

/// `iso − f(p)`: positive outside. Taylor linear bounds come from the
/// per-primitive derivative enclosure ([`ScalisSegment::derivative_range`]).
impl<T: Real> Field<T> for ScalisSegment<T> {
    fn eval<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        -self.density(p) + self.iso
    }

    fn taylor_linear(&self, ray: &Ray<T>, t0: T, t1: T) -> Option<ForwardLinear<T>> {
        let f0: Interval<T> = self.eval(ray.at(t0, t0));
        let d = self.derivative_range(ray, t0, t1);
        let h = (Interval::point(t1) - Interval::point(t0)).lo();
        Some(ForwardLinear::taylor(f0, -d, h.max(T::ZERO)))
    }
    fn taylor_quadratic(&self, ray: &Ray<T>, t0: T, t1: T) -> Option<ForwardQuadratic<T>> {
        self.field_taylor_quadratic(ray, t0, t1)
    }
}

/// Whether the box enclosure `e` of the query point(s) certainly misses
/// the axis-aligned box `[lo, hi]` (NaN or empty enclosures never miss).
#[inline]
fn box_misses<T: Real>(e: &[Interval<T>; 3], lo: &[T; 3], hi: &[T; 3]) -> bool {
    let mut k = 0;
    while k < 3 {
        if !e[k].is_empty() && (e[k].hi() < lo[k] || e[k].lo() > hi[k]) {
            return true;
        }
        k += 1;
    }
    false
}

/// The enclosures of a point's coordinates.
#[inline]
fn enclose3<T: Real, N: FieldNum<T>>(p: &[N; 3]) -> [Interval<T>; 3] {
    [p[0].enclosure(), p[1].enclosure(), p[2].enclosure()]
}

impl<T: Real> ScalisSegment<T> {
    /// Whether the support is compact (a compact kernel: a
    /// [`support_box`](Self::support_box)); `false` for the Cauchy kernel.
    #[inline]
    pub fn has_compact_support(&self) -> bool {
        self.m != 0
    }

    /// The axis-aligned box `[lo, hi]` outside of which the density is
    /// exactly `0` (compact kernels: the segment's box grown by
    /// `σ·max(r_a, r_b)`, rounded outward); `None` for the Cauchy kernel
    /// (infinite support).
    #[inline]
    pub fn support_box(&self) -> Option<[[T; 3]; 2]> {
        if self.m == 0 {
            None
        } else {
            Some(self.support_box)
        }
    }

    /// Whether the enclosure `e` of the query point(s) certainly misses the
    /// compact support (so the density, its gradient and its second
    /// derivative are exactly `0` there); always `false` for Cauchy.
    #[inline]
    fn misses(&self, e: &[Interval<T>; 3]) -> bool {
        self.m != 0 && box_misses(e, &self.support_box[0], &self.support_box[1])
    }

    /// A global Lipschitz bound of the density (thesis Part III ch. 2
    /// §2.1.1 over the whole segment): `|∇f| ≤ 1/N · max|k'| · ∫₀ᴸ ds/τ²
    /// = max|k'|·L / (N·r_a·r_b)` (since `|∇h| = 1/τ`), rounded up.
    pub fn lipschitz_bound(&self) -> T {
        let iv = Interval::point;
        let l = iv(self.inv_norm) * self.kprime_max * self.seg.length()
            / (iv(self.seg.ra()) * self.seg.rb())
            * T::from_f64(1.0 + 1e-6);
        l.hi()
    }
}

/// A skeleton of SCALIS segments blended by summation, as the field
/// `iso − Σ fᵢ(p)` (all segments share the kernel and iso-value of the
/// first one's normalization; see [`ScalisSegment`]).
///
/// `S` is any storage of segments: a fixed array `[ScalisSegment<T>; K]`, a
/// slice or a `Vec` (like [`Blobs`](crate::blob::Blobs)). With a compact
/// kernel, evaluation and every bound **skip the segments whose support
/// box** ([`ScalisSegment::support_box`]) the query's enclosure
/// ([`FieldNum::enclosure`] of the point coordinates, or of the ray
/// segment for the Taylor bounds) cannot reach: their density is exactly
/// `0` there, so the result is the same (a constant `0` term) and large
/// skeletons cost what their nearby segments cost.
///
/// ```
/// use boundtrace_fields::homothetic::{Segment, SegmentKernel};
/// use boundtrace_fields::scalis::{ScalisSegment, ScalisSkeleton};
/// use boundtrace_inclusion::{Field, FieldNum};
///
/// let k = SegmentKernel::compact_polynomial(6, 2.0).unwrap();
/// let seg = |x: f64| {
///     let s = Segment::new([x, 0.0, 0.0], 0.3, [x + 1.0, 0.0, 0.0], 0.3).unwrap();
///     ScalisSegment::new(s, k, 1.0).unwrap()
/// };
/// let sk = ScalisSkeleton::new([seg(0.0), seg(1.0), seg(10.0)]).unwrap();
/// assert!(sk.eval([1.0f64, 0.0, 0.0]) < 0.0); // inside, near the joint
/// assert!(sk.eval([5.0f64, 0.0, 0.0]) > 0.0); // between the pieces
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScalisSkeleton<T, S> {
    segments: S,
    iso: T,
}

impl<T: Real, S: AsRef<[ScalisSegment<T>]>> ScalisSkeleton<T, S> {
    /// A skeleton from its segments.
    ///
    /// # Errors
    ///
    /// [`FieldError::InvalidParameter`] when there is no segment or the
    /// segments differ in kernel or iso-value.
    pub fn new(segments: S) -> Result<Self, FieldError> {
        let segs = segments.as_ref();
        let Some(first) = segs.first() else {
            return Err(FieldError::InvalidParameter {
                name: "segments",
                reason: "a skeleton needs at least one segment",
            });
        };
        if segs
            .iter()
            .any(|s| s.kernel() != first.kernel() || s.iso != first.iso)
        {
            return Err(FieldError::InvalidParameter {
                name: "segments",
                reason: "all segments of a skeleton must share kernel and iso-value",
            });
        }
        let iso = first.iso;
        Ok(Self { segments, iso })
    }

    /// A skeleton of `segments` with the iso-value `iso`, unchecked: the
    /// GPU shader's form, which cannot build [`new`](Self::new)'s errors.
    /// The caller vouches that `segments` is what `new` accepts (non-empty,
    /// one kernel and iso-value, checked on the host before upload) and
    /// that `iso` is their iso-value; otherwise results are meaningless
    /// (never undefined behaviour).
    #[inline]
    pub fn new_unchecked(segments: S, iso: T) -> Self {
        Self { segments, iso }
    }

    /// The segments.
    #[inline]
    pub fn segments(&self) -> &[ScalisSegment<T>] {
        self.segments.as_ref()
    }

    /// The shared iso-value.
    #[inline]
    pub fn iso(&self) -> T {
        self.iso
    }

    /// `Σ fᵢ(p)` (segments whose support `p` cannot reach are skipped).
    pub fn density<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        let e = enclose3(&p);
        // `0` carrying the query's validity: a bound where every primitive is
        // culled must not claim validity beyond the interval the culling
        // was decided on (a constant's is infinite).
        let mut acc = crate::zero_like::<T, N>(&p[0]);
        // an index loop (rust-gpu cannot iterate a storage buffer's slice)
        let segs = self.segments.as_ref();
        let mut i = 0;
        while i < segs.len() {
            let s = &segs[i];
            i += 1;
            if s.misses(&e) {
                continue;
            }
            acc = acc + s.density(p);
        }
        acc
    }

    /// Enclosure of the ray segment `o + [t0, t1]·d`.
    fn ray_box(ray: &Ray<T>, t0: T, t1: T) -> [Interval<T>; 3] {
        ray.at::<Interval<T>>(t0, t1)
    }

    /// The sum of the per-primitive ranges (sound enclosure of `Σ fᵢ` on
    /// `[t0, t1]`).
    pub fn density_range(&self, ray: &Ray<T>, t0: T, t1: T) -> Interval<T> {
        let e = Self::ray_box(ray, t0, t1);
        let mut acc = Interval::point(T::ZERO);
        for s in self.segments.as_ref() {
            if s.misses(&e) {
                continue;
            }
            acc = acc + s.density_range(ray, t0, t1);
        }
        acc
    }

    /// The sum of the per-primitive directional Lipschitz bounds.
    pub fn directional_lipschitz(&self, ray: &Ray<T>, t0: T, t1: T) -> T {
        let e = Self::ray_box(ray, t0, t1);
        let mut acc = Interval::point(T::ZERO);
        for s in self.segments.as_ref() {
            if s.misses(&e) {
                continue;
            }
            acc = acc + Interval::point(s.directional_lipschitz(ray, t0, t1));
        }
        acc.hi()
    }
}

impl<T: Real, S: AsRef<[ScalisSegment<T>]>> Field<T> for ScalisSkeleton<T, S> {
    fn eval<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        -self.density(p) + self.iso
    }

    /// `Σ` [`ScalisSegment::lipschitz_bound`] (rounded up): sound
    /// everywhere, loose for large skeletons (only the segments whose
    /// support contains a point shape its gradient).
    fn lipschitz(&self) -> Option<T> {
        let mut acc = Interval::point(T::ZERO);
        for s in self.segments.as_ref() {
            acc = acc + Interval::point(s.lipschitz_bound());
        }
        Some(acc.hi())
    }

    fn taylor_linear(&self, ray: &Ray<T>, t0: T, t1: T) -> Option<ForwardLinear<T>> {
        let e = Self::ray_box(ray, t0, t1);
        let p0 = ray.at::<Interval<T>>(t0, t0);
        let e0 = enclose3(&p0);
        let mut f0 = Interval::point(T::ZERO);
        let mut d = Interval::point(T::ZERO);
        for s in self.segments.as_ref() {
            if s.misses(&e) {
                continue;
            }
            if !s.misses(&e0) {
                f0 = f0 + s.density(p0);
            }
            d = d + s.derivative_range(ray, t0, t1);
        }
        let h = (Interval::point(t1) - Interval::point(t0)).lo();
        Some(ForwardLinear::taylor(
            Interval::point(self.iso) - f0,
            -d,
            h.max(T::ZERO),
        ))
    }

    fn taylor_quadratic(&self, ray: &Ray<T>, t0: T, t1: T) -> Option<ForwardQuadratic<T>> {
        let e = Self::ray_box(ray, t0, t1);
        let mut f0 = Interval::point(T::ZERO);
        let mut d1 = Interval::point(T::ZERO);
        let mut d2 = Interval::point(T::ZERO);
        for s in self.segments.as_ref() {
            if s.m < 2 {
                return None;
            }
            if s.misses(&e) {
                continue;
            }
            let (a, b, c) = s.taylor_parts(ray, t0, t1)?;
            f0 = f0 + a;
            d1 = d1 + b;
            d2 = d2 + c;
        }
        let h = (Interval::point(t1) - Interval::point(t0))
            .lo()
            .max(T::ZERO);
        Some(ForwardQuadratic::taylor(
            Interval::point(self.iso) - f0,
            -d1,
            -d2,
            h,
        ))
    }
}

/// The normalized field `g(Σ fᵢ) − 1` of a skeleton (Part III eq. 1.5): an
/// approximate squared homothetic distance to the surface minus one,
/// positive outside, with the same zero set as the skeleton's field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Normalized<T, S>(pub ScalisSkeleton<T, S>);

impl<T: Real, S: AsRef<[ScalisSegment<T>]>> Field<T> for Normalized<T, S> {
    fn eval<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        let f = self.0.density(p);
        match self.0.segments().first() {
            Some(s) => s.g(f) - T::ONE,
            None => f,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seg(ra: f64, rb: f64) -> Segment<f64> {
        Segment::new([0.0, 0.0, 0.0], ra, [3.0, 0.0, 0.0], rb).unwrap()
    }

    #[test]
    fn words_are_the_whole_f32_segment_and_the_kernel_round_trips() {
        // every field a 4-byte word: no padding, so the words are the bytes
        assert_eq!(
            core::mem::size_of::<ScalisSegment<f32>>(),
            4 * SCALIS_SEGMENT_WORDS
        );
        let k = SegmentKernel::compact_polynomial(6, 2.0f32).unwrap();
        let sg = Segment::new([0.5f32, -1.0, 2.0], 0.25, [3.0, 1.0, 2.5], 0.5).unwrap();
        let s = ScalisSegment::new(sg, k, 1.0).unwrap();
        assert_eq!(s.kernel(), k);
        let w = s.to_words();
        assert_eq!(w[0], 0.5f32.to_bits());
        assert_eq!(w[3], 0.25f32.to_bits());
        assert_eq!(w[13], KIND_COMPACT);
        assert_eq!(w[14], 6);
        assert_eq!(w[15], 1.0f32.to_bits());
        assert_eq!(w[16], 3); // m
        assert_eq!(w[17], 2.0f32.to_bits()); // σ
        assert_eq!(w[SCALIS_SEGMENT_WORDS - 6], s.support_box[0][0].to_bits());
        assert_eq!(w[SCALIS_SEGMENT_WORDS - 1], s.support_box[1][2].to_bits());
        let c = SegmentKernel::cauchy(3, 2.0f32).unwrap();
        let sc = ScalisSegment::new(sg, c, 1.0).unwrap();
        assert_eq!(sc.kernel(), c);
        assert_eq!(sc.to_words()[13], KIND_CAUCHY);
    }

    #[test]
    fn validation() {
        let k6 = SegmentKernel::compact_polynomial(6, 2.0).unwrap();
        assert!(ScalisSegment::new(seg(0.5, 0.5), k6, 1.0).is_ok());
        assert!(ScalisSegment::new(seg(0.5, 0.5), k6, -1.0).is_err());
        // σ·|rb − ra| = 2·2 ≥ L = 3
        assert!(ScalisSegment::new(seg(0.5, 2.5), k6, 1.0).is_err());
        let k10 = SegmentKernel::compact_polynomial(10, 2.0).unwrap();
        assert!(ScalisSegment::new(seg(0.5, 0.5), k10, 1.0).is_err());
        let c5 = SegmentKernel::cauchy(5, 1.0).unwrap();
        assert!(ScalisSegment::new(seg(0.5, 0.5), c5, 1.0).is_err());
    }

    #[test]
    fn density_is_zero_outside_the_support_and_symmetric() {
        let k = SegmentKernel::compact_polynomial(6, 2.0).unwrap();
        let s = ScalisSegment::new(seg(0.5, 0.5), k, 1.0).unwrap();
        assert_eq!(s.density([1.5, 1.0 + 1e-9, 0.0]), 0.0);
        assert_eq!(s.density([-1.0 - 1e-9, 0.0, 0.0]), 0.0);
        let a: f64 = s.density([0.7, 0.3, 0.1]);
        let b: f64 = s.density([2.3, -0.1, 0.3]);
        assert!((a - b).abs() < 1e-13 && a > 0.0);
        // an interval at a point encloses the float value
        let i: Interval<f64> = s.density([0.7, 0.3, 0.1].map(Interval::point));
        assert!(i.contains(a));
    }

    #[test]
    fn g_inverts_the_line_field() {
        for k in [
            SegmentKernel::compact_polynomial(4, 1.5).unwrap(),
            SegmentKernel::cauchy(3, 1.0).unwrap(),
        ] {
            let s = ScalisSegment::new(seg(0.5, 0.5), k, 2.0).unwrap();
            let g1: f64 = s.g(2.0);
            assert!((g1 - 1.0).abs() < 1e-12);
            let (ga, gb): (f64, f64) = (s.g(1.0), s.g(3.0));
            assert!(ga > 1.0 && gb < 1.0);
        }
    }

    #[test]
    fn range_and_lipschitz_on_a_crossing_ray() {
        let k = SegmentKernel::compact_polynomial(6, 2.0).unwrap();
        let s = ScalisSegment::new(seg(0.4, 0.6), k, 1.0).unwrap();
        let ray = Ray::new([1.0, -3.0, 0.2], [0.0, 1.0, 0.0]);
        let r = s.density_range(&ray, 1.0, 5.0);
        let l = s.directional_lipschitz(&ray, 1.0, 5.0);
        let mut prev: Option<f64> = None;
        for i in 0..=400 {
            let t = 1.0 + 4.0 * f64::from(i) / 400.0;
            let f: f64 = s.density(ray.at(t, t));
            assert!(r.contains(f), "{r:?} misses {f}");
            if let Some(p) = prev {
                assert!((f - p).abs() <= l * 0.01 + 1e-12);
            }
            prev = Some(f);
        }
        assert!(
            s.field_range(&ray, 1.0, 5.0)
                .contains(1.0 - s.density([1.0, 0.0, 0.2]))
        );
    }

    /// Culling by support boxes leaves every value and bound unchanged:
    /// a skeleton with far-away segments gives the same results as the
    /// skeleton of the near ones, and the Lipschitz bound holds.
    #[test]
    fn culled_bounds_keep_the_window_validity() {
        let k = SegmentKernel::compact_polynomial(6, 2.0).unwrap();
        let seg = Segment::new([10.0, 0.0, 0.0], 0.3, [11.0, 0.0, 0.0], 0.3).unwrap();
        let sk = ScalisSkeleton::new([ScalisSegment::new(seg, k, 1.0).unwrap()]).unwrap();
        let ray = Ray::new([0.0; 3], [0.0, 1.0, 0.0]);
        let q: ForwardQuadratic<f64> = sk.eval(ray.at(0.0, 1.0));
        assert!(q.validity() <= 1.0, "{q:?}");
        let v: f64 = sk.eval(ray.at(0.5, 0.5));
        assert!(q.range().contains(v));
    }

    #[test]
    fn culling_keeps_values_and_bounds() {
        let k = SegmentKernel::compact_polynomial(6, 2.0).unwrap();
        let mk = |a: [f64; 3], b: [f64; 3], ra: f64, rb: f64| {
            ScalisSegment::new(Segment::new(a, ra, b, rb).unwrap(), k, 1.0).unwrap()
        };
        let near = [
            mk([0.0, 0.0, 0.0], [1.0, 0.2, 0.0], 0.3, 0.35),
            mk([1.0, 0.2, 0.0], [1.8, 1.0, 0.1], 0.35, 0.3),
        ];
        let far = mk([10.0, 0.0, 0.0], [11.0, 0.0, 0.0], 0.3, 0.3);
        let small = ScalisSkeleton::new(near).unwrap();
        let big = ScalisSkeleton::new([near[0], far, near[1], far]).unwrap();
        // the far segment's support box excludes the near region
        let [lo, _] = far.support_box().unwrap();
        assert!(lo[0] > 9.0 && lo[0] <= 10.0 - 0.6);
        let ray = Ray::new([-1.0, -0.7, 0.05], [1.0, 0.6, 0.0]);
        for i in 0..30 {
            let t0 = 0.1 * f64::from(i);
            let t1 = t0 + 0.3;
            let p: [f64; 3] = ray.at(t0, t0);
            assert_eq!(small.eval(p), big.eval(p));
            let iv: Interval<f64> = big.eval(ray.at(t0, t1));
            let iv_small: Interval<f64> = small.eval(ray.at(t0, t1));
            assert_eq!(iv, iv_small);
            let qb = big.taylor_quadratic(&ray, t0, t1).unwrap();
            let qs = small.taylor_quadratic(&ray, t0, t1).unwrap();
            assert_eq!(qb, qs);
            let lb = big.taylor_linear(&ray, t0, t1).unwrap();
            for j in 0..=8 {
                let tau = 0.3 * f64::from(j) / 8.0;
                let v: f64 = big.eval(ray.at(t0 + tau, t0 + tau));
                assert!(qb.bounds_at(tau).contains(v), "quadratic at {t0}+{tau}");
                assert!(lb.bounds_at(tau).contains(v), "linear at {t0}+{tau}");
            }
        }
        // the global Lipschitz bound holds between sampled points
        let l = big.lipschitz().unwrap();
        assert!(l > 0.0 && l.is_finite());
        let mut prev: Option<(f64, [f64; 3])> = None;
        for i in 0..=300 {
            let p: [f64; 3] = ray.at(f64::from(i) / 100.0, f64::from(i) / 100.0);
            let v: f64 = big.eval(p);
            if let Some((pv, pp)) = prev {
                let d = ((p[0] - pp[0]).powi(2) + (p[1] - pp[1]).powi(2) + (p[2] - pp[2]).powi(2))
                    .sqrt();
                assert!((v - pv).abs() <= l * d + 1e-12);
            }
            prev = Some((v, p));
        }
        assert!(ScalisSkeleton::<f64, [ScalisSegment<f64>; 0]>::new([]).is_err());
    }
}
