//! boundtrace's SPIR-V compute shader: thin `#[spirv(compute)]` entry
//! points over [`boundtrace_gpu_kernel::render_pixel`], which calls the
//! tracer's own per-pixel code. Built by `scripts/build-spirv.sh` with the
//! pinned rust-gpu nightly; the host (`boundtrace-gpu`) loads the module.
//!
//! Entry points:
//! - `interval_square`: the toolchain probe (ia-core interval arithmetic
//!   on the GPU), always built;
//! - `arith_ops`: the arithmetic probe (`÷ × + −` as the driver computes
//!   them), always built;
//! - `outward_ops`: the outward-rounding probe (`ia-core`'s quotient and
//!   square-root bounds on the GPU), always built;
//! - `transcendental_ops`, `pow_ops` and `trig_ops`: `ia-core`'s `exp`,
//!   `ln`, `pow`, `sin` and `cos` interval bounds on the GPU, always built;
//! - `trace_sphere`: sphere tracing of the blob scenes in resumable legs
//!   (`render_sphere_leg_in::<BlobKinds>`), feature `sphere` (default): a
//!   driver that inlines every call (lavapipe) compiles it;
//! - `trace_sphere_blobtree`: the same for flat blobtrees
//!   (`render_sphere_leg_in::<BlobtreeOnly>`), feature `sphere-blobtree`,
//!   a module of its own;
//! - `trace_segment_blobs` and `trace_segment_groups`: segment tracing in
//!   resumable legs (`render_segment_leg_in`) of one scene kind each, the
//!   same bindings, features `segment-blobs` and `segment-groups`; likewise
//!   `trace_linear_taylor_{blobs,groups}` and
//!   `trace_quadratic_taylor_{blobs,groups}` (forward linear and quadratic
//!   inclusions from Taylor bounds), features `linear-taylor-blobs`, …:
//!   each in a module of its own (`scripts/build-spirv.sh` builds all
//!   eight);
//! - `trace_segment_hrbf`, `trace_linear_bottom_up_hrbf`,
//!   `trace_quadratic_bottom_up_hrbf` and the mixed pairs
//!   `{trace,taylor}_{linear,quadratic}_mixed_hrbf`: the HRBF scenes
//!   (segment tracing with the CPU's bound, from bottom-up lines; the
//!   forward bottom-up and mixed methods), features `segment-hrbf`, …, a
//!   module each;
//! - `trace_{sphere,segment,linear_taylor}_homothetic`,
//!   `trace_{linear,quadratic}_bottom_up_homothetic` and the mixed pairs
//!   `{trace,taylor}_{linear,quadratic}_mixed_homothetic`: the
//!   homothetic-distance skeletons of scene files, features
//!   `sphere-homothetic`, …, a module each;
//! - `trace_scalis` and `trace_scalis_tight` (its intervals' tight
//!   stages, a pipeline of its own): `scalis-quadratic` and the
//!   per-primitive `interval` bisection on SCALIS skeletons
//!   (`render_scalis_leg`, over the frame's primitive lists, built on the
//!   host), feature `scalis`, a module of their own with other bindings
//!   1–3 (list offsets, lists, segments) and 7 (`ScalisLeg`);
//! - `trace_pixels`: every GPU method ([`render_pixel`]), feature `trace`
//!   (`BOUNDTRACE_SHADER_FEATURES=trace scripts/build-spirv.sh`): it links,
//!   but is too large for such a driver (BENCHMARKS.md "GPU").
#![cfg_attr(target_arch = "spirv", no_std)]

// (unused in a module of the `scalis` entry point alone)
#[allow(unused_imports)]
use boundtrace_fields::PointBlob;
#[cfg(feature = "scalis")]
use boundtrace_fields::scalis::ScalisSegment;
#[cfg(feature = "scalis")]
use boundtrace_gpu_kernel::ScalisLeg;
#[allow(unused_imports)]
use boundtrace_gpu_kernel as kernel;
#[cfg(feature = "trace")]
use boundtrace_gpu_kernel::render_pixel;
use boundtrace_gpu_kernel::{Constants, HitOut, PixelLeg, PixelOut};
use boundtrace_ia_core::{Interval, round};
use boundtrace_tracer::Root;
#[cfg(feature = "scalis")]
use boundtrace_tracer::scalis::PrimitiveHit;
use spirv_std::glam::UVec3;
use spirv_std::spirv;

