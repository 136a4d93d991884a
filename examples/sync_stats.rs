//! Synchronized tracing (synchronized-tracing paper §6, Alg. 3) against
//! full-tree evaluation with the same method, on the blobtree scenes.
//!
//! ```text
//! cargo run --release --example sync_stats -- [--scenes a,b] [--method M]
//!     [--size N] [--full-size N] [--tile T] [--m-overlap M] [--max-fetch F]
//!     [--seed S]
//! ```
//! (add `--features parallel` to render on every core). Defaults: the
//! scenes `aggregate-1,aggregate-2,aggregate-3,aggregate-4`, method
//! `sphere`, `--size 64` for both renders (`--full-size` renders the
//! full-tree image at another size, `0` skips it), 8×8 tiles,
//! `M_overlap = 128`, 8 optional fetches.
//!
//! Per scene it prints one Markdown row: primitives, full-tree render time,
//! synchronized time split into ABVs, A-buffer and ray processing (paper
//! Fig. 20), the speed-up (full / synchronized total, same method, same
//! image, one run), node evaluations per box ray both ways, the
//! A-buffer's fragments, pruned views built and overflows, and how many
//! pixels disagree on hit/miss (must be 0). Bad arguments print a message
//! and exit with status 2.

use boundtrace::tracer::Method;
use boundtrace::tracer::camera::Camera;
use boundtrace::tracer::render::{Frame, RenderSettings, render};
use boundtrace::tracer::scenes::{DEFAULT_SEED, Scene, SceneField};
use boundtrace::tracer::sync::SyncConfig;
use boundtrace::tracer::sync_render::{SyncSettings, render_sync};
use std::process::ExitCode;
use std::time::Instant;

const USAGE: &str = "usage: sync_stats [--scenes a,b] [--method M] [--size N] [--full-size N] \
[--tile T] [--m-overlap M] [--max-fetch F] [--seed S]";

struct Options {
    scenes: Vec<String>,
    method: Method,
    size: u32,
    full_size: Option<u32>,
    sync: SyncSettings,
    seed: u64,
}

fn parse(args: &[String]) -> Result<Options, String> {
    let mut o = Options {
        scenes: ["aggregate-1", "aggregate-2", "aggregate-3", "aggregate-4"]
            .map(String::from)
            .to_vec(),
        method: Method::Sphere,
        size: 64,
        full_size: None,
        sync: SyncSettings::default(),
        seed: DEFAULT_SEED,
    };
    let mut it = args.iter();
    while let Some(flag) = it.next() {
        let value = it
            .next()
            .ok_or_else(|| format!("{flag} needs a value\n{USAGE}"))?;
        let num = |v: &str| -> Result<u64, String> {
            v.parse::<u64>()
                .map_err(|_| format!("{flag}: not a number: {v}\n{USAGE}"))
        };
        match flag.as_str() {
            "--scenes" => o.scenes = value.split(',').map(String::from).collect(),
            "--method" => {
                o.method = value
                    .parse()
                    .map_err(|e| format!("--method: {e}\n{USAGE}"))?
            }
            "--size" => o.size = num(value)? as u32,
            "--full-size" => o.full_size = Some(num(value)? as u32),
            "--tile" => o.sync.tile_size = num(value)? as u32,
            "--m-overlap" => {
                o.sync.config = SyncConfig {
                    m_overlap: num(value)? as u32,
                    ..o.sync.config
                }
            }
            "--max-fetch" => o.sync.config.max_fetch = num(value)? as u32,
            "--seed" => o.seed = num(value)?,
            _ => return Err(format!("unknown option {flag}\n{USAGE}")),
        }
    }
    Ok(o)
}

/// Node evaluations per box ray of a full-tree frame.
fn full_node_evals(frame: &Frame<f64>, nodes: usize) -> f64 {
    let t = frame.totals();
    let evals = t.field_evals + t.bound_evals;
    if t.box_rays == 0 {
        0.0
    } else {
        (evals as f64 * nodes as f64) / t.box_rays as f64
    }
}

