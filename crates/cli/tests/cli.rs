//! Integration tests of the `boundtrace` binary: every subcommand, the
//! error cases (exit status and message), outputs never clobbered on
//! failure, scene files rendering like the built-in generators, and
//! golden hit/miss masks of two shipped scenes.

use boundtrace_cli::scene_format::SceneFile;
use boundtrace_tracer::camera::Camera;
use boundtrace_tracer::render::{Frame, RenderSettings, render_scene};
use boundtrace_tracer::scenes::{DEFAULT_SEED, Scene};
use boundtrace_tracer::{Method, Mode};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_boundtrace"))
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn scene_path(name: &str) -> String {
    repo()
        .join("examples/scenes")
        .join(name)
        .display()
        .to_string()
}

fn run(args: &[&str]) -> Output {
    bin().args(args).output().expect("running boundtrace")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

struct TempDir(PathBuf);

impl TempDir {
    fn new(tag: &str) -> Self {
        let d = std::env::temp_dir().join(format!(
            "boundtrace-cli-{tag}-{}-{}",
            std::process::id(),
            std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map(|d| d.as_nanos())
                .unwrap_or(0)
        ));
        std::fs::create_dir_all(&d).unwrap();
        Self(d)
    }
    fn path(&self, name: &str) -> String {
        self.0.join(name).display().to_string()
    }
    fn entries(&self) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(&self.0)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Asserts a failed run: exit status `code`, stderr containing every
/// needle, and no panic.
fn assert_fails(o: &Output, code: i32, needles: &[&str]) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(code), "stderr: {err}");
    for n in needles {
        assert!(err.contains(n), "`{n}` not in stderr: {err}");
    }
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn methods_lists_every_method() {
    let o = run(&["methods"]);
    assert!(o.status.success());
    let out = stdout(&o);
    for m in Method::ALL {
        assert!(out.contains(m.name()), "{m} missing: {out}");
    }
}

#[test]
fn scene_gen_check_and_render_like_the_generator() {
    let d = TempDir::new("gen");
    let file = d.path("blobs.json");
    let o = run(&["scene", "gen", "blobs", "-o", &file, "-q"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = run(&["scene", "check", &file]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("ok"));
    // the same PNG from the file and from the built-in generator
    let (a, b) = (d.path("a.png"), d.path("b.png"));
    for (scene, out) in [(file.as_str(), &a), ("blobs", &b)] {
        let o = run(&["render", scene, "-o", out, "--size", "24x16", "-q"]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let (pa, pb) = (std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    assert!(pa.starts_with(&[0x89, b'P', b'N', b'G']));
    assert_eq!(pa, pb, "file and generator render differently");
    // unknown standard scene name
    let o = run(&["scene", "gen", "no-such", "-o", &file]);
    assert_fails(&o, 2, &["no-such"]);
}

/// The frames of a standard scene and of its exported file are equal (every
/// pixel's trace and hits), for one scene of each field kind.
#[test]
fn scene_files_render_identically_to_the_generators() {
    for name in [
        "blobs",
        "molecule",
        "hrbf-8",
        "scalis-random",
        "aggregate-1-smooth",
    ] {
        let scene = Scene::<f64>::build(name, DEFAULT_SEED).unwrap();
        let back = SceneFile::parse(&SceneFile::from_scene(&scene).unwrap().to_json())
            .unwrap()
            .build::<f64>()
            .unwrap();
        let cam = Camera::framing(scene.bounds(), [-0.5, -0.6, -1.0], 35.0, 1.0).unwrap();
        for method in [Method::QuadraticTaylor, Method::Interval] {
            let s = RenderSettings::new(12, 12, method)
                .unwrap()
                .with_mode(Mode::Transparent);
            let f1: Frame<f64> = render_scene(&scene, &cam, &s).unwrap();
            let f2 = render_scene(&back, &cam, &s).unwrap();
            assert!(f1 == f2, "{name} {method}: frames differ");
        }
    }
}

#[test]
fn render_every_output_kind_and_camera_override() {
    let d = TempDir::new("kinds");
    for kind in ["shaded", "depth", "normal", "steps"] {
        let out = d.path(&format!("{kind}.png"));
        let o = run(&[
            "render",
            &scene_path("operators.json"),
            "-o",
            &out,
            "--size",
            "20x16",
            "--output",
            kind,
            "-q",
        ]);
        assert!(o.status.success(), "{kind}: {}", stderr(&o));
        assert!(std::fs::metadata(&out).unwrap().len() > 8);
    }
    let out = d.path("cam.png");
    let o = run(&[
        "render",
        &scene_path("blobs.json"),
        "-o",
        &out,
        "--size",
        "16x16",
        "--transparent",
        "--method",
        "affine",
        "--camera",
        r#"{"orthographic": {"eye": [0, 0, -3], "target": [0, 0, 0], "view_height": 2.5}}"#,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("transparent"));
    // a bad camera override is a usage error
    let o = run(&[
        "render",
        &scene_path("blobs.json"),
        "-o",
        &out,
        "--camera",
        r#"{"fisheye": {}}"#,
    ]);
    assert_fails(&o, 2, &["--camera", "fisheye"]);
}

/// Writes `text` as a scene file, renders it to an existing output that
/// must survive, and returns the failed run.
fn render_bad(text: &str, extra: &[&str]) -> Output {
    let d = TempDir::new("bad");
    let file = d.path("s.json");
    std::fs::write(&file, text).unwrap();
    let out = d.path("out.png");
    std::fs::write(&out, b"keep me").unwrap();
    let mut args = vec!["render", file.as_str(), "-o", out.as_str(), "--size", "8x8"];
    args.extend_from_slice(extra);
    let o = run(&args);
    assert!(!o.status.success());
    assert_eq!(std::fs::read(&out).unwrap(), b"keep me", "output clobbered");
    assert_eq!(
        d.entries(),
        vec!["out.png", "s.json"],
        "temporary files left"
    );
    o
}

const GOOD: &str = r#"{
  "version": 1,
  "field": { "blobs": {
    "iso": 0.5,
    "blobs": [ { "center": [0, 0, 0], "kernel": { "compact": { "degree": 6, "sigma": 0.8 } } } ]
  } }
}"#;

#[test]
fn malformed_json_reports_line_and_column() {
    let o = render_bad(&GOOD.replace("\"iso\": 0.5,", "\"iso\": 0.5,,"), &[]);
    assert_fails(&o, 1, &["line 4, column"]);
    let o = render_bad("{\"version\": 1, \"field\": ", &[]);
    assert_fails(&o, 1, &["line 1, column"]);
    let o = render_bad(&GOOD.replace("0.5", "1e999"), &[]);
    assert_fails(&o, 1, &["line 4", "field.blobs.iso"]);
    let o = render_bad(
        &[0xff_u8, 0xfe]
            .iter()
            .map(|&b| b as char)
            .collect::<String>(),
        &[],
    );
    assert_fails(&o, 1, &["line 1"]);
}

#[test]
fn invalid_values_name_the_field() {
    let o = render_bad(&GOOD.replace("\"sigma\": 0.8", "\"sigma\": -0.8"), &[]);
    assert_fails(&o, 1, &["field.blobs.blobs[0].kernel.compact.sigma", "> 0"]);
    let o = render_bad(&GOOD.replace("\"compact\"", "\"wendland\""), &[]);
    assert_fails(
        &o,
        1,
        &["field.blobs.blobs[0].kernel", "unknown variant `wendland`"],
    );
    let o = render_bad(&GOOD.replace("\"center\"", "\"centre\""), &[]);
    assert_fails(&o, 1, &["field.blobs.blobs[0]", "centre"]);
    let skeleton = |edges: &str, radius: &str| {
        format!(
            r#"{{"version": 1, "field": {{"skeleton": {{"iso": 1,
            "kernel": {{"compact": {{"degree": 6, "sigma": 2}}}},
            "vertices": [{{"position": [0, 0, 0], "radius": {radius}}},
                         {{"position": [0, 0, 0], "radius": 0.1}},
                         {{"position": [0.5, 0, 0], "radius": 0.1}}],
            "edges": {edges}}}}}}}"#
        )
    };
    let o = render_bad(&skeleton("[[0, 1]]", "0.1"), &[]);
    assert_fails(&o, 1, &["field.skeleton.edges[0]", "zero-length segment"]);
    let o = render_bad(&skeleton("[[0, 2]]", "-0.1"), &[]);
    assert_fails(&o, 1, &["field.skeleton.vertices[0].radius"]);
    let tree = |root: &str| {
        format!(
            r#"{{"version": 1, "bounds": [[-1, -1, -1], [1, 1, 1]],
            "field": {{"blobtree": {{"root": {root}}}}}}}"#
        )
    };
    let o = render_bad(&tree(r#"{"union": {"children": []}}"#), &[]);
    assert_fails(&o, 1, &["field.blobtree.root.union.children", "empty tree"]);
    let o = render_bad(
        &tree(
            r#"{"smooth-union": {"children": [{"sphere": {"radius": 1}}, {"sphere": {"radius": 0.5}}]}}"#,
        ),
        &[],
    );
    assert_fails(
        &o,
        1,
        &["field.blobtree.root.smooth-union.beta", "required"],
    );
    // too deep for the format (and the encoding's stack): 70 nested unions
    let mut root = r#"{"sphere": {"radius": 0.5}}"#.to_string();
    for _ in 0..70 {
        root = format!(r#"{{"union": {{"children": [{root}, {{"sphere": {{"radius": 0.1}}}}]}}}}"#);
    }
    let o = render_bad(&tree(&root), &[]);
    assert_fails(&o, 1, &["field"]);
    // the homothetic skeleton's compact kernel needs σ > 1
    let homothetic = skeleton("[[0, 2]]", "0.1")
        .replace("{\"iso\": 1,", "{\"distance\": \"homothetic\", \"iso\": 1,")
        .replace("\"sigma\": 2", "\"sigma\": 0.9");
    let o = render_bad(&homothetic, &[]);
    assert_fails(&o, 1, &["field.skeleton.kernel.compact.sigma", "sigma > 1"]);
    // too large for the flat encoding: a right comb of 40 differences needs
    // an evaluation stack of 41 entries (at most 32)
    let mut root = r#"{"sphere": {"radius": 0.5}}"#.to_string();
    for _ in 0..40 {
        root = format!(
            r#"{{"difference": {{"children": [{{"sphere": {{"radius": 0.9}}}}, {root}]}}}}"#
        );
    }
    let o = render_bad(&tree(&root), &[]);
    assert_fails(
        &o,
        1,
        &[
            "field.blobtree.root",
            "tree too large for the encoding",
            "stack of 41",
        ],
    );
    // a missing bounds for a field without computed bounds
    let o = render_bad(
        &GOOD.replace(
            "\"compact\": { \"degree\": 6, \"sigma\": 0.8 }",
            "\"gaussian\": { \"sigma\": 0.3 }",
        ),
        &[],
    );
    assert_fails(&o, 1, &["`bounds`", "required"]);
}

#[test]
fn unknown_method_and_bad_sizes_are_usage_errors() {
    let o = render_bad(GOOD, &["--method", "warp-drive"]);
    assert_fails(&o, 2, &["unknown method `warp-drive`", "quadratic-taylor"]);
    let d = TempDir::new("size");
    let o = run(&["render", "blobs", "-o", &d.path("x.png"), "--size", "0x10"]);
    assert_fails(&o, 2, &["WxH"]);
    let o = run(&[
        "render",
        "blobs",
        "-o",
        &d.path("x.png"),
        "--size",
        "16000x16000",
    ]);
    assert_fails(&o, 2, &["at most 40000000 pixels"]);
    assert!(d.entries().is_empty());
    let o = run(&["stats", "blobs", "--methods", "sphere,nope"]);
    assert_fails(&o, 2, &["unknown method `nope`"]);
    let o = run(&["render", "no/such/scene.json", "-o", "x.png"]);
    assert_fails(&o, 1, &["neither a scene file nor a standard scene"]);
}

#[test]
fn unsupported_method_writes_nothing() {
    // HRBF has no Taylor bound: every ray is unsupported
    let text = std::fs::read_to_string(scene_path("hrbf.json")).unwrap();
    let o = render_bad(&text, &["--method", "linear-taylor"]);
    assert_fails(&o, 1, &["not supported", "nothing written"]);
}

/// The shipped homothetic skeleton renders (default method and segment
/// tracing), its statistics agree with the dense reference for every
/// supported method, and the unsupported quadratic Taylor bound is a clear
/// error.
#[test]
fn homothetic_skeleton_renders_and_measures() {
    let scene = scene_path("skeleton-homothetic.json");
    let d = TempDir::new("homothetic");
    let out = d.path("h.png");
    for (extra, method) in [
        (&[][..], "interval"),
        (&["--method", "segment"][..], "segment"),
    ] {
        let mut args = vec!["render", &scene, "-o", &out, "--size", "24x20"];
        args.extend_from_slice(extra);
        let o = run(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(stdout(&o).contains(method), "{}", stdout(&o));
        assert!(std::fs::read(&out).unwrap().starts_with(&[0x89, b'P']));
    }
    let o = run(&[
        "stats",
        &scene,
        "--methods",
        "sphere,segment,linear-taylor,quadratic-mixed,interval",
        "--rays",
        "60",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let rep = boundtrace_cli::report::parse(&stdout(&o)).expect("schema");
    assert_eq!(rep.methods.len(), 5);
    assert!(rep.reference_hits > 0);
    for m in &rep.methods {
        assert_eq!(m.finished, 60, "{m:?}");
        assert_eq!(m.missed + m.stepped_past, 0, "{m:?}");
    }
    let text = std::fs::read_to_string(&scene).unwrap();
    let o = render_bad(&text, &["--method", "quadratic-taylor"]);
    assert_fails(&o, 1, &["not supported", "nothing written"]);
    let o = run(&["slice", &scene, "--layers", "2", "-o", &d.path("no")]);
    assert_fails(&o, 1, &["SCALIS"]);
}

/// Without `--features gpu`, `--backend gpu` is a clear error with nothing
/// written (with it, the default method renders: next test).
#[cfg(not(feature = "gpu"))]
#[test]
fn gpu_backend_without_gpu_is_a_clear_error() {
    let o = render_bad(GOOD, &["--backend", "gpu"]);
    assert_fails(&o, 1, &["GPU backend:"]);
}

/// With `--features gpu` (CI: `cargo test -p boundtrace-cli --features gpu
/// --test cli gpu_backend`, on lavapipe): sphere tracing and the default
/// method (`quadratic-taylor`) render PNGs on the GPU (the shader's
/// `trace_sphere` and `trace_quadratic_taylor_blobs` entry points; their
/// agreement with the CPU is the GPU crate's difftest), and a method
/// without a GPU entry point in the module is a clear error with nothing
/// written; an HRBF and a homothetic skeleton render with the GPU's
/// default method on them, and a standard blobtree by tile programs.
#[cfg(feature = "gpu")]
#[test]
fn gpu_backend_renders_sphere_tracing() {
    let d = TempDir::new("gpu");
    let scene = scene_path("blobs.json");
    let base = [
        "--method", "sphere", "--size", "24x24", "--output", "depth", "--quiet",
    ];
    let gpu_png = d.path("gpu.png");
    let mut args = vec![
        "render",
        scene.as_str(),
        "-o",
        gpu_png.as_str(),
        "--backend",
        "gpu",
    ];
    args.extend(base);
    let o = run(&args);
    let err = stderr(&o);
    let ci = std::env::var("CI").is_ok_and(|v| v == "true" || v == "1");
    if !o.status.success() && !ci && err.contains("no usable adapter") {
        eprintln!("\n!!!!!!!! SKIPPING the GPU backend test: {err} !!!!!!!!\n");
        return;
    }
    assert!(o.status.success(), "{err}");
    let png = std::fs::read(&gpu_png).unwrap();
    assert!(png.len() > 8 && png[1..4] == *b"PNG", "not a PNG");
    // The default method (`quadratic-taylor`) runs on the GPU too.
    let default_png = d.path("default.png");
    let o = run(&[
        "render",
        &scene,
        "-o",
        &default_png,
        "--backend",
        "gpu",
        "--size",
        "8x8",
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let png = std::fs::read(&default_png).unwrap();
    assert!(png.len() > 8 && png[1..4] == *b"PNG", "not a PNG");
    // The mixed methods too (two pipelines per module since session 32).
    let mixed_png = d.path("mixed.png");
    let o = run(&[
        "render",
        &scene,
        "-o",
        &mixed_png,
        "--backend",
        "gpu",
        "--method",
        "quadratic-mixed",
        "--size",
        "8x8",
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let png = std::fs::read(&mixed_png).unwrap();
    assert!(png.len() > 8 && png[1..4] == *b"PNG", "not a PNG");
    // A method without GPU code is refused, and no file is written.
    let no = d.path("no.png");
    let o = run(&[
        "render",
        &scene,
        "-o",
        &no,
        "--backend",
        "gpu",
        "--method",
        "affine",
        "--size",
        "8x8",
    ]);
    let err = stderr(&o);
    assert_fails(&o, 1, &["GPU backend:", "affine"]);
    assert!(!Path::new(&no).exists(), "{err}");
    // An HRBF renders with the GPU's default method on it,
    // `quadratic-bottom-up` (the CPU's, `affine`, has no GPU code).
    let hrbf_png = d.path("hrbf.png");
    let o = run(&[
        "render",
        "hrbf-8",
        "-o",
        &hrbf_png,
        "--backend",
        "gpu",
        "--size",
        "8x8",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("quadratic-bottom-up"), "{}", stdout(&o));
    let png = std::fs::read(&hrbf_png).unwrap();
    assert!(png.len() > 8 && png[1..4] == *b"PNG", "not a PNG");
    // A homothetic skeleton (a scene file) renders with the GPU's default
    // method on it, `linear-taylor` (the CPU's, `interval`, has no GPU code).
    let homothetic = scene_path("skeleton-homothetic.json");
    let homothetic_png = d.path("homothetic.png");
    let o = run(&[
        "render",
        &homothetic,
        "-o",
        &homothetic_png,
        "--backend",
        "gpu",
        "--size",
        "8x8",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("linear-taylor"), "{}", stdout(&o));
    let png = std::fs::read(&homothetic_png).unwrap();
    assert!(png.len() > 8 && png[1..4] == *b"PNG", "not a PNG");
    // A blobtree (a standard scene by name) renders with one program per
    // 8 × 8 tile (`TilePrograms`): the 11,110-primitive `aggregate-4` too.
    let tree_png = d.path("tree.png");
    let o = run(&[
        "render",
        "aggregate-4",
        "-o",
        &tree_png,
        "--backend",
        "gpu",
        "--method",
        "sphere",
        "--size",
        "16x16",
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let png = std::fs::read(&tree_png).unwrap();
    assert!(png.len() > 8 && png[1..4] == *b"PNG", "not a PNG");
}

#[test]
fn scene_check_finds_bounds_that_cut_the_surface() {
    let d = TempDir::new("check");
    let file = d.path("s.json");
    let text = GOOD.replace(
        "\"version\": 1,",
        "\"version\": 1, \"bounds\": [[-0.2, -1, -1], [1, 1, 1]],",
    );
    std::fs::write(&file, text).unwrap();
    let o = run(&["scene", "check", &file]);
    assert_fails(&o, 1, &["`bounds`", "surface leaves the box"]);
    for f in std::fs::read_dir(repo().join("examples/scenes")).unwrap() {
        let p = f.unwrap().path().display().to_string();
        let o = run(&["scene", "check", &p]);
        assert!(o.status.success(), "{p}: {}", stderr(&o));
    }
}

#[test]
fn stats_json_follows_the_schema() {
    let o = run(&[
        "stats",
        &scene_path("blobs.json"),
        "--methods",
        "segment,quadratic-taylor",
        "--rays",
        "50",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let rep = boundtrace_cli::report::parse(&stdout(&o)).expect("schema");
    assert_eq!(rep.schema, boundtrace_cli::report::SCHEMA);
    assert_eq!(rep.rays, 50);
    assert_eq!(rep.methods.len(), 2);
    assert_eq!(rep.methods[1].method, "quadratic-taylor");
    for m in &rep.methods {
        assert_eq!(m.missed + m.stepped_past, 0, "{m:?}");
        assert!(m.steps.mean > 0.0 && f64::from(m.steps.max) >= m.steps.median);
    }
    // round trip of the schema types
    let again = serde_json::to_string(&rep).unwrap();
    assert_eq!(boundtrace_cli::report::parse(&again).unwrap(), rep);
    // the markdown table, transparent mode
    let o = run(&[
        "stats",
        "hrbf-8",
        "--methods",
        "interval",
        "--rays",
        "20",
        "--transparent",
        "--baseline",
        "none",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("Transparent") && stdout(&o).contains("| interval"));
}

#[test]
fn slice_writes_a_complete_stack_or_nothing() {
    let d = TempDir::new("slice");
    let out = d.path("stack");
    let o = run(&[
        "slice",
        &scene_path("skeleton.json"),
        "--layers",
        "3",
        "--size",
        "16x12",
        "-o",
        &out,
        "-q",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let n = std::fs::read_dir(&out).unwrap().count();
    assert_eq!(n, 3);
    assert_eq!(d.entries(), vec!["stack"], "temporary directory left");
    let o = run(&[
        "slice",
        &scene_path("blobs.json"),
        "--layers",
        "3",
        "-o",
        &d.path("no"),
    ]);
    assert_fails(&o, 1, &["SCALIS"]);
    assert_eq!(d.entries(), vec!["stack"]);
}

/// The hit/miss mask of a shipped scene at 32 × 24 (`#` hit, `.` miss).
fn mask(name: &str) -> String {
    let text = std::fs::read_to_string(scene_path(name)).unwrap();
    let file = SceneFile::parse(&text).unwrap();
    let scene = file.build::<f64>().unwrap();
    let (w, h) = (32, 24);
    let cam = match file.camera_spec() {
        boundtrace_cli::scene_format::CameraSpec::Perspective {
            eye,
            target,
            up,
            fov_deg,
        } => Camera::perspective(eye, target, up, fov_deg, 32.0 / 24.0).unwrap(),
        boundtrace_cli::scene_format::CameraSpec::Framing { direction, fov_deg } => {
            Camera::framing(scene.bounds(), direction, fov_deg, 32.0 / 24.0).unwrap()
        }
        other => panic!("unexpected camera {other:?}"),
    };
    let s = RenderSettings::new(w, h, Method::Interval).unwrap();
    let f = render_scene(&scene, &cam, &s).unwrap();
    let mut out = String::new();
    for y in 0..h {
        for x in 0..w {
            out.push(if f.hits(x, y).is_empty() { '.' } else { '#' });
        }
        out.push('\n');
    }
    out
}

#[test]
fn golden_masks_of_two_shipped_scenes() {
    for (scene, golden) in [
        ("blobs.json", "blobs.mask"),
        ("operators.json", "operators.mask"),
    ] {
        let got = mask(scene);
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/golden")
            .join(golden);
        if std::env::var_os("BOUNDTRACE_BLESS").is_some() {
            std::fs::write(&path, &got).unwrap();
        }
        let want = std::fs::read_to_string(&path).unwrap();
        let differ = got
            .chars()
            .zip(want.chars())
            .filter(|(a, b)| a != b)
            .count();
        assert!(
            got.len() == want.len() && differ == 0,
            "{scene}: {differ} pixels differ from {golden}\n{got}"
        );
        assert!(
            got.contains('#') && got.contains('.'),
            "{scene}: degenerate mask"
        );
    }
}
