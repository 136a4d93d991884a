//! Interval soundness, side by side: our outward-rounded
//! [`Interval<f32>`](boundtrace_ia_core::Interval) against fidget's `f32`
//! [`Interval`](fidget::types::Interval) (which rounds to nearest), on
//! random input intervals, each result checked for containment of the
//! `f64` values of the operation at the inputs' endpoints, at the
//! operation's critical points inside them and at random interior points.
//!
//! Why `f64` is a fair reference: every `f32` is an `f64`, and `+ − × ÷ √`
//! are correctly rounded in `f64`, so for a true value `v` and an `f32`
//! bound `b ≥ v`, `round₆₄(v) ≤ b` (rounding is monotone): a sound bound is
//! never reported as a failure (the transcendental functions of `std` are
//! not correctly rounded in `f64`, but within an `f64` ulp, far below the
//! `f32` ulp that separates a bound from the value it rounds). A failure
//! found this way is a real one; the count can only *under*-state the
//! failures (a value that differs from a bound by less than an `f64`
//! ulp).
//!
//! fidget returns the `NaN` interval for inputs partly outside an
//! operation's domain (`√` of an interval containing negatives, `ln`/`1/x`/
//! `÷` across zero); these are counted as "no bound", not as failures.

use boundtrace_ia_core::Interval as Ours;
use fidget::types::Interval as Theirs;

/// The operations compared.
pub const OPS: &[&str] = &[
    "add", "sub", "mul", "div", "recip", "sqrt", "square", "exp", "ln", "sin", "cos", "abs", "min",
    "max", "neg",
];

/// Containment counts of one operation.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct OpCounts {
    /// Random input intervals (pairs for binary operations).
    pub samples: u64,
    /// Reference values checked per implementation.
    pub checks: u64,
    /// Input intervals where our result missed a reference value.
    pub ours_failures: u64,
    /// Input intervals where fidget's result missed a reference value.
    pub fidget_failures: u64,
    /// Input intervals where fidget returned the `NaN` interval (no bound).
    pub fidget_nan: u64,
    /// Input intervals where our result was empty although a reference
    /// value existed (counted in `ours_failures` too).
    pub ours_empty: u64,
    /// The first case fidget failed: inputs, result, a missed reference.
    pub fidget_example: Option<String>,
    /// The first case we failed (there must be none).
    pub ours_example: Option<String>,
}

/// A tiny deterministic PRNG (splitmix64).
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator from `seed`.
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in `[0, 1)`.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in `[a, b)`.
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unit()
    }
}

/// `x` moved by `n` ulps (`n` may be negative), staying finite.
fn ulps(x: f32, n: i32) -> f32 {
    let mut y = x;
    for _ in 0..n.unsigned_abs() {
        y = if n > 0 { y.next_up() } else { y.next_down() };
    }
    if y.is_finite() { y } else { x }
}

/// A random finite `f32` interval `[lo, hi]` of one of several shapes:
/// moderate values, wide magnitude ranges, narrow (a few ulps), points,
/// and intervals near multiples of π/2 (the trigonometric extrema).
pub fn random_interval(rng: &mut Rng, positive: bool) -> (f32, f32) {
    let kind = rng.next_u64() % 6;
    let sign = |rng: &mut Rng| {
        if positive || rng.next_u64().is_multiple_of(2) {
            1.0
        } else {
            -1.0
        }
    };
    let mag = |rng: &mut Rng, lo: f64, hi: f64| 10f64.powf(rng.range(lo, hi));
    let (a, b) = match kind {
        0 => {
            let a = rng.range(-10.0, 10.0) as f32;
            let b = rng.range(-10.0, 10.0) as f32;
            (a, b)
        }
        1 => {
            let a = (sign(rng) * mag(rng, -6.0, 6.0)) as f32;
            let b = (sign(rng) * mag(rng, -6.0, 6.0)) as f32;
            (a, b)
        }
        2 => {
            let a = (sign(rng) * mag(rng, -3.0, 3.0)) as f32;
            (a, ulps(a, (rng.next_u64() % 5) as i32))
        }
        3 => {
            let a = (sign(rng) * mag(rng, -2.0, 2.0)) as f32;
            (a, a)
        }
        4 => {
            // near k·π/2
            let k = (rng.next_u64() % 2001) as f64 - 1000.0;
            let c = (k * core::f64::consts::FRAC_PI_2) as f32;
            let w = mag(rng, -7.0, 0.0) as f32;
            (c - w * rng.unit() as f32, c + w * rng.unit() as f32)
        }
        _ => {
            let a = rng.range(-100.0, 100.0) as f32;
            (a, a + mag(rng, -6.0, 1.0) as f32)
        }
    };
    let (mut lo, mut hi) = if a <= b { (a, b) } else { (b, a) };
    if positive {
        lo = lo.abs();
        hi = hi.abs();
        if lo > hi {
            core::mem::swap(&mut lo, &mut hi);
        }
    }
    (lo, hi)
}

