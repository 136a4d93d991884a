//! Marching methods: sphere tracing, segment tracing and forward linear /
//! quadratic marching (forward-inclusion paper Alg. 1).
//!
//! Every marcher walks the ray from `t0` and only ever advances by a step
//! that a bound **proves** root-free; they differ in the bound:
//!
//! | method | bound at `t` | step |
//! | --- | --- | --- |
//! | `sphere` | `f(t) ± L·|d|·τ`, global Lipschitz `L` (paper eq. 10; Hart 1996) | `|f|/(L·|d|)`, optionally `ω·` that with the overlap check of Keinert et al. 2014 |
//! | `segment` | `f(t) ± λ·τ`, `λ = max |f′|` on the segment (eq. 11; Galin et al. 2020) | to the bounding line's root, or the whole segment |
//! | `linear-*` | asymmetric lines `f(t) + m±·τ` (eq. 12–15) | to the relevant line's root, or the validity end |
//! | `quadratic-*` | asymmetric parabolas (§6) | to the relevant parabola's first root, or the validity end |
//!
//! The segment ("window") `[t, t_end]` on which a bound is built follows
//! Alg. 1: the whole span first, then `t_end = t + k·step`. The sign of the
//! bound's start selects the side (lower bound outside, upper bound inside,
//! §4.3).
//!
//! # Roots
//!
//! When the safe step falls below `eps` (or the start enclosure contains
//! `0`), a root may lie within `eps`: the marcher *probes* `f(t + eps)`.
//! - A sign change brackets a root in `[t + step, t + eps]`: it is
//!   registered at the bracket's middle (so within `eps / 2` of a true
//!   root) as [`Side::Entering`] or [`Side::Leaving`].
//! - No sign change: an interval enclosure of `f` on `[t, t + eps]`
//!   decides. If it excludes `0`, the marcher steps `eps` (proven
//!   root-free); otherwise the ray touches the surface within rounding or
//!   within the enclosure's width and a [`Side::Touch`] root is registered.
//!
//! In opaque mode tracing stops at the first root; in transparent mode it
//! resumes just past the root on the other side, with the window reset to
//! the rest of the span (Alg. 1 started afresh), so every root is
//! registered once (roots closer than `eps` may be reported once).
//!
//! # Minimal step
//!
//! With `Params::min_step > 0`, a safe step shorter than `min_step` (but at
//! least `eps`) is replaced by a step of `min_step` when an interval
//! enclosure of `f` over it excludes `0` (one more bound evaluation);
//! otherwise the safe step is kept. Steps therefore never pass a root.

use crate::method::{Method, Mode, Params};
use crate::trace::{RayStats, Root, Side, Status, Trace};
use boundtrace_ia_core::{Interval, Real, round};
use boundtrace_inclusion::{BoundKind, Composition, Field, ForwardLinear, ForwardQuadratic, Ray};
use core::marker::PhantomData;

/// The sign of an enclosure: `1` if it is positive, `-1` if negative, `0`
/// if it contains `0` (or is empty).
#[inline]
pub(crate) fn sign_of<T: Real>(iv: Interval<T>) -> i32 {
    if iv.is_empty() {
        0
    } else if iv.lo() > T::ZERO {
        1
    } else if iv.hi() < T::ZERO {
        -1
    } else {
        0
    }
}

/// `t + d`, rounded down, but at least the next float after `t` (so every
/// advance makes progress even when `d` is below `t`'s resolution).
#[inline]
fn advance<T: Real>(t: T, d: T) -> T {
    let a = round::add_down(t, d);
    if a > t { a } else { t.next_up() }
}

/// `f(t)` as a sound enclosure (one point evaluation in interval arithmetic).
#[inline]
pub(crate) fn value_enclosure<T: Real, F: Field<T>>(field: &F, ray: &Ray<T>, t: T) -> Interval<T> {
    field.eval(ray.at::<Interval<T>>(t, t))
}

/// What a bound says at `t` about `[t, t + h]`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct StepBound<T> {
    /// Enclosure of `f(t)`.
    start: Interval<T>,
    /// The proven root-free length `τ` (the relevant side's first root), or
    /// `None` when the side has no root on the validity interval.
    safe: Option<T>,
    /// The validity length `h` (the window, possibly shortened).
    h: T,
    /// `false` when the method needs a bound the field lacks (a flag rather
    /// than an `Option<StepBound>`: rust-gpu 0.11 cannot move this struct
    /// out of an enum, "cannot memcpy dynamically sized data").
    supported: bool,
}

impl<T: Real> StepBound<T> {
    /// No bound at `t` (supported method): the marcher certifies the step
    /// with interval enclosures.
    fn none() -> Self {
        Self {
            start: Interval::EMPTY,
            safe: None,
            h: T::ZERO,
            supported: true,
        }
    }

    /// The bound's answer, clipped to the window length `len` it was built
    /// for (a bound of `f` on `[t, t + len]` says nothing beyond it, even if
    /// its validity is longer, e.g. a constant where every primitive was
    /// culled).
    fn clipped(start: Interval<T>, safe: Option<T>, h: T, len: T) -> Self {
        let h = h.min(len);
        Self {
            start,
            safe: safe.filter(|&r| r <= h),
            h,
            supported: true,
        }
    }
    /// The answer for a method whose bound the field lacks.
    fn unsupported() -> Self {
        Self {
            start: Interval::EMPTY,
            safe: None,
            h: T::ZERO,
            supported: false,
        }
    }
    fn from_linear(b: ForwardLinear<T>, len: T) -> Self {
        Self::clipped(b.start(), b.first_root(), b.validity(), len)
    }
    fn from_quadratic(b: ForwardQuadratic<T>, len: T) -> Self {
        Self::clipped(b.start(), b.first_root(), b.validity(), len)
    }
    // `match` instead of `?`/`map`: see `supported`.
    fn from_linear_or_unsupported(b: Option<ForwardLinear<T>>, len: T) -> Self {
        match b {
            Some(b) => Self::from_linear(b, len),
            None => Self::unsupported(),
        }
    }
    fn from_quadratic_or_unsupported(b: Option<ForwardQuadratic<T>>, len: T) -> Self {
        match b {
            Some(b) => Self::from_quadratic(b, len),
            None => Self::unsupported(),
        }
    }
}

/// The root buffer of one ray: `len` slots of `buf` from `base` (a window
/// rather than a sub-slice, which a GPU cannot take of a mutable storage
/// buffer). Built by [`trace_in`](crate::trace::trace_in), which checks
/// `base + len <= buf.len()`.
pub(crate) struct RootSlots<'a, T> {
    pub(crate) buf: &'a mut [Root<T>],
    pub(crate) base: usize,
    pub(crate) len: usize,
}

impl<'a, T: Copy> RootSlots<'a, T> {
    /// The slots `window = [base, len]` of `buf` (the caller checked that
    /// they lie inside it).
    #[inline]
    pub(crate) fn new(buf: &'a mut [Root<T>], window: [usize; 2]) -> Self {
        let [base, len] = window;
        Self { buf, base, len }
    }

    #[inline]
    pub(crate) fn get(&self, i: usize) -> Root<T> {
        self.buf[self.base + i]
    }
    #[inline]
    pub(crate) fn set(&mut self, i: usize, root: Root<T>) {
        self.buf[self.base + i] = root;
    }
}

/// The per-ray state shared by the marchers and bisections: the root
/// buffer, the counters and the mode.
pub(crate) struct Walk<'a, T> {
    pub(crate) roots: RootSlots<'a, T>,
    pub(crate) n: u32,
    pub(crate) stats: RayStats,
    pub(crate) mode: Mode,
    pub(crate) eps: T,
    /// Where the current step's inner loop resumes (see [`Inner`]).
    pub(crate) inner: Inner,
    /// The counts of the current step's inner-loop iterations that were
    /// completed in earlier legs, or in this one: merged into `stats` when
    /// the step completes.
    pub(crate) inner_stats: RayStats,
}

/// Where a step's inner loop resumes after a guard cut it, or the result
/// it reached.
///
/// [`StepGuard::after_step`] is also asked after each iteration of the
/// loops inside a step — the interval halvings of a step certified by
/// enclosures and the bisection that decides a short interval near the
/// surface (both in `march.rs`) — so that a step that needs more
/// loop iterations than a driver's loop limit allows still ends, over
/// several legs. A paused step is redone from its start on resume (its
/// loop variables are those of the paused trace); its inner loop goes on
/// from here, or gives the result it reached, without evaluating again.
/// Only iterations the guard accepted are recorded here.
///
/// `#[repr(C)]`, 3 words.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[repr(C)]
pub struct Inner {
    /// One of the `INNER_*` constants.
    pub stage: u32,
    /// The halvings already tried ([`INNER_HALVING`]) or of the step found
    /// ([`INNER_STEP`]); for the bisection stages, the path to the interval
    /// to examine or where it ended (bit `i` set: the right half at depth
    /// `i + 1`).
    pub at: u32,
    /// The bisection stages: the depth of that interval (`0`: the whole
    /// interval).
    pub depth: u32,
}

/// [`Inner::stage`]: the step starts afresh.
pub const INNER_NONE: u32 = 0;
/// [`Inner::stage`]: the interval halvings resume at [`Inner::at`].
pub const INNER_HALVING: u32 = 1;
/// [`Inner::stage`]: the halvings found a step after [`Inner::at`]
/// halvings.
pub const INNER_STEP: u32 = 2;
/// [`Inner::stage`]: the halvings (if any) found no step; the bisection
/// resumes at the interval of path [`Inner::at`] and depth [`Inner::depth`].
pub const INNER_BISECTION: u32 = 3;
/// [`Inner::stage`]: the bisection proved its interval root-free.
pub const INNER_CLEAR: u32 = 4;
/// [`Inner::stage`]: the bisection ended in a touch at the interval of
/// [`Inner::at`] and [`Inner::depth`].
pub const INNER_TOUCH: u32 = 5;
/// [`Inner::stage`]: the bisection found a sign change in the interval of
/// [`Inner::at`] and [`Inner::depth`].
pub const INNER_CROSSING: u32 = 6;

/// Whether to go on after registering a root.
///
/// A struct with a flag rather than an enum `Go | Stop(Trace)`: rust-gpu
/// 0.11 cannot move a `Trace` out of an enum ("cannot memcpy dynamically
/// sized data", "cannot cast between pointer types").
#[derive(Clone, Copy)]
pub(crate) struct Next<T> {
    /// Stop with `trace`; else continue tracing.
    pub(crate) stop: bool,
    /// The final trace record when `stop`.
    pub(crate) trace: Trace<T>,
    /// (Not `stop`.) The guard cut the step's inner loop: the step is
    /// undone and the trace pauses before it, its inner loop to resume at
    /// [`Walk::inner`].
    pub(crate) cut: bool,
}

impl<'a, T: Real> Walk<'a, T> {
    pub(crate) fn new(roots: RootSlots<'a, T>, mode: Mode, eps: T) -> Self {
        Self {
            roots,
            n: 0,
            stats: RayStats::default(),
            mode,
            eps,
            inner: Inner::default(),
            inner_stats: RayStats::default(),
        }
    }

