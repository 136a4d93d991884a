//! The per-pixel kernel of boundtrace's GPU path, shared by the SPIR-V
//! compute shader (`crates/gpu-shader`, thin `#[spirv(compute)]` wrappers
//! around [`render_pixel`]) and the wgpu host (`boundtrace-gpu`), which
//! fills [`Constants`] and the scene buffers and reads [`PixelOut`] and
//! [`HitOut`] back.
//!
//! Nothing here re-implements tracing: [`render_pixel`] builds the scene's
//! field over the flat buffers (a [`BlobtreeRef`], a [`Blobs`] over a
//! `&[PointBlob<f32>]` or a [`FlatBlobGroups`]) and calls the tracer's
//! `trace_pixel_in` and [`normal`], the same functions the CPU renderer
//! calls ([`trace_pixel_in`] is [`trace_pixel`](boundtrace_tracer::pixel::trace_pixel)
//! with the root buffer as a window). Scenes are data: editing one never recompiles the shader.
//!
//! ```
//! use boundtrace_fields::{Kernel, PointBlob};
//! use boundtrace_gpu_kernel::{Constants, HitOut, SceneKind, render_pixel};
//! use boundtrace_tracer::camera::Camera;
//! use boundtrace_tracer::pixel::PixelSetup;
//! use boundtrace_tracer::{Method, Mode, Params, Root, Side};
//!
//! let k = Kernel::compact(6, 0.5f32)?;
//! let blobs = [PointBlob::new([0.0, 0.0, 0.0], 1.0, k)?];
//! let bounds = [[-0.6f32; 3], [0.6; 3]];
//! let setup = PixelSetup {
//!     camera: Camera::framing(bounds, [0.0, 0.0, -1.0], 40.0, 1.0)?,
//!     bounds,
//!     width: 8,
//!     height: 8,
//!     method: Method::Segment,
//!     mode: Mode::Opaque,
//!     params: Params::new(),
//! };
//! let c = Constants::new(&setup, SceneKind::Blobs, 0.5, 1, 0);
//! let mut roots = [Root { t: 0.0, side: Side::Touch }; 1];
//! let mut hits = [HitOut::default(); 1];
//! let out = render_pixel(&c, &[], &[], &blobs, 4, 4, &mut roots, &mut hits, 0);
//! assert_eq!(out.roots, 1); // the centre pixel hits the blob
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![cfg_attr(not(feature = "std"), no_std)]
// `!(a < b)` is deliberate: it is also true for NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

#[cfg(all(not(feature = "std"), not(feature = "libm")))]
compile_error!("boundtrace-gpu-kernel needs the `std` or the `libm` feature for its math");

mod groups;
mod scalis;

pub use groups::FlatBlobGroups;
pub use scalis::{ScalisLeg, render_scalis_leg, render_scalis_tight_leg};

use boundtrace_fields::AlgebraicPrimitives;
use boundtrace_fields::blobtree::{BlobtreeRef, BlobtreeWindow};
use boundtrace_fields::homothetic::{KERNEL_CAUCHY, KERNEL_COMPACT, SEGMENT_WORDS};
use boundtrace_fields::homothetic_skeleton::{FlatSegments, HomotheticSkeleton, PARAMETER_WORDS};
use boundtrace_fields::hrbf::{CENTER_WORDS, FlatCenters, Hrbf};
use boundtrace_fields::{Blobs, PointBlob};
use boundtrace_inclusion::{Field, Ray};
#[cfg(test)]
use boundtrace_tracer::Side;
use boundtrace_tracer::camera::{Camera, Projection, ray_box_span};
use boundtrace_tracer::march::{MarchState, StepGuard, TaylorCache};
use boundtrace_tracer::pixel::{PixelSetup, PixelTrace, trace_pixel_in, trace_pixel_with};
use boundtrace_tracer::{
    Leg, Method, Mode, Params, RayStats, Root, Status, Trace, fill_taylor_cache, normal,
    trace_linear_bottom_up_resume_in, trace_linear_mixed_cached_resume_in,
    trace_linear_taylor_resume_in, trace_quadratic_bottom_up_resume_in,
    trace_quadratic_mixed_cached_resume_in, trace_quadratic_taylor_resume_in,
    trace_segment_lines_resume_in, trace_segment_resume_in, trace_sphere_in,
    trace_sphere_resume_in,
};

/// The largest per-pixel root buffer of the GPU (transparent mode): a
/// fixed-size local array in the shader.
pub const MAX_GPU_ROOTS: u32 = 8;

/// Threads per workgroup along x and y (an 8 × 8 tile of pixels).
pub const WORKGROUP: u32 = 8;

/// The iterations of the loop-limit probe ([`loops_complete`]) that
/// [`Constants::new`] sets: two, the fewest that show a loop cut after its
/// first iteration.
pub const GUARD_LOOPS: u32 = 2;

/// Which field [`render_pixel`] builds over the scene buffers
/// (`#[repr(u32)]`, stored in [`Constants::scene`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum SceneKind {
    /// A flat blobtree: node words in the `u32` buffer, parameters in the
    /// `f32` buffer ([`BlobtreeRef::new`] validates them); or, when
    /// [`Constants::groups`] is not `0`, one program per 8 × 8 tile in the
    /// `u32` buffer ([`BlobtreeWindow::tile`]) over the same parameters.
    Blobtree = 0,
    /// One summed blob set over the blob buffer, with [`Constants::iso`].
    Blobs = 1,
    /// The sharp union of blob groups ([`FlatBlobGroups`]): group ends in
    /// the `u32` buffer, blobs in the blob buffer.
    BlobGroups = 2,
    /// A SCALIS skeleton ([`render_scalis_leg`]): its segments in the
    /// blob buffer's binding, the frame's per-ray primitive lists in the
    /// `f32` buffer's and their offsets (one per pixel, and the end) in
    /// the `u32` buffer, with [`Constants::iso`].
    Scalis = 3,
    /// An HRBF ([`Hrbf`] over [`FlatCenters`]): [`Constants::groups`]
    /// centers in the `f32` buffer, [`CENTER_WORDS`] words each
    /// (`cₓ c_y c_z α βₓ β_y β_z`), then the polynomial `a₀ a₁ a₂ b`. It
    /// has no global Lipschitz bound: the forward methods trace it,
    /// sphere and segment tracing report [`Status::Unsupported`] as on
    /// the CPU.
    Hrbf = 4,
    /// A homothetic-distance skeleton ([`HomotheticSkeleton`] over
    /// [`FlatSegments`]): the kernel's code `[kind, degree]`
    /// ([`SegmentKernel::code`](boundtrace_fields::homothetic::SegmentKernel::code))
    /// in the `u32` buffer (a kind other than [`KERNEL_COMPACT`] and
    /// [`KERNEL_CAUCHY`] gives unsupported pixels); in the `f32` buffer
    /// [`Constants::groups`] segments of [`SEGMENT_WORDS`] words, then the skeleton's
    /// [`PARAMETER_WORDS`] parameter words; its global Lipschitz bound in
    /// [`Constants::lipschitz`] (the CPU scene's, which sphere tracing
    /// uses).
    Homothetic = 5,
}

impl SceneKind {
    /// The kind of a code, `None` for an unknown one.
    pub const fn from_code(code: u32) -> Option<Self> {
        match code {
            0 => Some(Self::Blobtree),
            1 => Some(Self::Blobs),
            2 => Some(Self::BlobGroups),
            3 => Some(Self::Scalis),
            4 => Some(Self::Hrbf),
            5 => Some(Self::Homothetic),
            _ => None,
        }
    }
}

/// Which [`SceneKind`]s a kernel entry point compiles: a type, so that an
/// entry point can hold one scene kind's field code alone (a driver that
/// inlines every call needs tens of gigabytes for segment tracing over
/// both blob kinds at once: BENCHMARKS.md "GPU"). Pixels of another kind
/// are [`Status::Unsupported`].
pub trait SceneKinds {
    /// Whether [`SceneKind::Blobs`] scenes are traced.
    const BLOBS: bool;
    /// Whether [`SceneKind::BlobGroups`] scenes are traced.
    const GROUPS: bool;
    /// Whether [`SceneKind::Blobtree`] scenes are traced.
    const BLOBTREE: bool;
    /// Whether [`SceneKind::Hrbf`] scenes are traced.
    const HRBF: bool;
    /// Whether [`SceneKind::Homothetic`] scenes are traced.
    const HOMOTHETIC: bool;
}

/// Declares unit marker types and their [`SceneKinds`] flags.
macro_rules! scene_kinds {
    ($($(#[$doc:meta])* $name:ident = [$blobs:literal, $groups:literal, $blobtree:literal, $hrbf:literal, $homothetic:literal];)*) => {$(
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, Default)]
        pub struct $name;

        impl SceneKinds for $name {
            const BLOBS: bool = $blobs;
            const GROUPS: bool = $groups;
            const BLOBTREE: bool = $blobtree;
            const HRBF: bool = $hrbf;
            const HOMOTHETIC: bool = $homothetic;
        }
    )*};
}

// The flags in the order `[BLOBS, GROUPS, BLOBTREE, HRBF, HOMOTHETIC]`.
scene_kinds! {
    /// Every scene kind ([`SceneKinds`]).
    AllKinds = [true, true, true, true, true];
    /// The blob scenes, [`SceneKind::Blobs`] and [`SceneKind::BlobGroups`]
    /// ([`SceneKinds`]): the shader's `trace_sphere`.
    BlobKinds = [true, true, false, false, false];
    /// [`SceneKind::Blobtree`] only ([`SceneKinds`]): the shader's
    /// `trace_sphere_blobtree`.
    BlobtreeOnly = [false, false, true, false, false];
    /// [`SceneKind::Blobs`] only ([`SceneKinds`]).
    BlobsOnly = [true, false, false, false, false];
    /// [`SceneKind::BlobGroups`] only ([`SceneKinds`]).
    GroupsOnly = [false, true, false, false, false];
    /// [`SceneKind::Hrbf`] only ([`SceneKinds`]): the shader's `*_hrbf`
    /// entry points.
    HrbfOnly = [false, false, false, true, false];
    /// [`SceneKind::Homothetic`] only ([`SceneKinds`]): the shader's
    /// `*_homothetic` entry points.
    HomotheticOnly = [false, false, false, false, true];
}

/// The frame's constants, as uploaded (plain `u32`/`f32` words, `#[repr(C)]`,
/// no padding: 37 words).
///
/// Enums travel as their `#[repr(u32)]` codes; [`Constants::setup`]
/// decodes them (an unknown code gives `None`, and the pixel is reported
/// [`Status::Unsupported`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct Constants {
    /// [`Camera::eye`].
    pub eye: [f32; 3],
    /// [`Camera::right`].
    pub right: [f32; 3],
    /// [`Camera::up`].
    pub up: [f32; 3],
    /// [`Camera::forward`].
    pub forward: [f32; 3],
    /// [`Camera::scale`].
    pub scale: [f32; 2],
    /// [`Camera::projection`] code.
    pub projection: u32,
    /// Scene box minimum.
    pub bounds_lo: [f32; 3],
    /// Scene box maximum.
    pub bounds_hi: [f32; 3],
    /// [`Params::eps`].
    pub eps: f32,
    /// [`Params::min_step`].
    pub min_step: f32,
    /// [`Params::omega`].
    pub omega: f32,
    /// [`Params::k`].
    pub k: f32,
    /// [`Params::max_steps`].
    pub max_steps: u32,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// [`Method`] code.
    pub method: u32,
    /// [`Mode`] code.
    pub mode: u32,
    /// Root slots per pixel (`1..=`[`MAX_GPU_ROOTS`]; opaque mode uses one).
    pub max_roots: u32,
    /// [`SceneKind`] code.
    pub scene: u32,
    /// The iso-value of the blob scenes.
    pub iso: f32,
    /// The number of blob groups ([`SceneKind::BlobGroups`]), HRBF
    /// centers ([`SceneKind::Hrbf`]) or skeleton segments
    /// ([`SceneKind::Homothetic`]); for
    /// [`SceneKind::Blobtree`] the number of 8 × 8 tiles per image row when
    /// `words` holds one program per tile
    /// ([`BlobtreeWindow::tile`](boundtrace_fields::blobtree::BlobtreeWindow::tile),
    /// the host's `TilePrograms`), `0` when it holds the tree.
    pub groups: u32,
    /// Iterations of the loop-limit probe run after each sphere-tracing
    /// step of [`render_sphere_leg`] (`0`: no probe; the host sets
    /// [`GUARD_LOOPS`]).
    pub guard_loops: u32,
    /// The most sphere-tracing steps a pixel takes per dispatch in
    /// [`render_sphere_leg`] (`0`: no limit), so that a frame can be
    /// traced in short dispatches (a GPU watchdog, or to test resumption).
    pub leg_steps: u32,
    /// A global Lipschitz bound of a [`SceneKind::Blobs`] field that
    /// replaces the blobs' own in sphere tracing when `> 0` (`0`, as
    /// [`Constants::new`] sets it: the blobs' own): the `molecule` scene's
    /// tighter bound, computed once by its generator (the CPU's
    /// `scenes::WithLipschitz`). The host vouches for it, as there.
    pub lipschitz: f32,
}

