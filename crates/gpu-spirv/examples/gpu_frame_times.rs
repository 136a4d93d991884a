//! GPU frame times at full resolution (the forward-inclusion paper's
//! Table 1 / Table 2 style), with the CPU renderer on every core beside
//! them and a pixel-by-pixel comparison of the two frames. Needs a Vulkan
//! adapter and the modules of `scripts/build-spirv.sh`.
//!
//! ```text
//! scripts/build-spirv.sh
//! cargo run --release -p boundtrace-gpu --example gpu_frame_times -- [SIZE] [REPEATS] [cpu] [compile-only] [methods=M,M…] [scenes=S,S…]
//! ```
//!
//! For each blob scene × mode (opaque; transparent, all roots up to
//! [`MAX_GPU_ROOTS`]) × method the module set holds (or those named by
//! `methods=`: a method the modules lack prints its error), builds the
//! method's pipeline ([`GpuTracer::prepare`]; its time is printed; with
//! `compile-only`, nothing more), renders one frame, then `REPEATS`
//! (default 5) `SIZE × SIZE` (default 1,024) frames, and prints the median
//! of [`RenderProfile::dispatch`] (the tracing: first submission to the end
//! of the last dispatch) and of [`RenderProfile::total`] (the whole call:
//! buffer set-up, upload, read-back and the frame's assembly included).
//! With `cpu`, also renders the frame once with the CPU renderer
//! (`render`, rayon over every core, f32), and compares the frames: pixels
//! whose hit/miss, step count or first depth (relative 10⁻³) differ.

use boundtrace_gpu::{GpuScene, GpuTracer, MAX_GPU_ROOTS, RenderProfile};
use boundtrace_tracer::camera::Camera;
use boundtrace_tracer::render::{Frame, RenderSettings, render};
use boundtrace_tracer::scenes::{DEFAULT_SEED, Scene};
use boundtrace_tracer::{Method, Mode};
use std::time::{Duration, Instant};

/// Pixels of `a` and `b` (same size) whose hit/miss differs, whose step
/// count differs, and whose first depth differs by more than 10⁻³ relative
/// where both hit.
fn differences(a: &Frame<f32>, b: &Frame<f32>, size: u32) -> [usize; 3] {
    let mut d = [0; 3];
    for y in 0..size {
        for x in 0..size {
            let (ha, hb) = (a.hits(x, y), b.hits(x, y));
            d[0] += usize::from(ha.is_empty() != hb.is_empty());
            let (pa, pb) = (a.pixel(x, y), b.pixel(x, y));
            let steps =
                |p: Option<&boundtrace_tracer::render::Pixel<f32>>| p.map(|p| p.trace.stats.steps);
            d[1] += usize::from(steps(pa) != steps(pb));
            if let (Some(u), Some(v)) = (ha.first(), hb.first()) {
                d[2] += usize::from((u.t - v.t).abs() > 1e-3 * u.t.abs().max(v.t.abs()));
            }
        }
    }
    d
}

fn median(mut v: Vec<Duration>) -> f64 {
    v.sort();
    v[v.len() / 2].as_secs_f64() * 1e3
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let size: u32 = args.first().map(|s| s.parse()).transpose()?.unwrap_or(1024);
    let repeats: usize = args
        .get(1)
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(5)
        .max(1);
    let cpu = args.iter().any(|a| a == "cpu");
    let compile_only = args.iter().any(|a| a == "compile-only");
    let list = |key: &str| {
        args.iter()
            .find_map(|a| a.strip_prefix(key))
            .map(|v| v.split(',').map(str::to_owned).collect::<Vec<_>>())
    };
    let scenes = list("scenes=").unwrap_or_else(|| vec!["blobs".into(), "blobs-sum".into()]);
    let gpu = GpuTracer::new()?;
    let info = gpu.adapter_info();
    println!(
        "adapter: {} ({:?}, {:?}, driver {} {}); {size}x{size}, median of {repeats}; CPU: {} threads",
        info.name,
        info.device_type,
        info.backend,
        info.driver,
        info.driver_info,
        std::thread::available_parallelism().map_or(1, |n| n.get())
    );
    println!(
        "| scene | mode | method | GPU dispatch (ms) | GPU frame (ms) | dispatches | mean steps | CPU (ms) | CPU / GPU frame | hit/miss differ | steps differ | depth differ |"
    );
    println!("| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    let mut methods = gpu.methods();
    if let Some(named) = list("methods=") {
        methods = named
            .iter()
            .map(|m| m.parse::<Method>())
            .collect::<Result<_, _>>()?;
    }
    for name in &scenes {
        let scene = Scene::<f32>::build(name, DEFAULT_SEED)?;
        let data = GpuScene::from_scene(&scene)?;
        let camera = Camera::framing(scene.bounds(), [0.3, -0.4, -1.0], 40.0, 1.0)?;
        for mode in [Mode::Opaque, Mode::Transparent] {
            for &method in &methods {
                let settings = RenderSettings::new(size, size, method)?
                    .with_mode(mode)
                    .with_max_roots(MAX_GPU_ROOTS)?;
                let t = Instant::now();
                if let Err(e) = gpu.prepare(method, data.kind()) {
                    println!("| {name} | {mode:?} | {method} | error: {e} |");
                    continue;
                }
                eprintln!(
                    "{name} {mode:?} {method}: pipeline ready in {:.2} s",
                    t.elapsed().as_secs_f64()
                );
                if compile_only {
                    continue;
                }
                let t = Instant::now();
                let first = gpu.render_profiled(&data, &camera, &settings, 0);
                let (frame, _) = match first {
                    Ok(f) => f,
                    Err(e) => {
                        println!("| {name} | {mode:?} | {method} | error: {e} |");
                        continue;
                    }
                };
                eprintln!(
                    "{name} {mode:?} {method}: first frame {:.2} s",
                    t.elapsed().as_secs_f64()
                );
                let mut profiles: Vec<RenderProfile> = Vec::new();
                for _ in 0..repeats {
                    profiles.push(gpu.render_profiled(&data, &camera, &settings, 0)?.1);
                }
                let dispatch = median(profiles.iter().map(|p| p.dispatch).collect());
                let total = median(profiles.iter().map(|p| p.total).collect());
                let dispatches = profiles.iter().map(|p| p.dispatches).max().unwrap_or(0);
                let steps = frame.totals().steps as f64 / f64::from(size * size);
                let cpu_cols = if cpu {
                    let t = Instant::now();
                    let c = render(scene.field(), &camera, scene.bounds(), &settings)?;
                    let ms = t.elapsed().as_secs_f64() * 1e3;
                    let [hit, step, depth] = differences(&c, &frame, size);
                    format!("{ms:.1} | {:.2} | {hit} | {step} | {depth}", ms / total)
                } else {
                    "– | – | – | – | –".to_owned()
                };
                println!(
                    "| {name} | {mode:?} | {method} | {dispatch:.2} | {total:.2} | {dispatches} | {steps:.2} | {cpu_cols} |"
                );
            }
        }
    }
    Ok(())
}
