//! Rendering a field through a [`Camera`]: one traced ray per pixel, kept in
//! a [`Frame`] that gives depth, normal, shaded and steps-heatmap images and
//! the frame's statistics (the papers' figures: forward-inclusion paper
//! Fig. 10, 12 and 13, §7).
//!
//! Each pixel's ray is clipped to the scene's bounding box by
//! [`ray_box_span`](crate::camera::ray_box_span) and traced there by [`trace`](fn@crate::trace) with the
//! chosen [`Method`] and [`Mode`]: opaque mode keeps the first root,
//! transparent mode every root up to `max_roots` (a fixed per-pixel buffer,
//! [`Status::BufferFull`] beyond). At each root the surface normal
//! ([`normal`]) is stored.
//!
//! With the `parallel` feature, [`render`] renders rows on rayon's thread
//! pool; each pixel is computed by the same code from the same inputs, and
//! rows are assembled in order, so the frame is bit-identical to
//! [`render_serial`]'s.
//!
//! ```
//! use boundtrace_inclusion::{Field, FieldNum};
//! use boundtrace_tracer::camera::Camera;
//! use boundtrace_tracer::render::{RenderSettings, render};
//! use boundtrace_tracer::{Method, Status};
//!
//! struct Ball; // the unit ball as a signed distance
//! impl Field<f64> for Ball {
//!     fn eval<N: FieldNum<f64>>(&self, p: [N; 3]) -> N {
//!         (p[0].sqr() + p[1].sqr() + p[2].sqr()).sqrt() - 1.0
//!     }
//!     fn lipschitz(&self) -> Option<f64> { Some(1.0) }
//! }
//!
//! let bounds = [[-1.5; 3], [1.5; 3]];
//! let camera = Camera::framing(bounds, [0.0, 0.0, -1.0], 40.0, 1.0)?;
//! let settings = RenderSettings::new(32, 32, Method::Segment)?;
//! let frame = render(&Ball, &camera, bounds, &settings)?;
//! let totals = frame.totals();
//! assert_eq!(totals.rays, 32 * 32);
//! assert_eq!(totals.finished + totals.max_steps + totals.buffer_full + totals.unsupported,
//!            totals.box_rays);
//! let png = frame.shaded_image().to_png(); // or .write_png("ball.png")
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::camera::Camera;
use crate::image::{Image, ImageError, depth_gray, heat, normal_rgb};
use crate::method::{InvalidParams, Method, Mode, Params};
use crate::pixel::{PixelSetup, trace_pixel_with};
use crate::trace::{RayStats, Root, Side, Status, Trace, normal, trace};
use boundtrace_ia_core::Real;
use boundtrace_inclusion::{Field, Ray};
use core::fmt;

/// The largest `max_roots` of [`RenderSettings`].
pub const MAX_ROOTS: u32 = 1024;

/// What to render: image size, method, mode, tracing parameters and the
/// per-pixel root buffer of transparent mode.
///
/// Build with [`RenderSettings::new`] and the `with_*` setters, which
/// validate; [`render`] validates again (the fields are public).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderSettings<T> {
    /// Image width in pixels (`1 ..= MAX_DIMENSION`).
    pub width: u32,
    /// Image height in pixels (`1 ..= MAX_DIMENSION`, at most
    /// [`MAX_PIXELS`](crate::image::MAX_PIXELS) pixels in all).
    pub height: u32,
    /// The ray-processing method.
    pub method: Method,
    /// Opaque (first root) or transparent (every root).
    pub mode: Mode,
    /// Tracing parameters.
    pub params: Params<T>,
    /// Size of the per-pixel root buffer in transparent mode
    /// (`1 ..= MAX_ROOTS`); opaque mode uses one slot.
    pub max_roots: u32,
}

/// Invalid rendering input.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RenderError {
    /// The image size is zero or too large.
    Size(ImageError),
    /// A tracing parameter is invalid.
    Params(InvalidParams),
    /// `max_roots` is not in `1 ..= MAX_ROOTS`.
    MaxRoots,
    /// The bounding box is not finite with `min ≤ max` on every axis.
    Bounds,
}

impl fmt::Display for RenderError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RenderError::Size(e) => write!(f, "render: {e}"),
            RenderError::Params(e) => write!(f, "render: {e}"),
            RenderError::MaxRoots => write!(f, "render: max_roots must be in 1..={MAX_ROOTS}"),
            RenderError::Bounds => {
                f.write_str("render: the bounding box must be finite with min <= max on every axis")
            }
        }
    }
}

impl std::error::Error for RenderError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            RenderError::Size(e) => Some(e),
            RenderError::Params(e) => Some(e),
            _ => None,
        }
    }
}