/// Toolchain probe: `data[i] ← hi([data[i], data[i] + 1]²)` in the
/// crate's outward-rounded interval arithmetic.
#[spirv(compute(threads(64)))]
pub fn interval_square(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] data: &mut [f32],
) {
    let i = id.x as usize;
    if i < data.len() {
        let x = Interval::new(data[i], data[i] + 1.0);
        data[i] = x.sqr().hi();
    }
}

/// Arithmetic probe: for each `[a, b, _, _]` in `data`, writes
/// `[a / b, a · b, a + b, a − b]` as the GPU computes them, for the host to
/// compare with the CPU's correctly rounded results (the interval code's
/// outward rounding assumes them).
#[spirv(compute(threads(64)))]
pub fn arith_ops(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] data: &mut [f32],
) {
    let i = id.x as usize * 4;
    if i + 3 < data.len() {
        let (a, b) = (data[i], data[i + 1]);
        data[i] = a / b;
        data[i + 1] = a * b;
        data[i + 2] = a + b;
        data[i + 3] = a - b;
    }
}

/// Outward-rounding probe: for each `[a, b, _, _]` in `data`, writes
/// `[div_down(a, b), div_up(a, b), sqrt_down(|a|), sqrt_up(|a|)]`, the
/// `ia-core` bounds (`round`) that the interval code builds quotients and
/// square roots from, as compiled to SPIR-V, for the host to check that
/// they enclose the exact results.
#[spirv(compute(threads(64)))]
pub fn outward_ops(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] data: &mut [f32],
) {
    let i = id.x as usize * 4;
    if i + 3 < data.len() {
        let (a, b) = (data[i], data[i + 1]);
        data[i] = round::div_down(a, b);
        data[i + 1] = round::div_up(a, b);
        data[i + 2] = round::sqrt_down(a.abs());
        data[i + 3] = round::sqrt_up(a.abs());
    }
}

/// Transcendental probe: for each `[a, b, _, _]` in `data`, writes the
/// bounds of `ia-core`'s `Interval` `exp([a, a])` and `ln([|a|, |a|])`,
/// `[exp_lo, exp_hi, ln_lo, ln_hi]`, as compiled to SPIR-V (`ia-core`'s
/// own `f32` `exp` and `ln` there, not the driver's), for the host to
/// check that they enclose the exact results.
#[spirv(compute(threads(64)))]
pub fn transcendental_ops(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] data: &mut [f32],
) {
    let i = id.x as usize * 4;
    if i + 3 < data.len() {
        let a = data[i];
        let e = Interval::point(a).exp();
        let l = Interval::point(a.abs()).ln();
        data[i] = e.lo();
        data[i + 1] = e.hi();
        data[i + 2] = l.lo();
        data[i + 3] = l.hi();
    }
}

/// Power probe: for each `[a, b, _, _]` in `data`, writes the bounds of
/// `Interval::pow([|a|, |a|], b)` (`ia-core`'s own `f32` `pow` on
/// SPIR-V), `[pow_lo, pow_hi, a, b]`.
#[spirv(compute(threads(64)))]
pub fn pow_ops(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] data: &mut [f32],
) {
    let i = id.x as usize * 4;
    if i + 3 < data.len() {
        let (a, b) = (data[i], data[i + 1]);
        let r = Interval::point(a.abs()).pow(b);
        data[i] = r.lo();
        data[i + 1] = r.hi();
    }
}

