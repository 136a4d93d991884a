//! Slices a SCALIS scene for additive manufacturing (thesis Part III ch. 2
//! §2.2, Table 2.1) and compares the cost with sampling the field at every
//! voxel centre with the same primitive lists.
//!
//! ```text
//! cargo run --release --example slice -- [--scene scalis-foam] [--size 128]
//!     [--slices 256] [--sample-2n] [--reps R] [--out DIR]
//! ```
//! Prints the time of slicing (the column classifier,
//! [`slice_scalis`]) with `N` and `2N` slices and of per-voxel sampling
//! with `N` slices (and `2N` with `--sample-2n`), the ratios, and the
//! voxels that differ, and the least evaluation work of a classifier
//! ([`least_work`]); with `--reps R` (R ≥ 2), times everything R times
//! and prints a Markdown table of min/median/max times and ratios (the
//! ratios are taken within each repetition); with `--out`, writes the `N`
//! slices as PNG files.
//! Single thread. Bad arguments exit with 2.

use boundtrace::fields::scalis::ScalisSegment;
use boundtrace::inclusion::Ray;
use boundtrace::tracer::Params;
use boundtrace::tracer::scalis::{PrimitiveHit, RayPrimitives};
use boundtrace::tracer::scenes::{Scene, SceneField};
use boundtrace::tracer::slice::{SliceSettings, SliceStack, sample_scalis, slice_scalis};
use std::process::ExitCode;
use std::time::Instant;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (mut scene, mut size, mut slices, mut out, mut sample_2n) =
        ("scalis-foam".to_string(), 128u32, 256u32, None, false);
    let mut reps = 1u32;
    let mut i = 0;
    while i + 1 < args.len() + 1 && i < args.len() {
        let v = args.get(i + 1).cloned().unwrap_or_default();
        let num = |v: &str| v.parse::<u32>().ok().filter(|&n| n > 0);
        match args[i].as_str() {
            "--scene" => scene = v,
            "--size" => match num(&v) {
                Some(n) => size = n,
                None => return bad("--size needs a positive integer"),
            },
            "--slices" => match num(&v) {
                Some(n) => slices = n,
                None => return bad("--slices needs a positive integer"),
            },
            "--reps" => match num(&v) {
                Some(n) => reps = n,
                None => return bad("--reps needs a positive integer"),
            },
            "--out" => out = Some(std::path::PathBuf::from(v)),
            "--sample-2n" => {
                sample_2n = true;
                i += 1;
                continue;
            }
            a => return bad(&format!("unknown argument `{a}`")),
        }
        i += 2;
    }
    let sc = match Scene::<f64>::build(&scene, 2023) {
        Ok(s) => s,
        Err(e) => return bad(&e.to_string()),
    };
    let SceneField::Scalis(w) = sc.field() else {
        return bad("slicing needs a SCALIS scene (scalis-tree, scalis-foam, scalis-random)");
    };
    let params = Params::new();
    let run = |n: u32, sample: bool| {
        let s = SliceSettings {
            width: size,
            height: size,
            slices: n,
        };
        let (c, cpu0) = (Instant::now(), cpu_time());
        let r = if sample {
            sample_scalis(w.field(), sc.bounds(), s, &params)
        } else {
            slice_scalis(w.field(), sc.bounds(), s, &params)
        };
        let wall = c.elapsed().as_secs_f64();
        // CPU time of this thread when available (the figures to compare
        // on a loaded machine), else the wall time
        let t = match (cpu0, cpu_time()) {
            (Some(a), Some(b)) => b - a,
            _ => wall,
        };
        eprintln!(
            "  ({n} slices, {}: {t:.2} s CPU, {wall:.2} s wall)",
            if sample { "sampling" } else { "slicing" }
        );
        (r, t)
    };
    let (a, ta) = run(slices, false);
    let (b, tb) = run(2 * slices, false);
    let (c, tc) = run(slices, true);
    let (a, _b, c) = match (a, b, c) {
        (Ok(a), Ok(b), Ok(c)) => (a, b, c),
        (Err(e), _, _) | (_, Err(e), _) | (_, _, Err(e)) => {
            eprintln!("slice: {e}");
            return ExitCode::FAILURE;
        }
    };
    let mut differ = 0u64;
    for k in 0..slices {
        for y in 0..size {
            for x in 0..size {
                differ += u64::from(a.inside(x, y, k) != c.inside(x, y, k));
            }
        }
    }
    println!("{scene}: {size}x{size}, release, 1 thread, times in CPU seconds of the thread");
    println!(
        "slicing, {slices} slices: {ta:.2} s ({} intervals, {} point evaluations of a primitive, {} ranges)",
        a.stats.steps, a.stats.field_evals, a.stats.bound_evals
    );
    println!(
        "slicing, {} slices: {tb:.2} s ({:.2}x the time of {slices})",
        2 * slices,
        tb / ta
    );
    println!(
        "per-voxel sampling, {slices} slices: {tc:.2} s ({} point evaluations of a primitive); slicing is {:.2}x faster",
        c.stats.field_evals,
        tc / ta
    );
    let mut td = f64::NAN;
    if sample_2n {
        let (d, t) = run(2 * slices, true);
        if let Err(e) = d {
            eprintln!("slice: {e}");
            return ExitCode::FAILURE;
        }
        td = t;
        println!(
            "per-voxel sampling, {} slices: {td:.2} s ({:.2}x the time of {slices}); slicing is {:.2}x faster",
            2 * slices,
            td / tc,
            td / tb
        );
    }
    println!(
        "voxels that differ between slicing and sampling: {differ} of {}",
        u64::from(size) * u64::from(size) * u64::from(slices)
    );
    let (points, evals) = least_work(w.field().segments(), sc.bounds(), &c);
    println!(
        "least work: {points} voxel centres next to a sign change, {evals} point evaluations \
         of a primitive there ({:.1}x fewer than sampling, {:.1}x fewer than slicing)",
        c.stats.field_evals as f64 / evals as f64,
        a.stats.field_evals as f64 / evals as f64
    );
    if reps > 1 {
        let mut times = vec![[ta, tb, tc, td]];
        for _ in 1..reps {
            let t = |n, sample| run(n, sample).1;
            let d = if sample_2n {
                t(2 * slices, true)
            } else {
                f64::NAN
            };
            times.push([t(slices, false), t(2 * slices, false), t(slices, true), d]);
        }
        print_table(&times, slices, sample_2n);
    }
    if let Some(dir) = out {
        if let Err(e) = a.write_png_stack(&dir, &scene) {
            eprintln!("slice: writing {}: {e}", dir.display());
            return ExitCode::FAILURE;
        }
    }
    ExitCode::SUCCESS
}

