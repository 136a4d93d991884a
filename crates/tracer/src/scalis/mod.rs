//! Fast tracing of SCALIS skeletons (thesis Part III ch. 1 and ch. 2):
//! per-ray primitive lists, the `scalis-quadratic` method, per-ray
//! Lipschitz sphere tracing and per-primitive interval bisection.
//!
//! These methods need the skeleton (its segments and their supports), not a
//! generic [`Field`], so they have their own entry point, [`trace_scalis`];
//! the generic [`trace`](crate::trace()) answers
//! [`Status::Unsupported`] for [`Method::ScalisQuadratic`].
//!
//! # Ray processing
//!
//! A ray's [`PrimitiveHit`]s (the sphere-cone supports it crosses, §1.5)
//! are merged into covered *regions*; the empty space between them is
//! skipped without any evaluation (the field is `iso > 0` there). Inside a
//! region:
//!
//! - **`scalis-quadratic`** (Alg. 1 and 2, made sound): the region is
//!   pre-segmented at the argmins of the primitives' homothetic distances
//!   (§1.3.2) and each interval is processed left to right. A sum of
//!   per-primitive sound ranges (ch. 2 §2.1, by skeleton cells:
//!   [`bounds::density_bounds`], evaluated only for the primitives whose
//!   support meets the interval) that excludes the iso-value proves the
//!   interval root-free (when the cell sums cannot decide: the closed
//!   form's range on short intervals, then tight ranges for grazing
//!   stretches — [`bounds::log_concave_range`] for constant radii,
//!   quadratic Taylor models built at the interval's midpoint
//!   ([`bounds::taylor_model_at`]) per primitive and summed, with the
//!   second derivative enclosed on [`FINE_PIECES`] pieces when one piece
//!   is too wide; so does a field with the same strict sign at both ends
//!   whose summed models bound its derivative away from 0
//!   ([`bounds::taylor_model_slope`]: monotone, so root-free);
//!   otherwise the interval is split where the oracle of §1.4 predicts the
//!   root: the first root of the smooth piecewise-quadratic Bézier
//!   interpolant (eq. 1.10) of the Hermite data of the **normalized field**
//!   `g∘f∘δ − 1` at its ends, rational with middle weight 3 until a sign
//!   change isolates a root (Fig. 1.7), polynomial afterwards — or, before
//!   a sign change, the Newton step from the left end when it lies
//!   further (the far end's data pull the interpolant's root short on
//!   long intervals of a near-linear approach). The split
//!   is made at `t_root ± 0.45·eps`, so a correct prediction brackets the
//!   root in one step; a wrong one costs a bisection-like step. The thesis'
//!   oracle *rejects* intervals where it predicts no root (a heuristic that
//!   can miss thin features, §1.8); here only a sound range may reject, so
//!   the method never misses a root, and the oracle only decides where to
//!   split (the saved interval of Alg. 1 is the explicit stack).
//! - **`interval`** (ch. 2 §2.2): the same pre-segmented processing with
//!   midpoint splits (bisection); on intervals shorter than
//!   [`REFINE_EPS`]` · eps` with a sign change, the split point comes from
//!   the polynomial interpolant (polynomial refinement).
//! - **`sphere`** with the per-ray Lipschitz bound of §1.7: the region is
//!   cut where the set of crossed supports changes, and sphere tracing runs
//!   on each piece with the sum of the directional Lipschitz bounds
//!   ([`ScalisSegment::directional_lipschitz`], ch. 2 §2.1.1) of the
//!   primitives whose support the piece crosses — instead of one global
//!   constant that the thinnest primitive of the whole skeleton dictates
//!   ([`SphereLipschitz::PerWindow`]). [`trace_scalis_sphere`] also runs
//!   it with **one constant per ray** ([`SphereLipschitz::PerRay`]), the
//!   granularity of §1.7: the sum of those bounds over every primitive
//!   the ray crosses, each over its whole crossing (directional, so still
//!   tighter than the thesis' isotropic bound from the smallest radius).
//!
//! Every other method runs the generic [`trace`](crate::trace()) on the whole
//! skeleton.
//!
//! Root conventions are the crate's: a crossing is reported within `eps`
//! of a true root with its side; an interval no longer than
//! `eps / 2^TOUCH_DEPTH` whose range contains `0` without a sign change is
//! a [`Side::Touch`].

pub mod bounds;
pub mod list;

#[cfg(feature = "alloc")]
pub use list::PrimitiveLists;
pub use list::{ListError, PrimitiveHit, RayPrimitives, check_segments, for_each_region};

use crate::march::{StepGuard, TOUCH_DEPTH, Unguarded, Walk, sign_of};
use crate::method::{Method, Mode, Params};
use crate::trace::{Leg, RayStats, Root, Side, Status, Trace, trace};
use boundtrace_fields::scalis::{ScalisSegment, ScalisSkeleton};
use boundtrace_ia_core::{Interval, Real, round};
use boundtrace_inclusion::{Field, FieldNum, Jet, Ray};

/// Intervals shorter than this many `eps` with a sign change are split by
/// the polynomial interpolant in the `interval` method (refinement).
pub const REFINE_EPS: f64 = 1024.0;

/// Skeleton cells per primitive of the first range of an interval.
pub const CELLS: u32 = 16;

/// Skeleton cells per primitive of the second range, when the first one
/// cannot decide.
pub const FINE_CELLS: u32 = 64;

/// Ray intervals shorter than this fraction of a primitive's smallest
/// radius also get the closed form's range
/// ([`ScalisSegment::density_range`]: end-point values and monotony from
/// its derivative enclosure), costly but tight on short intervals, where
/// the cell sums are not (their error does not shrink with the interval).
pub const CLOSED_FORM_WIDTH: f64 = 1.0;

/// The depth of the explicit interval stack of the pre-segmented
/// processing (intervals that cannot be split further are leaves).
pub const STACK_CAPACITY: usize = 64;

/// The middle weight of the rational Bézier oracle before a root is
/// isolated (thesis §1.4.2: "a weight equal to 3 … was sufficient").
pub const ORACLE_WEIGHT: f64 = 3.0;

/// The pieces of a ray interval on which the second derivative of each
/// primitive is enclosed (the hull of the pieces' closed-form enclosures)
/// in the second pass of the tight stage ([`bounds::taylor_model_at`]):
/// an interval enclosure of the closed form over the whole interval is
/// hundreds of times the true `f''` on grazing stretches, and it shrinks
/// faster than the pieces.
pub const FINE_PIECES: u32 = 16;

/// The second pass with [`FINE_PIECES`] runs only where a second
/// derivative this many times narrower (placed as favourably as it can
/// be) would decide the interval: a cost filter, never a proof.
const FINE_GAIN: f64 = 64.0;

/// Traces `ray` on `span` through the SCALIS `skeleton` with `method` (see
/// the module docs), using `hits`, the ray's **complete** list of support
/// crossings on `span` ([`RayPrimitives`] that did not overflow, or
/// [`PrimitiveLists`]); every other method runs the generic
/// [`trace`](crate::trace()) on the skeleton.
///
/// [`Status::Unsupported`] for invalid parameters or span, an empty root
/// buffer, or a skeleton with an infinite (Cauchy) support when the method
/// needs the lists.
#[allow(clippy::too_many_arguments)]
pub fn trace_scalis<T: Real, S: AsRef<[ScalisSegment<T>]>>(
    skeleton: &ScalisSkeleton<T, S>,
    hits: &[PrimitiveHit<T>],
    ray: &Ray<T>,
    span: [T; 2],
    method: Method,
    mode: Mode,
    params: &Params<T>,
    roots: &mut [Root<T>],
) -> Trace<T> {
    let unsupported = Trace {
        roots: 0,
        status: Status::Unsupported,
        t_reached: span[0],
        stats: RayStats::default(),
    };
    if params.validate().is_err() || !(span[0] <= span[1]) || roots.is_empty() {
        return unsupported;
    }
    let segments = skeleton.segments();
    match method {
        Method::ScalisQuadratic | Method::Interval => {}
        Method::Sphere => {
            // validated above but for the segments
            if check_segments(segments).is_err() {
                return unsupported;
            }
            return sphere_per_ray(
                skeleton,
                hits,
                ray,
                span,
                SphereLipschitz::PerWindow,
                mode,
                params,
                roots,
            );
        }
        _ => return trace(skeleton, ray, span, method, mode, params, roots),
    }
    let len = roots.len();
    trace_scalis_in(
        segments,
        skeleton.iso(),
        hits,
        [0, hits.len()],
        ray,
        span,
        method,
        mode,
        params,
        roots,
        [0, len],
    )
}

/// [`trace_scalis`]'s `scalis-quadratic` and `interval` (the pre-segmented
/// processing, module docs) over flat data: the GPU shader's form. The
/// skeleton is `segments` with the iso-value `iso` (what
/// [`ScalisSkeleton::new`] accepts; a segment with an infinite support
/// gives [`Status::Unsupported`]); the ray's complete hit list is
/// `lists[list[0]..list[0] + list[1]]` (a window of the hit lists of a
/// whole frame, [`PrimitiveLists`] on the host); roots are written to the
/// window `roots[window[0]..window[0] + window[1]]`, as in
/// [`trace_in`](crate::trace_in). Indices, loops and no sub-slices, no
/// `Option` or `Result` of a trace, no closure: what rust-gpu compiles.
///
/// [`Status::Unsupported`] for another method, invalid parameters or span,
/// an empty or out-of-range root window or hit list.
#[allow(clippy::too_many_arguments)]
pub fn trace_scalis_in<T: Real>(
    segments: &[ScalisSegment<T>],
    iso: T,
    lists: &[PrimitiveHit<T>],
    list: [usize; 2],
    ray: &Ray<T>,
    span: [T; 2],
    method: Method,
    mode: Mode,
    params: &Params<T>,
    roots: &mut [Root<T>],
    window: [usize; 2],
) -> Trace<T> {
    let mut state = ScalisState::start();
    trace_scalis_resume_in(
        segments,
        iso,
        lists,
        list,
        ray,
        span,
        method,
        mode,
        params,
        roots,
        window,
        &mut state,
        &mut Unguarded,
    )
    .trace
}

