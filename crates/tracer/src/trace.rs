//! One ray: roots, per-ray statistics and the [`trace`] entry point.

#[cfg(not(target_arch = "spirv"))]
use crate::bisect;
use crate::march;
use crate::method::{Method, Mode, Params};
use boundtrace_ia_core::Real;
use boundtrace_inclusion::{Field, Ray, gradient};

/// How the field's sign changes at a root, seen along the ray.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum Side {
    /// From outside (`f > 0`) to inside (`f < 0`).
    Entering = 0,
    /// From inside (`f < 0`) to outside (`f > 0`).
    Leaving = 1,
    /// No sign change could be found within `eps`, but the field could not
    /// be proven nonzero there either: the ray touches (or grazes within
    /// rounding of) the surface.
    Touch = 2,
}

/// A root along the ray.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct Root<T> {
    /// The ray parameter, within `eps` of a true root (for [`Side::Touch`],
    /// of a point where the field could not be proven nonzero).
    pub t: T,
    /// How the sign changes there.
    pub side: Side,
}

/// Per-ray statistics (the papers' cost measures).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[repr(C)]
pub struct RayStats {
    /// Iterations of the method's main loop: marching steps, or intervals
    /// examined by a bisection.
    pub steps: u32,
    /// Point evaluations of the field (`f` at one `t`, in floats).
    pub field_evals: u32,
    /// Bound evaluations (a forward, interval or affine enclosure over an
    /// interval; a Taylor bound counts as one, "mixed" as two).
    pub bound_evals: u32,
}

impl core::ops::Add for RayStats {
    type Output = Self;
    /// Component-wise sum (saturating).
    fn add(self, o: Self) -> Self {
        Self {
            steps: self.steps.saturating_add(o.steps),
            field_evals: self.field_evals.saturating_add(o.field_evals),
            bound_evals: self.bound_evals.saturating_add(o.bound_evals),
        }
    }
}

/// Why the tracing of a ray stopped.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum Status {
    /// The ray was processed: the first root was found (opaque), or the
    /// whole span was processed (every root found, or there is none).
    #[default]
    Finished = 0,
    /// `max_steps` ran out at [`Trace::t_reached`]; no root is missing
    /// before that point.
    MaxSteps = 1,
    /// Transparent mode: the root buffer is full; no root is missing before
    /// [`Trace::t_reached`], tracing may resume from there.
    BufferFull = 2,
    /// The method needs what the field lacks (`sphere` a global Lipschitz
    /// bound, `*-taylor` a Taylor bound, `scalis-quadratic` a SCALIS
    /// skeleton through `scalis::trace_scalis`), or the parameters are invalid;
    /// nothing was traced.
    Unsupported = 3,
}

/// The result of tracing one ray; its roots are in the caller's buffer.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct Trace<T> {
    /// How many roots were written to the buffer (in increasing `t`).
    pub roots: u32,
    /// Why tracing stopped.
    pub status: Status,
    /// The ray parameter up to which the span is processed: no root in
    /// `[t0, t_reached)` is missing from the buffer.
    pub t_reached: T,
    /// The cost.
    pub stats: RayStats,
}

/// Traces `ray` on `span = [t0, t1]` with `method`: in [`Mode::Opaque`]
/// the first root, in [`Mode::Transparent`] every root, written to `roots`
/// in increasing `t` (opaque mode needs one slot). Allocation- and
/// recursion-free.
///
/// Soundness: no method ever steps past a root. A method that cannot
/// finish says why in [`Trace::status`], with the point reached.
///
/// ```
/// use boundtrace_inclusion::{Field, FieldNum, Ray};
/// use boundtrace_tracer::{Method, Mode, Params, Root, Side, Status, trace};
///
/// struct Ball; // the unit ball as a signed distance
/// impl Field<f64> for Ball {
///     fn eval<N: FieldNum<f64>>(&self, p: [N; 3]) -> N {
///         (p[0].sqr() + p[1].sqr() + p[2].sqr()).sqrt() - 1.0
///     }
///     fn lipschitz(&self) -> Option<f64> { Some(1.0) }
/// }
///
/// let ray = Ray::new([-3.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
/// let params = Params::new();
/// let mut roots = [Root { t: 0.0, side: Side::Touch }; 4];
/// for method in Method::ALL {
///     if matches!(method, Method::LinearTaylor | Method::QuadraticTaylor | Method::ScalisQuadratic) {
///         continue; // no Taylor bound, not a SCALIS skeleton: Status::Unsupported
///     }
///     let tr = trace(&Ball, &ray, [0.0, 6.0], method, Mode::Transparent, &params, &mut roots);
///     assert_eq!(tr.status, Status::Finished, "{method}");
///     assert_eq!(tr.roots, 2);
///     assert!((roots[0].t - 2.0).abs() <= params.eps && roots[0].side == Side::Entering);
///     assert!((roots[1].t - 4.0).abs() <= params.eps && roots[1].side == Side::Leaving);
/// }
/// ```
pub fn trace<T: Real, F: Field<T>>(
    field: &F,
    ray: &Ray<T>,
    span: [T; 2],
    method: Method,
    mode: Mode,
    params: &Params<T>,
    roots: &mut [Root<T>],
) -> Trace<T> {
    let len = roots.len();
    trace_in(field, ray, span, method, mode, params, roots, [0, len])
}