/// Points of `[lo, hi]` (in `f64`) where a unary reference is evaluated:
/// the endpoints, `extra` (critical points inside), and random points.
fn unary_points(rng: &mut Rng, lo: f32, hi: f32, extra: &[f64], out: &mut Vec<f64>) {
    out.clear();
    let (l, h) = (lo as f64, hi as f64);
    out.extend([l, h]);
    out.extend(extra.iter().copied().filter(|x| *x >= l && *x <= h));
    for _ in 0..4 {
        out.push((l + (h - l) * rng.unit()).clamp(l, h));
    }
}

/// Multiples `c + k·π` of `[lo, hi]` (at most 4 of them; `f64`).
fn periodic_points(lo: f32, hi: f32, c: f64) -> Vec<f64> {
    let pi = core::f64::consts::PI;
    let k0 = ((lo as f64 - c) / pi).ceil();
    (0..4)
        .map(|i| c + (k0 + i as f64) * pi)
        .filter(|x| *x <= hi as f64)
        .collect()
}

/// `true` when `[lo, hi]` (an `f32` result, widened to `f64`) contains `v`.
fn holds(lo: f32, hi: f32, v: f64) -> bool {
    (lo as f64) <= v && v <= (hi as f64)
}

/// The first finite reference value outside `[lo, hi]`, if any.
fn check(lo: f32, hi: f32, refs: &[f64]) -> Option<f64> {
    refs.iter()
        .copied()
        .find(|v| v.is_finite() && !holds(lo, hi, *v))
}

/// A failing case for the report.
fn describe(
    op: &str,
    a: (f32, f32),
    b: Option<(f32, f32)>,
    res: (f32, f32),
    missed: f64,
) -> String {
    let input = match b {
        Some(b) => format!("[{:e}, {:e}] {op} [{:e}, {:e}]", a.0, a.1, b.0, b.1),
        None => format!("{op}([{:e}, {:e}])", a.0, a.1),
    };
    format!(
        "`{input}` → `[{:e}, {:e}]` misses `{missed:e}`",
        res.0, res.1
    )
}