    pub(crate) fn done(&self, status: Status, t_reached: T) -> Trace<T> {
        Trace {
            roots: self.n,
            status,
            t_reached,
            stats: self.stats,
        }
    }

    fn go(&self, t: T) -> Next<T> {
        Next {
            stop: false,
            trace: self.done(Status::Finished, t),
            cut: false,
        }
    }

    fn stop(&self, status: Status, t_reached: T) -> Next<T> {
        Next {
            stop: true,
            trace: self.done(status, t_reached),
            cut: false,
        }
    }

    /// The step's inner loop was cut at `t` (see [`Next::cut`]).
    fn cut(&self, t: T) -> Next<T> {
        Next {
            stop: false,
            trace: self.done(Status::Finished, t),
            cut: true,
        }
    }

    /// Registers a root at `t` (the span before `t_before` is processed).
    /// A [`Side::Touch`] within `eps` of the previous root is the same
    /// contact and is dropped; a crossing within `eps` after a touch
    /// replaces it (roots closer than `eps` are reported once).
    pub(crate) fn register(&mut self, root: Root<T>, t_before: T) -> Next<T> {
        if let Some(last) = self.n.checked_sub(1).map(|i| self.roots.get(i as usize)) {
            if (root.t - last.t).abs() <= self.eps {
                if root.side == Side::Touch {
                    return self.go(root.t);
                }
                if last.side == Side::Touch {
                    self.n -= 1;
                }
            }
        }
        let i = self.n as usize;
        if i >= self.roots.len {
            return self.stop(Status::BufferFull, t_before);
        }
        self.roots.set(i, root);
        self.n += 1;
        match self.mode {
            Mode::Opaque => self.stop(Status::Finished, root.t),
            Mode::Transparent => self.go(root.t),
        }
    }
}

/// The outcome of a probe at `t` (a struct, not an enum: see [`Next`]):
/// stop with `next.trace`, or go on from `t` with the sign `sign` before
/// it (`rooted`: a root was registered; else `[t_probe, t]` was proven
/// root-free and `sign` is the sign at the probe).
#[derive(Clone, Copy)]
struct Probe<T> {
    next: Next<T>,
    t: T,
    sign: i32,
    rooted: bool,
}

impl<T> Probe<T> {
    /// After registering a root: go on from `t` with `sign`, unless `next`
    /// stops.
    fn root(next: Next<T>, t: T, sign: i32) -> Self {
        Self {
            next,
            t,
            sign,
            rooted: true,
        }
    }
}

/// The root test near `t`: `s` is the sign at `t` (`0` if `f(t)` is not
/// proven nonzero), `prev` the sign before `t` (`0` at the start of the
/// span), `r` the proven root-free length from `t`.
/// A cut of the bisection under `guard` gives a probe whose `next` is
/// [`cut`](Next::cut).
#[allow(clippy::too_many_arguments)]
fn probe<T: Real, F: Field<T>, G: StepGuard>(
    field: &F,
    ray: &Ray<T>,
    t: T,
    t1: T,
    s: i32,
    prev: i32,
    r: T,
    eps: T,
    w: &mut Walk<'_, T>,
    guard: &mut G,
) -> Probe<T> {
    let tp = advance(t, eps).min(t1);
    let sp = sign_of(value_enclosure(field, ray, tp));
    w.stats.field_evals += 1;
    let approach = if s != 0 { s } else { prev };
    let lo = advance(t, r).min(tp);
    if approach == 0 {
        // The span starts on the surface: the side is the sign after it.
        let side = match sp {
            -1 => Side::Entering,
            1 => Side::Leaving,
            _ => Side::Touch,
        };
        return Probe::root(w.register(Root { t, side }, t), tp, sp);
    }
    if sp != approach {
        // A sign change (or `f(tp)` zero within rounding) in [lo, tp].
        let t_root = if sp == 0 {
            tp
        } else {
            lo + (tp - lo) * T::HALF
        };
        let side = if approach > 0 {
            Side::Entering
        } else {
            Side::Leaving
        };
        return Probe::root(w.register(Root { t: t_root, side }, t), tp, -approach);
    }
    // Same sign at both ends: prove [t, tp] root-free, find a sign change
    // in it, or call it a touch.
    match resolve(field, ray, t, tp, approach, w, guard) {
        Fine::Cut => Probe {
            next: w.cut(t),
            t,
            sign: approach,
            rooted: false,
        },
        Fine::Clear => Probe {
            next: w.go(tp),
            t: tp,
            sign: approach,
            rooted: false,
        },
        Fine::Crossing(t_root, m) => {
            let side = if approach > 0 {
                Side::Entering
            } else {
                Side::Leaving
            };
            Probe::root(w.register(Root { t: t_root, side }, t), m, -approach)
        }
        Fine::Touch(u) => {
            let root = Root {
                t: u,
                side: Side::Touch,
            };
            Probe::root(w.register(root, t), tp, approach)
        }
    }
}

/// How many halvings below `eps` the marchers and bisections try before calling an
/// undecided interval a touch (`eps / 4096`).
pub const TOUCH_DEPTH: u32 = 12;

/// The verdict of [`resolve`] on a short interval.
pub(crate) enum Fine<T> {
    /// Proven root-free.
    Clear,
    /// A sign change in `(u, m]`: a root at `t` (the bracket's middle) and
    /// the point `m` after it, where the sign is the opposite one.
    Crossing(T, T),
    /// Neither proven root-free nor a sign change down to the finest
    /// resolution, first at `u`: the field touches `0` there within the
    /// enclosures' width.
    Touch(T),
    /// The guard cut the bisection: it resumes at [`Walk::inner`].
    Cut,
}

/// Decides a short interval `[a, b]` whose ends both have the sign `s ≠ 0`:
/// interval bisection, left to right, down to `(b − a) / 2^TOUCH_DEPTH`,
/// probing the sign at each midpoint. Interval enclosures are wide near a
/// surface (a root just outside `[a, b]` keeps `0` in a coarse enclosure),
/// so a coarse "cannot exclude `0`" alone would report spurious touches.
///
/// A depth-first walk without a stack: the interval to examine is its path
/// from `[a, b]` (bit `i`: the right half at depth `i + 1`), its ends
/// recomputed by the same halvings each time (so bit for bit those of a
/// stack of intervals). `guard` is asked after each interval (one interval
/// enclosure, perhaps a point); each accepted interval updates `w.inner`
/// (the next interval, or the result reached: see [`Inner`]) and its
/// counts go to `w.inner_stats`; when the guard refuses, the walk stops
/// before the refused interval and gives [`Fine::Cut`].
pub(crate) fn resolve<T: Real, F: Field<T>, G: StepGuard>(
    field: &F,
    ray: &Ray<T>,
    a: T,
    b: T,
    s: i32,
    w: &mut Walk<'_, T>,
    guard: &mut G,
) -> Fine<T> {
    let stage = w.inner.stage;
    if stage >= INNER_CLEAR {
        return bisection_result(a, b, w.inner);
    }
    let (mut path, mut depth) = (w.inner.at, w.inner.depth);
    if stage != INNER_BISECTION {
        (path, depth) = (0, 0);
    }
    // A `while` on a flag (see `run_guarded`): a loop that a driver ends
    // early leaves `running` set, and the walk pauses where it was.
    let mut running = true;
    while running {
        let (u, v) = bisected(a, b, path, depth);
        let enc: Interval<T> = field.eval(ray.at::<Interval<T>>(u, v));
        let cleared = sign_of(enc) == s;
        let m = u + (v - u) * T::HALF;
        let finest = !cleared && (depth >= TOUCH_DEPTH || !(m > u && m < v));
        let mut points = 0u32;
        let mut crossing = false;
        if !cleared && !finest {
            points = 1;
            crossing = sign_of(value_enclosure(field, ray, m)) != s;
        }
        // The next interval, in the walk's order: after a cleared one, the
        // right sibling of its nearest ancestor (itself included) that is
        // a left half; after a split one, its left half.
        let (mut next_path, mut next_depth) = (path, depth + 1);
        let mut last = false;
        if cleared {
            next_depth = depth;
            while next_depth > 0 && (next_path >> (next_depth - 1)) & 1 == 1 {
                next_path &= !(1u32 << (next_depth - 1));
                next_depth -= 1;
            }
            if next_depth == 0 {
                last = true;
            } else {
                next_path |= 1u32 << (next_depth - 1);
            }
        }
        if !guard.after_step() {
            break;
        }
        // Accepted: recorded (only accepted work is, so that a refusal
        // leaves `w.inner` as the last accepted interval left it).
        w.inner_stats.bound_evals += 1;
        w.inner_stats.field_evals += points;
        let mut stage = INNER_BISECTION;
        if finest || crossing {
            // A crossing: everything left of u is cleared, the first root
            // is in (u, m].
            stage = if finest { INNER_TOUCH } else { INNER_CROSSING };
            running = false;
        } else if last {
            stage = INNER_CLEAR;
            running = false;
        } else {
            (path, depth) = (next_path, next_depth);
        }
        w.inner = Inner {
            stage,
            at: path,
            depth,
        };
    }
    if running {
        return Fine::Cut;
    }
    // The result just saved, as a resumed step reads it.
    bisection_result(a, b, w.inner)
}

/// The result of a bisection of `[a, b]` that ended at `inner`
/// ([`INNER_CLEAR`], [`INNER_TOUCH`] or [`INNER_CROSSING`]).
fn bisection_result<T: Real>(a: T, b: T, inner: Inner) -> Fine<T> {
    if inner.stage == INNER_CLEAR {
        return Fine::Clear;
    }
    let (u, v) = bisected(a, b, inner.at, inner.depth);
    let m = u + (v - u) * T::HALF;
    if inner.stage == INNER_TOUCH {
        Fine::Touch(u)
    } else {
        Fine::Crossing(u + (m - u) * T::HALF, m)
    }
}

/// The interval of path `path` and depth `depth` in the bisection of
/// `[a, b]` ([`resolve`]).
fn bisected<T: Real>(a: T, b: T, path: u32, depth: u32) -> (T, T) {
    let (mut u, mut v) = (a, b);
    let mut i = 0u32;
    while i < depth {
        let m = u + (v - u) * T::HALF;
        if (path >> i) & 1 == 1 {
            u = m;
        } else {
            v = m;
        }
        i += 1;
    }
    (u, v)
}

/// A forward bound of the given kind (what `linear_bound`/`quadratic_bound`
/// of `boundtrace-inclusion` compute), counting its bound evaluations: one,
/// or two for "mixed" when the field has a Taylor bound.
fn by_kind<B>(
    kind: BoundKind,
    stats: &mut RayStats,
    bottom_up: impl FnOnce() -> B,
    taylor: impl FnOnce() -> Option<B>,
    tighter: impl FnOnce(B, B) -> B,
) -> Option<B> {
    stats.bound_evals += 1;
    match kind {
        BoundKind::BottomUp => Some(bottom_up()),
        BoundKind::Taylor => taylor(),
        BoundKind::Mixed => {
            let b = bottom_up();
            Some(match taylor() {
                Some(ty) => {
                    stats.bound_evals += 1;
                    tighter(b, ty)
                }
                None => b,
            })
        }
    }
}