impl<T: Real> RenderSettings<T> {
    /// Opaque rendering of a `width × height` image with `method`, default
    /// [`Params`] and a buffer of 16 roots (for transparent mode).
    ///
    /// # Errors
    /// [`RenderError::Size`] for a zero or too large size.
    pub fn new(width: u32, height: u32, method: Method) -> Result<Self, RenderError> {
        let s = Self {
            width,
            height,
            method,
            mode: Mode::Opaque,
            params: Params::new(),
            max_roots: 16,
        };
        s.validate().map(|()| s)
    }

    /// Checks every field.
    ///
    /// # Errors
    /// The first problem: size, parameters, `max_roots`.
    pub fn validate(&self) -> Result<(), RenderError> {
        check_size(self.width, self.height)?;
        self.params.validate().map_err(RenderError::Params)?;
        if self.max_roots == 0 || self.max_roots > MAX_ROOTS {
            return Err(RenderError::MaxRoots);
        }
        Ok(())
    }

    /// With opaque or transparent mode.
    pub fn with_mode(self, mode: Mode) -> Self {
        Self { mode, ..self }
    }

    /// With tracing parameters.
    ///
    /// # Errors
    /// [`RenderError::Params`] for invalid parameters.
    pub fn with_params(self, params: Params<T>) -> Result<Self, RenderError> {
        let s = Self { params, ..self };
        s.validate().map(|()| s)
    }

    /// With a per-pixel root buffer of `max_roots` (transparent mode).
    ///
    /// # Errors
    /// [`RenderError::MaxRoots`] unless `1 ≤ max_roots ≤ MAX_ROOTS`.
    pub fn with_max_roots(self, max_roots: u32) -> Result<Self, RenderError> {
        let s = Self { max_roots, ..self };
        s.validate().map(|()| s)
    }
}

/// The image-size rules of [`Image`], without allocating one.
fn check_size(width: u32, height: u32) -> Result<(), RenderError> {
    use crate::image::{MAX_DIMENSION, MAX_PIXELS};
    if width == 0 || height == 0 {
        return Err(RenderError::Size(ImageError::ZeroSize));
    }
    if width > MAX_DIMENSION
        || height > MAX_DIMENSION
        || u64::from(width) * u64::from(height) > MAX_PIXELS
    {
        return Err(RenderError::Size(ImageError::TooLarge));
    }
    Ok(())
}

/// One pixel's ray: its span in the bounding box and how tracing went.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pixel<T> {
    /// The span of the ray in the bounding box ([`ray_box_span`](crate::camera::ray_box_span)); `None`
    /// when the ray misses the box (it is then not traced).
    pub span: Option<[T; 2]>,
    /// The trace record: number of roots, [`Status`], point reached and
    /// [`RayStats`] (all zero, [`Status::Finished`], for a ray missing the
    /// box).
    pub trace: Trace<T>,
}

/// A root found along a pixel's ray, with the surface normal there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit<T> {
    /// The ray parameter (a distance: camera rays have unit direction).
    pub t: T,
    /// How the field's sign changes there.
    pub side: Side,
    /// The unit normal at `o + t·d` ([`normal`]; zero where the gradient
    /// vanishes).
    pub normal: [T; 3],
}

/// The sums over a frame (the papers' cost measures, thesis §1.8; Table 1
/// of the forward-inclusion paper reports steps per bounding-box ray).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Totals {
    /// Pixels (one ray each).
    pub rays: u64,
    /// Rays that cross the bounding box (the traced ones).
    pub box_rays: u64,
    /// Rays with at least one root.
    pub hit_rays: u64,
    /// Roots found, over all rays.
    pub roots: u64,
    /// Sum of [`RayStats::steps`].
    pub steps: u64,
    /// Sum of [`RayStats::field_evals`].
    pub field_evals: u64,
    /// Sum of [`RayStats::bound_evals`].
    pub bound_evals: u64,
    /// Traced rays that ended with [`Status::Finished`].
    pub finished: u64,
    /// Traced rays that ended with [`Status::MaxSteps`].
    pub max_steps: u64,
    /// Traced rays that ended with [`Status::BufferFull`].
    pub buffer_full: u64,
    /// Traced rays that ended with [`Status::Unsupported`].
    pub unsupported: u64,
}

impl Totals {
    /// The number of traced rays that ended with `status`.
    pub fn count(&self, status: Status) -> u64 {
        match status {
            Status::Finished => self.finished,
            Status::MaxSteps => self.max_steps,
            Status::BufferFull => self.buffer_full,
            Status::Unsupported => self.unsupported,
        }
    }

    /// Mean steps per bounding-box ray (0 without any).
    pub fn mean_steps(&self) -> f64 {
        if self.box_rays == 0 {
            0.0
        } else {
            self.steps as f64 / self.box_rays as f64
        }
    }

    /// The sums as one [`RayStats`] (saturating at `u32::MAX`).
    pub fn stats(&self) -> RayStats {
        let sat = |x: u64| u32::try_from(x).unwrap_or(u32::MAX);
        RayStats {
            steps: sat(self.steps),
            field_evals: sat(self.field_evals),
            bound_evals: sat(self.bound_evals),
        }
    }