/// [`trace_scalis_in`] in legs: the same trace from `state` (start with
/// [`ScalisState::start`], all zeros), pausing where `guard` says so and
/// saving where it stopped into `state` — the GPU's form, for a driver
/// that cuts long loops (lavapipe), as
/// [`trace_sphere_resume_in`](crate::trace_sphere_resume_in) is for the
/// marching methods. Called again with the same arguments and the saved
/// state, it goes on exactly where it stopped: the legs of a trace give the
/// roots, record and counters of the uninterrupted [`trace_scalis_in`],
/// whatever the pauses.
///
/// One iteration of the processing (the point evaluations one interval
/// asked for, then the interval taken from the stack, thesis Part III
/// §1.3–1.4) is one step between two guard calls: an iteration the guard
/// rejects after it ran ([`StepGuard::after_step`]) is undone — the state,
/// the stack entry it overwrote and the last root — and redone in the
/// next leg. The first iteration checks the segments' supports, each
/// region of overlapping supports starts with one that merges its hits.
///
/// ```
/// use boundtrace_fields::homothetic::{Segment, SegmentKernel};
/// use boundtrace_fields::scalis::{ScalisSegment, ScalisSkeleton};
/// use boundtrace_inclusion::Ray;
/// use boundtrace_tracer::march::StepGuard;
/// use boundtrace_tracer::scalis::{
///     PrimitiveHit, RayPrimitives, ScalisState, trace_scalis_in, trace_scalis_resume_in,
/// };
/// use boundtrace_tracer::{Method, Mode, Params, Root, Side};
///
/// let k = SegmentKernel::compact_polynomial(6, 2.0).unwrap();
/// let bone = Segment::new([0.0, -1.0, 0.0], 0.1, [0.0, 1.0, 0.0], 0.15).unwrap();
/// let sk = ScalisSkeleton::new([ScalisSegment::new(bone, k, 1.0).unwrap()]).unwrap();
/// let ray = Ray::new([-2.0, 0.05, 0.02], [1.0, 0.0, 0.0]);
/// let mut store = [PrimitiveHit::empty(); 4];
/// let hits = RayPrimitives::build(sk.segments(), &ray, [0.0, 6.0], &mut store).hits().to_vec();
/// let (p, m) = (Params::new(), Method::ScalisQuadratic);
/// let none = Root { t: 0.0, side: Side::Touch };
/// let mut whole = [none; 4];
/// let once = trace_scalis_in(
///     sk.segments(), sk.iso(), &hits, [0, hits.len()], &ray, [0.0, 6.0], m,
///     Mode::Transparent, &p, &mut whole, [0, 4],
/// );
/// /// Two iterations per leg.
/// struct Two(u32);
/// impl StepGuard for Two {
///     fn before_step(&mut self, _: u32) -> bool { self.0 += 1; self.0 <= 2 }
///     fn after_step(&mut self) -> bool { true }
/// }
/// let (mut state, mut roots, mut legs) = (ScalisState::start(), [none; 4], 0);
/// let last = loop {
///     legs += 1;
///     let leg = trace_scalis_resume_in(
///         sk.segments(), sk.iso(), &hits, [0, hits.len()], &ray, [0.0, 6.0], m,
///         Mode::Transparent, &p, &mut roots, [0, 4], &mut state, &mut Two(0),
///     );
///     if !leg.paused {
///         break leg.trace;
///     }
/// };
/// assert_eq!(once.roots, 2);
/// assert!(legs > 2);
/// assert_eq!((last, roots), (once, whole));
/// ```
#[allow(clippy::too_many_arguments)]
pub fn trace_scalis_resume_in<T: Real, G: StepGuard>(
    segments: &[ScalisSegment<T>],
    iso: T,
    lists: &[PrimitiveHit<T>],
    list: [usize; 2],
    ray: &Ray<T>,
    span: [T; 2],
    method: Method,
    mode: Mode,
    params: &Params<T>,
    roots: &mut [Root<T>],
    window: [usize; 2],
    state: &mut ScalisState<T>,
    guard: &mut G,
) -> Leg<T> {
    scalis_resume::<T, G, false>(
        segments, iso, lists, list, ray, span, method, mode, params, roots, window, state, guard,
    )
}

/// [`trace_scalis_resume_in`] without the tight stage (the log-concave
/// ranges and the Taylor models of the grazing stretches, most of the
/// code): an interval that needs it is left in the state
/// ([`ScalisWalk::tight`], status [`TIGHT_REQUESTED`]) and the leg pauses;
/// [`scalis_tight_resume_in`] runs it, and the next leg goes on with its
/// verdict. A GPU compiles the two as two entry points, each much smaller
/// than the whole (a driver that inlines every call compiles the whole in
/// more memory than a machine has). Alternating the two until a leg is
/// not paused gives the uninterrupted [`trace_scalis_in`]'s roots, record
/// and counters, whatever the pauses.
#[allow(clippy::too_many_arguments)]
pub fn trace_scalis_resume_deferred_in<T: Real, G: StepGuard>(
    segments: &[ScalisSegment<T>],
    iso: T,
    lists: &[PrimitiveHit<T>],
    list: [usize; 2],
    ray: &Ray<T>,
    span: [T; 2],
    method: Method,
    mode: Mode,
    params: &Params<T>,
    roots: &mut [Root<T>],
    window: [usize; 2],
    state: &mut ScalisState<T>,
    guard: &mut G,
) -> Leg<T> {
    scalis_resume::<T, G, true>(
        segments, iso, lists, list, ray, span, method, mode, params, roots, window, state, guard,
    )
}

/// The tight stage that [`trace_scalis_resume_deferred_in`] left in
/// `state` (status [`TIGHT_REQUESTED`]), for the same ray and hit list, in
/// legs: one hit of a pass per step, `guard` asked before and after each
/// (a step it rejects after it ran is undone). `true` once the stage has
/// its verdict (or there is none to run), `false` when paused. A state
/// whose region does not lie in the list gets the verdict "not proven
/// root-free", which is always sound (the interval is split further).
#[allow(clippy::too_many_arguments)]
pub fn scalis_tight_resume_in<T: Real, G: StepGuard>(
    segments: &[ScalisSegment<T>],
    iso: T,
    lists: &[PrimitiveHit<T>],
    list: [usize; 2],
    ray: &Ray<T>,
    state: &mut ScalisState<T>,
    guard: &mut G,
) -> bool {
    let walk = &mut state.walk;
    if walk.tight.status != TIGHT_REQUESTED {
        return true;
    }
    let (lo, n) = (list[0], list[1]);
    let (first, next) = (walk.first as usize, walk.next as usize);
    if lo > lists.len() || n > lists.len() - lo || first > next || next > n {
        walk.tight.status = TIGHT_NOT_FREE;
        return true;
    }
    let ctx = Ctx {
        segments,
        hits: lists,
        iso,
        ray,
    };
    let hits = HitRange {
        start: lo + first,
        end: lo + next,
    };
    loop {
        if !guard.before_step(walk.stats.steps) {
            return false;
        }
        let (tight, evals) = (walk.tight, walk.stats.bound_evals);
        let done = ctx.tight_step(&mut walk.tight, hits, &mut walk.stats);
        if !guard.after_step() {
            walk.tight = tight;
            walk.stats.bound_evals = evals;
            return false;
        }
        if done {
            return true;
        }
    }
}

/// [`trace_scalis_resume_in`] (`DEFER` false) and
/// [`trace_scalis_resume_deferred_in`] (`DEFER` true).
#[allow(clippy::too_many_arguments)]
fn scalis_resume<T: Real, G: StepGuard, const DEFER: bool>(
    segments: &[ScalisSegment<T>],
    iso: T,
    lists: &[PrimitiveHit<T>],
    list: [usize; 2],
    ray: &Ray<T>,
    span: [T; 2],
    method: Method,
    mode: Mode,
    params: &Params<T>,
    roots: &mut [Root<T>],
    window: [usize; 2],
    state: &mut ScalisState<T>,
    guard: &mut G,
) -> Leg<T> {
    let unsupported = Leg {
        paused: false,
        trace: Trace {
            roots: 0,
            status: Status::Unsupported,
            t_reached: span[0],
            stats: RayStats::default(),
        },
    };
    let split = if method == Method::ScalisQuadratic {
        Split::Oracle
    } else if method == Method::Interval {
        Split::Bisection
    } else {
        return unsupported;
    };
    let [base, len] = window;
    let (lo, n) = (list[0], list[1]);
    if !params.is_valid()
        || !(span[0] <= span[1])
        || len == 0
        || base > roots.len()
        || len > roots.len() - base
        || lo > lists.len()
        || n > lists.len() - lo
        || state.walk.sp as usize > STACK_CAPACITY
        || state.walk.roots as usize > len
    {
        return unsupported;
    }
    let ctx = Ctx {
        segments,
        hits: lists,
        iso,
        ray,
    };
    let slots = crate::march::RootSlots {
        buf: roots,
        base,
        len,
    };
    let mut w = Walk::new(slots, mode, params.eps);
    w.n = state.walk.roots;
    w.stats = state.walk.stats;
    let end = lo + n;
    let zero = ScalisPoint::new(T::ZERO, Interval::point(T::ZERO));
    loop {
        if !guard.before_step(w.stats.steps) {
            return Leg {
                paused: true,
                trace: w.done(Status::Finished, state.walk.region[0]),
            };
        }
        // What this iteration may overwrite, to undo it.
        let saved = state.walk;
        let sp = saved.sp as usize;
        let top = if sp > 0 {
            state.stack[sp - 1]
        } else {
            [zero; 2]
        };
        let last = if w.n > 0 {
            w.roots.get(w.n as usize - 1)
        } else {
            Root {
                t: T::ZERO,
                side: Side::Touch,
            }
        };
        let flow = if state.walk.started == 0 {
            state.walk.started = 1;
            if finite_supports(segments) {
                Flow::go()
            } else {
                Flow::stop(unsupported.trace)
            }
        } else if state.walk.in_region == 0 {
            // the next merged covered region (`for_each_region`)
            let i = lo + state.walk.next as usize;
            if i >= end {
                Flow::stop(w.done(Status::Finished, span[1]))
            } else {
                let (start, mut stop) = (lists[i].entry, lists[i].exit);
                let mut j = i + 1;
                while j < end && lists[j].entry <= stop {
                    stop = stop.max(lists[j].exit);
                    j += 1;
                }
                let (a, b) = (start.max(span[0]), stop.min(span[1]));
                state.walk.first = (i - lo) as u32;
                state.walk.next = (j - lo) as u32;
                if a <= b {
                    state.walk.start_region([a, b]);
                }
                Flow::go()
            }
        } else {
            let hits = HitRange {
                start: lo + state.walk.first as usize,
                end: lo + state.walk.next as usize,
            };
            let flow = region_iteration::<T, DEFER>(&ctx, state, hits, params, split, &mut w);
            if flow.done {
                state.walk.in_region = 0;
            }
            flow
        };
        if !guard.after_step() {
            // undo the iteration: it is done again in the next leg
            state.walk = saved;
            if sp > 0 {
                state.stack[sp - 1] = top;
            }
            if saved.roots > 0 {
                w.roots.set(saved.roots as usize - 1, last);
            }
            w.n = saved.roots;
            w.stats = saved.stats;
            return Leg {
                paused: true,
                trace: w.done(Status::Finished, state.walk.region[0]),
            };
        }
        state.walk.roots = w.n;
        state.walk.stats = w.stats;
        if flow.stop {
            return Leg {
                paused: false,
                trace: flow.trace,
            };
        }
        if flow.wait {
            return Leg {
                paused: true,
                trace: w.done(Status::Finished, state.walk.region[0]),
            };
        }
    }
}

