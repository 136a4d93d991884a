//! `boundtrace`: render, measure and slice implicit surfaces from scene
//! files (see `docs/scene-format.md`) or the standard scenes.
//!
//! ```text
//! boundtrace render SCENE -o OUT.png [--method M] [--size WxH] [--camera JSON|FILE]
//!                   [--output shaded|depth|normal|steps] [--transparent] [--backend cpu|gpu]
//! boundtrace stats SCENE --methods m1,m2,…|all [--rays N] [--transparent] [--json]
//! boundtrace slice SCENE --layers N --size WxH -o DIR
//! boundtrace scene gen NAME [--seed S] -o FILE
//! boundtrace scene check FILE
//! boundtrace methods
//! ```
//! `SCENE` is a scene file, or the name of a standard scene (`boundtrace
//! scene gen --help` lists them). Exit status: 0 on success, 1 for an
//! invalid scene or a failed run (nothing is written), 2 for bad
//! command-line usage.

use boundtrace_cli::output::{heat_legend, shade, write_atomic, write_dir_atomic};
use boundtrace_cli::report::{self, StatsReport};
use boundtrace_cli::scene_format::{CameraSpec, FormatError, SceneFile};
use boundtrace_ia_core::Real;
use boundtrace_tracer::camera::Camera;
use boundtrace_tracer::render::{Frame, RenderSettings, render_scene_with_progress};
use boundtrace_tracer::scenes::{DEFAULT_SEED, NAMES, Scene, SceneField};
use boundtrace_tracer::slice::{SliceSettings, slice_scalis_with_progress};
use boundtrace_tracer::stats::{
    MethodStats, RaySet, ReferenceParams, enlarged, markdown_table, run_scene_method_with_progress,
    scene_reference,
};
use boundtrace_tracer::{Method, Mode, Params};
use clap::{Parser, Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

/// Sound ray tracing of implicit surfaces.
#[derive(Parser, Debug)]
#[command(name = "boundtrace", version, about, long_about = None)]
struct Cli {
    /// No progress bars and no summaries (errors are still printed).
    #[arg(long, short, global = true)]
    quiet: bool,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Render a scene to a PNG image.
    Render(RenderArgs),
    /// Per-method statistics against the dense reference.
    Stats(StatsArgs),
    /// Slice a SCALIS skeleton into a PNG stack (for 3D printing).
    Slice(SliceArgs),
    /// Generate or check scene files.
    #[command(subcommand)]
    Scene(SceneCommand),
    /// List the tracing methods.
    Methods,
}

#[derive(Parser, Debug)]
struct RenderArgs {
    /// A scene file or a standard scene name.
    scene: String,
    /// The PNG to write (written to a temporary file, then renamed).
    #[arg(short = 'o', long = "out")]
    output: PathBuf,
    /// Tracing method (`boundtrace methods`); default: `quadratic-taylor`,
    /// or `interval` on blobtrees and homothetic skeletons and `affine` on
    /// HRBFs (which have no quadratic Taylor bounds); with `--backend gpu`
    /// the GPU's: `quadratic-taylor`, or `sphere` on blobtrees,
    /// `quadratic-bottom-up` on HRBFs, `scalis-quadratic` on SCALIS
    /// skeletons and `linear-taylor` on homothetic skeletons.
    #[arg(long, value_parser = parse_method)]
    method: Option<Method>,
    /// Image size.
    #[arg(long, default_value = "512x512", value_parser = parse_size)]
    size: (u32, u32),
    /// Camera as JSON (`{"perspective": {"eye": …, "target": …}}`) or a
    /// JSON file; default: the scene file's camera.
    #[arg(long)]
    camera: Option<String>,
    /// What to draw.
    #[arg(long = "output", default_value = "shaded")]
    kind: OutputKind,
    /// Find every root (transparent mode) instead of the first one.
    #[arg(long)]
    transparent: bool,
    /// Where to trace.
    #[arg(long, default_value = "cpu")]
    backend: Backend,
    /// Step count shown at the top of the steps heatmap's colour bar.
    #[arg(long, default_value_t = 75, value_parser = clap::value_parser!(u32).range(1..))]
    heat_max: u32,
    /// Seed of a standard scene.
    #[arg(long, default_value_t = DEFAULT_SEED)]
    seed: u64,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum OutputKind {
    /// Lambert shading with the scene's lights.
    Shaded,
    /// Depth as gray.
    Depth,
    /// Normals as colours.
    Normal,
    /// Steps heatmap with a colour bar.
    Steps,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Backend {
    /// The CPU renderer (all cores).
    Cpu,
    /// The GPU renderer (build with `--features gpu`).
    Gpu,
}

#[derive(Parser, Debug)]
struct StatsArgs {
    /// A scene file or a standard scene name.
    scene: String,
    /// Comma-separated methods, or `all`.
    #[arg(long, default_value = "all")]
    methods: String,
    /// Number of rays (from the faces of the bounds).
    #[arg(long, default_value_t = 2000, value_parser = clap::value_parser!(u64).range(1..=10_000_000))]
    rays: u64,
    /// Transparent mode (every root).
    #[arg(long)]
    transparent: bool,
    /// Print the JSON report (schema in `boundtrace_cli::report`).
    #[arg(long)]
    json: bool,
    /// Seed of the ray set.
    #[arg(long, default_value_t = 1)]
    ray_seed: u64,
    /// Seed of a standard scene.
    #[arg(long, default_value_t = DEFAULT_SEED)]
    seed: u64,
    /// Steps and time ratios against this method (`none` for no ratios).
    #[arg(long, default_value = "segment")]
    baseline: String,
}

#[derive(Parser, Debug)]
struct SliceArgs {
    /// A SCALIS scene file or standard scene name.
    scene: String,
    /// Number of slices along z.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16384))]
    layers: u32,
    /// Slice resolution.
    #[arg(long, default_value = "256x256", value_parser = parse_size)]
    size: (u32, u32),
    /// Output directory (the stack appears there only when complete).
    #[arg(short = 'o', long = "out")]
    output: PathBuf,
    /// Seed of a standard scene.
    #[arg(long, default_value_t = DEFAULT_SEED)]
    seed: u64,
}

#[derive(Subcommand, Debug)]
enum SceneCommand {
    /// Write a standard scene to a scene file.
    Gen {
        /// The standard scene.
        #[arg(value_parser = clap::builder::PossibleValuesParser::new(NAMES))]
        name: String,
        /// Generator seed.
        #[arg(long, default_value_t = DEFAULT_SEED)]
        seed: u64,
        /// The file to write.
        #[arg(short = 'o', long = "out")]
        output: PathBuf,
    },
    /// Validate a scene file (and sample f > 0 on its bounds' faces).
    Check {
        /// The file.
        file: PathBuf,
    },
}

/// The largest width or height.
const MAX_SIDE: u32 = 16384;

/// The most pixels of one rendered image (a frame keeps every pixel's
/// trace: about 100 bytes each).
const MAX_PIXELS: u64 = 40_000_000;

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("expected WxH with 1 ≤ W, H ≤ {MAX_SIDE} (e.g. 512x384), got `{s}`");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let w: u32 = w.trim().parse().map_err(|_| bad())?;
    let h: u32 = h.trim().parse().map_err(|_| bad())?;
    if (1..=MAX_SIDE).contains(&w) && (1..=MAX_SIDE).contains(&h) {
        Ok((w, h))
    } else {
        Err(bad())
    }
}

fn method_list() -> String {
    Method::ALL.map(|m| m.name()).join(", ")
}

fn parse_method(s: &str) -> Result<Method, String> {
    Method::from_name(s.trim())
        .ok_or_else(|| format!("unknown method `{s}`; expected one of: {}", method_list()))
}

/// One line of help per method.
fn method_help(m: Method) -> &'static str {
    match m {
        Method::Sphere => "sphere tracing with the field's global Lipschitz bound (Hart 1996)",
        Method::Segment => {
            "segment tracing with local directional Lipschitz bounds (Galin et al. 2020)"
        }
        Method::LinearTaylor => {
            "forward linear marching with Taylor bounds (forward-inclusion paper §4)"
        }
        Method::LinearBottomUp => "forward linear marching with bottom-up (affine) bounds",
        Method::LinearMixed => {
            "forward linear marching, the tighter of Taylor and bottom-up per side"
        }
        Method::QuadraticTaylor => {
            "forward quadratic marching with Taylor bounds (default; paper §5–6)"
        }
        Method::QuadraticBottomUp => "forward quadratic marching with bottom-up bounds",
        Method::QuadraticMixed => "forward quadratic marching, the tighter bound per side",
        Method::Interval => "interval-arithmetic bisection (Mitchell 1990)",
        Method::Affine => "revised-affine-arithmetic bisection (Fryazinov et al. 2010)",
        Method::ScalisQuadratic => {
            "SCALIS fast tracing with per-ray primitive lists (SCALIS scenes only; thesis Part III)"
        }
    }
}

/// A failure: the message and the exit status.
struct Fail(String, u8);

impl From<FormatError> for Fail {
    fn from(e: FormatError) -> Self {
        Fail(e.to_string(), 1)
    }
}

fn fail(msg: impl Into<String>) -> Fail {
    Fail(msg.into(), 1)
}

/// Reads a scene file, or builds a standard scene by name.
fn load(arg: &str, seed: u64) -> Result<(SceneFile, Scene<f64>), Fail> {
    let path = Path::new(arg);
    if path.is_file() {
        let bytes = std::fs::read(path).map_err(|e| fail(format!("reading {arg}: {e}")))?;
        let file = SceneFile::parse_bytes(&bytes).map_err(|e| fail(format!("{arg}: {e}")))?;
        let scene = file
            .build::<f64>()
            .map_err(|e| fail(format!("{arg}: {e}")))?;
        return Ok((file, scene));
    }
    if NAMES.contains(&arg) {
        let scene = Scene::<f64>::build(arg, seed).map_err(|e| fail(e.to_string()))?;
        let file = SceneFile::from_scene(&scene)?;
        return Ok((file, scene));
    }
    Err(fail(format!(
        "`{arg}` is neither a scene file nor a standard scene; standard scenes: {}",
        NAMES.join(", ")
    )))
}

/// The one progress bar of the command, on stderr: determinate over `len`
/// `unit`s (a spinner when `len` is `None`), hidden with `--quiet` or when
/// stderr is not a terminal (pipes and logs get no control characters;
/// stdout, the deterministic output, is never touched).
fn progress(quiet: bool, len: Option<u64>, unit: &str, msg: &str) -> ProgressBar {
    if quiet || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let (pb, template) = match len {
        Some(n) => (
            ProgressBar::new(n),
            format!(
                "{{msg}} {{bar:30}} {{human_pos}}/{{human_len}} {unit} [{{elapsed}} < {{eta}}]"
            ),
        ),
        None => (
            ProgressBar::new_spinner(),
            "{spinner} {msg} [{elapsed}]".to_string(),
        ),
    };
    if let Ok(style) = ProgressStyle::with_template(&template) {
        pb.set_style(style);
    }
    pb.set_message(msg.to_string());
    pb.enable_steady_tick(Duration::from_millis(120));
    pb
}

fn camera_spec(file: &SceneFile, arg: Option<&str>) -> Result<CameraSpec, Fail> {
    let Some(arg) = arg else {
        return Ok(file.camera_spec());
    };
    let text = if arg.trim_start().starts_with('{') {
        arg.to_string()
    } else {
        std::fs::read_to_string(arg)
            .map_err(|e| Fail(format!("--camera: reading {arg}: {e}"), 2))?
    };
    serde_json::from_str::<CameraSpec>(&text).map_err(|e| Fail(format!("--camera: {e}"), 2))
}

fn make_camera(
    spec: &CameraSpec,
    bounds: [[f64; 3]; 2],
    w: u32,
    h: u32,
) -> Result<Camera<f64>, Fail> {
    let aspect = f64::from(w) / f64::from(h);
    match *spec {
        CameraSpec::Framing { direction, fov_deg } => {
            Camera::framing(bounds, direction, fov_deg, aspect)
        }
        CameraSpec::Perspective {
            eye,
            target,
            up,
            fov_deg,
        } => Camera::perspective(eye, target, up, fov_deg, aspect),
        CameraSpec::Orthographic {
            eye,
            target,
            up,
            view_height,
        } => Camera::orthographic(eye, target, up, view_height, aspect),
    }
    .map_err(|e| fail(format!("`camera`: {e}")))
}

/// The default method of a field: the fastest supported one in our
/// measurements (README, "Methods").
fn default_method<T>(field: &SceneField<T>) -> Method {
    match field {
        SceneField::Blobtree(_) => Method::Interval,
        SceneField::Hrbf(_) => Method::Affine,
        // no quadratic Taylor bound; fastest in `boundtrace stats` (README)
        SceneField::Homothetic(_) => Method::Interval,
        _ => Method::QuadraticTaylor,
    }
}

/// The default method of a field on the GPU backend: the fastest that the
/// GPU runs on it (`boundtrace-gpu`'s modules: no `interval` on blobtrees
/// or homothetic skeletons, no `affine`, only the SCALIS methods on SCALIS
/// skeletons).
fn default_gpu_method<T>(field: &SceneField<T>) -> Method {
    match field {
        SceneField::Blobtree(_) => Method::Sphere,
        // no Taylor bound; fewer steps than `linear-bottom-up`
        SceneField::Hrbf(_) => Method::QuadraticBottomUp,
        SceneField::Scalis(_) => Method::ScalisQuadratic,
        // no quadratic Taylor bound; the fastest of the GPU's methods
        // (`boundtrace stats` on `skeleton-homothetic.json`: segment's
        // steps in 0.8 of its time)
        SceneField::Homothetic(_) => Method::LinearTaylor,
        _ => Method::QuadraticTaylor,
    }
}

fn mode(transparent: bool) -> Mode {
    if transparent {
        Mode::Transparent
    } else {
        Mode::Opaque
    }
}

fn render(a: &RenderArgs, quiet: bool) -> Result<(), Fail> {
    let (file, scene) = load(&a.scene, a.seed)?;
    let spec = camera_spec(&file, a.camera.as_deref())?;
    let (w, h) = a.size;
    if u64::from(w) * u64::from(h) > MAX_PIXELS {
        return Err(Fail(
            format!("--size {w}x{h}: at most {MAX_PIXELS} pixels per image"),
            2,
        ));
    }
    let method = a.method.unwrap_or_else(|| match a.backend {
        Backend::Cpu => default_method(scene.field()),
        Backend::Gpu => default_gpu_method(scene.field()),
    });
    let mode = mode(a.transparent);
    let clock = Instant::now();
    match a.backend {
        Backend::Cpu => {
            let camera = make_camera(&spec, scene.bounds(), w, h)?;
            let settings = RenderSettings::new(w, h, method)
                .map_err(|e| fail(e.to_string()))?
                .with_mode(mode);
            let pb = progress(
                quiet,
                Some(u64::from(h)),
                "rows",
                &format!("rendering {} ({w}x{h}, {method})", scene.name()),
            );
            let frame = render_scene_with_progress(&scene, &camera, &settings, &|n| {
                pb.inc(u64::from(n));
            })
            .map_err(|e| fail(e.to_string()));
            pb.finish_and_clear();
            finish_render(a, &file, &frame?, clock, "CPU", quiet)
        }
        Backend::Gpu => {
            let frame = render_gpu(&file, &spec, (w, h), method, mode, quiet)?;
            finish_render(a, &file, &frame, clock, "GPU", quiet)
        }
    }
}

/// Checks a rendered frame, turns it into the requested image and writes it
/// atomically (shared by the CPU and GPU backends).
fn finish_render<T: Real>(
    a: &RenderArgs,
    file: &SceneFile,
    frame: &Frame<T>,
    clock: Instant,
    backend: &str,
    quiet: bool,
) -> Result<(), Fail> {
    let method = frame.settings().method;
    let (w, h) = (frame.width(), frame.height());
    let totals = frame.totals();
    if totals.unsupported > 0 {
        return Err(fail(format!(
            "method `{}` is not supported on this field ({} of {} rays unsupported: it needs \
             bounds this field does not provide); nothing written. Try `interval` or `affine`, \
             or see `boundtrace methods`",
            method, totals.unsupported, totals.rays
        )));
    }
    let image = match a.kind {
        OutputKind::Shaded => {
            shade(frame, &file.lights, &file.material_spec()).map_err(|e| fail(e.to_string()))?
        }
        OutputKind::Depth => frame.depth_image(),
        OutputKind::Normal => frame.normal_image(),
        OutputKind::Steps => heat_legend(&frame.heatmap_image(a.heat_max), a.heat_max)
            .map_err(|e| fail(e.to_string()))?,
    };
    ensure_parent(&a.output)?;
    write_atomic(&a.output, &image.to_png()).map_err(|e| fail(e.to_string()))?;
    if totals.max_steps > 0 || totals.buffer_full > 0 {
        eprintln!(
            "warning: {} rays hit the step limit and {} filled the root buffer; those pixels may be incomplete",
            totals.max_steps, totals.buffer_full
        );
    }
    if !quiet {
        println!(
            "wrote {} ({w}x{h}, {}, {}, {backend}, {:.3} s)",
            a.output.display(),
            method,
            if a.transparent {
                "transparent"
            } else {
                "opaque"
            },
            clock.elapsed().as_secs_f64()
        );
        println!("{totals}");
    }
    Ok(())
}

/// The GPU backend's frame: the one place that calls the GPU tracer.
/// Without the `gpu` feature it is a clear error.
#[cfg(not(feature = "gpu"))]
fn render_gpu(
    _file: &SceneFile,
    _spec: &CameraSpec,
    _size: (u32, u32),
    _method: Method,
    _mode: Mode,
    _quiet: bool,
) -> Result<Frame<f32>, Fail> {
    Err(fail(
        "GPU backend: this boundtrace was built without GPU support; rebuild with \
         `cargo run --release -p boundtrace-cli --features gpu -- render …` (and build the \
         shader with scripts/build-spirv.sh, see docs/GPU.md)",
    ))
}

/// The GPU backend's frame: the one place that calls the GPU tracer
/// (`boundtrace_gpu::GpuTracer`), in `f32`.
#[cfg(feature = "gpu")]
fn render_gpu(
    file: &SceneFile,
    spec: &CameraSpec,
    (w, h): (u32, u32),
    method: Method,
    mode: Mode,
    quiet: bool,
) -> Result<Frame<f32>, Fail> {
    use boundtrace_gpu::{GpuScene, GpuTracer};
    use boundtrace_tracer::tile_programs::TilePrograms;
    let gpu_err = |e: boundtrace_gpu::GpuError| fail(format!("GPU backend: {e}"));
    let scene = file.build::<f32>()?;
    let b = scene.bounds().map(|c| c.map(f64::from));
    let c = make_camera(spec, b, w, h)?;
    let f = |v: [f64; 3]| v.map(|x| x as f32);
    let camera = Camera::<f32> {
        eye: f(c.eye),
        right: f(c.right),
        up: f(c.up),
        forward: f(c.forward),
        scale: c.scale.map(|x| x as f32),
        projection: c.projection,
    };
    // Blobtrees: one program per 8 × 8 tile (the primitives whose ABVs
    // the tile's rays meet), built for this camera and size.
    let gpu_scene = match scene.field() {
        SceneField::Blobtree(tree) => {
            let programs = TilePrograms::build(tree, &camera, scene.bounds(), w, h)
                .map_err(|e| fail(format!("GPU backend: {e}")))?;
            GpuScene::from_tile_programs(&scene, &programs)
        }
        _ => GpuScene::from_scene(&scene),
    }
    .map_err(gpu_err)?;
    let tracer = GpuTracer::new().map_err(gpu_err)?;
    let settings = RenderSettings::<f32>::new(w, h, method)
        .map_err(|e| fail(e.to_string()))?
        .with_mode(mode);
    let pb = progress(
        quiet,
        None,
        "",
        &format!("rendering on {}", tracer.adapter_info().name),
    );
    let frame = tracer
        .render(&gpu_scene, &camera, &settings)
        .map_err(gpu_err);
    pb.finish_and_clear();
    frame
}

fn stats(a: &StatsArgs, quiet: bool) -> Result<(), Fail> {
    let methods: Vec<Method> = if a.methods.trim() == "all" {
        Method::ALL.to_vec()
    } else {
        a.methods
            .split(',')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(|s| parse_method(s).map_err(|e| Fail(format!("--methods: {e}"), 2)))
            .collect::<Result<_, _>>()?
    };
    if methods.is_empty() {
        return Err(Fail("--methods: no method given".into(), 2));
    }
    let baseline = match a.baseline.as_str() {
        "none" => None,
        s => Some(parse_method(s).map_err(|e| Fail(format!("--baseline: {e}"), 2))?),
    };
    let (_, scene) = load(&a.scene, a.seed)?;
    let params = Params::new();
    let rays = RaySet::new(enlarged(scene.bounds(), 1e-3), a.rays as usize, a.ray_seed)
        .map_err(|e| fail(e.to_string()))?;
    let n_rays = rays.len() as u64;
    // the dense reference counts as one pass over the rays
    let pb = progress(
        quiet,
        Some((methods.len() as u64 + 1) * n_rays),
        "rays",
        &format!("{}: dense reference", scene.name()),
    );
    let m = mode(a.transparent);
    // the bar is cleared on success and on error alike
    let run = || -> Result<(f64, usize, Vec<MethodStats>), Fail> {
        let clock = Instant::now();
        let rp = ReferenceParams::new(params.eps).map_err(|e| fail(e.to_string()))?;
        let reference = scene_reference(&scene, &rays, &rp).map_err(|e| fail(e.to_string()))?;
        let reference_s = clock.elapsed().as_secs_f64();
        pb.inc(n_rays);
        let mut rows: Vec<MethodStats> = Vec::with_capacity(methods.len());
        for &method in &methods {
            pb.set_message(format!("{}: {method}", scene.name()));
            let on_rays = |n: usize| pb.inc(n as u64);
            rows.push(
                run_scene_method_with_progress(
                    &scene, &rays, &reference, method, m, &params, &on_rays,
                )
                .map_err(|e| fail(e.to_string()))?,
            );
        }
        Ok((reference_s, reference.hits(), rows))
    };
    let result = run();
    pb.finish_and_clear();
    let (reference_s, reference_hits, rows) = result?;
    let rep = StatsReport {
        schema: report::SCHEMA.into(),
        scene: scene.name().to_string(),
        primitives: scene.primitive_count(),
        rays: rays.len(),
        ray_seed: a.ray_seed,
        reference_hits,
        reference_seconds: reference_s,
        eps: params.eps,
        max_steps: params.max_steps,
        methods: &rows[..],
    };
    if a.json {
        println!("{}", report::to_json(&rep));
    } else {
        println!(
            "## {} ({} primitives), {m:?}\n\n{} rays (seed {}), {} hit the surface; eps {:e}, max_steps {}\n",
            rep.scene,
            rep.primitives,
            rep.rays,
            rep.ray_seed,
            rep.reference_hits,
            rep.eps,
            rep.max_steps
        );
        println!("{}", markdown_table(&rows, baseline));
    }
    Ok(())
}

fn slice(a: &SliceArgs, quiet: bool) -> Result<(), Fail> {
    let (_, scene) = load(&a.scene, a.seed)?;
    let SceneField::Scalis(w) = scene.field() else {
        return Err(fail(format!(
            "slicing needs a SCALIS skeleton scene (`skeleton` field with distance `scalis`); `{}` is not one",
            a.scene
        )));
    };
    let settings = SliceSettings {
        width: a.size.0,
        height: a.size.1,
        slices: a.layers,
    };
    let pb = progress(
        quiet,
        Some(u64::from(a.size.0) * u64::from(a.size.1)),
        "columns",
        &format!("slicing {} into {} layers", scene.name(), a.layers),
    );
    let stack =
        slice_scalis_with_progress(w.field(), scene.bounds(), settings, &Params::new(), &|n| {
            pb.inc(n)
        })
        .map_err(|e| fail(e.to_string()));
    pb.finish_and_clear();
    let stack = stack?;
    let stem = sanitize(scene.name());
    ensure_parent(&a.output)?;
    let pb = progress(
        quiet,
        Some(u64::from(a.layers)),
        "layers",
        &format!("writing {}", a.output.display()),
    );
    let files = write_dir_atomic(&a.output, |tmp| {
        for k in 0..a.layers {
            stack
                .write_png_slice(tmp, &stem, k)
                .map_err(|e| format!("writing slice {k}: {e}"))?;
            pb.inc(1);
        }
        Ok(())
    });
    pb.finish_and_clear();
    let files = files.map_err(fail)?;
    if !quiet {
        println!(
            "wrote {} slices to {} ({}x{})",
            files.len(),
            a.output.display(),
            a.size.0,
            a.size.1
        );
    }
    Ok(())
}

/// Creates the parent directory of an output file if missing.
fn ensure_parent(path: &Path) -> Result<(), Fail> {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() && !d.is_dir() => {
            std::fs::create_dir_all(d).map_err(|e| fail(format!("creating {}: {e}", d.display())))
        }
        _ => Ok(()),
    }
}