    fn add_pixel<T>(&mut self, p: &Pixel<T>) {
        self.rays += 1;
        if p.span.is_none() {
            return;
        }
        self.box_rays += 1;
        self.hit_rays += u64::from(p.trace.roots > 0);
        self.roots += u64::from(p.trace.roots);
        self.steps += u64::from(p.trace.stats.steps);
        self.field_evals += u64::from(p.trace.stats.field_evals);
        self.bound_evals += u64::from(p.trace.stats.bound_evals);
        match p.trace.status {
            Status::Finished => self.finished += 1,
            Status::MaxSteps => self.max_steps += 1,
            Status::BufferFull => self.buffer_full += 1,
            Status::Unsupported => self.unsupported += 1,
        }
    }
}

impl fmt::Display for Totals {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let per = |x: u64| {
            if self.box_rays == 0 {
                0.0
            } else {
                x as f64 / self.box_rays as f64
            }
        };
        writeln!(
            f,
            "rays {} (bounding box {}, hit {}), roots {}",
            self.rays, self.box_rays, self.hit_rays, self.roots
        )?;
        writeln!(
            f,
            "per box ray: steps {:.3}, field evals {:.3}, bound evals {:.3}",
            per(self.steps),
            per(self.field_evals),
            per(self.bound_evals)
        )?;
        write!(
            f,
            "status: finished {}, max-steps {}, buffer-full {}, unsupported {}",
            self.finished, self.max_steps, self.buffer_full, self.unsupported
        )
    }
}

/// The quantity a heatmap shows ([`Frame::heatmap_image_by`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Metric {
    /// [`RayStats::steps`] (the papers' figures).
    #[default]
    Steps,
    /// [`RayStats::field_evals`].
    FieldEvals,
    /// [`RayStats::bound_evals`].
    BoundEvals,
}

/// Colours and opacity of [`Frame::shaded_image_with`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shading {
    /// Surface colour at full light.
    pub surface: [u8; 3],
    /// Colour of pixels without a root (and behind transparent surfaces).
    pub background: [u8; 3],
    /// Light that reaches surfaces facing away from the eye, `[0, 1]`.
    pub ambient: f64,
    /// Opacity of each surface layer in transparent mode, `[0, 1]`.
    pub alpha: f64,
}

impl Default for Shading {
    /// A warm gray surface on a dark blue-gray background, ambient 0.15,
    /// alpha 0.35.
    fn default() -> Self {
        Self {
            surface: [235, 215, 180],
            background: [28, 30, 38],
            ambient: 0.15,
            alpha: 0.35,
        }
    }
}

/// `x` clamped to `[0, 1]`; NaN gives 0.
fn unit(x: f64) -> f64 {
    if x > 0.0 { x.min(1.0) } else { 0.0 }
}

/// A rendered frame: every pixel's [`Pixel`] and [`Hit`]s, with the camera
/// and settings that made it.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame<T> {
    settings: RenderSettings<T>,
    camera: Camera<T>,
    pixels: Vec<Pixel<T>>,
    /// Hits of pixel `i` are `hits[offsets[i]..offsets[i + 1]]`.
    offsets: Vec<usize>,
    hits: Vec<Hit<T>>,
    totals: Totals,
}

/// Renders `field` through `camera` inside `bounds = [min, max]`: one ray per
/// pixel, clipped to the box by [`ray_box_span`](crate::camera::ray_box_span) and traced with the
/// settings' method and mode. With the `parallel` feature rows are rendered
/// in parallel (rayon), with a result bit-identical to [`render_serial`].
///
/// # Errors
/// Invalid settings ([`RenderSettings::validate`]) or bounds
/// ([`RenderError::Bounds`]).
pub fn render<T, F>(
    field: &F,
    camera: &Camera<T>,
    bounds: [[T; 3]; 2],
    settings: &RenderSettings<T>,
) -> Result<Frame<T>, RenderError>
where
    T: Real + Send + Sync,
    F: Field<T> + Sync,
{
    let tracer = field_tracer(field, settings);
    render_with(field, &tracer, camera, bounds, settings, &|_| {})
}

/// [`render`] of a standard scene: on the SCALIS scenes, `scalis-quadratic`,
/// `sphere` and `interval` go through [`crate::scalis`] (per-ray primitive
/// lists built per pixel, up to
/// [`SCALIS_LIST_CAPACITY`](crate::stats::SCALIS_LIST_CAPACITY) supports,
/// full evaluation beyond), every other case through [`render`].
///
/// # Errors
/// As [`render`].
pub fn render_scene<T>(
    scene: &crate::scenes::Scene<T>,
    camera: &Camera<T>,
    settings: &RenderSettings<T>,
) -> Result<Frame<T>, RenderError>
where
    T: Real + Send + Sync,
{
    render_scene_with_progress(scene, camera, settings, &|_| {})
}

