//! The statistics harness and the dense reference (thesis Part III §1.8,
//! "Statistics"; forward-inclusion paper §7).
//!
//! The methodology of the thesis: rays are launched from the faces of the
//! scene's axis-aligned bounding box in the six axis directions, with
//! origins uniform on each face ([`RaySet`]). Every method traces the same
//! rays ([`run_method`]), which gives per-method averages, medians and
//! maxima of the steps, the average number of field and bound evaluations
//! and the average time per ray ([`MethodStats`]), and checks every answer
//! against a dense reference computed once per ray set ([`Reference`],
//! [`reference_roots`]) with the rules of [`classify`].
//!
//! ```
//! use boundtrace_inclusion::{Field, FieldNum};
//! use boundtrace_tracer::stats::{RaySet, Reference, ReferenceParams, markdown_table, run_method};
//! use boundtrace_tracer::{Method, Mode, Params};
//!
//! struct Ball; // the unit ball as a signed distance
//! impl Field<f64> for Ball {
//!     fn eval<N: FieldNum<f64>>(&self, p: [N; 3]) -> N {
//!         (p[0].sqr() + p[1].sqr() + p[2].sqr()).sqrt() - 1.0
//!     }
//!     fn lipschitz(&self) -> Option<f64> { Some(1.0) }
//! }
//!
//! let rays = RaySet::new([[-1.5; 3], [1.5; 3]], 600, 7)?;
//! let params = Params::new();
//! let reference = Reference::compute(&Ball, &rays, &ReferenceParams::new(params.eps)?)?;
//! // A ray hits the ball when its origin is within the unit disk of its face.
//! let hits = (0..rays.len()).filter(|&i| reference.roots(i).iter().any(|r| r.certain())).count();
//! assert!(hits > 150 && hits < 270, "{hits}"); // π/9 ≈ 35% of the rays
//!
//! let stats = run_method(&Ball, &rays, &reference, Method::Segment, Mode::Opaque, &params)?;
//! if stats.traced() > 0 {
//!     assert_eq!(stats.stepped_past, 0);
//! }
//! println!("{}", markdown_table(&[stats], Some(Method::Segment)));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::method::{InvalidParams, Method, Mode, Params};
use crate::scenes::{Scene, SceneField};
use crate::trace::{RayStats, Root, Side, Status, Trace, trace};
use boundtrace_ia_core::{Interval, Real};
use boundtrace_inclusion::{Field, FieldNum, Ray};
use std::fmt;
use std::fmt::Write as _;
use std::string::String;
use std::time::Instant;
use std::vec::Vec;

/// At most this many disagreeing rays are kept, with their roots, in
/// [`MethodStats::failures`].
pub const MAX_FAILURES: usize = 8;

/// Rays per work item (parallel threads; progress reports).
const CHUNK: usize = 256;

/// `Sync` with the `parallel` feature (the field and the numbers are shared
/// between threads), any type without it.
#[cfg(feature = "parallel")]
pub trait MaybeSync: Sync {}
#[cfg(feature = "parallel")]
impl<X: Sync + ?Sized> MaybeSync for X {}
/// `Sync` with the `parallel` feature (the field and the numbers are shared
/// between threads), any type without it.
#[cfg(not(feature = "parallel"))]
pub trait MaybeSync {}
#[cfg(not(feature = "parallel"))]
impl<X: ?Sized> MaybeSync for X {}

/// An error of the statistics harness (bad input, never a panic).
#[derive(Clone, Debug, PartialEq)]
pub enum StatsError {
    /// The bounding box is not finite with `lo < hi` on every axis.
    Bounds,
    /// A ray set needs at least one ray.
    NoRays,
    /// A span is not finite with `t0 ≤ t1`.
    Span,
    /// A [`ReferenceParams`] field is invalid.
    Reference {
        /// The field's name.
        name: &'static str,
        /// What is required of it.
        reason: &'static str,
    },
    /// The tracing parameters are invalid.
    Params(InvalidParams),
    /// The tracing `eps` differs from the reference's: the classification
    /// would not measure what the tracer promises.
    EpsMismatch,
    /// The reference was computed for a ray set of another size.
    RayCountMismatch {
        /// Rays in the set.
        rays: usize,
        /// Rays in the reference.
        reference: usize,
    },
}

impl fmt::Display for StatsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StatsError::Bounds => f.write_str(
                "invalid bounding box: every coordinate must be finite, with lo < hi on every axis",
            ),
            StatsError::NoRays => f.write_str("the ray count must be at least 1"),
            StatsError::Span => f.write_str("invalid span: t0 and t1 must be finite, t0 <= t1"),
            StatsError::Reference { name, reason } => {
                write!(f, "invalid reference parameter `{name}`: {reason}")
            }
            StatsError::Params(e) => write!(f, "{e}"),
            StatsError::EpsMismatch => {
                f.write_str("the tracing eps differs from the reference's eps")
            }
            StatsError::RayCountMismatch { rays, reference } => write!(
                f,
                "the reference has {reference} rays but the ray set has {rays}"
            ),
        }
    }
}

impl std::error::Error for StatsError {}

impl From<InvalidParams> for StatsError {
    fn from(e: InvalidParams) -> Self {
        StatsError::Params(e)
    }
}

// ---------------------------------------------------------------------------
// Rays

/// One ray of a [`RaySet`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampleRay<T> {
    /// The ray: origin on a face of the box, unit axis direction into it.
    pub ray: Ray<T>,
    /// `[0, extent of the box along the ray's axis]`.
    pub span: [T; 2],
    /// The face: `2·axis` for direction `+axis` (origin on the `lo` face),
    /// `2·axis + 1` for `−axis` (origin on the `hi` face).
    pub face: u8,
}

/// Deterministic rays from the faces of a box in the 6 axis directions
/// (thesis §1.8): ray `i` starts on face `i mod 6` (so every face gets an
/// equal share, ±1), at a point uniform on the face, drawn from a local
/// PRNG seeded by `(seed, i)` alone. The same `(bounds, seed)` gives the
/// same rays on every platform, and a smaller set is a prefix of a larger.
#[derive(Clone, Debug, PartialEq)]
pub struct RaySet<T> {
    bounds: [[T; 3]; 2],
    seed: u64,
    rays: Vec<SampleRay<T>>,
}

