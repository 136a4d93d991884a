//! The wgpu host of boundtrace's GPU path: runs the tracer, compiled to
//! SPIR-V by rust-gpu (`crates/gpu-shader`, built by
//! `scripts/build-spirv.sh`), on a Vulkan adapter (lavapipe in CI, any GPU
//! for users), and returns the same [`Frame`] type as the CPU renderer.
//!
//! The shader is a thin wrapper: each invocation calls
//! [`boundtrace_gpu_kernel::render_sphere_leg`],
//! [`boundtrace_gpu_kernel::render_segment_leg_in`] (and its Taylor
//! siblings) or [`boundtrace_gpu_kernel::render_pixel`], which call the
//! tracer's
//! [`trace_sphere_resume_in`](boundtrace_tracer::trace_sphere_resume_in) /
//! [`trace_segment_resume_in`](boundtrace_tracer::trace_segment_resume_in) /
//! [`trace_pixel`](boundtrace_tracer::pixel::trace_pixel) and
//! [`normal`](boundtrace_tracer::normal) over the scene's flat data — the
//! same code the CPU runs. Scenes are buffers ([`GpuScene`]), so a new
//! scene never recompiles the shader.
//!
//! ```no_run
//! use boundtrace_gpu::{GpuScene, GpuTracer};
//! use boundtrace_tracer::Method;
//! use boundtrace_tracer::camera::Camera;
//! use boundtrace_tracer::render::RenderSettings;
//! use boundtrace_tracer::scenes::{DEFAULT_SEED, Scene};
//!
//! let gpu = GpuTracer::new()?; // needs a Vulkan adapter and the built module
//! let scene = Scene::<f32>::build("blobs", DEFAULT_SEED)?;
//! let data = GpuScene::from_scene(&scene)?;
//! let camera = Camera::framing(scene.bounds(), [0.0, 0.0, -1.0], 40.0, 1.0)?;
//! let settings = RenderSettings::new(64, 64, Method::Sphere)?;
//! let frame = gpu.render(&data, &camera, &settings)?;
//! frame.shaded_image().write_png("blobs-gpu.png")?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! **Status** (issue 9, open): every marching method runs on the GPU and
//! gives the CPU's frame: sphere tracing, segment tracing and the forward
//! linear and quadratic methods from Taylor, bottom-up and mixed bounds
//! (`linear-taylor`, `linear-bottom-up`, `linear-mixed`, and the same
//! three quadratic ones). The main module's `trace_sphere` and the leg
//! modules' `trace_segment_*`, `trace_linear_taylor_*`,
//! `trace_quadratic_taylor_*`, `trace_{linear,quadratic}_{bottom_up,mixed}_*`
//! and `trace_sphere_blobtree` (sphere tracing of the `aggregate-*`
//! blobtrees), and for the HRBF scenes (no global Lipschitz or Taylor
//! bound) `trace_segment_hrbf` (segment tracing with the CPU's bound, from
//! bottom-up lines:
//! [`trace_segment_lines_resume_in`](boundtrace_tracer::trace_segment_lines_resume_in))
//! and `trace_{linear,quadratic}_{bottom_up,mixed}_hrbf` (session 34),
//! and for the homothetic-distance skeletons of scene files
//! `trace_{sphere,segment,linear_taylor}_homothetic` (session 35; no
//! quadratic Taylor bound, as on the CPU) and
//! `trace_{linear,quadratic}_{bottom_up,mixed}_homothetic` (session 36),
//! entry points ([`leg_spirv_path`]) trace
//! each pixel in resumable legs
//! ([`boundtrace_gpu_kernel::render_sphere_leg_in`],
//! [`boundtrace_gpu_kernel::render_segment_leg_in`], …), and
//! [`GpuTracer::render`] dispatches until every pixel is done. On
//! lavapipe, llvmpipe stops every loop of an 8-lane group after 65,535
//! loop iterations in all, silently (and it runs every loop at least
//! once, also in code that no lane of the group takes: a loop in a
//! blobtree operator's code costs an iteration at every node, so the
//! shared code keeps such paths loop-free, e.g.
//! [`Real::powi_std`](boundtrace_ia_core::Real::powi_std)); a probe loop after each step sees
//! it, the step is undone and the pixel resumes in the next dispatch, so
//! the limit costs dispatches, never results (CI: `tests/difftest.rs`,
//! every pixel of both blob scenes in both modes, every leg method, and
//! of `aggregate-1` to `-3` by sphere tracing). Blobtrees also render
//! tiled ([`GpuScene::from_tile_programs`]): one pruned program per 8 × 8
//! tile, built on the host from the tile A-buffer's lists
//! ([`TilePrograms`]), so each workgroup evaluates only the primitives its
//! rays meet; the frame is its CPU twin's bit for bit, and `aggregate-4`
//! (11,110 primitives) renders that way on lavapipe (difftest
//! `sphere_matches_the_cpu_on_blobtrees_whole_and_tiled`; the CLI's GPU backend
//! renders blobtrees tiled). The tiles' programs are whole along each ray,
//! not the paper's per-depth ranges.
//! [`interval_probe`] and [`arith_probe`] check the driver's arithmetic
//! against the CPU's. The bottom-up and mixed modules are built without
//! spirv-opt (the driver inlines and optimises them; lavapipe does,
//! BENCHMARKS.md "GPU", session 28). A mixed module has two entry points:
//! `trace_{linear,quadratic}_mixed_*`, the legs with the bottom-up side of
//! each step's bound, which pause before a step until the Taylor side is
//! in the pixel's [`MixedLeg`], and `taylor_{linear,quadratic}_mixed_*`,
//! dispatched after each leg, which computes it
//! ([`boundtrace_tracer::fill_taylor_cache`]): two pipelines of one bound
//! each, where one with both took lavapipe ≈ 20 GB and 8-9 min to compile
//! (BENCHMARKS.md "GPU", sessions 28 and 32). `scalis-quadratic` and the
//! per-primitive `interval` bisection on SCALIS skeletons have a module of
//! their own with two entry points, `trace_scalis` and
//! [`SCALIS_TIGHT_ENTRY`] (built without spirv-opt): [`GpuScene::from_scene`]
//! takes the SCALIS scenes, and each frame's per-ray primitive lists (the
//! A-buffer of thesis Part III §1.5) are built on the host
//! ([`PrimitiveLists`]) and uploaded with the segments. `trace_scalis` runs
//! the tracer's
//! [`trace_scalis_resume_deferred_in`](boundtrace_tracer::scalis::trace_scalis_resume_deferred_in)
//! in resumable legs like the other leg methods (each pixel's interval
//! stack in its [`ScalisLeg`], 3,344 bytes: a frame of more pixels than
//! the device binds in one buffer is refused), leaving each interval its
//! ranges cannot decide to the tight stage, which `trace_scalis_tight`
//! runs in a dispatch of its own after each leg — two pipelines that a
//! driver inlining every call compiles in far less memory than the one
//! they were (BENCHMARKS.md "GPU", sessions 29-30). On the host the two
//! kernels give the CPU renderer's frames bit for bit, in one leg or in
//! legs of a few steps (unit test), and on lavapipe both methods give
//! them on every pixel (difftest, since session 33; a diagnostic unit
//! test compares the legs with the host's word for word). The
//! other methods (interval and affine on other scenes) live in the
//! `trace_pixels` entry point
//! ([`render_pixel`](boundtrace_gpu_kernel::render_pixel), shader feature
//! `trace`), which rust-gpu links but which is still far too large for a
//! driver that inlines every call; on a module without it
//! [`GpuTracer::render`] answers [`GpuError::MethodUnavailable`]
//! (BENCHMARKS.md "GPU").
//!
//! **Drivers.** Checked on lavapipe (CI) only. NVIDIA's Vulkan driver
//! 580 (H100, session 12; H200, session 22) runs the probes but crashes
//! (SIGSEGV in its NVVM back end) compiling every tracing entry point; the
//! cause is not yet found: not a stack overflow, not the phis of structs
//! holding pointers alone (BENCHMARKS.md "GPU", sessions 12 and 22). The
//! host rewrites rust-gpu's Vulkan memory model declaration to GLSL450
//! before the driver sees a module, since wgpu does not enable the
//! `vulkanMemoryModel` feature.
//!
//! Limits: `f32` only; the per-pixel root buffer of transparent mode holds
//! [`MAX_GPU_ROOTS`] roots (more is a [`GpuError::MaxRoots`]); scenes with
//! flat GPU data are the blob scenes (`blobs`, `blobs-sum`), `molecule`
//! (which lavapipe's loop limit makes slow, in many legs: see
//! [`GpuScene::from_scene`] and [`GpuError::LoopLimit`]) and the
//! `aggregate-*` blobtrees (sphere tracing only, in the `sphere-blobtree`
//! module; on lavapipe the 11,110-primitive `aggregate-4` ends in
//! [`GpuError::LoopLimit`] untiled, and renders tiled).
//!
//! # Soundness on a GPU
//! The interval code rounds outward from correctly rounded `+ − ×` (Vulkan
//! requires them) with the same exact-sum test as on the CPU; the host
//! decorates every float sum, difference, product and quotient of the
//! module `NoContraction` before the driver sees it, so that no driver
//! fuses or reassociates them. Quotients of `f32`s are computed in `f64`
//! and rounded once, which gives the correctly rounded quotient under
//! Vulkan's 2.5-ulp division. Square roots of `f32`s are rounded by
//! `ia-core` itself on SPIR-V (the driver's GLSL `Sqrt`, only a few ulp by
//! Vulkan's precision table and 0.92 ulp off on NVIDIA 580, is just the
//! estimate: one Newton step in `f64` and an exact midpoint test give the
//! correctly rounded root), so they equal the CPU's on every driver with
//! IEEE `f64` arithmetic ([`outward_probe`] checks the bounds against
//! exact results and the CPU's). `f32` exponentials (the `molecule`'s
//! Gaussian kernels) are `ia-core`'s own on SPIR-V too, within one step
//! of `e^x` without the driver's `Exp` (the CPU computes the same
//! `exp_f32`, so the molecule's frames are the CPU's bit for bit: the
//! kernels on the host and the difftests on lavapipe check it), and so
//! are `f32` logarithms, powers (`x^p` for `x > 0`), sines and cosines (`|x| < 2²⁸`; beyond, the
//! interval bound is `[−1, 1]`): `f64` series and one rounding, within one
//! step ([`transcendental_probe`], [`pow_probe`] and [`trig_probe`] check
//! the interval bounds against exact results on the driver in use). Only
//! `f64` transcendental functions remain the driver's (the GPU tracer
//! computes in `f32`). On lavapipe the GPU thus computes the CPU's bounds of the
//! blob scenes bit for bit ([`arith_probe`], [`outward_probe`] and the
//! difftests check it on the driver in use).
//! Subnormals are assumed preserved (Vulkan allows flushing them).

use boundtrace_fields::PointBlob;
use boundtrace_fields::scalis::{SCALIS_SEGMENT_WORDS, ScalisSegment};
use boundtrace_gpu_kernel::{
    Constants, HitOut, MixedLeg, PHASE_DONE, PHASE_SHADING, PixelLeg, PixelOut, ScalisLeg,
    WORKGROUP,
};
pub use boundtrace_gpu_kernel::{MAX_GPU_ROOTS, SceneKind};
use boundtrace_tracer::camera::Camera;
use boundtrace_tracer::camera::ray_box_span;
use boundtrace_tracer::pixel::PixelSetup;
use boundtrace_tracer::render::{Frame, Hit, Pixel, RenderError, RenderSettings};
use boundtrace_tracer::scalis::{PrimitiveHit, PrimitiveLists, check_segments};
use boundtrace_tracer::scenes::{Scene, SceneField};
use boundtrace_tracer::tile_programs::{TILE_SIZE, TilePrograms};
use boundtrace_tracer::{Method, Mode, RayStats, Side, Status, Trace};
use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

// A tile program serves the pixels of one workgroup.
const _: () = assert!(TILE_SIZE == WORKGROUP);

/// The command that builds the SPIR-V module (run from the repository root).
pub const BUILD_COMMAND: &str = "scripts/build-spirv.sh";

/// The environment variable naming the SPIR-V module explicitly.
pub const SPV_ENV: &str = "BOUNDTRACE_GPU_SPV";

/// The compute entry point that traces pixels with any GPU method (the
/// shader's `trace` feature).
const ENTRY: &str = "trace_pixels";

/// The compute entry point that traces pixels with sphere tracing (always
/// in the module).
const SPHERE_ENTRY: &str = "trace_sphere";

/// The leg modules: the method each traces in legs like [`SPHERE_ENTRY`],
/// on one scene kind, and its name in the shader's features, the module's
/// file name and its entry point (`segment-blobs`: feature
/// `segment-blobs`, `…-segment-blobs.spv`, `trace_segment_blobs`); see
/// [`leg_spirv_path`].
const LEG_MODULE_LIST: [(Method, SceneKind, &str); 29] = [
    (Method::Segment, SceneKind::Blobs, "segment-blobs"),
    (Method::Segment, SceneKind::BlobGroups, "segment-groups"),
    (
        Method::LinearTaylor,
        SceneKind::Blobs,
        "linear-taylor-blobs",
    ),
    (
        Method::LinearTaylor,
        SceneKind::BlobGroups,
        "linear-taylor-groups",
    ),
    (
        Method::QuadraticTaylor,
        SceneKind::Blobs,
        "quadratic-taylor-blobs",
    ),
    (
        Method::QuadraticTaylor,
        SceneKind::BlobGroups,
        "quadratic-taylor-groups",
    ),
    (Method::Sphere, SceneKind::Blobtree, "sphere-blobtree"),
    (
        Method::LinearBottomUp,
        SceneKind::Blobs,
        "linear-bottom-up-blobs",
    ),
    (
        Method::LinearBottomUp,
        SceneKind::BlobGroups,
        "linear-bottom-up-groups",
    ),
    (
        Method::QuadraticBottomUp,
        SceneKind::Blobs,
        "quadratic-bottom-up-blobs",
    ),
    (
        Method::QuadraticBottomUp,
        SceneKind::BlobGroups,
        "quadratic-bottom-up-groups",
    ),
    (Method::LinearMixed, SceneKind::Blobs, "linear-mixed-blobs"),
    (
        Method::LinearMixed,
        SceneKind::BlobGroups,
        "linear-mixed-groups",
    ),
    (
        Method::QuadraticMixed,
        SceneKind::Blobs,
        "quadratic-mixed-blobs",
    ),
    (
        Method::QuadraticMixed,
        SceneKind::BlobGroups,
        "quadratic-mixed-groups",
    ),
    // The HRBF scenes: segment tracing with the CPU's bound (bottom-up
    // lines), the bottom-up and the mixed methods (an HRBF has no global
    // Lipschitz or Taylor bound).
    (Method::Segment, SceneKind::Hrbf, "segment-hrbf"),
    (
        Method::LinearBottomUp,
        SceneKind::Hrbf,
        "linear-bottom-up-hrbf",
    ),
    (
        Method::QuadraticBottomUp,
        SceneKind::Hrbf,
        "quadratic-bottom-up-hrbf",
    ),
    // (their bottom-up side alone, as on the CPU)
    (Method::LinearMixed, SceneKind::Hrbf, "linear-mixed-hrbf"),
    (
        Method::QuadraticMixed,
        SceneKind::Hrbf,
        "quadratic-mixed-hrbf",
    ),
    // The homothetic-distance skeletons of scene files: a global and a
    // directional Lipschitz bound, no quadratic Taylor bound (as on the
    // CPU, whose answers every module's difftest compares).
    (Method::Sphere, SceneKind::Homothetic, "sphere-homothetic"),
    (Method::Segment, SceneKind::Homothetic, "segment-homothetic"),
    (
        Method::LinearTaylor,
        SceneKind::Homothetic,
        "linear-taylor-homothetic",
    ),
    (
        Method::LinearBottomUp,
        SceneKind::Homothetic,
        "linear-bottom-up-homothetic",
    ),
    (
        Method::QuadraticBottomUp,
        SceneKind::Homothetic,
        "quadratic-bottom-up-homothetic",
    ),
    (
        Method::LinearMixed,
        SceneKind::Homothetic,
        "linear-mixed-homothetic",
    ),
    (
        Method::QuadraticMixed,
        SceneKind::Homothetic,
        "quadratic-mixed-homothetic",
    ),
    // One module and entry point (`trace_scalis`) for both methods of the
    // pre-segmented SCALIS processing.
    (Method::ScalisQuadratic, SceneKind::Scalis, "scalis"),
    (Method::Interval, SceneKind::Scalis, "scalis"),
];

/// How many leg modules there are.
const LEG_MODULES: usize = LEG_MODULE_LIST.len();

/// The index of the leg module of `method` on `kind`, if there is one.
fn leg_slot(method: Method, kind: SceneKind) -> Option<usize> {
    LEG_MODULE_LIST
        .iter()
        .position(|&(m, k, _)| m == method && k == kind)
}

/// The method, scene kind and name (`segment-blobs`) of leg module `slot`.
fn leg_module(slot: usize) -> (Method, SceneKind, String) {
    let (method, kind, name) = LEG_MODULE_LIST[slot];
    (method, kind, name.to_string())
}

/// The entry point of leg module `slot` (`trace_segment_blobs`).
fn leg_entry(slot: usize) -> String {
    format!("trace_{}", leg_module(slot).2.replace('-', "_"))
}

