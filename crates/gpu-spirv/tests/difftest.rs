//! Difftests: the SPIR-V tracer on wgpu against the CPU renderer, for every
//! standard scene with flat GPU data × every GPU method: `blobs` and
//! `blobs-sum` at 32 × 32, `molecule` (500 Gaussian atoms) at 8 × 8, and
//! by sphere tracing the blobtrees `aggregate-1` (16 × 16), `aggregate-2`
//! and `aggregate-3` (8 × 8), CSG and smooth ([`BLOBTREES`]), and tiled
//! `aggregate-2-smooth` to `aggregate-4-smooth` ([`TILED_BLOBTREES`]). On
//! lavapipe, whose llvmpipe ends every loop of 8 pixels after 65,535
//! iterations per dispatch, every `molecule` frame of [`MOLECULE_ON_LAVAPIPE`]
//! must render and match (steps, their inner bisections and normals resume
//! across dispatches); any other `molecule` frame must match or end in
//! `GpuError::LoopLimit` (BENCHMARKS.md "GPU", sessions 16 and 21).
//!
//! Same algorithm, same data, `f32` on both sides: hit/miss must agree on
//! ≥ 99.9 % of pixels, depths within 1e-3 (relative) where both hit, step
//! counts identical on ≥ 99 % of pixels, and the trace status identical on
//! ≥ 99.9 %.
//!
//! Sphere tracing, segment tracing and the forward Taylor, bottom-up and
//! mixed methods (the module's `trace_sphere` and the leg modules'
//! `trace_segment_*`, `trace_{linear,quadratic}_taylor_*`,
//! `trace_{linear,quadratic}_bottom_up_*` and
//! `trace_{linear,quadratic}_mixed_*` with `taylor_{linear,quadratic}_mixed_*`
//! entry points) run in CI on lavapipe, every pixel compared.
//! Needs the module and a Vulkan adapter
//! (lavapipe: `apt-get install mesa-vulkan-drivers libvulkan1`; both done
//! by `scripts/gpu-test.sh`). Without either the tests FAIL when `CI` is
//! set (`true`/`1`) and are skipped loudly otherwise.

use boundtrace_fields::homothetic::{Segment, SegmentKernel};
use boundtrace_fields::homothetic_skeleton::HomotheticSkeleton;
use boundtrace_gpu::{GpuError, GpuScene, GpuTracer, MAX_GPU_ROOTS};
use boundtrace_inclusion::Field;
use boundtrace_tracer::camera::Camera;
use boundtrace_tracer::render::{Frame, RenderSettings, render_scene, render_serial};
use boundtrace_tracer::scenes::{DEFAULT_SEED, Scene, SceneField, WithLipschitz};
use boundtrace_tracer::tile_programs::{TilePrograms, render_tile_programs};
use boundtrace_tracer::{Method, Mode};
use std::sync::{Mutex, MutexGuard, Once, PoisonError};

/// A scene of the difftests: its name, the frame's side in pixels, and
/// whether [`short_legs_match`] runs on it too.
type SceneCase = (&'static str, u32, bool);

/// The scenes with flat GPU data, by scene kind: the leg methods have one
/// module per kind, and [`run`] gives each kind a tracer of its own, so
/// that one such pipeline is alive at a time (on lavapipe a leg method's
/// pipeline takes several GB: the forward-Taylor difftests peaked at
/// 13.7 GB and 16.3 GB with both kinds' pipelines in one tracer, session
/// 25). Sphere tracing has one module for both kinds: one tracer for all.
const SCENES: [&[SceneCase]; 2] = [
    &[("blobs", 32, true)],
    &[("blobs-sum", 32, true), ("molecule", 8, false)],
];

/// The blobtree scenes (`aggregate-*`, flat blobtrees of A-SDF primitives
/// under CSG or compact smooth unions), traced on the GPU by sphere tracing
/// only (the `sphere-blobtree` module), with the tracer of the tiled
/// blobtrees ([`TILED_BLOBTREES`]). `aggregate-4`
/// (11,110 primitives) ends in `GpuError::LoopLimit` on lavapipe: a
/// normal (three evaluations of 22,219 nodes) needs more than its 65,535
/// loop iterations, and so does a step where the 8 pixels of a group
/// evaluate the tree at different places of the step's code
/// (BENCHMARKS.md "GPU", session 24); tiled, it renders.
const BLOBTREES: &[SceneCase] = &[
    ("aggregate-1", 16, true),
    ("aggregate-1-smooth", 16, false),
    ("aggregate-2", 8, false),
    ("aggregate-2-smooth", 8, false),
    ("aggregate-3", 8, false),
    ("aggregate-3-smooth", 8, false),
];

/// The `molecule` frames that fit lavapipe's loop limit: they must render
/// and match the CPU there — since session 21 (resumable inner loops of a
/// step) every leg method in both modes, and since session 32 the mixed
/// ones too (a mixed step, both bounds over every atom, needed more loop
/// iterations than one dispatch allows until the Taylor side got a
/// dispatch of its own: BENCHMARKS.md "GPU", sessions 28 and 32). Any
/// other frame must match or end in [`GpuError::LoopLimit`] on a CPU
/// adapter (BENCHMARKS.md "GPU", sessions 16 and 21), and match elsewhere.
const MOLECULE_ON_LAVAPIPE: [(Method, Mode); 16] = [
    (Method::Sphere, Mode::Opaque),
    (Method::Sphere, Mode::Transparent),
    (Method::Segment, Mode::Opaque),
    (Method::Segment, Mode::Transparent),
    (Method::LinearTaylor, Mode::Opaque),
    (Method::LinearTaylor, Mode::Transparent),
    (Method::QuadraticTaylor, Mode::Opaque),
    (Method::QuadraticTaylor, Mode::Transparent),
    (Method::LinearBottomUp, Mode::Opaque),
    (Method::LinearBottomUp, Mode::Transparent),
    (Method::QuadraticBottomUp, Mode::Opaque),
    (Method::QuadraticBottomUp, Mode::Transparent),
    (Method::LinearMixed, Mode::Opaque),
    (Method::LinearMixed, Mode::Transparent),
    (Method::QuadraticMixed, Mode::Opaque),
    (Method::QuadraticMixed, Mode::Transparent),
];

/// The marching methods (the GPU methods of the issue).
const METHODS: [Method; 8] = [
    Method::Sphere,
    Method::Segment,
    Method::LinearTaylor,
    Method::LinearBottomUp,
    Method::LinearMixed,
    Method::QuadraticTaylor,
    Method::QuadraticBottomUp,
    Method::QuadraticMixed,
];

fn in_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true" || v == "1")
}