impl Constants {
    /// The constants of a frame: `setup`, the scene kind, the blob scenes'
    /// iso-value and group count, and `max_roots` (clamped to
    /// `1..=`[`MAX_GPU_ROOTS`]).
    pub fn new(
        setup: &PixelSetup<f32>,
        scene: SceneKind,
        iso: f32,
        max_roots: u32,
        groups: u32,
    ) -> Self {
        let c = &setup.camera;
        let p = &setup.params;
        Self {
            eye: c.eye,
            right: c.right,
            up: c.up,
            forward: c.forward,
            scale: c.scale,
            projection: c.projection as u32,
            bounds_lo: setup.bounds[0],
            bounds_hi: setup.bounds[1],
            eps: p.eps,
            min_step: p.min_step,
            omega: p.omega,
            k: p.k,
            max_steps: p.max_steps,
            width: setup.width,
            height: setup.height,
            method: setup.method as u32,
            mode: setup.mode as u32,
            max_roots: max_roots.clamp(1, MAX_GPU_ROOTS),
            scene: scene as u32,
            iso,
            groups,
            guard_loops: GUARD_LOOPS,
            leg_steps: 0,
            lipschitz: 0.0,
        }
    }

    /// The constants as `u32` words in field order (for the upload).
    pub fn to_words(&self) -> [u32; 37] {
        let f = |x: f32| x.to_bits();
        let [e, r, u, fw] = [self.eye, self.right, self.up, self.forward];
        let (lo, hi) = (self.bounds_lo, self.bounds_hi);
        [
            f(e[0]),
            f(e[1]),
            f(e[2]),
            f(r[0]),
            f(r[1]),
            f(r[2]),
            f(u[0]),
            f(u[1]),
            f(u[2]),
            f(fw[0]),
            f(fw[1]),
            f(fw[2]),
            f(self.scale[0]),
            f(self.scale[1]),
            self.projection,
            f(lo[0]),
            f(lo[1]),
            f(lo[2]),
            f(hi[0]),
            f(hi[1]),
            f(hi[2]),
            f(self.eps),
            f(self.min_step),
            f(self.omega),
            f(self.k),
            self.max_steps,
            self.width,
            self.height,
            self.method,
            self.mode,
            self.max_roots,
            self.scene,
            f(self.iso),
            self.groups,
            self.guard_loops,
            self.leg_steps,
            f(self.lipschitz),
        ]
    }

    /// The tracer's view of the constants; `None` for an unknown method,
    /// mode or projection code.
    pub fn setup(&self) -> Option<PixelSetup<f32>> {
        self.codes_valid().then(|| self.decode())
    }

    /// Whether the method, mode and projection codes are known.
    pub fn codes_valid(&self) -> bool {
        self.projection <= 1 && self.mode <= 1 && Method::from_code(self.method).is_some()
    }

    /// The tracer's view of the constants, unknown codes read as the first
    /// value of their enum (check [`codes_valid`](Self::codes_valid) first).
    /// Option-free, so that the shader never moves a niche-encoded value.
    pub fn decode(&self) -> PixelSetup<f32> {
        let projection = if self.projection == 1 {
            Projection::Orthographic
        } else {
            Projection::Perspective
        };
        let mode = if self.mode == 1 {
            Mode::Transparent
        } else {
            Mode::Opaque
        };
        let method = match Method::from_code(self.method) {
            Some(m) => m,
            None => Method::Sphere,
        };
        PixelSetup {
            camera: Camera {
                eye: self.eye,
                right: self.right,
                up: self.up,
                forward: self.forward,
                scale: self.scale,
                projection,
            },
            bounds: [self.bounds_lo, self.bounds_hi],
            width: self.width,
            height: self.height,
            method,
            mode,
            params: Params {
                eps: self.eps,
                min_step: self.min_step,
                omega: self.omega,
                k: self.k,
                max_steps: self.max_steps,
            },
        }
    }
}

/// One pixel's result (`#[repr(C)]`, 9 words): the trace record and the
/// ray's span in the box.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct PixelOut {
    /// `1` when the ray meets the box (then `span` is set), else `0`.
    pub has_span: u32,
    /// The span `[t0, t1]` of the ray in the box.
    pub span: [f32; 2],
    /// Roots written to the pixel's hits (≤ `max_roots`).
    pub roots: u32,
    /// The [`Status`] code.
    pub status: u32,
    /// [`Trace::t_reached`](boundtrace_tracer::Trace::t_reached).
    pub t_reached: f32,
    /// [`RayStats::steps`](boundtrace_tracer::RayStats::steps).
    pub steps: u32,
    /// [`RayStats::field_evals`](boundtrace_tracer::RayStats::field_evals).
    pub field_evals: u32,
    /// [`RayStats::bound_evals`](boundtrace_tracer::RayStats::bound_evals).
    pub bound_evals: u32,
}

/// One root of a pixel with the surface normal there (`#[repr(C)]`, 5
/// words).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct HitOut {
    /// The ray parameter (the depth along the unit-speed camera ray).
    pub t: f32,
    /// The [`Side`](boundtrace_tracer::Side) code.
    pub side: u32,
    /// The unit normal ([`normal`]).
    pub normal: [f32; 3],
}

/// An unsupported pixel (bad constants or scene data): nothing traced.
const fn unsupported() -> PixelOut {
    PixelOut {
        has_span: 0,
        span: [0.0; 2],
        roots: 0,
        status: Status::Unsupported as u32,
        t_reached: 0.0,
        steps: 0,
        field_evals: 0,
        bound_evals: 0,
    }
}

/// Traces pixel `(x, y)` of the frame described by `c` over the scene
/// buffers (`words`: blobtree node words or blob-group ends; `floats`:
/// blobtree parameters; `blobs`: the blob scenes' blobs), with
/// `roots[base..base + c.max_roots]` as its root buffer, writing its roots
/// and normals to `hits[base..base + c.max_roots]` and returning the trace
/// record. A `roots` too short gives [`Status::Unsupported`]; hit indices
/// past the end of `hits` are not written.
///
/// Bad constants or scene data (unknown codes, a blobtree with an odd or
/// zero word count, bad group ends) give [`Status::Unsupported`] with
/// nothing traced. Blobtree data is not validated here (the shader cannot
/// build `BlobtreeRef::new`'s errors): the host validates it before
/// upload, and other invalid trees give NaN field values, never a read
/// out of bounds.
#[allow(clippy::too_many_arguments)]
pub fn render_pixel(
    c: &Constants,
    words: &[u32],
    floats: &[f32],
    blobs: &[PointBlob<f32>],
    x: u32,
    y: u32,
    roots: &mut [Root<f32>],
    hits: &mut [HitOut],
    base: usize,
) -> PixelOut {
    render_with::<_, AllKinds>(
        &mut AnyMethod,
        c,
        words,
        floats,
        blobs,
        x,
        y,
        roots,
        hits,
        base,
    )
}

/// [`render_pixel`] for [`Method::Sphere`] only (other methods give
/// [`Status::Unsupported`]): the shader's `trace_sphere` entry point.
///
/// It links the tracer's sphere tracing alone
/// ([`trace_sphere_in`]), not the method dispatch: a GPU driver that
/// inlines every call (lavapipe does) compiles this one, while the whole
/// tracer is orders of magnitude larger (BENCHMARKS.md "GPU").
#[allow(clippy::too_many_arguments)]
pub fn render_sphere_pixel(
    c: &Constants,
    words: &[u32],
    floats: &[f32],
    blobs: &[PointBlob<f32>],
    x: u32,
    y: u32,
    roots: &mut [Root<f32>],
    hits: &mut [HitOut],
    base: usize,
) -> PixelOut {
    if c.method != Method::Sphere as u32 {
        return unsupported();
    }
    render_with::<_, AllKinds>(
        &mut SphereOnly,
        c,
        words,
        floats,
        blobs,
        x,
        y,
        roots,
        hits,
        base,
    )
}

/// What a kernel does with the field of a pixel: the choice is a type (not
/// a value) so that a shader entry point's call graph holds only the code
/// it runs.
trait PixelKernel {
    /// Traces and shades pixel `(x, y)` over `field`.
    #[allow(clippy::too_many_arguments)]
    fn run<F: Field<f32>>(
        &mut self,
        field: &F,
        setup: &PixelSetup<f32>,
        max_roots: u32,
        x: u32,
        y: u32,
        roots: &mut [Root<f32>],
        hits: &mut [HitOut],
        base: usize,
    ) -> PixelOut;
}

/// Every method, through the tracer's dispatch ([`trace_pixel_in`]).
struct AnyMethod;

impl PixelKernel for AnyMethod {
    fn run<F: Field<f32>>(
        &mut self,
        field: &F,
        setup: &PixelSetup<f32>,
        max_roots: u32,
        x: u32,
        y: u32,
        roots: &mut [Root<f32>],
        hits: &mut [HitOut],
        base: usize,
    ) -> PixelOut {
        let window = [base, window_len(max_roots)];
        let px = trace_pixel_in(field, setup, x, y, roots, window);
        shade(field, &px, roots, hits, base);
        record(&px)
    }
}

/// Sphere tracing alone ([`trace_sphere_in`]).
struct SphereOnly;

impl PixelKernel for SphereOnly {
    fn run<F: Field<f32>>(
        &mut self,
        field: &F,
        setup: &PixelSetup<f32>,
        max_roots: u32,
        x: u32,
        y: u32,
        roots: &mut [Root<f32>],
        hits: &mut [HitOut],
        base: usize,
    ) -> PixelOut {
        let window = [base, window_len(max_roots)];
        let px = trace_pixel_with(setup, x, y, window[1], |ray, span| {
            trace_sphere_in(field, ray, span, setup.mode, &setup.params, roots, window)
        });
        shade(field, &px, roots, hits, base);
        record(&px)
    }
}

/// A pixel's resumable trace between two dispatches
/// ([`render_sphere_leg`], [`render_segment_leg`]): the tracer's loop state
/// the pixel's phase and its shading progress (`#[repr(C)]`, 19 words; the
/// host zero-fills the buffer, i.e. [`PHASE_FRESH`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct PixelLeg {
    /// Where the trace resumes ([`PHASE_TRACING`]).
    pub state: MarchState<f32>,
    /// [`PHASE_FRESH`], [`PHASE_TRACING`], [`PHASE_SHADING`] or
    /// [`PHASE_DONE`].
    pub phase: u32,
    /// [`PHASE_SHADING`]: the roots whose hits (with normals) are written;
    /// shading resumes at this root, so that a pixel with many roots
    /// shades them over several dispatches (one normal loops over every
    /// primitive three times, [`boundtrace_inclusion::gradient`]).
    pub shaded: u32,
}

/// [`PixelLeg::phase`]: not started.
pub const PHASE_FRESH: u32 = 0;
/// [`PixelLeg::phase`]: paused between two steps.
pub const PHASE_TRACING: u32 = 1;
/// [`PixelLeg::phase`]: traced, its record written; the hits' normals from
/// root [`PixelLeg::shaded`] on are still to be written.
pub const PHASE_SHADING: u32 = 2;
/// [`PixelLeg::phase`]: record and hits written.
pub const PHASE_DONE: u32 = 3;

/// The [`PixelOut::status`] of a pixel whose trace is paused (not a
/// [`Status`] code); its `steps` are those taken so far.
pub const STATUS_PAUSED: u32 = 4;

/// Runs a loop of `n` iterations (`n` read at run time, so no compiler can
/// count it) and says whether all of them ran.
///
/// lavapipe (llvmpipe) ends every loop of a shader invocation group once
/// the group has run 65,535 loop iterations in all (Mesa's
/// `LP_MAX_TGSI_LOOP_ITERATIONS`), silently: from then on each loop stops
/// after its first iteration. A loop of two iterations that ran once
/// shows that the limit was reached, and that the work since the last
/// such probe cannot be trusted. On other drivers it is always `true`.
pub fn loops_complete(n: u32) -> bool {
    let mut i = 0u32;
    while i < n {
        i += 1;
    }
    i == n
}

/// The tracer's step guard of the leg kernels: at most `until`
/// steps in all, and [`loops_complete`] after every step and every
/// iteration of a step's inner loops (so that a step whose bisection needs
/// more loop iterations than the limit ends over several legs:
/// [`MarchState::inner`]).
struct LimitProbe {
    loops: u32,
    until: u32,
}

impl LimitProbe {
    /// The probe of `loops` iterations for a leg of at most `leg_steps`
    /// steps (`0`: no limit) after the `done` steps of the earlier legs.
    fn for_leg(loops: u32, leg_steps: u32, done: u32) -> Self {
        // (No `saturating_add`: rust-gpu 0.11 lacks it.)
        let until = if leg_steps == 0 || leg_steps > u32::MAX - done {
            u32::MAX
        } else {
            done + leg_steps
        };
        Self { loops, until }
    }
}