/// Runs `samples` random cases of operation `op` (one of [`OPS`]) with
/// `seed`.
///
/// # Errors
/// An unknown operation name.
pub fn run_op(op: &str, samples: u64, seed: u64) -> Result<OpCounts, String> {
    if !OPS.contains(&op) {
        return Err(format!(
            "unknown interval operation `{op}`; expected one of {}",
            OPS.join(", ")
        ));
    }
    let mut rng = Rng::new(seed ^ op.bytes().fold(0u64, |h, b| h.wrapping_mul(31) ^ b as u64));
    let mut c = OpCounts::default();
    let mut pts = Vec::new();
    let mut refs = Vec::new();
    let binary = matches!(op, "add" | "sub" | "mul" | "div" | "min" | "max");
    let positive = matches!(op, "sqrt" | "ln");
    for _ in 0..samples {
        c.samples += 1;
        let (alo, ahi) = random_interval(&mut rng, positive);
        let (blo, bhi) = random_interval(&mut rng, false);
        refs.clear();
        let (ours, theirs): (Ours<f32>, Theirs) = if binary {
            let (a, b) = (Ours::new(alo, ahi), Ours::new(blo, bhi));
            let (fa, fb) = (Theirs::new(alo, ahi), Theirs::new(blo, bhi));
            let mut xs = vec![alo as f64, ahi as f64];
            let mut ys = vec![blo as f64, bhi as f64];
            for _ in 0..3 {
                xs.push(
                    (alo as f64 + (ahi as f64 - alo as f64) * rng.unit())
                        .clamp(alo as f64, ahi as f64),
                );
                ys.push(
                    (blo as f64 + (bhi as f64 - blo as f64) * rng.unit())
                        .clamp(blo as f64, bhi as f64),
                );
            }
            for &x in &xs {
                for &y in &ys {
                    let v = match op {
                        "add" => x + y,
                        "sub" => x - y,
                        "mul" => x * y,
                        "div" if y != 0.0 => x / y,
                        "min" => x.min(y),
                        "max" => x.max(y),
                        _ => f64::NAN,
                    };
                    refs.push(v);
                }
            }
            match op {
                "add" => (a + b, fa + fb),
                "sub" => (a - b, fa - fb),
                "mul" => (a * b, fa * fb),
                "div" => (a / b, fa / fb),
                "min" => (a.min(b), fa.min_choice(fb).0),
                _ => (a.max(b), fa.max_choice(fb).0),
            }
        } else {
            let a = Ours::new(alo, ahi);
            let fa = Theirs::new(alo, ahi);
            let extra: Vec<f64> = match op {
                "sin" => periodic_points(alo, ahi, core::f64::consts::FRAC_PI_2),
                "cos" => periodic_points(alo, ahi, 0.0),
                "square" | "abs" => vec![0.0],
                _ => Vec::new(),
            };
            unary_points(&mut rng, alo, ahi, &extra, &mut pts);
            for &x in &pts {
                let v = match op {
                    "recip" if x != 0.0 => 1.0 / x,
                    "sqrt" if x >= 0.0 => x.sqrt(),
                    "square" => x * x,
                    "exp" => x.exp(),
                    "ln" if x > 0.0 => x.ln(),
                    "sin" => x.sin(),
                    "cos" => x.cos(),
                    "abs" => x.abs(),
                    "neg" => -x,
                    _ => f64::NAN,
                };
                refs.push(v);
            }
            match op {
                "recip" => (a.recip(), fa.recip()),
                "sqrt" => (a.sqrt(), fa.sqrt()),
                "square" => (a.sqr(), fa.square()),
                "exp" => (a.exp(), fa.exp()),
                "ln" => (a.ln(), fa.ln()),
                "sin" => (a.sin(), fa.sin()),
                "cos" => (a.cos(), fa.cos()),
                "abs" => (a.abs(), fa.abs()),
                _ => (-a, -fa),
            }
        };
        c.checks += refs.iter().filter(|v| v.is_finite()).count() as u64;
        let any_ref = refs.iter().any(|v| v.is_finite());
        let b = binary.then_some((blo, bhi));
        if ours.is_empty() {
            if any_ref {
                c.ours_failures += 1;
                c.ours_empty += 1;
                c.ours_example.get_or_insert_with(|| {
                    describe(op, (alo, ahi), b, (f32::NAN, f32::NAN), refs[0])
                });
            }
        } else if let Some(v) = check(ours.lo(), ours.hi(), &refs) {
            c.ours_failures += 1;
            c.ours_example
                .get_or_insert_with(|| describe(op, (alo, ahi), b, (ours.lo(), ours.hi()), v));
        }
        if theirs.has_nan() {
            c.fidget_nan += 1;
        } else if let Some(v) = check(theirs.lower(), theirs.upper(), &refs) {
            c.fidget_failures += 1;
            c.fidget_example.get_or_insert_with(|| {
                describe(op, (alo, ahi), b, (theirs.lower(), theirs.upper()), v)
            });
        }
    }
    Ok(c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ours_is_sound_on_a_small_sample() {
        for op in OPS {
            let c = run_op(op, 2000, 7).unwrap();
            assert_eq!(c.ours_failures, 0, "{op}: {c:?}");
            assert!(c.checks > c.samples, "{op}");
        }
    }

    #[test]
    fn the_reference_catches_round_to_nearest() {
        // fidget's `+` rounds to nearest: some sum must miss its reference
        let c = run_op("add", 5000, 3).unwrap();
        assert!(c.fidget_failures > 0, "{c:?}");
        assert!(c.fidget_example.is_some() && c.ours_example.is_none());
    }

    #[test]
    fn unknown_ops_are_refused() {
        assert!(run_op("tanh", 1, 1).is_err());
    }
}