/// Whether every segment has a finite (compact) support: the lists'
/// precondition ([`check_segments`] without an error value).
fn finite_supports<T: Real>(segments: &[ScalisSegment<T>]) -> bool {
    let mut i = 0;
    while i < segments.len() {
        if !segments[i].has_compact_support() {
            return false;
        }
        i += 1;
    }
    true
}

/// Where [`trace_scalis_resume_in`] resumes: the pre-segmented
/// processing's loop state ([`ScalisWalk`]) and its explicit interval
/// stack. `#[repr(C)]`, with no `bool` or enum field, so that a GPU keeps
/// one per pixel in a storage buffer; all zeros
/// ([`start`](Self::start)) is a trace not begun.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct ScalisState<T> {
    /// Everything but the stack.
    pub walk: ScalisWalk<T>,
    /// The intervals still to examine, `stack[..walk.sp]` (each a pair of
    /// end points with their enclosures), the next one last.
    pub stack: [[ScalisPoint<T>; 2]; STACK_CAPACITY],
}

impl<T: Real> ScalisState<T> {
    /// The state before the first iteration (all zeros).
    pub fn start() -> Self {
        let zero = ScalisPoint::new(T::ZERO, Interval::point(T::ZERO));
        Self {
            walk: ScalisWalk {
                started: 0,
                in_region: 0,
                first: 0,
                next: 0,
                region: [T::ZERO; 2],
                roots: 0,
                stats: RayStats::default(),
                sp: 0,
                cur_pending: 0,
                kind: PENDING_START,
                nreq: 0,
                req: [T::ZERO; 2],
                fix: [0; 2],
                cur: zero,
                split: [zero; 2],
                pair: [zero; 2],
                tight: ScalisTight::none(),
            },
            stack: [[zero; 2]; STACK_CAPACITY],
        }
    }
}

/// The loop state of [`ScalisState`] but its stack (`#[repr(C)]`, flags
/// as `u32`): where the trace is in the ray's list of hits, the covered
/// region being processed, the roots and counters so far, and the points
/// the last iteration asked for (evaluated at the top of the next one).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct ScalisWalk<T> {
    /// `1` once the segments' supports were checked (the first
    /// iteration).
    pub started: u32,
    /// `1` while a covered region is processed.
    pub in_region: u32,
    /// The region's first hit, relative to the ray's list.
    pub first: u32,
    /// The hit after the region's last, relative to the ray's list: where
    /// the next region starts.
    pub next: u32,
    /// The region `[r0, r1]` (clipped to the span).
    pub region: [T; 2],
    /// Roots registered so far.
    pub roots: u32,
    /// The counters so far.
    pub stats: RayStats,
    /// The stack's height.
    pub sp: u32,
    /// `1` while the cursor's point is not yet evaluated.
    pub cur_pending: u32,
    /// What the requested points are for: [`PENDING_START`],
    /// [`PENDING_SPLIT`] or [`PENDING_TOUCH_END`].
    pub kind: u32,
    /// How many points are requested, `req[..nreq]`.
    pub nreq: u32,
    /// The requested points.
    pub req: [T; 2],
    /// [`PENDING_TOUCH_END`]: whether the stack's top interval's start and
    /// the cursor move to the requested point.
    pub fix: [u32; 2],
    /// The cursor: where the next pre-segmented interval starts.
    pub cur: ScalisPoint<T>,
    /// [`PENDING_SPLIT`]: the interval cut at the requested points.
    pub split: [ScalisPoint<T>; 2],
    /// The interval taken from the stack whose tight stage runs (or ran)
    /// in [`tight`](Self::tight).
    pub pair: [ScalisPoint<T>; 2],
    /// The tight stage of `pair`.
    pub tight: ScalisTight<T>,
}

impl<T: Real> ScalisWalk<T> {
    /// Starts processing the covered region `r` (its hits were set).
    fn start_region(&mut self, r: [T; 2]) {
        let origin = ScalisPoint::new(r[0], Interval::point(T::ZERO));
        self.in_region = 1;
        self.region = r;
        self.sp = 0;
        self.cur = origin;
        self.cur_pending = 1;
        self.kind = PENDING_START;
        self.req = [r[0]; 2];
        self.nreq = 0;
        self.split = [origin; 2];
        self.fix = [0; 2];
    }
}

/// [`ScalisWalk::kind`]: the cursor's point (when not yet evaluated) and
/// the next argmin's, which start a pre-segmented interval (none: nothing
/// to evaluate).
pub const PENDING_START: u32 = 0;
/// [`ScalisWalk::kind`]: the cuts of [`ScalisWalk::split`], pushed as
/// sub-intervals.
pub const PENDING_SPLIT: u32 = 1;
/// [`ScalisWalk::kind`]: the end of a touch, for the stack's top interval
/// and the cursor ([`ScalisWalk::fix`]).
pub const PENDING_TOUCH_END: u32 = 2;

/// The tight stage of one interval between two steps (`#[repr(C)]`, flags
/// as `u32`, 18 words): [`ScalisWalk::tight`], where a GPU's tracing legs
/// leave an interval their ranges could not decide for a smaller entry
/// point of its own ([`scalis_tight_resume_in`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct ScalisTight<T> {
    /// [`TIGHT_NONE`], [`TIGHT_REQUESTED`] (running), [`TIGHT_FREE`] or
    /// [`TIGHT_NOT_FREE`].
    pub status: u32,
    /// The interval `[a, b]`.
    pub ab: [T; 2],
    /// Where the Taylor models are built (its midpoint).
    pub c: T,
    /// The enclosure of `iso − f` on `[a, b]` so far.
    pub r: Interval<T>,
    /// `1` when both ends have the same strict sign.
    pub same: u32,
    /// The pieces of this pass (`1`, then [`FINE_PIECES`]).
    pub pieces: u32,
    /// The pass's next hit, relative to the region's first.
    pub k: u32,
    /// The pass's sum of per-primitive ranges so far.
    pub sum: Interval<T>,
    /// The pass's summed Taylor model so far (`f0`, `f'`, `f''`).
    pub model: [Interval<T>; 3],
    /// `1` while every primitive so far has a Taylor model.
    pub whole: u32,
}

impl<T: Real> ScalisTight<T> {
    /// No tight stage (all zeros).
    fn none() -> Self {
        let zero = Interval::point(T::ZERO);
        Self {
            status: TIGHT_NONE,
            ab: [T::ZERO; 2],
            c: T::ZERO,
            r: zero,
            same: 0,
            pieces: 0,
            k: 0,
            sum: zero,
            model: [zero; 3],
            whole: 0,
        }
    }

    /// The tight stage of `[a.t, b.t]`, whose range so far is `r`.
    fn start(a: &ScalisPoint<T>, b: &ScalisPoint<T>, r: Interval<T>) -> Self {
        let same = (a.f.lo() > T::ZERO && b.f.lo() > T::ZERO)
            || (a.f.hi() < T::ZERO && b.f.hi() < T::ZERO);
        let (a, b) = (a.t, b.t);
        // the models are built at the midpoint (a quarter of the quadratic
        // term of a model built at an end)
        let c = (a + (b - a) * T::HALF).max(a).min(b);
        Self {
            status: TIGHT_REQUESTED,
            ab: [a, b],
            c,
            r,
            same: u32::from(same),
            pieces: 1,
            whole: 1,
            ..Self::none()
        }
    }
}

/// [`ScalisTight::status`]: no tight stage.
pub const TIGHT_NONE: u32 = 0;
/// [`ScalisTight::status`]: the tight stage is running (or, in a GPU's
/// tracing legs, waiting for [`scalis_tight_resume_in`]).
pub const TIGHT_REQUESTED: u32 = 1;
/// [`ScalisTight::status`]: the interval is proven root-free.
pub const TIGHT_FREE: u32 = 2;
/// [`ScalisTight::status`]: the tight stage could not prove it.
pub const TIGHT_NOT_FREE: u32 = 3;

/// Where the Lipschitz constant of SCALIS sphere tracing
/// ([`trace_scalis_sphere`]) is valid.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SphereLipschitz {
    /// One constant per window of the ray between two support entries or
    /// exits: the sum of the directional bounds of the primitives whose
    /// support the window crosses, over the window (what `sphere` in
    /// [`trace_scalis`] uses).
    PerWindow,
    /// One constant for the whole ray (thesis Part III §1.7, "per primitive
    /// and per ray"): the sum over every primitive the ray crosses on the
    /// span of its directional bound over its whole crossing.
    PerRay,
}

/// Sphere tracing of a SCALIS skeleton through the ray's primitive list,
/// with the Lipschitz constant of `lipschitz` (module docs); empty space
/// between supports is skipped in both cases. `hits`, `span`, `mode`,
/// `params` and `roots` are as for [`trace_scalis`], whose `sphere` is
/// this function with [`SphereLipschitz::PerWindow`].
///
/// [`Status::Unsupported`] for invalid parameters or span, an empty root
/// buffer, or a skeleton with an infinite (Cauchy) support.
#[allow(clippy::too_many_arguments)]
pub fn trace_scalis_sphere<T: Real, S: AsRef<[ScalisSegment<T>]>>(
    skeleton: &ScalisSkeleton<T, S>,
    hits: &[PrimitiveHit<T>],
    ray: &Ray<T>,
    span: [T; 2],
    lipschitz: SphereLipschitz,
    mode: Mode,
    params: &Params<T>,
    roots: &mut [Root<T>],
) -> Trace<T> {
    if params.validate().is_err()
        || !(span[0] <= span[1])
        || roots.is_empty()
        || check_segments(skeleton.segments()).is_err()
    {
        return Trace {
            roots: 0,
            status: Status::Unsupported,
            t_reached: span[0],
            stats: RayStats::default(),
        };
    }
    sphere_per_ray(skeleton, hits, ray, span, lipschitz, mode, params, roots)
}