/// SplitMix64 (Steele, Lea and Flood 2014): the ray generator's PRNG.
fn splitmix64(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A uniform number in `[0, 1)` from 53 random bits.
fn unit_f64(bits: u64) -> f64 {
    (bits >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

impl<T: Real> RaySet<T> {
    /// `count` rays from the faces of `bounds = [lo, hi]` (see the type's
    /// docs). Use [`enlarged`] to start the rays strictly outside a
    /// tight box.
    ///
    /// # Errors
    /// [`StatsError::Bounds`] unless every coordinate is finite with
    /// `lo < hi` on every axis; [`StatsError::NoRays`] when `count == 0`.
    pub fn new(bounds: [[T; 3]; 2], count: usize, seed: u64) -> Result<Self, StatsError> {
        let [lo, hi] = bounds;
        for a in 0..3 {
            if !(lo[a].is_finite() && hi[a].is_finite() && lo[a] < hi[a]) {
                return Err(StatsError::Bounds);
            }
        }
        if count == 0 {
            return Err(StatsError::NoRays);
        }
        let rays = (0..count)
            .map(|i| Self::make_ray(bounds, seed, i))
            .collect();
        Ok(Self { bounds, seed, rays })
    }

    fn make_ray(bounds: [[T; 3]; 2], seed: u64, index: usize) -> SampleRay<T> {
        let [lo, hi] = bounds;
        let face = (index % 6) as u8;
        let axis = usize::from(face / 2);
        let positive = face % 2 == 0;
        let mut state = seed ^ splitmix64(&mut (index as u64).wrapping_mul(0xD1B5_4A32_D192_ED03));
        let mut origin = [T::ZERO; 3];
        for (a, o) in origin.iter_mut().enumerate() {
            *o = if a == axis {
                if positive { lo[a] } else { hi[a] }
            } else {
                let u = T::from_f64(unit_f64(splitmix64(&mut state)));
                (lo[a] + u * (hi[a] - lo[a])).min(hi[a])
            };
        }
        let mut dir = [T::ZERO; 3];
        dir[axis] = if positive { T::ONE } else { -T::ONE };
        SampleRay {
            ray: Ray::new(origin, dir),
            span: [T::ZERO, hi[axis] - lo[axis]],
            face,
        }
    }

    /// The box.
    pub fn bounds(&self) -> [[T; 3]; 2] {
        self.bounds
    }

    /// The seed.
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// The number of rays.
    pub fn len(&self) -> usize {
        self.rays.len()
    }

    /// Whether there is no ray (never, for a set built by [`RaySet::new`]).
    pub fn is_empty(&self) -> bool {
        self.rays.is_empty()
    }

    /// The rays, in index order.
    pub fn rays(&self) -> &[SampleRay<T>] {
        &self.rays
    }

    /// The first `n` rays (all when `n ≥ len`): the set built with count
    /// `n`, without regenerating it.
    pub fn prefix(&self, n: usize) -> Self {
        Self {
            bounds: self.bounds,
            seed: self.seed,
            rays: self.rays[..n.min(self.rays.len())].to_vec(),
        }
    }
}

/// `bounds` grown by `rel` times the box diagonal on every side (so rays
/// start strictly outside a box that is tight on the surface); `bounds`
/// unchanged for `rel ≤ 0` or a non-finite result.
pub fn enlarged<T: Real>(bounds: [[T; 3]; 2], rel: T) -> [[T; 3]; 2] {
    let [lo, hi] = bounds;
    let diag = ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2) + (hi[2] - lo[2]).powi(2)).sqrt();
    let m = rel * diag;
    if !(m > T::ZERO && m.is_finite()) {
        return bounds;
    }
    [
        [lo[0] - m, lo[1] - m, lo[2] - m],
        [hi[0] + m, hi[1] + m, hi[2] + m],
    ]
}

// ---------------------------------------------------------------------------
// The dense reference

/// Parameters of the dense reference ([`reference_roots`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReferenceParams<T> {
    /// ε: roots closer than this are merged into one group (the tracer
    /// reports them once), and the tolerance of [`classify`]. Use the
    /// tracer's [`Params::eps`].
    pub eps: T,
    /// Grid cells per span: the span is sampled at `cells + 1` equally
    /// spaced points (4096 by default: spacing ≤ extent/4096).
    pub cells: u32,
    /// With [`enclosures`](Self::enclosures), a cell whose enclosure
    /// contains 0 is subdivided down to this width (`eps/4` by default).
    pub finest: T,
    /// Width of the final bisection bracket of a root (`eps/64` by
    /// default): a reference root is within `tol/2` of a sign change.
    pub tol: T,
    /// Use sound interval enclosures to skip root-free parts of the span and
    /// to look for root pairs inside cells (default `true`); `false` samples
    /// the grid only (fully independent of interval arithmetic, but blind to
    /// root pairs inside one cell).
    pub enclosures: bool,
}

impl<T: Real> ReferenceParams<T> {
    /// The defaults for `eps`: `cells = 4096`, `finest = eps/4`,
    /// `tol = eps/64`, enclosures on.
    ///
    /// # Errors
    /// [`StatsError::Reference`] unless `eps` is finite and `> 0`.
    pub fn new(eps: T) -> Result<Self, StatsError> {
        let p = Self {
            eps,
            cells: 4096,
            finest: eps / T::from_f64(4.0),
            tol: eps / T::from_f64(64.0),
            enclosures: true,
        };
        p.validate().map(|()| p)
    }

    /// Checks every field: `eps` finite and `> 0`, `cells ≥ 1`, `finest`
    /// finite and `> 0`, `tol` finite with `0 < tol ≤ eps`.
    ///
    /// # Errors
    /// The first invalid field, as [`StatsError::Reference`].
    pub fn validate(&self) -> Result<(), StatsError> {
        let bad = |name, reason| Err(StatsError::Reference { name, reason });
        if !(self.eps.is_finite() && self.eps > T::ZERO) {
            return bad("eps", "must be finite and > 0");
        }
        if self.cells == 0 {
            return bad("cells", "must be >= 1");
        }
        if !(self.finest.is_finite() && self.finest > T::ZERO) {
            return bad("finest", "must be finite and > 0");
        }
        if !(self.tol > T::ZERO && self.tol <= self.eps) {
            return bad("tol", "must be in (0, eps]");
        }
        Ok(())
    }
}

/// A root group of the reference along one ray.
///
/// A *certain* group (`count ≥ 1`) holds `count` sign changes of the field,
/// each within `tol/2` of its reported position, consecutive ones closer
/// than `eps`; its `side` is the sign change's for a single one and
/// [`Side::Touch`] for a merged group. An *optional* group (`count == 0`,
/// side `Touch`) marks cells of width ≤ `finest` without a sign change whose
/// interval enclosure contains 0 (consecutive ones closer than `eps`
/// merged): the field may touch zero there, so a method may report a root
/// there but need not.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RefRoot<T> {
    /// The first root of the group.
    pub t: T,
    /// The last root of the group (`t` for a single root).
    pub t_end: T,
    /// The side (see above).
    pub side: Side,
    /// Sign changes in the group (0: optional group).
    pub count: u32,
}

impl<T: Real> RefRoot<T> {
    /// Whether the group holds a sign change (every method must find it).
    pub fn certain(&self) -> bool {
        self.count > 0
    }
}

fn positive<T: Real>(v: T) -> bool {
    v > T::ZERO
}

fn excludes_zero<T: Real>(iv: Interval<T>) -> bool {
    !iv.is_empty() && (iv.lo() > T::ZERO || iv.hi() < T::ZERO)
}

/// A raw event of the reference: a sign change or a possible touch.
#[derive(Clone, Copy)]
struct RawEvent<T> {
    t: T,
    side: Side,
}