/// A file-name-safe stem.
fn sanitize(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() { "scene".into() } else { s }
}

fn scene_cmd(c: &SceneCommand, quiet: bool) -> Result<(), Fail> {
    match c {
        SceneCommand::Gen { name, seed, output } => {
            let scene = Scene::<f64>::build(name, *seed).map_err(|e| fail(e.to_string()))?;
            let json = SceneFile::from_scene(&scene)?.to_json();
            ensure_parent(output)?;
            write_atomic(output, json.as_bytes()).map_err(|e| fail(e.to_string()))?;
            if !quiet {
                println!("wrote {} ({})", output.display(), scene.description());
            }
            Ok(())
        }
        SceneCommand::Check { file } => {
            let arg = file.display().to_string();
            let bytes = std::fs::read(file).map_err(|e| fail(format!("reading {arg}: {e}")))?;
            let f = SceneFile::parse_bytes(&bytes).map_err(|e| fail(format!("{arg}: {e}")))?;
            let scene = f.build::<f64>().map_err(|e| fail(format!("{arg}: {e}")))?;
            let n = SceneFile::check_bounds(&scene, 33).map_err(|e| fail(format!("{arg}: {e}")))?;
            if !quiet {
                let [lo, hi] = scene.bounds();
                println!(
                    "{arg}: ok: `{}`, {} primitives, bounds {lo:?}..{hi:?}; f > 0 at {n} samples on the box faces",
                    scene.name(),
                    scene.primitive_count()
                );
            }
            Ok(())
        }
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Render(a) => render(a, cli.quiet),
        Command::Stats(a) => stats(a, cli.quiet),
        Command::Slice(a) => slice(a, cli.quiet),
        Command::Scene(c) => scene_cmd(c, cli.quiet),
        Command::Methods => {
            for m in Method::ALL {
                println!("{:<20} {}", m.name(), method_help(m));
            }
            Ok(())
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Fail(msg, code)) => {
            eprintln!("error: {msg}");
            ExitCode::from(code)
        }
    }
}