/// [`trace_scalis`] that builds the ray's primitive list in `storage`
/// first ([`RayPrimitives::build`]); when the storage overflows, the
/// methods that need the list fall back to the generic tracer on the whole
/// skeleton (`scalis-quadratic` to `segment`, the others to themselves):
/// slower, never wrong.
#[allow(clippy::too_many_arguments)]
pub fn trace_scalis_ray<T: Real, S: AsRef<[ScalisSegment<T>]>>(
    skeleton: &ScalisSkeleton<T, S>,
    ray: &Ray<T>,
    span: [T; 2],
    method: Method,
    mode: Mode,
    params: &Params<T>,
    roots: &mut [Root<T>],
    storage: &mut [PrimitiveHit<T>],
) -> Trace<T> {
    let list = RayPrimitives::build(skeleton.segments(), ray, span, storage);
    if list.overflowed() {
        let m = if method == Method::ScalisQuadratic {
            Method::Segment
        } else {
            method
        };
        return trace(skeleton, ray, span, m, mode, params, roots);
    }
    trace_scalis(
        skeleton,
        list.hits(),
        ray,
        span,
        method,
        mode,
        params,
        roots,
    )
}

/// How the pre-segmented processing splits an undecided interval.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Split {
    /// At the oracle's predicted root (`scalis-quadratic`).
    Oracle,
    /// At the midpoint, the oracle on short bracketed intervals (`interval`).
    Bisection,
}

/// A range `start..end` of [`Ctx::hits`] (an index range rather than a
/// sub-slice: rust-gpu cannot sub-slice a storage buffer).
#[derive(Clone, Copy)]
struct HitRange {
    start: usize,
    end: usize,
}

/// Whether an iteration of [`region_iteration`] goes on, ends its region
/// (`done`), or stops tracing with `trace` (a struct rather than
/// `Result<(), Trace>`: rust-gpu 0.11 cannot move a `Trace` out of an
/// enum).
#[derive(Clone, Copy)]
struct Flow<T> {
    stop: bool,
    done: bool,
    /// The iteration left its interval's tight stage to
    /// [`scalis_tight_resume_in`] (or waits for it): the leg pauses.
    wait: bool,
    trace: Trace<T>,
}

impl<T: Real> Flow<T> {
    fn go() -> Self {
        Self {
            stop: false,
            done: false,
            wait: false,
            trace: Trace {
                roots: 0,
                status: Status::Finished,
                t_reached: T::ZERO,
                stats: RayStats::default(),
            },
        }
    }
    fn done() -> Self {
        Self {
            done: true,
            ..Self::go()
        }
    }
    fn wait() -> Self {
        Self {
            wait: true,
            ..Self::go()
        }
    }
    fn stop(trace: Trace<T>) -> Self {
        Self {
            stop: true,
            done: false,
            wait: false,
            trace,
        }
    }
}

/// One ray through the skeleton, with its hits.
struct Ctx<'a, T> {
    segments: &'a [ScalisSegment<T>],
    hits: &'a [PrimitiveHit<T>],
    iso: T,
    ray: &'a Ray<T>,
}

/// A point of the ray with an enclosure of `iso − f` there and, once
/// computed (`has_herm == 1`), the Hermite data `herm = (G, G')` of the
/// normalized field (`#[repr(C)]`, 6 words: an entry of
/// [`ScalisState::stack`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct ScalisPoint<T> {
    /// The ray parameter.
    pub t: T,
    /// The enclosure of `iso − f(t)`.
    pub f: Interval<T>,
    /// `1` when `herm` holds the Hermite data.
    pub has_herm: u32,
    /// `(G, G')` at `t`.
    pub herm: [T; 2],
}

impl<T: Real> ScalisPoint<T> {
    /// `t` with the enclosure `f`, no Hermite data yet.
    fn new(t: T, f: Interval<T>) -> Self {
        Self {
            t,
            f,
            has_herm: 0,
            herm: [T::ZERO; 2],
        }
    }
}

/// `true` unless the field is proven positive (the bisection's convention).
#[inline]
fn inside<T: Real>(f: Interval<T>) -> bool {
    !(f.lo() > T::ZERO)
}

impl<T: Real> Ctx<'_, T> {
    fn seg(&self, h: &PrimitiveHit<T>) -> &ScalisSegment<T> {
        &self.segments[h.index as usize]
    }

    /// A sound enclosure of `iso − f` at `t`, from the hits whose
    /// `[entry, exit]` contains `t` (the others are exactly `0` there).
    fn value(&self, hits: HitRange, t: T) -> Interval<T> {
        Interval::point(self.iso) - self.density_at::<Interval<T>>(hits, t)
    }

    /// The density `f(o + t·d)` in `N`, summed over the hits whose
    /// `[entry, exit]` contains `t` (the others are exactly `0` there).
    fn density_at<N: FieldNum<T>>(&self, hits: HitRange, t: T) -> N {
        let p = self.ray.at::<N>(t, t);
        let mut acc = N::constant(T::ZERO);
        let mut k = hits.start;
        while k < hits.end {
            let h = self.hits[k];
            k += 1;
            if h.entry > t {
                break;
            }
            if h.exit >= t {
                acc = acc + self.seg(&h).density(p);
            }
        }
        acc
    }

    /// `(G, G')` of the normalized field `g(f(o + t·d)) − 1` at `t`.
    fn hermite(&self, hits: HitRange, t: T) -> [T; 2] {
        let acc = self.density_at::<Jet<T>>(hits, t);
        let s = self.seg(&self.hits[hits.start]);
        if !(acc.v > T::ZERO) {
            // outside every support: g(0) − 1, flat
            let g0 = s.g(Jet::constant(T::ZERO));
            return [g0.v - T::ONE, T::ZERO];
        }
        let g = s.g(acc);
        [g.v - T::ONE, g.d1]
    }

    /// A sound enclosure of `iso − f` on `[a, b]`: the sum over the hits
    /// whose support meets it of their per-primitive ranges by skeleton
    /// cells ([`bounds::density_bounds`] on the part of `[a, b]` inside the
    /// hit's `[entry, exit]`, joined with `0` when that is only a part;
    /// [`CELLS`] cells, then [`FINE_CELLS`] when the first sum cannot
    /// decide, then intersected with the closed form's range on short
    /// intervals, [`CLOSED_FORM_WIDTH`]; the tight stage,
    /// [`tight_density`](Self::tight_density), follows in
    /// [`root_free`](Self::root_free)). `stats` counts one bound
    /// evaluation per stage.
    fn range(&self, hits: HitRange, a: T, b: T, stats: &mut RayStats) -> Interval<T> {
        let zero = Interval::point(T::ZERO);
        let mut r = Interval::ENTIRE;
        let mut stage = 0;
        while stage < 3 {
            stats.bound_evals += 1;
            let mut acc = zero;
            let mut k = hits.start;
            while k < hits.end {
                let h = self.hits[k];
                k += 1;
                if h.entry > b {
                    break;
                }
                if h.exit < a {
                    continue;
                }
                let (u, v) = (a.max(h.entry), b.min(h.exit));
                let s = self.seg(&h);
                let cells = if stage == 0 { CELLS } else { FINE_CELLS };
                let mut d = bounds::density_bounds(s, self.ray, u, v, cells);
                if stage == 2 {
                    let sk = s.segment();
                    let short = (Interval::point(v) - Interval::point(u)).hi() * self.ray.speed()
                        <= sk.ra().min(sk.rb()) * T::from_f64(CLOSED_FORM_WIDTH);
                    if short {
                        let c = s.density_range(self.ray, u, v).intersection(d);
                        if !c.is_empty() {
                            d = c;
                        }
                    }
                }
                acc = acc + if u > a || v < b { d.hull(zero) } else { d };
            }
            r = Interval::point(self.iso) - acc;
            if !r.contains(T::ZERO) {
                break;
            }
            stage += 1;
        }
        r
    }

    /// Whether `[a.t, b.t]` is proven root-free: a range of `iso − f`
    /// that excludes `0` ([`range`](Self::range), then the tight stage,
    /// [`tight_step`](Self::tight_step)), or the same strict sign at
    /// both ends with a derivative enclosure of the summed Taylor models
    /// ([`bounds::taylor_model_slope`]) that excludes `0` (a monotone
    /// field). The tight stage runs with one piece per primitive, then,
    /// when [`FINE_GAIN`] says it may decide, with [`FINE_PIECES`].
    fn root_free(
        &self,
        hits: HitRange,
        a: &ScalisPoint<T>,
        b: &ScalisPoint<T>,
        stats: &mut RayStats,
    ) -> bool {
        let r = self.range(hits, a.t, b.t, stats);
        if !r.contains(T::ZERO) {
            return true;
        }
        let mut tight = ScalisTight::start(a, b, r);
        while !self.tight_step(&mut tight, hits, stats) {}
        tight.status == TIGHT_FREE
    }

    /// One step of the tight stage of [`root_free`](Self::root_free) on
    /// `t`'s interval: one more hit into the pass's sums, or, after the
    /// last hit, the pass's verdict ([`TIGHT_FREE`], [`TIGHT_NOT_FREE`],
    /// or a second pass with [`FINE_PIECES`]). `true` once decided.
    ///
    /// A pass encloses the density on `[a, b]` soundly by the
    /// intersection of
    ///
    /// - the sum over the hits of per-primitive ranges: the log-concave
    ///   bounds of constant-radius segments
    ///   ([`bounds::log_concave_range`]) intersected with the range of the
    ///   primitive's quadratic Taylor model built at `c`, with `f''` on
    ///   `pieces` pieces ([`bounds::taylor_model_at`]), the cell sums
    ///   ([`FINE_CELLS`]) when neither applies;
    /// - the range of the **sum** of the quadratic Taylor models (a
    ///   primitive without one enters as its constant range), which keeps
    ///   the cancellations between primitives;
    ///
    /// and when every primitive has a model, the summed model's derivative
    /// enclosure may prove the field monotone.
    fn tight_step(&self, t: &mut ScalisTight<T>, hits: HitRange, stats: &mut RayStats) -> bool {
        let zero = Interval::point(T::ZERO);
        let (a, b, c) = (t.ab[0], t.ab[1], t.c);
        let k = hits.start + t.k as usize;
        if k < hits.end && !(self.hits[k].entry > b) {
            t.k += 1;
            let h = self.hits[k];
            if h.exit < a {
                return false;
            }
            let s = self.seg(&h);
            let lc = bounds::log_concave_range_or_empty(s, self.ray, a, b);
            let tm = bounds::taylor_model_at_or_empty(s, self.ray, c, a, b, t.pieces);
            let has_tm = !tm[0].is_empty();
            let tr = if has_tm {
                bounds::taylor_model_range_at(tm, c, a, b)
            } else {
                Interval::EMPTY
            };
            let has_lc = !lc.is_empty();
            let mut per = if has_lc && has_tm {
                let c = lc.intersection(tr);
                if c.is_empty() { lc } else { c }
            } else if has_lc {
                lc
            } else if has_tm {
                tr
            } else {
                let (u, v) = (a.max(h.entry), b.min(h.exit));
                let d = bounds::density_bounds(s, self.ray, u, v, FINE_CELLS);
                if u > a || v < b { d.hull(zero) } else { d }
            };
            per = Interval::new(per.lo().max(T::ZERO), per.hi());
            t.sum = t.sum + per;
            if has_tm {
                t.model[0] = t.model[0] + tm[0];
                t.model[1] = t.model[1] + tm[1];
                t.model[2] = t.model[2] + tm[2];
            } else {
                t.model[0] = t.model[0] + per;
                t.whole = 0;
            }
            return false;
        }
        // the pass's verdict
        stats.bound_evals += 1;
        let model = t.model;
        let whole = t.whole != 0;
        let m = t
            .sum
            .intersection(bounds::taylor_model_range_at(model, c, a, b));
        let d = if m.is_empty() { t.sum } else { m };
        let x = t.r.intersection(Interval::point(self.iso) - d);
        if !x.is_empty() {
            t.r = x;
        }
        t.status = TIGHT_NOT_FREE;
        if !t.r.contains(T::ZERO) {
            t.status = TIGHT_FREE;
            return true;
        }
        let same = t.same != 0;
        if same && whole {
            let slope = bounds::taylor_model_slope(model, c, a, b);
            if !slope.is_empty() && !slope.contains(T::ZERO) {
                t.status = TIGHT_FREE;
                return true;
            }
        }
        if t.pieces >= FINE_PIECES || !whole {
            return true;
        }
        // Would a second derivative FINE_GAIN times narrower, at the
        // point of this one nearest 0, decide? (Only a filter: what is
        // proven comes from the second pass itself.)
        let [f0, d1, d2] = model;
        let near = if d2.lo() > T::ZERO {
            d2.lo()
        } else if d2.hi() < T::ZERO {
            d2.hi()
        } else {
            T::ZERO
        };
        let rad = (d2.hi() - d2.lo()) * T::HALF / T::from_f64(FINE_GAIN);
        let hope = [f0, d1, Interval::new(near - rad, near + rad)];
        let hope_range = Interval::point(self.iso) - bounds::taylor_model_range_at(hope, c, a, b);
        let hope_slope = bounds::taylor_model_slope(hope, c, a, b);
        let hopeless_range = hope_range.contains(T::ZERO);
        let hopeless_slope = !same || hope_slope.contains(T::ZERO);
        if hopeless_range && hopeless_slope {
            return true;
        }
        // the second pass
        t.status = TIGHT_REQUESTED;
        t.pieces = FINE_PIECES;
        t.k = 0;
        t.sum = zero;
        t.model = [zero; 3];
        t.whole = 1;
        false
    }
}

