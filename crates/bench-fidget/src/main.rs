//! boundtrace against fidget, side by side (issue 12). Bench-only: this
//! crate is outside the main workspace, so neither CI nor library users
//! ever compile fidget.
//!
//! ```text
//! cargo run --release --manifest-path crates/bench-fidget/Cargo.toml -- heightmap \
//!     [--scenes aggregate-1,aggregate-2,examples/scenes/primitives.json] [--size N] \
//!     [--threads 1,2] [--reps R] [--renderers fidget-jit,full:sphere,sync:sphere] \
//!     [--full-max-primitives P] [--eps E|voxel]
//! cargo run --release --manifest-path crates/bench-fidget/Cargo.toml -- intervals \
//!     [--samples N] [--seed S]
//! ```
//!
//! `heightmap` prints two Markdown tables: the agreement of every renderer's
//! hit mask and voxel depth with fidget's JIT heightmap (checked first), then
//! the wall times (min / median / max over `R` runs after one warm-up) and
//! the per-run ratio to fidget's JIT. `intervals` prints the interval
//! containment counts of both libraries. Bad arguments print a message and
//! exit with status 2.

mod heightmap;
mod intervals;
mod translate;

use boundtrace_cli::scene_format::SceneFile;
use boundtrace_tracer::Method;
use boundtrace_tracer::scenes::{DEFAULT_SEED, Scene, SceneField};
use fidget::render::ThreadPool;
use heightmap::{
    Agreement, Renderer, View, confirm_only_ours, min_med_max, prepare, render_once, shapes,
};
use std::process::ExitCode;