/// A tracer of one test: GPU tests run one at a time, each with its
/// tracers, dropped (with their pipelines) before the next test starts. On
/// a CPU adapter with a cold shader cache, lavapipe holds several gigabytes
/// per compiled pipeline until the pipeline is dropped (BENCHMARKS.md
/// "GPU", sessions 13 and 25): a tracer shared by every test, or tests in
/// parallel, passed 20 GB.
struct Gpu {
    tracer: GpuTracer,
    _one: MutexGuard<'static, ()>,
}

impl std::ops::Deref for Gpu {
    type Target = GpuTracer;
    fn deref(&self) -> &GpuTracer {
        &self.tracer
    }
}

fn gpu() -> Option<Gpu> {
    static ONE: Mutex<()> = Mutex::new(());
    static SHOWN: Once = Once::new();
    let one = ONE.lock().unwrap_or_else(PoisonError::into_inner);
    match GpuTracer::new() {
        Ok(g) => {
            SHOWN.call_once(|| eprintln!("GPU difftests on {:?}", g.adapter_info()));
            Some(Gpu {
                tracer: g,
                _one: one,
            })
        }
        Err(e @ (GpuError::NoAdapter(_) | GpuError::ShaderMissing { .. })) if in_ci() => {
            panic!("CI must run the GPU difftests, but: {e}")
        }
        Err(e @ (GpuError::NoAdapter(_) | GpuError::ShaderMissing { .. })) => {
            eprintln!("\n!!!!!!!! SKIPPING the GPU difftests: {e} !!!!!!!!\n");
            None
        }
        Err(e) => panic!("GPU error: {e}"),
    }
}