/// The first root in `[0, 1]` of `c0 + c1·u + c2·u²` and whether there is
/// one.
///
/// A flag rather than an `Option`, and no early return: with an `Option`
/// and early returns (here and in [`oracle`]'s loop over the pieces),
/// lavapipe computed no root for inputs that have one where the oracle
/// was inlined into the SCALIS module's tracing (while the same function
/// alone in a probe entry point computed it): one split at a midpoint
/// instead of at the predicted root, and different step counts
/// (BENCHMARKS.md "GPU", session 33).
fn first_unit_root<T: Real>(c0: T, c1: T, c2: T) -> (T, bool) {
    let ok = |u: T| u >= T::ZERO && u <= T::ONE;
    let scale = c0.abs().max(c1.abs()).max(c2.abs());
    let mut root = T::ZERO;
    let mut found = false;
    if scale > T::ZERO && scale.is_finite() {
        if c2.abs() <= scale * T::from_f64(1e-12) {
            if c1 != T::ZERO {
                root = -c0 / c1;
                found = ok(root);
            }
        } else {
            let disc = c1 * c1 - T::from_f64(4.0) * c2 * c0;
            if !(disc < T::ZERO) {
                let sq = disc.sqrt();
                let q = if c1 >= T::ZERO {
                    -(c1 + sq) * T::HALF
                } else {
                    (sq - c1) * T::HALF
                };
                let (r0, r1) = (q / c2, if q != T::ZERO { c0 / q } else { q / c2 });
                let (lo, hi) = if r1 < r0 { (r1, r0) } else { (r0, r1) };
                if ok(lo) {
                    root = lo;
                    found = true;
                } else if ok(hi) {
                    root = hi;
                    found = true;
                }
            }
        }
    }
    (root, found)
}

/// The first root in `[0, 1]` of the rational quadratic Bézier piece with
/// ordinates `p0, p1, p2` and middle weight `weight` (the roots of its
/// numerator `(1−u)²p0 + 2w·u(1−u)p1 + u²p2`), and whether there is one.
fn piece_root<T: Real>(p0: T, p1: T, p2: T, weight: T) -> (T, bool) {
    let wp1 = weight * p1;
    let c0 = p0;
    let c1 = (wp1 - p0) * T::TWO;
    let c2 = p0 - wp1 * T::TWO + p2;
    first_unit_root(c0, c1, c2)
}

/// The oracle of §1.4 on `[a, b]` with Hermite data `(ga, da)`, `(gb, db)`:
/// the first root of the smooth piecewise-quadratic interpolant (eq. 1.10:
/// two quadratic Bézier pieces on the halves, middle ordinate
/// `(ga + gb)/2 + L/8·(da − db)`), each piece rational with middle weight
/// `weight` (its roots are those of the weighted numerator), and whether
/// there is one. Both pieces are solved, then the first root taken (no
/// early return: [`first_unit_root`]).
pub(crate) fn oracle<T: Real>(a: T, b: T, ga: T, da: T, gb: T, db: T, weight: T) -> (T, bool) {
    let l = b - a;
    let mid = (ga + gb) * T::HALF + l * T::from_f64(0.125) * (da - db);
    let quarter = l * T::from_f64(0.25);
    let (u0, f0) = piece_root(ga, ga + quarter * da, mid, weight);
    let (u1, f1) = piece_root(mid, gb - quarter * db, gb, weight);
    let t0 = a + l * T::HALF * u0;
    let t1 = (a + l * T::HALF) + l * T::HALF * u1;
    if f0 && t0.is_finite() {
        (t0, true)
    } else if f1 && t1.is_finite() {
        (t1, true)
    } else {
        (T::ZERO, false)
    }
}

/// One iteration of the pre-segmented processing of the covered region
/// `s.walk.region = [r0, r1]` whose hits are `ctx.hits[hits.start..hits.end]`
/// (module docs): the points the previous iteration asked for are
/// evaluated (all at this one call site: a GPU driver inlines every call)
/// and applied, then the next interval is taken from the stack and decided,
/// split or reported. Roots go to `w`; the [`Flow`] says whether the region
/// is done or tracing stops (with the final record).
///
/// With `DEFER`, an interval that needs the tight stage is left in
/// [`ScalisWalk::tight`] for [`scalis_tight_resume_in`] (the iteration
/// waits for it, and resumes with its verdict); without, the tight stage
/// runs here.
fn region_iteration<T: Real, const DEFER: bool>(
    ctx: &Ctx<'_, T>,
    s: &mut ScalisState<T>,
    hits: HitRange,
    params: &Params<T>,
    split: Split,
    w: &mut Walk<'_, T>,
) -> Flow<T> {
    let eps = params.eps;
    let fine = eps / T::from_f64(f64::from(1u32 << TOUCH_DEPTH));
    let delta = eps * T::from_f64(0.45);
    let refine = eps * T::from_f64(REFINE_EPS);
    let consts = [fine, delta, refine];
    let origin = ScalisPoint::new(s.walk.region[0], Interval::point(T::ZERO));
    let mut sp = s.walk.sp as usize;
    if s.walk.tight.status != TIGHT_NONE {
        // the interval taken from the stack waits for, or has, the verdict
        // of its tight stage
        if s.walk.tight.status == TIGHT_REQUESTED {
            if DEFER {
                return Flow::wait();
            }
            while !ctx.tight_step(&mut s.walk.tight, hits, &mut w.stats) {}
        }
        let free = s.walk.tight.status == TIGHT_FREE;
        s.walk.tight = ScalisTight::none();
        if free {
            return Flow::go();
        }
        let [a, b] = s.walk.pair;
        let flow = region_finish(ctx, s, &mut sp, a, b, hits, params, split, w, consts);
        s.walk.sp = sp as u32;
        return flow;
    }
    let nreq = s.walk.nreq as usize;
    let mut vals = [origin; 2];
    let mut q = 0;
    while q < nreq {
        w.stats.field_evals += 1;
        let t = s.walk.req[q];
        vals[q] = ScalisPoint::new(t, ctx.value(hits, t));
        q += 1;
    }
    let kind = s.walk.kind;
    if kind == PENDING_START {
        if nreq > 0 {
            let mut q = 0;
            if s.walk.cur_pending != 0 {
                s.walk.cur = vals[0];
                s.walk.cur_pending = 0;
                q = 1;
            }
            if q < nreq {
                let nb = vals[q];
                s.stack[0] = [s.walk.cur, nb];
                sp = 1;
                s.walk.cur = nb;
            }
        }
    } else if kind == PENDING_SPLIT {
        let mut right = s.walk.split[1];
        let mut k = nreq;
        while k > 0 {
            k -= 1;
            let p = vals[k];
            s.stack[sp] = [p, right];
            sp += 1;
            right = p;
        }
        s.stack[sp] = [s.walk.split[0], right];
        sp += 1;
    } else {
        // PENDING_TOUCH_END
        let mut q = 0;
        if s.walk.fix[0] != 0 {
            s.stack[sp - 1][0] = vals[q];
            q += 1;
        }
        if s.walk.fix[1] != 0 {
            s.walk.cur = vals[q];
        }
    }
    s.walk.kind = PENDING_START;
    s.walk.nreq = 0;
    let flow = region_decide::<T, DEFER>(ctx, s, &mut sp, hits, params, split, w, consts);
    s.walk.sp = sp as u32;
    flow
}