/// An error of the GPU path.
#[derive(Debug)]
pub enum GpuError {
    /// No usable adapter (no Vulkan driver: install one, e.g. lavapipe,
    /// `apt-get install mesa-vulkan-drivers libvulkan1`).
    NoAdapter(String),
    /// The adapter refused to create a device.
    Device(String),
    /// The SPIR-V module is not at `path`; build it with [`BUILD_COMMAND`].
    ShaderMissing {
        /// Where it was looked for.
        path: PathBuf,
    },
    /// The SPIR-V module could not be read or was rejected.
    Shader(String),
    /// The scene has no flat GPU data.
    UnsupportedScene(String),
    /// Invalid render settings or bounds.
    Render(RenderError),
    /// Transparent mode asks for more than [`MAX_GPU_ROOTS`] roots per pixel.
    MaxRoots(u32),
    /// Running the shader or reading its results failed.
    Dispatch(String),
    /// `pixels` pixels made no progress in a dispatch: the work between two
    /// checks of the loop limit — one tracing step, or one iteration of the
    /// interval halvings or the bisection inside a step
    /// (`boundtrace_tracer::march::Inner`), or one normal — needs more
    /// loop iterations than the driver runs in one shader invocation
    /// (llvmpipe, lavapipe's compiler, ends every loop of a group of 8
    /// pixels after 65,535 iterations in all). A
    /// scene with fewer primitives, another method or mode, or another
    /// driver may trace it.
    LoopLimit {
        /// The pixels that made no progress.
        pixels: usize,
        /// Of those, the pixels already traced, with normals still to be
        /// written (the others are still tracing).
        shading: usize,
    },
    /// The module has no entry point for the method (only `trace_sphere`
    /// unless the shader was built with its `trace` feature), or the driver
    /// could not compile the entry point that has it.
    MethodUnavailable {
        /// The method asked for.
        method: Method,
        /// Why it cannot run.
        why: String,
    },
}

impl fmt::Display for GpuError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GpuError::NoAdapter(e) => write!(
                f,
                "gpu: no usable adapter ({e}); install a Vulkan driver \
                 (e.g. lavapipe: apt-get install mesa-vulkan-drivers libvulkan1)"
            ),
            GpuError::Device(e) => write!(f, "gpu: cannot create a device: {e}"),
            GpuError::ShaderMissing { path } => write!(
                f,
                "gpu: the SPIR-V module {} is missing; build it with `{BUILD_COMMAND}` \
                 (or set {SPV_ENV})",
                path.display()
            ),
            GpuError::Shader(e) => write!(f, "gpu: bad SPIR-V module: {e}"),
            GpuError::UnsupportedScene(e) => write!(f, "gpu: {e}"),
            GpuError::Render(e) => write!(f, "gpu: {e}"),
            GpuError::MaxRoots(n) => write!(
                f,
                "gpu: transparent mode keeps at most {MAX_GPU_ROOTS} roots per pixel, {n} asked"
            ),
            GpuError::Dispatch(e) => write!(f, "gpu: dispatch failed: {e}"),
            GpuError::LoopLimit { pixels, shading } => write!(
                f,
                "gpu: {pixels} pixels ({shading} of them shading) made no progress in a \
                 dispatch: the work between two checks of the loop limit (a tracing step, \
                 one iteration inside it, or one normal) of this scene needs more loop \
                 iterations than the driver allows in one shader invocation \
                 (llvmpipe/lavapipe: 65,535 per 8 pixels); use fewer primitives, another \
                 method or mode, or another driver"
            ),
            GpuError::MethodUnavailable { method, why } => {
                write!(
                    f,
                    "gpu: method `{method}` is not available on this GPU: {why}"
                )
            }
        }
    }
}

impl std::error::Error for GpuError {}

impl From<RenderError> for GpuError {
    fn from(e: RenderError) -> Self {
        GpuError::Render(e)
    }
}

/// Where [`GpuTracer::new`] looks for the module: `$BOUNDTRACE_GPU_SPV`,
/// else `$CARGO_TARGET_DIR/spirv/boundtrace-gpu-shader.spv` (the target
/// dir at run time, else at compile time, else the repository's
/// `target/`), as written by [`BUILD_COMMAND`].
pub fn default_spirv_path() -> PathBuf {
    if let Some(p) = std::env::var_os(SPV_ENV) {
        return PathBuf::from(p);
    }
    let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .or_else(|| option_env!("CARGO_TARGET_DIR").map(PathBuf::from))
        .map(|t| if t.is_absolute() { t } else { repo.join(t) })
        .unwrap_or_else(|| repo.join("target"));
    target.join("spirv").join("boundtrace-gpu-shader.spv")
}

/// Where [`GpuTracer::new`] looks for the module that traces `method` on
/// scenes of `kind` in legs (segment tracing and the forward Taylor
/// methods on the blob scenes: entry points `trace_segment_blobs`,
/// `trace_linear_taylor_groups`, …, built by [`BUILD_COMMAND`] into modules
/// of their own): beside [`default_spirv_path`],
/// `…/boundtrace-gpu-shader-segment-blobs.spv`,
/// `…-linear-taylor-groups.spv`, … (for `BOUNDTRACE_GPU_SPV=dir/x.spv`:
/// `dir/x-segment-blobs.spv`, …); `None` for other methods and kinds.
pub fn leg_spirv_path(method: Method, kind: SceneKind) -> Option<PathBuf> {
    Some(leg_path_beside(
        &default_spirv_path(),
        leg_slot(method, kind)?,
    ))
}

/// Leg module `slot` beside the main module `main`.
fn leg_path_beside(main: &Path, slot: usize) -> PathBuf {
    let stem = main
        .file_stem()
        .map_or_else(|| "boundtrace-gpu-shader".into(), |s| s.to_string_lossy());
    main.with_file_name(format!("{stem}-{}.spv", leg_module(slot).2))
}

/// A scene as GPU buffers: blobtree node words and parameters, or blobs
/// (with group ends for a union of groups), and its bounding box.
#[derive(Clone, Debug, PartialEq)]
pub struct GpuScene {
    kind: SceneKind,
    bounds: [[f32; 3]; 2],
    words: Vec<u32>,
    floats: Vec<f32>,
    blobs: Vec<PointBlob<f32>>,
    /// The segments of a SCALIS skeleton ([`SceneKind::Scalis`]).
    segments: Vec<ScalisSegment<f32>>,
    iso: f32,
    groups: u32,
    /// The global Lipschitz bound that replaces the blobs' own (`0`: none).
    lipschitz: f32,
    /// The image size the tile programs were built for (tiled blobtrees).
    tiles: Option<[u32; 2]>,
}

impl GpuScene {
    /// The flat data of a standard scene: `blobs` (union of blob groups),
    /// `blobs-sum` (one blob set) and `molecule` (one blob set of 500
    /// Gaussian atoms with its generator's global Lipschitz bound,
    /// [`Constants::lipschitz`]) and the `aggregate-*` blobtrees (node
    /// words and parameters as built, with the tree's Lipschitz bound as
    /// the CPU computes it; sphere tracing only, by the
    /// `sphere-blobtree` module, [`leg_spirv_path`]; primitives of every
    /// kind but gyroids and blobs), and the SCALIS skeletons
    /// (`scalis-tree`, `scalis-foam`, `scalis-random`: the segments, for
    /// `scalis-quadratic` and `interval` in the `scalis` module; the frame's
    /// primitive lists are built at each render), and the HRBF scenes
    /// (`hrbf-8`, `hrbf-17`: the centers and polynomial, for `segment` with
    /// the CPU's bottom-up bound and the bottom-up and mixed methods in the
    /// `*-hrbf` modules; an HRBF has no global Lipschitz or Taylor
    /// bound, so sphere tracing and the Taylor methods are unsupported on it,
    /// as on the CPU). Homothetic-distance skeletons (scene files) have
    /// GPU data too: the segments, the kernel and the scene's Lipschitz
    /// bound, for `sphere`, `segment`, `linear-taylor`, the bottom-up and
    /// the mixed methods in the `*-homothetic` modules (no quadratic
    /// Taylor bound, as on the CPU).
    ///
    /// A `molecule` field call loops over 500 atoms: lavapipe's llvmpipe
    /// allows 65,535 loop iterations per 8 pixels and dispatch, so its
    /// frames run in many legs, each step, each iteration inside a step
    /// and each normal checked against the limit (at most 4 field calls
    /// between two checks on the difftests' 8 × 8 frames). Measured there:
    /// the four leg methods render `molecule` in both modes and match the
    /// CPU; until session 21 the transparent frames of `sphere`, `segment`
    /// and `linear-taylor` ended in [`GpuError::LoopLimit`] (a step of up
    /// to 72 field calls); BENCHMARKS.md "GPU", sessions 16, 17 and 21.
    ///
    /// # Errors
    /// [`GpuError::UnsupportedScene`] for the other scenes: SCALIS
    /// skeletons with an infinite support (Cauchy kernels: no primitive
    /// lists), blobtrees with gyroid or blob primitives, and a scene whose
    /// global Lipschitz bound is not a positive number.
    pub fn from_scene(scene: &Scene<f32>) -> Result<Self, GpuError> {
        let bounds = scene.bounds();
        let unsupported = |why: &str| {
            Err(GpuError::UnsupportedScene(format!(
                "scene `{}` has no GPU data: {why}",
                scene.name()
            )))
        };
        let mut s = Self {
            kind: SceneKind::Blobs,
            bounds,
            words: Vec::new(),
            floats: Vec::new(),
            blobs: Vec::new(),
            segments: Vec::new(),
            iso: 0.0,
            groups: 0,
            lipschitz: 0.0,
            tiles: None,
        };
        match scene.field() {
            SceneField::Blobs(b) => {
                s.iso = b.iso();
                s.blobs = b.blobs().to_vec();
            }
            SceneField::BlobGroups(u) => {
                s.kind = SceneKind::BlobGroups;
                let children = u.children();
                let Some(first) = children.first() else {
                    return unsupported("a union without groups");
                };
                s.iso = first.iso();
                for g in children {
                    if g.iso() != s.iso {
                        return unsupported("groups with different iso-values");
                    }
                    s.blobs.extend_from_slice(g.blobs());
                    s.words.push(s.blobs.len() as u32);
                }
                s.groups = children.len() as u32;
            }
            SceneField::Blobtree(tree) => {
                // Validated when it was built (`FlatBlobtree`); the shader
                // decodes it without checks.
                let t = tree.as_ref();
                if !t.primitives_among::<boundtrace_fields::AlgebraicPrimitives>() {
                    return unsupported(
                        "it has gyroid or blob primitives, which the GPU's blobtree field \
                         leaves out (their transcendental functions would double the shader)",
                    );
                }
                let Some(l) = t
                    .lipschitz_bound::<f32>()
                    .filter(|l| *l > 0.0 && l.is_finite())
                else {
                    return unsupported("its Lipschitz bound is not a positive number");
                };
                s.kind = SceneKind::Blobtree;
                s.words = t.nodes().to_vec();
                s.floats = t.params().to_vec();
                s.lipschitz = l;
            }
            SceneField::Molecule(m) => {
                let l = m.bound();
                if !(l > 0.0 && l.is_finite()) {
                    return unsupported("its Lipschitz bound is not a positive number");
                }
                s.iso = m.field().iso();
                s.blobs = m.field().blobs().to_vec();
                s.lipschitz = l;
            }
            SceneField::Hrbf(h) => {
                // `SceneKind::Hrbf`'s layout: the centers' words, then the
                // polynomial; `groups` centers.
                s.kind = SceneKind::Hrbf;
                s.floats = h.center_words();
                s.floats.extend_from_slice(&h.poly());
                s.groups = h.centers().len() as u32;
            }
            SceneField::Scalis(w) => {
                let sk = w.field();
                if let Err(e) = check_segments(sk.segments()) {
                    return unsupported(&format!(
                        "its SCALIS segments have no primitive lists ({e})"
                    ));
                }
                s.kind = SceneKind::Scalis;
                s.iso = sk.iso();
                s.segments = sk.segments().to_vec();
            }
            SceneField::Homothetic(w) => {
                // `SceneKind::Homothetic`'s layout: the kernel's code, the
                // segments' words then the parameters; `groups` segments;
                // the scene's global Lipschitz bound (the CPU's
                // `WithLipschitz`), which the kernel uses only when `> 0`.
                let l = w.bound();
                if l.is_nan() || l <= 0.0 {
                    return unsupported("its Lipschitz bound is not a positive number");
                }
                let sk = w.field();
                let (code, params) = sk.parameter_words();
                s.kind = SceneKind::Homothetic;
                s.words = code.to_vec();
                s.floats = sk.segment_words();
                s.floats.extend_from_slice(&params);
                s.groups = sk.segment_count() as u32;
                s.lipschitz = l;
            }
        }
        Ok(s)
    }

    /// The tiled flat data of a blobtree scene: one program per 8 × 8
    /// tile ([`TilePrograms`], built from this scene's tree for the camera
    /// and image size of the frames to render), so that the pixels of a
    /// workgroup evaluate only the primitives whose ABVs their rays meet:
    /// the tile lists of synchronized tracing, whole along each ray. The
    /// frame equals the CPU twin's,
    /// [`render_tile_programs`](boundtrace_tracer::tile_programs::render_tile_programs)
    /// (same programs, same code); its surface the full tree's (the ABV
    /// property). Rendering it at another image size is refused.
    ///
    /// ```no_run
    /// use boundtrace_gpu::{GpuScene, GpuTracer};
    /// use boundtrace_tracer::Method;
    /// use boundtrace_tracer::camera::Camera;
    /// use boundtrace_tracer::render::RenderSettings;
    /// use boundtrace_tracer::scenes::{DEFAULT_SEED, Scene, SceneField};
    /// use boundtrace_tracer::tile_programs::TilePrograms;
    ///
    /// let scene = Scene::<f32>::build("aggregate-4", DEFAULT_SEED)?;
    /// let SceneField::Blobtree(tree) = scene.field() else { unreachable!() };
    /// let camera = Camera::framing(scene.bounds(), [0.0, 0.0, -1.0], 40.0, 1.0)?;
    /// let programs = TilePrograms::build(tree, &camera, scene.bounds(), 64, 64)?;
    /// let data = GpuScene::from_tile_programs(&scene, &programs)?;
    /// let settings = RenderSettings::new(64, 64, Method::Sphere)?;
    /// let frame = GpuTracer::new()?.render(&data, &camera, &settings)?;
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// As [`from_scene`](Self::from_scene), and
    /// [`GpuError::UnsupportedScene`] for a scene that is not a blobtree.
    pub fn from_tile_programs(
        scene: &Scene<f32>,
        programs: &TilePrograms,
    ) -> Result<Self, GpuError> {
        let mut s = Self::from_scene(scene)?;
        if s.kind != SceneKind::Blobtree {
            return Err(GpuError::UnsupportedScene(format!(
                "scene `{}` is not a blobtree: tile programs are blobtree programs",
                scene.name()
            )));
        }
        let g = programs.grid();
        s.words = programs.words().to_vec();
        s.groups = g.tiles_x;
        s.tiles = Some([g.width, g.height]);
        Ok(s)
    }

    /// The image size of a tiled scene's programs
    /// ([`from_tile_programs`](Self::from_tile_programs)); `None` when
    /// untiled.
    pub fn tiles(&self) -> Option<[u32; 2]> {
        self.tiles
    }

    /// The frame constants the shader reads for this scene, `camera` and
    /// `settings`, with `slots` root slots per pixel (no leg limit).
    fn constants(
        &self,
        camera: &Camera<f32>,
        settings: &RenderSettings<f32>,
        slots: u32,
    ) -> Constants {
        let setup = PixelSetup {
            camera: *camera,
            bounds: self.bounds,
            width: settings.width,
            height: settings.height,
            method: settings.method,
            mode: settings.mode,
            params: settings.params,
        };
        Constants {
            lipschitz: self.lipschitz,
            ..Constants::new(&setup, self.kind, self.iso, slots, self.groups)
        }
    }

    /// The kind of field the shader builds.
    pub fn kind(&self) -> SceneKind {
        self.kind
    }

    /// The box enclosing the surface.
    pub fn bounds(&self) -> [[f32; 3]; 2] {
        self.bounds
    }

    /// The words of the scene buffers (bindings 1 to 3) of a frame through
    /// `camera` with `settings`: node words or group ends, parameters and
    /// blobs; for a SCALIS skeleton the frame's primitive lists
    /// ([`scalis_lists`]), their offsets and the segments.
    fn buffers(&self, camera: &Camera<f32>, settings: &RenderSettings<f32>) -> [Vec<u32>; 3] {
        if self.kind == SceneKind::Scalis {
            let (offsets, lists) = scalis_lists(&self.segments, self.bounds, camera, settings);
            let segments = self.segments.iter().flat_map(|s| s.to_words()).collect();
            return [offsets, lists, segments];
        }
        [
            self.words.clone(),
            self.floats.iter().map(|x| x.to_bits()).collect(),
            blob_words(&self.blobs),
        ]
    }
}

