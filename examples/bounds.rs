//! Interval, revised affine and forward linear/quadratic bounds of small
//! ray-field expressions.
//!
//! Run with `cargo run --release --example bounds`. Each expression of the
//! ray parameter `t` is written once, generically over
//! [`FieldNum`](boundtrace::inclusion::FieldNum), and evaluated with every
//! number type. On `t ∈ [t0, t1]` and on its halves and quarters the example
//! prints the range enclosed by interval arithmetic, revised affine
//! arithmetic, forward linear and forward quadratic bounds (the latter two on
//! their validity interval `[t0, t0 + h]`, marked `*` when an operation
//! shortened it), a dense-sampling estimate of the true range, and the safe
//! marching step of the quadratic bound (paper Alg. 1: never past the first
//! root). Every bound must contain the samples (a line is flagged
//! `NOT ENCLOSED` otherwise).

use boundtrace::ia_core::{Affine, Interval};
use boundtrace::inclusion::{FieldNum, ForwardLinear, ForwardQuadratic};

/// Sphere SDF along a ray: o = (−2, 0.3, 0), d = (1, 0, 0), radius 1.
fn sphere<N: FieldNum<f64>>(t: N) -> N {
    ((t - 2.0).sqr() + 0.09).sqrt() - 1.0
}

/// A Gaussian blob minus an iso-value, along the same ray (positive outside).
fn blob<N: FieldNum<f64>>(t: N) -> N {
    -(-((t - 2.0).sqr() + 0.09)).exp() + 0.5
}

/// Cauchy-kernel field `1/(1 + d²)` with a polynomial in `t`.
fn cauchy<N: FieldNum<f64>>(t: N) -> N {
    -((t.sqr() - t).sqr() + 1.0).recip() + 0.9
}

fn sampled_range(f: fn(f64) -> f64, t0: f64, t1: f64) -> (f64, f64) {
    let n = 10_000;
    (0..=n)
        .map(|i| f(t0 + (t1 - t0) * i as f64 / n as f64))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        })
}

fn show(iv: Interval<f64>) -> String {
    format!("[{:>8.4}, {:>8.4}]", iv.lo(), iv.hi())
}

/// Evaluates one expression with every number type on `[t0, t1]`.
macro_rules! row {
    ($f:ident, $t0:expr, $t1:expr) => {{
        let (t0, t1): (f64, f64) = ($t0, $t1);
        let ia: Interval<f64> = $f(Interval::new(t0, t1));
        let aa: Affine<f64, 1> = $f(FieldNum::ray_param(t0, t1));
        let aa = aa.to_interval();
        let fl: ForwardLinear<f64> = $f(ForwardLinear::ray_param(t0, t1));
        let fq: ForwardQuadratic<f64> = $f(ForwardQuadratic::ray_param(t0, t1));
        let (lo, hi) = sampled_range($f::<f64>, t0, t1);
        let (llo, lhi) = sampled_range($f::<f64>, t0, fl.validity_end(t0));
        let (qlo, qhi) = sampled_range($f::<f64>, t0, fq.validity_end(t0));
        let encloses = |b: Interval<f64>, lo: f64, hi: f64| b.lo() <= lo && hi <= b.hi();
        let sound = encloses(ia, lo, hi)
            && encloses(aa, lo, hi)
            && encloses(fl.range(), llo, lhi)
            && encloses(fq.range(), qlo, qhi);
        let mark = |h: f64| if h < t1 - t0 { '*' } else { ' ' };
        println!(
            "  [{:>5.2}, {:>5.2}]  {}  {}  {}{}  {}{}  {}  {:>9.5}{}",
            t0,
            t1,
            show(ia),
            show(aa),
            show(fl.range()),
            mark(fl.validity()),
            show(fq.range()),
            mark(fq.validity()),
            show(Interval::new(lo, hi)),
            fq.safe_step(),
            if sound { "" } else { "  NOT ENCLOSED" }
        );
    }};
}

fn main() {
    macro_rules! expr {
        ($name:expr, $f:ident, $a:expr, $b:expr) => {{
            println!("{}", $name);
            println!(
                "  {:>14}  {:>20}  {:>20}  {:>21}  {:>21}  {:>20}  {:>9}",
                "t range",
                "interval",
                "affine",
                "forward linear",
                "forward quadratic",
                "sampled (true ≈)",
                "q. step"
            );
            for depth in 0..3 {
                let pieces = 1 << depth;
                for k in 0..pieces {
                    let t0 = $a + ($b - $a) * k as f64 / pieces as f64;
                    let t1 = $a + ($b - $a) * (k + 1) as f64 / pieces as f64;
                    row!($f, t0, t1);
                }
            }
            println!();
        }};
    }
    expr!("sphere SDF  sqrt((t-2)^2 + 0.09) - 1", sphere, 0.0, 4.0);
    expr!("blob        0.5 - exp(-((t-2)^2 + 0.09))", blob, 0.0, 4.0);
    expr!("cauchy      0.9 - 1/(1 + (t^2 - t)^2)", cauchy, 0.0, 1.5);
    println!("* = validity interval shortened by an operation (paper §4.2)");
}