/// The second half of [`region_iteration`]: with the stack's height `sp`,
/// the next interval, or the next pre-segmented one when the stack is
/// empty (or the region's end).
#[allow(clippy::too_many_arguments)]
fn region_decide<T: Real, const DEFER: bool>(
    ctx: &Ctx<'_, T>,
    s: &mut ScalisState<T>,
    sp: &mut usize,
    hits: HitRange,
    params: &Params<T>,
    split: Split,
    w: &mut Walk<'_, T>,
    consts: [T; 3],
) -> Flow<T> {
    let r1 = s.walk.region[1];
    let eps = params.eps;
    if *sp == 0 {
        if s.walk.cur_pending != 0 {
            s.walk.req[0] = s.walk.cur.t;
            s.walk.nreq = 1;
            return Flow::go();
        }
        let cur = s.walk.cur.t;
        if !(cur < r1) {
            return Flow::done();
        }
        // the next argmin after the cursor (pre-segmentation, §1.3)
        let mut next = r1;
        let mut k = hits.start;
        while k < hits.end {
            let argmin = ctx.hits[k].argmin;
            k += 1;
            if argmin > cur + eps && argmin < next - eps {
                next = argmin;
            }
        }
        s.walk.req[0] = next;
        s.walk.nreq = 1;
        return Flow::go();
    }
    *sp -= 1;
    let [a, b] = s.stack[*sp];
    if w.stats.steps >= params.max_steps {
        return Flow::stop(w.done(Status::MaxSteps, a.t));
    }
    w.stats.steps += 1;
    let (leaf, crossing) = leaf_crossing(&a, &b, *sp, eps);
    // a leaf with a sign change is a crossing without further proof
    if !(leaf && crossing) {
        if DEFER {
            let r = ctx.range(hits, a.t, b.t, &mut w.stats);
            if !r.contains(T::ZERO) {
                return Flow::go();
            }
            // the tight stage, in a smaller entry point of its own
            s.walk.pair = [a, b];
            s.walk.tight = ScalisTight::start(&a, &b, r);
            return Flow::wait();
        }
        if ctx.root_free(hits, &a, &b, &mut w.stats) {
            return Flow::go();
        }
    }
    region_finish(ctx, s, sp, a, b, hits, params, split, w, consts)
}

/// Whether the interval `[a, b]` taken from the stack (whose height is
/// now `sp`) is a leaf (too short or too deep to split), and whether its
/// ends' signs differ.
fn leaf_crossing<T: Real>(
    a: &ScalisPoint<T>,
    b: &ScalisPoint<T>,
    sp: usize,
    eps: T,
) -> (bool, bool) {
    let len = b.t - a.t;
    let mid = a.t + len * T::HALF;
    let splittable = mid > a.t && mid < b.t && sp + 3 <= STACK_CAPACITY;
    let leaf = !(len > eps) || !splittable;
    (leaf, inside(a.f) != inside(b.f))
}

/// The rest of an iteration for the interval `[a, b]` taken from the stack
/// and not proven root-free: a root at a leaf, else the interval split at
/// the oracle's predicted root or its midpoint (evaluated at the next
/// iteration's top).
#[allow(clippy::too_many_arguments)]
fn region_finish<T: Real>(
    ctx: &Ctx<'_, T>,
    s: &mut ScalisState<T>,
    sp: &mut usize,
    mut a: ScalisPoint<T>,
    mut b: ScalisPoint<T>,
    hits: HitRange,
    params: &Params<T>,
    split: Split,
    w: &mut Walk<'_, T>,
    [fine, delta, refine]: [T; 3],
) -> Flow<T> {
    let r1 = s.walk.region[1];
    let eps = params.eps;
    let len = b.t - a.t;
    let mid = a.t + len * T::HALF;
    let splittable = mid > a.t && mid < b.t && *sp + 3 <= STACK_CAPACITY;
    let leaf = !(len > eps) || !splittable;
    // a leaf with a sign change is a crossing without further proof
    // (a flag and a side, not an `Option`: no niche-encoded value on a
    // GPU)
    let (ia, ib) = (inside(a.f), inside(b.f));
    let crossing = ia != ib;
    let crossing_side = if ib { Side::Entering } else { Side::Leaving };
    if leaf {
        // A leaf: a crossing, or (after halving below eps) a touch.
        let side = if crossing {
            crossing_side
        } else {
            if splittable && len > fine {
                // halve it (evaluated at the next iteration's top)
                s.walk.kind = PENDING_SPLIT;
                s.walk.req[0] = mid;
                s.walk.nreq = 1;
                s.walk.split = [a, b];
                return Flow::go();
            }
            Side::Touch
        };
        let t = if a.f.contains(T::ZERO) { a.t } else { mid };
        let next = w.register(Root { t, side }, a.t);
        if next.stop {
            return Flow::stop(next.trace);
        }
        if side == Side::Touch {
            // the rest of this contact, up to t + eps, is the same root
            let end = (t + eps).min(r1);
            while *sp > 0 && s.stack[*sp - 1][1].t <= end {
                *sp -= 1;
            }
            let fix_top = *sp > 0 && s.stack[*sp - 1][0].t < end;
            let fix_cur = s.walk.cur.t < end;
            if fix_top || fix_cur {
                s.walk.kind = PENDING_TOUCH_END;
                s.walk.req = [end; 2];
                s.walk.nreq = u32::from(fix_top) + u32::from(fix_cur);
                s.walk.fix = [u32::from(fix_top), u32::from(fix_cur)];
            }
        }
        return Flow::go();
    }
    let (sa, sb) = (sign_of(a.f), sign_of(b.f));
    let bracketed = sa * sb < 0;
    let use_oracle = match split {
        Split::Oracle => true,
        Split::Bisection => bracketed && len <= refine,
    };
    // the predicted root, when `has_guess` (flags, not NaN sentinels)
    let mut guess = mid;
    let mut has_guess = false;
    if use_oracle {
        // the Hermite data of both ends, from one call site
        let ends = [a, b];
        let mut herm = [[T::ZERO; 2]; 2];
        let mut e = 0;
        while e < 2 {
            herm[e] = if ends[e].has_herm != 0 {
                ends[e].herm
            } else {
                w.stats.field_evals += 1;
                ctx.hermite(hits, ends[e].t)
            };
            e += 1;
        }
        (a.herm, b.herm) = (herm[0], herm[1]);
        (a.has_herm, b.has_herm) = (1, 1);
        let [[ga, da], [gb, db]] = herm;
        let weight = if bracketed {
            T::ONE
        } else {
            T::from_f64(ORACLE_WEIGHT)
        };
        let (g, has_g) = oracle(a.t, b.t, ga, da, gb, db, weight);
        // Before a sign change, the Newton step from the left end where
        // it lies further than the oracle's root: on a long interval
        // the far end's Hermite data pull the interpolant's root short
        // of a near-linear approach, one short guess after another.
        let mut newton = mid;
        let mut has_newton = false;
        if !bracketed && ga * da < T::ZERO {
            let t = a.t - ga / da;
            if t > a.t && t < b.t {
                newton = t;
                has_newton = true;
            }
        }
        has_guess = has_g || has_newton;
        guess = if has_g && has_newton {
            if newton > g { newton } else { g }
        } else if has_g {
            g
        } else {
            newton
        };
    }
    // split at t_root ± δ (both, one or none of them inside), else at
    // the midpoint
    let mut cuts = [mid; 2];
    let mut nc = 1;
    if has_guess && guess > a.t && guess < b.t {
        let g = guess;
        let (u, v) = (round::sub_down(g, delta), round::add_down(g, delta));
        nc = 0;
        let uv = [u, v];
        let mut q = 0;
        while q < 2 {
            let c = uv[q];
            q += 1;
            if c > a.t && c < b.t && (nc == 0 || c > cuts[0]) {
                cuts[nc] = c;
                nc += 1;
            }
        }
        if nc == 0 {
            cuts[0] = g;
            nc = 1;
        }
    }
    s.walk.kind = PENDING_SPLIT;
    s.walk.req = cuts;
    s.walk.nreq = nc as u32;
    s.walk.split = [a, b];
    Flow::go()
}

/// A window of the ray as a [`Field`]: the sum over its hits (support-box
/// culled) with a Lipschitz bound valid on the window only.
struct Window<'a, T> {
    ctx: &'a Ctx<'a, T>,
    hits: &'a [PrimitiveHit<T>],
    lipschitz: T,
}

impl<T: Real> Field<T> for Window<'_, T> {
    fn eval<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        let e = [p[0].enclosure(), p[1].enclosure(), p[2].enclosure()];
        let mut acc = if e[0].is_bounded() {
            p[0] * T::ZERO
        } else {
            N::constant(T::ZERO)
        };
        for h in self.hits {
            let s = self.ctx.seg(h);
            if let Some([lo, hi]) = s.support_box() {
                if (0..3).any(|k| !e[k].is_empty() && (e[k].hi() < lo[k] || e[k].lo() > hi[k])) {
                    continue;
                }
            }
            acc = acc + s.density(p);
        }
        -acc + self.ctx.iso
    }
    fn lipschitz(&self) -> Option<T> {
        Some(self.lipschitz)
    }
}

