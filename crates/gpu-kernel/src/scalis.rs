//! `scalis-quadratic` (and the per-primitive `interval` bisection) on the
//! GPU: the tracer's [`trace_scalis_in`] over the frame's per-ray primitive
//! lists, built on the host (the A-buffer of thesis Part III §1.5,
//! [`PrimitiveLists`](boundtrace_tracer::scalis::PrimitiveLists)).

use crate::{
    Constants, HitOut, PHASE_DONE, PHASE_FRESH, PHASE_SHADING, PixelLeg, PixelOut, SceneKind,
    hit_at, loops_complete, record, unsupported, window_len,
};
use boundtrace_fields::scalis::{ScalisSegment, ScalisSkeleton};
use boundtrace_tracer::camera::ray_box_span;
use boundtrace_tracer::pixel::PixelTrace;
use boundtrace_tracer::scalis::{PrimitiveHit, trace_scalis_in};
use boundtrace_tracer::{Method, RayStats, Root, Status, Trace};

/// One leg of pixel `(x, y)` of a SCALIS frame (the leg kernels' state
/// machine, [`PixelLeg`]; the shader's `trace_scalis` entry point): the
/// pixel's trace with [`trace_scalis_in`] over its primitive list
/// `lists[offsets[i]..offsets[i + 1]]` (`i = y·width + x`) and the
/// skeleton `segments` with [`Constants::iso`], then its hits with normals
/// (the normal of the whole skeleton, as the CPU renderer computes it).
///
/// The trace itself is not resumable: when the loop-limit probe
/// ([`loops_complete`]) fails after it, the pixel stays
/// [`PHASE_FRESH`](crate::PHASE_FRESH) and the next dispatch traces it
/// again (a host sees no progress when a trace always needs more loop
/// iterations than the driver allows). Shading resumes root by root, as in
/// the other leg kernels.
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
    leg: &mut PixelLeg,
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
    if leg.phase == PHASE_FRESH {
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
                trace_scalis_in(
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
                )
            }
        };
        if !loops_complete(c.guard_loops) {
            // the driver's loop limit cut the trace: trace it again
            return;
        }
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
