//! Binary blobtree operators on A-SDF operands: CSG, polynomial smooth and
//! **compact** smooth operators with their operator ranges `R_o`
//! (synchronized-tracing paper §4).
//!
//! Sign convention: `f > 0` outside, `f < 0` inside.
//!
//! - CSG (eqs. 6–7): `csg∪ = min(f₀, f₁)`, `csg∩ = max(f₀, f₁)`,
//!   `csg∖ = max(f₀, −f₁)`; range `R_o = [0, 0]`.
//! - Smooth (eqs. 8–11), with
//!   `d(f₀, f₁, β) = β/6 · max(1 − |f₀ − f₁|/β, 0)³`:
//!   `g∪ = csg∪ − d(f₀, f₁)`, `g∩ = csg∩ + d(f₀, f₁)`,
//!   `g∖ = csg∖ + d(f₀, −f₁)`; their operands interact at any field value,
//!   `R_o = (−∞, +∞)`.
//! - Compact (eq. 12): `G_op = ḡ_op` when both operands lie in
//!   `R_o = [r_o⁻, r_o⁺]`, `csg_op` otherwise, with (eq. 17)
//!   `ḡ∪(f₀, f₁) = g∪(f₀, f₁, b_r(g∪(f₀, f₁, β)))` and the transition
//!   (eq. 18) `b_r(x) = β max(1 − 6x/(6r_o − β), 0)`; for `∩` and `∖` the
//!   argument of `b_r` is `|g_op(f₀, f₁, β)|`. `r_o⁺ = r_o`;
//!   `r_o⁻ = −∞` for the union, `−r_o` for the intersection and difference.
//!   `G∖(f₀, f₁) = G∩(f₀, −f₁)` (the range is symmetric).
//!
//! # Continuity and the admissible `r_o`
//!
//! Eq. 18 needs `6r_o − β > 0`. Continuity of `G_op` on the boundary of
//! `R_o²` needs more. For the union at `f₀ = r_o` and `f₁ = r_o − u`
//! (`u ≥ 0`), `ḡ∪ = csg∪ = f₁` requires `b_r ≤ u`; for `u ≥ β` this reads
//! `u (7β − 6r_o) ≤ β²`, which must hold for every `u` (the union's range
//! is unbounded below): **`r_o ≥ 7β/6`**. For the intersection (and
//! difference) at `f₀ = −r_o`, `u = f₁ + r_o ≤ 2r_o` gives the condition
//! `β (4 + 3v − v²) ≤ 6 r_o` for `v = u/β ≤ 1`: **`r_o ≥ β`**. The
//! constructors enforce these (which imply `6r_o − β > 0`);
//! [`Operator::default_r_o`] gives `r_o = 1.25 β`. The unit and property
//! tests check continuity across the boundary.
//!
//! # Lipschitz factor
//!
//! CSG and smooth operators are convex combinations of the operand
//! gradients (`∂g∪/∂f₀ = 1 − h²/2`, `∂g∪/∂f₁ = h²/2`, `h = 1 − |f₀−f₁|/β`),
//! so they keep the operands' Lipschitz bound (factor 1). In the compact
//! blend, with `k = 6β/(6r_o − β)` the slope of `b_r` and `σ = s/b`,
//! `∂ḡ/∂f₀ + ∂ḡ/∂f₁ = 1 + k h²(1 + 2σ)/6 ≤ 1 + k/6`, both partials `≥ 0`:
//! the factor is **`6r_o / (6r_o − β)`** (the "field compression" of §8;
//! 7/6 for `r_o = 7β/6`, 15/13 ≈ 1.154 for the default `1.25 β`). A tree
//! is bounded by the product of the factors along a root–leaf path
//! ([`Operator::lipschitz_factor`]); the paper traces with 1.45.
//!
//! # Sound evaluation with bound types
//!
//! Whether an operand lies in `R_o` is decided with
//! [`FieldNum::enclosure`]: inside for every value → blend, outside for
//! every value → CSG, undecided → `csg.join(blend)`, which encloses both
//! (the operator takes one of the two values at each point). The blend is
//! finite for all finite operands, inside `R_o` or not.
//!
//! # Where NaN arises, and how it is avoided
//!
//! `b_r` itself divides by the constant `6r_o − β > 0`; a NaN can only come
//! from a NaN argument (e.g. `f₀ = f₁ = −∞` gives `|f₀ − f₁| = NaN`), and
//! it is filtered to `b = 0` as the paper says. The real trap is the second
//! evaluation `d(s, b) = b/6 (1 − s/b)₊³` with a **variable** `b` that reaches
//! `0` (on the outer part of `R_o`): `s/b` is `0/0` for points and
//! `[0, ∞]`/empty for bound types whose `b` contains 0. The code branches on
//! the enclosure of `b`: `b ≤ 0` (or NaN) → `d = 0`; `b > 0` → the formula;
//! undecided → `d ∈ [0, (b − s)₊/6]` (since `0 ≤ h ≤ 1` and
//! `d = (b − s)₊ h²/6`), built as `0.join((b − s)₊/6)`.
//!
//! # Missing operands
//!
//! In a pruned (sparse) evaluation an inactive operand is treated as
//! `+∞` (§4: "treating the missing operand as having an infinite value"):
//! see [`Operator::eval_partial`].