/// Sphere tracing with per-ray Lipschitz bounds, per window or per ray
/// (§1.7; module docs).
#[allow(clippy::too_many_arguments)]
fn sphere_per_ray<T: Real, S: AsRef<[ScalisSegment<T>]>>(
    skeleton: &ScalisSkeleton<T, S>,
    hits: &[PrimitiveHit<T>],
    ray: &Ray<T>,
    span: [T; 2],
    scope: SphereLipschitz,
    mode: Mode,
    params: &Params<T>,
    roots: &mut [Root<T>],
) -> Trace<T> {
    let ctx = Ctx {
        segments: skeleton.segments(),
        hits,
        iso: skeleton.iso(),
        ray,
    };
    let [x, y, z] = ray.dir;
    let speed_lo = (Interval::point(x).sqr() + Interval::point(y).sqr() + Interval::point(z).sqr())
        .sqrt()
        .lo();
    // the sum over `hs` of each one's directional bound on its part of
    // `[a, b]`, per unit of `t`
    let lipschitz_on = |hs: &[PrimitiveHit<T>], a: T, b: T| {
        let mut lip = Interval::point(T::ZERO);
        for h in hs {
            if h.entry <= b && h.exit >= a {
                let (u, v) = (a.max(h.entry), b.min(h.exit));
                lip = lip + Interval::point(ctx.seg(h).directional_lipschitz(ray, u, v));
            }
        }
        round::div_up(lip.hi(), speed_lo)
    };
    let per_ray = match scope {
        SphereLipschitz::PerRay => Some(lipschitz_on(hits, span[0], span[1])),
        SphereLipschitz::PerWindow => None,
    };
    let mut n = 0usize;
    let mut stats = RayStats::default();
    let mut out: Option<Trace<T>> = None;
    for_each_region(hits, |r0, r1, i, j| {
        let (r0, r1) = (r0.max(span[0]), r1.min(span[1]));
        if !(r0 <= r1) {
            return true;
        }
        let rh = &hits[i..j];
        let mut a = r0;
        while a < r1 {
            // the next event (an entry or exit) after a; one window per
            // region with the per-ray constant
            let mut b = r1;
            if per_ray.is_none() {
                for h in rh {
                    if h.entry > a && h.entry < b {
                        b = h.entry;
                    }
                    if h.exit > a && h.exit < b {
                        b = h.exit;
                    }
                }
            }
            let lipschitz = per_ray.unwrap_or_else(|| lipschitz_on(rh, a, b));
            let left = params.max_steps.saturating_sub(stats.steps);
            let (Ok(p), true) = (params.with_max_steps(left.max(1)), left > 0) else {
                out = Some(Trace {
                    roots: n as u32,
                    status: Status::MaxSteps,
                    t_reached: a,
                    stats,
                });
                return false;
            };
            let win = Window {
                ctx: &ctx,
                hits: rh,
                lipschitz: if lipschitz > T::ZERO {
                    lipschitz
                } else {
                    T::MIN_SUBNORMAL
                },
            };
            let buf = &mut roots[n..];
            if buf.is_empty() {
                out = Some(Trace {
                    roots: n as u32,
                    status: Status::BufferFull,
                    t_reached: a,
                    stats,
                });
                return false;
            }
            let tr = trace(&win, ray, [a, b], Method::Sphere, mode, &p, buf);
            stats = stats + tr.stats;
            let mut got = tr.roots as usize;
            // a root on the window boundary may be reported twice
            if got > 0 && n > 0 && (roots[n].t - roots[n - 1].t).abs() <= params.eps {
                roots.copy_within(n + 1..n + got, n);
                got -= 1;
            }
            n += got;
            match tr.status {
                Status::Finished if mode == Mode::Opaque && n > 0 => {
                    out = Some(Trace {
                        roots: n as u32,
                        status: Status::Finished,
                        t_reached: roots[n - 1].t,
                        stats,
                    });
                    return false;
                }
                Status::Finished => {}
                s => {
                    out = Some(Trace {
                        roots: n as u32,
                        status: s,
                        t_reached: tr.t_reached,
                        stats,
                    });
                    return false;
                }
            }
            a = b;
        }
        true
    });
    out.unwrap_or(Trace {
        roots: n as u32,
        status: Status::Finished,
        t_reached: span[1],
        stats,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    extern crate alloc;
    use alloc::format;
    use alloc::string::ToString;
    use alloc::vec::Vec;
    use boundtrace_fields::homothetic::{Segment, SegmentKernel};

    const NONE: Root<f64> = Root {
        t: f64::NAN,
        side: Side::Touch,
    };

    fn skeleton() -> ScalisSkeleton<f64, [ScalisSegment<f64>; 3]> {
        let k = SegmentKernel::compact_polynomial(6, 2.0).unwrap();
        let mk = |a: [f64; 3], b: [f64; 3], ra: f64, rb: f64| {
            ScalisSegment::new(Segment::new(a, ra, b, rb).unwrap(), k, 1.0).unwrap()
        };
        ScalisSkeleton::new([
            mk([0.0, -1.0, 0.0], [0.0, 1.0, 0.0], 0.1, 0.15),
            mk([0.0, 1.0, 0.0], [1.0, 1.5, 0.0], 0.15, 0.1),
            mk([2.0, -1.0, 0.0], [2.0, 1.0, 0.3], 0.08, 0.08),
        ])
        .unwrap()
    }

    /// Roots by dense sampling of the sign (for rays crossing cleanly).
    fn sampled_roots(sk: &impl Field<f64>, ray: &Ray<f64>, span: [f64; 2]) -> Vec<(f64, Side)> {
        let n = 200_000;
        let mut out = Vec::new();
        let f = |t: f64| -> f64 { sk.eval(ray.at::<f64>(t, t)) };
        let mut prev = f(span[0]);
        for i in 1..=n {
            let t = span[0] + (span[1] - span[0]) * f64::from(i) / f64::from(n);
            let v = f(t);
            if prev > 0.0 && v <= 0.0 {
                out.push((t, Side::Entering));
            } else if prev <= 0.0 && v > 0.0 {
                out.push((t, Side::Leaving));
            }
            prev = v;
        }
        out
    }

    /// Rays through [`skeleton`] crossing it at least twice.
    const RAYS: [([f64; 3], [f64; 3]); 3] = [
        ([-2.0, 0.05, 0.02], [1.0, 0.0, 0.0]),
        ([-2.0, 0.9, 0.01], [1.0, 0.1, 0.0]),
        ([-2.0, -0.5, 0.1], [1.0, 0.02, 0.0]),
    ];

    /// Every interval `root_free` proves has no root nor touch (the field,
    /// sampled densely, keeps the strict sign of its ends), and the tight
    /// stages (the midpoint models, the fine pieces, the monotone test)
    /// prove intervals that the cell sums and the closed form's range
    /// (`range`) alone do not.
    #[test]
    fn root_free_proofs_hold_and_reach_beyond_the_ranges() {
        let sk = skeleton();
        let span = [0.0, 6.0];
        let (mut proven, mut beyond) = (0, 0);
        for (o, d) in RAYS {
            let ray = Ray::new(o, d);
            let mut store = [PrimitiveHit::empty(); 8];
            let list = RayPrimitives::build(sk.segments(), &ray, span, &mut store);
            let ctx = Ctx {
                segments: sk.segments(),
                hits: list.hits(),
                iso: sk.iso(),
                ray: &ray,
            };
            let all = HitRange {
                start: 0,
                end: list.hits().len(),
            };
            let pt = |t: f64| ScalisPoint::new(t, ctx.value(all, t));
            for len in [0.5, 0.1, 0.02, 0.004] {
                let n = (6.0 / len) as u32;
                for i in 0..n {
                    let (a, b) = (f64::from(i) * len, f64::from(i + 1) * len);
                    let mut stats = RayStats::default();
                    if !ctx.root_free(all, &pt(a), &pt(b), &mut stats) {
                        continue;
                    }
                    proven += 1;
                    let positive = sk.eval(ray.at::<f64>(a, a)) > 0.0;
                    for k in 0..=2000 {
                        let t = a + (b - a) * f64::from(k) / 2000.0;
                        let v: f64 = sk.eval(ray.at::<f64>(t, t));
                        assert!(
                            v != 0.0 && (v > 0.0) == positive,
                            "[{a}, {b}] proven root-free, field {v} at {t}"
                        );
                    }
                    let r = ctx.range(all, a, b, &mut stats);
                    beyond += usize::from(r.contains(0.0));
                }
            }
        }
        assert!(proven > 0 && beyond > 0, "{proven} {beyond}");
    }

    /// `got` are the roots of `expect` (within `2·eps`, same sides).
    fn assert_roots(what: &str, got: &[Root<f64>], expect: &[(f64, Side)], eps: f64) {
        assert_eq!(got.len(), expect.len(), "{what}: {got:?} vs {expect:?}");
        for (g, e) in got.iter().zip(expect) {
            assert!((g.t - e.0).abs() <= 2.0 * eps, "{what}: {g:?} vs {e:?}");
            assert_eq!(g.side, e.1, "{what}");
        }
    }

    /// A guard that pauses before every `every`-th iteration and rejects
    /// iterations after they ran (the driver's loop limit) at pseudo-random.
    struct Chaos {
        seed: u64,
        every: u32,
        calls: u32,
        rejected: u32,
    }

    impl StepGuard for Chaos {
        fn before_step(&mut self, _steps: u32) -> bool {
            self.calls += 1;
            self.calls % self.every != 0
        }
        fn after_step(&mut self) -> bool {
            self.seed ^= self.seed << 13;
            self.seed ^= self.seed >> 7;
            self.seed ^= self.seed << 17;
            let ok = self.seed % 3 != 0;
            self.rejected += u32::from(!ok);
            ok
        }
    }

    /// The legs of a trace, paused and undone at random, give the
    /// uninterrupted trace's roots, record and counters exactly, in both
    /// modes, for both methods, with small root windows (buffer full) and
    /// a step limit, with the tight stage inline or deferred to
    /// [`scalis_tight_resume_in`]; a leg whose every iteration is rejected
    /// changes nothing.
    #[test]
    fn resumed_legs_give_the_uninterrupted_trace() {
        let sk = skeleton();
        let span = [0.0, 6.0];
        let (mut rejected, mut max_legs, mut deferrals) = (0, 0, 0);
        let rays = RAYS.into_iter().chain([
            ([-2.0, 1.16, 0.0], [1.0, 0.0, 0.0]),
            ([2.0, -3.0, 0.1], [0.0, 1.0, 0.02]),
            ([-1.0, 1.3, -0.3], [1.0, 0.05, 0.1]),
        ]);
        let guards = [
            (2, false),
            (3, false),
            (7, false),
            (1 << 30, true),
            (3, true),
        ];
        for (o, d) in rays {
            let ray = Ray::new(o, d);
            let mut store = [PrimitiveHit::empty(); 8];
            let list = RayPrimitives::build(sk.segments(), &ray, span, &mut store);
            assert!(!list.overflowed());
            let hits = list.hits().to_vec();
            let (segs, iso, all) = (sk.segments(), sk.iso(), [0, hits.len()]);
            for method in [Method::ScalisQuadratic, Method::Interval] {
                for mode in [Mode::Transparent, Mode::Opaque] {
                    for (cap, max_steps) in [(16, 100_000), (1, 100_000), (16, 12)] {
                        let mut params = Params::new();
                        params.max_steps = max_steps;
                        let p = &params;
                        let mut whole = [NONE; 16];
                        let once = trace_scalis_in(
                            segs,
                            iso,
                            &hits,
                            all,
                            &ray,
                            span,
                            method,
                            mode,
                            p,
                            &mut whole,
                            [0, cap],
                        );
                        for (every, deferred) in guards {
                            let seed = 0x9e37_79b9_7f4a_7c15 ^ u64::from(every);
                            let mut g = Chaos {
                                seed,
                                every,
                                calls: 0,
                                rejected: 0,
                            };
                            let mut state = ScalisState::start();
                            let (st, mut roots, mut legs) = (&mut state, [NONE; 16], 0);
                            let r = &mut roots;
                            let last = loop {
                                legs += 1;
                                assert!(legs < 100_000, "no progress");
                                let leg = if deferred {
                                    trace_scalis_resume_deferred_in(
                                        segs,
                                        iso,
                                        &hits,
                                        all,
                                        &ray,
                                        span,
                                        method,
                                        mode,
                                        p,
                                        r,
                                        [0, cap],
                                        st,
                                        &mut g,
                                    )
                                } else {
                                    trace_scalis_resume_in(
                                        segs,
                                        iso,
                                        &hits,
                                        all,
                                        &ray,
                                        span,
                                        method,
                                        mode,
                                        p,
                                        r,
                                        [0, cap],
                                        st,
                                        &mut g,
                                    )
                                };
                                if !leg.paused {
                                    break leg.trace;
                                }
                                if st.walk.tight.status == TIGHT_REQUESTED {
                                    assert!(deferred);
                                    deferrals += 1;
                                    while !scalis_tight_resume_in(
                                        segs, iso, &hits, all, &ray, st, &mut g,
                                    ) {
                                        legs += 1;
                                        assert!(legs < 100_000, "no progress");
                                    }
                                    assert!(st.walk.tight.status >= TIGHT_FREE);
                                }
                            };
                            let what = format!(
                                "{method} {mode:?} cap {cap} every {every} deferred {deferred}"
                            );
                            assert_eq!(last, once, "{what}");
                            let n = once.roots as usize;
                            assert_eq!(roots[..n], whole[..n], "{what}");
                            rejected += g.rejected;
                            max_legs = max_legs.max(legs);
                        }
                    }
                }
            }
        }
        assert!(
            rejected > 100 && max_legs > 20 && deferrals > 20,
            "{rejected} {max_legs} {deferrals}"
        );
        // Every iteration rejected: the state does not move.
        struct Never;
        impl StepGuard for Never {
            fn before_step(&mut self, _: u32) -> bool {
                true
            }
            fn after_step(&mut self) -> bool {
                false
            }
        }
        let ray = Ray::new(RAYS[0].0, RAYS[0].1);
        let mut store = [PrimitiveHit::empty(); 8];
        let hits = RayPrimitives::build(sk.segments(), &ray, span, &mut store)
            .hits()
            .to_vec();
        let mut state = ScalisState::start();
        let mut roots = [NONE; 4];
        for _ in 0..40 {
            let mut guard = Chaos {
                seed: 7,
                every: 1 << 30,
                calls: 0,
                rejected: 0,
            };
            let _ = trace_scalis_resume_in(
                sk.segments(),
                sk.iso(),
                &hits,
                [0, hits.len()],
                &ray,
                span,
                Method::ScalisQuadratic,
                Mode::Transparent,
                &Params::new(),
                &mut roots,
                [0, 4],
                &mut state,
                &mut guard,
            );
            let before = state;
            let leg = trace_scalis_resume_in(
                sk.segments(),
                sk.iso(),
                &hits,
                [0, hits.len()],
                &ray,
                span,
                Method::ScalisQuadratic,
                Mode::Transparent,
                &Params::new(),
                &mut roots,
                [0, 4],
                &mut state,
                &mut Never,
            );
            if !leg.paused {
                break;
            }
            assert_eq!(state, before);
        }
    }

    #[test]
    fn every_scalis_method_finds_every_root() {
        let sk = skeleton();
        let params = Params::new();
        let span = [0.0, 6.0];
        for (o, d) in RAYS {
            let ray = Ray::new(o, d);
            let expect = sampled_roots(&sk, &ray, span);
            assert!(expect.len() >= 2, "{expect:?}");
            let mut store = [PrimitiveHit::empty(); 8];
            let list = RayPrimitives::build(sk.segments(), &ray, span, &mut store);
            assert!(!list.overflowed());
            for method in [Method::ScalisQuadratic, Method::Interval, Method::Sphere] {
                let mut buf = [NONE; 16];
                let tr = trace_scalis(
                    &sk,
                    list.hits(),
                    &ray,
                    span,
                    method,
                    Mode::Transparent,
                    &params,
                    &mut buf,
                );
                assert_eq!(tr.status, Status::Finished, "{method}");
                let what = method.to_string();
                assert_roots(&what, &buf[..tr.roots as usize], &expect, params.eps);
                let mut one = [NONE; 1];
                let tr = trace_scalis(
                    &sk,
                    list.hits(),
                    &ray,
                    span,
                    method,
                    Mode::Opaque,
                    &params,
                    &mut one,
                );
                assert_eq!((tr.status, tr.roots), (Status::Finished, 1), "{method}");
                assert!(
                    (one[0].t - expect[0].0).abs() <= 2.0 * params.eps,
                    "{method}"
                );
            }
        }
    }

    /// The per-ray constant (§1.7) finds the same roots as the per-window
    /// constants, in at least as many steps on these rays (its constant
    /// bounds every window's).
    #[test]
    fn per_ray_sphere_finds_every_root_in_more_steps() {
        let sk = skeleton();
        let params = Params::new();
        let span = [0.0, 6.0];
        let mut more = 0;
        for (o, d) in RAYS {
            let ray = Ray::new(o, d);
            let expect = sampled_roots(&sk, &ray, span);
            let mut store = [PrimitiveHit::empty(); 8];
            let list = RayPrimitives::build(sk.segments(), &ray, span, &mut store);
            let mut steps = [0; 2];
            for (k, scope) in [SphereLipschitz::PerWindow, SphereLipschitz::PerRay]
                .into_iter()
                .enumerate()
            {
                let mut buf = [NONE; 16];
                let tr = trace_scalis_sphere(
                    &sk,
                    list.hits(),
                    &ray,
                    span,
                    scope,
                    Mode::Transparent,
                    &params,
                    &mut buf,
                );
                assert_eq!(tr.status, Status::Finished, "{scope:?}");
                let what = format!("{scope:?}");
                assert_roots(&what, &buf[..tr.roots as usize], &expect, params.eps);
                steps[k] = tr.stats.steps;
            }
            assert!(steps[1] >= steps[0], "{steps:?}");
            more += usize::from(steps[1] > steps[0]);
        }
        assert!(more > 0, "the per-ray constant never cost a step more");
        // invalid input is refused, not traced
        let ray = Ray::new([-2.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
        let tr = trace_scalis_sphere(
            &sk,
            &[],
            &ray,
            [1.0, 0.0],
            SphereLipschitz::PerRay,
            Mode::Opaque,
            &params,
            &mut [NONE; 1],
        );
        assert_eq!(tr.status, Status::Unsupported);
    }

    #[test]
    fn empty_space_costs_nothing_and_misses_are_misses() {
        let sk = skeleton();
        let params = Params::new();
        let ray = Ray::new([-2.0, 5.0, 0.0], [1.0, 0.0, 0.0]);
        let mut buf = [NONE; 4];
        let mut store = [PrimitiveHit::empty(); 8];
        let tr = trace_scalis_ray(
            &sk,
            &ray,
            [0.0, 6.0],
            Method::ScalisQuadratic,
            Mode::Opaque,
            &params,
            &mut buf,
            &mut store,
        );
        assert_eq!((tr.status, tr.roots), (Status::Finished, 0));
        assert_eq!(tr.stats, RayStats::default());
    }

    #[test]
    fn overflow_falls_back_and_generic_trace_is_unsupported() {
        let sk = skeleton();
        let params = Params::new();
        let ray = Ray::new([-2.0, 0.05, 0.02], [1.0, 0.0, 0.0]);
        let mut store = [PrimitiveHit::empty(); 1];
        let mut a = [NONE; 1];
        let tr = trace_scalis_ray(
            &sk,
            &ray,
            [0.0, 6.0],
            Method::ScalisQuadratic,
            Mode::Opaque,
            &params,
            &mut a,
            &mut store,
        );
        assert_eq!((tr.status, tr.roots), (Status::Finished, 1));
        let mut b = [NONE; 1];
        let seg = trace(
            &sk,
            &ray,
            [0.0, 6.0],
            Method::Segment,
            Mode::Opaque,
            &params,
            &mut b,
        );
        assert_eq!((a[0].t, tr.stats), (b[0].t, seg.stats));
        let tr = trace(
            &sk,
            &ray,
            [0.0, 6.0],
            Method::ScalisQuadratic,
            Mode::Opaque,
            &params,
            &mut b,
        );
        assert_eq!(tr.status, Status::Unsupported);
        let bad = Params { eps: 0.0, ..params };
        let tr = trace_scalis(
            &sk,
            &[],
            &ray,
            [0.0, 6.0],
            Method::ScalisQuadratic,
            Mode::Opaque,
            &bad,
            &mut b,
        );
        assert_eq!(tr.status, Status::Unsupported);
    }

    #[test]
    fn oracle_predicts_the_root_of_a_parabola() {
        // G(t) = (t − 1)² − 0.25 on [0, 1]: the interpolant is exact, the
        // first root is t = 0.5
        let (ga, da, gb, db) = (0.75, -2.0, -0.25, 0.0);
        let (t, found) = oracle(0.0, 1.0, ga, da, gb, db, 1.0);
        assert!(found && (t - 0.5).abs() < 1e-12, "{t}");
        // a weight > 1 pulls the curve toward its control polygon: a dip
        // that the polynomial misses is found by the rational oracle
        let (ga, da, gb, db) = (0.1, -0.6, 0.3, 0.0);
        assert!(!oracle(0.0, 1.0, ga, da, gb, db, 1.0).1);
        assert!(oracle(0.0, 1.0, ga, da, gb, db, 3.0).1);
        // the input lavapipe answered "no root" for (BENCHMARKS.md "GPU",
        // session 33): a flat left end outside every support, no root in
        // the first piece, the root in the second
        let f = f32::from_bits;
        let (t, found) = oracle(
            f(0x407d_d9a9),
            f(0x4080_1938),
            3.0,
            0.0,
            f(0xbeab_0120),
            f(0xc26e_d71c),
            1.0,
        );
        assert!(found && t.to_bits() == 0x407f_e5df, "{t}");
        assert!(!first_unit_root(1.0, 0.0, 1.0).1);
        assert_eq!(first_unit_root(-1.0, 2.0, 0.0), (0.5, true));
    }
}