/// A bound at `t` on `[t, e]` for the window-based methods; not
/// [`supported`](StepBound::supported) when the method needs a bound the
/// field lacks.
fn window_bound<T: Real, F: Field<T>>(
    field: &F,
    ray: &Ray<T>,
    t: T,
    e: T,
    method: Method,
    stats: &mut RayStats,
) -> StepBound<T> {
    let len = e - t;
    let linear = |kind, stats: &mut RayStats| {
        by_kind(
            kind,
            stats,
            || field.eval(ray.at(t, e)),
            || field.taylor_linear(ray, t, e),
            ForwardLinear::tighter,
        )
    };
    let quadratic = |kind, stats: &mut RayStats| {
        by_kind(
            kind,
            stats,
            || bottom_up_quadratic(field, ray, t, e),
            || field.taylor_quadratic(ray, t, e),
            ForwardQuadratic::tighter,
        )
    };
    match method {
        Method::Segment => segment_bound(field, ray, t, e, stats),
        Method::LinearTaylor => {
            StepBound::from_linear_or_unsupported(linear(BoundKind::Taylor, stats), len)
        }
        Method::LinearBottomUp => {
            StepBound::from_linear_or_unsupported(linear(BoundKind::BottomUp, stats), len)
        }
        Method::LinearMixed => {
            StepBound::from_linear_or_unsupported(linear(BoundKind::Mixed, stats), len)
        }
        Method::QuadraticTaylor => {
            StepBound::from_quadratic_or_unsupported(quadratic(BoundKind::Taylor, stats), len)
        }
        Method::QuadraticBottomUp => {
            StepBound::from_quadratic_or_unsupported(quadratic(BoundKind::BottomUp, stats), len)
        }
        Method::QuadraticMixed => {
            StepBound::from_quadratic_or_unsupported(quadratic(BoundKind::Mixed, stats), len)
        }
        // Sphere, Interval and Affine have their own loops.
        Method::Sphere | Method::Interval | Method::Affine | Method::ScalisQuadratic => {
            StepBound::unsupported()
        }
    }
}

/// Segment tracing's bound (Galin et al. 2020) at `t` on `[t, e]`.
fn segment_bound<T: Real, F: Field<T>>(
    field: &F,
    ray: &Ray<T>,
    t: T,
    e: T,
    stats: &mut RayStats,
) -> StepBound<T> {
    // Galin et al.'s local Lipschitz bound λ = max |f′| on the
    // segment (eq. 11): from the Taylor lines when the field has
    // them, else from the bottom-up lines.
    stats.bound_evals += 1;
    let b = match field.taylor_linear(ray, t, e) {
        Some(b) => b,
        None => field.eval(ray.at(t, e)),
    };
    segment_from_lines(b, e - t)
}

/// [`segment_bound`] from the Taylor lines only: where the field has none
/// on `[t, e]`, no bound (the marcher certifies the step with interval
/// enclosures, as at a kink).
fn segment_taylor_bound<T: Real, F: Field<T>>(
    field: &F,
    ray: &Ray<T>,
    t: T,
    e: T,
    stats: &mut RayStats,
) -> StepBound<T> {
    stats.bound_evals += 1;
    match field.taylor_linear(ray, t, e) {
        Some(b) => segment_from_lines(b, e - t),
        None => StepBound::none(),
    }
}

/// Segment tracing's bound from lines `b` on a window of length `len`: the
/// Lipschitz lines of `λ = max |m±|` from `b`'s start.
fn segment_from_lines<T: Real>(b: ForwardLinear<T>, len: T) -> StepBound<T> {
    if !b.is_valid() {
        return StepBound::from_linear(b, len);
    }
    let [m_lo, m_hi] = b.slopes();
    let lambda = m_lo.abs().max(m_hi.abs());
    if !lambda.is_finite() {
        // No local Lipschitz bound here (e.g. |x| at x = 0).
        return StepBound::none();
    }
    StepBound::from_linear(
        ForwardLinear::lipschitz(b.start(), lambda, b.validity().min(len)),
        len,
    )
}

/// The bottom-up quadratic bound of `f` on `[t, e]`, composed with the
/// forward-inclusion paper's App. B Fig. 21 (c) variant
/// ([`Composition::RelaxMax`]): exact at `t` and valid on the whole window.
///
/// The paper's main variant (Fig. 21 a) ends the validity interval where the
/// argument of a convex/concave function turns back — for a distance
/// `√(|p − c|²)`, at the ray's closest approach to *every* primitive's centre,
/// even far from the surface and for primitives a `min` discards. On the
/// aggregates (110 primitives) that cut each window short: measured on
/// `aggregate-2`, 300 rays, one run, `quadratic-bottom-up` took 98.6 steps
/// per ray with (a) and 8.2 with (c); `hrbf-8` 8.5 and 5.0; `blobs`
/// unchanged (6.1); agreement 100% and no step past a root in every case
/// (BENCHMARKS.md, "Validity cuts").
fn bottom_up_quadratic<T: Real, F: Field<T>>(
    field: &F,
    ray: &Ray<T>,
    t: T,
    e: T,
) -> ForwardQuadratic<T> {
    let tq = ForwardQuadratic::ray_param_with(t, e, Composition::RelaxMax);
    let [dx, dy, dz] = ray.dir;
    let [ox, oy, oz] = ray.origin;
    field.eval([tq * dx + ox, tq * dy + oy, tq * dz + oz])
}

/// What [`interval_step`] found.
enum Halving<T> {
    /// A root-free step of this length.
    Step(T),
    /// No step down to `eps`.
    Fail,
    /// The guard cut the halvings: they resume at [`Walk::inner`].
    Cut,
}

/// The longest of `e − t`, `(e − t)/2`, … (down to `eps`) over which an
/// interval enclosure of `f` has the sign `s ≠ 0`; [`Halving::Fail`] if none
/// has.
///
/// `guard` is asked after each halving tried; when it refuses, the
/// halvings stop before the refused one, `w.inner` says where they resume
/// and the result is [`Halving::Cut`]. A step found is saved there too, so
/// that a resumed step does not try the halvings again (after a failure
/// the bisection that follows, [`resolve`], records its first accepted
/// interval, from which a resumed step skips the halvings). The counts go
/// to `w.inner_stats`.
#[allow(clippy::too_many_arguments)]
fn interval_step<T: Real, F: Field<T>, G: StepGuard>(
    field: &F,
    ray: &Ray<T>,
    t: T,
    e: T,
    s: i32,
    eps: T,
    w: &mut Walk<'_, T>,
    guard: &mut G,
) -> Halving<T> {
    let stage = w.inner.stage;
    if s == 0 || stage >= INNER_BISECTION {
        return Halving::Fail;
    }
    let mut k = if stage == INNER_HALVING || stage == INNER_STEP {
        w.inner.at
    } else {
        0u32
    };
    let mut len = e - t;
    let mut i = 0u32;
    while i < k {
        len = len * T::HALF;
        i += 1;
    }
    if stage == INNER_STEP {
        return Halving::Step(len);
    }
    let mut found = false;
    let mut refused = false;
    while !found && len >= eps {
        let enc: Interval<T> = field.eval(ray.at::<Interval<T>>(t, advance(t, len)));
        let fits = sign_of(enc) == s;
        if !guard.after_step() {
            refused = true;
            break;
        }
        // Accepted: recorded (only accepted work is, see `resolve`).
        w.inner_stats.bound_evals += 1;
        if fits {
            found = true;
        } else {
            len = len * T::HALF;
            k += 1;
        }
        w.inner = Inner {
            stage: if found { INNER_STEP } else { INNER_HALVING },
            at: k,
            depth: 0,
        };
    }
    if found {
        Halving::Step(len)
    } else if refused || len >= eps {
        // Refused, or a loop that a driver ended early (`len ≥ eps`).
        Halving::Cut
    } else {
        Halving::Fail
    }
}

/// Tries to replace a short safe step by `min_step` (see the module docs):
/// returns the step to take.
#[allow(clippy::too_many_arguments)]
fn min_step_extension<T: Real, F: Field<T>>(
    field: &F,
    ray: &Ray<T>,
    t: T,
    t1: T,
    step: T,
    sign: i32,
    params: &Params<T>,
    stats: &mut RayStats,
) -> T {
    if !(params.min_step > step) || sign == 0 {
        return step;
    }
    let e = advance(t, params.min_step).min(t1);
    let enc: Interval<T> = field.eval(ray.at::<Interval<T>>(t, e));
    stats.bound_evals += 1;
    if sign_of(enc) == sign { e - t } else { step }
}

/// Marches `ray` on `span` with a window-based method or sphere tracing.
pub(crate) fn march<T: Real, F: Field<T>>(
    field: &F,
    ray: &Ray<T>,
    span: [T; 2],
    method: Method,
    mode: Mode,
    params: &Params<T>,
    roots: RootSlots<'_, T>,
) -> Trace<T> {
    if method == Method::Sphere {
        return sphere(field, ray, span, mode, params, roots);
    }
    let mut state = MarchState::start(span, params);
    let next = window_run::<AnyWindow, _, _, _>(
        field,
        ray,
        span,
        mode,
        params,
        roots,
        &mut state,
        &mut Unguarded,
        method,
        (),
    );
    final_record(next)
}

/// Which bound a window marcher builds: a type rather than a [`Method`]
/// value, so that a caller needing one method links that method's bound
/// alone (a GPU driver inlines every call: BENCHMARKS.md "GPU").
///
/// Associated functions, not methods: rust-gpu cannot take a pointer to a
/// zero-sized field ("cannot offset a pointer to an arbitrary element").
pub(crate) trait WindowBounds {
    /// What the bounds read besides the field, kept in the marcher's loop
    /// variables and passed by value (`()` for all but [`CachedMixed`]).
    type Cache<T: Copy>: Copy;

    /// The bound of `method` at `t` on `[t, e]` (see [`window_bound`]).
    fn bound<T: Real, F: Field<T>>(
        method: Method,
        field: &F,
        ray: &Ray<T>,
        t: T,
        e: T,
        stats: &mut RayStats,
        cache: Self::Cache<T>,
    ) -> StepBound<T>;

    /// Whether the bound on `[t, e]` can be built now; when not, the step
    /// is undone and the trace pauses before it ([`CachedMixed`]: until
    /// the Taylor part is in the cache).
    #[inline]
    fn ready<T: Real>(_cache: Self::Cache<T>, _t: T, _e: T) -> bool {
        true
    }
}

/// Every window method, chosen at run time.
pub(crate) struct AnyWindow;

impl WindowBounds for AnyWindow {
    type Cache<T: Copy> = ();

    fn bound<T: Real, F: Field<T>>(
        method: Method,
        field: &F,
        ray: &Ray<T>,
        t: T,
        e: T,
        stats: &mut RayStats,
        _cache: (),
    ) -> StepBound<T> {
        window_bound(field, ray, t, e, method, stats)
    }
}