/// [`render_scene`], calling `on_rows(n)` (from any thread) each time `n`
/// more rows of the image are done, for progress bars; the frame is the
/// same.
///
/// # Errors
/// As [`render`].
pub fn render_scene_with_progress<T>(
    scene: &crate::scenes::Scene<T>,
    camera: &Camera<T>,
    settings: &RenderSettings<T>,
    on_rows: &(dyn Fn(u32) + Sync),
) -> Result<Frame<T>, RenderError>
where
    T: Real + Send + Sync,
{
    let field = scene.field();
    match field {
        crate::scenes::SceneField::Scalis(w)
            if matches!(
                settings.method,
                Method::ScalisQuadratic | Method::Sphere | Method::Interval
            ) =>
        {
            let tracer = |ray: &Ray<T>, span: [T; 2], buf: &mut [Root<T>]| {
                let mut storage =
                    [crate::scalis::PrimitiveHit::empty(); crate::stats::SCALIS_LIST_CAPACITY];
                crate::scalis::trace_scalis_ray(
                    w.field(),
                    ray,
                    span,
                    settings.method,
                    settings.mode,
                    &settings.params,
                    buf,
                    &mut storage,
                )
            };
            render_with(field, &tracer, camera, scene.bounds(), settings, on_rows)
        }
        _ => {
            let tracer = field_tracer(field, settings);
            render_with(field, &tracer, camera, scene.bounds(), settings, on_rows)
        }
    }
}

/// [`render`] with any per-ray tracer (`field` gives the normals).
fn render_with<T, F, R>(
    field: &F,
    tracer: &R,
    camera: &Camera<T>,
    bounds: [[T; 3]; 2],
    settings: &RenderSettings<T>,
    on_rows: &(dyn Fn(u32) + Sync),
) -> Result<Frame<T>, RenderError>
where
    T: Real + Send + Sync,
    F: Field<T> + Sync,
    R: Fn(&Ray<T>, [T; 2], &mut [Root<T>]) -> Trace<T> + Sync,
{
    check(&bounds, settings)?;
    #[cfg(feature = "parallel")]
    let rows: Vec<Row<T>> = {
        use rayon::prelude::*;
        (0..settings.height)
            .into_par_iter()
            .map_init(
                || root_buffer(settings),
                |buf, y| {
                    let row = render_row(field, tracer, camera, &bounds, settings, y, buf);
                    on_rows(1);
                    row
                },
            )
            .collect()
    };
    #[cfg(not(feature = "parallel"))]
    let rows = serial_rows(field, tracer, camera, &bounds, settings, on_rows);
    Ok(assemble(*camera, *settings, rows))
}

/// [`render`] on the calling thread only (the reference that the parallel
/// renderer reproduces bit for bit).
///
/// # Errors
/// As [`render`].
pub fn render_serial<T: Real, F: Field<T>>(
    field: &F,
    camera: &Camera<T>,
    bounds: [[T; 3]; 2],
    settings: &RenderSettings<T>,
) -> Result<Frame<T>, RenderError> {
    check(&bounds, settings)?;
    let tracer = field_tracer(field, settings);
    let rows = serial_rows(field, &tracer, camera, &bounds, settings, &|_| {});
    Ok(assemble(*camera, *settings, rows))
}

/// [`render_serial`] with a field per pixel: pixel `(x, y)` is traced, and
/// its hits shaded, with `field_of(x, y)` (the settings' method, mode and
/// parameters), e.g. the program of the pixel's image tile
/// ([`crate::tile_programs`]).
///
/// ```
/// use boundtrace_tracer::camera::Camera;
/// use boundtrace_tracer::render::{RenderSettings, render_serial, render_serial_with};
/// use boundtrace_tracer::Method;
/// use boundtrace_inclusion::{Field, FieldNum};
/// struct Ball(f64);
/// impl Field<f64> for Ball {
///     fn eval<N: FieldNum<f64>>(&self, p: [N; 3]) -> N {
///         (p[0].sqr() + p[1].sqr() + p[2].sqr()).sqrt() - self.0
///     }
///     fn lipschitz(&self) -> Option<f64> {
///         Some(1.0)
///     }
/// }
/// let bounds = [[-1.0; 3], [1.0; 3]];
/// let camera = Camera::framing(bounds, [0.0, 0.0, -1.0], 40.0, 1.0)?;
/// let settings = RenderSettings::new(8, 8, Method::Sphere)?;
/// // The left half sees a smaller ball.
/// let two = render_serial_with(|x, _| Ball(if x < 4 { 0.3 } else { 0.5 }), &camera, bounds, &settings)?;
/// let one = render_serial(&Ball(0.5), &camera, bounds, &settings)?;
/// assert_eq!(two.depth(6, 4), one.depth(6, 4));
/// assert!(two.depth(3, 4) > one.depth(3, 4));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// Invalid settings or bounds.
pub fn render_serial_with<T: Real, F: Field<T>, G: Fn(u32, u32) -> F>(
    field_of: G,
    camera: &Camera<T>,
    bounds: [[T; 3]; 2],
    settings: &RenderSettings<T>,
) -> Result<Frame<T>, RenderError> {
    check(&bounds, settings)?;
    let setup = PixelSetup {
        camera: *camera,
        bounds,
        width: settings.width,
        height: settings.height,
        method: settings.method,
        mode: settings.mode,
        params: settings.params,
    };
    let mut buf = root_buffer(settings);
    let rows = (0..settings.height)
        .map(|y| {
            let mut row = Row {
                pixels: Vec::with_capacity(settings.width as usize),
                hits: Vec::new(),
            };
            for x in 0..settings.width {
                let field = field_of(x, y);
                let tracer = field_tracer(&field, settings);
                let px = trace_pixel_with(&setup, x, y, buf.len(), |ray, span| {
                    tracer(ray, span, &mut buf)
                });
                for root in &buf[..px.trace.roots as usize] {
                    row.hits.push(hit_at(&field, &px.ray, root));
                }
                row.pixels.push(Pixel {
                    span: px.span,
                    trace: px.trace,
                });
            }
            row
        })
        .collect();
    Ok(assemble(*camera, *settings, rows))
}

