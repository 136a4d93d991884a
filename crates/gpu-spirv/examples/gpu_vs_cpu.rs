//! GPU (SPIR-V on wgpu) vs CPU render time for a few scenes and methods:
//! `sphere`, `segment`, `linear-taylor` and `quadratic-taylor` (the
//! `trace_sphere`, `trace_segment_*`, `trace_linear_taylor_*` and
//! `trace_quadratic_taylor_*` entry points, built by default), and the
//! bottom-up and mixed methods when the module has `trace_pixels`
//! ([`GpuTracer::methods`] lists them)
//! (`BOUNDTRACE_SHADER_FEATURES=trace scripts/build-spirv.sh`; see
//! BENCHMARKS.md "GPU"). Needs a Vulkan adapter.
//!
//! ```text
//! scripts/build-spirv.sh
//! cargo run --release -p boundtrace-gpu --example gpu_vs_cpu -- [SIZE] [REPEATS] [SCENES]
//! ```
//!
//! `SCENES`: comma-separated standard scenes with flat GPU data (default
//! `blobs,blobs-sum`; `molecule` and the `aggregate-*` blobtrees too, the
//! latter by sphere tracing alone).
//!
//! Prints, per scene × method, the best of `REPEATS` (default 3) wall-clock
//! times of a `SIZE × SIZE` (default 128) frame: the single-threaded CPU
//! renderer (`render_serial`, f32) and the GPU (upload, dispatch, read-back
//! and frame assembly included; each method's pipeline is built once
//! before, by an 8 × 8 frame whose time is printed), and
//! their ratio. Also compares the frames (hit/miss and step counts per
//! pixel) and prints the dispatches the GPU frame took (the methods of
//! the default modules run in legs: more than one where a driver's loop
//! limit cut rays short).

use boundtrace_gpu::{GpuError, GpuScene, GpuTracer};
use boundtrace_tracer::camera::Camera;
use boundtrace_tracer::render::{RenderSettings, render_serial};
use boundtrace_tracer::scenes::{DEFAULT_SEED, Scene};
use std::time::Instant;

#[path = "common/args.rs"]
mod args;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (size, repeats, scenes) = args::size_repeats_scenes(128, "blobs,blobs-sum")?;
    let t = Instant::now();
    let gpu = GpuTracer::new()?;
    let info = gpu.adapter_info();
    println!(
        "adapter: {} ({:?}, {:?}); pipeline built in {:.2} s; {size}x{size}, best of {repeats}",
        info.name,
        info.device_type,
        info.backend,
        t.elapsed().as_secs_f64()
    );
    println!(
        "| scene | method | CPU 1 thread (ms) | GPU (ms) | CPU / GPU | hit/miss agree | steps agree | GPU dispatches |"
    );
    println!("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |");
    let methods = gpu.methods();
    // Build every pipeline before timing (the first frame of a method and
    // scene kind builds its pipeline); a method without an entry point for
    // the scene's kind (every method but sphere tracing on the blobtrees)
    // is skipped, and said so.
    let mut available = Vec::new();
    for name in &scenes {
        let scene = Scene::<f32>::build(name, DEFAULT_SEED)?;
        let data = GpuScene::from_scene(&scene)?;
        let camera = Camera::framing(scene.bounds(), [0.3, -0.4, -1.0], 40.0, 1.0)?;
        for &method in &methods {
            let t = Instant::now();
            match gpu.render(&data, &camera, &RenderSettings::new(8, 8, method)?) {
                Ok(_) => available.push((name.clone(), method)),
                Err(e @ GpuError::MethodUnavailable { .. }) => {
                    eprintln!("{name} {method}: skipped ({e})");
                    continue;
                }
                Err(e) => return Err(e.into()),
            }
            eprintln!(
                "{name} {method}: pipeline built (and an 8x8 frame) in {:.2} s",
                t.elapsed().as_secs_f64()
            );
        }
    }
    for name in &scenes {
        let scene = Scene::<f32>::build(name, DEFAULT_SEED)?;
        let data = GpuScene::from_scene(&scene)?;
        let camera = Camera::framing(scene.bounds(), [0.3, -0.4, -1.0], 40.0, 1.0)?;
        for &method in &methods {
            if !available.contains(&(name.clone(), method)) {
                continue;
            }
            let settings = RenderSettings::new(size, size, method)?;
            let (mut best_cpu, mut best_gpu) = (f64::INFINITY, f64::INFINITY);
            let (mut cpu_frame, mut gpu_frame) = (None, None);
            let mut dispatches = 0;
            for _ in 0..repeats {
                let t = Instant::now();
                cpu_frame = Some(render_serial(
                    scene.field(),
                    &camera,
                    scene.bounds(),
                    &settings,
                )?);
                best_cpu = best_cpu.min(t.elapsed().as_secs_f64());
                let t = Instant::now();
                let (frame, d) = gpu.render_in_legs(&data, &camera, &settings, 0)?;
                (gpu_frame, dispatches) = (Some(frame), d);
                best_gpu = best_gpu.min(t.elapsed().as_secs_f64());
            }
            let (c, g) = (cpu_frame.unwrap(), gpu_frame.unwrap());
            let (mut agree, mut steps) = (0, 0);
            for y in 0..size {
                for x in 0..size {
                    agree += usize::from(c.hits(x, y).is_empty() == g.hits(x, y).is_empty());
                    let (a, b) = (c.pixel(x, y).unwrap(), g.pixel(x, y).unwrap());
                    steps += usize::from(a.trace.stats.steps == b.trace.stats.steps);
                }
            }
            let pct = |k: usize| 100.0 * k as f64 / (size * size) as f64;
            println!(
                "| {name} | {method} | {:.1} | {:.1} | {:.2} | {:.2} % | {:.2} % | {dispatches} |",
                best_cpu * 1e3,
                best_gpu * 1e3,
                best_cpu / best_gpu,
                pct(agree),
                pct(steps)
            );
        }
    }
    Ok(())
}
