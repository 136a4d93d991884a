//! How much field work one marching step takes: for each resumable method
//! and both modes, the most field evaluations any single step of a pixel
//! makes (every [`Field::eval`] call, in any number type, and every Taylor
//! bound call), over a small frame of a shipped scene.
//!
//! ```text
//! cargo run --release --example step_work -- [--scene molecule] [--size 8]
//!     [--methods sphere,segment,linear-taylor,quadratic-taylor]
//! ```
//!
//! This is the figure that decides whether a step fits lavapipe's loop
//! limit (65,535 loop iterations per group of 8 invocations and dispatch,
//! see `boundtrace_gpu_kernel::loops_complete`): a blob set's evaluation
//! loops once per blob, so a step of `k` evaluations over `n` blobs runs
//! at least `k·n` iterations. The frame and camera are the GPU difftests'
//! (`Camera::framing` of the scene's bounds from `[0.3, −0.4, −1]`, 40°).
//! Besides the worst pixel, each row of 8 pixels (a group of 8 lanes when
//! a workgroup's rows are its subgroups) gets the sum of its pixels' worst
//! steps: an upper estimate of one group step where the lanes diverge.
//!
//! The step guard is asked after each step and after each iteration of the
//! loops inside a step (`boundtrace::tracer::march::Inner`): work between
//! two such checks is what one leg must fit at least, so the last two
//! columns give the most calls between two checks (worst pixel, and the
//! worst row's sum). Single thread; counts, not times. Bad arguments exit
//! with 2.

use std::cell::Cell;
use std::process::ExitCode;

use boundtrace::inclusion::{Field, FieldNum, ForwardLinear, ForwardQuadratic, Ray};
use boundtrace::tracer::camera::ray_box_span;
use boundtrace::tracer::march::{MarchState, StepGuard};
use boundtrace::tracer::render::RenderSettings;
use boundtrace::tracer::scenes::{DEFAULT_SEED, Scene};
use boundtrace::tracer::{Camera, Method, Mode, Root, Side, trace_resume_in};

/// A field that counts its evaluations and Taylor bound calls.
struct Counted<'a, F> {
    field: &'a F,
    calls: &'a Cell<u64>,
}

impl<F> Counted<'_, F> {
    fn tick(&self) {
        self.calls.set(self.calls.get() + 1);
    }
}

impl<F: Field<f32>> Field<f32> for Counted<'_, F> {
    fn eval<N: FieldNum<f32>>(&self, p: [N; 3]) -> N {
        self.tick();
        self.field.eval(p)
    }
    fn lipschitz(&self) -> Option<f32> {
        self.field.lipschitz()
    }
    fn taylor_linear(&self, ray: &Ray<f32>, t0: f32, t1: f32) -> Option<ForwardLinear<f32>> {
        self.tick();
        self.field.taylor_linear(ray, t0, t1)
    }
    fn taylor_quadratic(&self, ray: &Ray<f32>, t0: f32, t1: f32) -> Option<ForwardQuadratic<f32>> {
        self.tick();
        self.field.taylor_quadratic(ray, t0, t1)
    }
}

/// A step guard that never pauses and records the calls of each step and
/// between two checks.
struct PerStep<'a> {
    calls: &'a Cell<u64>,
    /// The calls before the current step.
    before: u64,
    /// The calls at the last check.
    checked: u64,
    worst: u64,
    worst_between: u64,
    steps: u64,
}

impl StepGuard for PerStep<'_> {
    fn before_step(&mut self, _steps: u32) -> bool {
        self.before = self.calls.get();
        self.checked = self.before;
        self.steps += 1;
        true
    }
    fn after_step(&mut self) -> bool {
        let now = self.calls.get();
        // Within a step the calls since `before` only grow: the last
        // check of a step sees the whole step.
        self.worst = self.worst.max(now - self.before);
        self.worst_between = self.worst_between.max(now - self.checked);
        self.checked = now;
        true
    }
}