pub(crate) fn check<T: Real>(
    bounds: &[[T; 3]; 2],
    settings: &RenderSettings<T>,
) -> Result<(), RenderError> {
    settings.validate()?;
    let ok = (0..3).all(|i| {
        bounds[0][i].is_finite() && bounds[1][i].is_finite() && bounds[0][i] <= bounds[1][i]
    });
    if ok { Ok(()) } else { Err(RenderError::Bounds) }
}

/// One row's pixels and hits (hit counts per pixel are `trace.roots`).
pub(crate) struct Row<T> {
    pub(crate) pixels: Vec<Pixel<T>>,
    pub(crate) hits: Vec<Hit<T>>,
}

fn root_buffer<T: Real>(settings: &RenderSettings<T>) -> Vec<Root<T>> {
    let n = match settings.mode {
        Mode::Opaque => 1,
        Mode::Transparent => settings.max_roots as usize,
    };
    vec![
        Root {
            t: T::ZERO,
            side: Side::Touch,
        };
        n
    ]
}

fn serial_rows<T: Real, F: Field<T>, R: Fn(&Ray<T>, [T; 2], &mut [Root<T>]) -> Trace<T>>(
    field: &F,
    tracer: &R,
    camera: &Camera<T>,
    bounds: &[[T; 3]; 2],
    settings: &RenderSettings<T>,
    on_rows: &(dyn Fn(u32) + Sync),
) -> Vec<Row<T>> {
    let mut buf = root_buffer(settings);
    (0..settings.height)
        .map(|y| {
            let row = render_row(field, tracer, camera, bounds, settings, y, &mut buf);
            on_rows(1);
            row
        })
        .collect()
}

fn render_row<T: Real, F: Field<T>, R: Fn(&Ray<T>, [T; 2], &mut [Root<T>]) -> Trace<T>>(
    field: &F,
    tracer: &R,
    camera: &Camera<T>,
    bounds: &[[T; 3]; 2],
    settings: &RenderSettings<T>,
    y: u32,
    buf: &mut [Root<T>],
) -> Row<T> {
    let mut row = Row {
        pixels: Vec::with_capacity(settings.width as usize),
        hits: Vec::new(),
    };
    // The per-pixel code is the GPU shader's (`pixel::trace_pixel_with`).
    let setup = PixelSetup {
        camera: *camera,
        bounds: *bounds,
        width: settings.width,
        height: settings.height,
        method: settings.method,
        mode: settings.mode,
        params: settings.params,
    };
    for x in 0..settings.width {
        let px = trace_pixel_with(&setup, x, y, buf.len(), |ray, span| tracer(ray, span, buf));
        // The root count is clamped to `buf.len()`.
        for root in &buf[..px.trace.roots as usize] {
            row.hits.push(hit_at(field, &px.ray, root));
        }
        row.pixels.push(Pixel {
            span: px.span,
            trace: px.trace,
        });
    }
    row
}

/// The generic per-ray tracer of `render`/`render_serial`: [`trace`] with
/// the settings' method, mode and parameters.
fn field_tracer<'a, T: Real, F: Field<T>>(
    field: &'a F,
    settings: &'a RenderSettings<T>,
) -> impl Fn(&Ray<T>, [T; 2], &mut [Root<T>]) -> Trace<T> + 'a {
    move |ray, span, buf| {
        trace(
            field,
            ray,
            span,
            settings.method,
            settings.mode,
            &settings.params,
            buf,
        )
    }
}