/// Compares two frames; `Err` with a description when a threshold fails,
/// or when the CPU's frame hits nothing (a method unsupported on the scene
/// gives such frames on both sides: nothing would be compared).
fn compare(cpu: &Frame<f32>, gpu: &Frame<f32>) -> Result<String, String> {
    let (w, h) = (cpu.width(), cpu.height());
    let n = (w * h) as usize;
    let (mut hit_diff, mut step_diff, mut status_diff, mut roots_diff) = (0, 0, 0, 0);
    let mut cpu_hits = 0;
    let mut worst_depth = 0.0f32;
    let mut shown = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let (a, b) = (cpu.pixel(x, y).unwrap(), gpu.pixel(x, y).unwrap());
            let (ha, hb) = (cpu.hits(x, y), gpu.hits(x, y));
            cpu_hits += usize::from(!ha.is_empty());
            if ha.is_empty() != hb.is_empty() {
                hit_diff += 1;
            }
            if ha.len() != hb.len() {
                roots_diff += 1;
            }
            for (p, q) in ha.iter().zip(hb) {
                let rel = (p.t - q.t).abs() / p.t.abs().max(1e-6);
                worst_depth = worst_depth.max(rel);
            }
            if a.trace.stats.steps != b.trace.stats.steps {
                step_diff += 1;
            }
            if a.trace.status != b.trace.status {
                status_diff += 1;
            }
            if (a.trace, ha.len()) != (b.trace, hb.len()) && shown.len() < 4 {
                shown.push(format!(
                    "({x}, {y}): cpu {:?} {} roots {:?}, gpu {:?} {} roots {:?}",
                    a.trace,
                    ha.len(),
                    ha.iter().map(|h| (h.t, h.side)).collect::<Vec<_>>(),
                    b.trace,
                    hb.len(),
                    hb.iter().map(|h| (h.t, h.side)).collect::<Vec<_>>()
                ));
            }
        }
    }
    let frac = |k: usize| k as f64 / n as f64;
    let summary = format!(
        "{cpu_hits} pixels hit; hit/miss differ {hit_diff}, root counts differ {roots_diff}, steps differ {step_diff}, \
         status differs {status_diff} of {n}; worst relative depth {worst_depth:.2e}; \
         mean steps cpu {:.2} gpu {:.2}{}",
        cpu.totals().mean_steps(),
        gpu.totals().mean_steps(),
        if shown.is_empty() {
            String::new()
        } else {
            format!("; differing pixels: {}", shown.join("; "))
        }
    );
    let ok = cpu_hits > 0
        && frac(hit_diff) <= 0.001
        && frac(roots_diff) <= 0.001
        && frac(status_diff) <= 0.001
        && frac(step_diff) <= 0.01
        && worst_depth <= 1e-3;
    if ok { Ok(summary) } else { Err(summary) }
}

/// Every pixel of `scenes` × `methods` × both modes against the CPU, with
/// one tracer (so that each pipeline is compiled once) and, with `legs`,
/// [`short_legs_match`] with the same pipelines on the scenes that ask for
/// it. Returns the failures.
fn run_with(gpu: &GpuTracer, methods: &[Method], scenes: &[SceneCase], legs: bool) -> Vec<String> {
    let mut failures = Vec::new();
    for &(name, size, scene_legs) in scenes {
        one_scene(gpu, methods, name, size, legs && scene_legs, &mut failures);
    }
    failures
}

/// [`run_with`] every scene of [`SCENES`]: with one tracer for all when
/// `methods` is sphere tracing alone (one module for every kind), else one
/// tracer per kind; asserts that nothing failed.
fn run(methods: &[Method], legs: bool) {
    let mut failures = Vec::new();
    if methods == [Method::Sphere] {
        let Some(gpu) = gpu() else { return };
        for scenes in SCENES {
            failures.extend(run_with(&gpu, methods, scenes, legs));
        }
    } else {
        for scenes in SCENES {
            let Some(gpu) = gpu() else { return };
            failures.extend(run_with(&gpu, methods, scenes, legs));
        }
    }
    assert_none_failed(&failures);
}

/// Fails the test with every failure listed, if any.
fn assert_none_failed(failures: &[String]) {
    assert!(
        failures.is_empty(),
        "GPU/CPU differences:\n{}",
        failures.join("\n")
    );
}

/// [`run`] on one scene with the tracer `gpu`; appends what fails.
fn one_scene(
    gpu: &GpuTracer,
    methods: &[Method],
    name: &str,
    size: u32,
    legs: bool,
    failures: &mut Vec<String>,
) {
    let scene = Scene::<f32>::build(name, DEFAULT_SEED).unwrap();
    scene_frames(gpu, methods, &scene, size, legs, failures);
}