/// The roots of `field` along `ray` on `span`: the dense reference.
///
/// The field is sampled at the `cells + 1` grid points
/// `t_i = t0 + (t1 − t0)·i/cells`; "sign" means `f > 0` (outside) or not
/// (`f ≤ 0` or NaN). Every grid cell whose end signs differ holds a root,
/// bracketed by bisection on the sign down to width `tol`. With
/// [`ReferenceParams::enclosures`]:
/// - the span is split top-down (binary) along the grid, and a block of
///   cells is skipped when the interval enclosure
///   `field.eval(ray.at::<Interval<T>>(a, b))` excludes 0 (sound, so no root
///   is lost there);
/// - a cell whose enclosure contains 0 is subdivided, halves whose
///   enclosure contains 0 again, down to width `finest`; a sign change
///   found in a sub-cell is refined as above, and a finest sub-cell without
///   sign change whose enclosure still contains 0 becomes an *optional*
///   touch (see [`RefRoot`]).
///
/// Raw sign changes closer than `eps` (chained) form one certain group;
/// optional touches closer than `eps` form one optional group, dropped
/// when within `eps` of a certain group.
///
/// What the reference can miss: with enclosures, an odd number ≥ 3 of
/// sign changes inside one finest sub-cell (width ≤ `finest`) counts as one;
/// an even number there is an optional touch. Without enclosures, root
/// pairs within one grid cell are invisible and 3 roots in a cell count as
/// one. It relies on the soundness of [`Interval`] evaluation of the field
/// (tested in the workspace's containment tests).
///
/// # Errors
/// [`StatsError::Reference`] for invalid `params`, [`StatsError::Span`]
/// unless `span` is finite with `t0 ≤ t1`.
pub fn reference_roots<T: Real + FieldNum<T>, F: Field<T>>(
    field: &F,
    ray: &Ray<T>,
    span: [T; 2],
    params: &ReferenceParams<T>,
) -> Result<Vec<RefRoot<T>>, StatsError> {
    params.validate()?;
    let [t0, t1] = span;
    if !(t0.is_finite() && t1.is_finite() && t0 <= t1) {
        return Err(StatsError::Span);
    }
    let mut raw = Vec::new();
    let n = params.cells as usize;
    let grid = |i: usize| {
        if i >= n {
            t1
        } else {
            t0 + (t1 - t0) * T::from_f64(i as f64 / n as f64)
        }
    };
    let val = |t: T| field.eval(ray.at::<T>(t, t));
    if params.enclosures {
        let mut cache: Option<(usize, T)> = None;
        let mut at_grid = |i: usize| match cache {
            Some((j, v)) if j == i => v,
            _ => {
                let v = val(grid(i));
                cache = Some((i, v));
                v
            }
        };
        let mut stack = vec![(0usize, n)];
        while let Some((i, j)) = stack.pop() {
            let enc: Interval<T> = field.eval(ray.at::<Interval<T>>(grid(i), grid(j)));
            if excludes_zero(enc) {
                continue;
            }
            if j - i > 1 {
                let mid = i + (j - i) / 2;
                stack.push((mid, j));
                stack.push((i, mid));
                continue;
            }
            let fa = at_grid(i);
            let fb = at_grid(j);
            resolve_cell(field, ray, [grid(i), grid(j)], [fa, fb], params, &mut raw);
        }
    } else {
        let mut fa = val(t0);
        for i in 0..n {
            let (a, b) = (grid(i), grid(i + 1));
            let fb = val(b);
            if positive(fa) != positive(fb) {
                raw.push(bisect_sign(field, ray, a, b, fa, params.tol));
            }
            fa = fb;
        }
    }
    Ok(group_events(&raw, params.eps))
}

/// Subdivides one grid cell whose enclosure contains 0 (left first, so the
/// events come in increasing `t`).
fn resolve_cell<T: Real + FieldNum<T>, F: Field<T>>(
    field: &F,
    ray: &Ray<T>,
    cell: [T; 2],
    values: [T; 2],
    params: &ReferenceParams<T>,
    raw: &mut Vec<RawEvent<T>>,
) {
    // (a, b, f(a), f(b), enclosure already known to contain 0)
    let mut stack = vec![(cell[0], cell[1], values[0], values[1], true)];
    while let Some((a, b, fa, fb, checked)) = stack.pop() {
        let change = positive(fa) != positive(fb);
        if !change && !checked {
            let enc: Interval<T> = field.eval(ray.at::<Interval<T>>(a, b));
            if excludes_zero(enc) {
                continue;
            }
        }
        let m = a + (b - a) * T::HALF;
        let finest = b - a <= params.finest || !(m > a && m < b);
        if finest {
            if change {
                raw.push(bisect_sign(field, ray, a, b, fa, params.tol));
            } else {
                raw.push(RawEvent {
                    t: m,
                    side: Side::Touch,
                });
            }
            continue;
        }
        let fm = field.eval(ray.at::<T>(m, m));
        stack.push((m, b, fm, fb, false));
        stack.push((a, m, fa, fm, false));
    }
}

/// Bisection on the sign of a bracket `[a, b]` whose end signs differ,
/// down to width `tol`; the root is the final bracket's midpoint.
fn bisect_sign<T: Real + FieldNum<T>, F: Field<T>>(
    field: &F,
    ray: &Ray<T>,
    mut a: T,
    mut b: T,
    fa: T,
    tol: T,
) -> RawEvent<T> {
    let pa = positive(fa);
    let side = if pa { Side::Entering } else { Side::Leaving };
    while b - a > tol {
        let m = a + (b - a) * T::HALF;
        if !(m > a && m < b) {
            break;
        }
        if positive(field.eval(ray.at::<T>(m, m))) == pa {
            a = m;
        } else {
            b = m;
        }
    }
    RawEvent {
        t: a + (b - a) * T::HALF,
        side,
    }
}

/// Groups raw events (in increasing `t`): sign changes chained closer than
/// `eps` form certain groups; touches likewise optional groups, dropped
/// when within `eps` of a certain group.
fn group_events<T: Real>(raw: &[RawEvent<T>], eps: T) -> Vec<RefRoot<T>> {
    let chain = |touch: bool| {
        let mut out: Vec<RefRoot<T>> = Vec::new();
        for e in raw.iter().filter(|e| (e.side == Side::Touch) == touch) {
            match out.last_mut() {
                Some(g) if e.t - g.t_end <= eps => {
                    g.t_end = e.t;
                    if !touch {
                        g.count += 1;
                        g.side = Side::Touch;
                    }
                }
                _ => out.push(RefRoot {
                    t: e.t,
                    t_end: e.t,
                    side: e.side,
                    count: u32::from(!touch),
                }),
            }
        }
        out
    };
    let certain = chain(false);
    let optional = chain(true);
    let mut all: Vec<RefRoot<T>> = optional
        .into_iter()
        .filter(|o| {
            !certain
                .iter()
                .any(|c| o.t <= c.t_end + eps && c.t <= o.t_end + eps)
        })
        .collect();
    all.extend(certain);
    all.sort_by(|x, y| x.t.partial_cmp(&y.t).unwrap_or(core::cmp::Ordering::Equal));
    all
}

