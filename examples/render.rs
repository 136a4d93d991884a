//! Renders a standard scene to PNG files: a headlight-shaded image and a
//! steps heatmap (clamped to 75 steps, as the papers' figures), and prints
//! the frame's totals (rays, roots, steps and evaluations per bounding-box
//! ray, status counts).
//!
//! ```text
//! cargo run --release --example render -- [--scene blobs] [--method quadratic-taylor]
//!     [--mode opaque] [--size 512] [--out out/] [--heat-max 75]
//! ```
//!
//! Rows render in parallel with `--features parallel` (same images). Bad
//! arguments print a message and exit with code 2; rendering or I/O errors
//! exit with code 1.

use boundtrace::fields::{Blobs, Kernel, PointBlob};
use boundtrace::tracer::camera::Camera;
use boundtrace::tracer::render::{RenderSettings, render};
use boundtrace::tracer::{Method, Mode};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

const USAGE: &str = "usage: render [--scene NAME] [--method METHOD] [--mode opaque|transparent] \
[--size PIXELS] [--out DIR] [--heat-max STEPS]";

/// The largest `--size`.
const MAX_SIZE: u32 = 8192;

/// The scenes this example knows.
const SCENES: [&str; 1] = ["blobs"];

/// Parsed command line.
struct Args {
    scene: String,
    method: Method,
    mode: Mode,
    size: u32,
    out: PathBuf,
    heat_max: u32,
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
    };
    while let Some(flag) = it.next() {
        if flag == "--help" || flag == "-h" {
            return Ok(None);
        }
        let value = match flag.as_str() {
            "--scene" | "--method" | "--mode" | "--size" | "--out" | "--heat-max" => it
                .next()
                .ok_or_else(|| format!("missing value after {flag}"))?,
            _ => return Err(format!("unknown argument `{flag}`")),
        };
        match flag.as_str() {
            "--scene" => {
                if !SCENES.contains(&value.as_str()) {
                    return Err(format!(
                        "unknown scene `{value}`; expected one of: {}",
                        SCENES.join(" ")
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
            _ => args.out = PathBuf::from(value), // --out
        }
    }
    Ok(Some(args))
}

/// The field of the local "blobs" scene.
type BlobField = Blobs<f64, Vec<PointBlob<f64>>>;

/// The local "blobs" scene: five overlapping compact blobs (degree 6) blended by
/// summation, `f = ½ − Σ k` (forward-inclusion paper §4.4, eq. 7), with its
/// bounding box.
fn blobs_scene() -> Result<(BlobField, [[f64; 3]; 2]), String> {
    let err = |e: boundtrace::fields::FieldError| format!("building the scene: {e}");
    let k = Kernel::compact(6, 1.0).map_err(err)?;
    let centres: [[f64; 3]; 5] = [
        [-0.7, 0.0, 0.0],
        [0.0, 0.05, 0.0],
        [0.7, 0.0, 0.1],
        [0.35, 0.62, -0.1],
        [-0.3, -0.6, 0.3],
    ];
    let blobs = centres
        .iter()
        .map(|&c| PointBlob::new(c, 1.0, k))
        .collect::<Result<Vec<_>, _>>()
        .map_err(err)?;
    let field = Blobs::new(0.5, blobs).map_err(err)?;
    // Inside, Σ k ≥ ½, so some blob has k ≥ ½ / 5 = 0.1 there:
    // (1 − r²)³ ≥ 0.1 gives r ≤ 0.732, so every surface point lies within
    // 0.75 of a centre (a tighter box than the supports' of radius 1).
    let mut bounds = [centres[0], centres[0]];
    for c in centres {
        for k in 0..3 {
            bounds[0][k] = bounds[0][k].min(c[k] - 0.75);
            bounds[1][k] = bounds[1][k].max(c[k] + 0.75);
        }
    }
    Ok((field, bounds))
}

fn run(args: &Args) -> Result<(), String> {
    // "blobs" is the only scene (checked by `parse`).
    let (field, bounds) = blobs_scene()?;
    let camera = Camera::framing(bounds, [-0.5, -0.6, -1.0], 35.0, 1.0)
        .map_err(|e| format!("framing the scene: {e}"))?;
    let settings = RenderSettings::new(args.size, args.size, args.method)
        .map_err(|e| e.to_string())?
        .with_mode(args.mode);
    let start = Instant::now();
    let frame = render(&field, &camera, bounds, &settings).map_err(|e| e.to_string())?;
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
