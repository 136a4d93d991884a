//! Tiled blobtree rendering (one program per 8 × 8 tile,
//! `GpuScene::from_tile_programs`) against the whole tree, on the GPU and
//! on one CPU thread, by sphere tracing. Needs a Vulkan adapter and the
//! built modules (`scripts/build-spirv.sh`).
//!
//! ```text
//! cargo run --release -p boundtrace-gpu --example gpu_tiles -- [SIZE] [REPEATS] [SCENES]
//! ```
//!
//! `SCENES`: comma-separated blobtree scenes (default
//! `aggregate-2,aggregate-3`); a name ending in `:tiled` is rendered tiled
//! only (the whole tree of `aggregate-4` takes minutes on the CPU and does
//! not fit lavapipe's loop limit).
//!
//! Prints per scene the programs' size (mean and largest node count against
//! the tree's), the best of `REPEATS` (default 3) wall-clock times of a
//! `SIZE × SIZE` (default 32) opaque frame — the whole tree and the tiles,
//! on the CPU (`render_serial`, `render_tile_programs`) and on the GPU
//! (upload, dispatches, read-back included; pipelines built before) — and
//! how the tiled GPU frame agrees with its CPU twin (hit/miss and step
//! counts per pixel) and with the whole tree's CPU frame (hit/miss).

use boundtrace_gpu::{GpuScene, GpuTracer};
use boundtrace_tracer::Method;
use boundtrace_tracer::camera::Camera;
use boundtrace_tracer::render::{Frame, RenderSettings, render_serial};
use boundtrace_tracer::scenes::{DEFAULT_SEED, Scene, SceneField};
use boundtrace_tracer::tile_programs::{TilePrograms, render_tile_programs};
use std::time::Instant;

#[path = "common/args.rs"]
mod args;

/// The best of `n` wall-clock times of `f`, and its last result.
fn best<R>(n: u32, mut f: impl FnMut() -> R) -> (f64, R) {
    let mut t_best = f64::INFINITY;
    let mut out = None;
    for _ in 0..n {
        let t = Instant::now();
        out = Some(f());
        t_best = t_best.min(t.elapsed().as_secs_f64());
    }
    (t_best, out.expect("n ≥ 1"))
}

/// Percent of pixels where `same(x, y)` holds.
fn pct(size: u32, same: impl Fn(u32, u32) -> bool) -> f64 {
    let n = (0..size * size)
        .filter(|i| same(i % size, i / size))
        .count();
    100.0 * n as f64 / (size * size) as f64
}

fn hit(f: &Frame<f32>, x: u32, y: u32) -> bool {
    !f.hits(x, y).is_empty()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (size, repeats, scenes) = args::size_repeats_scenes(32, "aggregate-2,aggregate-3")?;
    let gpu = GpuTracer::new()?;
    println!(
        "adapter: {}; {size}x{size}, opaque, sphere, best of {repeats}",
        gpu.adapter_info().name
    );
    println!(
        "| scene | tree nodes | tile nodes mean / max | CPU whole (ms) | CPU tiles (ms) | GPU whole (ms) | GPU tiles (ms) | GPU whole / tiles | tiles GPU vs twin: hit/miss, steps | tiles vs whole: hit/miss | GPU dispatches (tiles) |"
    );
    println!("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    for spec in &scenes {
        let (name, tiled_only) = match spec.strip_suffix(":tiled") {
            Some(n) => (n, true),
            None => (spec.as_str(), false),
        };
        let scene = Scene::<f32>::build(name, DEFAULT_SEED)?;
        let SceneField::Blobtree(tree) = scene.field() else {
            return Err(format!("{name} is not a blobtree").into());
        };
        let camera = Camera::framing(scene.bounds(), [0.3, -0.4, -1.0], 40.0, 1.0)?;
        let settings = RenderSettings::new(size, size, Method::Sphere)?;
        let programs = TilePrograms::build(tree, &camera, scene.bounds(), size, size)?;
        let tiled = GpuScene::from_tile_programs(&scene, &programs)?;
        // Pipelines first (one 8 × 8 frame; the programs of that size).
        let small = RenderSettings::new(8, 8, Method::Sphere)?;
        let p8 = TilePrograms::build(tree, &camera, scene.bounds(), 8, 8)?;
        gpu.render(&GpuScene::from_tile_programs(&scene, &p8)?, &camera, &small)?;
        let (cpu_tiles, twin) = best(repeats, || {
            render_tile_programs(&programs, tree.as_ref(), &camera, scene.bounds(), &settings)
        });
        let twin = twin?;
        let (gpu_tiles, g) = best(repeats, || {
            gpu.render_in_legs(&tiled, &camera, &settings, 0)
        });
        let (g, dispatches) = g?;
        let agree = pct(size, |x, y| hit(&twin, x, y) == hit(&g, x, y));
        let steps = pct(size, |x, y| {
            twin.pixel(x, y).map(|p| p.trace.stats.steps)
                == g.pixel(x, y).map(|p| p.trace.stats.steps)
        });
        let (cpu_whole, gpu_whole, whole_agree) = if tiled_only {
            ("—".to_owned(), "—".to_owned(), "—".to_owned())
        } else {
            let data = GpuScene::from_scene(&scene)?;
            let (c, full) = best(repeats, || {
                render_serial(scene.field(), &camera, scene.bounds(), &settings)
            });
            let full = full?;
            let (gw, _) = best(repeats, || gpu.render(&data, &camera, &settings));
            let a = pct(size, |x, y| hit(&full, x, y) == hit(&twin, x, y));
            (
                format!("{:.1}", c * 1e3),
                format!("{:.1}", gw * 1e3),
                format!("{a:.2} %"),
            )
        };
        let ratio = gpu_whole
            .parse::<f64>()
            .map(|w| format!("{:.2}", w / (gpu_tiles * 1e3)))
            .unwrap_or_else(|_| "—".into());
        println!(
            "| {name} | {} | {:.1} / {} | {cpu_whole} | {:.1} | {gpu_whole} | {:.1} | {ratio} | {agree:.2} %, {steps:.2} % | {whole_agree} | {dispatches} |",
            tree.len(),
            programs.mean_nodes(),
            programs.max_nodes(),
            cpu_tiles * 1e3,
            gpu_tiles * 1e3,
        );
    }
    Ok(())
}