/// The dense reference of a whole [`RaySet`] (computed once, shared by
/// every method and mode).
#[derive(Clone, Debug, PartialEq)]
pub struct Reference<T> {
    params: ReferenceParams<T>,
    roots: Vec<Vec<RefRoot<T>>>,
}

impl<T: Real + FieldNum<T> + MaybeSync + Send> Reference<T> {
    /// [`reference_roots`] of every ray of `rays` on its span (in parallel
    /// with the `parallel` feature; the same result).
    ///
    /// # Errors
    /// [`StatsError::Reference`] for invalid `params`.
    pub fn compute<F: Field<T> + MaybeSync>(
        field: &F,
        rays: &RaySet<T>,
        params: &ReferenceParams<T>,
    ) -> Result<Self, StatsError> {
        params.validate()?;
        let one = |r: &SampleRay<T>| reference_roots(field, &r.ray, r.span, params);
        #[cfg(feature = "parallel")]
        let roots = {
            use rayon::prelude::*;
            rays.rays()
                .par_iter()
                .map(one)
                .collect::<Result<Vec<_>, _>>()?
        };
        #[cfg(not(feature = "parallel"))]
        let roots = rays.rays().iter().map(one).collect::<Result<Vec<_>, _>>()?;
        Ok(Self {
            params: *params,
            roots,
        })
    }
}

impl<T: Real> Reference<T> {
    /// The parameters it was computed with.
    pub fn params(&self) -> &ReferenceParams<T> {
        &self.params
    }

    /// The number of rays.
    pub fn len(&self) -> usize {
        self.roots.len()
    }

    /// Whether there is no ray.
    pub fn is_empty(&self) -> bool {
        self.roots.is_empty()
    }

    /// The root groups of ray `i` (empty when out of range).
    pub fn roots(&self, i: usize) -> &[RefRoot<T>] {
        self.roots.get(i).map_or(&[], Vec::as_slice)
    }

    /// The reference of the first `n` rays (of [`RaySet::prefix`]).
    pub fn prefix(&self, n: usize) -> Self {
        Self {
            params: self.params,
            roots: self.roots[..n.min(self.roots.len())].to_vec(),
        }
    }

    /// Rays with at least one certain root.
    pub fn hits(&self) -> usize {
        self.roots
            .iter()
            .filter(|r| r.iter().any(RefRoot::certain))
            .count()
    }
}

// ---------------------------------------------------------------------------
// Classification

/// How one traced ray compares with the reference ([`classify`]). The
/// flags other than `agree` and `unsupported` may combine.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Verdict {
    /// The method's answer matches the reference.
    pub agree: bool,
    /// [`Status::Unsupported`]: nothing traced, nothing compared.
    pub unsupported: bool,
    /// A certain reference root was not found and the method did not get
    /// past it (it stopped before, e.g. at `max_steps`).
    pub missed: bool,
    /// `missed` while the status is not [`Status::Finished`]: the method
    /// gave up before the root.
    pub gave_up: bool,
    /// A method root that no reference root explains.
    pub spurious: bool,
    /// A method root farther than the tolerance from every reference group.
    pub far: bool,
    /// **The method went past a certain reference root without reporting
    /// it** (the soundness violation the methods must never commit).
    pub stepped_past: bool,
    /// A method root matched a single sign change but with the opposite
    /// [`Side`] (informational; does not affect `agree`).
    pub wrong_side: bool,
}

impl fmt::Display for Verdict {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.unsupported {
            return f.write_str("unsupported");
        }
        let flags = [
            (self.agree, "agree"),
            (self.stepped_past, "stepped-past"),
            (self.missed, "missed"),
            (self.gave_up, "gave-up"),
            (self.spurious, "spurious"),
            (self.far, "far"),
            (self.wrong_side, "wrong-side"),
        ];
        let mut first = true;
        for (on, name) in flags {
            if on {
                if !first {
                    f.write_str(",")?;
                }
                f.write_str(name)?;
                first = false;
            }
        }
        if first {
            f.write_str("disagree")?;
        }
        Ok(())
    }
}

/// The matching tolerance at `t`: `eps + tol + 8·ulp·max(1, |t|)` (the
/// method's promise, the reference's bracket, a few rounding errors).
fn tolerance<T: Real>(params: &ReferenceParams<T>, t: T) -> T {
    params.eps + params.tol + T::from_f64(8.0) * T::EPSILON * t.abs().max(T::ONE)
}

fn near<T: Real>(m: T, g: &RefRoot<T>, tau: T) -> bool {
    m >= g.t - tau && m <= g.t_end + tau
}

fn opposite(a: Side, b: Side) -> bool {
    matches!(
        (a, b),
        (Side::Entering, Side::Leaving) | (Side::Leaving, Side::Entering)
    )
}

/// Classifies one traced ray: the method's `roots` (in increasing `t`),
/// its `status` and `t_reached`, against the `reference` groups of the
/// same ray. `τ(t) = eps + tol + 8·ulp·max(1, |t|)` (from `params`); a
/// method root `m` is *near* a group `[t, t_end]` when
/// `t − τ ≤ m ≤ t_end + τ`.
///
/// **Opaque** (first roots): let `r₀` be the first certain group's `t`
/// and `m₀` the method's root (only the first is read). `m₀` is
/// *explained* when `|m₀ − r₀| ≤ τ` or it is near an optional group
/// before `r₀`.
/// - stepped past ⇔ `r₀` exists and either `m₀ > r₀ + τ` (unexplained),
///   or there is no `m₀` although `t_reached > r₀ + τ`;
/// - missed ⇔ `r₀` exists, no `m₀`, `t_reached ≤ r₀ + τ`; gave up ⇔
///   missed and status not `Finished`;
/// - spurious ⇔ `m₀` unexplained and (no `r₀` or `m₀ < r₀ − τ`);
/// - far ⇔ `m₀` near no group at all;
/// - agree ⇔ none of stepped past, missed, spurious (so both none agree,
///   whatever the status).
///
/// **Transparent** (all roots): method roots are matched in order to
/// groups near them; a certain group of `count` sign changes takes at most
/// `count` method roots (one method root for a merged pair is fine), an
/// optional group any number, a group is used before the next one. Then:
/// - an unmatched method root is spurious (and far when near no group);
/// - an unmatched certain group with `t + τ < t_reached` was stepped past,
///   otherwise missed (gave up when the status is not `Finished`);
/// - agree ⇔ nothing unmatched and status `Finished`.
///
/// Wrong side (both modes, informational): a root matched to a single
/// sign change reports the opposite side. [`Status::Unsupported`] gives a
/// verdict with only `unsupported` set.
pub fn classify<T: Real>(
    mode: Mode,
    params: &ReferenceParams<T>,
    reference: &[RefRoot<T>],
    roots: &[Root<T>],
    status: Status,
    t_reached: T,
) -> Verdict {
    let mut v = Verdict::default();
    if status == Status::Unsupported {
        v.unsupported = true;
        return v;
    }
    match mode {
        Mode::Opaque => {
            classify_opaque(params, reference, roots.first(), status, t_reached, &mut v)
        }
        Mode::Transparent => {
            classify_transparent(params, reference, roots, status, t_reached, &mut v)
        }
    }
    v
}