/// The per-ray primitive lists of a SCALIS frame (the A-buffer of thesis
/// Part III §1.5, built on the host, in parallel: [`PrimitiveLists`]):
/// the offsets (`width·height + 1` words: pixel `i = y·width + x` has the
/// hits `offsets[i]..offsets[i + 1]`) and the hits' words
/// (`PrimitiveHit<f32>`: entry, exit, argmin, index). The rays are the
/// shader's (and the CPU renderer's): [`Camera::ray`] through each pixel,
/// clipped to the scene box by [`ray_box_span`]; a ray that misses the
/// box has no hits. The lists are complete: where the CPU renderer's
/// per-ray list (`SCALIS_LIST_CAPACITY` hits) would overflow and fall back
/// to segment tracing, the GPU still traces the pre-segmented processing.
fn scalis_lists(
    segments: &[ScalisSegment<f32>],
    bounds: [[f32; 3]; 2],
    camera: &Camera<f32>,
    settings: &RenderSettings<f32>,
) -> (Vec<u32>, Vec<u32>) {
    let (w, h) = (settings.width, settings.height);
    let mut rays = Vec::new();
    let mut which = Vec::with_capacity(w as usize * h as usize);
    for y in 0..h {
        for x in 0..w {
            let ray = camera.ray(x, y, w, h);
            match ray_box_span(&ray, &bounds) {
                Some(span) => {
                    which.push(Some(rays.len()));
                    rays.push((ray, span));
                }
                None => which.push(None),
            }
        }
    }
    let lists = PrimitiveLists::build(segments, &rays);
    let mut offsets = Vec::with_capacity(which.len() + 1);
    let mut words = Vec::with_capacity(lists.total_hits() * 4);
    offsets.push(0u32);
    for r in which {
        if let Some(r) = r {
            for hit in lists.hits(r) {
                words.extend_from_slice(&[
                    hit.entry.to_bits(),
                    hit.exit.to_bits(),
                    hit.argmin.to_bits(),
                    hit.index,
                ]);
            }
        }
        offsets.push((words.len() / 4) as u32);
    }
    (offsets, words)
}

/// `PointBlob<f32>` as the shader reads it (`#[repr(C)]`: center, weight,
/// kernel kind, degree, σ).
fn blob_words(blobs: &[PointBlob<f32>]) -> Vec<u32> {
    let mut w = Vec::with_capacity(blobs.len() * 7);
    for b in blobs {
        let c = b.center();
        let k = b.kernel();
        w.extend_from_slice(&[
            c[0].to_bits(),
            c[1].to_bits(),
            c[2].to_bits(),
            b.weight().to_bits(),
            k.kind() as u32,
            k.degree(),
            k.sigma().to_bits(),
        ]);
    }
    w
}

/// A wgpu device with the tracing pipelines.
pub struct GpuTracer {
    adapter: wgpu::AdapterInfo,
    device: wgpu::Device,
    queue: wgpu::Queue,
    /// The module's words, for the pipelines created on first use.
    module: Vec<u8>,
    /// The leg modules' words ([`leg_slot`]'s order), where there are
    /// some.
    leg_modules: [Option<Vec<u8>>; LEG_MODULES],
    /// The bind group layout shared by the tracing entry points.
    layout: wgpu::PipelineLayout,
    /// `trace_sphere`'s pipeline, created on first use like the others (a
    /// driver that cannot compile it leaves the other methods usable).
    sphere: OnceLock<Result<wgpu::ComputePipeline, String>>,
    /// The leg modules' pipelines ([`leg_slot`]'s order), created on first
    /// use (a driver takes about as long as for `trace_sphere`: only the
    /// renders of that method and kind pay).
    legs: [OnceLock<Result<wgpu::ComputePipeline, String>>; LEG_MODULES],
    /// [`SCALIS_TIGHT_ENTRY`]'s pipeline (dispatched after each
    /// `trace_scalis` leg), created on first use.
    scalis_tight: OnceLock<Result<wgpu::ComputePipeline, String>>,
    /// The mixed methods' Taylor pipelines (`taylor_*`, dispatched after
    /// each leg of their `trace_*`), by leg module, created on first use.
    taylor: [OnceLock<Result<wgpu::ComputePipeline, String>>; LEG_MODULES],
    /// Held while a pipeline created on first use compiles, and, on a CPU
    /// adapter, during a pipeline's first dispatch (lavapipe compiles its
    /// machine code then, in gigabytes: one at a time).
    compiling: std::sync::Mutex<()>,
    /// The pipelines (by address in `self`) dispatched at least once.
    dispatched: std::sync::Mutex<Vec<usize>>,
    /// `trace_pixels`' pipeline (every method), created on first use: a
    /// driver may take long or fail to compile it (lavapipe runs out of
    /// memory), so only renders that need it pay.
    general: OnceLock<Result<wgpu::ComputePipeline, String>>,
}

impl fmt::Debug for GpuTracer {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("GpuTracer")
            .field("adapter", &self.adapter.name)
            .field("backend", &self.adapter.backend)
            .finish()
    }
}

/// The shader's storage bindings (binding, read-only): constants, words,
/// floats, blobs; pixels, hits, the per-pixel root buffer (scratch,
/// `max_roots` [`Root`](boundtrace_tracer::Root)s of 2 words per pixel)
/// and `trace_sphere`'s per-pixel [`PixelLeg`]s.
const STORAGE_ENTRIES: [(u32, bool); 8] = [
    (0, true),
    (1, true),
    (2, true),
    (3, true),
    (4, false),
    (5, false),
    (6, false),
    (7, false),
];

/// Where the time of one GPU frame went
/// ([`GpuTracer::render_profiled`]), measured with the host's wall clock.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RenderProfile {
    /// The dispatches (legs) the frame took.
    pub dispatches: u32,
    /// From the first dispatch's submission until the GPU finished the
    /// last one: the tracing, with the read-backs of the legs' progress
    /// between dispatches, without buffer set-up, upload, the read-back of
    /// the results and the frame's assembly.
    pub dispatch: Duration,
    /// The whole call: checks, buffer set-up and upload, the dispatches,
    /// the read-back and the frame's assembly (the pipeline's first
    /// compilation too, on a method's first frame).
    pub total: Duration,
}

/// Words of a [`PixelLeg`].
const LEG_WORDS: usize = core::mem::size_of::<PixelLeg>() / 4;

/// The pipelines of a render: the tracing pipeline, whether it runs in
/// legs, and the pipeline dispatched after each of its legs.
type Pipelines<'a> = (
    &'a wgpu::ComputePipeline,
    bool,
    Option<&'a wgpu::ComputePipeline>,
);

/// The entry point that runs the tight stages `trace_scalis` legs leave
/// (dispatched after each of them, in the same module).
pub const SCALIS_TIGHT_ENTRY: &str = "trace_scalis_tight";

/// Words of a [`ScalisLeg`] (the SCALIS module's legs, with their
/// interval stacks).
const SCALIS_LEG_WORDS: usize = core::mem::size_of::<ScalisLeg>() / 4;

/// Words of a [`MixedLeg`] (the mixed methods' legs, with the Taylor
/// part of their next step's bound).
const MIXED_LEG_WORDS: usize = core::mem::size_of::<MixedLeg>() / 4;

/// The entry point dispatched after each leg of a mixed method's
/// `trace_*` entry point `entry` (`trace_linear_mixed_blobs` →
/// `taylor_linear_mixed_blobs`): the Taylor side of the paused pixels'
/// next steps, in the same module.
fn taylor_entry(entry: &str) -> String {
    format!("taylor_{}", entry.trim_start_matches("trace_"))
}

/// Which per-pixel leg record (binding 7) an entry point keeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum LegKind {
    /// [`PixelLeg`]: sphere, segment, Taylor and bottom-up methods.
    Pixel,
    /// [`MixedLeg`]: the mixed methods.
    Mixed,
    /// [`ScalisLeg`]: the SCALIS module.
    Scalis,
}

impl LegKind {
    /// The legs of `method` on scenes of `kind`.
    fn of(method: Method, kind: SceneKind) -> Self {
        if kind == SceneKind::Scalis {
            Self::Scalis
        } else if matches!(method, Method::LinearMixed | Method::QuadraticMixed) {
            Self::Mixed
        } else {
            Self::Pixel
        }
    }
}

/// A leg record's words and where its phase is in them.
#[derive(Clone, Copy, Debug)]
struct LegLayout {
    words: usize,
    phase_at: usize,
}

impl LegLayout {
    /// The legs of `kind`.
    fn of(kind: LegKind) -> Self {
        match kind {
            LegKind::Scalis => Self {
                words: SCALIS_LEG_WORDS,
                phase_at: core::mem::offset_of!(ScalisLeg, phase) / 4,
            },
            LegKind::Mixed => Self {
                words: MIXED_LEG_WORDS,
                phase_at: (core::mem::offset_of!(MixedLeg, leg)
                    + core::mem::offset_of!(PixelLeg, phase))
                    / 4,
            },
            LegKind::Pixel => Self {
                words: LEG_WORDS,
                phase_at: core::mem::offset_of!(PixelLeg, phase) / 4,
            },
        }
    }
}

impl GpuTracer {
    /// Selects an adapter (high-performance preference; `WGPU_BACKEND`
    /// and the other wgpu environment variables apply), creates a device
    /// and loads the module from [`default_spirv_path`].
    ///
    /// # Errors
    /// [`GpuError::ShaderMissing`] (naming [`BUILD_COMMAND`]) when the module
    /// is absent; [`GpuError::NoAdapter`] without a usable adapter; device
    /// or shader errors.
    pub fn new() -> Result<Self, GpuError> {
        let main = load_module()?;
        // The leg modules are optional: without one, its method on its
        // scene kind is a `MethodUnavailable` error naming the build
        // command.
        let main_path = default_spirv_path();
        let mut legs = Vec::new();
        for slot in 0..LEG_MODULES {
            let (method, kind, _) = leg_module(slot);
            match load_module_at(leg_path_beside(&main_path, slot)) {
                Ok(bytes) => legs.push((method, kind, bytes)),
                Err(GpuError::ShaderMissing { .. }) => {}
                Err(e) => return Err(e),
            }
        }
        let legs: Vec<_> = legs.iter().map(|(m, k, b)| (*m, *k, &b[..])).collect();
        Self::with_spirv_modules(&main, &legs)
    }

    /// As [`new`](Self::new), with the module's bytes given.
    ///
    /// # Errors
    /// As [`new`](Self::new); [`GpuError::Shader`] for bytes that are not a
    /// SPIR-V module with the `trace_sphere` entry point (a driver that
    /// cannot compile an entry point makes its method's renders fail with
    /// [`GpuError::MethodUnavailable`]).
    pub fn with_spirv(bytes: &[u8]) -> Result<Self, GpuError> {
        Self::with_spirv_modules(bytes, &[])
    }

    /// As [`with_spirv`](Self::with_spirv), with leg modules
    /// ([`leg_spirv_path`]): `(method, kind, bytes)` for the module that
    /// traces `method` on scenes of `kind`.
    ///
    /// # Errors
    /// As [`with_spirv`](Self::with_spirv); [`GpuError::Shader`] for a leg
    /// module that is not a SPIR-V module, or given for a method and kind
    /// that have none, or twice; also for any module whose storage buffers
    /// have another layout than this host's (a module built from other
    /// sources: it would read the scene and write the pixels wrongly,
    /// silently).
    pub fn with_spirv_modules(
        bytes: &[u8],
        legs: &[(Method, SceneKind, &[u8])],
    ) -> Result<Self, GpuError> {
        check_magic(bytes)?;
        check_layout_of(bytes, "the main module", LegKind::Pixel)?;
        let mut modules: [Option<Vec<u8>>; LEG_MODULES] = Default::default();
        for &(method, kind, m) in legs {
            let slot = leg_slot(method, kind).ok_or_else(|| {
                GpuError::Shader(format!(
                    "no leg module traces `{method}` on {kind:?} scenes (leg modules: {})",
                    (0..LEG_MODULES)
                        .map(|i| leg_module(i).2)
                        .collect::<Vec<_>>()
                        .join(", ")
                ))
            })?;
            if modules[slot].is_some() {
                return Err(GpuError::Shader(format!(
                    "two leg modules for `{method}` on {kind:?} scenes"
                )));
            }
            check_magic(m)?;
            check_layout_of(m, &leg_module(slot).2, LegKind::of(method, kind))?;
            modules[slot] = Some(m.to_vec());
        }
        let mut gpu = pollster::block_on(Self::create(bytes))?;
        gpu.leg_modules = modules;
        Ok(gpu)
    }