/// [`Method::Segment`] with the CPU's bound, [`segment_bound`]: the
/// Taylor lines where the field has them, else the bottom-up lines
/// (whatever the method given).
pub(crate) struct SegmentLines;

impl WindowBounds for SegmentLines {
    type Cache<T: Copy> = ();

    fn bound<T: Real, F: Field<T>>(
        _method: Method,
        field: &F,
        ray: &Ray<T>,
        t: T,
        e: T,
        stats: &mut RayStats,
        _cache: (),
    ) -> StepBound<T> {
        segment_bound(field, ray, t, e, stats)
    }
}

/// [`Method::Segment`] from Taylor lines only (whatever the method given):
/// the bottom-up lines' code is ≈ 30 times larger than the Taylor lines'
/// on a GPU that inlines every call (BENCHMARKS.md "GPU").
pub(crate) struct SegmentTaylor;

impl WindowBounds for SegmentTaylor {
    type Cache<T: Copy> = ();

    fn bound<T: Real, F: Field<T>>(
        _method: Method,
        field: &F,
        ray: &Ray<T>,
        t: T,
        e: T,
        stats: &mut RayStats,
        _cache: (),
    ) -> StepBound<T> {
        segment_taylor_bound(field, ray, t, e, stats)
    }
}

/// One forward bound alone, whatever the method given: Taylor
/// (`BOTTOM_UP = false`) or bottom-up (the field evaluated in forward
/// arithmetic), linear or quadratic (`QUADRATIC`), as [`window_bound`]
/// builds it for [`Method::LinearTaylor`], [`Method::QuadraticTaylor`],
/// [`Method::LinearBottomUp`] and [`Method::QuadraticBottomUp`], so that a
/// caller links none of the other three (BENCHMARKS.md "GPU").
pub(crate) struct OneBound<const BOTTOM_UP: bool, const QUADRATIC: bool>;

/// [`Method::LinearTaylor`] (`QUADRATIC = false`) or
/// [`Method::QuadraticTaylor`]: the Taylor bound alone.
pub(crate) type TaylorWindow<const QUADRATIC: bool> = OneBound<false, QUADRATIC>;

/// [`Method::LinearBottomUp`] (`QUADRATIC = false`) or
/// [`Method::QuadraticBottomUp`]: the bottom-up bound alone.
pub(crate) type BottomUpWindow<const QUADRATIC: bool> = OneBound<true, QUADRATIC>;

impl<const BOTTOM_UP: bool, const QUADRATIC: bool> WindowBounds for OneBound<BOTTOM_UP, QUADRATIC> {
    type Cache<T: Copy> = ();

    fn bound<T: Real, F: Field<T>>(
        _method: Method,
        field: &F,
        ray: &Ray<T>,
        t: T,
        e: T,
        stats: &mut RayStats,
        _cache: (),
    ) -> StepBound<T> {
        // One bound evaluation, as `by_kind` counts a Taylor or bottom-up
        // bound.
        stats.bound_evals += 1;
        let len = e - t;
        if QUADRATIC {
            let b = if BOTTOM_UP {
                Some(bottom_up_quadratic(field, ray, t, e))
            } else {
                field.taylor_quadratic(ray, t, e)
            };
            StepBound::from_quadratic_or_unsupported(b, len)
        } else {
            let b = if BOTTOM_UP {
                Some(field.eval(ray.at(t, e)))
            } else {
                field.taylor_linear(ray, t, e)
            };
            StepBound::from_linear_or_unsupported(b, len)
        }
    }
}

/// [`Method::LinearMixed`] (`QUADRATIC = false`) or
/// [`Method::QuadraticMixed`] alone, whatever the method given: the
/// bottom-up bound and, where the field has one, the Taylor bound, the
/// tighter side of each kept, as [`window_bound`] builds them (`by_kind`
/// with "mixed"), so that a caller links neither the other kind's bounds
/// nor the single-bound methods (BENCHMARKS.md "GPU").
pub(crate) struct MixedWindow<const QUADRATIC: bool>;

impl<const QUADRATIC: bool> WindowBounds for MixedWindow<QUADRATIC> {
    type Cache<T: Copy> = ();

    fn bound<T: Real, F: Field<T>>(
        _method: Method,
        field: &F,
        ray: &Ray<T>,
        t: T,
        e: T,
        stats: &mut RayStats,
        _cache: (),
    ) -> StepBound<T> {
        let len = e - t;
        if QUADRATIC {
            let b = by_kind(
                BoundKind::Mixed,
                stats,
                || bottom_up_quadratic(field, ray, t, e),
                || field.taylor_quadratic(ray, t, e),
                ForwardQuadratic::tighter,
            );
            StepBound::from_quadratic_or_unsupported(b, len)
        } else {
            let b = by_kind(
                BoundKind::Mixed,
                stats,
                || field.eval(ray.at(t, e)),
                || field.taylor_linear(ray, t, e),
                ForwardLinear::tighter,
            );
            StepBound::from_linear_or_unsupported(b, len)
        }
    }
}

/// The Taylor part of a [`Method::LinearMixed`] or [`Method::QuadraticMixed`]
/// step's bound, computed apart from the rest of the trace
/// ([`fill_taylor_cache`](crate::fill_taylor_cache)) and read by
/// [`trace_linear_mixed_cached_resume_in`](crate::trace_linear_mixed_cached_resume_in)
/// and [`trace_quadratic_mixed_cached_resume_in`](crate::trace_quadratic_mixed_cached_resume_in).
///
/// A GPU that inlines every call compiles a mixed step — a bottom-up and a
/// Taylor bound over every primitive — into one pipeline of 3.4–3.9 M
/// SPIR-V instructions, which lavapipe needed ≈ 20 GB and 8–9 minutes to
/// compile (BENCHMARKS.md "GPU", session 28). With the Taylor part in a
/// pipeline of its own, run between two legs, each pipeline holds one
/// bound. The trace is the same, bit for bit: the same function builds the
/// Taylor bound on the same window, and the step combines it with the
/// bottom-up bound as an uninterrupted mixed trace does.
///
/// `#[repr(C)]`, 17 words for `f32`: a GPU keeps one per pixel beside the
/// pixel's [`MarchState`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct TaylorCache<T> {
    /// The window `[t, e]` the bound is for (when `filled != 0`).
    pub t: T,
    /// The window's end.
    pub e: T,
    /// `1` when the cache holds the Taylor bound on `[t, e]`, else `0`.
    pub filled: u32,
    /// `1` when the field has a Taylor bound on `[t, e]` (the cached
    /// `linear` or `quadratic` one), `0` when it has none (the step uses
    /// the bottom-up bound alone, as an uninterrupted mixed trace does).
    pub some: u32,
    /// The linear Taylor bound ([`Method::LinearMixed`]).
    pub linear: ForwardLinear<T>,
    /// The quadratic Taylor bound ([`Method::QuadraticMixed`]).
    pub quadratic: ForwardQuadratic<T>,
}

impl<T: Real> TaylorCache<T> {
    /// The empty cache (no bound).
    pub const EMPTY: Self = Self {
        t: T::ZERO,
        e: T::ZERO,
        filled: 0,
        some: 0,
        linear: ForwardLinear::INVALID,
        quadratic: ForwardQuadratic::INVALID,
    };

    /// Whether the cache holds the bound on `[t, e]` (the same window; a
    /// NaN end is never held).
    #[inline]
    pub fn holds(&self, t: T, e: T) -> bool {
        self.filled != 0 && self.t == t && self.e == e
    }
}

impl<T: Real> Default for TaylorCache<T> {
    fn default() -> Self {
        Self::EMPTY
    }
}

/// [`MixedWindow`] with the Taylor part of each bound read from a
/// [`TaylorCache`]: a step whose window the cache does not hold is not
/// taken (the trace pauses before it, for the cache to be filled), so the
/// code of the Taylor bounds is not linked in.
pub(crate) struct CachedMixed<const QUADRATIC: bool>;

impl<const QUADRATIC: bool> WindowBounds for CachedMixed<QUADRATIC> {
    type Cache<T: Copy> = TaylorCache<T>;

    fn bound<T: Real, F: Field<T>>(
        _method: Method,
        field: &F,
        ray: &Ray<T>,
        t: T,
        e: T,
        stats: &mut RayStats,
        cache: TaylorCache<T>,
    ) -> StepBound<T> {
        let len = e - t;
        let some = cache.some != 0;
        if QUADRATIC {
            let b = by_kind(
                BoundKind::Mixed,
                stats,
                || bottom_up_quadratic(field, ray, t, e),
                || some.then_some(cache.quadratic),
                ForwardQuadratic::tighter,
            );
            StepBound::from_quadratic_or_unsupported(b, len)
        } else {
            let b = by_kind(
                BoundKind::Mixed,
                stats,
                || field.eval(ray.at(t, e)),
                || some.then_some(cache.linear),
                ForwardLinear::tighter,
            );
            StepBound::from_linear_or_unsupported(b, len)
        }
    }

    #[inline]
    fn ready<T: Real>(cache: TaylorCache<T>, t: T, e: T) -> bool {
        cache.holds(t, e)
    }
}

/// The window `[t, e]` of the next step of a window marcher in state `st`
/// on a span ending at `t1` ([`Window`]'s step builds its bound there).
#[inline]
pub(crate) fn next_window<T: Real>(st: &MarchState<T>, t1: T, eps: T) -> [T; 2] {
    [st.t, window_end(st.t, st.win, eps, t1)]
}

/// The end of the window of length `win` (at least `eps`) from `t`,
/// before `t1`.
#[inline]
fn window_end<T: Real>(t: T, win: T, eps: T, t1: T) -> T {
    advance(t, win.max(eps)).min(t1)
}

/// The window marcher (forward-inclusion paper Alg. 1) from `st`, under
/// `guard`: `stop` with the final record, or paused (`!stop`, `trace` the
/// counts so far) with `st` where to resume.
#[allow(clippy::too_many_arguments)]
pub(crate) fn window_run<B: WindowBounds, T: Real, F: Field<T>, G: StepGuard>(
    field: &F,
    ray: &Ray<T>,
    span: [T; 2],
    mode: Mode,
    params: &Params<T>,
    roots: RootSlots<'_, T>,
    st: &mut MarchState<T>,
    guard: &mut G,
    method: Method,
    cache: B::Cache<T>,
) -> Next<T> {
    let mut w = Walk::new(roots, mode, params.eps);
    w.n = st.roots;
    w.stats = st.stats;
    (w.inner, w.inner_stats) = (st.inner, st.inner_stats);
    let mut s = Window::<T, B> {
        t: st.t,
        win: st.win,
        prev: st.prev,
        method,
        cache,
        bounds: PhantomData,
    };
    let next = run_guarded(field, ray, span[1], params, &mut s, &mut w, guard);
    if !next.stop {
        *st = MarchState {
            t: s.t,
            win: s.win,
            prev: s.prev,
            roots: w.n,
            stats: w.stats,
            inner: w.inner,
            inner_stats: w.inner_stats,
            ..*st
        };
    }
    next
}