fn classify_opaque<T: Real>(
    params: &ReferenceParams<T>,
    reference: &[RefRoot<T>],
    m0: Option<&Root<T>>,
    status: Status,
    t_reached: T,
    v: &mut Verdict,
) {
    let first = reference.iter().find(|g| g.certain());
    let before = |g: &&RefRoot<T>| !g.certain() && first.is_none_or(|c| g.t < c.t);
    match (m0, first) {
        (None, None) => {}
        (None, Some(g0)) => {
            if t_reached > g0.t + tolerance(params, g0.t) {
                v.stepped_past = true;
            } else {
                v.missed = true;
                v.gave_up = status != Status::Finished;
            }
        }
        (Some(m), g0) => {
            let tau = tolerance(params, m.t);
            let at_first = g0.is_some_and(|g| (m.t - g.t).abs() <= tau);
            let explained = at_first || reference.iter().filter(before).any(|g| near(m.t, g, tau));
            v.far = !reference.iter().any(|g| near(m.t, g, tau));
            if !explained {
                match g0 {
                    Some(g) if m.t > g.t + tau => v.stepped_past = true,
                    _ => v.spurious = true,
                }
            }
            if let Some(g) = g0 {
                v.wrong_side = at_first && g.count == 1 && opposite(g.side, m.side);
            }
        }
    }
    v.agree = !(v.stepped_past || v.missed || v.spurious);
}

fn classify_transparent<T: Real>(
    params: &ReferenceParams<T>,
    reference: &[RefRoot<T>],
    roots: &[Root<T>],
    status: Status,
    t_reached: T,
    v: &mut Verdict,
) {
    // Matches per group.
    let mut used = vec![0u32; reference.len()];
    let mut j = 0; // first group not yet behind the current method root
    let mut unmatched_method = false;
    for m in roots {
        let tau = tolerance(params, m.t);
        while j < reference.len() && reference[j].t_end + tau < m.t {
            j += 1;
        }
        let mut matched = false;
        for k in j..reference.len() {
            let g = &reference[k];
            if !near(m.t, g, tau) {
                break;
            }
            if !g.certain() || used[k] < g.count {
                used[k] += 1;
                matched = true;
                if g.count == 1 && opposite(g.side, m.side) {
                    v.wrong_side = true;
                }
                j = k; // later roots may not use earlier groups
                break;
            }
        }
        if !matched {
            unmatched_method = true;
            v.spurious = true;
            if !reference.iter().any(|g| near(m.t, g, tau)) {
                v.far = true;
            }
        }
    }
    let mut unmatched_ref = false;
    for (g, &u) in reference.iter().zip(&used) {
        if g.certain() && u == 0 {
            unmatched_ref = true;
            if g.t + tolerance(params, g.t) < t_reached {
                v.stepped_past = true;
            } else {
                v.missed = true;
                v.gave_up |= status != Status::Finished;
            }
        }
    }
    v.agree = !unmatched_method && !unmatched_ref && status == Status::Finished;
}

// ---------------------------------------------------------------------------
// Running a method

/// One disagreeing ray, with what is needed to reproduce it (in `f64`).
#[derive(Clone, Debug, PartialEq)]
pub struct Failure {
    /// The ray's index in its [`RaySet`].
    pub ray: usize,
    /// The ray's origin.
    pub origin: [f64; 3],
    /// The ray's direction.
    pub dir: [f64; 3],
    /// The traced span.
    pub span: [f64; 2],
    /// The verdict.
    pub verdict: Verdict,
    /// The method's status.
    pub status: Status,
    /// The method's `t_reached`.
    pub t_reached: f64,
    /// The method's roots.
    pub roots: Vec<Root<f64>>,
    /// The reference's groups.
    pub reference: Vec<RefRoot<f64>>,
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "ray {} [{}] origin {:?} dir {:?} span {:?}: status {:?}, t_reached {}, method roots [",
            self.ray, self.verdict, self.origin, self.dir, self.span, self.status, self.t_reached
        )?;
        for (i, r) in self.roots.iter().enumerate() {
            let sep = if i > 0 { ", " } else { "" };
            write!(f, "{sep}{} {:?}", r.t, r.side)?;
        }
        f.write_str("], reference [")?;
        for (i, g) in self.reference.iter().enumerate() {
            let sep = if i > 0 { ", " } else { "" };
            if g.t_end > g.t {
                write!(f, "{sep}{}..{} {:?}", g.t, g.t_end, g.side)?;
            } else {
                write!(f, "{sep}{} {:?}", g.t, g.side)?;
            }
            if !g.certain() {
                f.write_str(" (optional)")?;
            }
        }
        f.write_str("]")
    }
}

/// The statistics of one method in one mode on one [`RaySet`]. Averages,
/// the median and the maximum are over the traced (supported) rays; the
/// correctness counts are numbers of rays with that [`Verdict`] flag.
#[derive(Clone, Debug, PartialEq)]
pub struct MethodStats {
    /// The method.
    pub method: Method,
    /// The mode.
    pub mode: Mode,
    /// Rays in the set.
    pub rays: usize,
    /// Rays with [`Status::Unsupported`] (not traced, not compared).
    pub unsupported: usize,
    /// Rays with [`Status::Finished`].
    pub finished: usize,
    /// Rays with [`Status::MaxSteps`].
    pub max_steps: usize,
    /// Rays with [`Status::BufferFull`].
    pub buffer_full: usize,
    /// Average [`RayStats::steps`].
    pub steps_avg: f64,
    /// Median steps (the mean of the two middle values for an even count).
    pub steps_median: f64,
    /// Maximal steps.
    pub steps_max: u32,
    /// Average [`RayStats::field_evals`].
    pub field_evals_avg: f64,
    /// Average [`RayStats::bound_evals`].
    pub bound_evals_avg: f64,
    /// Average wall time of [`trace`] per ray, in nanoseconds
    /// (`std::time::Instant` around each call; the per-ray sum, so it stays
    /// meaningful with the `parallel` feature).
    pub ns_per_ray: f64,
    /// Rays that agree with the reference.
    pub agree: usize,
    /// Rays with a missed root.
    pub missed: usize,
    /// Rays with a spurious root.
    pub spurious: usize,
    /// Rays with a root far from every reference root.
    pub far: usize,
    /// Rays where the method stepped past a root (must be 0).
    pub stepped_past: usize,
    /// Rays where the method gave up before a root.
    pub gave_up: usize,
    /// Rays with a root of the wrong side (informational).
    pub wrong_side: usize,
    /// The first [`MAX_FAILURES`] disagreeing rays (and those with a wrong
    /// side), by ray index.
    pub failures: Vec<Failure>,
}

impl MethodStats {
    /// Rays traced (not unsupported).
    pub fn traced(&self) -> usize {
        self.rays - self.unsupported
    }

    /// `agree / traced`, `None` when nothing was traced.
    pub fn agree_ratio(&self) -> Option<f64> {
        let n = self.traced();
        (n > 0).then(|| self.agree as f64 / n as f64)
    }
}