use crate::FieldError;
use boundtrace_ia_core::Real;
use boundtrace_inclusion::FieldNum;

/// The operator types (the 5-bit `nodeop` field, paper §7).
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum OperatorKind {
    /// `min(f₀, f₁)` (eq. 6).
    Union = 0,
    /// `max(f₀, f₁)` (eq. 7).
    Intersection = 1,
    /// `max(f₀, −f₁)` (eq. 7).
    Difference = 2,
    /// `g∪` (eqs. 8–9).
    SmoothUnion = 3,
    /// `g∩` (eq. 10).
    SmoothIntersection = 4,
    /// `g∖` (eq. 11).
    SmoothDifference = 5,
    /// `G∪` (eqs. 12, 17, 18).
    CompactUnion = 6,
    /// `G∩` (eqs. 12, 17, 18 with `|·|`).
    CompactIntersection = 7,
    /// `G∖` (eqs. 12, 17, 18 with `|·|`).
    CompactDifference = 8,
}

/// How an operator selects its operands outside its range (paper §4,
/// §7 `ignoreMod`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum OperatorClass {
    /// Union-like: `R_c = [r_n⁻, max(r_n⁺, r_o⁺)]` (eq. 13).
    UnionLike,
    /// Intersection-like: `R_c = [min(r_n⁻, r_o⁻), r_n⁺]` (eq. 14).
    IntersectionLike,
    /// Difference-like: eqs. 15–16 (the right operand's range is inverted).
    DifferenceLike,
}

impl OperatorKind {
    /// Every kind, in code order.
    pub const ALL: [OperatorKind; 9] = [
        OperatorKind::Union,
        OperatorKind::Intersection,
        OperatorKind::Difference,
        OperatorKind::SmoothUnion,
        OperatorKind::SmoothIntersection,
        OperatorKind::SmoothDifference,
        OperatorKind::CompactUnion,
        OperatorKind::CompactIntersection,
        OperatorKind::CompactDifference,
    ];

    /// The operator's class.
    pub const fn class(self) -> OperatorClass {
        match self {
            OperatorKind::Union | OperatorKind::SmoothUnion | OperatorKind::CompactUnion => {
                OperatorClass::UnionLike
            }
            OperatorKind::Intersection
            | OperatorKind::SmoothIntersection
            | OperatorKind::CompactIntersection => OperatorClass::IntersectionLike,
            OperatorKind::Difference
            | OperatorKind::SmoothDifference
            | OperatorKind::CompactDifference => OperatorClass::DifferenceLike,
        }
    }

    /// Number of 128-bit slots of the flat parameters: 0 for CSG, 1
    /// (`[β, r_o, 0, 0]`) otherwise.
    pub const fn param_vec4s(self) -> u32 {
        match self {
            OperatorKind::Union | OperatorKind::Intersection | OperatorKind::Difference => 0,
            _ => 1,
        }
    }

    /// The kind with code `x`, if any.
    pub fn from_u32(x: u32) -> Option<Self> {
        // A `match`, not an index into `ALL`: rust-gpu cannot take a
        // slice of a constant array.
        Some(match x {
            0 => OperatorKind::Union,
            1 => OperatorKind::Intersection,
            2 => OperatorKind::Difference,
            3 => OperatorKind::SmoothUnion,
            4 => OperatorKind::SmoothIntersection,
            5 => OperatorKind::SmoothDifference,
            6 => OperatorKind::CompactUnion,
            7 => OperatorKind::CompactIntersection,
            8 => OperatorKind::CompactDifference,
            _ => return None,
        })
    }

