//! Cost of `Interval` and `Affine` operations relative to plain float ops.
//!
//! Each benchmark applies one operation to 1024 pre-generated operands, so
//! the time is per 1024 operations; compare the `float`, `interval` and
//! `affine` lines of one group (one run, same machine) as ratios. Run with
//! `cargo bench --bench ia_ops`, or e.g. `cargo bench --bench ia_ops -- add`
//! for one group.

use boundtrace::ia_core::{Affine, Interval};
use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;

mod common;
use common::values;

type A = Affine<f64, 1>;

struct Inputs {
    x: Vec<f64>,
    y: Vec<f64>,
    xi: Vec<Interval<f64>>,
    yi: Vec<Interval<f64>>,
    xa: Vec<A>,
    ya: Vec<A>,
}

fn inputs(lo: f64, hi: f64) -> Inputs {
    let x = values(1, lo, hi);
    let y = values(2, lo, hi);
    let w = values(3, 0.0, 0.1);
    let iv = |v: &[f64]| -> Vec<Interval<f64>> {
        v.iter()
            .zip(&w)
            .map(|(&a, &d)| Interval::new(a, a + d))
            .collect()
    };
    let (xi, yi) = (iv(&x), iv(&y));
    let xa = xi.iter().map(|&i| A::variable(i, 0)).collect();
    let ya = yi.iter().map(|&i| A::variable(i, 0)).collect();
    Inputs {
        x,
        y,
        xi,
        yi,
        xa,
        ya,
    }
}

macro_rules! binary {
    ($c:expr, $name:literal, $inp:expr, $op:tt) => {{
        let inp = &$inp;
        let mut g = $c.benchmark_group($name);
        g.bench_function("float", |b| {
            b.iter(|| {
                let mut acc = 0.0;
                for (x, y) in inp.x.iter().zip(&inp.y) {
                    acc += black_box(*x) $op black_box(*y);
                }
                acc
            })
        });
        g.bench_function("interval", |b| {
            b.iter(|| {
                let mut acc = 0.0;
                for (x, y) in inp.xi.iter().zip(&inp.yi) {
                    acc += (black_box(*x) $op black_box(*y)).hi();
                }
                acc
            })
        });
        g.bench_function("affine", |b| {
            b.iter(|| {
                let mut acc = 0.0;
                for (x, y) in inp.xa.iter().zip(&inp.ya) {
                    acc += (black_box(*x) $op black_box(*y)).center();
                }
                acc
            })
        });
        g.finish();
    }};
}

macro_rules! unary {
    ($c:expr, $name:literal, $inp:expr, $f:expr, $fi:expr, $fa:expr) => {{
        let inp = &$inp;
        let mut g = $c.benchmark_group($name);
        g.bench_function("float", |b| {
            b.iter(|| inp.x.iter().map(|&x| $f(black_box(x))).sum::<f64>())
        });
        g.bench_function("interval", |b| {
            b.iter(|| inp.xi.iter().map(|&x| $fi(black_box(x)).hi()).sum::<f64>())
        });
        if let Some(fa) = $fa {
            g.bench_function("affine", |b| {
                b.iter(|| {
                    inp.xa
                        .iter()
                        .map(|&x| fa(black_box(x)).center())
                        .sum::<f64>()
                })
            });
        }
        g.finish();
    }};
}

fn bench_ops(c: &mut Criterion) {
    let mixed = inputs(-4.0, 4.0);
    let pos = inputs(0.5, 4.0);
    binary!(c, "add", mixed, +);
    binary!(c, "mul", mixed, *);
    binary!(c, "div", pos, /);
    unary!(c, "sqr", mixed, |x: f64| x * x, Interval::sqr, Some(A::sqr));
    unary!(c, "sqrt", pos, f64::sqrt, Interval::sqrt, Some(A::sqrt));
    unary!(c, "exp", mixed, f64::exp, Interval::exp, Some(A::exp));
    unary!(c, "ln", pos, f64::ln, Interval::ln, Some(A::ln));
    unary!(
        c,
        "recip",
        pos,
        |x: f64| 1.0 / x,
        Interval::recip,
        Some(A::recip)
    );
    unary!(c, "sin", mixed, f64::sin, Interval::sin, None::<fn(A) -> A>);
    unary!(c, "cos", mixed, f64::cos, Interval::cos, None::<fn(A) -> A>);
    unary!(
        c,
        "powi3",
        mixed,
        |x: f64| x.powi(3),
        |x: Interval<f64>| x.powi(3),
        None::<fn(A) -> A>
    );
}

criterion_group!(benches, bench_ops);
criterion_main!(benches);