/// Per-chunk accumulator of [`run_method`].
#[derive(Default)]
struct Acc {
    steps: Vec<u32>,
    field_evals: u64,
    bound_evals: u64,
    ns: u128,
    status: [usize; 4],
    verdicts: [usize; 7],
    failures: Vec<Failure>,
}

impl Acc {
    fn merge(&mut self, o: Acc) {
        self.steps.extend(o.steps);
        self.field_evals += o.field_evals;
        self.bound_evals += o.bound_evals;
        self.ns += o.ns;
        for (a, b) in self.status.iter_mut().zip(o.status) {
            *a += b;
        }
        for (a, b) in self.verdicts.iter_mut().zip(o.verdicts) {
            *a += b;
        }
        for f in o.failures {
            if self.failures.len() < MAX_FAILURES {
                self.failures.push(f);
            }
        }
    }
}

/// What [`run_method_with`] needs per ray (shared by the threads).
struct Job<'a, T, R> {
    tracer: &'a R,
    rays: &'a RaySet<T>,
    reference: &'a Reference<T>,
    mode: Mode,
    capacity: usize,
}

impl<T: Real, R: Fn(&SampleRay<T>, &mut [Root<T>]) -> Trace<T>> Job<'_, T, R> {
    fn run(&self, start: usize, rays: &[SampleRay<T>]) -> Acc {
        let mut acc = Acc::default();
        let mut buf = vec![
            Root {
                t: T::ZERO,
                side: Side::Touch,
            };
            self.capacity
        ];
        for (k, r) in rays.iter().enumerate() {
            let i = start + k;
            let clock = Instant::now();
            let tr = (self.tracer)(r, &mut buf);
            let ns = clock.elapsed().as_nanos();
            acc.status[tr.status as usize] += 1;
            if tr.status == Status::Unsupported {
                continue;
            }
            acc.ns += ns;
            let RayStats {
                steps,
                field_evals,
                bound_evals,
            } = tr.stats;
            acc.steps.push(steps);
            acc.field_evals += u64::from(field_evals);
            acc.bound_evals += u64::from(bound_evals);
            let found = &buf[..(tr.roots as usize).min(buf.len())];
            let reference = self.reference.roots(i);
            let v = classify(
                self.mode,
                self.reference.params(),
                reference,
                found,
                tr.status,
                tr.t_reached,
            );
            let flags = [
                v.agree,
                v.missed,
                v.spurious,
                v.far,
                v.stepped_past,
                v.gave_up,
                v.wrong_side,
            ];
            for (c, on) in acc.verdicts.iter_mut().zip(flags) {
                *c += usize::from(on);
            }
            if (!v.agree || v.wrong_side) && acc.failures.len() < MAX_FAILURES {
                let f64s = |p: [T; 3]| [p[0].as_f64(), p[1].as_f64(), p[2].as_f64()];
                acc.failures.push(Failure {
                    ray: i,
                    origin: f64s(r.ray.origin),
                    dir: f64s(r.ray.dir),
                    span: [r.span[0].as_f64(), r.span[1].as_f64()],
                    verdict: v,
                    status: tr.status,
                    t_reached: tr.t_reached.as_f64(),
                    roots: found
                        .iter()
                        .map(|x| Root {
                            t: x.t.as_f64(),
                            side: x.side,
                        })
                        .collect(),
                    reference: reference
                        .iter()
                        .map(|g| RefRoot {
                            t: g.t.as_f64(),
                            t_end: g.t_end.as_f64(),
                            side: g.side,
                            count: g.count,
                        })
                        .collect(),
                });
            }
        }
        acc
    }
}

/// Traces every ray of `rays` with `method` in `mode` and compares each
/// answer with `reference` ([`classify`]). In transparent mode the root
/// buffer holds `max(64, 4·most reference groups of a ray + 16)` roots.
/// With the `parallel` feature the rays are processed by rayon in chunks;
/// every count (and the failures kept) is the same as single-threaded.
///
/// # Errors
/// Invalid `params`; [`StatsError::EpsMismatch`] when `params.eps`
/// differs from the reference's; [`StatsError::RayCountMismatch`] when the
/// reference is for another ray count.
pub fn run_method<T, F>(
    field: &F,
    rays: &RaySet<T>,
    reference: &Reference<T>,
    method: Method,
    mode: Mode,
    params: &Params<T>,
) -> Result<MethodStats, StatsError>
where
    T: Real + MaybeSync + Send,
    F: Field<T> + MaybeSync,
{
    let tracer = |r: &SampleRay<T>, buf: &mut [Root<T>]| {
        trace(field, &r.ray, r.span, method, mode, params, buf)
    };
    run_method_with(&tracer, rays, reference, method, mode, params)
}

/// [`run_method`] with any per-ray tracer: `tracer(ray, roots)` traces one
/// sample ray with `method` in `mode` and `params` (used for the SCALIS
/// methods of [`crate::scalis`], which need the skeleton).
///
/// # Errors
/// As [`run_method`].
pub fn run_method_with<T, R>(
    tracer: &R,
    rays: &RaySet<T>,
    reference: &Reference<T>,
    method: Method,
    mode: Mode,
    params: &Params<T>,
) -> Result<MethodStats, StatsError>
where
    T: Real + MaybeSync + Send,
    R: Fn(&SampleRay<T>, &mut [Root<T>]) -> Trace<T> + MaybeSync,
{
    run_method_progress(tracer, rays, reference, method, mode, params, &|_| {})
}

/// [`run_method_with`], calling `on_rays(n)` (from any thread) each time
/// `n` more rays are done, outside the timed part; the result is the same.
fn run_method_progress<T, R>(
    tracer: &R,
    rays: &RaySet<T>,
    reference: &Reference<T>,
    method: Method,
    mode: Mode,
    params: &Params<T>,
    on_rays: &(dyn Fn(usize) + Sync),
) -> Result<MethodStats, StatsError>
where
    T: Real + MaybeSync + Send,
    R: Fn(&SampleRay<T>, &mut [Root<T>]) -> Trace<T> + MaybeSync,
{
    params.validate()?;
    if params.eps != reference.params().eps {
        return Err(StatsError::EpsMismatch);
    }
    if rays.len() != reference.len() {
        return Err(StatsError::RayCountMismatch {
            rays: rays.len(),
            reference: reference.len(),
        });
    }
    let most = reference.roots.iter().map(Vec::len).max().unwrap_or(0);
    let job = Job {
        tracer,
        rays,
        reference,
        mode,
        capacity: match mode {
            Mode::Opaque => 1,
            Mode::Transparent => (4 * most + 16).max(64),
        },
    };
    #[cfg(feature = "parallel")]
    let acc = {
        use rayon::prelude::*;
        let parts: Vec<Acc> = job
            .rays
            .rays()
            .par_chunks(CHUNK)
            .enumerate()
            .map(|(c, chunk)| {
                let acc = job.run(c * CHUNK, chunk);
                on_rays(chunk.len());
                acc
            })
            .collect();
        let mut acc = Acc::default();
        for p in parts {
            acc.merge(p);
        }
        acc
    };
    #[cfg(not(feature = "parallel"))]
    let acc = {
        // chunk by chunk, merged in order: the same as one run
        let mut acc = Acc::default();
        for (c, chunk) in job.rays.rays().chunks(CHUNK).enumerate() {
            acc.merge(job.run(c * CHUNK, chunk));
            on_rays(chunk.len());
        }
        acc
    };
    Ok(summarize(method, mode, rays.len(), acc))
}