impl StepGuard for LimitProbe {
    fn before_step(&mut self, steps: u32) -> bool {
        steps < self.until
    }
    fn after_step(&mut self) -> bool {
        loops_complete(self.loops)
    }
}

/// Which resumable trace a leg kernel runs: a type, so that an entry
/// point links one method's tracer.
trait LegTrace: Copy {
    /// The method traced.
    const METHOD: Method;
    /// One leg of the trace from `state` (the tracer's `trace_*_resume_in`).
    #[allow(clippy::too_many_arguments)]
    fn trace<F: Field<f32>>(
        field: &F,
        ray: &Ray<f32>,
        span: [f32; 2],
        mode: Mode,
        params: &Params<f32>,
        roots: &mut [Root<f32>],
        window: [usize; 2],
        state: &mut MarchState<f32>,
        cache: &TaylorCache<f32>,
        guard: &mut LimitProbe,
    ) -> Leg<f32>;
}

/// A [`LegTrace`] type: `$trace` traces `$method` in legs with the
/// tracer's `$resume` (`trace_*_resume_in`).
macro_rules! leg_trace {
    ($(#[$doc:meta])* $trace:ident, $method:expr, $resume:path) => {
        $(#[$doc])*
        #[derive(Clone, Copy)]
        struct $trace;

        impl LegTrace for $trace {
            const METHOD: Method = $method;
            fn trace<F: Field<f32>>(
                field: &F,
                ray: &Ray<f32>,
                span: [f32; 2],
                mode: Mode,
                params: &Params<f32>,
                roots: &mut [Root<f32>],
                window: [usize; 2],
                state: &mut MarchState<f32>,
                _cache: &TaylorCache<f32>,
                guard: &mut LimitProbe,
            ) -> Leg<f32> {
                $resume(field, ray, span, mode, params, roots, window, state, guard)
            }
        }
    };
}

leg_trace!(
    /// Sphere tracing ([`trace_sphere_resume_in`]).
    SphereTrace,
    Method::Sphere,
    trace_sphere_resume_in
);

leg_trace!(
    /// Segment tracing ([`trace_segment_resume_in`]).
    SegmentTrace,
    Method::Segment,
    trace_segment_resume_in
);

/// The leg kernels' [`PixelKernel`]: one leg of the pixel's trace with
/// `M`, or its shading.
///
/// It holds its leg and record by value: rust-gpu cannot keep pointers in a
/// struct ("not a logical pointer").
struct Legs<M> {
    _method: M,
    leg: PixelLeg,
    /// The Taylor parts of the mixed methods' bounds
    /// ([`render_linear_mixed_leg_in`]); unread by the other methods.
    cache: TaylorCache<f32>,
    out: PixelOut,
    loops: u32,
    leg_steps: u32,
    /// Whether [`PixelKernel::run`] was called (else the pixel is
    /// unsupported).
    ran: bool,
}

impl<M: LegTrace> PixelKernel for Legs<M> {
    fn run<F: Field<f32>>(
        &mut self,
        field: &F,
        setup: &PixelSetup<f32>,
        max_roots: u32,
        x: u32,
        y: u32,
        roots: &mut [Root<f32>],
        hits: &mut [HitOut],
        base: usize,
    ) -> PixelOut {
        self.ran = true;
        let window = [base, window_len(max_roots)];
        let mut leg = self.leg;
        // `trace_pixel_with` without its closure: rust-gpu cannot capture
        // pointers to locals in a closure ("not a logical pointer").
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
                    if leg.phase == PHASE_FRESH {
                        leg.state = MarchState::start(span, &setup.params);
                    }
                    let mut guard =
                        LimitProbe::for_leg(self.loops, self.leg_steps, leg.state.stats.steps);
                    let r = M::trace(
                        field,
                        &ray,
                        span,
                        setup.mode,
                        &setup.params,
                        roots,
                        window,
                        &mut leg.state,
                        &self.cache,
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
                let mut out = record(&px);
                out.status = STATUS_PAUSED;
                out.steps = leg.state.stats.steps;
                (self.leg, self.out) = (leg, out);
                return out;
            }
            // Traced: the record is final (the trace is not run again).
            self.out = record(&px);
            leg.phase = PHASE_SHADING;
            leg.shaded = 0;
        }
        // Shading, one root at a time from `leg.shaded`: a normal loops
        // over the primitives too, so a hit is written only when the
        // loop-limit probe after it passes, and the next leg resumes at
        // the first root not written.
        let out = self.out;
        let mut i = leg.shaded;
        while i < out.roots {
            let k = base + i as usize;
            let hit = hit_at(field, &ray, roots[k]);
            if !loops_complete(self.loops) {
                break;
            }
            if k < hits.len() {
                hits[k] = hit;
            }
            i += 1;
        }
        leg.shaded = i;
        if i >= out.roots {
            leg.phase = PHASE_DONE;
        }
        self.leg = leg;
        out
    }
}

/// Declares [`LegKernel`] as the `Fn` signature given once, with the
/// blanket impl that makes every function of that signature one.
macro_rules! leg_kernel {
    ($(#[$doc:meta])* Fn $args:tt) => {
        $(#[$doc])*
        pub trait LegKernel: Fn $args {}
        impl<F: Fn $args> LegKernel for F {}
    };
}

leg_kernel! {
    /// The signature of the leg kernels ([`render_sphere_leg`],
    /// [`render_sphere_leg_in`], [`render_segment_leg_in`],
    /// [`render_linear_taylor_leg_in`], [`render_quadratic_taylor_leg_in`]):
    /// `(constants, words, floats, blobs, x, y, roots, hits, base, leg, out)`.
    /// The shader's leg entry points take any `LegKernel`; every function of
    /// that signature is one.
    Fn(
        &Constants,
        &[u32],
        &[f32],
        &[PointBlob<f32>],
        u32,
        u32,
        &mut [Root<f32>],
        &mut [HitOut],
        usize,
        &mut PixelLeg,
        &mut PixelOut,
    )
}

/// One leg of pixel `(x, y)`'s sphere tracing ([`render_sphere_pixel`] in
/// steps that a driver's loop limit cannot corrupt): from `leg`
/// (zero-filled before the first dispatch), it traces until the trace ends
/// ([`Constants::leg_steps`] steps at most) or the loop-limit probe
/// ([`loops_complete`], [`Constants::guard_loops`]
/// iterations after every step and every iteration of a step's inner
/// loops) fails, undoing the step the limit cut short (its inner loop
/// resumes after the last iteration the probe accepted), and saves the
/// state in `leg`. A finished trace writes its record
/// to `out` once; its hits (with normals) are written when a leg shades
/// them without reaching the limit. The pixel is done at [`PHASE_DONE`];
/// until then `out.status` may be [`STATUS_PAUSED`].
///
/// A host dispatches the frame again until every pixel is done: the
/// result is the uninterrupted [`render_sphere_pixel`]'s, bit for bit
/// (the tracer's legs give the same trace, and a cut shading is redone).
/// A leg that cannot take one step nor shade makes no progress: the host
/// must detect it (a step that needs more loop iterations than the limit).
#[allow(clippy::too_many_arguments)]
pub fn render_sphere_leg(
    c: &Constants,
    words: &[u32],
    floats: &[f32],
    blobs: &[PointBlob<f32>],
    x: u32,
    y: u32,
    roots: &mut [Root<f32>],
    hits: &mut [HitOut],
    base: usize,
    leg: &mut PixelLeg,
    out: &mut PixelOut,
) {
    render_sphere_leg_in::<AllKinds>(c, words, floats, blobs, x, y, roots, hits, base, leg, out);
}

/// [`render_sphere_leg`] for the scene kinds `K` only (other kinds give
/// [`Status::Unsupported`] pixels): the shader's `trace_sphere`
/// ([`BlobKinds`]) and `trace_sphere_blobtree` ([`BlobtreeOnly`]) entry
/// points, so that neither holds the other's field code.
#[allow(clippy::too_many_arguments)]
pub fn render_sphere_leg_in<K: SceneKinds>(
    c: &Constants,
    words: &[u32],
    floats: &[f32],
    blobs: &[PointBlob<f32>],
    x: u32,
    y: u32,
    roots: &mut [Root<f32>],
    hits: &mut [HitOut],
    base: usize,
    leg: &mut PixelLeg,
    out: &mut PixelOut,
) {
    render_leg::<_, K>(
        SphereTrace,
        c,
        words,
        floats,
        blobs,
        x,
        y,
        roots,
        hits,
        base,
        leg,
        out,
    );
}

/// [`render_sphere_leg`] for [`Method::Segment`] (other methods give
/// [`Status::Unsupported`] pixels): segment tracing in legs
/// ([`trace_segment_resume_in`]: `λ` from the field's Taylor lines), the
/// same records as [`render_pixel`]'s, bit for bit, wherever the field has
/// Taylor lines (the blob scenes' compact kernels).
#[allow(clippy::too_many_arguments)]
pub fn render_segment_leg(
    c: &Constants,
    words: &[u32],
    floats: &[f32],
    blobs: &[PointBlob<f32>],
    x: u32,
    y: u32,
    roots: &mut [Root<f32>],
    hits: &mut [HitOut],
    base: usize,
    leg: &mut PixelLeg,
    out: &mut PixelOut,
) {
    render_segment_leg_in::<AllKinds>(c, words, floats, blobs, x, y, roots, hits, base, leg, out);
}

/// [`render_segment_leg`] for the scene kinds `K` only (other kinds give
/// [`Status::Unsupported`] pixels): the shader's `trace_segment_blobs`
/// ([`BlobsOnly`]) and `trace_segment_groups` ([`GroupsOnly`]) entry
/// points, one per module.
#[allow(clippy::too_many_arguments)]
pub fn render_segment_leg_in<K: SceneKinds>(
    c: &Constants,
    words: &[u32],
    floats: &[f32],
    blobs: &[PointBlob<f32>],
    x: u32,
    y: u32,
    roots: &mut [Root<f32>],
    hits: &mut [HitOut],
    base: usize,
    leg: &mut PixelLeg,
    out: &mut PixelOut,
) {
    render_leg::<_, K>(
        SegmentTrace,
        c,
        words,
        floats,
        blobs,
        x,
        y,
        roots,
        hits,
        base,
        leg,
        out,
    );
}

/// A single-method leg kernel: the [`LegTrace`] type `$trace` of `$method`
/// (one leg with the tracer's `$resume`) and the public kernel `$render`
/// (the leg kernels' signature, [`LegKernel`]), the same records as
/// [`render_pixel`]'s, bit for bit.
macro_rules! leg_method {
    ($(#[$doc:meta])* $render:ident, $trace:ident, $method:expr, $resume:path) => {
        leg_trace!($trace, $method, $resume);

        $(#[$doc])*
        #[allow(clippy::too_many_arguments)]
        pub fn $render<K: SceneKinds>(
            c: &Constants,
            words: &[u32],
            floats: &[f32],
            blobs: &[PointBlob<f32>],
            x: u32,
            y: u32,
            roots: &mut [Root<f32>],
            hits: &mut [HitOut],
            base: usize,
            leg: &mut PixelLeg,
            out: &mut PixelOut,
        ) {
            render_leg::<_, K>(
                $trace, c, words, floats, blobs, x, y, roots, hits, base, leg, out,
            );
        }
    };
}

leg_method!(
    /// [`render_segment_leg_in`] for [`Method::LinearTaylor`] (forward
    /// linear inclusions from Taylor bounds, in legs:
    /// [`trace_linear_taylor_resume_in`]): the same records as
    /// [`render_pixel`]'s, bit for bit. The shader's
    /// `trace_linear_taylor_blobs` and `trace_linear_taylor_groups` entry
    /// points, one per module.
    render_linear_taylor_leg_in,
    LinearTaylorTrace,
    Method::LinearTaylor,
    trace_linear_taylor_resume_in
);

leg_method!(
    /// [`render_segment_leg_in`] with the CPU's segment bound, the Taylor
    /// lines or else the bottom-up lines
    /// ([`trace_segment_lines_resume_in`]): the same records as
    /// [`render_pixel`]'s on every field, bit for bit. The shader's
    /// `trace_segment_hrbf` (an HRBF has no Taylor lines).
    render_segment_lines_leg_in,
    SegmentLinesTrace,
    Method::Segment,
    trace_segment_lines_resume_in
);

leg_method!(
    /// [`render_linear_taylor_leg_in`] for [`Method::QuadraticTaylor`]
    /// ([`trace_quadratic_taylor_resume_in`]; the shader's
    /// `trace_quadratic_taylor_blobs` and `trace_quadratic_taylor_groups`).
    render_quadratic_taylor_leg_in,
    QuadraticTaylorTrace,
    Method::QuadraticTaylor,
    trace_quadratic_taylor_resume_in
);

leg_method!(
    /// [`render_linear_taylor_leg_in`] for [`Method::LinearBottomUp`]
    /// (forward linear bottom-up bounds: [`trace_linear_bottom_up_resume_in`];
    /// the shader's `trace_linear_bottom_up_blobs` and
    /// `trace_linear_bottom_up_groups`).
    render_linear_bottom_up_leg_in,
    LinearBottomUpTrace,
    Method::LinearBottomUp,
    trace_linear_bottom_up_resume_in
);

leg_method!(
    /// [`render_linear_taylor_leg_in`] for [`Method::QuadraticBottomUp`]
    /// ([`trace_quadratic_bottom_up_resume_in`]; the shader's
    /// `trace_quadratic_bottom_up_blobs` and `trace_quadratic_bottom_up_groups`).
    render_quadratic_bottom_up_leg_in,
    QuadraticBottomUpTrace,
    Method::QuadraticBottomUp,
    trace_quadratic_bottom_up_resume_in
);

/// A pixel's resumable trace with a mixed method ([`render_linear_mixed_leg_in`],
/// [`fill_linear_taylor_in`]): its [`PixelLeg`] and the Taylor part of its
/// next step's bound (`#[repr(C)]`, 36 words; zero-filled by the host:
/// [`PHASE_FRESH`], an empty cache).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct MixedLeg {
    /// The leg, as the other leg kernels keep it.
    pub leg: PixelLeg,
    /// The Taylor bound on the next step's window, filled by
    /// [`fill_linear_taylor_in`] (or [`fill_quadratic_taylor_in`]).
    pub cache: TaylorCache<f32>,
}

/// A mixed method's kernels: the [`LegTrace`] type `$trace` of `$method`
/// (one leg with the tracer's cached `$resume`, the Taylor part read from
/// the leg's cache), its leg kernel `$render` and its Taylor kernel
/// `$fill` (the leg kernels' signatures, with a [`MixedLeg`]).
macro_rules! mixed_method {
    (
        $(#[$tdoc:meta])* $trace:ident, $method:expr, $resume:path;
        $(#[$rdoc:meta])* $render:ident;
        $(#[$fdoc:meta])* $fill:ident
    ) => {
        $(#[$tdoc])*
        #[derive(Clone, Copy)]
        struct $trace;

        impl LegTrace for $trace {
            const METHOD: Method = $method;
            fn trace<F: Field<f32>>(
                field: &F,
                ray: &Ray<f32>,
                span: [f32; 2],
                mode: Mode,
                params: &Params<f32>,
                roots: &mut [Root<f32>],
                window: [usize; 2],
                state: &mut MarchState<f32>,
                cache: &TaylorCache<f32>,
                guard: &mut LimitProbe,
            ) -> Leg<f32> {
                $resume(field, ray, span, mode, params, roots, window, state, cache, guard)
            }
        }

        $(#[$rdoc])*
        #[allow(clippy::too_many_arguments)]
        pub fn $render<K: SceneKinds>(
            c: &Constants,
            words: &[u32],
            floats: &[f32],
            blobs: &[PointBlob<f32>],
            x: u32,
            y: u32,
            roots: &mut [Root<f32>],
            hits: &mut [HitOut],
            base: usize,
            leg: &mut MixedLeg,
            out: &mut PixelOut,
        ) {
            let cache = leg.cache;
            render_leg_cached::<_, K>(
                $trace, c, words, floats, blobs, x, y, roots, hits, base, &mut leg.leg, out,
                cache,
            );
        }

        $(#[$fdoc])*
        #[allow(clippy::too_many_arguments)]
        pub fn $fill<K: SceneKinds>(
            c: &Constants,
            words: &[u32],
            floats: &[f32],
            blobs: &[PointBlob<f32>],
            x: u32,
            y: u32,
            roots: &mut [Root<f32>],
            hits: &mut [HitOut],
            base: usize,
            leg: &mut MixedLeg,
        ) {
            fill_taylor_in::<K>($method, c, words, floats, blobs, x, y, roots, hits, base, leg);
        }
    };
}

mixed_method!(
    /// `linear-mixed` in legs with the Taylor part filled apart
    /// ([`trace_linear_mixed_cached_resume_in`]).
    LinearMixedTrace,
    Method::LinearMixed,
    trace_linear_mixed_cached_resume_in;
    /// One leg of pixel `(x, y)` with [`Method::LinearMixed`] (forward linear
    /// mixed bounds: the bottom-up and Taylor bounds, the tighter side of
    /// each), the Taylor part of each step's bound read from `leg.cache`: a
    /// leg pauses before a step whose window the cache does not hold, and
    /// [`fill_linear_taylor_in`], dispatched after it, fills it (the tracer's
    /// [`trace_linear_mixed_cached_resume_in`]). So the shader's
    /// `trace_linear_mixed_blobs` (`_groups`) and `taylor_linear_mixed_blobs`
    /// (`_groups`) are two pipelines holding one bound each, where one
    /// pipeline with both needed ≈ 20 GB on lavapipe (BENCHMARKS.md "GPU",
    /// session 28). Alternating the two until the pixel is done gives
    /// [`render_pixel`]'s records bit for bit, one step per leg at most.
    render_linear_mixed_leg_in;
    /// The other half of [`render_linear_mixed_leg_in`]: for a pixel paused
    /// in its trace ([`PHASE_TRACING`]) with [`Method::LinearMixed`], the
    /// field's linear Taylor bound on its next step's window, into
    /// `leg.cache` ([`fill_taylor_cache`]), unless the cache holds it. Kept
    /// only when the loop-limit probe after it passes (else the next dispatch
    /// tries again; a bound that never fits in the limit leaves the pixel
    /// without progress, which the host reports). The shader's
    /// `taylor_linear_mixed_blobs` and `taylor_linear_mixed_groups`.
    fill_linear_taylor_in
);

mixed_method!(
    /// `quadratic-mixed` in legs with the Taylor part filled apart
    /// ([`trace_quadratic_mixed_cached_resume_in`]).
    QuadraticMixedTrace,
    Method::QuadraticMixed,
    trace_quadratic_mixed_cached_resume_in;
    /// [`render_linear_mixed_leg_in`] for [`Method::QuadraticMixed`]
    /// ([`trace_quadratic_mixed_cached_resume_in`]; the shader's
    /// `trace_quadratic_mixed_blobs` and `trace_quadratic_mixed_groups`, with
    /// [`fill_quadratic_taylor_in`] after each leg).
    render_quadratic_mixed_leg_in;
    /// [`fill_linear_taylor_in`] for [`Method::QuadraticMixed`] (the quadratic
    /// Taylor bound; the shader's `taylor_quadratic_mixed_blobs` and
    /// `taylor_quadratic_mixed_groups`).
    fill_quadratic_taylor_in
);

/// The body of [`fill_linear_taylor_in`] and [`fill_quadratic_taylor_in`].
#[allow(clippy::too_many_arguments)]
fn fill_taylor_in<K: SceneKinds>(
    method: Method,
    c: &Constants,
    words: &[u32],
    floats: &[f32],
    blobs: &[PointBlob<f32>],
    x: u32,
    y: u32,
    roots: &mut [Root<f32>],
    hits: &mut [HitOut],
    base: usize,
    leg: &mut MixedLeg,
) {
    if leg.leg.phase != PHASE_TRACING || c.method != method as u32 {
        return;
    }
    let mut k = TaylorFill {
        state: leg.leg.state,
        cache: leg.cache,
        quadratic: method == Method::QuadraticMixed,
        loops: c.guard_loops,
    };
    let _ = render_with::<_, K>(&mut k, c, words, floats, blobs, x, y, roots, hits, base);
    leg.cache = k.cache;
}

/// [`fill_taylor_in`]'s [`PixelKernel`] (its record is not used).
struct TaylorFill {
    state: MarchState<f32>,
    cache: TaylorCache<f32>,
    quadratic: bool,
    loops: u32,
}

impl PixelKernel for TaylorFill {
    fn run<F: Field<f32>>(
        &mut self,
        field: &F,
        setup: &PixelSetup<f32>,
        _max_roots: u32,
        x: u32,
        y: u32,
        _roots: &mut [Root<f32>],
        _hits: &mut [HitOut],
        _base: usize,
    ) -> PixelOut {
        // The ray and span as `Legs::run` computes them.
        let ray = setup.camera.ray(x, y, setup.width, setup.height);
        if let Some(span) = ray_box_span(&ray, &setup.bounds) {
            let mut cache = self.cache;
            fill_taylor_cache(
                field,
                &ray,
                span,
                &setup.params,
                &self.state,
                self.quadratic,
                &mut cache,
            );
            if loops_complete(self.loops) {
                self.cache = cache;
            }
        }
        unsupported()
    }
}

/// The leg kernels with `M`'s tracer.
#[allow(clippy::too_many_arguments)]
fn render_leg<M: LegTrace, K: SceneKinds>(
    method: M,
    c: &Constants,
    words: &[u32],
    floats: &[f32],
    blobs: &[PointBlob<f32>],
    x: u32,
    y: u32,
    roots: &mut [Root<f32>],
    hits: &mut [HitOut],
    base: usize,
    leg: &mut PixelLeg,
    out: &mut PixelOut,
) {
    render_leg_cached::<_, K>(
        method,
        c,
        words,
        floats,
        blobs,
        x,
        y,
        roots,
        hits,
        base,
        leg,
        out,
        TaylorCache::EMPTY,
    );
}

/// [`render_leg`] with the mixed methods' Taylor cache.
#[allow(clippy::too_many_arguments)]
fn render_leg_cached<M: LegTrace, K: SceneKinds>(
    method: M,
    c: &Constants,
    words: &[u32],
    floats: &[f32],
    blobs: &[PointBlob<f32>],
    x: u32,
    y: u32,
    roots: &mut [Root<f32>],
    hits: &mut [HitOut],
    base: usize,
    leg: &mut PixelLeg,
    out: &mut PixelOut,
    cache: TaylorCache<f32>,
) {
    if leg.phase >= PHASE_DONE {
        return;
    }
    if c.method != M::METHOD as u32 {
        *out = unsupported();
        leg.phase = PHASE_DONE;
        return;
    }
    let mut k = Legs {
        _method: method,
        leg: *leg,
        cache,
        out: *out,
        loops: c.guard_loops,
        leg_steps: c.leg_steps,
        ran: false,
    };
    let o = render_with::<_, K>(&mut k, c, words, floats, blobs, x, y, roots, hits, base);
    if !k.ran {
        k.out = o;
        k.leg.phase = PHASE_DONE;
    }
    (*leg, *out) = (k.leg, k.out);
}

/// The length of a pixel's root window.
fn window_len(max_roots: u32) -> usize {
    if max_roots == 0 {
        1
    } else {
        max_roots as usize
    }
}

/// [`render_pixel`] with the kernel `p`.
#[allow(clippy::too_many_arguments)]
fn render_with<P: PixelKernel, K: SceneKinds>(
    p: &mut P,
    c: &Constants,
    words: &[u32],
    floats: &[f32],
    blobs: &[PointBlob<f32>],
    x: u32,
    y: u32,
    roots: &mut [Root<f32>],
    hits: &mut [HitOut],
    base: usize,
) -> PixelOut {
    if !c.codes_valid() {
        return unsupported();
    }
    let setup = c.decode();
    match SceneKind::from_code(c.scene) {
        // The host validates the tree (`BlobtreeRef::new`, whose error
        // values the shader cannot build); here only the word count is
        // checked, and other invalid data gives NaN values, never a read
        // out of bounds.
        Some(SceneKind::Blobtree)
            if K::BLOBTREE && c.groups == 0 && (words.is_empty() || words.len() % 2 != 0) =>
        {
            unsupported()
        }
        Some(SceneKind::Blobtree) if K::BLOBTREE => {
            // One field type for the whole tree and the tiles' programs, so
            // that the module holds the tracer once. Gyroids and blobs left
            // out: their transcendental functions would double the shader
            // (the host checks the tree has none).
            let field = if c.groups > 0 {
                // Tiled (`Constants::groups` tiles per row): the program of
                // the pixel's 8 × 8 tile, with its own Lipschitz bound.
                let tile = (y / WORKGROUP)
                    .wrapping_mul(c.groups)
                    .wrapping_add(x / WORKGROUP);
                BlobtreeWindow::<AlgebraicPrimitives>::tile(words, floats, tile as usize)
            } else {
                BlobtreeWindow::whole(BlobtreeRef::new_unchecked(words, floats), c.lipschitz)
            };
            p.run(&field, &setup, c.max_roots, x, y, roots, hits, base)
        }
        Some(SceneKind::Blobtree) => unsupported(),
        Some(SceneKind::Blobs) if K::BLOBS && c.iso.is_finite() => {
            let field = GlobalLipschitz {
                field: Blobs::new_unchecked(c.iso, blobs),
                lipschitz: c.lipschitz,
            };
            p.run(&field, &setup, c.max_roots, x, y, roots, hits, base)
        }
        Some(SceneKind::Blobs) => unsupported(),
        Some(SceneKind::BlobGroups) if K::GROUPS => {
            let field = FlatBlobGroups::from_parts(c.iso, words, c.groups as usize, blobs);
            if field.is_valid() {
                p.run(&field, &setup, c.max_roots, x, y, roots, hits, base)
            } else {
                unsupported()
            }
        }
        Some(SceneKind::BlobGroups) => unsupported(),
        Some(SceneKind::Hrbf) if K::HRBF => {
            // `groups` centers, then the polynomial (`SceneKind::Hrbf`);
            // checked without `Option`s (the shader never moves a
            // niche-encoded value) and without overflow.
            let n = c.groups as usize;
            if n <= floats.len() / CENTER_WORDS && floats.len() - n * CENTER_WORDS >= 4 {
                let at = n * CENTER_WORDS;
                let poly = [floats[at], floats[at + 1], floats[at + 2], floats[at + 3]];
                let centers = FlatCenters::new_unchecked(floats, n);
                let field = Hrbf::from_parts_unchecked(centers, poly);
                p.run(&field, &setup, c.max_roots, x, y, roots, hits, base)
            } else {
                unsupported()
            }
        }
        Some(SceneKind::Hrbf) => unsupported(),
        Some(SceneKind::Homothetic) if K::HOMOTHETIC => {
            // The kernel's code, then (in `floats`) `groups` segments and
            // the parameters (`SceneKind::Homothetic`), checked without
            // `Option`s and without overflow.
            let n = c.groups as usize;
            if words.len() >= 2
                && (words[0] == KERNEL_COMPACT || words[0] == KERNEL_CAUCHY)
                && n <= floats.len() / SEGMENT_WORDS
                && floats.len() - n * SEGMENT_WORDS >= PARAMETER_WORDS
            {
                let at = n * SEGMENT_WORDS;
                let mut params = [0.0f32; PARAMETER_WORDS];
                let mut k = 0;
                while k < PARAMETER_WORDS {
                    params[k] = floats[at + k];
                    k += 1;
                }
                let segments = FlatSegments::new_unchecked(floats, n);
                let field = GlobalLipschitz {
                    field: HomotheticSkeleton::from_parameter_words_unchecked(
                        segments,
                        [words[0], words[1]],
                        params,
                    ),
                    lipschitz: c.lipschitz,
                };
                p.run(&field, &setup, c.max_roots, x, y, roots, hits, base)
            } else {
                unsupported()
            }
        }
        Some(SceneKind::Homothetic) => unsupported(),
        // traced by `render_scalis_leg` alone
        Some(SceneKind::Scalis) => unsupported(),
        None => unsupported(),
    }
}

/// A field whose global Lipschitz bound is `lipschitz` when that is `> 0`
/// and the field's own otherwise ([`Constants::lipschitz`]); everything
/// else is the field's. With a bound it traces as the CPU's
/// `scenes::WithLipschitz` does, without one as the field alone: one type
/// for both, so that a module holds the blob tracing code once.
struct GlobalLipschitz<F> {
    field: F,
    lipschitz: f32,
}

impl<F: Field<f32>> Field<f32> for GlobalLipschitz<F> {
    #[inline]
    fn eval<N: boundtrace_inclusion::FieldNum<f32>>(&self, p: [N; 3]) -> N {
        self.field.eval(p)
    }
    fn lipschitz(&self) -> Option<f32> {
        if self.lipschitz > 0.0 {
            Some(self.lipschitz)
        } else {
            self.field.lipschitz()
        }
    }
    fn taylor_linear(
        &self,
        ray: &Ray<f32>,
        t0: f32,
        t1: f32,
    ) -> Option<boundtrace_inclusion::ForwardLinear<f32>> {
        self.field.taylor_linear(ray, t0, t1)
    }
    fn taylor_quadratic(
        &self,
        ray: &Ray<f32>,
        t0: f32,
        t1: f32,
    ) -> Option<boundtrace_inclusion::ForwardQuadratic<f32>> {
        self.field.taylor_quadratic(ray, t0, t1)
    }
}

/// Writes the hits of a traced pixel: its roots (in `roots[base..]`) with
/// the normals there.
fn shade<F: Field<f32>>(
    field: &F,
    px: &PixelTrace<f32>,
    roots: &[Root<f32>],
    hits: &mut [HitOut],
    base: usize,
) {
    // The root buffer is this pixel's window of a storage buffer: rust-gpu
    // can neither sub-slice a mutable storage buffer nor turn a local array
    // into a slice.
    let mut i = 0usize;
    while i < px.trace.roots as usize {
        let hit = hit_at(field, &px.ray, roots[base + i]);
        if base + i < hits.len() {
            hits[base + i] = hit;
        }
        i += 1;
    }
}

/// The hit of `root` on `ray`: its depth, side and the normal there.
fn hit_at<F: Field<f32>>(field: &F, ray: &Ray<f32>, root: Root<f32>) -> HitOut {
    let o = ray.origin;
    let d = ray.dir;
    let p = [
        o[0] + root.t * d[0],
        o[1] + root.t * d[1],
        o[2] + root.t * d[2],
    ];
    HitOut {
        t: root.t,
        side: root.side as u32,
        normal: normal(field, p),
    }
}

/// A traced pixel's record.
fn record(px: &PixelTrace<f32>) -> PixelOut {
    let (has_span, span) = match px.span {
        Some(s) => (1, s),
        None => (0, [0.0; 2]),
    };
    PixelOut {
        has_span,
        span,
        roots: px.trace.roots,
        status: px.trace.status as u32,
        t_reached: px.trace.t_reached,
        steps: px.trace.stats.steps,
        field_evals: px.trace.stats.field_evals,
        bound_evals: px.trace.stats.bound_evals,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constants_round_trip_through_setup() {
        let bounds = [[-1.0f32; 3], [1.0; 3]];
        let setup = PixelSetup {
            camera: Camera::framing(bounds, [0.3, -0.2, -1.0], 35.0, 1.5).unwrap(),
            bounds,
            width: 12,
            height: 8,
            method: Method::QuadraticMixed,
            mode: Mode::Transparent,
            params: Params::new().with_k(3.0).unwrap(),
        };
        let c = Constants::new(&setup, SceneKind::BlobGroups, 0.5, 99, 4);
        assert_eq!(c.setup(), Some(setup));
        assert_eq!(c.max_roots, MAX_GPU_ROOTS);
        let w = c.to_words();
        assert_eq!(core::mem::size_of::<Constants>(), 37 * 4);
        assert_eq!(w.len(), 37);
        assert_eq!(
            w[36],
            0.0f32.to_bits(),
            "no Lipschitz bound unless the host sets one"
        );
        assert_eq!(core::mem::size_of::<PixelLeg>(), 19 * 4);
        assert_eq!(w[34], GUARD_LOOPS);
        assert_eq!(w[28], Method::QuadraticMixed as u32);
        assert_eq!(f32::from_bits(w[32]), 0.5);
        let bad = Constants { method: 77, ..c };
        assert_eq!(bad.setup(), None);
        let mut hits = [HitOut::default(); 1];
        let mut roots = [Root {
            t: 0.0,
            side: Side::Touch,
        }; 1];
        let out = render_pixel(&bad, &[], &[], &[], 0, 0, &mut roots, &mut hits, 0);
        assert_eq!(out.status, Status::Unsupported as u32);
    }

    /// Two overlapping blobs and their box.
    fn two_blobs() -> ([PointBlob<f32>; 2], [[f32; 3]; 2]) {
        let k = boundtrace_fields::Kernel::compact(6, 0.9f32).unwrap();
        let blobs = [
            PointBlob::new([0.0, 0.0, 0.0], 1.0, k).unwrap(),
            PointBlob::new([0.3, 0.1, 0.0], 1.0, k).unwrap(),
        ];
        (blobs, [[-0.8f32; 3], [0.8; 3]])
    }

    /// The methods and modes the sphere-kernel tests run (segment: refused).
    const CASES: [(Method, Mode); 3] = [
        (Method::Sphere, Mode::Opaque),
        (Method::Sphere, Mode::Transparent),
        (Method::Segment, Mode::Opaque),
    ];

    /// A leg kernel, as the tests pass them around.
    type LegFn = &'static dyn LegKernel;

    /// Runs leg kernel `f` on pixel `(x, y)` of the scene data `(words,
    /// floats, blobs)` in one leg from a fresh state (the CPU never cuts a
    /// loop short), asserts that the pixel is done, and returns its output
    /// and its 4 hit slots.
    fn one_leg(
        f: LegFn,
        c: &Constants,
        (words, floats, blobs): (&[u32], &[f32], &[PointBlob<f32>]),
        x: u32,
        y: u32,
    ) -> (PixelOut, [HitOut; 4]) {
        let r = Root {
            t: 0.0,
            side: Side::Touch,
        };
        let (mut rs, mut hs) = ([r; 4], [HitOut::default(); 4]);
        let (mut leg, mut out) = (PixelLeg::default(), PixelOut::default());
        f(
            c, words, floats, blobs, x, y, &mut rs, &mut hs, 0, &mut leg, &mut out,
        );
        assert_eq!(leg.phase, PHASE_DONE, "({x}, {y})");
        (out, hs)
    }

    /// A 6 × 6 frame of `bounds` for `method` and `mode`.
    fn six_by_six(bounds: [[f32; 3]; 2], method: Method, mode: Mode) -> PixelSetup<f32> {
        PixelSetup {
            camera: Camera::framing(bounds, [0.2, -0.3, -1.0], 40.0, 1.0).unwrap(),
            bounds,
            width: 6,
            height: 6,
            method,
            mode,
            params: Params::new(),
        }
    }

    #[test]
    fn sphere_kernel_matches_the_general_one() {
        let (blobs, bounds) = two_blobs();
        for (method, mode) in CASES {
            let setup = six_by_six(bounds, method, mode);
            let c = Constants::new(&setup, SceneKind::Blobs, 0.5, 4, 0);
            let mut hit_pixels = 0;
            for y in 0..6 {
                for x in 0..6 {
                    let fresh = || {
                        let r = Root {
                            t: 0.0,
                            side: Side::Touch,
                        };
                        ([r; 4], [HitOut::default(); 4])
                    };
                    let ((mut ra, mut ha), (mut rb, mut hb)) = (fresh(), fresh());
                    let a = render_pixel(&c, &[], &[], &blobs, x, y, &mut ra, &mut ha, 0);
                    let b = render_sphere_pixel(&c, &[], &[], &blobs, x, y, &mut rb, &mut hb, 0);
                    if method == Method::Sphere {
                        assert_eq!((a, ha), (b, hb));
                        hit_pixels += usize::from(a.roots > 0);
                    } else {
                        assert_eq!(b.status, Status::Unsupported as u32);
                        assert_eq!(b.roots, 0);
                    }
                }
            }
            if method == Method::Sphere {
                assert!(hit_pixels > 4, "{hit_pixels}");
            }
        }
    }

    /// [`Constants::lipschitz`]: sphere tracing of the blobs with a global
    /// bound traces as the CPU's `WithLipschitz` field (every pixel, both
    /// modes), and with `0` as the blobs alone; the two differ.
    #[test]
    fn a_global_lipschitz_bound_traces_as_on_the_cpu() {
        use boundtrace_fields::Blobs;
        use boundtrace_tracer::scenes::WithLipschitz;
        let (blobs, bounds) = two_blobs();
        let own = Blobs::new_unchecked(0.5, &blobs[..]).lipschitz().unwrap();
        // a valid, looser bound: more sphere-tracing steps
        let loose = 3.0 * own;
        let mut more_steps = 0;
        for mode in [Mode::Opaque, Mode::Transparent] {
            let setup = six_by_six(bounds, Method::Sphere, mode);
            let plain = Constants::new(&setup, SceneKind::Blobs, 0.5, 4, 0);
            let bound = Constants {
                lipschitz: loose,
                ..plain
            };
            let cpu_field = WithLipschitz::new(Blobs::new_unchecked(0.5, &blobs[..]), loose);
            for y in 0..6 {
                for x in 0..6 {
                    let r = Root {
                        t: 0.0,
                        side: Side::Touch,
                    };
                    let (mut ra, mut ha) = ([r; 4], [HitOut::default(); 4]);
                    let (mut rb, mut hb) = ([r; 4], [HitOut::default(); 4]);
                    let a =
                        render_sphere_pixel(&bound, &[], &[], &blobs, x, y, &mut ra, &mut ha, 0);
                    let b =
                        render_sphere_pixel(&plain, &[], &[], &blobs, x, y, &mut rb, &mut hb, 0);
                    let mut rc = [r; 4];
                    let cpu = trace_pixel_in(&cpu_field, &setup, x, y, &mut rc, [0, 4]);
                    assert_eq!(a.steps, cpu.trace.stats.steps, "({x}, {y}) {mode:?}");
                    assert_eq!(a.roots, cpu.trace.roots);
                    assert_eq!(a.status, cpu.trace.status as u32);
                    for k in 0..a.roots as usize {
                        assert_eq!(ha[k].t.to_bits(), rc[k].t.to_bits());
                    }
                    assert!(
                        a.steps >= b.steps,
                        "({x}, {y}): a looser bound, fewer steps"
                    );
                    more_steps += usize::from(a.steps > b.steps);
                }
            }
        }
        assert!(more_steps > 10, "{more_steps}");
    }

    #[test]
    fn legs_match_one_pass() {
        use boundtrace_tracer::march::StepGuard;
        use boundtrace_tracer::trace_resume_in;
        /// Allows `n − 1` steps per leg (`Steps(n)`).
        struct Steps(u32);
        impl StepGuard for Steps {
            fn before_step(&mut self, _steps: u32) -> bool {
                self.0 = self.0.saturating_sub(1);
                self.0 > 0
            }
            fn after_step(&mut self) -> bool {
                true
            }
        }
        let (blobs, bounds) = two_blobs();
        let kernels: [(Method, LegFn); 4] = [
            (Method::Sphere, &render_sphere_leg),
            (Method::Segment, &render_segment_leg),
            (
                Method::LinearTaylor,
                &render_linear_taylor_leg_in::<AllKinds>,
            ),
            (
                Method::QuadraticTaylor,
                &render_quadratic_taylor_leg_in::<AllKinds>,
            ),
        ];
        let mut resumed = 0;
        let mut shaded_from_one = 0;
        // Hits of each kernel's own method.
        let mut method_hits = [0usize; 4];
        for ((method, mode), (kernel, render_leg)) in kernels
            .iter()
            .flat_map(|&(m, _)| [(m, Mode::Opaque), (m, Mode::Transparent)])
            .flat_map(|case| kernels.map(|k| (case, k)))
        {
            let setup = six_by_six(bounds, method, mode);
            let c = Constants::new(&setup, SceneKind::Blobs, 0.5, 4, 0);
            assert_eq!(c.guard_loops, GUARD_LOOPS);
            let field = Blobs::new_unchecked(0.5, &blobs[..]);
            for y in 0..6 {
                for x in 0..6 {
                    let r = Root {
                        t: 0.0,
                        side: Side::Touch,
                    };
                    let (mut ra, mut ha) = ([r; 4], [HitOut::default(); 4]);
                    let a = if method == kernel {
                        render_pixel(&c, &[], &[], &blobs, x, y, &mut ra, &mut ha, 0)
                    } else {
                        unsupported()
                    };
                    if method == kernel {
                        let i = kernels.iter().position(|&(m, _)| m == method).unwrap();
                        method_hits[i] += usize::from(a.roots > 0);
                    }
                    // In one leg (the CPU never cuts a loop short).
                    let (mut rb, mut hb) = ([r; 4], [HitOut::default(); 4]);
                    let (mut leg, mut out) = (PixelLeg::default(), PixelOut::default());
                    render_leg(
                        &c,
                        &[],
                        &[],
                        &blobs,
                        x,
                        y,
                        &mut rb,
                        &mut hb,
                        0,
                        &mut leg,
                        &mut out,
                    );
                    assert_eq!(leg.phase, PHASE_DONE);
                    assert_eq!((out, hb), (a, ha));
                    // In legs of at most 3 steps.
                    let c3 = Constants { leg_steps: 3, ..c };
                    let (mut rl, mut hl) = ([r; 4], [HitOut::default(); 4]);
                    let (mut legl, mut outl) = (PixelLeg::default(), PixelOut::default());
                    let mut n = 0;
                    while legl.phase != PHASE_DONE {
                        n += 1;
                        assert!(n < 1000);
                        render_leg(
                            &c3,
                            &[],
                            &[],
                            &blobs,
                            x,
                            y,
                            &mut rl,
                            &mut hl,
                            0,
                            &mut legl,
                            &mut outl,
                        );
                        if legl.phase != PHASE_DONE {
                            assert_eq!(outl.status, STATUS_PAUSED);
                        }
                    }
                    assert_eq!((outl, hl), (a, ha));
                    if method == kernel {
                        assert_eq!(n, a.steps.max(1).div_ceil(3), "{x} {y}");
                    }
                    // Done pixels are left alone.
                    let before = (leg, out, hb);
                    render_leg(
                        &c,
                        &[],
                        &[],
                        &blobs,
                        x,
                        y,
                        &mut rb,
                        &mut hb,
                        0,
                        &mut leg,
                        &mut out,
                    );
                    assert_eq!((leg, out, hb), before);
                    assert_eq!(leg.shaded, a.roots);
                    // A cut shading is redone from the first root not
                    // written (`from`): the hits before it are left alone.
                    for from in [0, 1] {
                        if from > 0 && a.roots <= from {
                            continue;
                        }
                        let mut leg2 = PixelLeg {
                            phase: PHASE_SHADING,
                            shaded: from,
                            ..leg
                        };
                        let mut hb2 = [HitOut::default(); 4];
                        render_leg(
                            &c,
                            &[],
                            &[],
                            &blobs,
                            x,
                            y,
                            &mut rb,
                            &mut hb2,
                            0,
                            &mut leg2,
                            &mut out,
                        );
                        assert_eq!((leg2.phase, leg2.shaded, out), (PHASE_DONE, a.roots, a));
                        let k = from as usize;
                        assert!(hb2[..k].iter().all(|h| *h == HitOut::default()));
                        assert_eq!(hb2[k..], ha[k..]);
                        shaded_from_one += usize::from(from == 1);
                    }
                    if method != kernel {
                        assert_eq!(out.status, Status::Unsupported as u32);
                        continue;
                    }
                    // Paused after 2 steps by the tracer, resumed by the kernel.
                    let (mut rc, mut hc) = ([r; 4], [HitOut::default(); 4]);
                    let mut leg3 = PixelLeg::default();
                    let px = trace_pixel_with(&setup, x, y, 4, |ray, span| {
                        leg3.state = MarchState::start(span, &setup.params);
                        let l = trace_resume_in(
                            &field,
                            ray,
                            span,
                            method,
                            mode,
                            &setup.params,
                            &mut rc,
                            [0, 4],
                            &mut leg3.state,
                            &mut Steps(3),
                        );
                        leg3.phase = if l.paused { PHASE_TRACING } else { PHASE_FRESH };
                        l.trace
                    });
                    if leg3.phase != PHASE_TRACING {
                        continue;
                    }
                    assert!(px.span.is_some());
                    resumed += 1;
                    let mut out3 = PixelOut::default();
                    render_leg(
                        &c,
                        &[],
                        &[],
                        &blobs,
                        x,
                        y,
                        &mut rc,
                        &mut hc,
                        0,
                        &mut leg3,
                        &mut out3,
                    );
                    assert_eq!((leg3.phase, out3, hc), (PHASE_DONE, a, ha));
                }
            }
        }
        assert!(resumed > 20, "{resumed}");
        assert!(shaded_from_one > 8, "{shaded_from_one}");
        assert!(method_hits.iter().all(|&n| n > 8), "{method_hits:?}");
    }

    /// A mixed method's leg kernel (`render_*_mixed_leg_in`).
    type MixedFn = fn(
        &Constants,
        &[u32],
        &[f32],
        &[PointBlob<f32>],
        u32,
        u32,
        &mut [Root<f32>],
        &mut [HitOut],
        usize,
        &mut MixedLeg,
        &mut PixelOut,
    );

    /// A mixed method's Taylor fill (`fill_*_taylor_in`).
    type FillFn = fn(
        &Constants,
        &[u32],
        &[f32],
        &[PointBlob<f32>],
        u32,
        u32,
        &mut [Root<f32>],
        &mut [HitOut],
        usize,
        &mut MixedLeg,
    );

    /// Pixel `(x, y)` of the scene data `data` by the leg kernel `render`
    /// alternated with the Taylor fill `fill` (as the host dispatches the
    /// two pipelines) from a fresh leg until it is done, asserting one step
    /// per leg at most: its record, its 4 hit slots and the legs run.
    fn mixed_until_done(
        render: MixedFn,
        fill: FillFn,
        c: &Constants,
        (words, floats, blobs): (&[u32], &[f32], &[PointBlob<f32>]),
        x: u32,
        y: u32,
    ) -> (PixelOut, [HitOut; 4], u32) {
        let mut rb = [Root {
            t: 0.0,
            side: Side::Touch,
        }; 4];
        let mut hb = [HitOut::default(); 4];
        let (mut leg, mut out) = (MixedLeg::default(), PixelOut::default());
        let mut rounds = 0;
        loop {
            rounds += 1;
            assert!(rounds < 10_000, "no progress");
            let before = leg.leg.state.stats.steps;
            render(
                c, words, floats, blobs, x, y, &mut rb, &mut hb, 0, &mut leg, &mut out,
            );
            if leg.leg.phase == PHASE_DONE {
                return (out, hb, rounds);
            }
            if leg.leg.phase == PHASE_TRACING {
                assert!(leg.leg.state.stats.steps <= before + 1, "two steps");
            }
            fill(c, words, floats, blobs, x, y, &mut rb, &mut hb, 0, &mut leg);
        }
    }

    /// The mixed methods' leg kernels alternated with their Taylor fills
    /// (as the host dispatches the two pipelines) give `render_pixel`'s
    /// records and hits bit for bit, one step per leg at most; a kernel
    /// or fill of the other method leaves the pixel unsupported or its
    /// cache untouched.
    #[test]
    fn mixed_legs_with_their_taylor_fills_match_one_pass() {
        let (blobs, bounds) = two_blobs();
        let kernels: [(Method, MixedFn, FillFn); 2] = [
            (
                Method::LinearMixed,
                render_linear_mixed_leg_in::<AllKinds>,
                fill_linear_taylor_in::<AllKinds>,
            ),
            (
                Method::QuadraticMixed,
                render_quadratic_mixed_leg_in::<AllKinds>,
                fill_quadratic_taylor_in::<AllKinds>,
            ),
        ];
        let r = Root {
            t: 0.0,
            side: Side::Touch,
        };
        for (method, render, fill) in kernels {
            for mode in [Mode::Opaque, Mode::Transparent] {
                let setup = six_by_six(bounds, method, mode);
                let c = Constants::new(&setup, SceneKind::Blobs, 0.5, 4, 0);
                let (mut hit_pixels, mut steps) = (0, 0);
                for y in 0..6 {
                    for x in 0..6 {
                        let (mut ra, mut ha) = ([r; 4], [HitOut::default(); 4]);
                        let a = render_pixel(&c, &[], &[], &blobs, x, y, &mut ra, &mut ha, 0);
                        let (out, hb, rounds) =
                            mixed_until_done(render, fill, &c, (&[], &[], &blobs), x, y);
                        assert_eq!((out, hb), (a, ha), "{method} {mode:?} ({x}, {y})");
                        assert!(
                            rounds > a.steps,
                            "{method}: {rounds} rounds, {} steps",
                            a.steps
                        );
                        hit_pixels += usize::from(a.roots > 0);
                        steps += a.steps;
                    }
                }
                assert!(hit_pixels > 4, "{method} {mode:?}: {hit_pixels}");
                assert!(steps > 36, "{method} {mode:?}: {steps}");
                // The other method's kernel and fill.
                let (_, other, other_fill) = kernels.iter().find(|k| k.0 != method).unwrap();
                let (mut rb, mut hb) = ([r; 4], [HitOut::default(); 4]);
                let (mut leg, mut out) = (MixedLeg::default(), PixelOut::default());
                other(
                    &c,
                    &[],
                    &[],
                    &blobs,
                    3,
                    3,
                    &mut rb,
                    &mut hb,
                    0,
                    &mut leg,
                    &mut out,
                );
                assert_eq!(
                    (leg.leg.phase, out.status),
                    (PHASE_DONE, Status::Unsupported as u32)
                );
                let mut paused = MixedLeg::default();
                render(
                    &c,
                    &[],
                    &[],
                    &blobs,
                    3,
                    3,
                    &mut rb,
                    &mut hb,
                    0,
                    &mut paused,
                    &mut out,
                );
                assert_eq!(paused.leg.phase, PHASE_TRACING);
                let mut filled = paused;
                other_fill(&c, &[], &[], &blobs, 3, 3, &mut rb, &mut hb, 0, &mut filled);
                assert_eq!(filled, paused);
                fill(&c, &[], &[], &blobs, 3, 3, &mut rb, &mut hb, 0, &mut filled);
                assert_eq!(filled.cache.filled, 1);
            }
        }
    }

    #[test]
    fn kind_filtered_legs_trace_their_kind_alone() {
        let (blobs, bounds) = two_blobs();
        // Each method's kernel for every kind, blobs only, groups only.
        macro_rules! by_kind {
            ($f:ident) => {
                [
                    &$f::<AllKinds> as LegFn,
                    &$f::<BlobsOnly>,
                    &$f::<GroupsOnly>,
                ]
            };
        }
        let kernels: [(Method, [LegFn; 3]); 3] = [
            (Method::Segment, by_kind!(render_segment_leg_in)),
            (Method::LinearTaylor, by_kind!(render_linear_taylor_leg_in)),
            (
                Method::QuadraticTaylor,
                by_kind!(render_quadratic_taylor_leg_in),
            ),
        ];
        for (method, fs) in kernels {
            let setup = six_by_six(bounds, method, Mode::Transparent);
            let c = Constants::new(&setup, SceneKind::Blobs, 0.5, 4, 0);
            let mut hits_seen = 0;
            for y in 0..6 {
                for x in 0..6 {
                    let one = |f: LegFn| one_leg(f, &c, (&[], &[], &blobs), x, y);
                    let all = one(fs[0]);
                    assert_eq!(one(fs[1]), all, "{method}");
                    let (other, _) = one(fs[2]);
                    assert_eq!(other.status, Status::Unsupported as u32, "{method}");
                    hits_seen += usize::from(all.0.roots > 0);
                }
            }
            assert!(hits_seen > 4, "{method}: {hits_seen}");
        }
    }

    /// The segment-tracing (bottom-up lines) and forward bottom-up leg
    /// kernels of the kinds `K`.
    fn bottom_up_legs<K: SceneKinds + 'static>() -> [(Method, LegFn); 3] {
        [
            (Method::Segment, &render_segment_lines_leg_in::<K>),
            (Method::LinearBottomUp, &render_linear_bottom_up_leg_in::<K>),
            (
                Method::QuadraticBottomUp,
                &render_quadratic_bottom_up_leg_in::<K>,
            ),
        ]
    }

    /// Runs leg kernel `f` on pixel `(x, y)` of the scene data `data`
    /// ([`one_leg`]) and asserts that its record and roots are the CPU's
    /// trace of `field` with `setup` (steps, status, roots bit for bit);
    /// returns whether it hit.
    #[allow(clippy::too_many_arguments)]
    fn leg_is_the_cpus<F: Field<f32>>(
        f: LegFn,
        c: &Constants,
        data: (&[u32], &[f32], &[PointBlob<f32>]),
        field: &F,
        setup: &PixelSetup<f32>,
        x: u32,
        y: u32,
        at: &str,
    ) -> bool {
        let (gpu, hs) = one_leg(f, c, data, x, y);
        let mut rc = [Root {
            t: 0.0,
            side: Side::Touch,
        }; 4];
        let cpu = trace_pixel_in(field, setup, x, y, &mut rc, [0, 4]);
        assert_eq!(gpu.steps, cpu.trace.stats.steps, "{at}");
        assert_eq!(gpu.status, cpu.trace.status as u32, "{at}");
        assert_eq!(gpu.roots, cpu.trace.roots, "{at}");
        for k in 0..gpu.roots as usize {
            assert_eq!(hs[k].t.to_bits(), rc[k].t.to_bits(), "{at}");
        }
        gpu.roots > 0
    }

    /// [`SceneKind::Hrbf`]: the segment-tracing (bottom-up lines) and
    /// forward bottom-up legs trace `hrbf-8` and `hrbf-17` over the flat
    /// words as the CPU traces the scene's field ([`leg_is_the_cpus`]), in
    /// both modes; the kernels of the other kinds and short buffers give
    /// unsupported pixels, and the methods that need a global Lipschitz or
    /// a Taylor bound (which an HRBF lacks) the CPU's status, unsupported.
    #[test]
    fn hrbf_bottom_up_legs_trace_as_on_the_cpu() {
        use boundtrace_tracer::scenes::{DEFAULT_SEED, Scene, SceneField};
        let unsupported = |o: PixelOut| o.status == Status::Unsupported as u32;
        for name in ["hrbf-8", "hrbf-17"] {
            let scene = Scene::<f32>::build(name, DEFAULT_SEED).unwrap();
            let SceneField::Hrbf(h) = scene.field() else {
                panic!("{name} is an HRBF");
            };
            let n = h.centers().len() as u32;
            let mut floats = h.center_words();
            floats.extend_from_slice(&h.poly());
            let others = [
                bottom_up_legs::<BlobKinds>(),
                bottom_up_legs::<BlobtreeOnly>(),
            ];
            let mut hit_pixels = 0;
            for (i, (method, kernel)) in bottom_up_legs::<HrbfOnly>().into_iter().enumerate() {
                for mode in [Mode::Opaque, Mode::Transparent] {
                    let setup = six_by_six(scene.bounds(), method, mode);
                    let c = Constants::new(&setup, SceneKind::Hrbf, 0.0, 4, n);
                    for y in 0..6 {
                        for x in 0..6 {
                            let at = format!("{name} {method} {mode:?} ({x}, {y})");
                            let data = (&[][..], &floats[..], &[][..]);
                            let hit =
                                leg_is_the_cpus(kernel, &c, data, scene.field(), &setup, x, y, &at);
                            hit_pixels += usize::from(hit);
                            let run = |f: LegFn, c: &Constants, floats: &[f32]| {
                                one_leg(f, c, (&[], floats, &[]), x, y).0
                            };
                            for other in &others {
                                assert!(unsupported(run(other[i].1, &c, &floats)), "{at}");
                            }
                            // the polynomial's last word missing
                            let short = &floats[..floats.len() - 1];
                            assert!(unsupported(run(kernel, &c, short)), "{at}");
                            // more centers than words
                            let more = Constants { groups: n + 1, ..c };
                            assert!(unsupported(run(kernel, &more, &floats)), "{at}");
                            let huge = Constants {
                                groups: u32::MAX,
                                ..c
                            };
                            assert!(unsupported(run(kernel, &huge, &floats)), "{at}");
                        }
                    }
                }
            }
            assert!(hit_pixels >= 16, "{name}: {hit_pixels}");
            // No global Lipschitz bound (sphere tracing), no Taylor bound:
            // unsupported on the CPU and here.
            let lacking: [(Method, LegFn); 3] = [
                (Method::Sphere, &render_sphere_leg_in::<AllKinds>),
                (
                    Method::LinearTaylor,
                    &render_linear_taylor_leg_in::<AllKinds>,
                ),
                (
                    Method::QuadraticTaylor,
                    &render_quadratic_taylor_leg_in::<AllKinds>,
                ),
            ];
            for (method, kernel) in lacking {
                let setup = six_by_six(scene.bounds(), method, Mode::Opaque);
                let c = Constants::new(&setup, SceneKind::Hrbf, 0.0, 4, n);
                let mut rc = [Root {
                    t: 0.0,
                    side: Side::Touch,
                }; 4];
                let cpu = trace_pixel_in(scene.field(), &setup, 3, 3, &mut rc, [0, 4]);
                let (gpu, _) = one_leg(kernel, &c, (&[], &floats, &[]), 3, 3);
                assert_eq!(gpu.status, cpu.trace.status as u32, "{method}");
                assert!(unsupported(gpu), "{method}");
            }
        }
    }

    /// The mixed methods on [`SceneKind::Hrbf`] (no Taylor bound: the
    /// bottom-up side alone, as on the CPU): their leg kernels alternated
    /// with their Taylor fills trace `hrbf-8` as the CPU does, bit for bit.
    #[test]
    fn hrbf_mixed_legs_trace_as_on_the_cpu() {
        use boundtrace_tracer::scenes::{DEFAULT_SEED, Scene, SceneField};
        let scene = Scene::<f32>::build("hrbf-8", DEFAULT_SEED).unwrap();
        let SceneField::Hrbf(h) = scene.field() else {
            panic!("hrbf-8 is an HRBF");
        };
        let mut floats = h.center_words();
        floats.extend_from_slice(&h.poly());
        let kernels: [(Method, MixedFn, FillFn); 2] = [
            (
                Method::LinearMixed,
                render_linear_mixed_leg_in::<HrbfOnly>,
                fill_linear_taylor_in::<HrbfOnly>,
            ),
            (
                Method::QuadraticMixed,
                render_quadratic_mixed_leg_in::<HrbfOnly>,
                fill_quadratic_taylor_in::<HrbfOnly>,
            ),
        ];
        let mut hit_pixels = 0;
        for (method, render, fill) in kernels {
            for mode in [Mode::Opaque, Mode::Transparent] {
                let setup = six_by_six(scene.bounds(), method, mode);
                let c = Constants::new(&setup, SceneKind::Hrbf, 0.0, 4, h.centers().len() as u32);
                for y in 0..6 {
                    for x in 0..6 {
                        let (gpu, hs, _) =
                            mixed_until_done(render, fill, &c, (&[], &floats, &[]), x, y);
                        let mut rc = [Root {
                            t: 0.0,
                            side: Side::Touch,
                        }; 4];
                        let cpu = trace_pixel_in(scene.field(), &setup, x, y, &mut rc, [0, 4]);
                        let at = format!("{method} {mode:?} ({x}, {y})");
                        assert_eq!(gpu.steps, cpu.trace.stats.steps, "{at}");
                        assert_eq!(gpu.status, cpu.trace.status as u32, "{at}");
                        assert_eq!(gpu.roots, cpu.trace.roots, "{at}");
                        for k in 0..gpu.roots as usize {
                            assert_eq!(hs[k].t.to_bits(), rc[k].t.to_bits(), "{at}");
                        }
                        hit_pixels += usize::from(gpu.roots > 0);
                    }
                }
            }
        }
        assert!(hit_pixels >= 16, "{hit_pixels}");
    }

    /// [`homothetic_case`]'s scene field, bounds, words, floats and bound.
    type HomotheticCase = (
        boundtrace_tracer::scenes::SceneField<f32>,
        [[f32; 3]; 2],
        Vec<u32>,
        Vec<f32>,
        f32,
    );

    /// A homothetic-distance skeleton with `kernel` as the CPU scene
    /// (`WithLipschitz` with the skeleton's own bound, as scene files
    /// build it), its GPU words and floats ([`SceneKind::Homothetic`]) and
    /// the bound.
    fn homothetic_case(
        kernel: boundtrace_fields::homothetic::SegmentKernel<f32>,
    ) -> HomotheticCase {
        use boundtrace_fields::homothetic::Segment;
        use boundtrace_tracer::scenes::{SceneField, WithLipschitz};
        let v: [([f32; 3], f32); 4] = [
            ([0.0, -0.8, 0.0], 0.4),
            ([0.0, 0.0, 0.0], 0.3),
            ([-0.5, 0.45, 0.1], 0.15),
            ([0.45, 0.5, -0.1], 0.2),
        ];
        let segments: Vec<Segment<f32>> = [(0, 1), (1, 2), (1, 3)]
            .iter()
            .map(|&(i, j)| Segment::new(v[i].0, v[i].1, v[j].0, v[j].1).unwrap())
            .collect();
        let sk = HomotheticSkeleton::new(segments, kernel, 1.0).unwrap();
        let (code, params) = sk.parameter_words();
        let mut floats = sk.segment_words();
        floats.extend_from_slice(&params);
        let l = sk.lipschitz().unwrap();
        // (the box of the supports would frame a compact kernel's
        // skeleton; this one frames the surface, for more hits)
        let bounds = [[-1.0, -1.4, -0.7], [1.0, 1.0, 0.7]];
        let field = SceneField::Homothetic(WithLipschitz::new(sk, l));
        (field, bounds, code.to_vec(), floats, l)
    }

    /// [`SceneKind::Homothetic`], compact and Cauchy kernels: the sphere,
    /// segment, `linear-taylor` and forward bottom-up legs, and the mixed
    /// legs alternated with their Taylor fills, trace the skeleton over
    /// the flat words as the CPU traces the scene's field (steps, status,
    /// roots bit for bit), in both modes; `quadratic-taylor` is
    /// unsupported on both (no quadratic Taylor bound); other kinds'
    /// kernels, short buffers and a missing or unknown kernel code give unsupported
    /// pixels.
    #[test]
    fn homothetic_legs_trace_as_on_the_cpu() {
        use boundtrace_fields::homothetic::SegmentKernel;
        let unsupported = |o: PixelOut| o.status == Status::Unsupported as u32;
        let legs: [(Method, LegFn, LegFn); 5] = [
            (
                Method::Sphere,
                &render_sphere_leg_in::<HomotheticOnly>,
                &render_sphere_leg_in::<BlobKinds>,
            ),
            (
                Method::Segment,
                &render_segment_leg_in::<HomotheticOnly>,
                &render_segment_leg_in::<HrbfOnly>,
            ),
            (
                Method::LinearTaylor,
                &render_linear_taylor_leg_in::<HomotheticOnly>,
                &render_linear_taylor_leg_in::<BlobsOnly>,
            ),
            (
                Method::LinearBottomUp,
                &render_linear_bottom_up_leg_in::<HomotheticOnly>,
                &render_linear_bottom_up_leg_in::<HrbfOnly>,
            ),
            (
                Method::QuadraticBottomUp,
                &render_quadratic_bottom_up_leg_in::<HomotheticOnly>,
                &render_quadratic_bottom_up_leg_in::<BlobtreeOnly>,
            ),
        ];
        let mixed: [(Method, MixedFn, FillFn); 2] = [
            (
                Method::LinearMixed,
                render_linear_mixed_leg_in::<HomotheticOnly>,
                fill_linear_taylor_in::<HomotheticOnly>,
            ),
            (
                Method::QuadraticMixed,
                render_quadratic_mixed_leg_in::<HomotheticOnly>,
                fill_quadratic_taylor_in::<HomotheticOnly>,
            ),
        ];
        for kernel in [
            SegmentKernel::compact_polynomial(4, 1.6).unwrap(),
            SegmentKernel::cauchy(3, 1.2).unwrap(),
        ] {
            let (field, bounds, words, floats, l) = homothetic_case(kernel);
            let n = (floats.len() - PARAMETER_WORDS) / SEGMENT_WORDS;
            let constants = |setup: &PixelSetup<f32>| Constants {
                lipschitz: l,
                ..Constants::new(setup, SceneKind::Homothetic, 0.0, 4, n as u32)
            };
            let data = (&words[..], &floats[..], &[][..]);
            let mut hit_pixels = 0;
            for &(method, leg, other) in &legs {
                for mode in [Mode::Opaque, Mode::Transparent] {
                    let setup = six_by_six(bounds, method, mode);
                    let c = constants(&setup);
                    for y in 0..6 {
                        for x in 0..6 {
                            let at = format!("{kernel:?} {method} {mode:?} ({x}, {y})");
                            let hit = leg_is_the_cpus(leg, &c, data, &field, &setup, x, y, &at);
                            hit_pixels += usize::from(hit);
                            let run = |f: LegFn, c: &Constants, w: &[u32], fl: &[f32]| {
                                one_leg(f, c, (w, fl, &[]), x, y).0
                            };
                            assert!(unsupported(run(other, &c, &words, &floats)), "{at}");
                            // the last parameter word missing
                            let short = &floats[..floats.len() - 1];
                            assert!(unsupported(run(leg, &c, &words, short)), "{at}");
                            // no kernel code, or an unknown one
                            assert!(unsupported(run(leg, &c, &words[..1], &floats)), "{at}");
                            let unknown = [KERNEL_CAUCHY + 1, words[1]];
                            assert!(unsupported(run(leg, &c, &unknown, &floats)), "{at}");
                            let more = Constants {
                                groups: n as u32 + 1,
                                ..c
                            };
                            assert!(unsupported(run(leg, &more, &words, &floats)), "{at}");
                            let huge = Constants {
                                groups: u32::MAX,
                                ..c
                            };
                            assert!(unsupported(run(leg, &huge, &words, &floats)), "{at}");
                        }
                    }
                }
            }
            eprintln!("{kernel:?}: {hit_pixels} hits");
            assert!(hit_pixels >= 5 * 2 * 4, "{kernel:?}: {hit_pixels}");
            for (method, render, fill) in mixed {
                for mode in [Mode::Opaque, Mode::Transparent] {
                    let setup = six_by_six(bounds, method, mode);
                    let c = constants(&setup);
                    for y in 0..6 {
                        for x in 0..6 {
                            let (gpu, hs, _) = mixed_until_done(render, fill, &c, data, x, y);
                            let mut rc = [Root {
                                t: 0.0,
                                side: Side::Touch,
                            }; 4];
                            let cpu = trace_pixel_in(&field, &setup, x, y, &mut rc, [0, 4]);
                            let at = format!("{kernel:?} {method} {mode:?} ({x}, {y})");
                            assert_eq!(gpu.steps, cpu.trace.stats.steps, "{at}");
                            assert_eq!(gpu.status, cpu.trace.status as u32, "{at}");
                            assert_eq!(gpu.roots, cpu.trace.roots, "{at}");
                            for k in 0..gpu.roots as usize {
                                assert_eq!(hs[k].t.to_bits(), rc[k].t.to_bits(), "{at}");
                            }
                        }
                    }
                }
            }
            // No quadratic Taylor bound: unsupported on the CPU and here.
            let setup = six_by_six(bounds, Method::QuadraticTaylor, Mode::Opaque);
            let c = constants(&setup);
            let mut rc = [Root {
                t: 0.0,
                side: Side::Touch,
            }; 4];
            let cpu = trace_pixel_in(&field, &setup, 3, 3, &mut rc, [0, 4]);
            let kernel_fn: LegFn = &render_quadratic_taylor_leg_in::<HomotheticOnly>;
            let (gpu, _) = one_leg(kernel_fn, &c, data, 3, 3);
            assert_eq!(gpu.status, cpu.trace.status as u32);
            assert!(unsupported(gpu));
        }
    }

    /// The blobtree's segment-tracing (bottom-up lines) and forward
    /// bottom-up legs trace `aggregate-1` as the CPU traces it (steps,
    /// status, roots bit for bit), in both modes, on the host; other kinds'
    /// kernels do not hold the blobtree. (No module ships these legs yet:
    /// lavapipe had not compiled the segment one, built without
    /// spirv-opt, after 14 minutes at 8.9 GB: BENCHMARKS.md "GPU", session
    /// 34.)
    #[test]
    fn blobtree_bottom_up_legs_trace_as_on_the_cpu() {
        use boundtrace_tracer::scenes::{DEFAULT_SEED, Scene, SceneField};
        let scene = Scene::<f32>::build("aggregate-1", DEFAULT_SEED).unwrap();
        let SceneField::Blobtree(tree) = scene.field() else {
            panic!("aggregate-1 is a blobtree");
        };
        let t = tree.as_ref();
        let others = [bottom_up_legs::<BlobKinds>(), bottom_up_legs::<HrbfOnly>()];
        let mut hit_pixels = 0;
        for (i, (method, kernel)) in bottom_up_legs::<BlobtreeOnly>().into_iter().enumerate() {
            for mode in [Mode::Opaque, Mode::Transparent] {
                let setup = six_by_six(scene.bounds(), method, mode);
                let c = Constants {
                    lipschitz: t.lipschitz_bound::<f32>().unwrap(),
                    ..Constants::new(&setup, SceneKind::Blobtree, 0.0, 4, 0)
                };
                let data = (t.nodes(), t.params(), &[][..]);
                for y in 0..6 {
                    for x in 0..6 {
                        let at = format!("{method} {mode:?} ({x}, {y})");
                        let hit =
                            leg_is_the_cpus(kernel, &c, data, scene.field(), &setup, x, y, &at);
                        hit_pixels += usize::from(hit);
                        for other in &others {
                            let (o, _) = one_leg(other[i].1, &c, data, x, y);
                            assert_eq!(o.status, Status::Unsupported as u32, "{at}");
                        }
                    }
                }
            }
        }
        assert!(hit_pixels >= 24, "{hit_pixels}");
    }

    #[test]
    fn blobtree_sphere_legs_trace_as_on_the_cpu() {
        use boundtrace_tracer::scenes::{DEFAULT_SEED, Scene, SceneField};
        let scene = Scene::<f32>::build("aggregate-1", DEFAULT_SEED).unwrap();
        let SceneField::Blobtree(tree) = scene.field() else {
            panic!("aggregate-1 is a blobtree");
        };
        let t = tree.as_ref();
        let r = Root {
            t: 0.0,
            side: Side::Touch,
        };
        let mut hit_pixels = 0;
        for mode in [Mode::Opaque, Mode::Transparent] {
            let setup = six_by_six(scene.bounds(), Method::Sphere, mode);
            let c = Constants {
                // The host's bound: the CPU field's own.
                lipschitz: t.lipschitz_bound::<f32>().unwrap(),
                ..Constants::new(&setup, SceneKind::Blobtree, 0.0, 4, 0)
            };
            for y in 0..6 {
                for x in 0..6 {
                    let run = |f: LegFn| one_leg(f, &c, (t.nodes(), t.params(), &[]), x, y);
                    let (gpu, hs) = run(&render_sphere_leg_in::<BlobtreeOnly>);
                    let mut rc = [r; 4];
                    let cpu = trace_pixel_in(scene.field(), &setup, x, y, &mut rc, [0, 4]);
                    assert_eq!(gpu.steps, cpu.trace.stats.steps, "({x}, {y}) {mode:?}");
                    assert_eq!(gpu.status, cpu.trace.status as u32);
                    assert_eq!(gpu.roots, cpu.trace.roots);
                    for k in 0..gpu.roots as usize {
                        assert_eq!(hs[k].t.to_bits(), rc[k].t.to_bits());
                    }
                    hit_pixels += usize::from(gpu.roots > 0);
                    // `trace_sphere`'s kinds do not hold the blobtree.
                    let (other, _) = run(&render_sphere_leg_in::<BlobKinds>);
                    assert_eq!(other.status, Status::Unsupported as u32);
                }
            }
        }
        assert!(hit_pixels >= 8, "{hit_pixels}");
    }

    /// Tiled blobtrees: each pixel traced with its 8 × 8 tile's program
    /// ([`Constants::groups`] tiles per row), as the CPU twin
    /// (`render_tile_programs`) traces it, bit for bit, in both modes.
    #[test]
    fn tiled_blobtree_legs_trace_as_the_cpu_twin() {
        use boundtrace_tracer::scenes::{DEFAULT_SEED, Scene, SceneField};
        use boundtrace_tracer::tile_programs::{TilePrograms, render_tile_programs};
        let scene = Scene::<f32>::build("aggregate-2", DEFAULT_SEED).unwrap();
        let SceneField::Blobtree(tree) = scene.field() else {
            panic!("aggregate-2 is a blobtree");
        };
        let t = tree.as_ref();
        let size = 20;
        let (mut hit_pixels, mut tiles_seen) = (0, std::collections::BTreeSet::new());
        for mode in [Mode::Opaque, Mode::Transparent] {
            let setup = PixelSetup {
                width: size,
                height: size,
                ..six_by_six(scene.bounds(), Method::Sphere, mode)
            };
            let programs =
                TilePrograms::build(tree, &setup.camera, scene.bounds(), size, size).unwrap();
            assert!(programs.max_nodes() < t.len());
            let settings =
                boundtrace_tracer::render::RenderSettings::new(size, size, Method::Sphere)
                    .unwrap()
                    .with_mode(mode)
                    .with_max_roots(4)
                    .unwrap();
            let cpu = render_tile_programs(&programs, t, &setup.camera, scene.bounds(), &settings)
                .unwrap();
            let c = Constants::new(&setup, SceneKind::Blobtree, 0.0, 4, programs.grid().tiles_x);
            for y in 0..size {
                for x in 0..size {
                    let (out, hs) = one_leg(
                        &render_sphere_leg_in::<BlobtreeOnly>,
                        &c,
                        (programs.words(), t.params(), &[]),
                        x,
                        y,
                    );
                    let px = cpu.pixel(x, y).unwrap();
                    assert_eq!(out.steps, px.trace.stats.steps, "({x}, {y}) {mode:?}");
                    assert_eq!(out.status, px.trace.status as u32);
                    assert_eq!(out.roots, px.trace.roots);
                    for (k, h) in cpu.hits(x, y).iter().enumerate() {
                        assert_eq!(hs[k].t.to_bits(), h.t.to_bits(), "({x}, {y})");
                        assert_eq!(hs[k].normal.map(f32::to_bits), h.normal.map(f32::to_bits));
                    }
                    hit_pixels += usize::from(out.roots > 0);
                    tiles_seen.insert((x / 8, y / 8));
                }
            }
        }
        assert_eq!(tiles_seen.len(), 9);
        assert!(hit_pixels >= 40, "{hit_pixels}");
    }

    #[test]
    fn bad_scene_data_is_unsupported() {
        let bounds = [[-1.0f32; 3], [1.0; 3]];
        let setup = PixelSetup {
            camera: Camera::framing(bounds, [0.0, 0.0, -1.0], 35.0, 1.0).unwrap(),
            bounds,
            width: 4,
            height: 4,
            method: Method::Segment,
            mode: Mode::Opaque,
            params: Params::new(),
        };
        let mut hits = [HitOut::default(); 1];
        let mut roots = [Root {
            t: 0.0,
            side: Side::Touch,
        }; 1];
        // A blobtree with an odd word count, or none.
        let c = Constants::new(&setup, SceneKind::Blobtree, 0.0, 1, 0);
        let out = render_pixel(&c, &[1, 2, 3], &[], &[], 1, 1, &mut roots, &mut hits, 0);
        assert_eq!(out.status, Status::Unsupported as u32);
        let out = render_pixel(&c, &[], &[], &[], 1, 1, &mut roots, &mut hits, 0);
        assert_eq!(out.status, Status::Unsupported as u32);
        // More groups than words.
        let c = Constants::new(&setup, SceneKind::BlobGroups, 0.5, 1, 3);
        let out = render_pixel(&c, &[1], &[], &[], 1, 1, &mut roots, &mut hits, 0);
        assert_eq!(out.status, Status::Unsupported as u32);
        let c = Constants { scene: 9, ..c };
        let out = render_pixel(&c, &[], &[], &[], 1, 1, &mut roots, &mut hits, 0);
        assert_eq!(out.status, Status::Unsupported as u32);
    }
}