/// The loop variables of [`window_run`].
struct Window<T: Copy, B: WindowBounds> {
    t: T,
    /// The length of the next window.
    win: T,
    /// The sign before `t`.
    prev: i32,
    /// The method, for [`AnyWindow`].
    method: Method,
    /// What the bounds read ([`WindowBounds::Cache`]).
    cache: B::Cache<T>,
    bounds: PhantomData<B>,
}

impl<T: Copy, B: WindowBounds> Clone for Window<T, B> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<T: Copy, B: WindowBounds> Copy for Window<T, B> {}

impl<T: Real, B: WindowBounds> Stepper<T> for Window<T, B> {
    fn at(&self) -> T {
        self.t
    }

    /// One step of Alg. 1 from `t` (before `t1`).
    fn step<F: Field<T>, G: StepGuard>(
        &mut self,
        field: &F,
        ray: &Ray<T>,
        t1: T,
        params: &Params<T>,
        w: &mut Walk<'_, T>,
        guard: &mut G,
    ) -> Next<T> {
        let eps = params.eps;
        let t = self.t;
        w.stats.steps += 1;
        let e = window_end(t, self.win, eps, t1);
        if !B::ready(self.cache, t, e) {
            return w.cut(t);
        }
        let b = B::bound(self.method, field, ray, t, e, &mut w.stats, self.cache);
        if !b.supported {
            return w.stop(Status::Unsupported, t);
        }
        // A bound undefined at t, not exact there (e.g. |x| or √ at a kink
        // of the field), or valid on less than `eps` (validity intervals,
        // paper §4.2, can collapse near a kink or a near-tangency: stepping
        // by them would crawl): certify a step with interval enclosures.
        let mut s = sign_of(b.start);
        let degenerate = b.start.is_empty() || !(b.h >= eps.min(e - t));
        if degenerate || s == 0 {
            let f = value_enclosure(field, ray, t);
            w.stats.field_evals += 1;
            s = sign_of(f);
        }
        // The proven root-free length when a root may lie within eps.
        let near = if degenerate || (s != 0 && sign_of(b.start) == 0) {
            match interval_step(field, ray, t, e, s, eps, w, guard) {
                Halving::Step(step) => {
                    self.prev = s;
                    self.t = advance(t, step);
                    self.win = step * params.k;
                    return w.go(self.t);
                }
                Halving::Cut => return w.cut(t),
                Halving::Fail => Some(T::ZERO),
            }
        } else {
            match b.safe {
                _ if s == 0 => Some(T::ZERO),
                Some(r) if r < eps => Some(r),
                _ => None,
            }
        };
        if let Some(r) = near {
            let p = probe(field, ray, t, t1, s, self.prev, r, eps, w, guard);
            if p.next.stop || p.next.cut {
                return p.next;
            }
            (self.t, self.prev) = (p.t, p.sign);
            // Past a root (transparent mode) Alg. 1 starts afresh on the
            // rest of the span [t, t1]; after a cleared eps it grows again.
            self.win = if p.rooted {
                t1 - self.t
            } else {
                eps * params.k
            };
            return w.go(self.t);
        }
        let step = match b.safe {
            Some(r) => min_step_extension(field, ray, t, t1, r, s, params, &mut w.stats),
            // No root of the bound on its validity interval: skip it all.
            None => b.h,
        };
        self.prev = s;
        self.t = advance(t, step);
        self.win = step * params.k;
        w.go(self.t)
    }
}

/// The loop variables of a marcher, one step at a time.
trait Stepper<T: Real>: Copy {
    /// The ray parameter the next step starts from.
    fn at(&self) -> T;
    /// One step from [`at`](Stepper::at) (before `t1`): `stop` with the
    /// final record, go on from the updated loop variables, or
    /// [`cut`](Next::cut) by `guard` inside the step (the caller undoes
    /// the step; its inner loop resumes at [`Walk::inner`]).
    fn step<F: Field<T>, G: StepGuard>(
        &mut self,
        field: &F,
        ray: &Ray<T>,
        t1: T,
        params: &Params<T>,
        w: &mut Walk<'_, T>,
        guard: &mut G,
    ) -> Next<T>;
}

/// The marching loop under `guard`: `stop` with the final record, or
/// paused (`!stop`) with `s` and `w` where to resume.
fn run_guarded<T: Real, F: Field<T>, S: Stepper<T>, G: StepGuard>(
    field: &F,
    ray: &Ray<T>,
    t1: T,
    params: &Params<T>,
    s: &mut S,
    w: &mut Walk<'_, T>,
    guard: &mut G,
) -> Next<T> {
    // A `while` on a flag, not `loop` with returns: a driver that ends loops
    // early (llvmpipe's loop limit, see `StepGuard`) leaves this loop after
    // a verified step with `running` still set, and the trace pauses there
    // instead of running into code that Rust deems unreachable.
    let mut out = w.go(s.at());
    let mut running = true;
    while running {
        if !(s.at() < t1) {
            out = w.stop(Status::Finished, t1);
            running = false;
            continue;
        }
        if w.stats.steps >= params.max_steps {
            out = w.stop(Status::MaxSteps, s.at());
            running = false;
            continue;
        }
        if !guard.before_step(w.stats.steps) {
            break;
        }
        // What the step may change, to undo it: the loop variables, the
        // counters and the last root (a crossing may replace a touch).
        let (before, n, stats) = (*s, w.n, w.stats);
        let last = if n > 0 {
            w.roots.get(n as usize - 1)
        } else {
            Root {
                t: T::ZERO,
                side: Side::Touch,
            }
        };
        let mut next = s.step(field, ray, t1, params, w, guard);
        // Undone when cut inside, or refused after: the step's inner loop
        // keeps the progress its guard accepted (`w.inner`).
        if next.cut || !guard.after_step() {
            if n > 0 {
                w.roots.set(n as usize - 1, last);
            }
            (*s, w.n, w.stats) = (before, n, stats);
            break;
        }
        // The step is done: its inner loops' counts join the trace's.
        w.stats.field_evals += w.inner_stats.field_evals;
        w.stats.bound_evals += w.inner_stats.bound_evals;
        (w.inner, w.inner_stats) = (Inner::default(), RayStats::default());
        if next.stop {
            next.trace.stats = w.stats;
            out = next;
            running = false;
        }
    }
    if running {
        return w.go(s.at());
    }
    out
}

/// Sphere tracing with the global Lipschitz bound and optional
/// over-relaxation (Keinert et al. 2014): an over-relaxed step `ω·r` is
/// kept only when the unbounding intervals at both ends overlap (so the
/// whole step is proven root-free); otherwise the marcher falls back to the
/// safe step `r` and stops over-relaxing for this ray.
pub(crate) fn sphere<T: Real, F: Field<T>>(
    field: &F,
    ray: &Ray<T>,
    span: [T; 2],
    mode: Mode,
    params: &Params<T>,
    roots: RootSlots<'_, T>,
) -> Trace<T> {
    let mut state = MarchState::start(span, params);
    let next = sphere_run(
        field,
        ray,
        span,
        mode,
        params,
        roots,
        &mut state,
        &mut Unguarded,
    );
    final_record(next)
}

/// The record of a run that is not resumed: `Unguarded` never pauses, but
/// a driver that ends loops early can make [`sphere_run`] pause (see
/// there); such a ray is reported unfinished ([`Status::MaxSteps`] at the
/// point reached), never `Finished`.
fn final_record<T>(next: Next<T>) -> Trace<T> {
    if next.stop {
        next.trace
    } else {
        Trace {
            status: Status::MaxSteps,
            ..next.trace
        }
    }
}

/// Everything a marcher carries from one step to the next, so that it can
/// pause between two steps and resume later with the same result as an
/// uninterrupted trace ([`trace_resume_in`](crate::trace_resume_in),
/// [`trace_sphere_resume_in`](crate::trace_sphere_resume_in),
/// [`trace_segment_resume_in`](crate::trace_segment_resume_in)).
///
/// `#[repr(C)]`, 17 words for `f32`: the GPU keeps one per pixel in a
/// storage buffer between dispatches. The root buffer (roots `0..roots`)
/// is kept by the caller. A state belongs to one method and one span.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct MarchState<T> {
    /// The ray parameter the next step starts from.
    pub t: T,
    /// Sphere tracing: the over-relaxation factor still in force (`1` once
    /// an over-relaxed step failed).
    pub omega: T,
    /// Window methods: the length of the next window (Alg. 1).
    pub win: T,
    /// Sphere tracing: the enclosure of `f(t)` when it is already known
    /// (`has_known != 0`): its `[lo, hi]`.
    pub known: [T; 2],
    /// `1` when `known` holds the enclosure of `f(t)`, else `0`.
    pub has_known: u32,
    /// The sign of `f` before `t` (`0` at the start of the span).
    pub prev: i32,
    /// Roots registered so far.
    pub roots: u32,
    /// The counters so far (of the steps completed).
    pub stats: RayStats,
    /// Where the next step's inner loop resumes, when a guard cut it.
    pub inner: Inner,
    /// The counts of that step's inner-loop iterations already done.
    pub inner_stats: RayStats,
}

impl<T: Real> MarchState<T> {
    /// The state before the first step on `span`, for any marcher.
    pub fn start(span: [T; 2], params: &Params<T>) -> Self {
        Self {
            t: span[0],
            omega: params.omega,
            win: span[1] - span[0],
            known: [T::ZERO; 2],
            has_known: 0,
            prev: 0,
            roots: 0,
            stats: RayStats::default(),
            inner: Inner::default(),
            inner_stats: RayStats::default(),
        }
    }
}

/// Decides, between two steps of a resumable trace, whether it goes on.
///
/// A GPU driver may cut a shader's loops short (lavapipe's loop limiter,
/// BENCHMARKS.md "GPU"): a guard that detects it lets the trace undo the
/// step whose loops were cut and pause before it, so the host can resume
/// it in a new dispatch with a fresh limit. On the CPU, [`Unguarded`].
pub trait StepGuard {
    /// Called before each step, with the steps taken so far: `false`
    /// pauses the trace there.
    fn before_step(&mut self, steps: u32) -> bool;
    /// Called after each step, and after each iteration of the loops
    /// inside a step (see [`Inner`]): `false` says the work since the
    /// previous call cannot be trusted; the step is undone and the trace
    /// pauses before it, its inner loop to resume after the last iteration
    /// accepted.
    fn after_step(&mut self) -> bool;
}

/// The guard that never pauses a trace.
#[derive(Clone, Copy, Debug, Default)]
pub struct Unguarded;

impl StepGuard for Unguarded {
    #[inline]
    fn before_step(&mut self, _steps: u32) -> bool {
        true
    }
    #[inline]
    fn after_step(&mut self) -> bool {
        true
    }
}