/// [`one_scene`] for a scene built by the caller.
fn scene_frames(
    gpu: &GpuTracer,
    methods: &[Method],
    scene: &Scene<f32>,
    size: u32,
    legs: bool,
    failures: &mut Vec<String>,
) {
    let name = scene.name();
    let data = GpuScene::from_scene(scene).unwrap();
    let camera = Camera::framing(scene.bounds(), [0.3, -0.4, -1.0], 40.0, 1.0).unwrap();
    for &method in methods {
        for mode in [Mode::Opaque, Mode::Transparent] {
            let settings = RenderSettings::new(size, size, method)
                .unwrap()
                .with_mode(mode)
                .with_max_roots(MAX_GPU_ROOTS)
                .unwrap();
            let lavapipe = gpu.adapter_info().device_type == wgpu::DeviceType::Cpu;
            let case = (method, mode);
            let t = std::time::Instant::now();
            let cpu = render_serial(scene.field(), &camera, scene.bounds(), &settings).unwrap();
            let cpu_s = t.elapsed().as_secs_f64();
            let t = std::time::Instant::now();
            let rendered = gpu.render_in_legs(&data, &camera, &settings, 0);
            let gpu_s = t.elapsed().as_secs_f64();
            let (g, dispatches) = match rendered {
                Ok(r) => r,
                Err(GpuError::LoopLimit { pixels, shading })
                    if lavapipe && name == "molecule" && !MOLECULE_ON_LAVAPIPE.contains(&case) =>
                {
                    eprintln!(
                        "cut  {name:20} {method:20} {mode:?}: lavapipe's loop limit \
                         ({pixels} pixels made no progress, {shading} of them shading); \
                         CPU {cpu_s:.2} s, GPU {gpu_s:.2} s"
                    );
                    continue;
                }
                Err(e) => {
                    failures.push(format!("{name} {method} {mode:?}: {e}"));
                    eprintln!("FAIL {name:20} {method:20} {mode:?}: {e}");
                    continue;
                }
            };
            if method == Method::Sphere && name == "blobs-sum" && lavapipe {
                // lavapipe's loop limit cuts the busiest rays: legs must
                // have run (and still match).
                assert!(dispatches > 1, "lavapipe traced {name} in one dispatch");
            }
            match compare(&cpu, &g) {
                Ok(s) => {
                    eprintln!(
                        "ok   {name:20} {method:20} {mode:?}: {s}; {dispatches} dispatches; \
                         CPU {cpu_s:.2} s, GPU {gpu_s:.2} s"
                    )
                }
                Err(s) => {
                    eprintln!(
                        "FAIL {name:20} {method:20} {mode:?}: {s}; CPU {cpu_s:.2} s, GPU {gpu_s:.2} s"
                    );
                    failures.push(format!("{name} {method} {mode:?}: {s}"));
                }
            }
            if legs {
                if let Err(s) = short_legs_match(gpu, &data, &camera, name, method, mode) {
                    failures.push(s);
                }
            }
        }
    }
}

/// Resumption on the GPU: legs of at most 7 steps per dispatch give the
/// frame of unlimited legs, bit for bit (records, roots and normals), at
/// 16 × 16; `Err` with the summary otherwise.
fn short_legs_match(
    gpu: &GpuTracer,
    data: &GpuScene,
    camera: &Camera<f32>,
    name: &str,
    method: Method,
    mode: Mode,
) -> Result<(), String> {
    let settings = RenderSettings::new(16, 16, method)
        .unwrap()
        .with_mode(mode)
        .with_max_roots(MAX_GPU_ROOTS)
        .unwrap();
    let (whole, d0) = gpu.render_in_legs(data, camera, &settings, 0).unwrap();
    let (legs, d7) = gpu.render_in_legs(data, camera, &settings, 7).unwrap();
    let max_steps = (0..16 * 16)
        .map(|i| whole.pixel(i % 16, i / 16).unwrap().trace.stats.steps)
        .max()
        .unwrap();
    let mut differ = 0;
    for y in 0..16 {
        for x in 0..16 {
            let (a, b) = (whole.pixel(x, y).unwrap(), legs.pixel(x, y).unwrap());
            let same_hits = whole.hits(x, y).len() == legs.hits(x, y).len()
                && whole.hits(x, y).iter().zip(legs.hits(x, y)).all(|(p, q)| {
                    p.t.to_bits() == q.t.to_bits()
                        && p.side == q.side
                        && p.normal.map(f32::to_bits) == q.normal.map(f32::to_bits)
                });
            differ += usize::from(a != b || !same_hits);
        }
    }
    let summary = format!(
        "{name} {method} {mode:?}: {differ} of 256 pixels differ; {d0} dispatches unlimited, \
         {d7} in legs of 7 steps (max {max_steps} steps)"
    );
    eprintln!("legs {summary}");
    if differ > 0 || d7 < max_steps.div_ceil(7) {
        Err(format!("legs: {summary}"))
    } else {
        Ok(())
    }
}

/// Sphere tracing (the module's `trace_sphere` entry point, run in CI on
/// lavapipe) against the CPU on every pixel of the scenes ([`SCENES`]), opaque and
/// transparent, with the thresholds.
///
/// On lavapipe, llvmpipe's loop limit (65,535 loop iterations per 8-lane
/// group) cuts the busiest rays of `blobs-sum` short in one dispatch: the
/// shader traces in legs that a cut undoes, and the host dispatches until
/// every pixel is done. The test checks that this happened there (more
/// than one dispatch on a CPU adapter) and still matches the CPU.
#[test]
fn sphere_matches_the_cpu_in_both_modes() {
    run(&[Method::Sphere], true);
}

/// Sphere tracing of flat blobtrees (the `sphere-blobtree` module's
/// `trace_sphere_blobtree`) against the CPU on every pixel of the
/// [`BLOBTREES`] scenes, opaque and transparent, with the issue's
/// thresholds, resumed legs on `aggregate-1`; then, with the same pipeline,
/// the tiled blobtrees ([`tiled_blobtrees_match`]).
#[test]
fn sphere_matches_the_cpu_on_blobtrees_whole_and_tiled() {
    let Some(gpu) = gpu() else { return };
    let mut failures = run_with(&gpu, &[Method::Sphere], BLOBTREES, true);
    failures.extend(tiled_blobtrees_match(&gpu));
    assert_none_failed(&failures);
}