fn hit_at<T: Real, F: Field<T>>(field: &F, ray: &Ray<T>, root: &Root<T>) -> Hit<T> {
    let p = [0, 1, 2].map(|i| ray.origin[i] + root.t * ray.dir[i]);
    Hit {
        t: root.t,
        side: root.side,
        normal: normal(field, p),
    }
}

pub(crate) fn assemble<T: Real>(
    camera: Camera<T>,
    settings: RenderSettings<T>,
    rows: Vec<Row<T>>,
) -> Frame<T> {
    let n = settings.width as usize * settings.height as usize;
    let mut frame = Frame {
        settings,
        camera,
        pixels: Vec::with_capacity(n),
        offsets: Vec::with_capacity(n + 1),
        hits: Vec::new(),
        totals: Totals::default(),
    };
    frame.offsets.push(0);
    for row in rows {
        for p in &row.pixels {
            let end = frame.offsets[frame.offsets.len() - 1] + p.trace.roots as usize;
            frame.offsets.push(end);
            frame.totals.add_pixel(p);
        }
        frame.pixels.extend(row.pixels);
        frame.hits.extend(row.hits);
    }
    frame
}

impl<T: Real> Frame<T> {
    /// A frame from per-pixel results computed elsewhere (the GPU host):
    /// `pixels` row by row from the top, and the hits of pixel `i` are the
    /// next `pixels[i].trace.roots` entries of `hits`. `None` when the
    /// settings are invalid, the pixel count is not `width × height` or
    /// the hit count does not match the pixels' root counts.
    pub fn from_parts(
        camera: Camera<T>,
        settings: RenderSettings<T>,
        pixels: Vec<Pixel<T>>,
        hits: Vec<Hit<T>>,
    ) -> Option<Self> {
        settings.validate().ok()?;
        let n = settings.width as usize * settings.height as usize;
        let roots: usize = pixels.iter().map(|p| p.trace.roots as usize).sum();
        if pixels.len() != n || roots != hits.len() {
            return None;
        }
        Some(assemble(camera, settings, vec![Row { pixels, hits }]))
    }

    /// Image width in pixels.
    pub fn width(&self) -> u32 {
        self.settings.width
    }

    /// Image height in pixels.
    pub fn height(&self) -> u32 {
        self.settings.height
    }

    /// The settings the frame was rendered with.
    pub fn settings(&self) -> &RenderSettings<T> {
        &self.settings
    }

    /// The camera the frame was rendered with.
    pub fn camera(&self) -> &Camera<T> {
        &self.camera
    }

    /// Every pixel, row by row from the top.
    pub fn pixels(&self) -> &[Pixel<T>] {
        &self.pixels
    }

    /// The pixel at `(x, y)` (`y = 0` is the top row), if inside.
    pub fn pixel(&self, x: u32, y: u32) -> Option<&Pixel<T>> {
        self.index(x, y).map(|i| &self.pixels[i])
    }

    /// The hits of pixel `(x, y)` in increasing `t` (empty outside the
    /// image).
    pub fn hits(&self, x: u32, y: u32) -> &[Hit<T>] {
        self.index(x, y).map_or(&[], |i| self.hits_of(i))
    }

    /// The first hit's ray parameter (the depth along the unit-speed ray)
    /// at `(x, y)`, if any.
    pub fn depth(&self, x: u32, y: u32) -> Option<T> {
        self.hits(x, y).first().map(|h| h.t)
    }

    /// The frame's sums and status counts.
    pub fn totals(&self) -> Totals {
        self.totals
    }

    fn index(&self, x: u32, y: u32) -> Option<usize> {
        (x < self.width() && y < self.height())
            .then(|| y as usize * self.width() as usize + x as usize)
    }

    fn hits_of(&self, i: usize) -> &[Hit<T>] {
        &self.hits[self.offsets[i]..self.offsets[i + 1]]
    }

    fn image(&self, mut f: impl FnMut(usize, u32, u32) -> [u8; 3]) -> Image {
        let w = self.width();
        // A frame exists only after `render` checked its size against the
        // same rules as `Image`'s, so this cannot fail.
        Image::from_fn(w, self.height(), |x, y| {
            f(y as usize * w as usize + x as usize, x, y)
        })
        .expect("frame size validated before rendering")
    }

    /// The first-hit depth as gray: white at the nearest hit of the frame,
    /// dark gray at the farthest ([`depth_gray`]); black without a hit.
    pub fn depth_image(&self) -> Image {
        let (mut near, mut far) = (f64::INFINITY, f64::NEG_INFINITY);
        for i in 0..self.pixels.len() {
            if let Some(h) = self.hits_of(i).first() {
                let t = h.t.as_f64();
                near = near.min(t);
                far = far.max(t);
            }
        }
        self.image(|i, _, _| {
            self.hits_of(i)
                .first()
                .map_or([0; 3], |h| depth_gray(h.t.as_f64(), near, far))
        })
    }

