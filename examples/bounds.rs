//! Interval vs revised affine bounds of small ray-field expressions.
//!
//! Run with `cargo run --release --example bounds`. For each expression of the
//! ray parameter `t` it prints, on `t ∈ [t0, t1]` and on its halves and
//! quarters, the interval-arithmetic range, the revised-affine-arithmetic
//! range and a dense-sampling estimate of the true range. Both bounds must
//! contain the samples (a line is flagged `NOT ENCLOSED` otherwise). Neither
//! method always wins: interval arithmetic is exact for expressions where
//! each variable occurs once per monotone piece (`sqr` knows its argument),
//! while affine forms keep the correlation between repeated occurrences of
//! `t` (`t² − t` in the Cauchy example) and win there as the range shrinks
//! (the dependency problem, thesis Part II §2.2.2).

use boundtrace::ia_core::{Affine, Interval};

/// An expression evaluated three ways: plain `f64`, `Interval`, `Affine`.
struct Expr {
    name: &'static str,
    plain: fn(f64) -> f64,
    interval: fn(Interval<f64>) -> Interval<f64>,
    affine: fn(Affine<f64, 1>) -> Affine<f64, 1>,
    domain: (f64, f64),
}

fn sampled_range(f: fn(f64) -> f64, t0: f64, t1: f64) -> (f64, f64) {
    let n = 10_000;
    (0..=n)
        .map(|i| f(t0 + (t1 - t0) * i as f64 / n as f64))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        })
}

fn main() {
    let exprs = [
        Expr {
            // Sphere SDF along a ray: o = (−2, 0.3, 0), d = (1, 0, 0), radius 1.
            name: "sphere SDF  sqrt((t-2)^2 + 0.09) - 1",
            plain: |t| ((t - 2.0) * (t - 2.0) + 0.09).sqrt() - 1.0,
            interval: |t| ((t - 2.0).sqr() + 0.09).sqrt() - 1.0,
            affine: |t| ((t - 2.0).sqr() + 0.09).sqrt() - 1.0,
            domain: (0.0, 4.0),
        },
        Expr {
            // A Gaussian blob minus an iso-value, along the same ray.
            name: "blob        exp(-((t-2)^2 + 0.09)) - 0.5",
            plain: |t| (-((t - 2.0) * (t - 2.0) + 0.09)).exp() - 0.5,
            interval: |t| (-((t - 2.0).sqr() + 0.09)).exp() - 0.5,
            affine: |t| (-((t - 2.0).sqr() + 0.09)).exp() - 0.5,
            domain: (0.0, 4.0),
        },
        Expr {
            // Cauchy-kernel field 1/(1 + d²) with a polynomial in t.
            name: "cauchy      1/(1 + (t^2 - t)^2) - 0.9",
            plain: |t| 1.0 / (1.0 + (t * t - t) * (t * t - t)) - 0.9,
            interval: |t| (1.0 + (t.sqr() - t).sqr()).recip() - 0.9,
            affine: |t| (1.0 + (t.sqr() - t).sqr()).recip() - 0.9,
            domain: (0.0, 1.5),
        },
    ];

    for e in &exprs {
        println!("{}", e.name);
        println!(
            "  {:>16}  {:>26}  {:>26}  {:>26}",
            "t range", "interval", "affine", "sampled (true ≈)"
        );
        for depth in 0..3 {
            let pieces = 1 << depth;
            let (a, b) = e.domain;
            for k in 0..pieces {
                let t0 = a + (b - a) * k as f64 / pieces as f64;
                let t1 = a + (b - a) * (k + 1) as f64 / pieces as f64;
                let t = Interval::new(t0, t1);
                let ia = (e.interval)(t);
                let aa = (e.affine)(Affine::variable(t, 0)).to_interval();
                let (lo, hi) = sampled_range(e.plain, t0, t1);
                let sound = ia.lo() <= lo && hi <= ia.hi() && aa.lo() <= lo && hi <= aa.hi();
                println!(
                    "  [{:>6.3}, {:>6.3}]  [{:>11.5}, {:>11.5}]  [{:>11.5}, {:>11.5}]  [{:>11.5}, {:>11.5}]{}",
                    t0,
                    t1,
                    ia.lo(),
                    ia.hi(),
                    aa.lo(),
                    aa.hi(),
                    lo,
                    hi,
                    if sound { "" } else { "  NOT ENCLOSED" }
                );
            }
        }
        println!();
    }
}