/// The tiled blobtree scenes: name and frame side (tile programs are
/// built for each frame's camera and size).
const TILED_BLOBTREES: [(&str, u32); 4] = [
    ("aggregate-2-smooth", 16),
    ("aggregate-3", 16),
    ("aggregate-4", 16),
    ("aggregate-4-smooth", 8),
];

/// Tiled blobtrees (`GpuScene::from_tile_programs`: one program per 8 × 8
/// tile, a workgroup's pixels evaluate their tile's program) against the
/// CPU twin (`render_tile_programs`, the same programs), every pixel, both
/// modes, with the thresholds (`tests/tracer_tile_programs.rs`
/// compares the CPU twin with the full tree); a frame of another size is
/// refused. `aggregate-4`, whose full tree lavapipe's loop limit refuses,
/// renders tiled. Returns the failures.
fn tiled_blobtrees_match(gpu: &GpuTracer) -> Vec<String> {
    let mut failures = Vec::new();
    for (name, size) in TILED_BLOBTREES {
        let scene = Scene::<f32>::build(name, DEFAULT_SEED).unwrap();
        let SceneField::Blobtree(tree) = scene.field() else {
            panic!("{name} is a blobtree")
        };
        let camera = Camera::framing(scene.bounds(), [0.3, -0.4, -1.0], 40.0, 1.0).unwrap();
        let programs = TilePrograms::build(tree, &camera, scene.bounds(), size, size).unwrap();
        let data = GpuScene::from_tile_programs(&scene, &programs).unwrap();
        for mode in [Mode::Opaque, Mode::Transparent] {
            let settings = RenderSettings::new(size, size, Method::Sphere)
                .unwrap()
                .with_mode(mode)
                .with_max_roots(MAX_GPU_ROOTS)
                .unwrap();
            let t = std::time::Instant::now();
            let twin =
                render_tile_programs(&programs, tree.as_ref(), &camera, scene.bounds(), &settings)
                    .unwrap();
            let cpu_s = t.elapsed().as_secs_f64();
            let t = std::time::Instant::now();
            let rendered = gpu.render_in_legs(&data, &camera, &settings, 0);
            let gpu_s = t.elapsed().as_secs_f64();
            let what = format!(
                "{name} {mode:?}, tiles of {:.1} nodes on average (max {}, tree {})",
                programs.mean_nodes(),
                programs.max_nodes(),
                tree.len()
            );
            match rendered
                .map_err(|e| e.to_string())
                .and_then(|(g, d)| compare(&twin, &g).map(|s| format!("{s}; {d} dispatches")))
            {
                Ok(s) => eprintln!("ok   tiled {what}: {s}; CPU {cpu_s:.2} s, GPU {gpu_s:.2} s"),
                Err(s) => {
                    eprintln!("FAIL tiled {what}: {s}");
                    failures.push(format!("tiled {what}: {s}"));
                }
            }
        }
        // A frame of another size is refused.
        let other = RenderSettings::new(size + 8, size, Method::Sphere).unwrap();
        assert!(matches!(
            gpu.render(&data, &camera, &other),
            Err(GpuError::UnsupportedScene(_))
        ));
    }
    failures
}

/// Segment tracing (the segment modules' `trace_segment_*` entry points, in legs like
/// sphere tracing) against the CPU on every pixel of the scenes ([`SCENES`]), opaque
/// and transparent, with the thresholds.
#[test]
fn segment_matches_the_cpu_in_both_modes() {
    run(&[Method::Segment], true);
}

/// Forward linear inclusions from Taylor bounds (the leg modules'
/// `trace_linear_taylor_*` entry points) against the CPU on every pixel of
/// the scenes ([`SCENES`]), opaque and transparent, with the thresholds.
#[test]
fn linear_taylor_matches_the_cpu_in_both_modes() {
    run(&[Method::LinearTaylor], true);
}

/// [`linear_taylor_matches_the_cpu_in_both_modes`] for forward quadratic
/// inclusions (`trace_quadratic_taylor_*`).
#[test]
fn quadratic_taylor_matches_the_cpu_in_both_modes() {
    run(&[Method::QuadraticTaylor], true);
}

/// Forward linear bottom-up bounds (the field evaluated in
/// `ForwardLinear` arithmetic; the leg modules' `trace_linear_bottom_up_*`
/// entry points) against the CPU on every pixel of the scenes ([`SCENES`]),
/// opaque and transparent, with the thresholds.
#[test]
fn linear_bottom_up_matches_the_cpu_in_both_modes() {
    run(&[Method::LinearBottomUp], true);
}