    /// Whether the kind is one of the compact operators `G_op`.
    pub const fn is_compact(self) -> bool {
        matches!(
            self,
            OperatorKind::CompactUnion
                | OperatorKind::CompactIntersection
                | OperatorKind::CompactDifference
        )
    }
}

/// A binary operator: its kind, blend parameter `β` and range parameter
/// `r_o` (both `0` where unused). Built by validated constructors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Operator<T> {
    kind: OperatorKind,
    beta: T,
    r_o: T,
}

fn invalid(name: &'static str, reason: &'static str) -> FieldError {
    FieldError::InvalidParameter { name, reason }
}

impl<T: Real> Operator<T> {
    fn csg(kind: OperatorKind) -> Self {
        Self {
            kind,
            beta: T::ZERO,
            r_o: T::ZERO,
        }
    }

    /// CSG union `min(f₀, f₁)` (eq. 6).
    pub fn union() -> Self {
        Self::csg(OperatorKind::Union)
    }

    /// CSG intersection `max(f₀, f₁)` (eq. 7).
    pub fn intersection() -> Self {
        Self::csg(OperatorKind::Intersection)
    }

    /// CSG difference `max(f₀, −f₁)` (eq. 7).
    pub fn difference() -> Self {
        Self::csg(OperatorKind::Difference)
    }

    fn smooth(kind: OperatorKind, beta: T) -> Result<Self, FieldError> {
        let beta = crate::error::positive("beta", beta)?;
        Ok(Self {
            kind,
            beta,
            r_o: T::ZERO,
        })
    }

    /// Smooth union `g∪` with blend range `β > 0` (eqs. 8–9).
    ///
    /// # Errors
    /// [`FieldError::InvalidParameter`] when `β` is NaN, infinite or ≤ 0.
    pub fn smooth_union(beta: T) -> Result<Self, FieldError> {
        Self::smooth(OperatorKind::SmoothUnion, beta)
    }

    /// Smooth intersection `g∩` (eq. 10).
    ///
    /// # Errors
    /// As [`smooth_union`](Self::smooth_union).
    pub fn smooth_intersection(beta: T) -> Result<Self, FieldError> {
        Self::smooth(OperatorKind::SmoothIntersection, beta)
    }

    /// Smooth difference `g∖` (eq. 11).
    ///
    /// # Errors
    /// As [`smooth_union`](Self::smooth_union).
    pub fn smooth_difference(beta: T) -> Result<Self, FieldError> {
        Self::smooth(OperatorKind::SmoothDifference, beta)
    }

    /// The default range parameter for a blend `β`: `r_o = 1.25 β`
    /// (continuous for every compact kind, Lipschitz factor 15/13).
    pub fn default_r_o(beta: T) -> T {
        beta * T::from_f64(1.25)
    }

    /// The smallest `r_o` for which the compact operator of `kind` is
    /// continuous: `7β/6` for the union, `β` for intersection and
    /// difference (module docs); `0` for the other kinds.
    pub fn min_r_o(kind: OperatorKind, beta: T) -> T {
        match kind {
            OperatorKind::CompactUnion => beta * T::from_f64(7.0) / T::from_f64(6.0),
            OperatorKind::CompactIntersection | OperatorKind::CompactDifference => beta,
            _ => T::ZERO,
        }
    }

    fn compact(kind: OperatorKind, beta: T, r_o: T) -> Result<Self, FieldError> {
        let beta = crate::error::positive("beta", beta)?;
        let r_o = crate::error::positive("r_o", r_o)?;
        let denom = T::from_f64(6.0) * r_o - beta;
        if denom.is_nan() || denom <= T::ZERO {
            return Err(invalid("r_o", "6·r_o − β must be > 0 (eq. 18)"));
        }
        // A relative tolerance of 2⁻²⁰ lets parameters rounded to f32 pass
        // (continuity then holds up to that rounding).
        if r_o < Self::min_r_o(kind, beta) * (T::ONE - T::from_f64(9.5367431640625e-7)) {
            return Err(invalid(
                "r_o",
                "too small for β: continuity needs r_o ≥ 7β/6 (union) or r_o ≥ β (intersection, difference)",
            ));
        }
        Ok(Self { kind, beta, r_o })
    }