fn summarize(method: Method, mode: Mode, rays: usize, mut acc: Acc) -> MethodStats {
    let traced = acc.steps.len();
    let avg = |sum: f64| if traced > 0 { sum / traced as f64 } else { 0.0 };
    acc.steps.sort_unstable();
    let steps_median = match traced {
        0 => 0.0,
        n if n % 2 == 1 => f64::from(acc.steps[n / 2]),
        n => 0.5 * (f64::from(acc.steps[n / 2 - 1]) + f64::from(acc.steps[n / 2])),
    };
    let steps_sum: u64 = acc.steps.iter().map(|&s| u64::from(s)).sum();
    let [
        agree,
        missed,
        spurious,
        far,
        stepped_past,
        gave_up,
        wrong_side,
    ] = acc.verdicts;
    MethodStats {
        method,
        mode,
        rays,
        unsupported: acc.status[Status::Unsupported as usize],
        finished: acc.status[Status::Finished as usize],
        max_steps: acc.status[Status::MaxSteps as usize],
        buffer_full: acc.status[Status::BufferFull as usize],
        steps_avg: avg(steps_sum as f64),
        steps_median,
        steps_max: acc.steps.last().copied().unwrap_or(0),
        field_evals_avg: avg(acc.field_evals as f64),
        bound_evals_avg: avg(acc.bound_evals as f64),
        ns_per_ray: avg(acc.ns as f64),
        agree,
        missed,
        spurious,
        far,
        stepped_past,
        gave_up,
        wrong_side,
        failures: acc.failures,
    }
}

/// [`Reference::compute`] for a standard scene, non-generic: the harness
/// is compiled and optimised in this crate even when the caller (an
/// unoptimised test or example) is not.
///
/// # Errors
/// As [`Reference::compute`].
#[inline(never)]
pub fn scene_reference(
    scene: &Scene<f64>,
    rays: &RaySet<f64>,
    params: &ReferenceParams<f64>,
) -> Result<Reference<f64>, StatsError> {
    Reference::compute(scene.field(), rays, params)
}

/// [`run_method`] for a standard scene, non-generic (see
/// [`scene_reference`]).
///
/// # Errors
/// As [`run_method`].
#[inline(never)]
pub fn run_scene_method(
    scene: &Scene<f64>,
    rays: &RaySet<f64>,
    reference: &Reference<f64>,
    method: Method,
    mode: Mode,
    params: &Params<f64>,
) -> Result<MethodStats, StatsError> {
    run_scene_method_with_progress(scene, rays, reference, method, mode, params, &|_| {})
}

/// [`run_scene_method`], calling `on_rays(n)` (from any thread, outside
/// the timed part) each time `n` more rays are done, for progress bars;
/// the result is the same.
///
/// # Errors
/// As [`run_method`].
#[inline(never)]
pub fn run_scene_method_with_progress(
    scene: &Scene<f64>,
    rays: &RaySet<f64>,
    reference: &Reference<f64>,
    method: Method,
    mode: Mode,
    params: &Params<f64>,
    on_rays: &(dyn Fn(usize) + Sync),
) -> Result<MethodStats, StatsError> {
    match scene.field() {
        // SCALIS skeletons: `scalis-quadratic`, and `sphere` (per-ray
        // Lipschitz) and `interval` (per-primitive ranges) through the
        // per-ray primitive lists, built per ray (timed with the ray).
        SceneField::Scalis(w)
            if matches!(
                method,
                Method::ScalisQuadratic | Method::Sphere | Method::Interval
            ) =>
        {
            let tracer = |r: &SampleRay<f64>, buf: &mut [Root<f64>]| {
                let mut storage = [crate::scalis::PrimitiveHit::empty(); SCALIS_LIST_CAPACITY];
                crate::scalis::trace_scalis_ray(
                    w.field(),
                    &r.ray,
                    r.span,
                    method,
                    mode,
                    params,
                    buf,
                    &mut storage,
                )
            };
            run_method_progress(&tracer, rays, reference, method, mode, params, on_rays)
        }
        field => {
            let tracer = |r: &SampleRay<f64>, buf: &mut [Root<f64>]| {
                trace(field, &r.ray, r.span, method, mode, params, buf)
            };
            run_method_progress(&tracer, rays, reference, method, mode, params, on_rays)
        }
    }
}

/// [`run_scene_method`] for [`Method::Sphere`] with the Lipschitz constant
/// of `lipschitz` on SCALIS scenes ([`crate::scalis::trace_scalis_sphere`],
/// through per-ray primitive lists built per ray, timed with the ray; a
/// list longer than [`SCALIS_LIST_CAPACITY`] falls back to the generic
/// `sphere`). Other scenes have no per-ray constant: their `sphere` is
/// [`run_scene_method`]'s.
///
/// # Errors
/// As [`run_method`].
pub fn run_scene_sphere(
    scene: &Scene<f64>,
    rays: &RaySet<f64>,
    reference: &Reference<f64>,
    lipschitz: crate::scalis::SphereLipschitz,
    mode: Mode,
    params: &Params<f64>,
) -> Result<MethodStats, StatsError> {
    let SceneField::Scalis(w) = scene.field() else {
        return run_scene_method(scene, rays, reference, Method::Sphere, mode, params);
    };
    let sk = w.field();
    let tracer = |r: &SampleRay<f64>, buf: &mut [Root<f64>]| {
        let mut storage = [crate::scalis::PrimitiveHit::empty(); SCALIS_LIST_CAPACITY];
        let list = crate::scalis::RayPrimitives::build(sk.segments(), &r.ray, r.span, &mut storage);
        if list.overflowed() {
            return trace(sk, &r.ray, r.span, Method::Sphere, mode, params, buf);
        }
        crate::scalis::trace_scalis_sphere(
            sk,
            list.hits(),
            &r.ray,
            r.span,
            lipschitz,
            mode,
            params,
            buf,
        )
    };
    run_method_progress(
        &tracer,
        rays,
        reference,
        Method::Sphere,
        mode,
        params,
        &|_| {},
    )
}

/// The per-ray primitive list capacity of [`run_scene_method`] for SCALIS
/// scenes (a longer list falls back to full evaluation).
pub const SCALIS_LIST_CAPACITY: usize = 512;

// ---------------------------------------------------------------------------
// Output

/// The agreement percentage, truncated (never rounded up to 100).
fn percent(ratio: f64) -> String {
    if ratio >= 1.0 {
        "100".into()
    } else {
        format!("{:.3}", (ratio * 1e5).floor() / 1e3)
    }
}