/// [`sphere`] from `st`, under `guard`: `stop` with the final record, or
/// paused (`!stop`, `trace` the counts so far) with `st` where to resume.
#[allow(clippy::too_many_arguments)]
pub(crate) fn sphere_run<T: Real, F: Field<T>, G: StepGuard>(
    field: &F,
    ray: &Ray<T>,
    span: [T; 2],
    mode: Mode,
    params: &Params<T>,
    roots: RootSlots<'_, T>,
    st: &mut MarchState<T>,
    guard: &mut G,
) -> Next<T> {
    let [t0, t1] = span;
    let mut w = Walk::new(roots, mode, params.eps);
    w.n = st.roots;
    w.stats = st.stats;
    (w.inner, w.inner_stats) = (st.inner, st.inner_stats);
    let Some(l) = field.lipschitz() else {
        return w.stop(Status::Unsupported, t0);
    };
    let lambda = round::mul_up(l, ray.speed());
    if !(lambda > T::ZERO) || !lambda.is_finite() {
        return w.stop(Status::Unsupported, t0);
    }
    let mut s = Sphere {
        t: st.t,
        prev: st.prev,
        omega: st.omega,
        known: if st.has_known != 0 {
            Some(Interval::new(st.known[0], st.known[1]))
        } else {
            None
        },
        lambda,
    };
    let next = run_guarded(field, ray, t1, params, &mut s, &mut w, guard);
    if !next.stop {
        let (known, has_known) = match s.known {
            Some(k) => ([k.lo(), k.hi()], 1),
            None => ([T::ZERO; 2], 0),
        };
        *st = MarchState {
            t: s.t,
            omega: s.omega,
            known,
            has_known,
            prev: s.prev,
            roots: w.n,
            stats: w.stats,
            inner: w.inner,
            inner_stats: w.inner_stats,
            ..*st
        };
    }
    next
}

/// The loop variables of [`sphere_run`].
#[derive(Clone, Copy)]
struct Sphere<T> {
    t: T,
    prev: i32,
    omega: T,
    /// The enclosure of f at t when it is already known (after an
    /// over-relaxed step), to avoid evaluating it twice.
    known: Option<Interval<T>>,
    /// The Lipschitz bound along the ray, `L·|d|` rounded up.
    lambda: T,
}

impl<T: Real> Stepper<T> for Sphere<T> {
    fn at(&self) -> T {
        self.t
    }

    /// One sphere-tracing step from `t` (before `t1`).
    fn step<F: Field<T>, G: StepGuard>(
        &mut self,
        field: &F,
        ray: &Ray<T>,
        t1: T,
        params: &Params<T>,
        w: &mut Walk<'_, T>,
        guard: &mut G,
    ) -> Next<T> {
        let eps = params.eps;
        let t = self.t;
        w.stats.steps += 1;
        let f = match self.known.take() {
            Some(f) => f,
            None => {
                w.stats.field_evals += 1;
                value_enclosure(field, ray, t)
            }
        };
        let sg = sign_of(f);
        // |f| / λ, rounded down: the proven root-free length.
        let r = if sg == 0 {
            T::ZERO
        } else {
            round::div_down(f.mig(), self.lambda)
        };
        if r < eps {
            let p = probe(field, ray, t, t1, sg, self.prev, r, eps, w, guard);
            (self.t, self.prev) = (p.t, p.sign);
            return p.next;
        }
        self.prev = sg;
        if self.omega > T::ONE {
            let step = r * self.omega;
            let tn = advance(t, step).min(t1);
            let fn_ = value_enclosure(field, ray, tn);
            w.stats.field_evals += 1;
            // Root-free radius around tn (0 if the sign changed or is unknown).
            let rn = if sign_of(fn_) == sg {
                round::div_down(fn_.mig(), self.lambda)
            } else {
                T::ZERO
            };
            if round::add_down(r, rn) >= tn - t || tn >= t1 {
                self.t = tn;
                self.known = Some(fn_);
                return w.go(tn);
            }
            // Failed: fall back to the safe step, no more over-relaxation.
            self.omega = T::ONE;
        }
        let step = min_step_extension(field, ray, t, t1, r, sg, params, &mut w.stats);
        self.t = advance(t, step);
        w.go(self.t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trace::trace;
    use boundtrace_inclusion::FieldNum;

    /// A ball of radius `r` at the origin (signed distance, L = 1).
    struct Ball(f64);
    impl Field<f64> for Ball {
        fn eval<N: FieldNum<f64>>(&self, p: [N; 3]) -> N {
            (p[0].sqr() + p[1].sqr() + p[2].sqr()).sqrt() - self.0
        }
        fn lipschitz(&self) -> Option<f64> {
            Some(1.0)
        }
    }

    /// `f(x) = x² − c` along x (two roots at ±√c), no Lipschitz bound.
    struct Parabola(f64);
    impl Field<f64> for Parabola {
        fn eval<N: FieldNum<f64>>(&self, p: [N; 3]) -> N {
            p[0].sqr() - self.0
        }
    }

    const NONE: Root<f64> = Root {
        t: f64::NAN,
        side: Side::Touch,
    };

    fn methods() -> [Method; 6] {
        [
            Method::Sphere,
            Method::Segment,
            Method::LinearBottomUp,
            Method::LinearMixed,
            Method::QuadraticBottomUp,
            Method::QuadraticMixed,
        ]
    }

    #[test]
    fn ball_opaque_and_transparent() {
        let ray = Ray::new([-3.0, 0.1, 0.0], [1.0, 0.0, 0.0]);
        let p = Params::new();
        let exact = (1.0f64 - 0.01).sqrt();
        for m in methods() {
            let mut buf = [NONE; 4];
            let tr = trace(&Ball(1.0), &ray, [0.0, 6.0], m, Mode::Opaque, &p, &mut buf);
            assert_eq!(tr.status, Status::Finished, "{m}");
            assert_eq!(tr.roots, 1, "{m}");
            assert!(
                (buf[0].t - (3.0 - exact)).abs() <= p.eps,
                "{m}: {}",
                buf[0].t
            );
            assert_eq!(buf[0].side, Side::Entering);
            let tr = trace(
                &Ball(1.0),
                &ray,
                [0.0, 6.0],
                m,
                Mode::Transparent,
                &p,
                &mut buf,
            );
            assert_eq!((tr.status, tr.roots), (Status::Finished, 2), "{m}");
            assert!(
                (buf[1].t - (3.0 + exact)).abs() <= p.eps,
                "{m}: {}",
                buf[1].t
            );
            assert_eq!(buf[1].side, Side::Leaving);
        }
    }

    #[test]
    fn sphere_entry_matches_the_dispatch() {
        use crate::trace::{trace_in, trace_sphere_in};
        let p = Params::new();
        for (ray, mode) in [
            (Ray::new([-3.0, 0.1, 0.0], [1.0, 0.0, 0.0]), Mode::Opaque),
            (
                Ray::new([-3.0, 0.3, 0.2], [1.0, 0.1, 0.0]),
                Mode::Transparent,
            ),
            (
                Ray::new([-3.0, 1.5, 0.0], [1.0, 0.0, 0.0]),
                Mode::Transparent,
            ),
        ] {
            for (span, window) in [
                ([0.0, 6.0], [1, 2]),
                ([0.0, 6.0], [3, 2]),
                ([2.0, 1.0], [0, 2]),
            ] {
                let (mut a, mut b) = ([NONE; 4], [NONE; 4]);
                let ta = trace_in(
                    &Ball(1.0),
                    &ray,
                    span,
                    Method::Sphere,
                    mode,
                    &p,
                    &mut a,
                    window,
                );
                let tb = trace_sphere_in(&Ball(1.0), &ray, span, mode, &p, &mut b, window);
                assert_eq!(ta, tb);
                for (x, y) in a.iter().zip(&b) {
                    assert_eq!((x.t.to_bits(), x.side), (y.t.to_bits(), y.side));
                }
            }
        }
    }

    /// A guard that allows `left` steps per leg and rejects every `undo`-th
    /// step after the fact (as a driver's loop limiter would).
    struct Faulty<'a> {
        left: u32,
        undo: u32,
        calls: &'a mut u32,
    }
    impl StepGuard for Faulty<'_> {
        fn before_step(&mut self, _steps: u32) -> bool {
            if self.left == 0 {
                return false;
            }
            self.left -= 1;
            true
        }
        fn after_step(&mut self) -> bool {
            *self.calls += 1;
            *self.calls % self.undo != 0
        }
    }

    #[test]
    fn a_paused_run_is_reported_unfinished() {
        let ray = Ray::new([-3.0, 0.1, 0.0], [1.0, 0.0, 0.0]);
        let p = Params::new();
        let span = [0.0, 6.0];
        let mut buf = [NONE; 2];
        let mut st = MarchState::start(span, &p);
        let slots = RootSlots::new(&mut buf, [0, 2]);
        let mut calls = 0;
        let mut guard = Faulty {
            left: 1,
            undo: 1000,
            calls: &mut calls,
        };
        let next = sphere_run(
            &Ball(1.0),
            &ray,
            span,
            Mode::Opaque,
            &p,
            slots,
            &mut st,
            &mut guard,
        );
        assert!(!next.stop);
        let tr = final_record(next);
        assert_eq!(
            (tr.status, tr.roots, tr.stats.steps),
            (Status::MaxSteps, 0, 1)
        );
        // One safe step of |f| ≈ 2 from t = 0, before the ball at t ≈ 2.005.
        assert!(
            tr.t_reached > 1.9 && tr.t_reached < 2.005,
            "{}",
            tr.t_reached
        );
    }

    #[test]
    fn sphere_in_legs_matches_one_trace() {
        use crate::trace::{trace_sphere_in, trace_sphere_resume_in};
        // Two thin shells and a ball: touches, crossings and over-relaxed
        // steps that fail (ω = 1.9), many roots in transparent mode.
        struct Shells;
        impl Field<f64> for Shells {
            fn eval<N: FieldNum<f64>>(&self, p: [N; 3]) -> N {
                let r = (p[0].sqr() + p[1].sqr() + p[2].sqr()).sqrt();
                let a = (r - 1.0).abs() - 0.01;
                let b = (r - 2.0).abs() - 0.02;
                a.min(b).min(r - 0.3)
            }
            fn lipschitz(&self) -> Option<f64> {
                Some(1.0)
            }
        }
        let mut legs_seen = 0;
        for omega in [1.0, 1.9] {
            let p = Params::new().with_omega(omega).unwrap();
            for y in [0.0, 0.5, 0.99, 1.005, 2.01, 2.5] {
                let ray = Ray::new([-3.0, y, 0.1], [1.0, 0.0, 0.0]);
                for mode in [Mode::Opaque, Mode::Transparent] {
                    for (every, undo) in [(1, 1000), (2, 3), (5, 2), (7, 1000), (1000, 4)] {
                        let span = [0.0, 6.0];
                        let window = [1, 6];
                        let mut once = [NONE; 8];
                        let whole =
                            trace_sphere_in(&Shells, &ray, span, mode, &p, &mut once, window);
                        let mut buf = [NONE; 8];
                        let mut st = MarchState::start(span, &p);
                        let mut calls = 0;
                        let mut legs = 0;
                        let last = loop {
                            legs += 1;
                            assert!(legs < 10_000, "no progress");
                            let mut guard = Faulty {
                                left: every,
                                undo,
                                calls: &mut calls,
                            };
                            let leg = trace_sphere_resume_in(
                                &Shells, &ray, span, mode, &p, &mut buf, window, &mut st,
                                &mut guard,
                            );
                            if !leg.paused {
                                break leg.trace;
                            }
                        };
                        legs_seen += legs;
                        assert_eq!(last, whole, "y {y} {mode:?} ω {omega} {every}/{undo}");
                        for (x, z) in once.iter().zip(&buf) {
                            assert_eq!((x.t.to_bits(), x.side), (z.t.to_bits(), z.side));
                        }
                    }
                }
            }
        }
        // The guards did pause the traces.
        assert!(legs_seen > 500, "{legs_seen}");
    }