const USAGE: &str = "usage: boundtrace-bench-fidget heightmap [--scenes a,b,file.json] [--size N] \
[--threads 1,2] [--reps R] [--renderers fidget-jit,fidget-vm,full:METHOD,sync:METHOD] \
[--full-max-primitives P] [--eps E|voxel]\n       boundtrace-bench-fidget intervals [--samples N] [--seed S]";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.iter().any(|a| a == "--help" || a == "-h") {
        println!("{USAGE}");
        return ExitCode::SUCCESS;
    }
    let result = match args.first().map(String::as_str) {
        Some("heightmap") => heightmap_cmd(&args[1..]),
        Some("intervals") => intervals_cmd(&args[1..]),
        _ => Err(USAGE.to_string()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

/// `--flag value` pairs.
fn pairs(args: &[String]) -> Result<Vec<(&str, &str)>, String> {
    let mut out = Vec::new();
    let mut it = args.iter();
    while let Some(flag) = it.next() {
        let v = it
            .next()
            .ok_or_else(|| format!("{flag} needs a value\n{USAGE}"))?;
        out.push((flag.as_str(), v.as_str()));
    }
    Ok(out)
}

fn number<T: std::str::FromStr>(flag: &str, v: &str) -> Result<T, String> {
    v.parse()
        .map_err(|_| format!("{flag}: `{v}` is not a valid number"))
}

fn intervals_cmd(args: &[String]) -> Result<(), String> {
    let (mut samples, mut seed) = (200_000u64, 1u64);
    for (flag, v) in pairs(args)? {
        match flag {
            "--samples" => samples = number(flag, v)?,
            "--seed" => seed = number(flag, v)?,
            _ => return Err(format!("unknown option {flag}\n{USAGE}")),
        }
    }
    if samples == 0 {
        return Err("--samples must be >= 1".into());
    }
    println!(
        "| op | input intervals | reference values | ours: intervals missing a value | fidget: intervals missing a value | fidget: NaN (no bound) | first fidget miss |"
    );
    println!("| --- | ---: | ---: | ---: | ---: | ---: | --- |");
    let mut total_ours = 0;
    for op in intervals::OPS {
        let c = intervals::run_op(op, samples, seed)?;
        total_ours += c.ours_failures;
        if let Some(e) = &c.ours_example {
            eprintln!("SOUNDNESS BUG (ours): {e}");
        }
        let example = c.fidget_example.clone().unwrap_or_default();
        println!(
            "| {op} | {} | {} | **{}** | {} | {} | {example} |",
            c.samples, c.checks, c.ours_failures, c.fidget_failures, c.fidget_nan
        );
    }
    if total_ours > 0 {
        return Err(format!(
            "SOUNDNESS BUG: our Interval<f32> missed a reference value {total_ours} times"
        ));
    }
    Ok(())
}

struct HeightmapOptions {
    scenes: Vec<String>,
    size: u32,
    threads: Vec<usize>,
    reps: usize,
    renderers: Vec<Renderer>,
    full_max: usize,
    /// `None`: half the voxel pitch of each view.
    eps: Option<f32>,
}

fn heightmap_options(args: &[String]) -> Result<HeightmapOptions, String> {
    let mut o = HeightmapOptions {
        scenes: ["aggregate-1", "aggregate-2", "aggregate-3", "aggregate-4"]
            .map(String::from)
            .to_vec(),
        size: 256,
        threads: vec![1, 2],
        reps: 5,
        renderers: vec![
            Renderer::FidgetJit,
            Renderer::Full(Method::Sphere),
            Renderer::Sync(Method::Sphere),
        ],
        full_max: 200,
        eps: Some(1e-4),
    };
    for (flag, v) in pairs(args)? {
        match flag {
            "--scenes" => o.scenes = v.split(',').map(String::from).collect(),
            "--size" => o.size = number(flag, v)?,
            "--threads" => {
                o.threads = v
                    .split(',')
                    .map(|t| number(flag, t))
                    .collect::<Result<_, _>>()?
            }
            "--reps" => o.reps = number(flag, v)?,
            "--renderers" => {
                o.renderers = v
                    .split(',')
                    .map(Renderer::parse)
                    .collect::<Result<_, _>>()?
            }
            "--full-max-primitives" => o.full_max = number(flag, v)?,
            "--eps" if v == "voxel" => o.eps = None,
            "--eps" => o.eps = Some(number(flag, v)?),
            _ => return Err(format!("unknown option {flag}\n{USAGE}")),
        }
    }
    if !(8..=4096).contains(&o.size) {
        return Err("--size must be in 8..=4096".into());
    }
    if o.reps == 0 || o.threads.is_empty() || o.threads.contains(&0) {
        return Err("--reps and every --threads value must be >= 1".into());
    }
    if o.eps.is_some_and(|e| !(e > 0.0 && e.is_finite())) {
        return Err("--eps must be finite and > 0, or `voxel`".into());
    }
    if !o.renderers.contains(&Renderer::FidgetJit) {
        o.renderers.insert(0, Renderer::FidgetJit);
    }
    Ok(o)
}

/// Our tree, bounds and primitive count of a standard scene or a scene file.
fn load(
    name: &str,
) -> Result<
    (
        boundtrace_fields::blobtree::FlatBlobtree,
        [[f32; 3]; 2],
        usize,
    ),
    String,
> {
    let scene: Scene<f32> = if name.ends_with(".json") {
        let text =
            std::fs::read_to_string(name).map_err(|e| format!("cannot read `{name}`: {e}"))?;
        SceneFile::parse(&text)
            .and_then(|f| f.build::<f32>())
            .map_err(|e| format!("`{name}`: {e}"))?
    } else {
        Scene::build(name, DEFAULT_SEED).map_err(|e| e.to_string())?
    };
    match scene.field() {
        SceneField::Blobtree(t) => Ok((t.clone(), scene.bounds(), scene.primitive_count())),
        _ => Err(format!(
            "`{name}` is not a blobtree scene (only blobtrees translate to fidget)"
        )),
    }
}

fn heightmap_cmd(args: &[String]) -> Result<(), String> {
    let o = heightmap_options(args)?;
    let mut agreement_rows = Vec::new();
    let mut time_rows = Vec::new();
    let mut skipped = Vec::new();
    for name in &o.scenes {
        let (tree, bounds, prims) = load(name)?;
        let short = name
            .rsplit('/')
            .next()
            .unwrap_or(name)
            .trim_end_matches(".json");
        let p = match prepare(short, tree, bounds, prims, 300) {
            Ok(p) => p,
            Err(e) => {
                skipped.push(e);
                continue;
            }
        };
        let s = shapes(&p)?;
        let view = View::new(bounds, o.size);
        let eps = o.eps.unwrap_or(0.5 * view.pitch());
        let renderers: Vec<Renderer> = o
            .renderers
            .iter()
            .copied()
            .filter(|r| !matches!(r, Renderer::Full(_)) || prims <= o.full_max)
            .collect();
        for (ti, &threads) in o.threads.iter().enumerate() {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .map_err(|e| format!("thread pool: {e}"))?;
            let fidget_pool = if threads == 1 {
                None
            } else {
                Some(ThreadPool::Custom(
                    rayon::ThreadPoolBuilder::new()
                        .num_threads(threads)
                        .build()
                        .map_err(|e| format!("thread pool: {e}"))?,
                ))
            };
            // warm-up run of each renderer; its image is checked first
            let mut reference = None;
            for &r in &renderers {
                let (img, _) = render_once(&p, &s, &view, r, eps, &pool, fidget_pool.as_ref())?;
                match &reference {
                    None => reference = Some(img),
                    Some(fid) if ti == 0 => {
                        let g = Agreement::of(&img, fid);
                        let (checked, confirmed) = if r.is_fidget() {
                            (0, 0)
                        } else {
                            confirm_only_ours(&p, &view, &img, fid)
                        };
                        agreement_rows.push(format!(
                            "| {} | {} | {} | {:.1e} / {} | {} | {:.3} | {} | {} ({confirmed} of {checked} confirmed) | {} | {:.2} |",
                            p.name,
                            p.primitives,
                            p.fidget_nodes,
                            p.field_error,
                            p.sign_differs,
                            r.name(),
                            g.mask_percent(),
                            g.both,
                            g.only_a,
                            g.only_b,
                            g.depth_percent()
                        ));
                    }
                    Some(_) => {}
                }
            }
            let mut times: Vec<Vec<f64>> = vec![Vec::new(); renderers.len()];
            for _ in 0..o.reps {
                for (i, &r) in renderers.iter().enumerate() {
                    let (_, dt) = render_once(&p, &s, &view, r, eps, &pool, fidget_pool.as_ref())?;
                    times[i].push(dt.as_secs_f64() * 1e3);
                }
            }
            let fid = times[0].clone();
            for (i, &r) in renderers.iter().enumerate() {
                let mut ratios: Vec<f64> = times[i].iter().zip(&fid).map(|(a, b)| a / b).collect();
                let [rmin, rmed, rmax] = min_med_max(&mut ratios);
                let [tmin, tmed, tmax] = min_med_max(&mut times[i]);
                let ratio = if r.is_fidget() && i == 0 {
                    "1".to_string()
                } else {
                    format!("{rmin:.2} / **{rmed:.2}** / {rmax:.2}")
                };
                time_rows.push(format!(
                    "| {} | {} | {} | {} | {tmin:.1} | {tmed:.1} | {tmax:.1} | {ratio} |",
                    p.name,
                    p.primitives,
                    threads,
                    r.name()
                ));
            }
        }
        eprintln!(
            "{}: done (fidget JIT compile {:.1} ms)",
            p.name,
            s.jit_build.as_secs_f64() * 1e3
        );
    }
    println!(
        "Agreement with fidget's JIT heightmap ({n}×{n} pixels, {n} voxels deep; our eps = {eps}). \
         \"field check\": largest relative difference of the two fields on 300 random points of the \
         bounds / points where their signs differ. \"confirmed\": pixels hit only by us where our field \
         is < 0 within one voxel of our hit (64 samples along the ray): the surface passes between \
         fidget's voxel centres.\n",
        n = o.size,
        eps = match o.eps {
            Some(e) => format!("{e:e}"),
            None => "half the voxel pitch".into(),
        }
    );
    println!(
        "| scene | primitives | fidget nodes | field check | ours | hit/miss agree % | both hit | only ours | only fidget | depth within 1 voxel % |"
    );
    println!("| --- | ---: | ---: | --- | --- | ---: | ---: | ---: | ---: | ---: |");
    for r in &agreement_rows {
        println!("{r}");
    }
    println!(
        "\nWall time of one {n}×{n} frame [ms] over {reps} runs (after one warm-up), and the per-run ratio to fidget-jit (min / median / max; < 1: ours faster).\n",
        n = o.size,
        reps = o.reps
    );
    println!(
        "| scene | primitives | threads | renderer | min | median | max | ratio to fidget-jit |"
    );
    println!("| --- | ---: | ---: | --- | ---: | ---: | ---: | --- |");
    for r in &time_rows {
        println!("{r}");
    }
    for s in &skipped {
        println!("\nNot compared: {s}.");
    }
    // a blank line, so that the outputs of several runs concatenate
    println!();
    Ok(())
}