/// Trigonometric probe: for each `[a, b, _, _]` in `data`, writes the
/// bounds of `Interval::sin([a, a])` and `Interval::cos([a, a])`,
/// `[sin_lo, sin_hi, cos_lo, cos_hi]` (`ia-core`'s own `f32` `sin` and
/// `cos` on SPIR-V).
#[spirv(compute(threads(64)))]
pub fn trig_ops(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] data: &mut [f32],
) {
    let i = id.x as usize * 4;
    if i + 3 < data.len() {
        let x = Interval::point(data[i]);
        let (s, c) = (x.sin(), x.cos());
        data[i] = s.lo();
        data[i + 1] = s.hi();
        data[i + 2] = c.lo();
        data[i + 3] = c.hi();
    }
}

/// One invocation per pixel, 8 × 8 per workgroup: traces pixel
/// `(id.x, id.y)` and writes its record and hits.
///
/// Behind the `trace` feature. rust-gpu 0.11's linker inlines every
/// function that may panic, takes a storage-buffer pointer (or a struct
/// holding one) or is `#[inline]`; the shared code avoids the first and the
/// last on its leaves, so the link takes minutes (the module: ≈ 374 k
/// instructions). But a driver that inlines every remaining call, as
/// lavapipe does, faces ≈ 1.8·10¹⁰ instructions and runs out of memory
/// (BENCHMARKS.md "GPU").
#[cfg(feature = "trace")]
#[spirv(compute(threads(8, 8)))]
pub fn trace_pixels(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] constants: &Constants,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] words: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] floats: &[f32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] blobs: &[PointBlob<f32>],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] pixels: &mut [PixelOut],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 5)] hits: &mut [HitOut],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 6)] roots: &mut [Root<f32>],
) {
    trace_entry(
        id,
        constants,
        words,
        floats,
        blobs,
        pixels,
        hits,
        roots,
        render_pixel,
    );
}

/// [`trace_pixels`]'s bindings and layout plus a per-pixel [`PixelLeg`]
/// (binding 7): sphere tracing only, resumable ([`render_sphere_leg`]; other
/// methods give `Unsupported` pixels). The host dispatches it until every
/// pixel is done, so that a driver's loop limit costs dispatches, never
/// results.
#[cfg(feature = "sphere")]
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(8, 8)))]
pub fn trace_sphere(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] constants: &Constants,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] words: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] floats: &[f32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] blobs: &[PointBlob<f32>],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] pixels: &mut [PixelOut],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 5)] hits: &mut [HitOut],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 6)] roots: &mut [Root<f32>],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 7)] legs: &mut [PixelLeg],
) {
    leg_entry(
        id,
        constants,
        words,
        floats,
        blobs,
        pixels,
        hits,
        roots,
        legs,
        kernel::render_sphere_leg_in::<kernel::BlobKinds>,
    );
}

