//! Per-ray statistics of every method on every standard scene (thesis
//! Part III §1.8 methodology; forward-inclusion paper §7), checked against
//! the dense reference.
//!
//! ```text
//! cargo run --release --example stats -- [--scenes a,b|all] [--methods m,n|all]
//!     [--mode opaque|transparent|both] [--rays N] [--rays-for name=N,…]
//!     [--seed S] [--scene-seed S] [--eps E] [--max-steps N] [--baseline METHOD|none]
//!     [--sphere-lipschitz window|ray]
//! ```
//! (add `--features parallel` to trace the rays on every core; the counts
//! are the same). `--rays-for` gives some scenes their own ray count (the
//! large aggregates, whose full-tree methods cost seconds per ray). For each scene × mode it prints a Markdown table: rays are
//! launched from the faces of the scene's bounding box (enlarged by 0.1% of
//! its diagonal) in the 6 axis directions, origins uniform on the faces
//! ([`RaySet`]); per method the average/median/maximal steps, average field
//! and bound evaluations, average time per ray, the steps and time ratios
//! against the baseline, and the agreement with the dense reference
//! (`boundtrace::tracer::stats::classify`), followed by the first
//! disagreeing rays. On SCALIS scenes `sphere` has a Lipschitz constant per
//! window of the ray (default) or, with `--sphere-lipschitz ray`, one per
//! ray (thesis Part III §1.7; `boundtrace::tracer::scalis::SphereLipschitz`).
//! Bad arguments print a message and exit with status 2.

use boundtrace::tracer::scalis::SphereLipschitz;
use boundtrace::tracer::scenes::{self, Scene};
use boundtrace::tracer::stats::{
    MethodStats, RaySet, ReferenceParams, enlarged, markdown_table, run_scene_method,
    run_scene_sphere, scene_reference,
};
use boundtrace::tracer::{Method, Mode, Params};
use std::process::ExitCode;
use std::time::Instant;

const USAGE: &str = "usage: stats [--scenes a,b|all] [--methods m,n|all] \
[--mode opaque|transparent|both] [--rays N] [--rays-for name=N,...] [--seed S] [--scene-seed S] [--eps E] \
[--max-steps N] [--baseline METHOD|none] [--sphere-lipschitz window|ray]";

/// Failing rays printed per method.
const SHOWN_FAILURES: usize = 3;

struct Options {
    scenes: Vec<String>,
    methods: Vec<Method>,
    modes: Vec<Mode>,
    rays: usize,
    /// Per-scene ray counts overriding `rays` (`--rays-for name=N,…`).
    rays_for: Vec<(String, usize)>,
    seed: u64,
    scene_seed: u64,
    params: Params<f64>,
    baseline: Option<Method>,
    /// The Lipschitz constant of `sphere` on SCALIS scenes.
    sphere_lipschitz: SphereLipschitz,
}