/// [`linear_bottom_up_matches_the_cpu_in_both_modes`] for forward quadratic
/// bottom-up bounds (`ForwardQuadratic` arithmetic;
/// `trace_quadratic_bottom_up_*`).
#[test]
fn quadratic_bottom_up_matches_the_cpu_in_both_modes() {
    run(&[Method::QuadraticBottomUp], true);
}

/// Forward linear mixed bounds (bottom-up and Taylor, the tighter side of
/// each: `trace_linear_mixed_*` legs with the Taylor side filled by
/// `taylor_linear_mixed_*` between them) against the CPU on every pixel of
/// the scenes ([`SCENES`]), opaque and transparent, with the issue's
/// thresholds.
#[test]
fn linear_mixed_matches_the_cpu_in_both_modes() {
    run(&[Method::LinearMixed], true);
}

/// [`linear_mixed_matches_the_cpu_in_both_modes`] for forward quadratic
/// mixed bounds (`trace_quadratic_mixed_*`, `taylor_quadratic_mixed_*`).
#[test]
fn quadratic_mixed_matches_the_cpu_in_both_modes() {
    run(&[Method::QuadraticMixed], true);
}

/// The HRBF scenes ([`SceneCase`]s), with modules of their own (`*-hrbf`).
const HRBF_SCENES: &[SceneCase] = &[("hrbf-8", 24, true), ("hrbf-17", 24, false)];

/// The GPU methods of the HRBF scenes: segment tracing with the CPU's bound
/// (Galin et al.'s `λ` from bottom-up lines, `trace_segment_hrbf`), the
/// forward bottom-up methods (`trace_linear_bottom_up_hrbf`,
/// `trace_quadratic_bottom_up_hrbf`) and the mixed ones (their bottom-up
/// side alone, as on the CPU: `{trace,taylor}_*_mixed_hrbf`), against the
/// CPU on every pixel of
/// `hrbf-8` and `hrbf-17`, opaque and transparent, with the issue's
/// thresholds. (An HRBF has no global Lipschitz or Taylor bound: sphere
/// tracing and the Taylor methods are unsupported on it, on the CPU too.)
#[test]
fn hrbf_methods_match_the_cpu_in_both_modes() {
    let Some(gpu) = gpu() else { return };
    let methods = [
        Method::Segment,
        Method::LinearBottomUp,
        Method::QuadraticBottomUp,
        Method::LinearMixed,
        Method::QuadraticMixed,
    ];
    assert_none_failed(&run_with(&gpu, &methods, HRBF_SCENES, true));
}

/// The homothetic-distance skeleton of `examples/scenes/skeleton-homothetic.json`
/// (compact kernel of degree 4, `σ = 1.6`, five segments; the GPU tests
/// cannot read scene files, which the CLI crate parses), as its loader
/// builds it: bounds from the supports, the skeleton's own Lipschitz bound.
fn homothetic_scene() -> Scene<f32> {
    let v: [([f32; 3], f32); 6] = [
        ([0.0, -0.8, 0.0], 0.16),
        ([0.0, 0.0, 0.0], 0.12),
        ([-0.5, 0.45, 0.1], 0.06),
        ([0.45, 0.5, -0.1], 0.08),
        ([0.05, 0.75, 0.3], 0.05),
        ([-0.6, -0.75, 0.2], 0.04),
    ];
    let segments: Vec<Segment<f32>> = [(0, 1), (1, 2), (1, 3), (1, 4), (0, 5)]
        .iter()
        .map(|&(i, j)| Segment::new(v[i].0, v[i].1, v[j].0, v[j].1).unwrap())
        .collect();
    let kernel = SegmentKernel::compact_polynomial(4, 1.6).unwrap();
    let sk = HomotheticSkeleton::new(segments, kernel, 1.0).unwrap();
    let mut bounds = [[f32::INFINITY; 3], [f32::NEG_INFINITY; 3]];
    for s in sk.segments() {
        let [lo, hi] = sk.support_box(s).unwrap();
        for k in 0..3 {
            bounds[0][k] = bounds[0][k].min(lo[k]);
            bounds[1][k] = bounds[1][k].max(hi[k]);
        }
    }
    let l = sk.lipschitz().unwrap();
    let n = sk.segment_count();
    let field = SceneField::Homothetic(WithLipschitz::new(sk, l));
    Scene::from_parts(
        "skeleton-homothetic",
        String::new(),
        bounds,
        [0.0; 3],
        field,
        n,
    )
    .unwrap()
}