/// A Markdown table of `rows` (one scene and mode): steps (average,
/// median, max), average field and bound evaluations, time per ray, the
/// steps and time ratios against `baseline` (when it is among the traced
/// rows), the agreement percentage and the correctness counts, and rays
/// stopped at `max_steps`. A method with nothing traced shows `n/a`.
pub fn markdown_table(rows: &[MethodStats], baseline: Option<Method>) -> String {
    let base = baseline.and_then(|b| rows.iter().find(|r| r.method == b && r.traced() > 0));
    let mut s = String::new();
    s.push_str(
        "| method | rays | avg steps | median | max | field evals | bound evals | ns/ray \
         | steps ratio | time ratio | agree % | missed | spurious | far | stepped past \
         | gave up | max-steps |\n",
    );
    s.push_str("|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
    for r in rows {
        if r.traced() == 0 {
            let _ = writeln!(s, "| {} | n/a |{}", r.method, " |".repeat(15));
            continue;
        }
        let ratio = |x: f64, b: f64| {
            if b > 0.0 {
                format!("{:.2}", x / b)
            } else {
                "–".into()
            }
        };
        let (sr, tr) = match base {
            Some(b) => (
                ratio(r.steps_avg, b.steps_avg),
                ratio(r.ns_per_ray, b.ns_per_ray),
            ),
            None => ("–".into(), "–".into()),
        };
        let _ = writeln!(
            s,
            "| {} | {} | {:.2} | {} | {} | {:.2} | {:.2} | {:.0} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.method,
            r.traced(),
            r.steps_avg,
            r.steps_median,
            r.steps_max,
            r.field_evals_avg,
            r.bound_evals_avg,
            r.ns_per_ray,
            sr,
            tr,
            percent(r.agree_ratio().unwrap_or(0.0)),
            r.missed,
            r.spurious,
            r.far,
            r.stepped_past,
            r.gave_up,
            r.max_steps,
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use boundtrace_inclusion::FieldNum;

    /// `f(x) = (x − 1)(x − 1 − gap)`: two roots `gap` apart on the x axis.
    struct Pair {
        gap: f64,
    }
    impl Field<f64> for Pair {
        fn eval<N: FieldNum<f64>>(&self, p: [N; 3]) -> N {
            (p[0] - 1.0) * (p[0] - (1.0 + self.gap))
        }
    }

    /// `f(x) = (x − 1)² + c`: touches 0 at x = 1 for c = 0.
    struct Touching {
        c: f64,
    }
    impl Field<f64> for Touching {
        fn eval<N: FieldNum<f64>>(&self, p: [N; 3]) -> N {
            (p[0] - 1.0).sqr() + self.c
        }
    }

    fn x_ray() -> Ray<f64> {
        Ray::new([0.0, 0.0, 0.0], [1.0, 0.0, 0.0])
    }

    fn params() -> ReferenceParams<f64> {
        ReferenceParams::new(1e-4).unwrap()
    }

    #[test]
    fn separate_roots_are_found_with_sides() {
        for enclosures in [true, false] {
            let p = ReferenceParams {
                enclosures,
                ..params()
            };
            let r = reference_roots(&Pair { gap: 0.5 }, &x_ray(), [0.0, 3.0], &p).unwrap();
            assert_eq!(r.len(), 2, "{r:?}");
            assert!((r[0].t - 1.0).abs() <= p.tol && r[0].side == Side::Entering);
            assert!((r[1].t - 1.5).abs() <= p.tol && r[1].side == Side::Leaving);
            assert!(r.iter().all(|g| g.count == 1 && g.t == g.t_end));
        }
    }

    #[test]
    fn close_pairs_merge_and_in_cell_pairs_need_enclosures() {
        // 3e-4 apart: inside one grid cell (3/4096 ≈ 7.3e-4) but > eps.
        let p = params();
        let r = reference_roots(&Pair { gap: 3e-4 }, &x_ray(), [0.0, 3.0], &p).unwrap();
        assert_eq!(r.len(), 2, "{r:?}");
        let blind = ReferenceParams {
            enclosures: false,
            ..p
        };
        let r = reference_roots(&Pair { gap: 3e-4 }, &x_ray(), [0.0, 3.0], &blind).unwrap();
        assert!(r.is_empty(), "grid sampling alone cannot see it: {r:?}");
        // 5e-5 apart: one merged Touch group of two sign changes.
        let r = reference_roots(&Pair { gap: 5e-5 }, &x_ray(), [0.0, 3.0], &p).unwrap();
        assert_eq!(r.len(), 1, "{r:?}");
        assert_eq!((r[0].count, r[0].side), (2, Side::Touch));
        assert!(r[0].t_end > r[0].t && r[0].t_end - r[0].t <= p.eps);
    }

    #[test]
    fn tangency_is_an_optional_touch_and_misses_are_not() {
        let p = params();
        let r = reference_roots(&Touching { c: 0.0 }, &x_ray(), [0.0, 3.0], &p).unwrap();
        assert_eq!(r.len(), 1, "{r:?}");
        assert!(!r[0].certain() && (r[0].t - 1.0).abs() <= p.eps, "{r:?}");
        let r = reference_roots(&Touching { c: 0.01 }, &x_ray(), [0.0, 3.0], &p).unwrap();
        assert!(r.is_empty(), "{r:?}");
    }

    #[test]
    fn bad_input_is_an_error() {
        let p = params();
        let f = Pair { gap: 0.5 };
        assert_eq!(
            reference_roots(&f, &x_ray(), [1.0, 0.0], &p),
            Err(StatsError::Span)
        );
        assert_eq!(
            reference_roots(&f, &x_ray(), [0.0, f64::INFINITY], &p),
            Err(StatsError::Span)
        );
        let bad = ReferenceParams { cells: 0, ..p };
        assert!(matches!(
            reference_roots(&f, &x_ray(), [0.0, 1.0], &bad),
            Err(StatsError::Reference { name: "cells", .. })
        ));
        assert!(ReferenceParams::new(0.0).is_err());
        assert!(ReferenceParams::new(f64::NAN).is_err());
        assert_eq!(
            RaySet::new([[0.0; 3], [1.0, 0.0, 1.0]], 6, 1),
            Err(StatsError::Bounds)
        );
        assert_eq!(
            RaySet::new([[0.0; 3], [1.0; 3]], 0, 1),
            Err(StatsError::NoRays)
        );
        assert!(StatsError::Bounds.to_string().contains("lo < hi"));
    }

    #[test]
    fn enlarged_grows_every_side() {
        let b = enlarged([[0.0, 0.0, 0.0], [3.0, 4.0, 12.0]], 0.01);
        let want = [[-0.13, -0.13, -0.13], [3.13, 4.13, 12.13]];
        for s in 0..2 {
            for a in 0..3 {
                assert!((b[s][a] - want[s][a]).abs() < 1e-12, "{b:?}");
            }
        }
        let same = [[0.0; 3], [1.0; 3]];
        assert_eq!(enlarged(same, -1.0), same);
    }

    #[test]
    fn percent_never_rounds_up_to_100() {
        assert_eq!(percent(1.0), "100");
        assert_eq!(percent(0.999_999), "99.999");
        assert_eq!(percent(0.5), "50.000");
    }
}
