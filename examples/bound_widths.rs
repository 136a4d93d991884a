//! How tight are the bounds? Interval, revised affine (`N = 1`), forward
//! linear and forward quadratic bounds of four reference fields along random
//! rays, compared with the true range found by dense sampling.
//!
//! Run with `cargo run --release --example bound_widths`; it prints a
//! markdown report. The fields (forward-inclusion paper eqs. 6–9, thesis
//! eqs. 1.6–1.9) are evaluated at `p = o + t·d`, each written once over
//! [`FieldNum`]:
//!
//! 1. compact polynomial blob `max(1 − d²/R², 0)³ − iso` (`R = 1`, `iso = ½`);
//! 2. Gaussian blob `exp(−s·d²/R²) − iso` (`s = 2`, `R = 1`, `iso = ½`);
//! 3. one HRBF term with `φ(r) = r³`: `α r³ + 3 r β·(p − c)` (eq. 9);
//! 4. the sharp union `max(g₁, g₂) − iso` of two Gaussian blobs.
//!
//! For every field and interval length, a few thousand intervals
//! `[t₀, t₀ + len]` on random rays through the blobs are bounded with each
//! number type. The forward types bound `f` only on their validity interval
//! `[t₀, t₀ + h]` (`h ≤ len` when an operation shortened it); their true
//! range is sampled on that same sub-interval. Every sample is also checked
//! against every enclosure (pointwise against `bounds_at(τ)` for the forward
//! types): a sample outside is a soundness violation and is reported with
//! a reproduction.

use boundtrace::ia_core::{Affine, Interval};
use boundtrace::inclusion::{Composition, FieldNum, ForwardLinear, ForwardQuadratic, Ray};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Intervals per (field, length).
const INTERVALS: usize = 3000;
/// Samples of the true range per interval.
const SAMPLES: usize = 2000;
/// Interval lengths along the (unit-speed) rays.
const LENGTHS: [f64; 3] = [0.05, 0.2, 0.8];
/// Intervals whose true range is narrower than this are skipped.
const MIN_TRUE_WIDTH: f64 = 1e-12;
/// Relative slack of the soundness check.
const SLACK: f64 = 1e-9;
/// Violations printed in full.
const MAX_REPORTED: usize = 10;

/// Iso-value of the blobs.
const ISO: f64 = 0.5;
/// Gaussian sharpness `s`.
const S: f64 = 2.0;
/// Blob radius `R`.
const R: f64 = 1.0;
/// Centre of the single blobs and of the HRBF term.
const C0: [f64; 3] = [0.0; 3];
/// HRBF weight `α`.
const ALPHA: f64 = 1.0;
/// HRBF gradient weight `β`.
const BETA: [f64; 3] = [0.4, -0.3, 0.2];
/// Centre of the first blob of the union.
const C1: [f64; 3] = [-0.45, 0.0, 0.0];
/// Centre of the second blob of the union.
const C2: [f64; 3] = [0.45, 0.15, 0.0];
/// Distance from the ray origin to its target point.
const ORIGIN_DIST: f64 = 3.0;
/// Radius of the ball the target points are drawn from.
const TARGET_RADIUS: f64 = 1.0;
/// Half-width of the window of `t` around the target in which `t₀` lies.
const WINDOW: f64 = 1.5;

/// The reference fields.
#[derive(Clone, Copy, Debug)]
enum Func {
    Compact,
    Gauss,
    Hrbf,
    MaxGauss,
}

impl Func {
    const ALL: [Func; 4] = [Func::Compact, Func::Gauss, Func::Hrbf, Func::MaxGauss];

    fn name(self) -> &'static str {
        match self {
            Func::Compact => "compact blob  max(1 − d²/R², 0)³ − ½",
            Func::Gauss => "Gaussian blob  exp(−2 d²/R²) − ½",
            Func::Hrbf => "HRBF term  α r³ + 3 r β·(p − c),  φ(r) = r³",
            Func::MaxGauss => "union  max(g₁, g₂) − ½ of two Gaussian blobs",
        }
    }

    fn short(self) -> &'static str {
        match self {
            Func::Compact => "compact",
            Func::Gauss => "gauss",
            Func::Hrbf => "hrbf",
            Func::MaxGauss => "max-gauss",
        }
    }

    /// The field at `p = o + t·d` along `ray`, for the ray parameter `t`
    /// given in the number type `N` (usually `N::ray_param(t0, t1)`).
    fn eval<N: FieldNum<f64>>(self, ray: &Ray<f64>, t: N) -> N {
        let p = [0, 1, 2].map(|i| t * ray.dir[i] + ray.origin[i]);
        match self {
            Func::Compact => {
                (dist2(&p, C0) * (1.0 / (R * R)))
                    .one_minus_clamped()
                    .powi(3)
                    - ISO
            }
            Func::Gauss => gauss(&p, C0) - ISO,
            Func::Hrbf => {
                let x = [0, 1, 2].map(|i| p[i] - C0[i]);
                let r = (x[0].sqr() + x[1].sqr() + x[2].sqr()).sqrt();
                let dot = x[0] * BETA[0] + x[1] * BETA[1] + x[2] * BETA[2];
                r.powi(3) * ALPHA + r * dot * 3.0
            }
            Func::MaxGauss => gauss(&p, C1).max(gauss(&p, C2)) - ISO,
        }
    }
}

