//! The JSON report of `boundtrace stats --json` (schema
//! `boundtrace-stats/1`).
//!
//! ```json
//! {
//!   "schema": "boundtrace-stats/1",
//!   "scene": "blobs",            // scene name
//!   "primitives": 32,
//!   "rays": 2000, "ray_seed": 1,  // the RaySet: rays from the faces of the bounds
//!   "reference_hits": 1234,       // rays with a root in the dense reference
//!   "reference_seconds": 0.8,
//!   "eps": 0.0001, "max_steps": 100000,
//!   "methods": [ {
//!     "method": "quadratic-taylor",
//!     "mode": "opaque",           // or "transparent"
//!     "rays": 2000, "unsupported": 0, "finished": 2000, "max_steps": 0, "buffer_full": 0,
//!     "steps": { "mean": 12.3, "median": 11.0, "max": 40 },
//!     "field_evals_mean": 20.1, "bound_evals_mean": 12.3,
//!     "ns_per_ray": 950.0,        // wall time of one trace call, averaged
//!     "agree": 2000, "missed": 0, "spurious": 0, "far": 0,
//!     "stepped_past": 0, "gave_up": 0, "wrong_side": 0
//!   } ]
//! }
//! ```
//!
//! The counts are numbers of rays (see `boundtrace_tracer::stats::MethodStats`);
//! `missed`/`spurious` compare with the dense reference. Parse it back
//! with [`parse`]:
//!
//! ```
//! use boundtrace_cli::report::{SCHEMA, StatsReport, parse, to_json};
//! let rep = StatsReport {
//!     schema: SCHEMA.into(), scene: "s".into(), primitives: 1, rays: 10, ray_seed: 1,
//!     reference_hits: 3, reference_seconds: 0.5, eps: 1e-4, max_steps: 100, methods: &[][..],
//! };
//! let v = parse(&to_json(&rep))?;
//! assert_eq!(v.rays, 10);
//! # Ok::<(), serde_json::Error>(())
//! ```

use boundtrace_tracer::Mode;
use boundtrace_tracer::stats::MethodStats;
use serde::{Deserialize, Serialize};

/// The schema name and version.
pub const SCHEMA: &str = "boundtrace-stats/1";

/// A statistics report: the run's parameters and one entry per method.
///
/// `M` is `&[MethodStats]` when the command builds it and
/// `Vec<MethodJson>` as serialised ([`StatsJson`], the schema above); the
/// run fields are shared by both.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StatsReport<M> {
    /// [`SCHEMA`].
    pub schema: String,
    /// Scene name.
    pub scene: String,
    /// Primitive count.
    pub primitives: usize,
    /// Rays traced.
    pub rays: usize,
    /// Seed of the rays.
    pub ray_seed: u64,
    /// Rays with a reference root.
    pub reference_hits: usize,
    /// Time of the dense reference in seconds.
    pub reference_seconds: f64,
    /// The tracer's ε.
    pub eps: f64,
    /// The tracer's step limit.
    pub max_steps: u32,
    /// One entry per method.
    pub methods: M,
}

/// The report as serialised (the schema above).
pub type StatsJson = StatsReport<Vec<MethodJson>>;

/// One method's statistics.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MethodJson {
    /// Method name.
    pub method: String,
    /// `opaque` or `transparent`.
    pub mode: String,
    /// Rays in the set.
    pub rays: usize,
    /// Rays the method does not support on this field.
    pub unsupported: usize,
    /// Rays finished.
    pub finished: usize,
    /// Rays that hit the step limit.
    pub max_steps: usize,
    /// Rays that filled the root buffer.
    pub buffer_full: usize,
    /// Steps per ray.
    pub steps: StepsJson,
    /// Mean field evaluations per ray.
    pub field_evals_mean: f64,
    /// Mean bound evaluations per ray.
    pub bound_evals_mean: f64,
    /// Mean wall time per ray in nanoseconds.
    pub ns_per_ray: f64,
    /// Rays agreeing with the reference.
    pub agree: usize,
    /// Rays with a missed root.
    pub missed: usize,
    /// Rays with a spurious root.
    pub spurious: usize,
    /// Rays with a root far from every reference root.
    pub far: usize,
    /// Rays that stepped past a root (must be 0).
    pub stepped_past: usize,
    /// Rays that gave up before a root.
    pub gave_up: usize,
    /// Rays with a root of the wrong side (informational).
    pub wrong_side: usize,
}

/// Steps per ray.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StepsJson {
    /// Mean.
    pub mean: f64,
    /// Median.
    pub median: f64,
    /// Maximum.
    pub max: u32,
}

impl From<&MethodStats> for MethodJson {
    fn from(m: &MethodStats) -> Self {
        MethodJson {
            method: m.method.name().into(),
            mode: match m.mode {
                Mode::Opaque => "opaque",
                Mode::Transparent => "transparent",
            }
            .into(),
            rays: m.rays,
            unsupported: m.unsupported,
            finished: m.finished,
            max_steps: m.max_steps,
            buffer_full: m.buffer_full,
            steps: StepsJson {
                mean: m.steps_avg,
                median: m.steps_median,
                max: m.steps_max,
            },
            field_evals_mean: m.field_evals_avg,
            bound_evals_mean: m.bound_evals_avg,
            ns_per_ray: m.ns_per_ray,
            agree: m.agree,
            missed: m.missed,
            spurious: m.spurious,
            far: m.far,
            stepped_past: m.stepped_past,
            gave_up: m.gave_up,
            wrong_side: m.wrong_side,
        }
    }
}

impl<M> StatsReport<M> {
    /// The same run with other method entries.
    pub fn with_methods<N>(&self, methods: N) -> StatsReport<N> {
        StatsReport {
            schema: self.schema.clone(),
            scene: self.scene.clone(),
            primitives: self.primitives,
            rays: self.rays,
            ray_seed: self.ray_seed,
            reference_hits: self.reference_hits,
            reference_seconds: self.reference_seconds,
            eps: self.eps,
            max_steps: self.max_steps,
            methods,
        }
    }
}

/// The serialisable form.
pub fn to_value(r: &StatsReport<&[MethodStats]>) -> StatsJson {
    r.with_methods(r.methods.iter().map(MethodJson::from).collect())
}

/// Pretty JSON of the report.
pub fn to_json(r: &StatsReport<&[MethodStats]>) -> String {
    // plain data: serialisation cannot fail (non-finite floats become null)
    serde_json::to_string_pretty(&to_value(r)).unwrap_or_default()
}

/// Parses a report.
///
/// # Errors
/// Malformed JSON or a document that does not follow the schema.
pub fn parse(text: &str) -> Result<StatsJson, serde_json::Error> {
    serde_json::from_str(text)
}