    /// A guard like lavapipe's loop limiter: `budget` checks pass in a leg,
    /// every later one fails.
    struct Budget(u32);
    impl StepGuard for Budget {
        fn before_step(&mut self, _steps: u32) -> bool {
            true
        }
        fn after_step(&mut self) -> bool {
            if self.0 == 0 {
                return false;
            }
            self.0 -= 1;
            true
        }
    }

    #[test]
    fn steps_longer_than_a_leg_end_over_several_legs() {
        use crate::trace::{trace_in, trace_resume_in};
        use boundtrace_fields::{Blobs, Kernel, PointBlob};
        // Thin shells (sphere tracing's probes bisect near them) and
        // overlapping blobs (the window methods' steps certified by
        // interval halvings, then bisected).
        struct Shells;
        impl Field<f64> for Shells {
            fn eval<N: FieldNum<f64>>(&self, p: [N; 3]) -> N {
                let r = (p[0].sqr() + p[1].sqr() + p[2].sqr()).sqrt();
                ((r - 1.0).abs() - 0.01).min(r - 0.3)
            }
            fn lipschitz(&self) -> Option<f64> {
                Some(1.0)
            }
        }
        let k = Kernel::compact(6, 1.0).unwrap();
        let blobs = Blobs::new(
            0.35,
            [
                PointBlob::new([-1.2, 0.0, 0.0], 1.0, k).unwrap(),
                PointBlob::new([-0.3, 0.2, 0.0], 0.7, k).unwrap(),
                PointBlob::new([0.9, -0.1, 0.1], 1.1, k).unwrap(),
            ],
        )
        .unwrap();
        fn legs<F: Field<f64>>(
            field: &F,
            m: Method,
            y: f64,
            mode: Mode,
            budget: u32,
            mid_step: &mut u32,
        ) -> u32 {
            let p = Params::new();
            let ray = Ray::new([-3.0, y, 0.05], [1.0, 0.0, 0.0]);
            let (span, window) = ([0.0, 6.0], [1, 6]);
            let mut once = [NONE; 8];
            let whole = trace_in(field, &ray, span, m, mode, &p, &mut once, window);
            let mut buf = [NONE; 8];
            let mut st = MarchState::start(span, &p);
            let mut n = 0;
            let last = loop {
                n += 1;
                assert!(n < 100_000, "{m}: no progress");
                let leg = trace_resume_in(
                    field,
                    &ray,
                    span,
                    m,
                    mode,
                    &p,
                    &mut buf,
                    window,
                    &mut st,
                    &mut Budget(budget),
                );
                if !leg.paused {
                    break leg.trace;
                }
                *mid_step += u32::from(st.inner.stage != INNER_NONE);
            };
            assert_eq!(last, whole, "{m} y {y} {mode:?} budget {budget}");
            for (x, z) in once.iter().zip(&buf) {
                assert_eq!((x.t.to_bits(), x.side), (z.t.to_bits(), z.side));
            }
            n
        }
        let mut mid_step = 0;
        let mut total = 0;
        for budget in [1, 2, 3, 7] {
            for mode in [Mode::Opaque, Mode::Transparent] {
                for y in [0.0, 0.5, 0.99, 1.005] {
                    total += legs(&Shells, Method::Sphere, y, mode, budget, &mut mid_step);
                }
                for m in [
                    Method::Segment,
                    Method::LinearTaylor,
                    Method::LinearBottomUp,
                    Method::QuadraticTaylor,
                    Method::QuadraticMixed,
                ] {
                    for y in [0.0, 0.3, 0.55, 0.7] {
                        total += legs(&blobs, m, y, mode, budget, &mut mid_step);
                    }
                }
            }
        }
        // With one check per leg, every inner loop of more than one
        // iteration was cut inside its step.
        assert!(
            mid_step > 100,
            "{mid_step} of {total} legs paused inside a step"
        );
    }

    #[test]
    fn every_marcher_in_legs_matches_one_trace() {
        use crate::trace::{
            trace_in, trace_linear_bottom_up_resume_in, trace_linear_mixed_resume_in,
            trace_linear_taylor_resume_in, trace_quadratic_bottom_up_resume_in,
            trace_quadratic_mixed_resume_in, trace_quadratic_taylor_resume_in, trace_resume_in,
            trace_segment_lines_resume_in, trace_segment_resume_in,
        };
        use boundtrace_fields::{Blobs, Kernel, PointBlob};
        // Overlapping compact blobs: Taylor bounds exist, so every marcher
        // runs; several crossings per ray in transparent mode.
        let k = Kernel::compact(6, 1.0).unwrap();
        let blobs = Blobs::new(
            0.35,
            [
                PointBlob::new([-1.2, 0.0, 0.0], 1.0, k).unwrap(),
                PointBlob::new([-0.3, 0.2, 0.0], 0.7, k).unwrap(),
                PointBlob::new([0.9, -0.1, 0.1], 1.1, k).unwrap(),
                PointBlob::new([1.7, 0.3, 0.0], 0.6, k).unwrap(),
            ],
        )
        .unwrap();
        let p = Params::new();
        let mut legs_seen = 0;
        for m in Method::ALL {
            for y in [0.0, 0.3, 0.55, 0.7] {
                let ray = Ray::new([-3.0, y, 0.05], [1.0, 0.0, 0.0]);
                for mode in [Mode::Opaque, Mode::Transparent] {
                    let (span, window) = ([0.0, 6.0], [1, 6]);
                    let mut once = [NONE; 8];
                    let whole = trace_in(&blobs, &ray, span, m, mode, &p, &mut once, window);
                    let resumable = !matches!(
                        m,
                        Method::Interval | Method::Affine | Method::ScalisQuadratic
                    );
                    if resumable {
                        assert!(whole.stats.steps > 0, "{m}");
                    }
                    for (every, undo) in [(1, 1000), (2, 3), (5, 2), (1000, 4)] {
                        let mut buf = [NONE; 8];
                        let mut st = MarchState::start(span, &p);
                        let mut calls = 0;
                        let mut legs = 0;
                        let last = loop {
                            legs += 1;
                            assert!(legs < 10_000, "no progress");
                            let mut guard = Faulty {
                                left: every,
                                undo,
                                calls: &mut calls,
                            };
                            // The single-method functions (the GPU's) on
                            // every other leg: they resume each other's
                            // legs and the dispatching one's.
                            let one = legs % 2 == 0;
                            let leg = match m {
                                Method::Segment if legs % 4 == 0 => trace_segment_lines_resume_in(
                                    &blobs, &ray, span, mode, &p, &mut buf, window, &mut st,
                                    &mut guard,
                                ),
                                Method::Segment if one => trace_segment_resume_in(
                                    &blobs, &ray, span, mode, &p, &mut buf, window, &mut st,
                                    &mut guard,
                                ),
                                Method::LinearTaylor if one => trace_linear_taylor_resume_in(
                                    &blobs, &ray, span, mode, &p, &mut buf, window, &mut st,
                                    &mut guard,
                                ),
                                Method::QuadraticTaylor if one => trace_quadratic_taylor_resume_in(
                                    &blobs, &ray, span, mode, &p, &mut buf, window, &mut st,
                                    &mut guard,
                                ),
                                Method::LinearBottomUp if one => trace_linear_bottom_up_resume_in(
                                    &blobs, &ray, span, mode, &p, &mut buf, window, &mut st,
                                    &mut guard,
                                ),
                                Method::QuadraticBottomUp if one => {
                                    trace_quadratic_bottom_up_resume_in(
                                        &blobs, &ray, span, mode, &p, &mut buf, window, &mut st,
                                        &mut guard,
                                    )
                                }
                                Method::LinearMixed if one => trace_linear_mixed_resume_in(
                                    &blobs, &ray, span, mode, &p, &mut buf, window, &mut st,
                                    &mut guard,
                                ),
                                Method::QuadraticMixed if one => trace_quadratic_mixed_resume_in(
                                    &blobs, &ray, span, mode, &p, &mut buf, window, &mut st,
                                    &mut guard,
                                ),
                                _ => trace_resume_in(
                                    &blobs, &ray, span, m, mode, &p, &mut buf, window, &mut st,
                                    &mut guard,
                                ),
                            };
                            if !leg.paused {
                                break leg.trace;
                            }
                        };
                        legs_seen += legs;
                        if !resumable {
                            assert_eq!((last.status, legs), (Status::Unsupported, 1), "{m}");
                            continue;
                        }
                        assert_eq!(last, whole, "{m} y {y} {mode:?} {every}/{undo}");
                        for (x, z) in once.iter().zip(&buf) {
                            assert_eq!((x.t.to_bits(), x.side), (z.t.to_bits(), z.side));
                        }
                    }
                }
            }
        }
        // The guards did pause the traces.
        assert!(legs_seen > 1000, "{legs_seen}");
    }