/// `|p − c|²`.
fn dist2<N: FieldNum<f64>>(p: &[N; 3], c: [f64; 3]) -> N {
    (p[0] - c[0]).sqr() + (p[1] - c[1]).sqr() + (p[2] - c[2]).sqr()
}

/// `exp(−s·|p − c|²/R²)`.
fn gauss<N: FieldNum<f64>>(p: &[N; 3], c: [f64; 3]) -> N {
    (-(dist2(p, c) * (S / (R * R)))).exp()
}

/// xorshift64* PRNG.
struct Rng(u64);

impl Rng {
    fn new(seed: u64) -> Self {
        Self(seed.max(1))
    }

    fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// Uniform in `[0, 1)`.
    fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in the unit ball (rejection sampling).
    fn in_ball(&mut self) -> [f64; 3] {
        loop {
            let v = [0; 3].map(|_| 2.0 * self.uniform() - 1.0);
            let n2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
            if n2 <= 1.0 && n2 > 1e-6 {
                return v;
            }
        }
    }

    /// Uniform on the unit sphere.
    fn unit(&mut self) -> [f64; 3] {
        let v = self.in_ball();
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        v.map(|x| x / n)
    }
}

/// The bound types compared.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Interval,
    Affine,
    Linear,
    QuadRelaxMax,
    QuadValidity,
}

impl Kind {
    const ALL: [Kind; 5] = [
        Kind::Interval,
        Kind::Affine,
        Kind::Linear,
        Kind::QuadRelaxMax,
        Kind::QuadValidity,
    ];

    fn name(self) -> &'static str {
        match self {
            Kind::Interval => "interval",
            Kind::Affine => "affine (N=1)",
            Kind::Linear => "forward linear",
            Kind::QuadRelaxMax => "forward quadratic (RelaxMax)",
            Kind::QuadValidity => "forward quadratic (ValidityInterval)",
        }
    }

    fn is_forward(self) -> bool {
        !matches!(self, Kind::Interval | Kind::Affine)
    }
}

/// One bound of `f` over `[t0, t0 + h]`.
#[derive(Clone, Copy)]
enum Bound {
    /// An enclosure of the range (interval or affine).
    Range(Interval<f64>),
    /// A forward bound (linear bounds are stored as quadratics).
    Forward(ForwardQuadratic<f64>),
}

impl Bound {
    /// The enclosure of `f` over the bound's own interval.
    fn range(&self) -> Interval<f64> {
        match self {
            Bound::Range(iv) => *iv,
            Bound::Forward(q) => q.range(),
        }
    }

    /// The enclosure of `f(t0 + tau)`.
    fn at(&self, tau: f64) -> Interval<f64> {
        match self {
            Bound::Range(iv) => *iv,
            Bound::Forward(q) => q.bounds_at(tau),
        }
    }
}

/// Per-type statistics of one (field, length).
#[derive(Default)]
struct Acc {
    /// Enclosure width / true width.
    ratio: Vec<f64>,
    /// Enclosure width / interval enclosure width (paired, same interval).
    vs_ia: Vec<f64>,
    /// `bounds_at(h).width()` / interval enclosure width.
    end_vs_ia: Vec<f64>,
    /// Intervals where this bound is wider than the interval enclosure.
    wider: usize,
    /// Intervals with `h` shorter than the full length.
    shortened: usize,
    /// Sum of `h / len`.
    h_frac: f64,
    /// Intervals counted.
    n: usize,
    /// Invalid bounds (undefined at `t₀`).
    invalid: usize,
}

/// A sample outside an enclosure.
struct Violation {
    func: Func,
    kind: Kind,
    ray: Ray<f64>,
    t0: f64,
    len: f64,
    tau: f64,
    value: f64,
    bound: Interval<f64>,
}

