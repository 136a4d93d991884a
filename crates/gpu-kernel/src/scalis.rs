//! `scalis-quadratic` (and the per-primitive `interval` bisection) on the
//! GPU: the tracer's [`trace_scalis_in`] over the frame's per-ray primitive
//! lists, built on the host (the A-buffer of thesis Part III §1.5,
//! [`PrimitiveLists`](boundtrace_tracer::scalis::PrimitiveLists)).

use crate::{
    Constants, HitOut, LimitProbe, PHASE_DONE, PHASE_FRESH, PHASE_SHADING, PHASE_TRACING, PixelOut,
    STATUS_PAUSED, SceneKind, hit_at, loops_complete, record, unsupported, window_len,
};
use boundtrace_fields::scalis::{ScalisSegment, ScalisSkeleton};
use boundtrace_tracer::camera::ray_box_span;
use boundtrace_tracer::pixel::PixelTrace;
use boundtrace_tracer::scalis::{
    PrimitiveHit, ScalisState, TIGHT_REQUESTED, scalis_tight_resume_in,
    trace_scalis_resume_deferred_in,
};
use boundtrace_tracer::{Method, RayStats, Root, Status, Trace};

/// A SCALIS pixel's resumable trace between two dispatches
/// ([`render_scalis_leg`]): the pixel's phase, its shading progress and
/// the tracer's state ([`ScalisState`], with its interval stack).
/// `#[repr(C)]`; the host zero-fills the buffer ([`PHASE_FRESH`], the
/// state of a trace not begun).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct ScalisLeg {
    /// [`PHASE_FRESH`], [`PHASE_TRACING`], [`PHASE_SHADING`] or
    /// [`PHASE_DONE`].
    pub phase: u32,
    /// [`PHASE_SHADING`]: the roots whose hits (with normals) are written.
    pub shaded: u32,
    /// Where the trace resumes ([`PHASE_TRACING`]).
    pub state: ScalisState<f32>,
}

impl Default for ScalisLeg {
    /// A pixel not started (all zeros).
    fn default() -> Self {
        Self {
            phase: PHASE_FRESH,
            shaded: 0,
            state: ScalisState::start(),
        }
    }
}