    async fn create(bytes: &[u8]) -> Result<Self, GpuError> {
        let (info, device, queue) = open_device().await?;
        let entries: Vec<wgpu::BindGroupLayoutEntry> = STORAGE_ENTRIES
            .iter()
            .map(|&(binding, read_only)| wgpu::BindGroupLayoutEntry {
                binding,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            })
            .collect();
        let group = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("boundtrace"),
            entries: &entries,
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("boundtrace"),
            bind_group_layouts: &[Some(&group)],
            immediate_size: 0,
        });
        if !entry_points(bytes).iter().any(|e| e == SPHERE_ENTRY) {
            return Err(GpuError::Shader(format!(
                "the module has no `{SPHERE_ENTRY}` entry point (an old build? run {BUILD_COMMAND})"
            )));
        }
        Ok(Self {
            adapter: info,
            device,
            queue,
            module: bytes.to_vec(),
            leg_modules: Default::default(),
            layout,
            sphere: OnceLock::new(),
            legs: Default::default(),
            scalis_tight: OnceLock::new(),
            taylor: Default::default(),
            compiling: std::sync::Mutex::new(()),
            dispatched: std::sync::Mutex::new(Vec::new()),
            general: OnceLock::new(),
        })
    }

    /// The methods the modules hold an entry point for, on at least one
    /// scene kind: sphere tracing always, a leg method when one of its leg
    /// modules (or `trace_pixels`) is there, and the bottom-up and mixed
    /// forward methods with `trace_pixels`. Whether the driver compiles
    /// them shows at [`prepare`](Self::prepare).
    pub fn methods(&self) -> Vec<Method> {
        let entries = self.entry_points();
        let general = entries.iter().any(|e| e == ENTRY);
        let mut methods = vec![Method::Sphere];
        for slot in 0..LEG_MODULES {
            let method = leg_module(slot).0;
            let present = general || entries.contains(&leg_entry(slot));
            if present && !methods.contains(&method) {
                methods.push(method);
            }
        }
        if general {
            for method in [
                Method::LinearBottomUp,
                Method::LinearMixed,
                Method::QuadraticBottomUp,
                Method::QuadraticMixed,
            ] {
                if !methods.contains(&method) {
                    methods.push(method);
                }
            }
        }
        methods
    }

    /// The names of the compute entry points of the module
    /// (`trace_sphere`, `interval_square`, `arith_ops`, `outward_ops`,
    /// `transcendental_ops`, `pow_ops`, `trig_ops`, and
    /// `trace_pixels` when built with the `trace` feature) and of the leg
    /// modules (`trace_segment_blobs`, `trace_linear_taylor_groups`, …, and
    /// their own probes), without repeats.
    pub fn entry_points(&self) -> Vec<String> {
        let mut all = entry_points(&self.module);
        for e in self
            .leg_modules
            .iter()
            .flatten()
            .flat_map(|m| entry_points(m))
        {
            if !all.contains(&e) {
                all.push(e);
            }
        }
        all
    }

    /// The pipeline that traces `method` on scenes of `kind`, whether
    /// it runs in legs, and the pipeline dispatched after each of its legs
    /// (SCALIS: [`SCALIS_TIGHT_ENTRY`]): `trace_sphere` for sphere tracing,
    /// the leg entry point of `method` and `kind` (in the main module of a
    /// custom build, else in its leg module), else `trace_pixels`; all but
    /// the first created on first use.
    fn pipeline(&self, method: Method, kind: SceneKind) -> Result<Pipelines<'_>, GpuError> {
        let unavailable = |why: String| GpuError::MethodUnavailable { method, why };
        let slot = leg_slot(method, kind);
        if method == Method::Sphere && slot.is_none() {
            return self
                .lazy_pipeline(&self.sphere, &self.module, SPHERE_ENTRY)
                .as_ref()
                .map(|p| (p, true, None))
                .map_err(|e| unavailable(e.clone()));
        }
        let entries = entry_points(&self.module);
        let has = |m: &[u8], e: &str| entry_points(m).iter().any(|x| x == e);
        if let Some(slot) = slot {
            let entry = leg_entry(slot);
            let module = if has(&self.module, &entry) {
                Some(&self.module)
            } else {
                self.leg_modules[slot].as_ref().filter(|m| has(m, &entry))
            };
            if let Some(module) = module {
                let follow = match LegKind::of(method, kind) {
                    LegKind::Scalis | LegKind::Mixed => {
                        let (cell, after) = if kind == SceneKind::Scalis {
                            (&self.scalis_tight, SCALIS_TIGHT_ENTRY.to_string())
                        } else {
                            (&self.taylor[slot], taylor_entry(&entry))
                        };
                        if !has(module, &after) {
                            return Err(unavailable(format!(
                                "the module with `{entry}` lacks `{after}`: rebuild it \
                                 ({BUILD_COMMAND})"
                            )));
                        }
                        let p = self.lazy_pipeline(cell, module, &after);
                        Some(p.as_ref().map_err(|e| unavailable(e.clone()))?)
                    }
                    LegKind::Pixel => None,
                };
                // one pipeline per entry point (both SCALIS methods share one)
                let first = LEG_MODULE_LIST
                    .iter()
                    .position(|&(_, _, m)| m == LEG_MODULE_LIST[slot].2)
                    .unwrap_or(slot);
                return self
                    .lazy_pipeline(&self.legs[first], module, &entry)
                    .as_ref()
                    .map(|p| (p, true, follow))
                    .map_err(|e| unavailable(e.clone()));
            }
        }
        if !entries.iter().any(|e| e == ENTRY) {
            let missing = match slot {
                Some(slot) => format!(
                    "; `{method}` on this scene kind is in {}, which is missing \
                     (`{BUILD_COMMAND}` builds it)",
                    leg_path_beside(&default_spirv_path(), slot).display(),
                ),
                None => String::new(),
            };
            // The methods of the modules on this scene kind.
            let mut here: Vec<String> = Vec::new();
            if matches!(kind, SceneKind::Blobs | SceneKind::BlobGroups) {
                here.push(format!("{} (`{SPHERE_ENTRY}`)", Method::Sphere));
            }
            for &(m, k, name) in &LEG_MODULE_LIST {
                if k == kind {
                    here.push(format!("{m} (`{name}`)"));
                }
            }
            return Err(unavailable(format!(
                "the modules trace {kind:?} scenes with {}{missing}; every method is in \
                 `{ENTRY}`, built by BOUNDTRACE_SHADER_FEATURES=sphere,trace {BUILD_COMMAND}, \
                 which drivers that inline every call (lavapipe) cannot compile yet \
                 (BENCHMARKS.md \"GPU\")",
                if here.is_empty() {
                    "no method".to_string()
                } else {
                    here.join(", ")
                }
            )));
        }
        self.lazy_pipeline(&self.general, &self.module, ENTRY)
            .as_ref()
            .map(|p| (p, false, None))
            .map_err(|e| unavailable(e.clone()))
    }

    /// The pipeline of `module`'s `entry` in `cell`, created on first use.
    fn lazy_pipeline<'a>(
        &'a self,
        cell: &'a OnceLock<Result<wgpu::ComputePipeline, String>>,
        module: &[u8],
        entry: &str,
    ) -> &'a Result<wgpu::ComputePipeline, String> {
        cell.get_or_init(|| {
            // One pipeline compilation at a time: lavapipe needs several
            // gigabytes for each.
            let _one = self
                .compiling
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            let p = pollster::block_on(tracing_pipeline(&self.device, &self.layout, module, entry));
            release_freed_memory();
            p
        })
    }

    /// Compiles the pipeline that renders `method` on scenes of `kind`
    /// now rather than on the first frame that needs it (a driver takes
    /// seconds to minutes for one), so that frames are timed without it.
    ///
    /// # Errors
    /// [`GpuError::MethodUnavailable`] as for [`render`](Self::render).
    pub fn prepare(&self, method: Method, kind: SceneKind) -> Result<(), GpuError> {
        self.pipeline(method, kind).map(|_| ())
    }

    /// The adapter in use (name, backend, device type: lavapipe reports
    /// `DeviceType::Cpu`).
    pub fn adapter_info(&self) -> &wgpu::AdapterInfo {
        &self.adapter
    }

    /// Renders `scene` through `camera` with `settings` (method, mode,
    /// parameters, size; `f32`), one shader invocation per pixel in 8 × 8
    /// workgroups, into the CPU renderer's [`Frame`].
    ///
    /// # Errors
    /// Invalid settings ([`GpuError::Render`]); more than [`MAX_GPU_ROOTS`]
    /// roots per pixel in transparent mode; [`GpuError::MethodUnavailable`]
    /// for a method other than [`Method::Sphere`] and the leg modules'
    /// ([`leg_spirv_path`]) on their scene kinds
    /// when the module lacks the `trace_pixels` entry point, or when the
    /// driver cannot compile the method's entry point;
    /// [`GpuError::LoopLimit`] when the work between two checks of the
    /// loop limit (a step, one iteration inside it, or a normal) of some
    /// pixel needs more loop iterations than the driver runs per
    /// invocation (none of the difftests' frames on lavapipe since session
    /// 21); device errors.
    pub fn render(
        &self,
        scene: &GpuScene,
        camera: &Camera<f32>,
        settings: &RenderSettings<f32>,
    ) -> Result<Frame<f32>, GpuError> {
        self.render_in_legs(scene, camera, settings, 0)
            .map(|(frame, _)| frame)
    }

    /// [`render`](Self::render), the methods that run in legs at most
    /// `leg_steps` steps per pixel and dispatch (`0`: no limit), with the
    /// number of dispatches the frame took: one for the `trace_pixels`
    /// methods; for the others one per leg (one on a driver without a loop limit
    /// when `leg_steps` is `0`; on lavapipe as many as its loop limit
    /// needs). The frame is the same whatever the legs. Short dispatches
    /// keep a GPU watchdog quiet on heavy frames, and show that resumed
    /// traces give the uninterrupted result (the difftests). Other methods
    /// ignore `leg_steps`.
    ///
    /// # Errors
    /// As [`render`](Self::render).
    pub fn render_in_legs(
        &self,
        scene: &GpuScene,
        camera: &Camera<f32>,
        settings: &RenderSettings<f32>,
        leg_steps: u32,
    ) -> Result<(Frame<f32>, u32), GpuError> {
        self.render_profiled(scene, camera, settings, leg_steps)
            .map(|(frame, profile)| (frame, profile.dispatches))
    }

    /// [`render_in_legs`](Self::render_in_legs), with where the time went
    /// ([`RenderProfile`]): the dispatches alone, and the whole call. The
    /// frame is the same.
    ///
    /// # Errors
    /// As [`render`](Self::render).
    pub fn render_profiled(
        &self,
        scene: &GpuScene,
        camera: &Camera<f32>,
        settings: &RenderSettings<f32>,
        leg_steps: u32,
    ) -> Result<(Frame<f32>, RenderProfile), GpuError> {
        let start = Instant::now();
        settings.validate()?;
        let b = scene.bounds;
        if !(0..3).all(|i| b[0][i].is_finite() && b[1][i].is_finite() && b[0][i] <= b[1][i]) {
            return Err(GpuError::Render(RenderError::Bounds));
        }
        let slots = match settings.mode {
            Mode::Opaque => 1,
            Mode::Transparent if settings.max_roots <= MAX_GPU_ROOTS => settings.max_roots,
            Mode::Transparent => return Err(GpuError::MaxRoots(settings.max_roots)),
        };
        if let Some([w, h]) = scene.tiles
            && [w, h] != [settings.width, settings.height]
        {
            return Err(GpuError::UnsupportedScene(format!(
                "the scene's tile programs were built for {w}x{h} pixels, the frame is {}x{}",
                settings.width, settings.height
            )));
        }
        let (pipeline, resumable, follow) = self.pipeline(settings.method, scene.kind)?;
        let c = Constants {
            leg_steps,
            ..scene.constants(camera, settings, slots)
        };
        let n = settings.width as usize * settings.height as usize;
        let data = scene.buffers(camera, settings);
        let (pix_words, hit_words, dispatches, dispatch) = self.run(
            (pipeline, follow),
            resumable,
            LegLayout::of(LegKind::of(settings.method, scene.kind)),
            &c,
            &data,
            n,
            n * slots as usize,
        )?;
        let mut pixels = Vec::with_capacity(n);
        let mut hits = Vec::new();
        for i in 0..n {
            let p = read_pixel(&pix_words[i * 9..i * 9 + 9]);
            let roots = p.roots.min(slots);
            for k in 0..roots as usize {
                let at = (i * slots as usize + k) * 5;
                hits.push(read_hit(&hit_words[at..at + 5])?);
            }
            pixels.push(Pixel {
                span: (p.has_span != 0).then_some(p.span),
                trace: Trace {
                    roots,
                    status: status_of(p.status)?,
                    t_reached: p.t_reached,
                    stats: RayStats {
                        steps: p.steps,
                        field_evals: p.field_evals,
                        bound_evals: p.bound_evals,
                    },
                },
            });
        }
        let frame = Frame::from_parts(*camera, *settings, pixels, hits)
            .ok_or_else(|| GpuError::Dispatch("inconsistent results read back".into()))?;
        let profile = RenderProfile {
            dispatches,
            dispatch,
            total: start.elapsed(),
        };
        Ok((frame, profile))
    }

    /// Uploads, dispatches (until every pixel is done, for a `resumable`
    /// entry point) and reads back the pixel and hit words; also the number
    /// of dispatches and the wall-clock time from the first submission to
    /// the end of the last dispatch.
    #[allow(clippy::too_many_arguments)]
    fn run(
        &self,
        (pipeline, follow): (&wgpu::ComputePipeline, Option<&wgpu::ComputePipeline>),
        resumable: bool,
        leg: LegLayout,
        c: &Constants,
        data: &[Vec<u32>; 3],
        pixels: usize,
        hits: usize,
    ) -> Result<(Vec<u32>, Vec<u32>, u32, Duration), GpuError> {
        use wgpu::util::DeviceExt;
        let dev = &self.device;
        let words_of = |w: &[u32]| -> Vec<u8> {
            // wgpu rejects empty bindings: at least one word.
            let mut v: Vec<u8> = w.iter().flat_map(|x| x.to_le_bytes()).collect();
            if v.is_empty() {
                v.extend_from_slice(&[0; 4]);
            }
            v
        };
        let storage = wgpu::BufferUsages::STORAGE;
        let input = |label: &str, data: Vec<u8>| {
            dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: &data,
                usage: storage,
            })
        };
        let inputs = [
            input("constants", words_of(&c.to_words())),
            input("words", words_of(&data[0])),
            input("floats", words_of(&data[1])),
            input("blobs", words_of(&data[2])),
        ];
        let pix_bytes = (pixels * 9 * 4) as u64;
        let hit_bytes = (hits.max(1) * 5 * 4) as u64;
        let output = |label: &str, size: u64| {
            dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: storage | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        };
        let readback = |label: &str, size: u64| {
            dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let outs = [output("pixels", pix_bytes), output("hits", hit_bytes)];
        // The tracer's root buffer: a window of `max_roots` slots per pixel.
        let roots = output("roots", (hits.max(1) * 2 * 4) as u64);
        // The per-pixel legs, zero-filled by wgpu (`PHASE_FRESH`).
        let leg_bytes = (pixels.max(1) * leg.words * 4) as u64;
        let limits = dev.limits();
        let most = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        if leg_bytes > most {
            return Err(GpuError::UnsupportedScene(format!(
                "the frame's {pixels} pixels need {leg_bytes} bytes of resumable trace state \
                 ({} bytes each), more than the device binds in one buffer ({most}): \
                 render fewer pixels",
                leg.words * 4
            )));
        }
        let legs = output("legs", leg_bytes);
        let backs = [
            readback("pixels-read", pix_bytes),
            readback("hits-read", hit_bytes),
        ];
        let legs_back = readback("legs-read", leg_bytes);
        let all: Vec<&wgpu::Buffer> = inputs
            .iter()
            .chain(outs.iter())
            .chain([&roots, &legs])
            .collect();
        let entries: Vec<wgpu::BindGroupEntry> = all
            .iter()
            .enumerate()
            .map(|(i, b)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: b.as_entire_binding(),
            })
            .collect();
        let scope = dev.push_error_scope(wgpu::ErrorFilter::Validation);
        let bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("boundtrace"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Dispatch(error_chain(&e)));
        }
        // A CPU adapter (lavapipe) compiles the pipeline's machine code at
        // its first dispatch, in several gigabytes (BENCHMARKS.md "GPU",
        // session 13): one such first dispatch at a time, and the memory
        // freed after it handed back.
        let cpu = self.adapter.device_type == wgpu::DeviceType::Cpu;
        let key = std::ptr::from_ref(pipeline) as usize;
        let first = cpu
            && !self
                .dispatched
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .contains(&key);
        let one_at_a_time = first.then(|| {
            self.compiling
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
        });
        // The leg methods run in legs: dispatch until every
        // pixel is done.
        let mut dispatches = 0u32;
        let mut progress = None;
        let start = Instant::now();
        loop {
            let scope = dev.push_error_scope(wgpu::ErrorFilter::Validation);
            let mut enc =
                dev.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
            // the leg, then (SCALIS) the tight stages it left or (mixed)
            // the Taylor side of the paused pixels' next steps, in order
            for p in [Some(pipeline), follow].into_iter().flatten() {
                let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
                pass.set_pipeline(p);
                pass.set_bind_group(0, &bind, &[]);
                pass.dispatch_workgroups(
                    c.width.div_ceil(WORKGROUP),
                    c.height.div_ceil(WORKGROUP),
                    1,
                );
            }
            if resumable {
                enc.copy_buffer_to_buffer(&legs, 0, &legs_back, 0, leg_bytes);
            }
            self.queue.submit([enc.finish()]);
            dispatches += 1;
            if let Some(e) = pollster::block_on(scope.pop()) {
                return Err(GpuError::Dispatch(error_chain(&e)));
            }
            if !resumable {
                dev.poll(wgpu::PollType::wait_indefinitely())
                    .map_err(|e| GpuError::Dispatch(e.to_string()))?;
                break;
            }
            let mut words = read_back(dev, &legs_back)?;
            words.truncate(pixels * leg.words);
            #[cfg(test)]
            tests::LEG_SNAPSHOTS.with(|s| {
                if let Some(v) = s.borrow_mut().as_mut() {
                    v.push(words.clone());
                }
            });
            let (pending, shading) = leg_progress(&words, leg);
            if pending == 0 {
                break;
            }
            // The legs are deterministic: a dispatch that changed no
            // pixel's leg would be repeated forever.
            if progress.as_ref() == Some(&words) {
                return Err(GpuError::LoopLimit {
                    pixels: pending,
                    shading,
                });
            }
            progress = Some(words);
        }
        let dispatch = start.elapsed();
        if first {
            release_freed_memory();
            self.dispatched
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .push(key);
        }
        drop(one_at_a_time);
        let mut enc = dev.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        enc.copy_buffer_to_buffer(&outs[0], 0, &backs[0], 0, pix_bytes);
        enc.copy_buffer_to_buffer(&outs[1], 0, &backs[1], 0, hit_bytes);
        self.queue.submit([enc.finish()]);
        let pixels = read_back(dev, &backs[0])?;
        let hits = read_back(dev, &backs[1])?;
        Ok((pixels, hits, dispatches, dispatch))
    }
}

/// The pixels not done and those of them in [`PHASE_SHADING`], from the
/// legs' words.
fn leg_progress(words: &[u32], layout: LegLayout) -> (usize, usize) {
    let mut pending = 0;
    let mut shading = 0;
    for leg in words.chunks_exact(layout.words) {
        let phase = leg[layout.phase_at];
        pending += usize::from(phase < PHASE_DONE);
        shading += usize::from(phase == PHASE_SHADING);
    }
    (pending, shading)
}

/// The tracing pipeline of `entry` (8 × 8 workgroups, the shared layout);
/// the driver's or wgpu's error as text.
async fn tracing_pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    bytes: &[u8],
    entry: &str,
) -> Result<wgpu::ComputePipeline, String> {
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let module = shader_module(device, bytes, entry, (WORKGROUP, WORKGROUP, 1));
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(entry),
        layout: Some(layout),
        module: &module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    });
    match scope.pop().await {
        Some(e) => Err(format!("entry point `{entry}`: {}", error_chain(&e))),
        None => Ok(pipeline),
    }
}

/// Hands the memory the allocator holds freed back to the system: a driver
/// that compiles a large pipeline on the CPU (lavapipe: its NIR when the
/// pipeline is created, its machine code at the first dispatch) frees
/// gigabytes that glibc keeps in its arenas otherwise, so that each
/// further pipeline adds to the peak.
fn release_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    #[allow(unsafe_code)]
    {
        unsafe extern "C" {
            /// glibc's `malloc_trim` (malloc.h).
            fn malloc_trim(pad: usize) -> i32;
        }
        // SAFETY: `malloc_trim` only returns free heap pages to the
        // system; it is thread-safe and has no preconditions.
        unsafe {
            malloc_trim(0);
        }
    }
}

/// The names of a SPIR-V module's entry points (`OpEntryPoint`), in
/// order; empty for words that are not a module.
fn entry_points(bytes: &[u8]) -> Vec<String> {
    let words = le_words(bytes);
    let mut names = Vec::new();
    if words.len() < 5 || words[0] != 0x0723_0203 {
        return names;
    }
    let mut i = 5;
    while i < words.len() {
        let (count, op) = ((words[i] >> 16) as usize, words[i] & 0xffff);
        if count == 0 || i + count > words.len() {
            break;
        }
        if op == 15 && count > 3 {
            // OpEntryPoint: execution model, function id, name (nul-terminated).
            let raw: Vec<u8> = words[i + 3..i + count]
                .iter()
                .flat_map(|w| w.to_le_bytes())
                .take_while(|&b| b != 0)
                .collect();
            names.push(String::from_utf8_lossy(&raw).into_owned());
        }
        if op == 54 {
            break; // OpFunction: the entry points come before every function
        }
        i += count;
    }
    names
}