/// Results of one (field, length).
struct TaskResult {
    acc: Vec<Acc>,
    skipped: usize,
    samples_checked: u64,
    violations: u64,
    reported: Vec<Violation>,
}

/// Whether `v` lies outside `iv` by more than the slack.
fn outside(v: f64, iv: Interval<f64>) -> bool {
    if v.is_nan() {
        return false;
    }
    if iv.is_empty() {
        return true;
    }
    let s = SLACK * v.abs().max(1.0);
    v < iv.lo() - s || v > iv.hi() + s
}

/// Samples `f` on `[t0, t0 + h]`, checks every bound in `checks` at every
/// sample and returns the sampled `(min, max)`.
fn sample(
    func: Func,
    ray: &Ray<f64>,
    t0: f64,
    h: f64,
    checks: &[(Kind, Bound)],
    mut report: impl FnMut(Kind, f64, f64, Interval<f64>),
) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..SAMPLES {
        let tau = h * i as f64 / (SAMPLES - 1) as f64;
        let v = func.eval(ray, t0 + tau);
        lo = lo.min(v);
        hi = hi.max(v);
        for &(kind, b) in checks {
            let at = b.at(tau);
            if outside(v, at) {
                report(kind, tau, v, at);
            }
        }
    }
    // The whole-interval enclosures of the forward types, once per pass.
    for &(kind, b) in checks {
        if let Bound::Forward(_) = b {
            let r = b.range();
            for v in [lo, hi] {
                if outside(v, r) {
                    report(kind, h, v, r);
                }
            }
        }
    }
    (lo, hi)
}

fn run_task(func: Func, len: f64, seed: u64) -> TaskResult {
    let mut rng = Rng::new(seed);
    let mut acc: Vec<Acc> = Kind::ALL.iter().map(|_| Acc::default()).collect();
    let mut res_skipped = 0;
    let mut samples_checked = 0u64;
    let mut violations = 0u64;
    let mut reported = Vec::new();

    let centre = match func {
        Func::MaxGauss => [0, 1, 2].map(|i| 0.5 * (C1[i] + C2[i])),
        _ => C0,
    };
    for _ in 0..INTERVALS {
        // A ray from a point at distance ORIGIN_DIST through a random target
        // near the blobs; unit speed, so t measures distance.
        let b = rng.in_ball();
        let target = [0, 1, 2].map(|i| centre[i] + TARGET_RADIUS * b[i]);
        let u = rng.unit();
        let origin = [0, 1, 2].map(|i| target[i] + ORIGIN_DIST * u[i]);
        let ray = Ray::new(origin, u.map(|x| -x));
        let t0 = ORIGIN_DIST - WINDOW + rng.uniform() * (2.0 * WINDOW - len);
        let t1 = t0 + len;
        let full = ForwardQuadratic::<f64>::ray_param(t0, t1).validity();

        let ia = func.eval(&ray, Interval::ray_param(t0, t1));
        let aa = func.eval(&ray, <Affine<f64, 1>>::ray_param(t0, t1));
        let lin = func.eval(&ray, ForwardLinear::ray_param(t0, t1));
        let quad = |mode| func.eval(&ray, ForwardQuadratic::ray_param_with(t0, t1, mode));
        let bounds: [(Kind, Option<Bound>, f64); 5] = [
            (Kind::Interval, Some(Bound::Range(ia)), full),
            (Kind::Affine, Some(Bound::Range(aa.to_interval())), full),
            forward(Kind::Linear, lin.to_quadratic(), lin.is_valid()),
            {
                let q = quad(Composition::RelaxMax);
                forward(Kind::QuadRelaxMax, q, q.is_valid())
            },
            {
                let q = quad(Composition::ValidityInterval);
                forward(Kind::QuadValidity, q, q.is_valid())
            },
        ];

        let mut report = |kind: Kind, tau: f64, value: f64, bound: Interval<f64>| {
            violations += 1;
            if reported.len() < MAX_REPORTED {
                reported.push(Violation {
                    func,
                    kind,
                    ray,
                    t0,
                    len,
                    tau,
                    value,
                    bound,
                });
            }
        };

        // The full interval: interval, affine and the forward bounds that
        // kept the whole length; then each shortened forward bound on its
        // own validity interval.
        let full_checks: Vec<(Kind, Bound)> = bounds
            .iter()
            .filter(|&&(_, _, h)| h >= full)
            .filter_map(|&(k, b, _)| Some((k, b?)))
            .collect();
        let (lo, hi) = sample(func, &ray, t0, full, &full_checks, &mut report);
        samples_checked += (SAMPLES * full_checks.len()) as u64;
        let true_width = hi - lo;
        let own_true = bounds.map(|(kind, b, h)| match b {
            Some(b) if h < full => {
                let (l, u) = sample(func, &ray, t0, h, &[(kind, b)], &mut report);
                samples_checked += SAMPLES as u64;
                u - l
            }
            _ => true_width,
        });
        if true_width.is_nan() || true_width < MIN_TRUE_WIDTH {
            res_skipped += 1;
            continue;
        }
        let ia_width = ia.width();

        for ((a, &(kind, b, h)), own_true) in acc.iter_mut().zip(&bounds).zip(own_true) {
            let Some(b) = b else {
                a.invalid += 1;
                continue;
            };
            a.n += 1;
            let width = b.range().width();
            if own_true >= MIN_TRUE_WIDTH {
                a.ratio.push(width / own_true);
            }
            a.vs_ia.push(width / ia_width);
            if width > ia_width {
                a.wider += 1;
            }
            if kind.is_forward() {
                if h < full {
                    a.shortened += 1;
                }
                a.h_frac += h / full;
                a.end_vs_ia.push(b.at(h).width() / ia_width);
            }
        }
    }
    TaskResult {
        acc,
        skipped: res_skipped,
        samples_checked,
        violations,
        reported,
    }
}