fn parse_list<'a>(value: &'a str, all: &[&'a str]) -> Vec<&'a str> {
    if value == "all" {
        all.to_vec()
    } else {
        value
            .split(',')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .collect()
    }
}

fn parse(args: &[String]) -> Result<Options, String> {
    let mut o = Options {
        scenes: scenes::NAMES.iter().map(|s| s.to_string()).collect(),
        methods: Method::ALL.to_vec(),
        modes: vec![Mode::Opaque, Mode::Transparent],
        rays: 20_000,
        rays_for: Vec::new(),
        seed: 1,
        scene_seed: scenes::DEFAULT_SEED,
        params: Params::new(),
        baseline: Some(Method::Segment),
        sphere_lipschitz: SphereLipschitz::PerWindow,
    };
    let mut it = args.iter();
    while let Some(flag) = it.next() {
        let value = it
            .next()
            .ok_or_else(|| format!("{flag} needs a value"))?
            .as_str();
        let number = |what: &str| format!("{flag}: `{value}` is not {what}");
        match flag.as_str() {
            "--scenes" => {
                o.scenes = Vec::new();
                for name in parse_list(value, scenes::NAMES) {
                    if !scenes::NAMES.contains(&name) {
                        return Err(format!(
                            "unknown scene `{name}`; expected one of: {}",
                            scenes::NAMES.join(", ")
                        ));
                    }
                    o.scenes.push(name.to_string());
                }
            }
            "--methods" => {
                let names: Vec<&str> = Method::ALL.iter().map(|m| m.name()).collect();
                o.methods = Vec::new();
                for name in parse_list(value, &names) {
                    let m = name
                        .parse::<Method>()
                        .map_err(|e| format!("`{name}`: {e}"))?;
                    o.methods.push(m);
                }
            }
            "--mode" => {
                o.modes = match value {
                    "opaque" => vec![Mode::Opaque],
                    "transparent" => vec![Mode::Transparent],
                    "both" => vec![Mode::Opaque, Mode::Transparent],
                    _ => return Err(number("opaque, transparent or both")),
                }
            }
            "--rays" => {
                o.rays = value
                    .parse()
                    .ok()
                    .filter(|&n: &usize| n > 0)
                    .ok_or_else(|| number("a positive integer"))?
            }
            "--rays-for" => {
                for item in value.split(',').map(str::trim).filter(|s| !s.is_empty()) {
                    let (name, n) = item
                        .split_once('=')
                        .ok_or_else(|| format!("--rays-for: `{item}` is not name=N"))?;
                    if !scenes::NAMES.contains(&name) {
                        return Err(format!(
                            "--rays-for: unknown scene `{name}`; expected one of: {}",
                            scenes::NAMES.join(", ")
                        ));
                    }
                    let n =
                        n.parse().ok().filter(|&n: &usize| n > 0).ok_or_else(|| {
                            format!("--rays-for: `{n}` is not a positive integer")
                        })?;
                    o.rays_for.push((name.to_string(), n));
                }
            }
            "--seed" => o.seed = value.parse().map_err(|_| number("an integer"))?,
            "--scene-seed" => o.scene_seed = value.parse().map_err(|_| number("an integer"))?,
            "--eps" => {
                let eps: f64 = value.parse().map_err(|_| number("a number"))?;
                o.params = o.params.with_eps(eps).map_err(|e| e.to_string())?;
            }
            "--max-steps" => {
                let n: u32 = value.parse().map_err(|_| number("an integer"))?;
                o.params = o.params.with_max_steps(n).map_err(|e| e.to_string())?;
            }
            "--baseline" => {
                o.baseline = match value {
                    "none" => None,
                    _ => Some(value.parse().map_err(|e| format!("`{value}`: {e}"))?),
                }
            }
            "--sphere-lipschitz" => {
                o.sphere_lipschitz = match value {
                    "window" => SphereLipschitz::PerWindow,
                    "ray" => SphereLipschitz::PerRay,
                    _ => return Err(format!("{flag}: `{value}` is not window or ray")),
                }
            }
            _ => return Err(format!("unknown option `{flag}`")),
        }
    }
    if o.scenes.is_empty() || o.methods.is_empty() {
        return Err("no scene or no method selected".into());
    }
    Ok(o)
}

/// The tables of one scene.
fn scene_tables(scene: &Scene<f64>, o: &Options) -> Result<(), String> {
    let (name, primitives) = (scene.name(), scene.primitive_count());
    let count = o
        .rays_for
        .iter()
        .rev()
        .find(|(n, _)| n == name)
        .map_or(o.rays, |&(_, n)| n);
    let rays =
        RaySet::new(enlarged(scene.bounds(), 1e-3), count, o.seed).map_err(|e| e.to_string())?;
    let clock = Instant::now();
    let rp = ReferenceParams::new(o.params.eps).map_err(|e| e.to_string())?;
    let reference = scene_reference(scene, &rays, &rp).map_err(|e| e.to_string())?;
    let ref_s = clock.elapsed().as_secs_f64();
    for &mode in &o.modes {
        let mut rows: Vec<MethodStats> = Vec::new();
        for &m in &o.methods {
            let row = if m == Method::Sphere {
                run_scene_sphere(
                    scene,
                    &rays,
                    &reference,
                    o.sphere_lipschitz,
                    mode,
                    &o.params,
                )
            } else {
                run_scene_method(scene, &rays, &reference, m, mode, &o.params)
            };
            rows.push(row.map_err(|e| e.to_string())?);
        }
        println!(
            "## {name} ({primitives} primitives), {mode:?}\n\n{} rays (seed {}), {} hit the \
             surface (reference: {ref_s:.1} s); eps {:e}, max_steps {}{}\n",
            rays.len(),
            o.seed,
            reference.hits(),
            o.params.eps,
            o.params.max_steps,
            if scene.name().starts_with("scalis") && o.methods.contains(&Method::Sphere) {
                match o.sphere_lipschitz {
                    SphereLipschitz::PerWindow => "; sphere: Lipschitz constant per window",
                    SphereLipschitz::PerRay => "; sphere: one Lipschitz constant per ray (§1.7)",
                }
            } else {
                ""
            },
        );
        println!("{}", markdown_table(&rows, o.baseline));
        for r in rows.iter().filter(|r| !r.failures.is_empty()) {
            for f in r.failures.iter().take(SHOWN_FAILURES) {
                println!("- {} {mode:?}: {f}", r.method);
            }
        }
        println!();
    }
    Ok(())
}

fn run(o: &Options) -> Result<(), String> {
    for name in &o.scenes {
        let scene = Scene::<f64>::build(name, o.scene_seed).map_err(|e| format!("{name}: {e}"))?;
        scene_tables(&scene, o)?;
    }
    Ok(())
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.iter().any(|a| a == "--help" || a == "-h") {
        println!("{USAGE}");
        return ExitCode::SUCCESS;
    }
    let o = match parse(&args) {
        Ok(o) => o,
        Err(e) => {
            eprintln!("error: {e}\n{USAGE}");
            return ExitCode::from(2);
        }
    };
    let clock = Instant::now();
    let result = run(&o);
    println!("total wall time: {:.1} s", clock.elapsed().as_secs_f64());
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