/// Selects an adapter (high-performance preference; the wgpu environment
/// variables such as `WGPU_BACKEND` apply) and opens a device.
async fn open_device() -> Result<(wgpu::AdapterInfo, wgpu::Device, wgpu::Queue), GpuError> {
    let instance =
        wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter = instance
        .request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: None,
            apply_limit_buckets: false,
        })
        .await
        .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
    let info = adapter.get_info();
    // The `trace` module declares the Int8, Int64 and Float64 capabilities
    // (see crates/gpu-builder): request the matching features where the
    // adapter has them (without them its pipeline fails to build, reported
    // as a shader error).
    let wide = wgpu::Features::SHADER_F64 | wgpu::Features::SHADER_INT64;
    let (device, queue) = adapter
        .request_device(&wgpu::DeviceDescriptor {
            label: Some("boundtrace"),
            required_features: adapter.features() & (wgpu::Features::PASSTHROUGH_SHADERS | wide),
            required_limits: adapter.limits(),
            ..Default::default()
        })
        .await
        .map_err(|e| GpuError::Device(e.to_string()))?;
    Ok((info, device, queue))
}

/// The shader module: passed through to the driver when the device allows
/// it (wgpu's naga SPIR-V front end rejects the infinite float constants of
/// the interval code), else through naga.
fn shader_module(
    device: &wgpu::Device,
    bytes: &[u8],
    entry: &str,
    workgroup: (u32, u32, u32),
) -> wgpu::ShaderModule {
    let words = le_words(bytes);
    let words = forbid_contraction(&glsl450_memory_model(&words));
    if !device
        .features()
        .contains(wgpu::Features::PASSTHROUGH_SHADERS)
    {
        return device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("boundtrace-gpu-shader"),
            source: wgpu::ShaderSource::SpirV(words.into()),
        });
    }
    let desc = wgpu::ShaderModuleDescriptorPassthrough {
        label: Some("boundtrace-gpu-shader"),
        entry_points: vec![wgpu::PassthroughShaderEntryPoint {
            name: entry.to_owned().into(),
            workgroup_size: workgroup,
        }]
        .into(),
        spirv: Some(words.into()),
        ..Default::default()
    };
    // SAFETY: the bytes are a SPIR-V module (magic checked by
    // `load_module`/`with_spirv`) produced by rust-gpu, whose build runs
    // spirv-val on it; its bindings match the explicit layouts given to the
    // pipelines.
    #[allow(unsafe_code)]
    unsafe {
        device.create_shader_module_passthrough(desc)
    }
}

/// The module with every float product, sum and difference decorated
/// `NoContraction`.
///
/// Without it a driver may fuse `a·b + c` into one fused multiply-add
/// or reassociate sums (without the decoration Vulkan allows relaxations
/// beyond a CPU compiler's fast-math), which would change the values the
/// GPU computes and break `ia-core`'s exact-sum test (TwoSum): the GPU
/// must evaluate the Rust expressions as written, as the CPU does, for
/// the same bounds and the same steps. rust-gpu 0.11 emits no such
/// decorations, so the host adds them: `OpDecorate %r NoContraction` for
/// each result `%r` of `OpFMul`, `OpFAdd`, `OpFSub` and `OpFDiv`, placed before the
/// module's first annotation. A module that is not valid SPIR-V is
/// returned unchanged (the driver rejects it later with its own error).
fn forbid_contraction(words: &[u32]) -> Vec<u32> {
    const OP_DECORATE: u32 = 71;
    const NO_CONTRACTION: u32 = 42;
    // OpFAdd, OpFSub, OpFMul, OpFDiv: `opcode | result type | result | a | b`.
    const FLOAT_OPS: [u32; 4] = [129, 131, 133, 136];
    let mut results = Vec::new();
    let mut first_annotation = None;
    let mut i = 5;
    while i < words.len() {
        let (len, op) = ((words[i] >> 16) as usize, words[i] & 0xffff);
        if len == 0 || i + len > words.len() {
            return words.to_vec();
        }
        // The annotation opcodes: OpDecorate … OpGroupMemberDecorate,
        // OpDecorateId, OpDecorateString, OpMemberDecorateString.
        if first_annotation.is_none() && matches!(op, 71..=75 | 332 | 5632 | 5633) {
            first_annotation = Some(i);
        }
        if FLOAT_OPS.contains(&op) && len == 5 {
            results.push(words[i + 2]);
        }
        i += len;
    }
    let Some(at) = first_annotation else {
        return words.to_vec();
    };
    let mut out = Vec::with_capacity(words.len() + 3 * results.len());
    out.extend_from_slice(&words[..at]);
    for r in results {
        out.extend_from_slice(&[(3 << 16) | OP_DECORATE, r, NO_CONTRACTION]);
    }
    out.extend_from_slice(&words[at..]);
    out
}

/// The module with the GLSL450 memory model in place of the Vulkan one,
/// where that changes nothing the module does.
///
/// rust-gpu 0.11 declares the Vulkan memory model (capability
/// `VulkanMemoryModel`, extension `SPV_KHR_vulkan_memory_model`) in every
/// Vulkan module, but wgpu 30 enables the device's `vulkanMemoryModel`
/// feature only for its experimental cooperative matrices. A module that
/// declares the capability without the feature breaks a valid-usage rule
/// (`VUID-VkShaderModuleCreateInfo-pCode-01091`, reported by the Khronos
/// validation layer), and NVIDIA's driver 580 crashed (SIGSEGV in its
/// SPIR-V compiler) creating the tracing pipelines of such modules
/// (BENCHMARKS.md "GPU", session 12). Our shaders use no barrier, no
/// atomic and no memory operand that only the Vulkan model defines, and
/// for such a module the two models mean the same; a module that uses
/// any (`OpControlBarrier`, `OpMemoryBarrier`, an atomic, or a load,
/// store or copy with `MakePointerAvailable`, `MakePointerVisible` or
/// `NonPrivatePointer`) is returned unchanged, as is one that is not
/// valid SPIR-V.
fn glsl450_memory_model(words: &[u32]) -> Vec<u32> {
    const OP_EXTENSION: u32 = 10;
    const OP_MEMORY_MODEL: u32 = 14;
    const OP_CAPABILITY: u32 = 17;
    const VULKAN_MEMORY_MODEL: u32 = 5345;
    const MEMORY_MODEL_VULKAN: u32 = 3;
    const MEMORY_MODEL_GLSL450: u32 = 1;
    // MakePointerAvailable | MakePointerVisible | NonPrivatePointer.
    const VULKAN_ONLY_ACCESS: u32 = 0x8 | 0x10 | 0x20;
    let extension: Vec<u32> = {
        // A literal string: nul-terminated, padded with nuls to whole words.
        let mut b = b"SPV_KHR_vulkan_memory_model\0".to_vec();
        b.resize(b.len().div_ceil(4) * 4, 0);
        b.chunks_exact(4)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect()
    };
    if words.len() < 5 {
        return words.to_vec();
    }
    let mut out = Vec::with_capacity(words.len());
    out.extend_from_slice(&words[..5]);
    let mut i = 5;
    while i < words.len() {
        let (len, op) = ((words[i] >> 16) as usize, words[i] & 0xffff);
        if len == 0 || i + len > words.len() {
            return words.to_vec();
        }
        let inst = &words[i..i + len];
        let access = match op {
            // OpLoad: type, result, pointer, [access]; OpStore: pointer,
            // object, [access]; OpCopyMemory(Sized): target, source,
            // [size], [access]…
            61 => inst.get(4).copied(),
            62 | 63 => inst.get(3).copied(),
            64 => inst.get(4).copied(),
            _ => None,
        };
        // OpControlBarrier, OpMemoryBarrier, OpAtomicLoad … OpAtomicXor,
        // OpAtomicFlagTestAndSet/Clear, OpAtomicFMinEXT/FMaxEXT/FAddEXT.
        let synchronises = matches!(op, 224..=242 | 318 | 319 | 5614 | 5615 | 6035);
        if synchronises || access.is_some_and(|a| a & VULKAN_ONLY_ACCESS != 0) {
            return words.to_vec();
        }
        match op {
            OP_CAPABILITY if inst.get(1) == Some(&VULKAN_MEMORY_MODEL) => {}
            OP_EXTENSION if inst[1..] == extension[..] => {}
            OP_MEMORY_MODEL if len == 3 && inst[2] == MEMORY_MODEL_VULKAN => {
                out.extend_from_slice(&[inst[0], inst[1], MEMORY_MODEL_GLSL450]);
            }
            _ => out.extend_from_slice(inst),
        }
        i += len;
    }
    out
}

/// How a module lays out the storage buffer bound at one binding of
/// descriptor set 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum BufferLayout {
    /// A runtime array with this stride in bytes.
    Array(u32),
    /// A struct of this size in bytes (its last member's offset and size).
    Struct(u32),
}

/// The layouts this host gives the tracing entry points' buffers
/// ([`STORAGE_ENTRIES`]): the constants, the scene's words, floats and
/// blobs, then pixels, hits, roots and legs.
/// With `scalis`, those of the SCALIS module
/// (`trace_scalis`): binding 2 holds the frame's primitive lists
/// (`PrimitiveHit<f32>`), binding 3 the segments (`ScalisSegment<f32>`,
/// [`SCALIS_SEGMENT_WORDS`] words each).
fn host_layouts_of(legs: LegKind) -> [(u32, BufferLayout); 8] {
    use core::mem::size_of;
    let size = |n: usize| n as u32;
    let scalis = legs == LegKind::Scalis;
    let legs = 4 * LegLayout::of(legs).words;
    let (floats, blobs) = if scalis {
        (
            BufferLayout::Array(size(size_of::<PrimitiveHit<f32>>())),
            BufferLayout::Array(size(4 * SCALIS_SEGMENT_WORDS)),
        )
    } else {
        (BufferLayout::Array(4), BufferLayout::Array(size(7 * 4)))
    };
    [
        (0, BufferLayout::Struct(size(size_of::<Constants>()))),
        (1, BufferLayout::Array(4)),
        (2, floats),
        (3, blobs),
        (4, BufferLayout::Array(size(size_of::<PixelOut>()))),
        (5, BufferLayout::Array(size(size_of::<HitOut>()))),
        (
            6,
            BufferLayout::Array(size(size_of::<boundtrace_tracer::Root<f32>>())),
        ),
        (7, BufferLayout::Array(size(legs))),
    ]
}

/// The layout of every storage variable of descriptor set 0 in the
/// module: `(binding, layout)` (several variables may share a binding:
/// the probes use bindings 0–2 with arrays of their own). Empty for words
/// that are not a readable module.
fn module_layouts(words: &[u32]) -> Vec<(u32, BufferLayout)> {
    use std::collections::HashMap;
    // OpDecorate ids: Binding, DescriptorSet, ArrayStride.
    let (mut binding, mut set, mut stride) = (HashMap::new(), HashMap::new(), HashMap::new());
    let mut offsets: HashMap<(u32, u32), u32> = HashMap::new();
    // Types: id → (opcode, operands after the result id).
    let mut types: HashMap<u32, (u32, Vec<u32>)> = HashMap::new();
    let mut constants: HashMap<u32, u32> = HashMap::new();
    let mut variables = Vec::new();
    let mut i = 5;
    while i < words.len() {
        let (len, op) = ((words[i] >> 16) as usize, words[i] & 0xffff);
        if len == 0 || i + len > words.len() {
            return Vec::new();
        }
        let w = &words[i + 1..i + len];
        match op {
            // OpDecorate target decoration literal.
            71 if w.len() == 3 => {
                let map = match w[1] {
                    33 => &mut binding,
                    34 => &mut set,
                    6 => &mut stride,
                    _ => {
                        i += len;
                        continue;
                    }
                };
                map.insert(w[0], w[2]);
            }
            // OpMemberDecorate struct member Offset value.
            72 if w.len() == 4 && w[2] == 35 => {
                offsets.insert((w[0], w[1]), w[3]);
            }
            // OpTypeInt, OpTypeFloat, OpTypeVector, OpTypeArray,
            // OpTypeRuntimeArray, OpTypeStruct, OpTypePointer.
            21 | 22 | 23 | 28 | 29 | 30 | 32 if !w.is_empty() => {
                types.insert(w[0], (op, w[1..].to_vec()));
            }
            // OpConstant type result value (array lengths).
            43 if w.len() == 3 => {
                constants.insert(w[1], w[2]);
            }
            // OpVariable type result StorageBuffer (12).
            59 if w.len() >= 3 && w[2] == 12 => variables.push((w[0], w[1])),
            _ => {}
        }
        i += len;
    }
    // Sizes in bytes, with a depth cap against malformed (cyclic) types.
    fn size_of_type(
        id: u32,
        depth: u32,
        types: &HashMap<u32, (u32, Vec<u32>)>,
        stride: &HashMap<u32, u32>,
        offsets: &HashMap<(u32, u32), u32>,
        constants: &HashMap<u32, u32>,
    ) -> Option<u32> {
        let (op, w) = types.get(&id)?;
        if depth > 16 {
            return None;
        }
        let inner = |t: u32| size_of_type(t, depth + 1, types, stride, offsets, constants);
        match (op, w.as_slice()) {
            (21 | 22, [width, ..]) => Some(width / 8),
            (23, [component, count]) => Some(inner(*component)? * count),
            (28, [_, length]) => Some(stride.get(&id)? * constants.get(length)?),
            (30, members) if !members.is_empty() => {
                let last = members.len() as u32 - 1;
                Some(offsets.get(&(id, last))? + inner(*members.last()?)?)
            }
            _ => None,
        }
    }
    let mut out = Vec::new();
    for (pointer, var) in variables {
        let (Some(&b), Some(0)) = (binding.get(&var), set.get(&var).copied()) else {
            continue;
        };
        // pointer → Block struct → its one member.
        let Some((32, p)) = types.get(&pointer) else {
            continue;
        };
        let Some((30, block)) = p.get(1).and_then(|t| types.get(t)) else {
            continue;
        };
        let Some(&member) = block.first() else {
            continue;
        };
        let layout = match types.get(&member) {
            Some((29, _)) => stride.get(&member).map(|&s| BufferLayout::Array(s)),
            Some((30, _)) => size_of_type(member, 0, &types, &stride, &offsets, &constants)
                .map(BufferLayout::Struct),
            _ => None,
        };
        if let Some(layout) = layout {
            out.push((b, layout));
        }
    }
    out
}

/// Fails when a storage buffer of the module has the same kind of layout
/// as this host's at its binding (array or struct) but another stride or
/// size: a module built from other sources than this host.
#[cfg(test)]
fn check_layout(bytes: &[u8], what: &str) -> Result<(), GpuError> {
    check_layout_of(bytes, what, LegKind::Pixel)
}

/// [`check_layout`] against [`host_layouts_of`]`(legs)`.
fn check_layout_of(bytes: &[u8], what: &str, legs: LegKind) -> Result<(), GpuError> {
    let words = le_words(bytes);
    let host = host_layouts_of(legs);
    for (b, layout) in module_layouts(&words) {
        let Some(&(_, want)) = host.iter().find(|(hb, _)| *hb == b) else {
            continue;
        };
        let same_kind = matches!(
            (layout, want),
            (BufferLayout::Array(_), BufferLayout::Array(_))
                | (BufferLayout::Struct(_), BufferLayout::Struct(_))
        );
        if same_kind && layout != want {
            return Err(GpuError::Shader(format!(
                "{what} was built from other sources than this host: its buffer at \
                 binding {b} is {layout:?} bytes, the host's {want:?}; rebuild the modules \
                 ({BUILD_COMMAND})"
            )));
        }
    }
    Ok(())
}

/// Little-endian 32-bit words of `bytes` (a SPIR-V module, a mapped
/// buffer); a trailing partial word is dropped.
fn le_words(bytes: &[u8]) -> Vec<u32> {
    bytes
        .chunks_exact(4)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect()
}

/// Reads the module from [`default_spirv_path`].
fn load_module() -> Result<Vec<u8>, GpuError> {
    load_module_at(default_spirv_path())
}

/// The module at `path`, checked for SPIR-V's magic number.
fn load_module_at(path: PathBuf) -> Result<Vec<u8>, GpuError> {
    if !path.is_file() {
        return Err(GpuError::ShaderMissing { path });
    }
    let bytes = std::fs::read(&path)
        .map_err(|e| GpuError::Shader(format!("cannot read {}: {e}", path.display())))?;
    check_magic(&bytes)?;
    Ok(bytes)
}

/// [`GpuError::Shader`] unless `bytes` look like a SPIR-V module.
fn check_magic(bytes: &[u8]) -> Result<(), GpuError> {
    if bytes.len() < 20 || bytes.len() % 4 != 0 || bytes[..4] != [0x03, 0x02, 0x23, 0x07] {
        return Err(GpuError::Shader(
            "not a SPIR-V module (bad magic or size)".into(),
        ));
    }
    Ok(())
}

/// The toolchain probe: runs the module's `interval_square` entry point,
/// `x ↦ hi([x, x + 1]²)` in `boundtrace-ia-core`'s outward-rounded interval
/// arithmetic compiled to SPIR-V, on `xs`, and returns the results with the
/// adapter used. The same Rust code on the CPU must give the same floats.
///
/// # Errors
/// As [`GpuTracer::new`].
pub fn interval_probe(xs: &[f32]) -> Result<(Vec<f32>, wgpu::AdapterInfo), GpuError> {
    let (words, info) = probe("interval_square", xs, xs.len() as u32)?;
    Ok((words.into_iter().map(f32::from_bits).collect(), info))
}