    /// The mixed methods with their Taylor parts filled apart
    /// ([`fill_taylor_cache`](crate::fill_taylor_cache) between legs, as
    /// the GPU's two pipelines run): the uninterrupted trace bit for bit,
    /// one step per leg at most, on a field with Taylor bounds and on one
    /// without (`Ball`: the bottom-up bound alone).
    #[test]
    fn mixed_with_the_taylor_part_filled_apart_matches_one_trace() {
        use crate::trace::{
            fill_taylor_cache, trace_in, trace_linear_mixed_cached_resume_in,
            trace_quadratic_mixed_cached_resume_in,
        };
        use boundtrace_fields::{Blobs, Kernel, PointBlob};
        let k = Kernel::compact(6, 1.0).unwrap();
        let blobs = Blobs::new(
            0.35,
            [
                PointBlob::new([-1.2, 0.0, 0.0], 1.0, k).unwrap(),
                PointBlob::new([-0.3, 0.2, 0.0], 0.7, k).unwrap(),
                PointBlob::new([0.9, -0.1, 0.1], 1.1, k).unwrap(),
                PointBlob::new([1.7, 0.3, 0.0], 0.6, k).unwrap(),
            ],
        )
        .unwrap();
        fn check<F: Field<f64>>(field: &F, what: &str) -> u32 {
            let p = Params::new();
            let mut legs_seen = 0;
            for m in [Method::LinearMixed, Method::QuadraticMixed] {
                let quadratic = m == Method::QuadraticMixed;
                for y in [0.0, 0.3, 0.55, 0.7, 0.95] {
                    let ray = Ray::new([-3.0, y, 0.05], [1.0, 0.0, 0.0]);
                    for mode in [Mode::Opaque, Mode::Transparent] {
                        let (span, window) = ([0.0, 6.0], [1, 6]);
                        let mut once = [NONE; 8];
                        let whole = trace_in(field, &ray, span, m, mode, &p, &mut once, window);
                        assert!(whole.stats.steps > 0, "{what} {m}");
                        for (every, undo) in [(1000, 1000), (2, 3), (1000, 4)] {
                            let mut buf = [NONE; 8];
                            let mut st = MarchState::start(span, &p);
                            let mut cache = TaylorCache::EMPTY;
                            let (mut calls, mut legs) = (0, 0u32);
                            let last = loop {
                                legs += 1;
                                assert!(legs < 10_000, "no progress");
                                let mut guard = Faulty {
                                    left: every,
                                    undo,
                                    calls: &mut calls,
                                };
                                let before = st.stats.steps;
                                // an empty window first: nothing to fill
                                // before the first leg
                                if legs > 1 {
                                    fill_taylor_cache(
                                        field, &ray, span, &p, &st, quadratic, &mut cache,
                                    );
                                }
                                let leg = if quadratic {
                                    trace_quadratic_mixed_cached_resume_in(
                                        field, &ray, span, mode, &p, &mut buf, window, &mut st,
                                        &cache, &mut guard,
                                    )
                                } else {
                                    trace_linear_mixed_cached_resume_in(
                                        field, &ray, span, mode, &p, &mut buf, window, &mut st,
                                        &cache, &mut guard,
                                    )
                                };
                                if !leg.paused {
                                    break leg.trace;
                                }
                                assert!(st.stats.steps <= before + 1, "{what} {m}: two steps");
                                if legs == 1 {
                                    assert_eq!(st, MarchState::start(span, &p), "a step was taken");
                                }
                            };
                            legs_seen += legs;
                            assert_eq!(last, whole, "{what} {m} y {y} {mode:?} {every}/{undo}");
                            assert!(legs > whole.stats.steps, "{what} {m}");
                            for (x, z) in once.iter().zip(&buf) {
                                assert_eq!((x.t.to_bits(), x.side), (z.t.to_bits(), z.side));
                            }
                        }
                    }
                }
            }
            legs_seen
        }
        assert!(check(&blobs, "blobs") > 100);
        assert!(check(&Ball(1.0), "ball") > 10);
    }

    #[test]
    fn segment_from_taylor_lines_only_stays_sound_without_them() {
        use crate::trace::{trace_in, trace_segment_resume_in};
        // `Ball` has no Taylor lines: every step is certified by interval
        // enclosures; the roots are those of the ball (within eps).
        let p = Params::new();
        for y in [0.0, 0.4, 0.9] {
            let ray = Ray::new([-3.0, y, 0.0], [1.0, 0.0, 0.0]);
            let x: f64 = (1.0 - y * y).sqrt();
            let (span, window) = ([0.0, 6.0], [0, 4]);
            let mut buf = [NONE; 4];
            let mut st = MarchState::start(span, &p);
            let leg = trace_segment_resume_in(
                &Ball(1.0),
                &ray,
                span,
                Mode::Transparent,
                &p,
                &mut buf,
                window,
                &mut st,
                &mut Unguarded,
            );
            assert!(!leg.paused);
            assert_eq!((leg.trace.status, leg.trace.roots), (Status::Finished, 2));
            for (r, want) in buf.iter().zip([3.0 - x, 3.0 + x]) {
                assert!((r.t - want).abs() <= p.eps, "{} vs {want}", r.t);
            }
            // The dispatching tracer (bottom-up lines) finds the same roots.
            let mut b2 = [NONE; 4];
            let tr = trace_in(
                &Ball(1.0),
                &ray,
                span,
                Method::Segment,
                Mode::Transparent,
                &p,
                &mut b2,
                window,
            );
            assert_eq!(tr.roots, 2);
            assert_ne!(tr.stats, leg.trace.stats, "two different bounds");
        }
    }

    #[test]
    fn miss_and_unsupported() {
        let ray = Ray::new([-3.0, 1.5, 0.0], [1.0, 0.0, 0.0]);
        let p = Params::new();
        for m in methods() {
            let mut buf = [NONE; 2];
            let tr = trace(&Ball(1.0), &ray, [0.0, 6.0], m, Mode::Opaque, &p, &mut buf);
            assert_eq!((tr.status, tr.roots), (Status::Finished, 0), "{m}");
            assert_eq!(tr.t_reached, 6.0);
        }
        // No Lipschitz bound: sphere tracing is unsupported; no Taylor bound:
        // the Taylor methods are.
        let mut buf = [NONE; 2];
        for m in [
            Method::Sphere,
            Method::LinearTaylor,
            Method::QuadraticTaylor,
        ] {
            let tr = trace(
                &Parabola(1.0),
                &ray,
                [0.0, 6.0],
                m,
                Mode::Opaque,
                &p,
                &mut buf,
            );
            assert_eq!(tr.status, Status::Unsupported, "{m}");
        }
        // So are the single-method Taylor marchers.
        for quadratic in [false, true] {
            let mut st = MarchState::start([0.0, 6.0], &p);
            let resume = if quadratic {
                crate::trace::trace_quadratic_taylor_resume_in
            } else {
                crate::trace::trace_linear_taylor_resume_in
            };
            let leg = resume(
                &Parabola(1.0),
                &ray,
                [0.0, 6.0],
                Mode::Opaque,
                &p,
                &mut buf,
                [0, 2],
                &mut st,
                &mut Unguarded,
            );
            assert!(!leg.paused);
            assert_eq!(
                leg.trace.status,
                Status::Unsupported,
                "quadratic {quadratic}"
            );
        }
    }

    #[test]
    fn start_inside_and_on_surface() {
        let p = Params::new();
        for m in methods() {
            let mut buf = [NONE; 4];
            // Inside: the first root leaves.
            let ray = Ray::new([0.0; 3], [1.0, 0.0, 0.0]);
            let tr = trace(
                &Ball(1.0),
                &ray,
                [0.0, 3.0],
                m,
                Mode::Transparent,
                &p,
                &mut buf,
            );
            assert_eq!(tr.roots, 1, "{m}: {:?}", &buf[..tr.roots as usize]);
            assert_eq!(buf[0].side, Side::Leaving);
            assert!((buf[0].t - 1.0).abs() <= p.eps);
            // On the surface, heading in: a root at t0, entering.
            let ray = Ray::new([-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
            let tr = trace(
                &Ball(1.0),
                &ray,
                [0.0, 3.0],
                m,
                Mode::Transparent,
                &p,
                &mut buf,
            );
            assert_eq!(tr.roots, 2, "{m}");
            assert_eq!((buf[0].t, buf[0].side), (0.0, Side::Entering), "{m}");
            assert!((buf[1].t - 2.0).abs() <= p.eps, "{m}");
        }
    }

    #[test]
    fn buffer_full_and_max_steps() {
        let p = Params::new();
        let ray = Ray::new([-3.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
        let mut buf = [NONE; 1];
        let tr = trace(
            &Ball(1.0),
            &ray,
            [0.0, 6.0],
            Method::Segment,
            Mode::Transparent,
            &p,
            &mut buf,
        );
        assert_eq!((tr.status, tr.roots), (Status::BufferFull, 1));
        assert!(tr.t_reached > 2.0 && tr.t_reached < 4.0);
        let p1 = p.with_max_steps(2).unwrap();
        let ray = Ray::new([-3.0, 0.5, 0.0], [1.0, 0.0, 0.0]);
        let tr = trace(
            &Ball(1.0),
            &ray,
            [0.0, 6.0],
            Method::Sphere,
            Mode::Opaque,
            &p1,
            &mut buf,
        );
        assert_eq!(tr.status, Status::MaxSteps);
        assert!(tr.t_reached < 2.134);
    }

    #[test]
    fn over_relaxation_never_passes_a_root() {
        // A thin shell: over-relaxed steps would jump it; the check stops them.
        struct Shell;
        impl Field<f64> for Shell {
            fn eval<N: FieldNum<f64>>(&self, p: [N; 3]) -> N {
                ((p[0].sqr() + p[1].sqr() + p[2].sqr()).sqrt() - 1.0).abs() - 0.01
            }
            fn lipschitz(&self) -> Option<f64> {
                Some(1.0)
            }
        }
        let p = Params::new().with_omega(1.9).unwrap();
        for y in [0.0, 0.5, 0.9, 0.999] {
            let ray = Ray::new([-3.0, y, 0.0], [1.0, 0.0, 0.0]);
            let mut buf = [NONE; 8];
            let tr = trace(
                &Shell,
                &ray,
                [0.0, 6.0],
                Method::Sphere,
                Mode::Opaque,
                &p,
                &mut buf,
            );
            let exact = 3.0 - (1.01f64 * 1.01 - y * y).sqrt();
            assert_eq!(tr.roots, 1);
            assert!(
                (buf[0].t - exact).abs() <= p.eps,
                "y = {y}: {} vs {exact}",
                buf[0].t
            );
        }
    }

    #[test]
    fn min_step_keeps_steps_safe() {
        // A near-grazing ray; a large minimal step must not pass the surface.
        let p = Params::new().with_min_step(0.05).unwrap();
        let ray = Ray::new([-3.0, 0.99, 0.0], [1.0, 0.0, 0.0]);
        let exact = 3.0 - (1.0f64 - 0.99 * 0.99).sqrt();
        for m in methods() {
            let mut buf = [NONE; 2];
            let tr = trace(&Ball(1.0), &ray, [0.0, 6.0], m, Mode::Opaque, &p, &mut buf);
            assert_eq!(tr.roots, 1, "{m}");
            assert!((buf[0].t - exact).abs() <= p.eps, "{m}");
        }
    }

    #[test]
    fn parabola_roots_without_lipschitz() {
        let ray = Ray::new([-2.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
        let p = Params::new();
        for m in [
            Method::Segment,
            Method::LinearBottomUp,
            Method::QuadraticBottomUp,
        ] {
            let mut buf = [NONE; 4];
            let tr = trace(
                &Parabola(0.25),
                &ray,
                [0.0, 4.0],
                m,
                Mode::Transparent,
                &p,
                &mut buf,
            );
            assert_eq!((tr.status, tr.roots), (Status::Finished, 2), "{m}");
            assert!((buf[0].t - 1.5).abs() <= p.eps && (buf[1].t - 2.5).abs() <= p.eps);
        }
    }

    #[test]
    fn touching_ray_registers_a_touch() {
        // f = x² along the ray touches zero at t = 2 without changing sign.
        let ray = Ray::new([-2.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
        let p = Params::new();
        for m in [Method::LinearBottomUp, Method::QuadraticBottomUp] {
            let mut buf = [NONE; 4];
            let tr = trace(
                &Parabola(0.0),
                &ray,
                [0.0, 4.0],
                m,
                Mode::Transparent,
                &p,
                &mut buf,
            );
            assert!(tr.roots >= 1, "{m}");
            assert_eq!(buf[0].side, Side::Touch, "{m}");
            assert!((buf[0].t - 2.0).abs() <= p.eps, "{m}: {}", buf[0].t);
        }
    }
}