/// The GPU methods of the homothetic-distance skeletons (`*-homothetic`
/// modules): sphere tracing with the scene's global Lipschitz bound,
/// segment tracing and `linear-taylor` with the skeleton's directional
/// Lipschitz lines, and `linear-bottom-up`, against the CPU on every pixel
/// of [`homothetic_scene`], opaque and transparent, with the issue's
/// thresholds, and in legs of 7 steps against unlimited legs
/// ([`homothetic_methods`]).
#[test]
fn homothetic_methods_match_the_cpu_in_both_modes() {
    homothetic_methods(&[
        Method::Sphere,
        Method::Segment,
        Method::LinearTaylor,
        Method::LinearBottomUp,
    ]);
}

/// [`homothetic_methods_match_the_cpu_in_both_modes`] for
/// `quadratic-bottom-up` and `linear-mixed` (a separate test, so that CI
/// can run the homothetic pipelines' compilations on two cores).
#[test]
fn homothetic_bottom_up_and_mixed_match_the_cpu_in_both_modes() {
    homothetic_methods(&[Method::QuadraticBottomUp, Method::LinearMixed]);
}

/// [`homothetic_methods_match_the_cpu_in_both_modes`] for
/// `quadratic-mixed` (its two pipelines, on a core of their own in CI).
#[test]
fn homothetic_quadratic_mixed_matches_the_cpu_in_both_modes() {
    homothetic_methods(&[Method::QuadraticMixed]);
}

/// The homothetic difftest of `methods`, each with a tracer of its own
/// (dropped with its pipelines: lavapipe keeps a pipeline's compile
/// memory, several GB, until then; one tracer for five methods reached
/// 13.7 GB).
fn homothetic_methods(methods: &[Method]) {
    let mut failures = Vec::new();
    for &method in methods {
        let Some(gpu) = gpu() else { return };
        scene_frames(
            &gpu,
            &[method],
            &homothetic_scene(),
            24,
            true,
            &mut failures,
        );
    }
    assert_none_failed(&failures);
}

/// The SCALIS skeletons and the size of their difftest frames.
const SCALIS_SCENES: [(&str, u32); 3] = [
    ("scalis-tree", 16),
    ("scalis-random", 16),
    ("scalis-foam", 16),
];

/// `scalis-quadratic` and the per-primitive `interval` bisection on the
/// SCALIS skeletons (the `scalis` module's `trace_scalis` and
/// `trace_scalis_tight`, over the frame's primitive lists built on the
/// host), both modes, every pixel against the CPU renderer's
/// `render_scene` (which builds the same lists per ray): every pixel
/// equals the CPU's (records, roots, depths, step counts), `interval`
/// since session 32 and `scalis-quadratic` since session 33, when the
/// oracle lost the `Option` and early returns that lavapipe miscompiled
/// (BENCHMARKS.md "GPU", session 33). lavapipe compiles the two
/// pipelines, shared by both methods, in about 4.5 min and 8.6 GB.
#[test]
fn scalis_methods_match_the_cpu_in_both_modes() {
    scalis_methods(&[Method::ScalisQuadratic, Method::Interval]);
}

/// The SCALIS difftest of `methods`: [`SCALIS_SCENES`], both modes.
fn scalis_methods(methods: &[Method]) {
    let Some(gpu) = gpu() else { return };
    let lavapipe = gpu.adapter_info().device_type == wgpu::DeviceType::Cpu;
    let mut failures = Vec::new();
    for (name, size) in SCALIS_SCENES {
        let scene = Scene::<f32>::build(name, DEFAULT_SEED).unwrap();
        let data = GpuScene::from_scene(&scene).unwrap();
        let camera = Camera::framing(scene.bounds(), [0.3, -0.4, -1.0], 40.0, 1.0).unwrap();
        // Like for like: the CPU's per-ray lists hold at most
        // SCALIS_LIST_CAPACITY hits (beyond, it traces `segment`), the GPU's
        // are complete.
        let SceneField::Scalis(w) = scene.field() else {
            panic!("{name} is not a SCALIS scene")
        };
        let longest = longest_list(w.field().segments(), scene.bounds(), &camera, size);
        assert!(
            longest <= boundtrace_tracer::stats::SCALIS_LIST_CAPACITY,
            "{name}: a ray crosses {longest} supports"
        );
        for &method in methods {
            for mode in [Mode::Opaque, Mode::Transparent] {
                let settings = RenderSettings::new(size, size, method)
                    .unwrap()
                    .with_mode(mode)
                    .with_max_roots(MAX_GPU_ROOTS)
                    .unwrap();
                let t = std::time::Instant::now();
                let cpu = render_scene(&scene, &camera, &settings).unwrap();
                let cpu_s = t.elapsed().as_secs_f64();
                let t = std::time::Instant::now();
                let rendered = gpu.render_in_legs(&data, &camera, &settings, 0);
                let gpu_s = t.elapsed().as_secs_f64();
                let (g, dispatches) = match rendered {
                    Ok(r) => r,
                    Err(e) => {
                        eprintln!("FAIL {name:20} {method:20} {mode:?}: {e}");
                        failures.push(format!("{name} {method} {mode:?}: {e}"));
                        continue;
                    }
                };
                match compare(&cpu, &g) {
                    Ok(s) => eprintln!(
                        "ok   {name:20} {method:20} {mode:?}: {s}; {dispatches} dispatches; \
                         CPU {cpu_s:.2} s, GPU {gpu_s:.2} s (lavapipe: {lavapipe}); \
                         longest list {longest}"
                    ),
                    Err(s) => {
                        eprintln!("FAIL {name:20} {method:20} {mode:?}: {s}");
                        failures.push(format!("{name} {method} {mode:?}: {s}"));
                    }
                }
            }
        }
    }
    assert_none_failed(&failures);
}