/// [`trace`](fn@trace) with the roots written to the window
/// `roots[base..base + len]` (`window = [base, len]`) rather than to a
/// sub-slice: a GPU shader cannot sub-slice a mutable storage buffer. A
/// window that is empty or does not fit in `roots` gives
/// [`Status::Unsupported`].
#[allow(clippy::too_many_arguments)]
pub fn trace_in<T: Real, F: Field<T>>(
    field: &F,
    ray: &Ray<T>,
    span: [T; 2],
    method: Method,
    mode: Mode,
    params: &Params<T>,
    roots: &mut [Root<T>],
    window: [usize; 2],
) -> Trace<T> {
    let unsupported = unsupported_trace(span);
    if !accepts(span, params, roots.len(), window) {
        return unsupported;
    }
    let slots = march::RootSlots::new(roots, window);
    match method {
        #[cfg(not(target_arch = "spirv"))]
        Method::Interval => {
            bisect::bisect::<T, F, bisect::ByInterval>(field, ray, span, mode, params, slots)
        }
        #[cfg(not(target_arch = "spirv"))]
        Method::Affine => {
            bisect::bisect::<T, F, bisect::ByAffine>(field, ray, span, mode, params, slots)
        }
        // Not on the GPU: the bisection methods are no GPU methods (issue 9),
        // and their code (affine arithmetic's index loops, i.e. panic paths)
        // would multiply the shader's size after rust-gpu's forced inlining.
        #[cfg(target_arch = "spirv")]
        Method::Interval | Method::Affine => unsupported,
        // needs the skeleton: `scalis::trace_scalis`
        Method::ScalisQuadratic => unsupported,
        _ => march::march(field, ray, span, method, mode, params, slots),
    }
}

/// The record of a ray that is not traced ([`Status::Unsupported`]).
fn unsupported_trace<T: Real>(span: [T; 2]) -> Trace<T> {
    Trace {
        roots: 0,
        status: Status::Unsupported,
        t_reached: span[0],
        stats: RayStats::default(),
    }
}

/// Whether [`trace_in`] traces at all: valid parameters, an ordered span
/// and a non-empty root window inside the buffer.
fn accepts<T: Real>(span: [T; 2], params: &Params<T>, buf_len: usize, window: [usize; 2]) -> bool {
    let [base, len] = window;
    let fits = len > 0 && base <= buf_len && len <= buf_len - base;
    params.is_valid() && span[0] <= span[1] && fits
}

/// [`trace_in`] with [`Method::Sphere`]: the same sphere tracer, reached
/// without the method dispatch, so that a caller (the GPU shader's
/// `trace_sphere` entry point) links sphere tracing alone. A GPU driver
/// inlines every call, so linking every method costs orders of magnitude
/// more code than this one (BENCHMARKS.md "GPU").
pub fn trace_sphere_in<T: Real, F: Field<T>>(
    field: &F,
    ray: &Ray<T>,
    span: [T; 2],
    mode: Mode,
    params: &Params<T>,
    roots: &mut [Root<T>],
    window: [usize; 2],
) -> Trace<T> {
    if !accepts(span, params, roots.len(), window) {
        return unsupported_trace(span);
    }
    let slots = march::RootSlots::new(roots, window);
    march::sphere(field, ray, span, mode, params, slots)
}

/// The outcome of one call of [`trace_resume_in`] (or
/// [`trace_sphere_resume_in`], [`trace_segment_resume_in`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Leg<T> {
    /// The trace paused between two steps (its guard said so); the state
    /// says where to resume, `trace` holds the counts so far.
    pub paused: bool,
    /// The final record when not `paused`.
    pub trace: Trace<T>,
}