    /// Compact union `G∪` (eqs. 12, 17, 18) with blend `β` and range
    /// `R_o = (−∞, r_o]`; see [`default_r_o`](Self::default_r_o).
    ///
    /// # Errors
    /// [`FieldError::InvalidParameter`] when `β` or `r_o` is NaN, infinite
    /// or ≤ 0, when `6r_o − β ≤ 0` (eq. 18), or when `r_o < 7β/6`
    /// (discontinuous, module docs).
    ///
    /// ```
    /// use boundtrace_fields::operator::Operator;
    /// let g = Operator::compact_union(0.3, 0.5).unwrap();
    /// // Outside R_o it is the CSG union; on the blend it is smooth.
    /// assert_eq!(g.eval(0.7f64, 0.2), 0.2);
    /// assert!(g.eval(0.05f64, 0.05) < 0.05);
    /// assert!(Operator::compact_union(0.3, 0.04).is_err());
    /// ```
    pub fn compact_union(beta: T, r_o: T) -> Result<Self, FieldError> {
        Self::compact(OperatorKind::CompactUnion, beta, r_o)
    }

    /// Compact intersection `G∩`, `R_o = [−r_o, r_o]`.
    ///
    /// # Errors
    /// As [`compact_union`](Self::compact_union), with `r_o ≥ β`.
    pub fn compact_intersection(beta: T, r_o: T) -> Result<Self, FieldError> {
        Self::compact(OperatorKind::CompactIntersection, beta, r_o)
    }

    /// Compact difference `G∖`, `R_o = [−r_o, r_o]`.
    ///
    /// # Errors
    /// As [`compact_intersection`](Self::compact_intersection).
    pub fn compact_difference(beta: T, r_o: T) -> Result<Self, FieldError> {
        Self::compact(OperatorKind::CompactDifference, beta, r_o)
    }

    /// The operator's kind.
    pub fn kind(&self) -> OperatorKind {
        self.kind
    }

    /// The blend parameter `β` (`0` for CSG).
    pub fn beta(&self) -> T {
        self.beta
    }

    /// The range parameter `r_o` (`0` for CSG and smooth operators).
    pub fn r_o(&self) -> T {
        self.r_o
    }

    /// The operator range `R_o = (r_o⁻, r_o⁺)`: `(0, 0)` for CSG,
    /// `(−∞, +∞)` for smooth operators, `(−∞, r_o)` for the compact union
    /// and `(−r_o, r_o)` for the compact intersection and difference (§4).
    pub fn range(&self) -> (T, T) {
        match self.kind {
            OperatorKind::Union | OperatorKind::Intersection | OperatorKind::Difference => {
                (T::ZERO, T::ZERO)
            }
            OperatorKind::SmoothUnion
            | OperatorKind::SmoothIntersection
            | OperatorKind::SmoothDifference => (T::NEG_INFINITY, T::INFINITY),
            OperatorKind::CompactUnion => (T::NEG_INFINITY, self.r_o),
            OperatorKind::CompactIntersection | OperatorKind::CompactDifference => {
                (-self.r_o, self.r_o)
            }
        }
    }

    /// The operator applied to operand values, in any number type; sound
    /// for bound types (undecided compact branches are joined, module
    /// docs).
    #[inline]
    pub fn eval<N: FieldNum<T>>(&self, f0: N, f1: N) -> N {
        // By class and family rather than one arm per kind, so that every
        // operation has one call site: the GPU shader inlines every call
        // (BENCHMARKS.md "GPU", session 36). Per kind, the same operations:
        // union `f₀ ∧ f₁`, intersection `f₀ ∨ f₁`, difference `f₀ ∨ −f₁`;
        // smooth: that `∓ d(|f₀ − f₁|, β)` (`|f₀ + f₁|` for the
        // difference); compact: [`compact`] with `f₁` or `−f₁`.
        let b = self.beta;
        let class = self.kind.class();
        let union = class == OperatorClass::UnionLike;
        let difference = class == OperatorClass::DifferenceLike;
        let g1 = if difference { -f1 } else { f1 };
        if self.kind.is_compact() {
            return compact(f0, g1, union, b, self.r_o);
        }
        let csg = if union { f0.min(g1) } else { f0.max(g1) };
        let smooth = matches!(
            self.kind,
            OperatorKind::SmoothUnion
                | OperatorKind::SmoothIntersection
                | OperatorKind::SmoothDifference
        );
        if !smooth {
            return csg;
        }
        let s = if difference { f0 + f1 } else { f0 - f1 };
        let d = blend_const(s.abs(), b);
        if union { csg - d } else { csg + d }
    }