/// The most supports a ray of a `size` × `size` frame through `camera`
/// crosses in the box `bounds`.
fn longest_list(
    segments: &[boundtrace_fields::scalis::ScalisSegment<f32>],
    bounds: [[f32; 3]; 2],
    camera: &Camera<f32>,
    size: u32,
) -> usize {
    let mut rays = Vec::new();
    for y in 0..size {
        for x in 0..size {
            let ray = camera.ray(x, y, size, size);
            if let Some(span) = boundtrace_tracer::camera::ray_box_span(&ray, &bounds) {
                rays.push((ray, span));
            }
        }
    }
    let lists = boundtrace_tracer::scalis::PrimitiveLists::build(segments, &rays);
    (0..lists.len())
        .map(|i| lists.hits(i).len())
        .max()
        .unwrap_or(0)
}

#[test]
fn methods_without_an_entry_point_are_refused_clearly() {
    let Some(gpu) = gpu() else { return };
    if gpu.entry_points().iter().any(|e| e == "trace_pixels") {
        eprintln!("the module has trace_pixels: nothing to refuse");
        return;
    }
    let scene = Scene::<f32>::build("blobs", DEFAULT_SEED).unwrap();
    let data = GpuScene::from_scene(&scene).unwrap();
    let camera = Camera::framing(scene.bounds(), [0.0, 0.0, -1.0], 40.0, 1.0).unwrap();
    // What the module set lists is what it renders: under CI every leg
    // module is built (scripts/build-spirv.sh; the SCALIS module has
    // `scalis-quadratic` and `interval`).
    let listed = gpu.methods();
    if std::env::var_os("CI").is_some() {
        assert_eq!(
            listed,
            [
                Method::Sphere,
                Method::Segment,
                Method::LinearTaylor,
                Method::QuadraticTaylor,
                Method::LinearBottomUp,
                Method::QuadraticBottomUp,
                Method::LinearMixed,
                Method::QuadraticMixed,
                Method::ScalisQuadratic,
                Method::Interval,
            ]
        );
    }
    // Affine has no GPU code at all.
    assert!(!listed.contains(&Method::Affine), "{listed:?}");
    let settings = RenderSettings::new(8, 8, Method::Affine).unwrap();
    let err = gpu.render(&data, &camera, &settings).unwrap_err();
    assert!(
        matches!(
            err,
            GpuError::MethodUnavailable {
                method: Method::Affine,
                ..
            }
        ),
        "{err}"
    );
    let msg = err.to_string();
    assert!(
        msg.contains("affine") && msg.contains("trace_pixels"),
        "{msg}"
    );
    // A leg method whose module is absent names the missing file and the
    // build command.
    let main = std::fs::read(boundtrace_gpu::default_spirv_path()).unwrap();
    let alone = GpuTracer::with_spirv(&main).unwrap();
    assert_eq!(alone.methods(), [Method::Sphere]);
    let settings = RenderSettings::new(8, 8, Method::QuadraticMixed).unwrap();
    let err = alone.render(&data, &camera, &settings).unwrap_err();
    let msg = err.to_string();
    assert!(
        matches!(
            err,
            GpuError::MethodUnavailable {
                method: Method::QuadraticMixed,
                ..
            }
        ) && msg.contains("quadratic-mixed-groups.spv")
            && msg.contains("build-spirv.sh"),
        "{msg}"
    );
}

const TRACE_PIXELS: &str = "needs the trace_pixels entry point (BOUNDTRACE_SHADER_FEATURES=trace \
     scripts/build-spirv.sh) and a driver that compiles it; lavapipe inlines every call and runs \
     out of memory on it (BENCHMARKS.md GPU)";

/// Every marching method, every scene, both modes (all roots in
/// transparent mode): needs `trace_pixels`.
#[test]
#[ignore = "needs trace_pixels (BOUNDTRACE_SHADER_FEATURES=trace) and a driver that compiles it: lavapipe cannot (BENCHMARKS.md GPU)"]
fn every_scene_and_method_matches_the_cpu_in_both_modes() {
    eprintln!("{TRACE_PIXELS}");
    run(&METHODS, false);
}