/// [`trace_sphere_in`] in legs: sphere tracing from `state` (start with
/// [`MarchState::start`](crate::march::MarchState::start)), pausing
/// where `guard` says so and saving the loop into `state`. Called again
/// with the same arguments and the saved state, it goes on exactly where
/// it stopped: the legs of a trace give the roots, record and counters of
/// the uninterrupted [`trace_sphere_in`], whatever the pauses.
///
/// The GPU shader traces this way so that a driver cutting loops short
/// costs a dispatch, never a result ([`StepGuard`](crate::march::StepGuard)).
///
/// ```
/// use boundtrace_inclusion::{Field, FieldNum, Ray};
/// use boundtrace_tracer::march::{MarchState, StepGuard, Unguarded};
/// use boundtrace_tracer::{Mode, Params, Root, Side, trace_sphere_in, trace_sphere_resume_in};
///
/// struct Ball;
/// impl Field<f64> for Ball {
///     fn eval<N: FieldNum<f64>>(&self, p: [N; 3]) -> N {
///         (p[0].sqr() + p[1].sqr() + p[2].sqr()).sqrt() - 0.5
///     }
///     fn lipschitz(&self) -> Option<f64> {
///         Some(1.0)
///     }
/// }
/// /// Allows three steps per leg.
/// struct Three(u32);
/// impl StepGuard for Three {
///     fn before_step(&mut self, _steps: u32) -> bool {
///         self.0 += 1;
///         self.0 <= 3
///     }
///     fn after_step(&mut self) -> bool {
///         true
///     }
/// }
/// let ray = Ray::new([0.0, 0.1, -2.0], [0.0, 0.0, 1.0]);
/// let (span, params) = ([0.0, 4.0], Params::new());
/// let blank = Root { t: 0.0, side: Side::Touch };
/// let mut whole = [blank; 4];
/// let once = trace_sphere_in(&Ball, &ray, span, Mode::Transparent, &params, &mut whole, [0, 4]);
///
/// let mut roots = [blank; 4];
/// let mut state = MarchState::start(span, &params);
/// let mut legs = 0;
/// let last = loop {
///     legs += 1;
///     let leg = trace_sphere_resume_in(
///         &Ball, &ray, span, Mode::Transparent, &params, &mut roots, [0, 4],
///         &mut state, &mut Three(0),
///     );
///     if !leg.paused {
///         break leg.trace;
///     }
/// };
/// assert!(legs > 1);
/// assert_eq!((last, roots), (once, whole));
/// # let _ = Unguarded;
/// ```
#[allow(clippy::too_many_arguments)]
pub fn trace_sphere_resume_in<T: Real, F: Field<T>, G: march::StepGuard>(
    field: &F,
    ray: &Ray<T>,
    span: [T; 2],
    mode: Mode,
    params: &Params<T>,
    roots: &mut [Root<T>],
    window: [usize; 2],
    state: &mut march::MarchState<T>,
    guard: &mut G,
) -> Leg<T> {
    if !accepts(span, params, roots.len(), window) {
        return Leg::unsupported(span);
    }
    let slots = march::RootSlots::new(roots, window);
    let next = march::sphere_run(field, ray, span, mode, params, slots, state, guard);
    Leg::of(next)
}

impl<T: Real> Leg<T> {
    /// The leg of a ray that is not traced (not paused).
    fn unsupported(span: [T; 2]) -> Self {
        Self {
            paused: false,
            trace: unsupported_trace(span),
        }
    }

    /// The leg a marcher's run ended with.
    fn of(next: march::Next<T>) -> Self {
        Self {
            paused: !next.stop,
            trace: next.trace,
        }
    }
}