/// A leg entry point like [`trace_sphere`] (the same bindings, layout and
/// legs) for one method and scene kind, `render` its kernel function, in a
/// module of its own (built with its feature alone): spirv-opt and drivers
/// that inline every call run out of memory on more (BENCHMARKS.md "GPU").
macro_rules! leg_entry_point {
    ($(#[$doc:meta])* $feature:literal, $name:ident, $render:path) => {
        $(#[$doc])*
        #[cfg(feature = $feature)]
        #[allow(clippy::too_many_arguments)]
        #[spirv(compute(threads(8, 8)))]
        pub fn $name(
            #[spirv(global_invocation_id)] id: UVec3,
            #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] constants: &Constants,
            #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] words: &[u32],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] floats: &[f32],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] blobs: &[PointBlob<f32>],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] pixels: &mut [PixelOut],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 5)] hits: &mut [HitOut],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 6)] roots: &mut [Root<f32>],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 7)] legs: &mut [PixelLeg],
        ) {
            leg_entry(
                id, constants, words, floats, blobs, pixels, hits, roots, legs, $render,
            );
        }
    };
}

leg_entry_point!(
    /// Segment tracing of `SceneKind::Blobs` scenes
    /// (`render_segment_leg_in::<BlobsOnly>`), feature `segment-blobs`.
    "segment-blobs",
    trace_segment_blobs,
    kernel::render_segment_leg_in::<kernel::BlobsOnly>
);

leg_entry_point!(
    /// Segment tracing of `SceneKind::BlobGroups` scenes
    /// (`render_segment_leg_in::<GroupsOnly>`), feature `segment-groups`.
    "segment-groups",
    trace_segment_groups,
    kernel::render_segment_leg_in::<kernel::GroupsOnly>
);

leg_entry_point!(
    /// Forward linear inclusions from Taylor bounds (`linear-taylor`) on
    /// `SceneKind::Blobs` scenes (`render_linear_taylor_leg_in::<BlobsOnly>`),
    /// feature `linear-taylor-blobs`.
    "linear-taylor-blobs",
    trace_linear_taylor_blobs,
    kernel::render_linear_taylor_leg_in::<kernel::BlobsOnly>
);

leg_entry_point!(
    /// `linear-taylor` on `SceneKind::BlobGroups` scenes, feature
    /// `linear-taylor-groups`.
    "linear-taylor-groups",
    trace_linear_taylor_groups,
    kernel::render_linear_taylor_leg_in::<kernel::GroupsOnly>
);

leg_entry_point!(
    /// Forward quadratic inclusions from Taylor bounds (`quadratic-taylor`)
    /// on `SceneKind::Blobs` scenes
    /// (`render_quadratic_taylor_leg_in::<BlobsOnly>`), feature
    /// `quadratic-taylor-blobs`.
    "quadratic-taylor-blobs",
    trace_quadratic_taylor_blobs,
    kernel::render_quadratic_taylor_leg_in::<kernel::BlobsOnly>
);

leg_entry_point!(
    /// `quadratic-taylor` on `SceneKind::BlobGroups` scenes, feature
    /// `quadratic-taylor-groups`.
    "quadratic-taylor-groups",
    trace_quadratic_taylor_groups,
    kernel::render_quadratic_taylor_leg_in::<kernel::GroupsOnly>
);

leg_entry_point!(
    /// Forward linear bottom-up bounds (`linear-bottom-up`) on
    /// `SceneKind::Blobs` scenes
    /// (`render_linear_bottom_up_leg_in::<BlobsOnly>`), feature
    /// `linear-bottom-up-blobs`.
    "linear-bottom-up-blobs",
    trace_linear_bottom_up_blobs,
    kernel::render_linear_bottom_up_leg_in::<kernel::BlobsOnly>
);

leg_entry_point!(
    /// `linear-bottom-up` on `SceneKind::BlobGroups` scenes, feature
    /// `linear-bottom-up-groups`.
    "linear-bottom-up-groups",
    trace_linear_bottom_up_groups,
    kernel::render_linear_bottom_up_leg_in::<kernel::GroupsOnly>
);

leg_entry_point!(
    /// Forward quadratic bottom-up bounds (`quadratic-bottom-up`) on
    /// `SceneKind::Blobs` scenes
    /// (`render_quadratic_bottom_up_leg_in::<BlobsOnly>`), feature
    /// `quadratic-bottom-up-blobs`.
    "quadratic-bottom-up-blobs",
    trace_quadratic_bottom_up_blobs,
    kernel::render_quadratic_bottom_up_leg_in::<kernel::BlobsOnly>
);

leg_entry_point!(
    /// `quadratic-bottom-up` on `SceneKind::BlobGroups` scenes, feature
    /// `quadratic-bottom-up-groups`.
    "quadratic-bottom-up-groups",
    trace_quadratic_bottom_up_groups,
    kernel::render_quadratic_bottom_up_leg_in::<kernel::GroupsOnly>
);

leg_entry_point!(
    /// Segment tracing of `SceneKind::Hrbf` scenes with the CPU's bound,
    /// from bottom-up lines (`render_segment_lines_leg_in::<HrbfOnly>`),
    /// feature `segment-hrbf`.
    "segment-hrbf",
    trace_segment_hrbf,
    kernel::render_segment_lines_leg_in::<kernel::HrbfOnly>
);

leg_entry_point!(
    /// `linear-bottom-up` on `SceneKind::Hrbf` scenes, feature
    /// `linear-bottom-up-hrbf`.
    "linear-bottom-up-hrbf",
    trace_linear_bottom_up_hrbf,
    kernel::render_linear_bottom_up_leg_in::<kernel::HrbfOnly>
);

leg_entry_point!(
    /// `quadratic-bottom-up` on `SceneKind::Hrbf` scenes, feature
    /// `quadratic-bottom-up-hrbf`.
    "quadratic-bottom-up-hrbf",
    trace_quadratic_bottom_up_hrbf,
    kernel::render_quadratic_bottom_up_leg_in::<kernel::HrbfOnly>
);

leg_entry_point!(
    /// Sphere tracing of `SceneKind::Homothetic` skeletons with the scene's
    /// global Lipschitz bound (`render_sphere_leg_in::<HomotheticOnly>`),
    /// feature `sphere-homothetic`.
    "sphere-homothetic",
    trace_sphere_homothetic,
    kernel::render_sphere_leg_in::<kernel::HomotheticOnly>
);

leg_entry_point!(
    /// Segment tracing of `SceneKind::Homothetic` skeletons with their
    /// directional Lipschitz lines (`render_segment_leg_in::<HomotheticOnly>`),
    /// feature `segment-homothetic`.
    "segment-homothetic",
    trace_segment_homothetic,
    kernel::render_segment_leg_in::<kernel::HomotheticOnly>
);

leg_entry_point!(
    /// `linear-taylor` on `SceneKind::Homothetic` skeletons (the directional
    /// Lipschitz lines), feature `linear-taylor-homothetic`.
    "linear-taylor-homothetic",
    trace_linear_taylor_homothetic,
    kernel::render_linear_taylor_leg_in::<kernel::HomotheticOnly>
);

leg_entry_point!(
    /// `linear-bottom-up` on `SceneKind::Homothetic` skeletons, feature
    /// `linear-bottom-up-homothetic`.
    "linear-bottom-up-homothetic",
    trace_linear_bottom_up_homothetic,
    kernel::render_linear_bottom_up_leg_in::<kernel::HomotheticOnly>
);

leg_entry_point!(
    /// `quadratic-bottom-up` on `SceneKind::Homothetic` skeletons, feature
    /// `quadratic-bottom-up-homothetic`.
    "quadratic-bottom-up-homothetic",
    trace_quadratic_bottom_up_homothetic,
    kernel::render_quadratic_bottom_up_leg_in::<kernel::HomotheticOnly>
);

/// The two entry points of a mixed-bounds module: `$trace`, one leg of
/// each pixel with `$render` (the bottom-up side; the Taylor side read from
/// the pixel's cache), and `$fill`, dispatched after it, the Taylor side of
/// each paused pixel's next step by `$fill_kernel` into that cache. Binding
/// 7 holds [`kernel::MixedLeg`]s; the other bindings are the leg entry
/// points'.
macro_rules! mixed_entry_points {
    ($(#[$doc:meta])* $feature:literal, $trace:ident, $render:path, $fill:ident, $fill_kernel:path) => {
        $(#[$doc])*
        #[cfg(feature = $feature)]
        #[allow(clippy::too_many_arguments)]
        #[spirv(compute(threads(8, 8)))]
        pub fn $trace(
            #[spirv(global_invocation_id)] id: UVec3,
            #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] constants: &Constants,
            #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] words: &[u32],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] floats: &[f32],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] blobs: &[PointBlob<f32>],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] pixels: &mut [PixelOut],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 5)] hits: &mut [HitOut],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 6)] roots: &mut [Root<f32>],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 7)] legs: &mut [kernel::MixedLeg],
        ) {
            let c = *constants;
            if id.x >= c.width || id.y >= c.height {
                return;
            }
            let i = (id.y * c.width + id.x) as usize;
            if i >= pixels.len() || i >= legs.len() {
                return;
            }
            let base = i * c.max_roots as usize;
            let mut leg = legs[i];
            let mut out = pixels[i];
            $render(
                &c, words, floats, blobs, id.x, id.y, roots, hits, base, &mut leg, &mut out,
            );
            legs[i] = leg;
            pixels[i] = out;
        }

        /// The Taylor side of the paused pixels' next steps (dispatched
        /// after each leg of the entry point above).
        #[cfg(feature = $feature)]
        #[allow(clippy::too_many_arguments)]
        #[spirv(compute(threads(8, 8)))]
        pub fn $fill(
            #[spirv(global_invocation_id)] id: UVec3,
            #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] constants: &Constants,
            #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] words: &[u32],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] floats: &[f32],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] blobs: &[PointBlob<f32>],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] pixels: &mut [PixelOut],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 5)] hits: &mut [HitOut],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 6)] roots: &mut [Root<f32>],
            #[spirv(storage_buffer, descriptor_set = 0, binding = 7)] legs: &mut [kernel::MixedLeg],
        ) {
            let c = *constants;
            if id.x >= c.width || id.y >= c.height {
                return;
            }
            let i = (id.y * c.width + id.x) as usize;
            if i >= pixels.len() || i >= legs.len() {
                return;
            }
            let base = i * c.max_roots as usize;
            let mut leg = legs[i];
            $fill_kernel(&c, words, floats, blobs, id.x, id.y, roots, hits, base, &mut leg);
            legs[i] = leg;
        }
    };
}

mixed_entry_points!(
    /// Forward linear mixed bounds (the tighter side of the bottom-up and
    /// Taylor bounds, `linear-mixed`) on `SceneKind::Blobs` scenes
    /// (`render_linear_mixed_leg_in::<BlobsOnly>`, with
    /// `taylor_linear_mixed_blobs` after each leg), feature
    /// `linear-mixed-blobs`.
    "linear-mixed-blobs",
    trace_linear_mixed_blobs,
    kernel::render_linear_mixed_leg_in::<kernel::BlobsOnly>,
    taylor_linear_mixed_blobs,
    kernel::fill_linear_taylor_in::<kernel::BlobsOnly>
);

mixed_entry_points!(
    /// `linear-mixed` on `SceneKind::BlobGroups` scenes, feature
    /// `linear-mixed-groups`.
    "linear-mixed-groups",
    trace_linear_mixed_groups,
    kernel::render_linear_mixed_leg_in::<kernel::GroupsOnly>,
    taylor_linear_mixed_groups,
    kernel::fill_linear_taylor_in::<kernel::GroupsOnly>
);

mixed_entry_points!(
    /// Forward quadratic mixed bounds (`quadratic-mixed`) on
    /// `SceneKind::Blobs` scenes (`render_quadratic_mixed_leg_in::<BlobsOnly>`,
    /// with `taylor_quadratic_mixed_blobs` after each leg), feature
    /// `quadratic-mixed-blobs`.
    "quadratic-mixed-blobs",
    trace_quadratic_mixed_blobs,
    kernel::render_quadratic_mixed_leg_in::<kernel::BlobsOnly>,
    taylor_quadratic_mixed_blobs,
    kernel::fill_quadratic_taylor_in::<kernel::BlobsOnly>
);

mixed_entry_points!(
    /// `quadratic-mixed` on `SceneKind::BlobGroups` scenes, feature
    /// `quadratic-mixed-groups`.
    "quadratic-mixed-groups",
    trace_quadratic_mixed_groups,
    kernel::render_quadratic_mixed_leg_in::<kernel::GroupsOnly>,
    taylor_quadratic_mixed_groups,
    kernel::fill_quadratic_taylor_in::<kernel::GroupsOnly>
);

mixed_entry_points!(
    /// `linear-mixed` on `SceneKind::Hrbf` scenes (no Taylor bound: the
    /// bottom-up side alone, as on the CPU; the Taylor side finds none),
    /// feature `linear-mixed-hrbf`.
    "linear-mixed-hrbf",
    trace_linear_mixed_hrbf,
    kernel::render_linear_mixed_leg_in::<kernel::HrbfOnly>,
    taylor_linear_mixed_hrbf,
    kernel::fill_linear_taylor_in::<kernel::HrbfOnly>
);

mixed_entry_points!(
    /// `quadratic-mixed` on `SceneKind::Hrbf` scenes, feature
    /// `quadratic-mixed-hrbf`.
    "quadratic-mixed-hrbf",
    trace_quadratic_mixed_hrbf,
    kernel::render_quadratic_mixed_leg_in::<kernel::HrbfOnly>,
    taylor_quadratic_mixed_hrbf,
    kernel::fill_quadratic_taylor_in::<kernel::HrbfOnly>
);

mixed_entry_points!(
    /// `linear-mixed` on `SceneKind::Homothetic` skeletons, feature
    /// `linear-mixed-homothetic`.
    "linear-mixed-homothetic",
    trace_linear_mixed_homothetic,
    kernel::render_linear_mixed_leg_in::<kernel::HomotheticOnly>,
    taylor_linear_mixed_homothetic,
    kernel::fill_linear_taylor_in::<kernel::HomotheticOnly>
);

mixed_entry_points!(
    /// `quadratic-mixed` on `SceneKind::Homothetic` skeletons, feature
    /// `quadratic-mixed-homothetic`.
    "quadratic-mixed-homothetic",
    trace_quadratic_mixed_homothetic,
    kernel::render_quadratic_mixed_leg_in::<kernel::HomotheticOnly>,
    taylor_quadratic_mixed_homothetic,
    kernel::fill_quadratic_taylor_in::<kernel::HomotheticOnly>
);

leg_entry_point!(
    /// [`trace_sphere`] for `SceneKind::Blobtree` scenes (the flat
    /// blobtrees of the `aggregate-*` scenes,
    /// `render_sphere_leg_in::<BlobtreeOnly>`), feature `sphere-blobtree`:
    /// a module of its own (beside `trace_sphere`, spirv-opt runs out of
    /// SPIR-V ids).
    "sphere-blobtree",
    trace_sphere_blobtree,
    kernel::render_sphere_leg_in::<kernel::BlobtreeOnly>
);

/// The body of the leg entry points: one leg of pixel `(id.x, id.y)` by
/// `render` (a kernel function, called directly: a generic, not a function
/// pointer), its leg and record written back.
#[cfg(any(
    feature = "sphere",
    feature = "sphere-blobtree",
    feature = "segment-blobs",
    feature = "segment-groups",
    feature = "linear-taylor-blobs",
    feature = "linear-taylor-groups",
    feature = "quadratic-taylor-blobs",
    feature = "quadratic-taylor-groups",
    feature = "linear-bottom-up-blobs",
    feature = "linear-bottom-up-groups",
    feature = "quadratic-bottom-up-blobs",
    feature = "quadratic-bottom-up-groups",
    feature = "segment-hrbf",
    feature = "linear-bottom-up-hrbf",
    feature = "quadratic-bottom-up-hrbf",
    feature = "sphere-homothetic",
    feature = "segment-homothetic",
    feature = "linear-taylor-homothetic",
    feature = "linear-bottom-up-homothetic",
    feature = "quadratic-bottom-up-homothetic"
))]
#[allow(clippy::too_many_arguments)]
fn leg_entry<R>(
    id: UVec3,
    constants: &Constants,
    words: &[u32],
    floats: &[f32],
    blobs: &[PointBlob<f32>],
    pixels: &mut [PixelOut],
    hits: &mut [HitOut],
    roots: &mut [Root<f32>],
    legs: &mut [PixelLeg],
    render: R,
) where
    R: kernel::LegKernel,
{
    let c = *constants;
    if id.x >= c.width || id.y >= c.height {
        return;
    }
    let i = (id.y * c.width + id.x) as usize;
    if i >= pixels.len() || i >= legs.len() {
        return;
    }
    let base = i * c.max_roots as usize;
    let mut leg = legs[i];
    let mut out = pixels[i];
    render(
        &c, words, floats, blobs, id.x, id.y, roots, hits, base, &mut leg, &mut out,
    );
    legs[i] = leg;
    pixels[i] = out;
}

/// `scalis-quadratic` and the per-primitive `interval` bisection on SCALIS
/// skeletons (`render_scalis_leg`), feature `scalis`, a module of its own:
/// the leg entry points' layout, with the `u32` buffer holding the
/// per-pixel offsets of the primitive lists, binding 2 the lists
/// (`PrimitiveHit<f32>`, built on the host), binding 3 the segments
/// (`ScalisSegment<f32>`) and binding 7 the pixels' resumable traces
/// (`ScalisLeg`, with their interval stacks).
#[cfg(feature = "scalis")]
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(8, 8)))]
pub fn trace_scalis(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] constants: &Constants,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] offsets: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] lists: &[PrimitiveHit<f32>],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] segments: &[ScalisSegment<f32>],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] pixels: &mut [PixelOut],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 5)] hits: &mut [HitOut],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 6)] roots: &mut [Root<f32>],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 7)] legs: &mut [ScalisLeg],
) {
    let c = *constants;
    if id.x >= c.width || id.y >= c.height {
        return;
    }
    let i = (id.y * c.width + id.x) as usize;
    if i >= pixels.len() || i >= legs.len() {
        return;
    }
    let base = i * c.max_roots as usize;
    let mut out = pixels[i];
    // the leg in place: its interval stack is 768 words
    kernel::render_scalis_leg(
        &c, offsets, lists, segments, id.x, id.y, roots, hits, base, &mut legs[i], &mut out,
    );
    pixels[i] = out;
}