    /// The operator with possibly missing (inactive) operands, each treated
    /// as `+∞` (§4): union-like → the present operand (`None` if both are
    /// missing); intersection-like → `None` (the node is inactive) unless
    /// both are present; difference-like → `f₀` when `f₁` is missing
    /// (`−∞` never wins the maximum), `None` when `f₀` is missing.
    #[inline]
    pub fn eval_partial<N: FieldNum<T>>(&self, f0: Option<N>, f1: Option<N>) -> Option<N> {
        match (f0, f1) {
            (Some(a), Some(b)) => Some(self.eval(a, b)),
            (Some(a), None) => match self.kind.class() {
                OperatorClass::UnionLike | OperatorClass::DifferenceLike => Some(a),
                OperatorClass::IntersectionLike => None,
            },
            (None, Some(b)) => match self.kind.class() {
                OperatorClass::UnionLike => Some(b),
                _ => None,
            },
            (None, None) => None,
        }
    }

    /// How the operator scales the operands' Lipschitz bound `L`: the
    /// result is `lipschitz_factor() · L`-Lipschitz. `1` for CSG and smooth
    /// operators, `6r_o / (6r_o − β)` for compact ones (module docs).
    pub fn lipschitz_factor(&self) -> T {
        if self.kind.is_compact() {
            let six = T::from_f64(6.0) * self.r_o;
            six / (six - self.beta)
        } else {
            T::ONE
        }
    }

    /// Writes `kind().param_vec4s() * 4` floats at the start of `out`:
    /// nothing for CSG, `[β, r_o, 0, 0]` otherwise (`r_o = 0` for smooth
    /// operators).
    ///
    /// # Errors
    /// [`FieldError::TooLarge`] when `out` is too short,
    /// [`FieldError::InvalidParameter`] when a value overflows `f32`.
    pub fn write_params(&self, out: &mut [f32]) -> Result<(), FieldError> {
        let n = self.kind.param_vec4s() as usize * 4;
        if out.len() < n {
            return Err(FieldError::TooLarge {
                what: "parameter floats",
                count: n,
                max: out.len(),
            });
        }
        if n == 4 {
            let b = self.beta.as_f64() as f32;
            let r = self.r_o.as_f64() as f32;
            if !(b.is_finite() && r.is_finite()) {
                return Err(invalid("params", "value overflows f32"));
            }
            out[0] = b;
            out[1] = r;
            out[2] = 0.0;
            out[3] = 0.0;
        }
        Ok(())
    }

    /// Reads parameters written by [`write_params`](Self::write_params);
    /// `None` when `d` is too short or the values fail the constructor's
    /// checks. Never panics.
    pub fn read_params(kind: OperatorKind, d: &[f32]) -> Option<Self> {
        let n = kind.param_vec4s() as usize * 4;
        if d.len() < n {
            return None;
        }
        let op = Self::decode_with(kind, |i| d[i]);
        let ok = match kind {
            OperatorKind::Union | OperatorKind::Intersection | OperatorKind::Difference => true,
            OperatorKind::SmoothUnion
            | OperatorKind::SmoothIntersection
            | OperatorKind::SmoothDifference => Self::smooth(kind, op.beta).is_ok(),
            _ => Self::compact(kind, op.beta, op.r_o).is_ok(),
        };
        ok.then_some(op)
    }

    /// [`read_params`](Self::read_params) without its checks, the `i`-th
    /// parameter float given by `param(i)` (`i < kind.param_vec4s() * 4`):
    /// for parameters that `read_params` accepted before (a validated
    /// blobtree), the same operator bit for bit; the decoding of the
    /// blobtree interpreters, on the CPU and in the GPU shader. Never
    /// panics.
    #[inline]
    pub(crate) fn decode_with(kind: OperatorKind, param: impl Fn(usize) -> f32) -> Self {
        let g = |i: usize| T::from_f64(f64::from(param(i)));
        match kind {
            OperatorKind::Union | OperatorKind::Intersection | OperatorKind::Difference => {
                Self::csg(kind)
            }
            OperatorKind::SmoothUnion
            | OperatorKind::SmoothIntersection
            | OperatorKind::SmoothDifference => Self {
                kind,
                beta: g(0),
                r_o: T::ZERO,
            },
            _ => Self {
                kind,
                beta: g(0),
                r_o: g(1),
            },
        }
    }
}