/// One leg of pixel `(x, y)` of a SCALIS frame (the shader's
/// `trace_scalis` entry point): the pixel's trace with
/// [`trace_scalis_resume_deferred_in`] over its primitive list
/// `lists[offsets[i]..offsets[i + 1]]` (`i = y·width + x`) and the
/// skeleton `segments` with [`Constants::iso`], then its hits with normals
/// (the normal of the whole skeleton, as the CPU renderer computes it).
///
/// The trace runs in legs, as [`render_sphere_leg`](crate::render_sphere_leg)'s:
/// [`Constants::leg_steps`] steps at most per leg, the loop-limit probe
/// ([`loops_complete`], [`Constants::guard_loops`] iterations) after every
/// iteration of the processing; an iteration the driver's loop limit cut
/// is undone and done again in the next leg, so that the record is the
/// uninterrupted [`trace_scalis_in`](boundtrace_tracer::scalis::trace_scalis_in)'s,
/// bit for bit. Shading resumes root by root. A leg that cannot complete
/// one iteration makes no progress: the host detects it.
///
/// The tight stage of an interval (the log-concave ranges and Taylor
/// models, most of the tracer's code) is not here: the leg pauses with the
/// interval in its state, and [`render_scalis_tight_leg`] (the shader's
/// `trace_scalis_tight`, a pipeline of its own, dispatched after this one)
/// gives its verdict. A host dispatches the two in turn until every pixel
/// is done.
///
/// [`Status::Unsupported`] for another method than `scalis-quadratic` or
/// `interval`, another scene kind than [`SceneKind::Scalis`], bad constants
/// or an `offsets` buffer too short for the image.
#[allow(clippy::too_many_arguments)]
pub fn render_scalis_leg(
    c: &Constants,
    offsets: &[u32],
    lists: &[PrimitiveHit<f32>],
    segments: &[ScalisSegment<f32>],
    x: u32,
    y: u32,
    roots: &mut [Root<f32>],
    hits: &mut [HitOut],
    base: usize,
    leg: &mut ScalisLeg,
    out: &mut PixelOut,
) {
    if leg.phase >= PHASE_DONE {
        return;
    }
    let pixel = y as usize * c.width as usize + x as usize;
    let method_ok =
        c.method == Method::ScalisQuadratic as u32 || c.method == Method::Interval as u32;
    if !c.codes_valid()
        || !method_ok
        || c.scene != SceneKind::Scalis as u32
        || x >= c.width
        || y >= c.height
        || pixel + 1 >= offsets.len()
        || segments.is_empty()
    {
        *out = unsupported();
        leg.phase = PHASE_DONE;
        return;
    }
    let setup = c.decode();
    let window = [base, window_len(c.max_roots)];
    let ray = setup.camera.ray(x, y, setup.width, setup.height);
    let span = ray_box_span(&ray, &setup.bounds);
    if leg.phase < PHASE_SHADING {
        let mut paused = false;
        let trace = match span {
            None => Trace {
                roots: 0,
                status: Status::Finished,
                t_reached: 0.0,
                stats: RayStats::default(),
            },
            Some(span) => {
                let first = offsets[pixel] as usize;
                let last = offsets[pixel + 1] as usize;
                let list = if first <= last {
                    [first, last - first]
                } else {
                    // bad offsets: an out-of-range list (Unsupported)
                    [lists.len() + 1, 0]
                };
                let mut guard =
                    LimitProbe::for_leg(c.guard_loops, c.leg_steps, leg.state.walk.stats.steps);
                let r = trace_scalis_resume_deferred_in(
                    segments,
                    c.iso,
                    lists,
                    list,
                    &ray,
                    span,
                    setup.method,
                    setup.mode,
                    &setup.params,
                    roots,
                    window,
                    &mut leg.state,
                    &mut guard,
                );
                paused = r.paused;
                r.trace
            }
        };
        // Never report more roots than the window holds.
        let n = if (trace.roots as usize) < window[1] {
            trace.roots
        } else {
            window[1] as u32
        };
        let px = PixelTrace {
            ray,
            span,
            trace: Trace { roots: n, ..trace },
        };
        if paused {
            leg.phase = PHASE_TRACING;
            *out = record(&px);
            out.status = STATUS_PAUSED;
            out.steps = leg.state.walk.stats.steps;
            return;
        }
        *out = record(&px);
        leg.phase = PHASE_SHADING;
        leg.shaded = 0;
    }
    // Shading, one root at a time from `leg.shaded` (the normal loops over
    // the skeleton's segments).
    let skeleton = ScalisSkeleton::new_unchecked(segments, c.iso);
    let roots_out = out.roots;
    let mut i = leg.shaded;
    while i < roots_out {
        let k = base + i as usize;
        let hit = hit_at(&skeleton, &ray, roots[k]);
        if !loops_complete(c.guard_loops) {
            break;
        }
        if k < hits.len() {
            hits[k] = hit;
        }
        i += 1;
    }
    leg.shaded = i;
    if i >= roots_out {
        leg.phase = PHASE_DONE;
    }
}

/// The tight stage a [`render_scalis_leg`] leg of pixel `(x, y)` left in
/// its state ([`scalis_tight_resume_in`]), in legs: the loop-limit probe
/// after every hit of a pass, a step the limit cut undone. A pixel without
/// a pending tight stage is left as it is. (The shader's
/// `trace_scalis_tight` entry point: the same bindings as `trace_scalis`.)
#[allow(clippy::too_many_arguments)]
pub fn render_scalis_tight_leg(
    c: &Constants,
    offsets: &[u32],
    lists: &[PrimitiveHit<f32>],
    segments: &[ScalisSegment<f32>],
    x: u32,
    y: u32,
    leg: &mut ScalisLeg,
) {
    if leg.phase != PHASE_TRACING || leg.state.walk.tight.status != TIGHT_REQUESTED {
        return;
    }
    let pixel = y as usize * c.width as usize + x as usize;
    if !c.codes_valid()
        || c.scene != SceneKind::Scalis as u32
        || x >= c.width
        || y >= c.height
        || pixel + 1 >= offsets.len()
    {
        return;
    }
    let setup = c.decode();
    let ray = setup.camera.ray(x, y, setup.width, setup.height);
    let first = offsets[pixel] as usize;
    let last = offsets[pixel + 1] as usize;
    // bad offsets: an out-of-range list (the verdict "not proven free")
    let list = if first <= last {
        [first, last - first]
    } else {
        [lists.len() + 1, 0]
    };
    let mut guard = LimitProbe::for_leg(c.guard_loops, 0, 0);
    scalis_tight_resume_in(
        segments,
        c.iso,
        lists,
        list,
        &ray,
        &mut leg.state,
        &mut guard,
    );
}
