//! Renders a standard scene ([`boundtrace::tracer::scenes`]) to PNG files: a headlight-shaded image and a
//! steps heatmap (clamped to 75 steps, as the papers' figures), and prints
//! the frame's totals (rays, roots, steps and evaluations per bounding-box
//! ray, status counts).
//!
//! ```text
//! cargo run --release --example render -- [--scene blobs] [--method quadratic-taylor]
//!     [--mode opaque] [--size 512] [--out out/] [--heat-max 75] [--seed 2023]
//! ```
//!
//! Scenes: every name of [`NAMES`] (an unknown name lists them).
//!
//! Rows render in parallel with `--features parallel` (same images). Bad
//! arguments print a message and exit with code 2; rendering or I/O errors
//! exit with code 1.

use boundtrace::tracer::camera::Camera;
use boundtrace::tracer::render::{RenderSettings, render_scene};
use boundtrace::tracer::scenes::{DEFAULT_SEED, NAMES, Scene};
use boundtrace::tracer::{Method, Mode};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

const USAGE: &str = "usage: render [--scene NAME] [--method METHOD] [--mode opaque|transparent] \
[--size PIXELS] [--out DIR] [--heat-max STEPS] [--seed N]";

/// The largest `--size`.
const MAX_SIZE: u32 = 8192;

/// Parsed command line.
struct Args {
    scene: String,
    method: Method,
    mode: Mode,
    size: u32,
    out: PathBuf,
    heat_max: u32,
    seed: u64,
}

/// Parses the arguments after the program name; `Ok(None)` for `--help`.
fn parse(mut it: impl Iterator<Item = String>) -> Result<Option<Args>, String> {
    let mut args = Args {
        scene: "blobs".into(),
        method: Method::QuadraticTaylor,
        mode: Mode::Opaque,
        size: 512,
        out: PathBuf::from("out"),
        heat_max: 75,
        seed: DEFAULT_SEED,
    };
    while let Some(flag) = it.next() {
        if flag == "--help" || flag == "-h" {
            return Ok(None);
        }
        let value = match flag.as_str() {
            "--scene" | "--method" | "--mode" | "--size" | "--out" | "--heat-max" | "--seed" => it
                .next()
                .ok_or_else(|| format!("missing value after {flag}"))?,
            _ => return Err(format!("unknown argument `{flag}`")),
        };
        match flag.as_str() {
            "--scene" => {
                if !NAMES.contains(&value.as_str()) {
                    return Err(format!(
                        "unknown scene `{value}`; expected one of: {}",
                        NAMES.join(" ")
                    ));
                }
                args.scene = value;
            }
            "--method" => args.method = value.parse().map_err(|e| format!("`{value}`: {e}"))?,
            "--mode" => {
                args.mode = match value.as_str() {
                    "opaque" => Mode::Opaque,
                    "transparent" => Mode::Transparent,
                    _ => {
                        return Err(format!(
                            "unknown mode `{value}`; expected opaque or transparent"
                        ));
                    }
                }
            }
            "--size" => {
                args.size = value
                    .parse()
                    .ok()
                    .filter(|s| (1..=MAX_SIZE).contains(s))
                    .ok_or_else(|| {
                        format!("--size must be an integer in 1..={MAX_SIZE}, got `{value}`")
                    })?;
            }
            "--heat-max" => {
                args.heat_max =
                    value.parse().ok().filter(|&s| s >= 1).ok_or_else(|| {
                        format!("--heat-max must be an integer >= 1, got `{value}`")
                    })?;
            }
            "--seed" => {
                args.seed = value
                    .parse()
                    .map_err(|_| format!("--seed must be an unsigned integer, got `{value}`"))?;
            }
            _ => args.out = PathBuf::from(value), // --out
        }
    }
    Ok(Some(args))
}

fn run(args: &Args) -> Result<(), String> {
    let scene = Scene::<f64>::build(&args.scene, args.seed).map_err(|e| e.to_string())?;
    let bounds = scene.bounds();
    println!("scene {}: {}", scene.name(), scene.description());
    let camera = Camera::framing(bounds, [-0.5, -0.6, -1.0], 35.0, 1.0)
        .map_err(|e| format!("framing the scene: {e}"))?;
    let settings = RenderSettings::new(args.size, args.size, args.method)
        .map_err(|e| e.to_string())?
        .with_mode(args.mode);
    let start = Instant::now();
    let frame = render_scene(&scene, &camera, &settings).map_err(|e| e.to_string())?;
    let elapsed = start.elapsed();
    std::fs::create_dir_all(&args.out)
        .map_err(|e| format!("creating {}: {e}", args.out.display()))?;
    let mode = match args.mode {
        Mode::Opaque => "opaque",
        Mode::Transparent => "transparent",
    };
    let stem = format!("{}-{}-{}", args.scene, args.method, mode);
    for (kind, image) in [
        ("shaded", frame.shaded_image()),
        ("heatmap", frame.heatmap_image(args.heat_max)),
    ] {
        let path = args.out.join(format!("{stem}-{kind}.png"));
        image
            .write_png(&path)
            .map_err(|e| format!("writing {}: {e}", path.display()))?;
        println!("wrote {}", path.display());
    }
    println!(
        "{} {} {}x{}: {:.3} s",
        args.method,
        mode,
        args.size,
        args.size,
        elapsed.as_secs_f64()
    );
    println!("{}", frame.totals());
    Ok(())
}

fn main() -> ExitCode {
    let args = match parse(std::env::args().skip(1)) {
        Ok(Some(args)) => args,
        Ok(None) => {
            println!("{USAGE}");
            return ExitCode::SUCCESS;
        }
        Err(msg) => {
            eprintln!("render: {msg}\n{USAGE}");
            return ExitCode::from(2);
        }
    };
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(msg) => {
            eprintln!("render: {msg}");
            ExitCode::FAILURE
        }
    }
}