/// Runs the module's `arith_ops` entry point on `pairs`: `[a / b, a · b,
/// a + b, a − b]` for each `[a, b]`, as the driver computes them, with the
/// adapter used. The interval code's outward rounding assumes `× + −`
/// correctly rounded (Vulkan requires it) and widens quotients on the GPU
/// by Vulkan's allowed 2.5 ulp (`ia-core`'s `math`); this shows what a
/// driver actually does.
///
/// # Errors
/// As [`interval_probe`].
pub fn arith_probe(pairs: &[[f32; 2]]) -> Result<(Vec<[f32; 4]>, wgpu::AdapterInfo), GpuError> {
    pair_probe("arith_ops", pairs)
}

/// Runs the module's `outward_ops` entry point on `pairs`: `[div_down(a,
/// b), div_up(a, b), sqrt_down(|a|), sqrt_up(|a|)]` for each `[a, b]`,
/// `ia-core`'s outward-rounded quotient and square-root bounds
/// (`boundtrace_ia_core::round`) as the module computes them on the
/// driver, with the adapter used. Every interval quotient and square root
/// on the GPU is built from these; `tests/probe.rs` checks that they
/// enclose the exact results.
///
/// # Errors
/// As [`interval_probe`].
pub fn outward_probe(pairs: &[[f32; 2]]) -> Result<(Vec<[f32; 4]>, wgpu::AdapterInfo), GpuError> {
    pair_probe("outward_ops", pairs)
}

/// Runs the module's `transcendental_ops` entry point on `pairs`: the
/// bounds `[exp_lo, exp_hi, ln_lo, ln_hi]` of `ia-core`'s
/// `Interval::exp([a, a])` and `Interval::ln([|a|, |a|])` for each
/// `[a, b]` (`b` unused), as the module computes them on the driver
/// (`ia-core`'s own `f32` `exp` and `ln` on SPIR-V), with the adapter
/// used; `tests/probe.rs` checks that they enclose the exact results.
///
/// # Errors
/// As [`interval_probe`].
pub fn transcendental_probe(
    pairs: &[[f32; 2]],
) -> Result<(Vec<[f32; 4]>, wgpu::AdapterInfo), GpuError> {
    pair_probe("transcendental_ops", pairs)
}

/// Runs the module's `pow_ops` entry point on `pairs`: `[pow_lo, pow_hi,
/// a, b]`, the bounds of `ia-core`'s `Interval::pow([|a|, |a|], b)` for
/// each `[a, b]` on the driver (`ia-core`'s own `f32` `pow` on SPIR-V
/// for a non-integer `b`), with the adapter used.
///
/// # Errors
/// As [`interval_probe`].
pub fn pow_probe(pairs: &[[f32; 2]]) -> Result<(Vec<[f32; 4]>, wgpu::AdapterInfo), GpuError> {
    pair_probe("pow_ops", pairs)
}

/// Runs the module's `trig_ops` entry point on `pairs`: `[sin_lo,
/// sin_hi, cos_lo, cos_hi]`, the bounds of `ia-core`'s
/// `Interval::sin([a, a])` and `Interval::cos([a, a])` for each `[a, b]`
/// (`b` unused) on the driver (`ia-core`'s own `f32` `sin` and `cos` on
/// SPIR-V), with the adapter used.
///
/// # Errors
/// As [`interval_probe`].
pub fn trig_probe(pairs: &[[f32; 2]]) -> Result<(Vec<[f32; 4]>, wgpu::AdapterInfo), GpuError> {
    pair_probe("trig_ops", pairs)
}

/// Runs a probe entry point that maps each `[a, b, _, _]` of its buffer to
/// four floats.
fn pair_probe(
    entry: &str,
    pairs: &[[f32; 2]],
) -> Result<(Vec<[f32; 4]>, wgpu::AdapterInfo), GpuError> {
    let data: Vec<f32> = pairs.iter().flat_map(|&[a, b]| [a, b, 0.0, 0.0]).collect();
    let (words, info) = probe(entry, &data, pairs.len() as u32)?;
    let out = words
        .chunks_exact(4)
        .map(|w| [0, 1, 2, 3].map(|k| f32::from_bits(w[k])))
        .collect();
    Ok((out, info))
}

/// Runs a probe entry point (64 threads per workgroup, one storage buffer
/// at binding 0) over `data` with `invocations` threads; the buffer's words
/// afterwards.
fn probe(
    entry: &str,
    xs: &[f32],
    invocations: u32,
) -> Result<(Vec<u32>, wgpu::AdapterInfo), GpuError> {
    let bytes = load_module()?;
    pollster::block_on(async {
        use wgpu::util::DeviceExt;
        let (info, device, queue) = open_device().await?;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = shader_module(&device, &bytes, entry, (64, 1, 1));
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: None,
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: false },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: None,
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        });
        let mut words: Vec<u8> = xs.iter().flat_map(|x| x.to_le_bytes()).collect();
        if words.is_empty() {
            words.extend_from_slice(&[0; 4]);
        }
        let size = words.len() as u64;
        let data = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("data"),
            contents: &words,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        });
        let back = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("data-read"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: data.as_entire_binding(),
            }],
        });
        let mut enc =
            device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.dispatch_workgroups(invocations.div_ceil(64).max(1), 1, 1);
        }
        enc.copy_buffer_to_buffer(&data, 0, &back, 0, size);
        queue.submit([enc.finish()]);
        if let Some(e) = scope.pop().await {
            return Err(GpuError::Shader(error_chain(&e)));
        }
        let mut words = read_back(&device, &back)?;
        words.truncate(xs.len());
        Ok((words, info))
    })
}

/// An error with its sources (wgpu's own message is only "Validation Error").
fn error_chain(e: &dyn std::error::Error) -> String {
    let mut msg = e.to_string();
    let mut src = e.source();
    while let Some(s) = src {
        msg.push_str(": ");
        msg.push_str(&s.to_string());
        src = s.source();
    }
    msg
}

/// Maps a `MAP_READ` buffer and returns its words.
fn read_back(device: &wgpu::Device, back: &wgpu::Buffer) -> Result<Vec<u32>, GpuError> {
    let slice = back.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| GpuError::Dispatch(e.to_string()))?;
    rx.recv()
        .map_err(|e| GpuError::Dispatch(e.to_string()))?
        .map_err(|e| GpuError::Dispatch(e.to_string()))?;
    let view = slice
        .get_mapped_range()
        .map_err(|e| GpuError::Dispatch(e.to_string()))?;
    let words = le_words(&view);
    drop(view);
    back.unmap();
    Ok(words)
}

fn read_pixel(w: &[u32]) -> PixelOut {
    let f = f32::from_bits;
    PixelOut {
        has_span: w[0],
        span: [f(w[1]), f(w[2])],
        roots: w[3],
        status: w[4],
        t_reached: f(w[5]),
        steps: w[6],
        field_evals: w[7],
        bound_evals: w[8],
    }
}

fn read_hit(w: &[u32]) -> Result<Hit<f32>, GpuError> {
    let f = f32::from_bits;
    let h = HitOut {
        t: f(w[0]),
        side: w[1],
        normal: [f(w[2]), f(w[3]), f(w[4])],
    };
    let side = match h.side {
        0 => Side::Entering,
        1 => Side::Leaving,
        2 => Side::Touch,
        s => return Err(GpuError::Dispatch(format!("bad side code {s} read back"))),
    };
    Ok(Hit {
        t: h.t,
        side,
        normal: h.normal,
    })
}