/// A forward entry of the bound list: `None` when invalid.
fn forward(kind: Kind, q: ForwardQuadratic<f64>, valid: bool) -> (Kind, Option<Bound>, f64) {
    if valid {
        (kind, Some(Bound::Forward(q)), q.validity())
    } else {
        (kind, None, 0.0)
    }
}

/// Median of a sample (NaN when empty).
fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Mean of a sample (NaN when empty).
fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

/// A ratio with three significant-ish digits.
fn fmt(x: f64) -> String {
    if x.is_nan() {
        "–".to_string()
    } else if x.is_infinite() {
        "∞".to_string()
    } else if x >= 1000.0 {
        format!("{x:.2e}")
    } else if x >= 100.0 {
        format!("{x:.1}")
    } else {
        format!("{x:.3}")
    }
}

/// A percentage of `n`.
fn pct(k: usize, n: usize) -> String {
    if n == 0 {
        "–".to_string()
    } else {
        format!("{:.1}%", 100.0 * k as f64 / n as f64)
    }
}

fn main() {
    let start = std::time::Instant::now();
    let tasks: Vec<(Func, f64)> = Func::ALL
        .iter()
        .flat_map(|&f| LENGTHS.iter().map(move |&l| (f, l)))
        .collect();
    let results: Vec<Mutex<Option<TaskResult>>> = tasks.iter().map(|_| Mutex::new(None)).collect();
    let next = AtomicUsize::new(0);
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
    std::thread::scope(|scope| {
        for _ in 0..threads.min(tasks.len()) {
            scope.spawn(|| {
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    let Some(&(func, len)) = tasks.get(i) else {
                        break;
                    };
                    let seed = 0x9E37_79B9_7F4A_7C15u64.wrapping_mul(i as u64 + 1);
                    let r = run_task(func, len, seed);
                    *results[i].lock().unwrap() = Some(r);
                }
            });
        }
    });
    let mut results: Vec<TaskResult> = results
        .into_iter()
        .map(|m| m.into_inner().unwrap().unwrap())
        .collect();

    println!("# Bound widths along rays: interval vs affine vs forward linear/quadratic");
    println!();
    println!(
        "{INTERVALS} intervals `[t₀, t₀ + len]` per field and length, on random unit-speed rays \
         (xorshift64*, fixed seeds) from distance {ORIGIN_DIST} through a random point within \
         {TARGET_RADIUS} of the blobs, `t₀` uniform in `[{}, {} − len]`; true ranges by \
         {SAMPLES} samples. Intervals with a true range narrower than {MIN_TRUE_WIDTH:e} are \
         skipped.",
        ORIGIN_DIST - WINDOW,
        ORIGIN_DIST + WINDOW
    );
    println!();
    println!("Columns (per bound type):");
    println!();
    println!(
        "- **w/true**: enclosure width (`range()` for the forward types, over their own \
         `[t₀, t₀ + h]`) / sampled true width over the same interval; median and mean."
    );
    println!(
        "- **w/IA**: median over intervals of the paired ratio enclosure width / interval-\
         arithmetic width on the same interval (the forward types may cover only `h ≤ len`)."
    );
    println!("- **> IA**: share of intervals where the bound is wider than the interval bound.");
    println!(
        "- **short**: share with `h < len`; **h/len**: mean validity fraction (forward types)."
    );
    println!(
        "- **end/IA**: median of `bounds_at(h).width()` / interval-arithmetic width (forward \
         types)."
    );
    println!();
    println!(
        "Fields: compact `max(1 − d²/R², 0)³ − ½`, Gaussian `exp(−{S} d²/R²) − ½` (R = {R}), \
         HRBF `α r³ + 3 r β·(p − c)` with α = {ALPHA}, β = {BETA:?}, c = {C0:?}; union of Gaussians \
         at {C1:?} and {C2:?}. `ForwardQuadratic` is shown with both `Composition::RelaxMax` \
         (never shortens) and the default `ValidityInterval`."
    );
    for (fi, func) in Func::ALL.iter().enumerate() {
        println!();
        println!("## {}. {}", fi + 1, func.name());
        println!();
        println!(
            "| len | bound | n | w/true median | w/true mean | w/IA median | > IA | short | h/len | end/IA median |"
        );
        println!("|---|---|---|---|---|---|---|---|---|---|");
        for (li, &len) in LENGTHS.iter().enumerate() {
            let r = &mut results[fi * LENGTHS.len() + li];
            for (kind, a) in Kind::ALL.iter().zip(r.acc.iter_mut()) {
                let fwd = kind.is_forward();
                let mean_ratio = mean(&a.ratio);
                let med_ratio = median(&mut a.ratio);
                let med_vs = median(&mut a.vs_ia);
                let med_end = median(&mut a.end_vs_ia);
                let invalid = if a.invalid > 0 {
                    format!(" ({} invalid)", a.invalid)
                } else {
                    String::new()
                };
                println!(
                    "| {len} | {} | {}{invalid} | {} | {} | {} | {} | {} | {} | {} |",
                    kind.name(),
                    a.n,
                    fmt(med_ratio),
                    fmt(mean_ratio),
                    fmt(med_vs),
                    pct(a.wider, a.n),
                    if fwd {
                        pct(a.shortened, a.n)
                    } else {
                        "–".into()
                    },
                    if fwd {
                        fmt(a.h_frac / a.n as f64)
                    } else {
                        "–".into()
                    },
                    if fwd { fmt(med_end) } else { "–".into() },
                );
            }
            if r.skipped > 0 {
                println!(
                    "| {len} | *skipped (true width < {MIN_TRUE_WIDTH:e})* | {} | | | | | | | |",
                    r.skipped
                );
            }
        }
    }

    println!();
    println!("## Summary: median width relative to interval arithmetic");
    println!();
    println!(
        "Paired median of width / interval width; in brackets the ratio of the medians of \
         w/true (bound type's median w/true divided by interval's median w/true)."
    );
    println!();
    println!(
        "| field | len | affine / interval | linear / interval | quadratic (RelaxMax) / interval | quadratic (ValidityInterval) / interval |"
    );
    println!("|---|---|---|---|---|---|");
    for (fi, func) in Func::ALL.iter().enumerate() {
        for (li, &len) in LENGTHS.iter().enumerate() {
            let r = &mut results[fi * LENGTHS.len() + li];
            let ia_med = median(&mut r.acc[0].ratio);
            let cells: Vec<String> = r.acc[1..]
                .iter_mut()
                .map(|a| {
                    let paired = median(&mut a.vs_ia);
                    let of_medians = median(&mut a.ratio) / ia_med;
                    format!("{} ({})", fmt(paired), fmt(of_medians))
                })
                .collect();
            println!("| {} | {len} | {} |", func.short(), cells.join(" | "));
        }
    }

    let checked: u64 = results.iter().map(|r| r.samples_checked).sum();
    let violations: u64 = results.iter().map(|r| r.violations).sum();
    println!();
    println!("## Soundness check");
    println!();
    println!(
        "{checked} (sample, bound) pairs checked, slack {SLACK:e}·max(1, |f|): \
         **{violations} violations** (expected 0)."
    );
    for v in results.iter().flat_map(|r| &r.reported) {
        println!(
            "- {} / {}: ray o = {:?}, d = {:?}, t0 = {:?}, len = {}: f(t0 + {:?}) = {:?} \
             outside [{:?}, {:?}]",
            v.func.short(),
            v.kind.name(),
            v.ray.origin,
            v.ray.dir,
            v.t0,
            v.len,
            v.tau,
            v.value,
            v.bound.lo(),
            v.bound.hi()
        );
    }
    eprintln!("elapsed: {:.1} s", start.elapsed().as_secs_f64());
}