/// The tight stages that `trace_scalis` legs left in their pixels' states
/// (`render_scalis_tight_leg`), feature `scalis`: `trace_scalis`'s
/// bindings, a pipeline of its own, dispatched after it.
#[cfg(feature = "scalis")]
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(8, 8)))]
pub fn trace_scalis_tight(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] constants: &Constants,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] offsets: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] lists: &[PrimitiveHit<f32>],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] segments: &[ScalisSegment<f32>],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] _pixels: &mut [PixelOut],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 5)] _hits: &mut [HitOut],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 6)] _roots: &mut [Root<f32>],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 7)] legs: &mut [ScalisLeg],
) {
    let c = *constants;
    if id.x >= c.width || id.y >= c.height {
        return;
    }
    let i = (id.y * c.width + id.x) as usize;
    if i >= legs.len() {
        return;
    }
    kernel::render_scalis_tight_leg(&c, offsets, lists, segments, id.x, id.y, &mut legs[i]);
}

/// The body of the tracing entry points: pixel `(id.x, id.y)` of the frame
/// in `constants`, traced by `render` (a kernel function, called directly:
/// a generic, not a function pointer), its record written to `pixels`.
#[cfg(feature = "trace")]
#[allow(clippy::too_many_arguments)]
fn trace_entry<R>(
    id: UVec3,
    constants: &Constants,
    words: &[u32],
    floats: &[f32],
    blobs: &[PointBlob<f32>],
    pixels: &mut [PixelOut],
    hits: &mut [HitOut],
    roots: &mut [Root<f32>],
    render: R,
) where
    R: Fn(
        &Constants,
        &[u32],
        &[f32],
        &[PointBlob<f32>],
        u32,
        u32,
        &mut [Root<f32>],
        &mut [HitOut],
        usize,
    ) -> PixelOut,
{
    let c = *constants;
    if id.x >= c.width || id.y >= c.height {
        return;
    }
    let i = (id.y * c.width + id.x) as usize;
    let base = i * c.max_roots as usize;
    let out = render(&c, words, floats, blobs, id.x, id.y, roots, hits, base);
    if i < pixels.len() {
        pixels[i] = out;
    }
}