    /// The first hit's normal as a colour ([`normal_rgb`]); black without a
    /// hit.
    pub fn normal_image(&self) -> Image {
        self.image(|i, _, _| {
            self.hits_of(i)
                .first()
                .map_or([0; 3], |h| normal_rgb(h.normal.map(Real::as_f64)))
        })
    }

    /// [`Frame::shaded_image_with`] the default [`Shading`].
    pub fn shaded_image(&self) -> Image {
        self.shaded_image_with(&Shading::default())
    }

    /// Headlight shading: a surface point gets
    /// `ambient + (1 − ambient)·|n·d|` of the surface colour (`d` the unit
    /// ray direction), pixels without a root the background. In
    /// transparent mode every root is a layer of opacity `alpha`,
    /// composited front to back over the background (as the papers'
    /// transparent renderings, forward-inclusion paper §7.2). `ambient`
    /// and `alpha` are clamped to `[0, 1]`.
    pub fn shaded_image_with(&self, shading: &Shading) -> Image {
        let ambient = unit(shading.ambient);
        let alpha = match self.settings.mode {
            Mode::Opaque => 1.0,
            Mode::Transparent => unit(shading.alpha),
        };
        let (w, h) = (self.width(), self.height());
        self.image(|i, x, y| {
            let hits = self.hits_of(i);
            if hits.is_empty() {
                return shading.background;
            }
            let d = self.camera.ray(x, y, w, h).dir.map(Real::as_f64);
            let mut acc = [0.0f64; 3];
            let mut through = 1.0f64;
            for hit in hits {
                let n = hit.normal.map(Real::as_f64);
                let light = (n[0] * d[0] + n[1] * d[1] + n[2] * d[2]).abs();
                let light = ambient + (1.0 - ambient) * unit(light);
                for (a, &c) in acc.iter_mut().zip(&shading.surface) {
                    *a += through * alpha * light * f64::from(c);
                }
                through *= 1.0 - alpha;
                if through == 0.0 {
                    break;
                }
            }
            let mut out = [0u8; 3];
            for k in 0..3 {
                let v = acc[k] + through * f64::from(shading.background[k]);
                out[k] = (unit(v / 255.0) * 255.0 + 0.5) as u8;
            }
            out
        })
    }

    /// The steps heatmap ([`heat`]): each pixel's [`RayStats::steps`]
    /// clamped to `max_for_display` (the papers clamp to 75,
    /// forward-inclusion paper Fig. 12). Rays missing the box show 0.
    pub fn heatmap_image(&self, max_for_display: u32) -> Image {
        self.heatmap_image_by(Metric::Steps, max_for_display)
    }