/// `d(s, β) = β/6 · (1 − s/β)₊³` for a constant `β > 0` (eq. 9), `s ≥ 0`.
#[inline]
fn blend_const<T: Real, N: FieldNum<T>>(s: N, beta: T) -> N {
    (s / beta).one_minus_clamped().powi(3) * (beta / T::from_f64(6.0))
}

/// `d(s, b)` for a variable `b ≥ 0` (module docs, "Where NaN arises").
#[inline]
fn blend_var<T: Real, N: FieldNum<T>>(s: N, b: N) -> N {
    let zero = N::constant(T::ZERO);
    let e = b.enclosure();
    // NaN is filtered to d = 0 (paper §4, eq. 18).
    if e.hi().is_nan() || e.hi() <= T::ZERO {
        return zero;
    }
    let sixth = T::ONE / T::from_f64(6.0);
    if e.lo() > T::ZERO {
        (s / b).one_minus_clamped().powi(3) * b * sixth
    } else {
        zero.join((b - s).max(zero) * sixth)
    }
}

/// Where the enclosure of an operand lies with respect to `R_o`.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Side {
    In,
    Out,
    Undecided,
}

#[inline]
fn side<T: Real, N: FieldNum<T>>(f: &N, lo: T, hi: T) -> Side {
    let e = f.enclosure();
    if e.lo() >= lo && e.hi() <= hi {
        Side::In
    } else if e.hi() < lo || e.lo() > hi {
        Side::Out
    } else {
        Side::Undecided
    }
}

/// A sound answer for operands whose enclosure is unbounded (or NaN): no
/// arithmetic that gives NaN for infinities (`∞ − ∞`, `0·∞`).
/// `G∩ ∈ [csg, csg + β/6]` since `b_r ≤ β` there. For the union,
/// `x = csg − d(s, β) ≥ csg − β/6`, so `b_r ≤ β(1 + kβ/6 − k·csg)₊` and
/// `d(s, b_r) ≤ b_r/6`: with `c₁ = β/6·(1 + kβ/6)` and `c₂ = kβ/6`,
/// `G∪ ∈ [min(csg, (1 + c₂)·csg − c₁), csg]`. With a finite lower end
/// `lo` of `csg`, the constant `D = β/6·(1 − k(lo − β/6))₊` is the same
/// bound taken at `lo`; without one the bound stays linear in `csg`, so a
/// forward bound's start stays finite (and encloses the blend) even when
/// its enclosure is unbounded. (`b_r` exceeds `β` where `x < 0`: the
/// constant `β/6` is not a bound there.) Point types get `csg`.
fn unbounded_fallback<T: Real, N: FieldNum<T>>(csg: N, union: bool, beta: T, r_o: T) -> N {
    let six = T::from_f64(6.0);
    if union {
        let lo = csg.enclosure().lo();
        let k = six / (six * r_o - beta);
        let linear = || {
            // c₁, c₂ (and k) carry a few roundings: widened by 16 ε
            // relative (an error of c₂ moves the bound by at most
            // c₂·csg ≤ c₁ where the bound is active).
            let widen = T::ONE + T::from_f64(16.0) * T::EPSILON;
            let c2 = k * beta / six * widen;
            let c1 = beta / six * (T::ONE + c2) * widen * widen;
            csg.join(csg.min(csg * (T::ONE + c2) - c1))
        };
        if lo.is_nan() || lo == T::NEG_INFINITY {
            return linear();
        }
        let d = beta * (T::ONE - k * (lo - beta / six)).max(T::ZERO) / six;
        if d.is_finite() {
            csg.join(csg - d)
        } else {
            linear()
        }
    } else {
        csg.join(csg + beta / six)
    }
}