fn run(o: &Options) -> Result<(), String> {
    println!(
        "method `{}`, {}x{} px (full tree: {}), {}x{} tiles, M_overlap {}, max fetch {}, parallel: {}",
        o.method,
        o.size,
        o.size,
        match o.full_size {
            Some(0) => "skipped".to_string(),
            Some(n) => format!("{n}x{n} px"),
            None => "same size".to_string(),
        },
        o.sync.tile_size,
        o.sync.tile_size,
        o.sync.config.m_overlap,
        o.sync.config.max_fetch,
        cfg!(feature = "parallel")
    );
    println!();
    println!(
        "| scene | primitives | full [ms] | sync total [ms] | ABVs [ms] | A-buffer [ms] | rays [ms] | speed-up | node evals / box ray full | sync | fragments | max / tile | views | overflows | hit/miss differ |"
    );
    println!(
        "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
    );
    for name in &o.scenes {
        let scene: Scene<f64> = Scene::build(name, o.seed).map_err(|e| e.to_string())?;
        let SceneField::Blobtree(tree) = scene.field() else {
            return Err(format!("{name} is not a blobtree scene"));
        };
        let bounds = scene.bounds();
        let camera =
            Camera::framing(bounds, [-0.3, -0.4, -1.0], 40.0, 1.0).map_err(|e| e.to_string())?;
        let settings = RenderSettings::new(o.size, o.size, o.method).map_err(|e| e.to_string())?;
        let t = Instant::now();
        let (sync, report) =
            render_sync(tree, &camera, bounds, &settings, &o.sync).map_err(|e| e.to_string())?;
        let sync_ms = t.elapsed().as_secs_f64() * 1e3;
        let ms = |d: std::time::Duration| d.as_secs_f64() * 1e3;
        let st = sync.totals();
        let sync_evals = if st.box_rays == 0 {
            0.0
        } else {
            report.counters.node_evals as f64 / st.box_rays as f64
        };
        let full_size = o.full_size.unwrap_or(o.size);
        let (full_ms, full_evals, differ, speedup) = if full_size == 0 {
            (
                "-".to_string(),
                "-".to_string(),
                "-".to_string(),
                "-".to_string(),
            )
        } else {
            let fs =
                RenderSettings::new(full_size, full_size, o.method).map_err(|e| e.to_string())?;
            let t = Instant::now();
            let full = render(&tree.as_ref(), &camera, bounds, &fs).map_err(|e| e.to_string())?;
            let full_ms = t.elapsed().as_secs_f64() * 1e3;
            let (differ, speedup) = if full_size == o.size {
                let mut d = 0;
                for y in 0..o.size {
                    for x in 0..o.size {
                        d += usize::from(sync.depth(x, y).is_some() != full.depth(x, y).is_some());
                    }
                }
                (d.to_string(), format!("{:.1}x", full_ms / sync_ms))
            } else {
                // Per pixel, the full image at another size.
                let per = |ms: f64, n: u32| ms / f64::from(n * n);
                (
                    "-".to_string(),
                    format!(
                        "{:.1}x (per pixel)",
                        per(full_ms, full_size) / per(sync_ms, o.size)
                    ),
                )
            };
            (
                format!("{full_ms:.1}"),
                format!("{:.0}", full_node_evals(&full, tree.len())),
                differ,
                speedup,
            )
        };
        println!(
            "| {name} | {} | {full_ms} | {sync_ms:.1} | {:.1} | {:.1} | {:.1} | {speedup} | {full_evals} | {sync_evals:.0} | {} | {} | {} | {} | {differ} |",
            scene.primitive_count(),
            ms(report.abvs_time),
            ms(report.abuffer_time),
            ms(report.trace_time),
            report.entries,
            report.max_tile_entries,
            report.counters.views,
            report.counters.overflow_ranges + report.counters.view_failures,
        );
    }
    Ok(())
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match parse(&args).and_then(|o| run(&o)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("{e}");
            ExitCode::from(2)
        }
    }
}