/// The Markdown table of `--reps`: min/median/max over the repetitions of
/// each time `[slicing N, slicing 2N, sampling N, sampling 2N]` and of the
/// ratios taken within each repetition.
fn print_table(times: &[[f64; 4]], n: u32, sample_2n: bool) {
    let row = |name: String, f: &dyn Fn(&[f64; 4]) -> f64| {
        let mut v: Vec<f64> = times.iter().map(f).collect();
        v.sort_by(f64::total_cmp);
        let med = if v.len() % 2 == 1 {
            v[v.len() / 2]
        } else {
            0.5 * (v[v.len() / 2 - 1] + v[v.len() / 2])
        };
        println!(
            "| {name} | {:.2} | {med:.2} | {:.2} |",
            v[0],
            v[v.len() - 1]
        );
    };
    println!(
        "\n{} repetitions (CPU seconds of the thread; ratios within each repetition):\n",
        times.len()
    );
    println!("| figure | min | median | max |\n| --- | --: | --: | --: |");
    row(format!("slicing, {n} slices (s)"), &|t| t[0]);
    row(format!("slicing, {} slices (s)", 2 * n), &|t| t[1]);
    row(format!("per-voxel sampling, {n} slices (s)"), &|t| t[2]);
    if sample_2n {
        row(format!("per-voxel sampling, {} slices (s)", 2 * n), &|t| {
            t[3]
        });
    }
    row(
        format!("slicing {} / {n} slices (time ratio)", 2 * n),
        &|t| t[1] / t[0],
    );
    row(format!("sampling / slicing, {n} slices (speed-up)"), &|t| {
        t[2] / t[0]
    });
    if sample_2n {
        row(
            format!("sampling / slicing, {} slices (speed-up)", 2 * n),
            &|t| t[3] / t[1],
        );
    }
}

/// The evaluations any classifier that evaluates the field where the stack
/// `st` changes sign needs: the voxel centres next to a sign change along
/// a column (a bound cannot decide a centre that close to the surface),
/// and the primitives whose supports contain them (what evaluating the
/// field there costs with the per-ray lists). Returns `(centres,
/// primitive evaluations)`.
fn least_work(
    segments: &[ScalisSegment<f64>],
    bounds: [[f64; 3]; 2],
    st: &SliceStack,
) -> (u64, u64) {
    let s = st.settings();
    let [lo, hi] = bounds;
    let (dx, dy) = (
        (hi[0] - lo[0]) / f64::from(s.width),
        (hi[1] - lo[1]) / f64::from(s.height),
    );
    let len = hi[2] - lo[2];
    let mut storage = vec![PrimitiveHit::empty(); segments.len()];
    let (mut points, mut evals) = (0u64, 0u64);
    for y in 0..s.height {
        for x in 0..s.width {
            let o = [
                lo[0] + (f64::from(x) + 0.5) * dx,
                lo[1] + (f64::from(y) + 0.5) * dy,
                lo[2],
            ];
            let ray = Ray::new(o, [0.0, 0.0, 1.0]);
            let list = RayPrimitives::build(segments, &ray, [0.0, len], &mut storage);
            let hits = list.hits();
            for k in 0..s.slices {
                let inside = st.inside(x, y, k);
                let next_to = (k > 0 && st.inside(x, y, k - 1) != inside)
                    || (k + 1 < s.slices && st.inside(x, y, k + 1) != inside);
                if next_to {
                    let t = len * (f64::from(k) + 0.5) / f64::from(s.slices);
                    points += 1;
                    evals += hits.iter().filter(|h| h.entry <= t && t <= h.exit).count() as u64;
                }
            }
        }
    }
    (points, evals)
}

/// The CPU time of the calling thread in seconds (Linux
/// `/proc/thread-self/schedstat`), `None` elsewhere.
fn cpu_time() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: f64 = s.split_whitespace().next()?.parse().ok()?;
    Some(ns * 1e-9)
}

fn bad(msg: &str) -> ExitCode {
    eprintln!("slice: {msg}");
    ExitCode::from(2)
}