/// `G∪` (`union = true`) or `G∩` (eqs. 12, 17, 18); `G∖(f₀, f₁)` is
/// `G∩(f₀, −f₁)`.
#[inline]
fn compact<T: Real, N: FieldNum<T>>(f0: N, f1: N, union: bool, beta: T, r_o: T) -> N {
    let lo = if union { T::NEG_INFINITY } else { -r_o };
    let csg = if union { f0.min(f1) } else { f0.max(f1) };
    let (s0, s1) = (side(&f0, lo, r_o), side(&f1, lo, r_o));
    if s0 == Side::Out || s1 == Side::Out {
        return csg;
    }
    let (e0, e1) = (f0.enclosure(), f1.enclosure());
    let finite = |e: boundtrace_ia_core::Interval<T>| {
        e.lo() > T::NEG_INFINITY && e.hi() < T::INFINITY && e.lo() <= e.hi()
    };
    if !(finite(e0) && finite(e1)) {
        return unbounded_fallback(csg, union, beta, r_o);
    }
    let s = (f0 - f1).abs();
    // First evaluation with β, then the transition b_r (eq. 18).
    let d0 = blend_const(s, beta);
    let x = if union { csg - d0 } else { (csg + d0).abs() };
    let k = T::from_f64(6.0) / (T::from_f64(6.0) * r_o - beta);
    let b = (x * k).one_minus_clamped() * beta;
    let d = blend_var(s, b);
    let blend = if union { csg - d } else { csg + d };
    if s0 == Side::In && s1 == Side::In {
        blend
    } else {
        csg.join(blend)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_round_trip() {
        for (i, k) in OperatorKind::ALL.iter().enumerate() {
            assert_eq!(OperatorKind::from_u32(i as u32), Some(*k));
            assert_eq!(*k as u32, i as u32);
        }
        assert_eq!(OperatorKind::from_u32(9), None);
    }

    #[test]
    fn decoding_without_checks_equals_read_params() {
        let d = [0.1f32, 0.25, 0.0, 0.0];
        for k in OperatorKind::ALL {
            let checked = Operator::<f64>::read_params(k, &d).unwrap();
            assert_eq!(Operator::<f64>::decode_with(k, |i| d[i]), checked, "{k:?}");
        }
        // r_o too small for β: rejected by the checks, decoded without them.
        let bad = [0.3f32, 0.1, 0.0, 0.0];
        assert!(Operator::<f64>::read_params(OperatorKind::CompactUnion, &bad).is_none());
    }

    #[test]
    fn unbounded_forward_operand_keeps_the_blend_in_the_start() {
        // A forward bound can be valid with infinite curvature coefficients
        // (so an unbounded enclosure) and an exact start; the compact union
        // must still subtract the blend at the start (regression: the start
        // was `min(f0, f1)` alone, above the true value).
        use boundtrace_ia_core::Interval;
        use boundtrace_inclusion::ForwardQuadratic;
        let inf = f64::INFINITY;
        let (v0, v1) = (0.20555832541155272, 0.19962202533782458);
        let f0 =
            ForwardQuadratic::from_parts(Interval::point(v0), [-1.17, -inf], [-0.55, inf], 0.5);
        let f1 =
            ForwardQuadratic::from_parts(Interval::point(v1), [-0.65, 1.0], [-0.58, 0.92], 0.5);
        for op in [
            Operator::compact_union(0.13, 0.26).unwrap(),
            Operator::compact_intersection(0.13, 0.26).unwrap(),
            Operator::compact_difference(0.13, 0.26).unwrap(),
        ] {
            let exact: f64 = op.eval(v0, v1);
            let b = op.eval(f0, f1);
            assert!(b.is_valid());
            assert!(
                b.start().contains(exact),
                "{op:?}: {exact} ∉ {:?}",
                b.start()
            );
        }
    }

    #[test]
    fn unbounded_union_operand_encloses_a_blend_above_beta_over_6() {
        // Fuzz `field_bounds` (regressions/field_bounds/crash-c1be…): an
        // operand with an unbounded forward enclosure and a start far
        // inside (csg ≈ −2.13) has b_r ≈ 5β, so the blend exceeds β/6;
        // the start was [csg − β/6, csg], above the true value.
        use boundtrace_ia_core::Interval;
        use boundtrace_inclusion::ForwardLinear;
        let inf = f64::INFINITY;
        let op = Operator::compact_union(0.33166003227233887, 0.5487979054450989).unwrap();
        let (v0, v1) = (-2.129690021987417, -1.392_720_503_019_807);
        let exact: f64 = op.eval(v0, v1);
        assert!(
            exact < v0 - 0.33166003227233887 / 6.0,
            "the case needs a blend > β/6"
        );
        let f0 = ForwardLinear::from_parts(Interval::point(v0), -inf, 1.0, 0.5);
        let f1 = ForwardLinear::from_parts(Interval::new(-1.4607, -1.3327), -1.0, 1.0, 0.5);
        let b = op.eval(f0, f1);
        assert!(b.start().contains(exact), "{exact} ∉ {:?}", b.start());
        // The same with plain intervals whose lower ends are unbounded.
        let i0 = Interval::new(-inf, v0);
        let i1 = Interval::new(-inf, v1);
        assert!(op.eval(i0, i1).contains(exact));
    }

    #[test]
    fn continuity_at_boundary() {
        for kind in [
            OperatorKind::CompactUnion,
            OperatorKind::CompactIntersection,
            OperatorKind::CompactDifference,
        ] {
            let beta = 0.4f64;
            let r_o = Operator::<f64>::min_r_o(kind, beta);
            let op = Operator::compact(kind, beta, r_o).unwrap();
            let e = 1e-9;
            let mut i = 0;
            while i < 400 {
                let f1 = -r_o * 3.0 + (i as f64) * r_o * 4.0 / 400.0;
                for edge in [r_o, -r_o] {
                    let a = op.eval(edge - e, f1);
                    let b = op.eval(edge + e, f1);
                    assert!((a - b).abs() < 1e-7, "{kind:?} {edge} {f1}: {a} {b}");
                }
                i += 1;
            }
        }
        // Just below the union's bound: discontinuous (so the check matters).
        let op = Operator {
            kind: OperatorKind::CompactUnion,
            beta: 1.0f64,
            r_o: 0.5,
        };
        assert!((op.eval(0.5 - 1e-9, -3.0) - op.eval(0.5 + 1e-9, -3.0)).abs() > 0.1);
    }

    #[test]
    fn rejects_bad_parameters() {
        assert!(Operator::smooth_union(0.0f64).is_err());
        assert!(Operator::smooth_union(f64::NAN).is_err());
        assert!(Operator::compact_union(1.0f64, 1.0 / 6.0).is_err());
        assert!(Operator::compact_union(1.0f64, 1.1).is_err());
        assert!(Operator::compact_union(1.0f64, 7.0 / 6.0).is_ok());
        assert!(Operator::compact_intersection(1.0f64, 1.0).is_ok());
        assert!(Operator::compact_difference(-1.0f64, 1.0).is_err());
    }

    #[test]
    fn missing_operand_is_plus_infinity() {
        let big = 1e30f64;
        for kind in OperatorKind::ALL {
            let op = match kind {
                OperatorKind::Union => Operator::union(),
                OperatorKind::Intersection => Operator::intersection(),
                OperatorKind::Difference => Operator::difference(),
                OperatorKind::SmoothUnion => Operator::smooth_union(0.3).unwrap(),
                OperatorKind::SmoothIntersection => Operator::smooth_intersection(0.3).unwrap(),
                OperatorKind::SmoothDifference => Operator::smooth_difference(0.3).unwrap(),
                OperatorKind::CompactUnion => Operator::compact_union(0.3, 0.4).unwrap(),
                OperatorKind::CompactIntersection => {
                    Operator::compact_intersection(0.3, 0.4).unwrap()
                }
                OperatorKind::CompactDifference => Operator::compact_difference(0.3, 0.4).unwrap(),
            };
            for a in [-2.0, -0.1, 0.0, 0.2, 3.0] {
                // A missing operand acts as +∞: `None` stands for a result
                // that is (beyond) +∞ itself.
                for (x, y) in [(Some(a), None), (None, Some(a))] {
                    let full = op.eval(x.unwrap_or(big), y.unwrap_or(big));
                    match op.eval_partial(x, y) {
                        Some(v) => assert_eq!(v, full, "{kind:?} {x:?} {y:?}"),
                        None => assert!(full >= big, "{kind:?} {x:?} {y:?}: {full}"),
                    }
                }
            }
            assert_eq!(op.eval_partial::<f64>(None, None), None);
        }
    }

    #[test]
    fn nan_free_at_b_zero() {
        let op = Operator::compact_union(0.3f64, 0.5).unwrap();
        // b_r = 0 at (r_o, r_o) with s = 0: 0/0 without the filter.
        let v = op.eval(0.5f64, 0.5);
        assert_eq!(v, 0.5);
        let v = op.eval(f64::NEG_INFINITY, f64::NEG_INFINITY);
        assert_eq!(v, f64::NEG_INFINITY);
    }
}