/// [`trace_in`] in legs, for every marching method: the same trace from
/// `state` (start with [`MarchState::start`](crate::march::MarchState::start)),
/// pausing where `guard` says so and saving the loop into `state`, as
/// [`trace_sphere_resume_in`] does for sphere tracing. The legs of a trace
/// give the roots, record and counters of the uninterrupted [`trace_in`],
/// whatever the pauses.
///
/// The bisection methods ([`Method::Interval`], [`Method::Affine`]) and
/// [`Method::ScalisQuadratic`] keep a stack, not a loop state: they are not
/// resumable here and give a [`Status::Unsupported`] record (never
/// paused); on SCALIS skeletons
/// [`trace_scalis_resume_in`](crate::scalis::trace_scalis_resume_in) runs
/// `scalis-quadratic` and `interval` in legs, with the stack in its state.
///
/// ```
/// use boundtrace_inclusion::{Field, FieldNum, Ray};
/// use boundtrace_tracer::march::{MarchState, StepGuard};
/// use boundtrace_tracer::{Method, Mode, Params, Root, Side, trace_in, trace_resume_in};
///
/// struct Ball;
/// impl Field<f64> for Ball {
///     fn eval<N: FieldNum<f64>>(&self, p: [N; 3]) -> N {
///         (p[0].sqr() + p[1].sqr() + p[2].sqr()).sqrt() - 0.5
///     }
/// }
/// /// One step per leg.
/// struct One(bool);
/// impl StepGuard for One {
///     fn before_step(&mut self, _steps: u32) -> bool {
///         !std::mem::replace(&mut self.0, true)
///     }
///     fn after_step(&mut self) -> bool {
///         true
///     }
/// }
/// let ray = Ray::new([0.0, 0.1, -2.0], [0.0, 0.0, 1.0]);
/// let (span, params, m) = ([0.0, 4.0], Params::new(), Method::QuadraticBottomUp);
/// let blank = Root { t: 0.0, side: Side::Touch };
/// let mut whole = [blank; 4];
/// let once = trace_in(&Ball, &ray, span, m, Mode::Transparent, &params, &mut whole, [0, 4]);
///
/// let mut roots = [blank; 4];
/// let mut state = MarchState::start(span, &params);
/// let last = loop {
///     let leg = trace_resume_in(
///         &Ball, &ray, span, m, Mode::Transparent, &params, &mut roots, [0, 4],
///         &mut state, &mut One(false),
///     );
///     if !leg.paused {
///         break leg.trace;
///     }
/// };
/// assert_eq!(once.roots, 2);
/// assert_eq!((last, roots), (once, whole));
/// ```
#[allow(clippy::too_many_arguments)]
pub fn trace_resume_in<T: Real, F: Field<T>, G: march::StepGuard>(
    field: &F,
    ray: &Ray<T>,
    span: [T; 2],
    method: Method,
    mode: Mode,
    params: &Params<T>,
    roots: &mut [Root<T>],
    window: [usize; 2],
    state: &mut march::MarchState<T>,
    guard: &mut G,
) -> Leg<T> {
    let resumable = !matches!(
        method,
        Method::Interval | Method::Affine | Method::ScalisQuadratic
    );
    if !resumable || !accepts(span, params, roots.len(), window) {
        return Leg::unsupported(span);
    }
    let slots = march::RootSlots::new(roots, window);
    let next = if method == Method::Sphere {
        march::sphere_run(field, ray, span, mode, params, slots, state, guard)
    } else {
        march::window_run::<march::AnyWindow, _, _, _>(
            field,
            ray,
            span,
            mode,
            params,
            slots,
            state,
            guard,
            method,
            (),
        )
    };
    Leg::of(next)
}