fn usage(msg: &str) -> ExitCode {
    eprintln!("step_work: {msg}");
    eprintln!("usage: step_work [--scene NAME] [--size N] [--methods M,M,...]");
    ExitCode::from(2)
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut scene_name = "molecule".to_string();
    let mut size = 8u32;
    let mut methods = vec![
        Method::Sphere,
        Method::Segment,
        Method::LinearTaylor,
        Method::QuadraticTaylor,
    ];
    let mut i = 0;
    while i < args.len() {
        let Some(v) = args.get(i + 1) else {
            return usage(&format!("{} needs a value", args[i]));
        };
        match args[i].as_str() {
            "--scene" => scene_name = v.clone(),
            "--size" => match v.parse::<u32>() {
                Ok(n) if (1..=256).contains(&n) => size = n,
                _ => return usage(&format!("--size {v}: a whole number in 1..=256")),
            },
            "--methods" => {
                let mut list = Vec::new();
                for name in v.split(',') {
                    match name.parse::<Method>() {
                        Ok(Method::Interval | Method::Affine | Method::ScalisQuadratic) => {
                            return usage(&format!("{name}: not a resumable marching method"));
                        }
                        Ok(m) => list.push(m),
                        Err(e) => return usage(&e.to_string()),
                    }
                }
                methods = list;
            }
            other => return usage(&format!("unknown argument {other}")),
        }
        i += 2;
    }
    let scene = match Scene::<f32>::build(&scene_name, DEFAULT_SEED) {
        Ok(s) => s,
        Err(e) => return usage(&e.to_string()),
    };
    let bounds = scene.bounds();
    let camera = match Camera::framing(bounds, [0.3, -0.4, -1.0], 40.0, 1.0) {
        Ok(c) => c,
        Err(e) => return usage(&format!("camera: {e}")),
    };
    println!(
        "{scene_name}: {size}x{size} pixels; field calls (evaluations and Taylor bounds) per step"
    );
    println!();
    println!(
        "| method | mode | steps | worst step (calls) | at pixel | worst row of 8: sum of its pixels' worst steps | worst between two checks (calls) | worst row of 8: sum |"
    );
    println!("| --- | --- | --: | --: | --- | --: | --: | --: |");
    for &method in &methods {
        for mode in [Mode::Opaque, Mode::Transparent] {
            let settings = match RenderSettings::new(size, size, method)
                .map(|s| s.with_mode(mode))
                .and_then(|s| s.with_max_roots(8))
            {
                Ok(s) => s,
                Err(e) => return usage(&format!("settings: {e}")),
            };
            let slots = match mode {
                Mode::Opaque => 1,
                Mode::Transparent => settings.max_roots as usize,
            };
            let (mut worst, mut at, mut steps, mut worst_row) = (0u64, (0, 0), 0u64, 0u64);
            let (mut worst_between, mut worst_row_between) = (0u64, 0u64);
            for y in 0..size {
                let mut row = vec![0u64; size as usize];
                let mut row_between = vec![0u64; size as usize];
                for x in 0..size {
                    let ray = camera.ray(x, y, size, size);
                    let Some(span) = ray_box_span(&ray, &bounds) else {
                        continue;
                    };
                    let calls = Cell::new(0);
                    let field = Counted {
                        field: scene.field(),
                        calls: &calls,
                    };
                    let blank = Root {
                        t: 0.0,
                        side: Side::Touch,
                    };
                    let mut roots = vec![blank; slots];
                    let mut state = MarchState::start(span, &settings.params);
                    let mut guard = PerStep {
                        calls: &calls,
                        before: 0,
                        checked: 0,
                        worst: 0,
                        worst_between: 0,
                        steps: 0,
                    };
                    let leg = trace_resume_in(
                        &field,
                        &ray,
                        span,
                        method,
                        mode,
                        &settings.params,
                        &mut roots,
                        [0, slots],
                        &mut state,
                        &mut guard,
                    );
                    if leg.paused {
                        eprintln!(
                            "step_work: pixel ({x}, {y}) paused under a guard that never pauses"
                        );
                        return ExitCode::FAILURE;
                    }
                    steps += guard.steps;
                    row[x as usize] = guard.worst;
                    row_between[x as usize] = guard.worst_between;
                    worst_between = worst_between.max(guard.worst_between);
                    if guard.worst > worst {
                        (worst, at) = (guard.worst, (x, y));
                    }
                }
                for group in row.chunks(8) {
                    worst_row = worst_row.max(group.iter().sum());
                }
                for group in row_between.chunks(8) {
                    worst_row_between = worst_row_between.max(group.iter().sum());
                }
            }
            println!(
                "| {method} | {mode:?} | {steps} | {worst} | ({}, {}) | {worst_row} | {worst_between} | {worst_row_between} |",
                at.0, at.1
            );
        }
    }
    ExitCode::SUCCESS
}
