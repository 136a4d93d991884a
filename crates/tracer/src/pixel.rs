//! One pixel of a rendered frame, allocation-free: the ray through the
//! pixel, clipped to the scene's box, traced. The CPU renderer
//! ([`render`](crate::render), feature `std`) and the GPU compute shader
//! (`crates/gpu-shader`) both call [`trace_pixel`], so a pixel's result
//! comes from the same code on both.

use crate::camera::{Camera, ray_box_span};
use crate::method::{Method, Mode, Params};
use crate::trace::{RayStats, Root, Status, Trace, trace_in};
use boundtrace_ia_core::Real;
use boundtrace_inclusion::Ray;

/// What every pixel of a frame shares: camera, scene box, image size,
/// method, mode and tracing parameters (plain data).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelSetup<T> {
    /// The camera.
    pub camera: Camera<T>,
    /// The box `[min, max]` enclosing the surface; rays are traced only
    /// inside it.
    pub bounds: [[T; 3]; 2],
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// The method.
    pub method: Method,
    /// Opaque or transparent.
    pub mode: Mode,
    /// The tracing parameters.
    pub params: Params<T>,
}

/// A traced pixel: its ray, the ray's span in the box (`None` when it
/// misses the box and is not traced) and the trace record (whose roots are
/// in the caller's buffer; all zero and [`Status::Finished`] for a ray
/// missing the box).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelTrace<T> {
    /// The pixel's ray ([`Camera::ray`]).
    pub ray: Ray<T>,
    /// The span of the ray in the box ([`ray_box_span`]).
    pub span: Option<[T; 2]>,
    /// The trace record; `roots` never exceeds the buffer's length.
    pub trace: Trace<T>,
}

/// Traces pixel `(x, y)` (`y = 0` is the top row): the ray through its
/// centre, clipped to `setup.bounds` by [`ray_box_span`], traced by
/// [`trace`](fn@crate::trace) with the setup's method and mode into `roots`
/// (opaque mode needs one slot). Allocation- and recursion-free.
pub fn trace_pixel<T: Real, F: boundtrace_inclusion::Field<T>>(
    field: &F,
    setup: &PixelSetup<T>,
    x: u32,
    y: u32,
    roots: &mut [Root<T>],
) -> PixelTrace<T> {
    let len = roots.len();
    trace_pixel_in(field, setup, x, y, roots, [0, len])
}

/// [`trace_pixel`] with the roots written to the window
/// `roots[base..base + len]` (`window = [base, len]`; see
/// [`trace_in`]): the GPU shader's form, one window per pixel of a storage
/// buffer. The reported root count never exceeds `len`.
pub fn trace_pixel_in<T: Real, F: boundtrace_inclusion::Field<T>>(
    field: &F,
    setup: &PixelSetup<T>,
    x: u32,
    y: u32,
    roots: &mut [Root<T>],
    window: [usize; 2],
) -> PixelTrace<T> {
    trace_pixel_with(setup, x, y, window[1], move |ray, span| {
        trace_in(
            field,
            ray,
            span,
            setup.method,
            setup.mode,
            &setup.params,
            roots,
            window,
        )
    })
}

/// The pixel loop body shared by every renderer: the ray through pixel
/// `(x, y)`, its span in `setup.bounds`, and `tracer(ray, span)` when the
/// ray meets the box (an all-zero [`Status::Finished`] record when it
/// does not); the reported root count is clamped to `max_roots`, the
/// tracer's buffer length. [`trace_pixel_in`] (the GPU shader) passes
/// [`trace_in`] with the setup's method, mode and parameters; the CPU
/// renderer ([`render`](crate::render)) its per-ray tracer (the same
/// [`trace`](fn@crate::trace), or a scene-specific one such as SCALIS's).
pub fn trace_pixel_with<T: Real, R: FnOnce(&Ray<T>, [T; 2]) -> Trace<T>>(
    setup: &PixelSetup<T>,
    x: u32,
    y: u32,
    max_roots: usize,
    tracer: R,
) -> PixelTrace<T> {
    let ray = setup.camera.ray(x, y, setup.width, setup.height);
    let span = ray_box_span(&ray, &setup.bounds);
    let tr = match span {
        None => Trace {
            roots: 0,
            status: Status::Finished,
            t_reached: T::ZERO,
            stats: RayStats::default(),
        },
        Some(span) => tracer(&ray, span),
    };
    // The tracer writes at most `max_roots` roots; never report more.
    let n = if (tr.roots as usize) < max_roots {
        tr.roots
    } else {
        max_roots as u32
    };
    PixelTrace {
        ray,
        span,
        trace: Trace { roots: n, ..tr },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trace::Side;
    use boundtrace_inclusion::{Field, FieldNum};

    struct Ball;
    impl Field<f64> for Ball {
        fn eval<N: FieldNum<f64>>(&self, p: [N; 3]) -> N {
            (p[0].sqr() + p[1].sqr() + p[2].sqr()).sqrt() - 0.5
        }
        fn lipschitz(&self) -> Option<f64> {
            Some(1.0)
        }
    }

    fn setup(mode: Mode) -> PixelSetup<f64> {
        let bounds = [[-1.0; 3], [1.0; 3]];
        PixelSetup {
            camera: Camera::framing(bounds, [0.0, 0.0, -1.0], 40.0, 1.0).unwrap(),
            bounds,
            width: 9,
            height: 9,
            method: Method::Segment,
            mode,
            params: Params::new(),
        }
    }

    #[test]
    fn centre_hits_corner_misses_the_ball() {
        let mut buf = [Root {
            t: 0.0,
            side: Side::Touch,
        }; 4];
        let s = setup(Mode::Transparent);
        let c = trace_pixel(&Ball, &s, 4, 4, &mut buf);
        assert_eq!(c.trace.roots, 2);
        assert!(c.span.is_some() && c.trace.stats.steps > 0);
        assert!(buf[0].side == Side::Entering && buf[1].side == Side::Leaving);
        // The distance from the eye to the ball along the central ray.
        let eye = s.camera.eye;
        let d2 = eye[0] * eye[0] + eye[1] * eye[1] + eye[2] * eye[2];
        let r = buf[0].t + 0.5; // the eye's distance to the centre
        assert!((r * r - d2).abs() < 1e-2, "{} vs {}", r * r, d2);
        let corner = trace_pixel(&Ball, &s, 0, 0, &mut buf);
        assert_eq!(corner.trace.roots, 0);
        // The same pixel in a window of a larger buffer.
        let mut big = [Root {
            t: -1.0,
            side: Side::Touch,
        }; 8];
        let w = trace_pixel_in(&Ball, &s, 4, 4, &mut big, [5, 3]);
        assert_eq!(w.trace, c.trace);
        assert_eq!(&big[5..7], &buf[..2]);
        assert!(big[..5].iter().all(|r| r.t == -1.0) && big[7].t == -1.0);
        // A window that does not fit is unsupported.
        let bad = trace_pixel_in(&Ball, &s, 4, 4, &mut big, [6, 3]);
        assert_eq!(bad.trace.status, Status::Unsupported);
    }

    #[test]
    fn roots_never_exceed_the_buffer() {
        let mut one = [Root {
            t: 0.0,
            side: Side::Touch,
        }];
        let c = trace_pixel(&Ball, &setup(Mode::Transparent), 4, 4, &mut one);
        assert_eq!(c.trace.roots, 1);
        assert_eq!(c.trace.status, Status::BufferFull);
    }
}