fn status_of(code: u32) -> Result<Status, GpuError> {
    Ok(match code {
        0 => Status::Finished,
        1 => Status::MaxSteps,
        2 => Status::BufferFull,
        3 => Status::Unsupported,
        s => return Err(GpuError::Dispatch(format!("bad status code {s} read back"))),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use boundtrace_fields::homothetic::{KERNEL_COMPACT, SEGMENT_WORDS, Segment, SegmentKernel};
    use boundtrace_fields::homothetic_skeleton::{HomotheticSkeleton, PARAMETER_WORDS};
    use boundtrace_tracer::scenes::{DEFAULT_SEED, WithLipschitz};
    use core::mem::size_of;

    std::thread_local! {
        /// When `Some`, [`GpuTracer::run`] pushes the legs' words after
        /// every dispatch (this thread's; for
        /// `scalis_legs_match_the_host_kernel_leg_by_leg`).
        pub(super) static LEG_SNAPSHOTS: std::cell::RefCell<Option<Vec<Vec<u32>>>> =
            const { std::cell::RefCell::new(None) };
    }

    /// The words of a leg, as the GPU keeps it in its legs' buffer.
    fn leg_words(leg: &ScalisLeg) -> Vec<u32> {
        let n = size_of::<ScalisLeg>() / 4;
        #[allow(unsafe_code)]
        // SAFETY: `ScalisLeg` is `#[repr(C)]` of `u32`s and `f32`s, no padding.
        let w = unsafe { std::slice::from_raw_parts(std::ptr::from_ref(leg).cast::<u32>(), n) };
        w.to_vec()
    }

    /// The name of word `w` of a [`ScalisLeg`]: `phase`, `shaded`, a
    /// [`ScalisWalk`](boundtrace_tracer::scalis::ScalisWalk) field and the
    /// word in it (`tight+4`), or a stack entry's point and word
    /// (`stack[2][1]+0`: the second end's `t`).
    fn leg_word_name(w: usize) -> String {
        use boundtrace_tracer::scalis::{ScalisPoint, ScalisState, ScalisWalk};
        use core::mem::offset_of;
        let state = offset_of!(ScalisLeg, state) / 4;
        if w < state {
            return ["phase", "shaded"][w].to_string();
        }
        let s = w - state;
        let stack = offset_of!(ScalisState<f32>, stack) / 4;
        let point = size_of::<ScalisPoint<f32>>() / 4;
        if s >= stack {
            let e = s - stack;
            return format!(
                "stack[{}][{}]+{}",
                e / (2 * point),
                e / point % 2,
                e % point
            );
        }
        let fields: [(&str, usize); 17] = [
            ("started", offset_of!(ScalisWalk<f32>, started)),
            ("in_region", offset_of!(ScalisWalk<f32>, in_region)),
            ("first", offset_of!(ScalisWalk<f32>, first)),
            ("next", offset_of!(ScalisWalk<f32>, next)),
            ("region", offset_of!(ScalisWalk<f32>, region)),
            ("roots", offset_of!(ScalisWalk<f32>, roots)),
            ("stats", offset_of!(ScalisWalk<f32>, stats)),
            ("sp", offset_of!(ScalisWalk<f32>, sp)),
            ("cur_pending", offset_of!(ScalisWalk<f32>, cur_pending)),
            ("kind", offset_of!(ScalisWalk<f32>, kind)),
            ("nreq", offset_of!(ScalisWalk<f32>, nreq)),
            ("req", offset_of!(ScalisWalk<f32>, req)),
            ("fix", offset_of!(ScalisWalk<f32>, fix)),
            ("cur", offset_of!(ScalisWalk<f32>, cur)),
            ("split", offset_of!(ScalisWalk<f32>, split)),
            ("pair", offset_of!(ScalisWalk<f32>, pair)),
            ("tight", offset_of!(ScalisWalk<f32>, tight)),
        ];
        // the field starting last at or before `s`
        let mut name = "?";
        let mut at = 0;
        for (f, o) in fields {
            if o / 4 <= s && o / 4 >= at {
                name = f;
                at = o / 4;
            }
        }
        format!("{name}+{}", s - at)
    }

    /// The settings of a `size` × `size` SCALIS test frame (at most
    /// [`MAX_GPU_ROOTS`] roots) and its root slots per pixel.
    fn scalis_settings(size: u32, method: Method, mode: Mode) -> (RenderSettings<f32>, u32) {
        let settings = RenderSettings::new(size, size, method)
            .unwrap()
            .with_mode(mode)
            .with_max_roots(MAX_GPU_ROOTS)
            .unwrap();
        let slots = match mode {
            Mode::Opaque => 1,
            Mode::Transparent => MAX_GPU_ROOTS,
        };
        (settings, slots)
    }

    /// The SCALIS legs on the adapter, leg by leg, against the host's: in
    /// legs of one step, the words of every pixel's [`ScalisLeg`] after
    /// each dispatch (both pipelines) equal those the host kernel
    /// (`render_scalis_leg`, then `render_scalis_tight_leg`) leaves after
    /// the same leg (the shading legs aside: the GPU shades a pixel's hits
    /// in as many as its loop limit needs), for `scalis-quadratic` and
    /// `interval` on the SCALIS skeletons, both modes. Where a pixel differs it prints the first
    /// differing leg's words by name (`leg_word_name`), both sides, and
    /// what the leg changed on the host: the tool that found the oracle
    /// lavapipe miscompiled (BENCHMARKS.md "GPU", session 33).
    /// Ignored: the difftests (`scalis_methods_match_the_cpu_in_both_modes`)
    /// cover the frames in CI; this one reads every pixel's 3,344 bytes
    /// back after every dispatch (about 2 min on lavapipe with its shader cache warm). Run it with
    /// the SCALIS module built (`scripts/build-spirv.sh`) and
    /// `cargo test -p boundtrace-gpu --lib -- --ignored scalis_legs_match`.
    #[test]
    #[ignore = "a diagnostic of the SCALIS difftests: minutes on lavapipe, needs the scalis module"]
    fn scalis_legs_match_the_host_kernel_leg_by_leg() {
        use boundtrace_gpu_kernel as k;
        use boundtrace_tracer::Root;
        let gpu = GpuTracer::new().unwrap();
        let size = 12;
        let mut differ = Vec::new();
        for name in ["scalis-tree", "scalis-random", "scalis-foam"] {
            let scene = Scene::<f32>::build(name, DEFAULT_SEED).unwrap();
            let data = GpuScene::from_scene(&scene).unwrap();
            let camera = Camera::framing(scene.bounds(), [0.3, -0.4, -1.0], 40.0, 1.0).unwrap();
            for (method, mode) in [
                (Method::ScalisQuadratic, Mode::Opaque),
                (Method::ScalisQuadratic, Mode::Transparent),
                (Method::Interval, Mode::Transparent),
            ] {
                let (settings, slots) = scalis_settings(size, method, mode);
                LEG_SNAPSHOTS.with(|s| *s.borrow_mut() = Some(Vec::new()));
                let rendered = gpu.render_in_legs(&data, &camera, &settings, 1);
                let snaps = LEG_SNAPSHOTS.with(|s| s.borrow_mut().take()).unwrap();
                let (_, dispatches) = rendered.unwrap();
                eprintln!("{name} {method} {mode:?}: {dispatches} dispatches");
                let c = Constants {
                    leg_steps: 1,
                    ..data.constants(&camera, &settings, slots)
                };
                let [offsets, lists, segments] = data.buffers(&camera, &settings);
                let lists: Vec<PrimitiveHit<f32>> = read_as(&lists);
                let segments: Vec<ScalisSegment<f32>> = read_as(&segments);
                let words = size_of::<ScalisLeg>() / 4;
                let none = Root {
                    t: 0.0,
                    side: Side::Touch,
                };
                for i in 0..(size * size) as usize {
                    let (x, y) = (i as u32 % size, i as u32 / size);
                    // each side's distinct states in order (a dispatch
                    // that stopped a pixel at the loop limit repeats one),
                    // but those in `PHASE_SHADING`: the GPU shades a
                    // pixel's hits in as many dispatches as its loop limit
                    // needs, the host in one leg
                    let shading = |w: &[u32]| w[0] == PHASE_SHADING;
                    let mut gpu_seq: Vec<&[u32]> = Vec::new();
                    for s in &snaps {
                        let w = &s[i * words..(i + 1) * words];
                        if gpu_seq.last() != Some(&w) && !shading(w) {
                            gpu_seq.push(w);
                        }
                    }
                    let mut roots = vec![none; slots as usize];
                    let mut hits = vec![HitOut::default(); slots as usize];
                    let (mut leg, mut p) = (ScalisLeg::default(), PixelOut::default());
                    let mut host_seq: Vec<Vec<u32>> = Vec::new();
                    while leg.phase != PHASE_DONE {
                        assert!(host_seq.len() < 100_000, "({x}, {y}): no progress");
                        k::render_scalis_leg(
                            &c, &offsets, &lists, &segments, x, y, &mut roots, &mut hits, 0,
                            &mut leg, &mut p,
                        );
                        k::render_scalis_tight_leg(&c, &offsets, &lists, &segments, x, y, &mut leg);
                        let w = leg_words(&leg);
                        if host_seq.last() != Some(&w) && !shading(&w) {
                            host_seq.push(w);
                        }
                    }
                    let same = gpu_seq.len() == host_seq.len()
                        && gpu_seq
                            .iter()
                            .zip(&host_seq)
                            .all(|(g, h)| *g == h.as_slice());
                    if same {
                        continue;
                    }
                    differ.push(format!("{name} {method} {mode:?} ({x}, {y})"));
                    let l = (0..gpu_seq.len().min(host_seq.len()))
                        .find(|&l| gpu_seq[l] != host_seq[l].as_slice())
                        .unwrap_or(gpu_seq.len().min(host_seq.len()));
                    eprintln!(
                        "{name} {method} {mode:?} ({x}, {y}): leg {l} of {} (GPU) / {} (host) differs",
                        gpu_seq.len(),
                        host_seq.len()
                    );
                    if l == 0 || l >= gpu_seq.len().min(host_seq.len()) {
                        continue;
                    }
                    let prev = &host_seq[l - 1];
                    let changed: Vec<String> = (0..words)
                        .filter(|&w| prev[w] != host_seq[l][w])
                        .map(|w| format!("{}={:e}", leg_word_name(w), f32::from_bits(prev[w])))
                        .collect();
                    eprintln!("   the host's leg changed: {}", changed.join(" "));
                    for w in 0..words {
                        let (a, b) = (gpu_seq[l][w], host_seq[l][w]);
                        if a != b {
                            eprintln!(
                                "   {:24} GPU {:>14e} ({a:#010x})  host {:>14e} ({b:#010x})",
                                leg_word_name(w),
                                f32::from_bits(a),
                                f32::from_bits(b)
                            );
                        }
                    }
                }
            }
        }
        assert!(
            differ.is_empty(),
            "{} pixels differ: {differ:?}",
            differ.len()
        );
    }

    #[test]
    fn blob_layout_is_seven_words() {
        // The shader reads `PointBlob<f32>` as #[repr(C)] {[f32; 3], f32, u32, u32, f32}.
        assert_eq!(std::mem::size_of::<PointBlob<f32>>(), 28);
        let k = boundtrace_fields::Kernel::compact(6, 0.25f32).unwrap();
        let b = PointBlob::new([1.0, 2.0, 3.0], 0.5, k).unwrap();
        let w = blob_words(&[b]);
        assert_eq!(
            w,
            [
                1.0f32.to_bits(),
                2.0f32.to_bits(),
                3.0f32.to_bits(),
                0.5f32.to_bits(),
                0,
                6,
                0.25f32.to_bits()
            ]
        );
    }

    #[test]
    fn scenes_with_and_without_gpu_data() {
        let blobs = Scene::<f32>::build("blobs", DEFAULT_SEED).unwrap();
        let g = GpuScene::from_scene(&blobs).unwrap();
        assert_eq!(g.kind(), SceneKind::BlobGroups);
        assert_eq!(
            (g.groups, g.blobs.len(), g.words.last().copied()),
            (4, 32, Some(32))
        );
        let sum = Scene::<f32>::build("blobs-sum", DEFAULT_SEED).unwrap();
        assert_eq!(GpuScene::from_scene(&sum).unwrap().kind(), SceneKind::Blobs);
        // one blob set and its generator's Lipschitz bound
        let mol = Scene::<f32>::build("molecule", DEFAULT_SEED).unwrap();
        let m = GpuScene::from_scene(&mol).unwrap();
        assert_eq!(
            (m.kind(), m.blobs.len(), m.groups),
            (SceneKind::Blobs, 500, 0)
        );
        let SceneField::Molecule(field) = mol.field() else {
            panic!("molecule is a Molecule field")
        };
        assert_eq!(m.lipschitz, field.bound());
        assert!(m.lipschitz > 0.0 && m.lipschitz.is_finite());
        // a blobtree: its words and parameters, and its own Lipschitz bound
        let agg = Scene::<f32>::build("aggregate-1", DEFAULT_SEED).unwrap();
        let a = GpuScene::from_scene(&agg).unwrap();
        let SceneField::Blobtree(tree) = agg.field() else {
            panic!("aggregate-1 is a blobtree")
        };
        assert_eq!(a.kind(), SceneKind::Blobtree);
        assert_eq!(
            (&a.words[..], &a.floats[..]),
            (tree.as_ref().nodes(), tree.as_ref().params())
        );
        assert_eq!(Some(a.lipschitz), tree.as_ref().lipschitz_bound::<f32>());
        assert_eq!(leg_slot(Method::Sphere, SceneKind::Blobtree), Some(6));
        // an HRBF: the centers' words, then the polynomial
        let hrbf = Scene::<f32>::build("hrbf-8", DEFAULT_SEED).unwrap();
        let h = GpuScene::from_scene(&hrbf).unwrap();
        let SceneField::Hrbf(field) = hrbf.field() else {
            panic!("hrbf-8 is an HRBF")
        };
        assert_eq!(h.kind(), SceneKind::Hrbf);
        assert_eq!(h.groups, 8);
        assert_eq!(h.floats.len(), 8 * 7 + 4);
        assert_eq!(h.floats[7 * 3 + 3], field.centers()[3].alpha);
        assert_eq!(h.floats[8 * 7..], field.poly());
        for method in [
            Method::Segment,
            Method::LinearBottomUp,
            Method::QuadraticBottomUp,
            Method::LinearMixed,
            Method::QuadraticMixed,
        ] {
            assert!(leg_slot(method, SceneKind::Hrbf).is_some(), "{method}");
        }
        // no module: sphere tracing and the Taylor methods need bounds an
        // HRBF lacks (unsupported on the CPU too)
        assert_eq!(leg_slot(Method::LinearTaylor, SceneKind::Hrbf), None);
        // a homothetic skeleton: the kernel's code; the segments' words,
        // then the parameters; the scene's Lipschitz bound
        let segs = vec![
            Segment::new([0.0; 3], 0.3, [1.0, 0.0, 0.0], 0.2).unwrap(),
            Segment::new([1.0, 0.0, 0.0], 0.2, [1.0, 1.0, 0.0], 0.1).unwrap(),
        ];
        let kernel = SegmentKernel::compact_polynomial(4, 1.6).unwrap();
        let sk = HomotheticSkeleton::new(segs, kernel, 1.0).unwrap();
        let field = SceneField::Homothetic(WithLipschitz::new(sk.clone(), 7.5));
        let box_ = [[-1.0; 3], [2.0; 3]];
        let scene = Scene::from_parts("h", String::new(), box_, [0.0; 3], field, 2).unwrap();
        let g = GpuScene::from_scene(&scene).unwrap();
        assert_eq!(g.kind(), SceneKind::Homothetic);
        assert_eq!((g.groups, g.lipschitz), (2, 7.5));
        assert_eq!(g.words, [KERNEL_COMPACT, 4]);
        assert_eq!(g.floats.len(), 2 * SEGMENT_WORDS + PARAMETER_WORDS);
        assert_eq!(g.floats[SEGMENT_WORDS + 3], 0.2);
        assert_eq!(g.floats[2 * SEGMENT_WORDS..], sk.parameter_words().1);
        assert_eq!(
            leg_slot(Method::QuadraticTaylor, SceneKind::Homothetic),
            None
        );
        assert_eq!(leg_slot(Method::Interval, SceneKind::Homothetic), None);
        for method in [
            Method::Sphere,
            Method::Segment,
            Method::LinearTaylor,
            Method::LinearBottomUp,
            Method::QuadraticBottomUp,
            Method::LinearMixed,
            Method::QuadraticMixed,
        ] {
            assert!(
                leg_slot(method, SceneKind::Homothetic).is_some(),
                "{method}"
            );
        }
        // a bound that is not a positive number is refused
        let field = SceneField::Homothetic(WithLipschitz::new(sk, f32::NAN));
        let scene = Scene::from_parts("h", String::new(), box_, [0.0; 3], field, 2).unwrap();
        let e = GpuScene::from_scene(&scene).unwrap_err().to_string();
        assert!(e.contains("Lipschitz"), "{e}");
    }

    #[test]
    fn entry_point_names_are_read_from_the_module() {
        let name = |s: &str| -> Vec<u32> {
            let mut b = s.as_bytes().to_vec();
            b.resize((b.len() / 4 + 1) * 4, 0); // nul-terminated, padded
            b.chunks(4)
                .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
                .collect()
        };
        let mut words = vec![0x0723_0203, 0x0001_0300, 0, 100, 0];
        for (id, n) in [(7, "trace_sphere"), (8, "interval_square")] {
            let text = name(n);
            words.push(((3 + text.len() as u32) << 16) | 15); // OpEntryPoint
            words.extend([5, id]); // GLCompute, function id
            words.extend(text);
        }
        words.push((5 << 16) | 54); // OpFunction: the scan stops here
        words.extend([1, 7, 0, 2]);
        words.push((4 << 16) | 15); // an OpEntryPoint-like word after it is ignored
        words.extend([5, 9, 0]);
        let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
        assert_eq!(entry_points(&bytes), ["trace_sphere", "interval_square"]);
        assert!(entry_points(&bytes[4..]).is_empty()); // bad magic
        assert!(entry_points(&[]).is_empty());
        // A truncated instruction ends the scan without panicking.
        assert_eq!(entry_points(&bytes[..bytes.len() - 40]).len(), 1);
    }

    #[test]
    fn leg_modules_sit_beside_the_main_one() {
        let main = Path::new("/t/spirv/boundtrace-gpu-shader.spv");
        let path = |m, k| leg_path_beside(main, leg_slot(m, k).unwrap());
        assert_eq!(
            path(Method::Segment, SceneKind::Blobs),
            Path::new("/t/spirv/boundtrace-gpu-shader-segment-blobs.spv")
        );
        assert_eq!(
            path(Method::QuadraticTaylor, SceneKind::BlobGroups),
            Path::new("/t/spirv/boundtrace-gpu-shader-quadratic-taylor-groups.spv")
        );
        let slot = leg_slot(Method::LinearTaylor, SceneKind::BlobGroups).unwrap();
        assert_eq!(
            leg_path_beside(Path::new("x/my.spv"), slot),
            Path::new("x/my-linear-taylor-groups.spv")
        );
        assert_eq!(leg_entry(slot), "trace_linear_taylor_groups");
        assert_eq!(leg_slot(Method::Segment, SceneKind::Blobtree), None);
        assert_eq!(leg_slot(Method::LinearMixed, SceneKind::Blobtree), None);
        assert_eq!(leg_slot(Method::Affine, SceneKind::Blobs), None);
        // Every slot is one method and kind.
        for slot in 0..LEG_MODULES {
            let (m, k, _) = leg_module(slot);
            assert_eq!(leg_slot(m, k), Some(slot));
        }
        // The build script's names (`${out%.spv}-$method-$kind.spv`), and
        // the shader's features and entry points.
        let script = include_str!("../../../scripts/build-spirv.sh");
        assert!(script.contains("\"${out%.spv}-$method-$kind.spv\""));
        assert!(script.contains("for method in segment linear-taylor quadratic-taylor; do"));
        assert!(script.contains("for kind in blobs groups; do"));
        assert!(script.contains("module sphere-blobtree \"${out%.spv}-sphere-blobtree.spv\""));
        assert!(script.contains(
            "methods=\"linear-bottom-up quadratic-bottom-up linear-mixed quadratic-mixed\""
        ));
        assert!(
            script.contains("module \"$method-$kind\" \"${out%.spv}-$method-$kind.spv\" no-opt")
        );
        let shader = include_str!("../../gpu-shader/src/lib.rs");
        let features = include_str!("../../gpu-shader/Cargo.toml");
        assert!(script.contains("module scalis \"${out%.spv}-scalis.spv\" no-opt"));
        // the SCALIS tight stages' entry point, in the same module
        assert!(shader.contains(&format!(
            "#[cfg(feature = \"scalis\")]\n#[allow(clippy::too_many_arguments)]\n\
             #[spirv(compute(threads(8, 8)))]\npub fn {SCALIS_TIGHT_ENTRY}("
        )));
        for slot in 0..LEG_MODULES {
            let (method, kind, name) = leg_module(slot);
            // the mixed methods' Taylor entry points, in the same module
            if LegKind::of(method, kind) == LegKind::Mixed {
                let after = taylor_entry(&leg_entry(slot));
                assert!(after.starts_with("taylor_") && after.ends_with(&name.replace('-', "_")));
                assert!(
                    shader.contains(&format!("    {after},\n    kernel::fill_")),
                    "{after}"
                );
            }
            assert!(features.contains(&format!("\n{name} = []")), "{name}");
            if kind == SceneKind::Scalis {
                // its own entry point (other bindings), not the macro's
                assert!(shader.contains(&format!(
                    "#[cfg(feature = \"{name}\")]\n#[allow(clippy::too_many_arguments)]\n\
                     #[spirv(compute(threads(8, 8)))]\npub fn {}(",
                    leg_entry(slot)
                )));
            } else {
                assert!(
                    shader.contains(&format!("\"{name}\",\n    {},", leg_entry(slot))),
                    "{name}"
                );
            }
        }
    }

    #[test]
    fn leg_progress_counts_pending_and_shading_pixels() {
        let phase_at = core::mem::offset_of!(PixelLeg, phase) / 4;
        let mut words = vec![0u32; 4 * LEG_WORDS];
        for (i, phase) in [PHASE_DONE, PHASE_SHADING, 1, PHASE_DONE]
            .into_iter()
            .enumerate()
        {
            words[i * LEG_WORDS + phase_at] = phase;
        }
        let layout = LegLayout::of(LegKind::Pixel);
        assert_eq!(leg_progress(&words, layout), (2, 1));
        // A fresh (zero-filled) frame: every pixel pending, none shading.
        assert_eq!(leg_progress(&vec![0; 3 * LEG_WORDS], layout), (3, 0));
        // The SCALIS legs: phase first, then the tracer's state.
        let layout = LegLayout::of(LegKind::Scalis);
        let mut words = vec![0u32; 3 * SCALIS_LEG_WORDS];
        words[SCALIS_LEG_WORDS] = PHASE_DONE;
        words[2 * SCALIS_LEG_WORDS] = PHASE_SHADING;
        assert_eq!(leg_progress(&words, layout), (2, 1));
        assert_eq!(
            SCALIS_LEG_WORDS,
            2 + core::mem::size_of::<boundtrace_tracer::scalis::ScalisState<f32>>() / 4
        );
        // (the size the crate docs give)
        assert_eq!(SCALIS_LEG_WORDS * 4, 3344);
        // The leg record: the tracer's state, then the phase and the roots
        // shaded (what the shader writes).
        assert_eq!(
            LEG_WORDS,
            core::mem::size_of::<boundtrace_tracer::march::MarchState<f32>>() / 4 + 2,
            "PixelLeg = MarchState + phase + shaded"
        );
        // The mixed legs: a `PixelLeg`, then the Taylor cache.
        let layout = LegLayout::of(LegKind::Mixed);
        assert_eq!(layout.phase_at, core::mem::offset_of!(PixelLeg, phase) / 4);
        assert_eq!(
            MIXED_LEG_WORDS,
            LEG_WORDS + core::mem::size_of::<boundtrace_tracer::march::TaylorCache<f32>>() / 4
        );
        // (the size the kernel's docs give)
        assert_eq!(MIXED_LEG_WORDS, 36);
        let mut words = vec![0u32; 2 * MIXED_LEG_WORDS];
        words[MIXED_LEG_WORDS + layout.phase_at] = PHASE_DONE;
        assert_eq!(leg_progress(&words, layout), (1, 0));
    }

    #[test]
    fn float_arithmetic_is_decorated_no_contraction() {
        let header = [0x0723_0203, 0x0001_0300, 0, 20, 0];
        let body = [
            (2 << 16) | 17, // OpCapability Shader
            1,
            (4 << 16) | 71, // OpDecorate %7 Binding 0
            7,
            33,
            0,
            (3 << 16) | 22, // %2 = OpTypeFloat 32
            2,
            32,
            (5 << 16) | 133, // %9 = OpFMul %2 %5 %6
            2,
            9,
            5,
            6,
            (5 << 16) | 129, // %10 = OpFAdd %2 %9 %6
            2,
            10,
            9,
            6,
            (5 << 16) | 128, // %11 = OpIAdd (not a float op)
            2,
            11,
            5,
            6,
        ];
        let module: Vec<u32> = header.iter().chain(&body).copied().collect();
        let out = forbid_contraction(&module);
        let decorations = [(3 << 16) | 71, 9, 42, (3 << 16) | 71, 10, 42];
        assert_eq!(out.len(), module.len() + 6);
        assert_eq!(&out[..7], &module[..7]);
        assert_eq!(&out[7..13], &decorations);
        assert_eq!(&out[13..], &module[7..]);
        // A truncated module is left alone.
        let cut = &module[..module.len() - 2];
        assert_eq!(forbid_contraction(cut), cut);
    }

    /// `OpExtension "SPV_KHR_vulkan_memory_model"`'s words.
    fn memory_model_extension() -> Vec<u32> {
        let mut b = b"SPV_KHR_vulkan_memory_model\0".to_vec();
        b.resize(b.len().div_ceil(4) * 4, 0);
        let mut w = vec![((1 + b.len() as u32 / 4) << 16) | 10];
        w.extend(
            b.chunks_exact(4)
                .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])),
        );
        w
    }

    #[test]
    fn vulkan_memory_model_becomes_glsl450() {
        let header = [0x0723_0203, 0x0001_0300, 0, 20, 0];
        let shader = [(2 << 16) | 17, 1]; // OpCapability Shader
        let vulkan = [(2 << 16) | 17, 5345]; // OpCapability VulkanMemoryModel
        let model = |m: u32| [(3 << 16) | 14, 0, m]; // OpMemoryModel Logical m
        let load = |access: u32| [(5 << 16) | 61, 2, 9, 5, access]; // %9 = OpLoad %2 %5 access
        let module = |tail: &[u32]| -> Vec<u32> {
            let mut m = header.to_vec();
            m.extend(shader);
            m.extend(vulkan);
            m.extend(memory_model_extension());
            m.extend(model(3));
            m.extend_from_slice(tail);
            m
        };
        // A plain load (access Aligned = 0x2): the capability and the
        // extension go, the model becomes GLSL450; nothing else changes.
        let plain = module(&load(0x2));
        let mut want = header.to_vec();
        want.extend(shader);
        want.extend(model(1));
        want.extend(load(0x2));
        assert_eq!(glsl450_memory_model(&plain), want);
        // Other extensions stay.
        let mut other = module(&[]);
        other.extend([(3 << 16) | 10, u32::from_le_bytes(*b"SPV_"), 0]);
        assert_eq!(glsl450_memory_model(&other).len(), other.len() - 2 - 8);
        // What only the Vulkan model defines keeps the module as it is:
        // a NonPrivatePointer load, a barrier, an atomic.
        for tail in [
            load(0x20).to_vec(),
            vec![(4 << 16) | 224, 1, 1, 0], // OpControlBarrier
            vec![(7 << 16) | 234, 2, 9, 5, 1, 0, 6], // OpAtomicIAdd
        ] {
            let m = module(&tail);
            assert_eq!(glsl450_memory_model(&m), m);
        }
        // So is a truncated module.
        let cut = &plain[..plain.len() - 2];
        assert_eq!(glsl450_memory_model(cut), cut);
    }

    /// A module with one storage buffer at `binding`: a runtime array of
    /// `u32` with byte stride `stride`, or (`stride == 0`) a struct of
    /// two `u32`s at offsets 0 and `offset`.
    fn one_buffer(binding: u32, stride: u32, offset: u32) -> Vec<u32> {
        // %1 uint, %2 runtime array or struct, %3 block, %4 pointer, %5 variable.
        let mut w = vec![0x0723_0203, 0x0001_0300, 0, 6, 0];
        if stride > 0 {
            w.extend([(4 << 16) | 71, 2, 6, stride]); // ArrayStride
        } else {
            w.extend([
                (5 << 16) | 72,
                2,
                0,
                35,
                0,
                (5 << 16) | 72,
                2,
                1,
                35,
                offset,
            ]);
        }
        w.extend([(5 << 16) | 72, 3, 0, 35, 0]); // Offset 0
        w.extend([(4 << 16) | 71, 5, 34, 0, (4 << 16) | 71, 5, 33, binding]);
        w.extend([(4 << 16) | 21, 1, 32, 0]);
        if stride > 0 {
            w.extend([(3 << 16) | 29, 2, 1]);
        } else {
            w.extend([(4 << 16) | 30, 2, 1, 1]);
        }
        w.extend([
            (3 << 16) | 30,
            3,
            2,
            (4 << 16) | 32,
            4,
            12,
            3,
            (4 << 16) | 59,
            4,
            5,
            12,
        ]);
        w
    }

    fn bytes(words: &[u32]) -> Vec<u8> {
        words.iter().flat_map(|w| w.to_le_bytes()).collect()
    }

    #[test]
    fn modules_of_another_layout_are_refused() {
        let pixel = size_of::<PixelOut>() as u32;
        assert_eq!(pixel, 36, "the host reads 9 words per pixel");
        assert_eq!(
            module_layouts(&one_buffer(4, pixel, 0)),
            [(4, BufferLayout::Array(pixel))]
        );
        assert!(check_layout(&bytes(&one_buffer(4, pixel, 0)), "m").is_ok());
        let e = check_layout(&bytes(&one_buffer(4, pixel + 4, 0)), "m").unwrap_err();
        assert!(e.to_string().contains(BUILD_COMMAND), "{e}");
        // The constants: a struct whose size is its last member's offset + 4.
        let constants = size_of::<Constants>() as u32;
        assert_eq!(
            module_layouts(&one_buffer(0, 0, constants - 4)),
            [(0, BufferLayout::Struct(constants))]
        );
        assert!(check_layout(&bytes(&one_buffer(0, 0, constants - 4)), "m").is_ok());
        assert!(check_layout(&bytes(&one_buffer(0, 0, constants)), "m").is_err());
        // An array where the host has a struct (the probes' binding 0) is
        // not the tracer's buffer: not compared.
        assert!(check_layout(&bytes(&one_buffer(0, 4, 0)), "m").is_ok());
        // Bindings the host does not use, and truncated modules, pass.
        assert!(check_layout(&bytes(&one_buffer(9, 12, 0)), "m").is_ok());
        let cut = one_buffer(4, 40, 0);
        assert!(module_layouts(&cut[..cut.len() - 2]).is_empty());
    }

    /// The modules `scripts/build-spirv.sh` built (required under
    /// `CI=true`) declare exactly the host's layout for every tracing
    /// buffer, so the check above sees real modules' layouts. Bindings 1
    /// and 2 (the blobtree words and parameters, or the SCALIS list
    /// offsets and lists) may be absent from a module whose entry points
    /// never read them (the mixed `Blobs` modules), and binding 3 (blobs)
    /// from the HRBF modules (their data is in binding 2): the compiler
    /// drops them; where present they must match.
    #[test]
    fn built_modules_have_the_host_layout() {
        let main = default_spirv_path();
        if !main.is_file() {
            assert!(
                std::env::var_os("CI").is_none(),
                "CI=true: {} missing",
                main.display()
            );
            return;
        }
        let mut paths = vec![(main.clone(), LegKind::Pixel, SceneKind::Blobs)];
        paths.extend((0..LEG_MODULES).map(|slot| {
            let (method, kind, _) = leg_module(slot);
            (
                leg_path_beside(&main, slot),
                LegKind::of(method, kind),
                kind,
            )
        }));
        for (path, legs, kind) in paths.into_iter().filter(|(p, _, _)| p.is_file()) {
            let bytes = std::fs::read(&path).unwrap();
            let found = module_layouts(&le_words(&bytes));
            for (b, want) in host_layouts_of(legs) {
                let optional = b == 1
                    || b == 2
                    || (b == 3 && matches!(kind, SceneKind::Hrbf | SceneKind::Homothetic));
                if optional && !found.iter().any(|&(fb, _)| fb == b) {
                    continue;
                }
                assert!(
                    found.contains(&(b, want)),
                    "{}: binding {b}: {want:?} not among {found:?}",
                    path.display()
                );
            }
            check_layout_of(&bytes, "module", legs).unwrap();
        }
    }

    /// The shader's leg kernels run on the host, pixel by pixel in
    /// unlimited legs until done, as the leg entry points run them on a
    /// GPU: the records (status, roots, steps, evaluations) and the roots'
    /// depths and sides, per pixel.
    fn emulate(
        scene: &GpuScene,
        camera: &Camera<f32>,
        settings: &RenderSettings<f32>,
    ) -> Vec<(PixelOut, Vec<(u32, u32)>)> {
        use boundtrace_gpu_kernel as k;
        use boundtrace_tracer::Root;
        let slots = match settings.mode {
            Mode::Opaque => 1,
            Mode::Transparent => settings.max_roots,
        };
        // the constants the host uploads
        let c = scene.constants(camera, settings, slots);
        let n = (c.width * c.height) as usize;
        let none = Root {
            t: 0.0,
            side: Side::Touch,
        };
        let mut roots = vec![none; n * slots as usize];
        let mut hits = vec![HitOut::default(); n * slots as usize];
        let mut out = Vec::with_capacity(n);
        for i in 0..n {
            let (x, y) = (i as u32 % c.width, i as u32 / c.width);
            let base = i * slots as usize;
            let (mut leg, mut pixel) = (PixelLeg::default(), PixelOut::default());
            let (w, f, b) = (&scene.words[..], &scene.floats[..], &scene.blobs[..]);
            for _ in 0..1000 {
                let (r, h) = (&mut roots[..], &mut hits[..]);
                let (l, o) = (&mut leg, &mut pixel);
                match (settings.method, scene.kind) {
                    (Method::Sphere, _) => {
                        k::render_sphere_leg(&c, w, f, b, x, y, r, h, base, l, o)
                    }
                    (Method::Segment, SceneKind::Blobs) => {
                        k::render_segment_leg_in::<k::BlobsOnly>(
                            &c, w, f, b, x, y, r, h, base, l, o,
                        )
                    }
                    (Method::LinearTaylor, SceneKind::Blobs) => {
                        k::render_linear_taylor_leg_in::<k::BlobsOnly>(
                            &c, w, f, b, x, y, r, h, base, l, o,
                        )
                    }
                    (Method::QuadraticTaylor, SceneKind::Blobs) => {
                        k::render_quadratic_taylor_leg_in::<k::BlobsOnly>(
                            &c, w, f, b, x, y, r, h, base, l, o,
                        )
                    }
                    other => panic!("no emulation of {other:?}"),
                }
                if leg.phase == PHASE_DONE {
                    break;
                }
            }
            assert_eq!(leg.phase, PHASE_DONE, "pixel ({x}, {y}) never finished");
            let found = (0..pixel.roots.min(slots) as usize)
                .map(|r| (hits[base + r].t.to_bits(), hits[base + r].side))
                .collect();
            out.push((pixel, found));
        }
        out
    }

    /// `molecule` (500 Gaussian atoms and its generator's Lipschitz
    /// bound) through the shader's kernels on the host against the CPU
    /// renderer: the same records and roots on every pixel, bit for bit,
    /// for every leg method and both modes. So a GPU that differs from
    /// the CPU there differs by its driver's arithmetic, not by the data
    /// or the kernels.
    #[test]
    fn molecule_kernels_on_the_host_match_the_cpu() {
        use boundtrace_tracer::render::render_serial;
        let scene = Scene::<f32>::build("molecule", DEFAULT_SEED).unwrap();
        let data = GpuScene::from_scene(&scene).unwrap();
        assert!(data.lipschitz > 0.0);
        let camera = Camera::framing(scene.bounds(), [0.3, -0.4, -1.0], 40.0, 1.0).unwrap();
        for (method, size) in [
            (Method::Segment, 8),
            (Method::LinearTaylor, 8),
            (Method::QuadraticTaylor, 8),
            (Method::Sphere, 4),
        ] {
            for mode in [Mode::Opaque, Mode::Transparent] {
                let settings = RenderSettings::new(size, size, method)
                    .unwrap()
                    .with_mode(mode)
                    .with_max_roots(MAX_GPU_ROOTS)
                    .unwrap();
                let cpu = render_serial(scene.field(), &camera, scene.bounds(), &settings).unwrap();
                let host = emulate(&data, &camera, &settings);
                let mut hits = 0;
                for (i, (p, roots)) in host.iter().enumerate() {
                    let (x, y) = (i as u32 % size, i as u32 / size);
                    let a = cpu.pixel(x, y).unwrap();
                    let want: Vec<(u32, u32)> = cpu
                        .hits(x, y)
                        .iter()
                        .map(|h| (h.t.to_bits(), h.side as u32))
                        .collect();
                    let got = (p.status, p.roots, p.steps, p.field_evals, p.bound_evals);
                    let s = &a.trace.stats;
                    let cpu_record = (
                        a.trace.status as u32,
                        a.trace.roots,
                        s.steps,
                        s.field_evals,
                        s.bound_evals,
                    );
                    assert_eq!(got, cpu_record, "{method} {mode:?} ({x}, {y})");
                    assert_eq!(roots, &want, "{method} {mode:?} ({x}, {y})");
                    hits += usize::from(!want.is_empty());
                }
                assert!(hits > 0, "{method} {mode:?}: no pixel hits the molecule");
            }
        }
    }

    /// The words of a scene buffer read as the shader reads them: `T`s
    /// (`#[repr(C)]` structs of 4-byte words).
    fn read_as<T: Copy>(words: &[u32]) -> Vec<T> {
        let size = core::mem::size_of::<T>();
        assert!(size % 4 == 0 && core::mem::align_of::<T>() <= 4);
        assert_eq!(words.len() * 4 % size, 0);
        let n = words.len() * 4 / size;
        #[allow(unsafe_code)]
        // SAFETY: the callers' `T`s (`ScalisSegment<f32>`, `PrimitiveHit<f32>`)
        // are `#[repr(C)]` structs of `f32`s and `u32`s (every bit pattern
        // valid, alignment 4), and `n` of them fit in `words`.
        let items = unsafe { std::slice::from_raw_parts(words.as_ptr().cast::<T>(), n) };
        items.to_vec()
    }

    /// The SCALIS kernel (`render_scalis_leg`) on the host over the
    /// buffers the host uploads (segments and primitive lists read back
    /// from their words as the shader reads them: the layout check of
    /// `to_words`) against the CPU renderer's `render_scene`: the same
    /// records and roots on every pixel, bit for bit, for both methods and
    /// modes, in one leg per pixel or in legs of a few steps, with the
    /// tight stages in `render_scalis_tight_leg` (the host's rounds).
    #[test]
    fn scalis_kernels_on_the_host_match_the_cpu() {
        use boundtrace_gpu_kernel as k;
        use boundtrace_tracer::Root;
        use boundtrace_tracer::render::render_scene;
        use boundtrace_tracer::scalis::TIGHT_REQUESTED;
        for name in ["scalis-tree", "scalis-random"] {
            let scene = Scene::<f32>::build(name, DEFAULT_SEED).unwrap();
            let data = GpuScene::from_scene(&scene).unwrap();
            assert_eq!(data.kind(), SceneKind::Scalis);
            let camera = Camera::framing(scene.bounds(), [0.3, -0.4, -1.0], 40.0, 1.0).unwrap();
            let size = 10;
            let combos = [
                (Method::ScalisQuadratic, Mode::Opaque, 0),
                (Method::ScalisQuadratic, Mode::Transparent, 0),
                (Method::Interval, Mode::Opaque, 0),
                (Method::Interval, Mode::Transparent, 0),
                (Method::ScalisQuadratic, Mode::Transparent, 2),
                (Method::Interval, Mode::Transparent, 5),
            ];
            for (method, mode, leg_steps) in combos {
                {
                    let (settings, slots) = scalis_settings(size, method, mode);
                    let c = Constants {
                        leg_steps,
                        ..data.constants(&camera, &settings, slots)
                    };
                    let [offsets, lists, segments] = data.buffers(&camera, &settings);
                    assert_eq!(offsets.len(), (size * size + 1) as usize);
                    let (mut max_legs, mut tight) = (0, 0);
                    let lists: Vec<PrimitiveHit<f32>> = read_as(&lists);
                    let segments: Vec<ScalisSegment<f32>> = read_as(&segments);
                    assert_eq!(segments, data.segments);
                    let cpu = render_scene(&scene, &camera, &settings).unwrap();
                    let n = (size * size) as usize;
                    let none = Root {
                        t: 0.0,
                        side: Side::Touch,
                    };
                    let mut roots = vec![none; n * slots as usize];
                    let mut hits = vec![HitOut::default(); n * slots as usize];
                    let mut hit_pixels = 0;
                    for i in 0..n {
                        let (x, y) = (i as u32 % size, i as u32 / size);
                        let base = i * slots as usize;
                        let (mut leg, mut p) = (ScalisLeg::default(), PixelOut::default());
                        // in legs of `leg_steps` steps (0: one leg)
                        let mut legs = 0;
                        while leg.phase != PHASE_DONE {
                            legs += 1;
                            assert!(legs < 100_000, "{name} {method} {mode:?}: no progress");
                            k::render_scalis_leg(
                                &c, &offsets, &lists, &segments, x, y, &mut roots, &mut hits, base,
                                &mut leg, &mut p,
                            );
                            // the tight stage it left (the host's second
                            // dispatch of each round)
                            tight += u32::from(leg.state.walk.tight.status == TIGHT_REQUESTED);
                            k::render_scalis_tight_leg(
                                &c, &offsets, &lists, &segments, x, y, &mut leg,
                            );
                        }
                        max_legs = max_legs.max(legs);
                        let a = cpu.pixel(x, y).unwrap();
                        let s = &a.trace.stats;
                        assert_eq!(
                            (p.status, p.roots, p.steps, p.field_evals, p.bound_evals),
                            (
                                a.trace.status as u32,
                                a.trace.roots,
                                s.steps,
                                s.field_evals,
                                s.bound_evals
                            ),
                            "{name} {method} {mode:?} ({x}, {y})"
                        );
                        let want: Vec<(u32, u32, [u32; 3])> = cpu
                            .hits(x, y)
                            .iter()
                            .map(|h| (h.t.to_bits(), h.side as u32, h.normal.map(f32::to_bits)))
                            .collect();
                        let got: Vec<(u32, u32, [u32; 3])> = (0..p.roots as usize)
                            .map(|r| {
                                let h = hits[base + r];
                                (h.t.to_bits(), h.side, h.normal.map(f32::to_bits))
                            })
                            .collect();
                        assert_eq!(got, want, "{name} {method} {mode:?} ({x}, {y})");
                        hit_pixels += usize::from(!want.is_empty());
                    }
                    assert!(hit_pixels > 0, "{name} {method} {mode:?}: no pixel hits");
                    // short legs: many per pixel, the same records
                    assert!(leg_steps == 0 || max_legs > 3, "{max_legs}");
                    assert!(tight > 0, "{name} {method} {mode:?}: no tight stage");
                }
            }
        }
    }

    #[test]
    fn missing_module_names_the_build_command() {
        let e = GpuError::ShaderMissing {
            path: PathBuf::from("/nowhere/x.spv"),
        };
        let msg = e.to_string();
        assert!(
            msg.contains(BUILD_COMMAND) && msg.contains("/nowhere/x.spv"),
            "{msg}"
        );
        assert!(default_spirv_path().ends_with("spirv/boundtrace-gpu-shader.spv"));
        assert!(matches!(
            GpuTracer::with_spirv(b"not spir-v"),
            Err(GpuError::Shader(_))
        ));
    }
}