    /// A heatmap of any [`Metric`] clamped to `max_for_display`.
    pub fn heatmap_image_by(&self, metric: Metric, max_for_display: u32) -> Image {
        self.image(|i, _, _| {
            let s = self.pixels[i].trace.stats;
            let v = match metric {
                Metric::Steps => s.steps,
                Metric::FieldEvals => s.field_evals,
                Metric::BoundEvals => s.bound_evals,
            };
            heat(v, max_for_display)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::ray_box_span;
    use boundtrace_inclusion::FieldNum;

    /// The unit ball as a signed distance (Lipschitz 1).
    struct Ball;
    impl Field<f64> for Ball {
        fn eval<N: FieldNum<f64>>(&self, p: [N; 3]) -> N {
            (p[0].sqr() + p[1].sqr() + p[2].sqr()).sqrt() - 1.0
        }
        fn lipschitz(&self) -> Option<f64> {
            Some(1.0)
        }
    }

    const BOX: [[f64; 3]; 2] = [[-1.25; 3], [1.25; 3]];

    fn camera() -> Camera<f64> {
        Camera::framing(BOX, [0.0, 0.0, -1.0], 40.0, 1.0).unwrap()
    }

    #[test]
    fn from_parts_rebuilds_a_frame_and_rejects_mismatches() {
        let settings = RenderSettings::new(6, 5, Method::Segment)
            .unwrap()
            .with_mode(Mode::Transparent);
        let frame = render_serial(&Ball, &camera(), BOX, &settings).unwrap();
        let hits: Vec<Hit<f64>> = (0..5)
            .flat_map(|y| (0..6).map(move |x| (x, y)))
            .flat_map(|(x, y)| frame.hits(x, y).to_vec())
            .collect();
        assert!(!hits.is_empty());
        let pixels = frame.pixels().to_vec();
        let again = Frame::from_parts(camera(), settings, pixels.clone(), hits.clone()).unwrap();
        assert_eq!(again, frame);
        assert!(
            Frame::from_parts(camera(), settings, pixels[1..].to_vec(), hits.clone()).is_none()
        );
        assert!(Frame::from_parts(camera(), settings, pixels, hits[1..].to_vec()).is_none());
    }

    #[test]
    fn settings_validation() {
        type S = RenderSettings<f64>;
        assert_eq!(
            S::new(0, 4, Method::Segment),
            Err(RenderError::Size(ImageError::ZeroSize))
        );
        assert_eq!(
            S::new(1 << 17, 1, Method::Segment),
            Err(RenderError::Size(ImageError::TooLarge))
        );
        let s = S::new(4, 4, Method::Segment).unwrap();
        assert_eq!(s.with_max_roots(0), Err(RenderError::MaxRoots));
        assert_eq!(s.with_max_roots(MAX_ROOTS + 1), Err(RenderError::MaxRoots));
        let bad = Params {
            eps: 0.0,
            ..Params::new()
        };
        assert!(matches!(s.with_params(bad), Err(RenderError::Params(_))));
        let mut hand = s;
        hand.params.max_steps = 0;
        assert!(render(&Ball, &camera(), BOX, &hand).is_err());
        let inverted = [[1.0; 3], [-1.0; 3]];
        assert_eq!(
            render(&Ball, &camera(), inverted, &s),
            Err(RenderError::Bounds)
        );
        let nan = [[f64::NAN; 3], [1.0; 3]];
        assert_eq!(
            render_serial(&Ball, &camera(), nan, &s),
            Err(RenderError::Bounds)
        );
        assert!(RenderError::MaxRoots.to_string().contains("max_roots"));
    }

    #[test]
    fn spans_and_bookkeeping() {
        let s = RenderSettings::new(24, 16, Method::Segment)
            .unwrap()
            .with_mode(Mode::Transparent);
        let cam = Camera::framing(BOX, [0.0, 0.0, -1.0], 40.0, 1.5).unwrap();
        let frame = render_serial(&Ball, &cam, BOX, &s).unwrap();
        let t = frame.totals();
        assert_eq!(t.rays, 24 * 16);
        assert!(t.box_rays > 0 && t.box_rays < t.rays); // corners miss the box
        assert_eq!(
            t.finished + t.max_steps + t.buffer_full + t.unsupported,
            t.box_rays
        );
        let mut roots = 0;
        for y in 0..16 {
            for x in 0..24 {
                let p = frame.pixel(x, y).unwrap();
                let ray = cam.ray(x, y, 24, 16);
                assert_eq!(p.span, ray_box_span(&ray, &BOX));
                assert_eq!(frame.hits(x, y).len(), p.trace.roots as usize);
                roots += p.trace.roots as u64;
                if p.span.is_none() {
                    assert_eq!(p.trace.stats, RayStats::default());
                }
            }
        }
        assert_eq!(roots, t.roots);
        assert!(frame.pixel(24, 0).is_none() && frame.hits(0, 16).is_empty());
        // the images have the frame's size
        for img in [
            frame.depth_image(),
            frame.normal_image(),
            frame.shaded_image(),
            frame.heatmap_image(75),
        ] {
            assert_eq!((img.width(), img.height()), (24, 16));
        }
    }

    #[test]
    fn ball_hits() {
        let s = RenderSettings::new(33, 33, Method::Segment).unwrap();
        let frame = render(&Ball, &camera(), BOX, &s).unwrap();
        assert_eq!(frame.totals().unsupported, 0);
        let centre = frame.hits(16, 16);
        assert_eq!(centre.len(), 1);
        let cam = camera();
        let dist = ((0..3).map(|i| cam.eye[i] * cam.eye[i]).sum::<f64>()).sqrt();
        assert!((centre[0].t - (dist - 1.0)).abs() <= 2.0 * s.params.eps);
        assert!(centre[0].normal[2] > 0.99);
        assert!(frame.hits(0, 0).is_empty());
        let shaded = frame.shaded_image();
        assert_eq!(shaded.get(0, 0), Some(Shading::default().background));
        assert_ne!(shaded.get(16, 16), Some(Shading::default().background));
    }

    #[cfg(feature = "parallel")]
    #[test]
    fn parallel_is_bit_identical_to_serial() {
        for mode in [Mode::Opaque, Mode::Transparent] {
            for method in [Method::Sphere, Method::Segment, Method::Interval] {
                let s = RenderSettings::new(29, 23, method).unwrap().with_mode(mode);
                let cam = Camera::framing(BOX, [1.0, -0.5, -2.0], 50.0, 29.0 / 23.0).unwrap();
                let par = render(&Ball, &cam, BOX, &s).unwrap();
                let ser = render_serial(&Ball, &cam, BOX, &s).unwrap();
                assert_eq!(par, ser);
                let bits = |f: &Frame<f64>| -> Vec<u64> {
                    f.hits
                        .iter()
                        .flat_map(|h| [h.t.to_bits(), h.normal[0].to_bits()])
                        .collect()
                };
                assert_eq!(bits(&par), bits(&ser));
                assert_eq!(par.shaded_image(), ser.shaded_image());
                assert_eq!(par.heatmap_image(75), ser.heatmap_image(75));
            }
        }
    }
}