/// A single-method resume function: [`trace_resume_in`] with `$method`
/// and the window bounds `$bounds` alone, reached without the method
/// dispatch (the body of each is [`window_resume_in`]).
macro_rules! single_method_resume {
    ($(#[$doc:meta])* $name:ident, $bounds:ty, $method:expr) => {
        $(#[$doc])*
        #[allow(clippy::too_many_arguments)]
        pub fn $name<T: Real, F: Field<T>, G: march::StepGuard>(
            field: &F,
            ray: &Ray<T>,
            span: [T; 2],
            mode: Mode,
            params: &Params<T>,
            roots: &mut [Root<T>],
            window: [usize; 2],
            state: &mut march::MarchState<T>,
            guard: &mut G,
        ) -> Leg<T> {
            window_resume_in::<$bounds, _, _, _>(
                field, ray, span, $method, mode, params, roots, window, state, guard, (),
            )
        }
    };
}

single_method_resume!(
    /// [`trace_resume_in`] with [`Method::Segment`], reached without the
    /// method dispatch, so that a caller (the GPU shader's `trace_segment_*`
    /// entry point) links segment tracing alone (see [`trace_sphere_in`]),
    /// with one difference: Galin et al.'s `λ` comes from the field's Taylor
    /// lines only ([`Field::taylor_linear`]). Where a field has none on a
    /// window, the step is certified with interval enclosures (as at a kink)
    /// instead of bottom-up lines, whose code is about 30 times larger on a GPU
    /// that inlines every call (BENCHMARKS.md "GPU"). So the trace equals
    /// [`trace_resume_in`]'s with [`Method::Segment`] bit for bit wherever the
    /// Taylor lines exist (e.g. blobs with compact kernels), and is as sound
    /// elsewhere.
    trace_segment_resume_in,
    march::SegmentTaylor,
    Method::Segment
);

single_method_resume!(
    /// [`trace_resume_in`] with [`Method::Segment`], reached without the
    /// method dispatch, with the CPU's bound: Galin et al.'s `λ` from the
    /// field's Taylor lines where it has them, else from its bottom-up lines.
    /// Equal to [`trace_resume_in`]'s trace bit for bit on every field. The
    /// GPU shader's `trace_segment_hrbf` entry point (an HRBF has no Taylor
    /// lines, where [`trace_segment_resume_in`] would certify every step
    /// with interval enclosures: more steps than the CPU's).
    trace_segment_lines_resume_in,
    march::SegmentLines,
    Method::Segment
);

single_method_resume!(
    /// [`trace_resume_in`] with [`Method::LinearTaylor`], reached without the
    /// method dispatch, so that a caller (the GPU shader's
    /// `trace_linear_taylor_*` entry points) links the Taylor linear bound
    /// alone (see [`trace_segment_resume_in`]). Equal to [`trace_resume_in`]'s
    /// trace bit for bit; [`Status::Unsupported`] where the field has no
    /// Taylor bound, as there.
    trace_linear_taylor_resume_in,
    march::TaylorWindow<false>,
    Method::LinearTaylor
);

single_method_resume!(
    /// [`trace_linear_taylor_resume_in`] with [`Method::QuadraticTaylor`]
    /// (the Taylor quadratic bound alone; the shader's
    /// `trace_quadratic_taylor_*` entry points).
    trace_quadratic_taylor_resume_in,
    march::TaylorWindow<true>,
    Method::QuadraticTaylor
);

single_method_resume!(
    /// [`trace_resume_in`] with [`Method::LinearBottomUp`], reached without
    /// the method dispatch, so that a caller links the bottom-up linear
    /// bound alone (see [`trace_segment_resume_in`]). Equal to
    /// [`trace_resume_in`]'s trace bit for bit. The GPU shader's
    /// `trace_linear_bottom_up_blobs` entry point (BENCHMARKS.md "GPU",
    /// session 27: the module fits since the forward compositions
    /// instantiate one function each).
    trace_linear_bottom_up_resume_in,
    march::BottomUpWindow<false>,
    Method::LinearBottomUp
);

single_method_resume!(
    /// [`trace_linear_bottom_up_resume_in`] with [`Method::QuadraticBottomUp`]
    /// (the bottom-up quadratic bound alone).
    trace_quadratic_bottom_up_resume_in,
    march::BottomUpWindow<true>,
    Method::QuadraticBottomUp
);

single_method_resume!(
    /// [`trace_resume_in`] with [`Method::LinearMixed`] (the bottom-up and
    /// Taylor linear bounds, the tighter side of each), reached without the
    /// method dispatch (see [`trace_segment_resume_in`]). Equal to
    /// [`trace_resume_in`]'s trace bit for bit.
    trace_linear_mixed_resume_in,
    march::MixedWindow<false>,
    Method::LinearMixed
);

single_method_resume!(
    /// [`trace_linear_mixed_resume_in`] with [`Method::QuadraticMixed`] (the
    /// bottom-up and Taylor quadratic bounds, the tighter side of each).
    trace_quadratic_mixed_resume_in,
    march::MixedWindow<true>,
    Method::QuadraticMixed
);

/// One leg of the window marcher with the bounds `B` (the body of the
/// single-method resume functions).
#[allow(clippy::too_many_arguments)]
fn window_resume_in<B: march::WindowBounds, T: Real, F: Field<T>, G: march::StepGuard>(
    field: &F,
    ray: &Ray<T>,
    span: [T; 2],
    method: Method,
    mode: Mode,
    params: &Params<T>,
    roots: &mut [Root<T>],
    window: [usize; 2],
    state: &mut march::MarchState<T>,
    guard: &mut G,
    cache: B::Cache<T>,
) -> Leg<T> {
    if !accepts(span, params, roots.len(), window) {
        return Leg::unsupported(span);
    }
    let slots = march::RootSlots::new(roots, window);
    let next = march::window_run::<B, _, _, _>(
        field, ray, span, mode, params, slots, state, guard, method, cache,
    );
    Leg::of(next)
}

/// [`trace_linear_mixed_resume_in`] with the Taylor part of each step's
/// bound read from `cache` ([`march::TaylorCache`]), so that a caller (the
/// GPU shader's `trace_linear_mixed_*` entry points) links the bottom-up
/// bound alone: a leg pauses before any step whose window `cache` does not
/// hold ([`Leg::paused`]), for [`fill_taylor_cache`] to fill it from the
/// state, and the next leg takes that step. The trace is
/// [`trace_linear_mixed_resume_in`]'s bit for bit (the same Taylor bound
/// on the same window, combined the same way), one step per leg at most.
#[allow(clippy::too_many_arguments)]
pub fn trace_linear_mixed_cached_resume_in<T: Real, F: Field<T>, G: march::StepGuard>(
    field: &F,
    ray: &Ray<T>,
    span: [T; 2],
    mode: Mode,
    params: &Params<T>,
    roots: &mut [Root<T>],
    window: [usize; 2],
    state: &mut march::MarchState<T>,
    cache: &march::TaylorCache<T>,
    guard: &mut G,
) -> Leg<T> {
    window_resume_in::<march::CachedMixed<false>, _, _, _>(
        field,
        ray,
        span,
        Method::LinearMixed,
        mode,
        params,
        roots,
        window,
        state,
        guard,
        *cache,
    )
}

/// [`trace_linear_mixed_cached_resume_in`] for [`Method::QuadraticMixed`]:
/// [`trace_quadratic_mixed_resume_in`]'s trace with the Taylor quadratic
/// bounds read from `cache`.
#[allow(clippy::too_many_arguments)]
pub fn trace_quadratic_mixed_cached_resume_in<T: Real, F: Field<T>, G: march::StepGuard>(
    field: &F,
    ray: &Ray<T>,
    span: [T; 2],
    mode: Mode,
    params: &Params<T>,
    roots: &mut [Root<T>],
    window: [usize; 2],
    state: &mut march::MarchState<T>,
    cache: &march::TaylorCache<T>,
    guard: &mut G,
) -> Leg<T> {
    window_resume_in::<march::CachedMixed<true>, _, _, _>(
        field,
        ray,
        span,
        Method::QuadraticMixed,
        mode,
        params,
        roots,
        window,
        state,
        guard,
        *cache,
    )
}

/// Fills `cache` with the Taylor bound (linear, or quadratic when
/// `quadratic`) of the next step of a mixed trace in `state` on `span`
/// (the window that step bounds), unless it holds that window already:
/// the other half of [`trace_linear_mixed_cached_resume_in`] and
/// [`trace_quadratic_mixed_cached_resume_in`]. `state` must be a window
/// marcher's (from [`march::MarchState::start`] or a mixed leg).
pub fn fill_taylor_cache<T: Real, F: Field<T>>(
    field: &F,
    ray: &Ray<T>,
    span: [T; 2],
    params: &Params<T>,
    state: &march::MarchState<T>,
    quadratic: bool,
    cache: &mut march::TaylorCache<T>,
) {
    let [t, e] = march::next_window(state, span[1], params.eps);
    if cache.holds(t, e) {
        return;
    }
    let mut c = march::TaylorCache {
        t,
        e,
        filled: 1,
        ..march::TaylorCache::EMPTY
    };
    if quadratic {
        if let Some(b) = field.taylor_quadratic(ray, t, e) {
            (c.some, c.quadratic) = (1, b);
        }
    } else if let Some(b) = field.taylor_linear(ray, t, e) {
        (c.some, c.linear) = (1, b);
    }
    *cache = c;
}

/// The first root of `ray` on `span` (opaque mode), with the trace record.
pub fn first_root<T: Real, F: Field<T>>(
    field: &F,
    ray: &Ray<T>,
    span: [T; 2],
    method: Method,
    params: &Params<T>,
) -> (Option<Root<T>>, Trace<T>) {
    let mut buf = [Root {
        t: T::ZERO,
        side: Side::Touch,
    }];
    let tr = trace(field, ray, span, method, Mode::Opaque, params, &mut buf);
    ((tr.roots > 0).then_some(buf[0]), tr)
}

/// The unit surface normal at `p` (normalized gradient, pointing outside),
/// or `[0, 0, 0]` where the gradient vanishes or is not finite.
pub fn normal<T: Real, F: Field<T>>(field: &F, p: [T; 3]) -> [T; 3] {
    let g = gradient(field, p);
    let n2 = g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
    if !(n2 > T::ZERO) || !n2.is_finite() {
        return [T::ZERO; 3];
    }
    let inv = T::ONE / n2.sqrt();
    [g[0] * inv, g[1] * inv, g[2] * inv]
}
