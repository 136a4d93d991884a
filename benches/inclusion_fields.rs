//! Cost of evaluating one field with every `FieldNum` type, relative to plain
//! floats: a Gaussian blob, a compact blob and a sphere SDF along rays, each
//! written once generically.
//!
//! Each benchmark evaluates the field on 1024 pre-generated ray intervals
//! (time per 1024 evaluations); compare the lines of one group (one run, same
//! machine) as ratios. Run with `cargo bench --bench inclusion_fields`.

use boundtrace::ia_core::{Affine, Interval};
use boundtrace::inclusion::{FieldNum, ForwardLinear, ForwardQuadratic, Jet};
use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;

mod common;
use common::{LEN, values};

/// `|o + t·d − c|²` with `o = (−3, y, z)`, `d = (1, 0, 0)`, `c = 0`.
fn d2<N: FieldNum<f64>>(t: N, y: f64, z: f64) -> N {
    (t - 3.0).sqr() + (y * y + z * z)
}

fn gaussian<N: FieldNum<f64>>(t: N, y: f64, z: f64) -> N {
    -(-d2(t, y, z) * 2.0).exp() + 0.5
}

fn compact<N: FieldNum<f64>>(t: N, y: f64, z: f64) -> N {
    -d2(t, y, z).one_minus_clamped().powi(3) + 0.5
}

fn sphere<N: FieldNum<f64>>(t: N, y: f64, z: f64) -> N {
    d2(t, y, z).sqrt() - 1.0
}

/// Benchmarks one generic field with every number type.
macro_rules! bench_field {
    ($c:expr, $name:expr, $f:ident) => {{
        let t0 = values(1, 0.0, 6.0);
        let len = values(2, 0.01, 0.5);
        let y = values(3, -0.8, 0.8);
        let z = values(4, -0.8, 0.8);
        let mut g = $c.benchmark_group($name);
        macro_rules! run {
            ($label:expr, $make:expr) => {
                g.bench_function($label, |b| {
                    b.iter(|| {
                        for i in 0..LEN {
                            let t = $make(black_box(t0[i]), black_box(t0[i] + len[i]));
                            black_box($f(t, y[i], z[i]));
                        }
                    })
                });
            };
        }
        run!("float", |a: f64, _b: f64| a);
        run!("jet", |a: f64, _b: f64| Jet::variable(a));
        run!("interval", |a: f64, b: f64| Interval::new(a, b));
        run!("affine", |a: f64, b: f64| {
            <Affine<f64, 1> as FieldNum<f64>>::ray_param(a, b)
        });
        run!("forward_linear", ForwardLinear::ray_param);
        run!("forward_quadratic", ForwardQuadratic::ray_param);
        g.finish();
    }};
}

fn fields(c: &mut Criterion) {
    bench_field!(c, "gaussian", gaussian);
    bench_field!(c, "compact", compact);
    bench_field!(c, "sphere", sphere);
}

criterion_group!(benches, fields);
criterion_main!(benches);
