//! Per-ray cost of every method on every standard scene (issue 12): a small
//! fixed set of box-face rays per scene (the thesis §1.8 rays of the
//! statistics harness, `RaySet`, seed 1), traced in opaque mode with the
//! default parameters (`eps = 1e-4`), in `f64` like `boundtrace stats`.
//!
//! Group `per_ray/<scene>`, one function per method; the throughput is the
//! number of rays, so criterion reports the time per ray. `scalis-quadratic`
//! (and `sphere`/`interval` on the SCALIS scenes) go through the per-ray
//! primitive lists, as in the statistics harness; methods that a scene does
//! not support (no Taylor bound, …) are left out, and so is any method
//! whose first pass over the rays takes more than 2 s (named on stderr;
//! e.g. `sphere` on `molecule`). `aggregate-3`/`-4` (and their smooth
//! variants) get 4 rays instead of 24: full-tree evaluation of 1,110 and
//! 11,110 primitives costs 10 ms to seconds per ray, so only the cheaper
//! methods stay under that limit there (synchronized tracing, the fast
//! path for them, is the `sync_tracing` bench).
//!
//! Run with `cargo bench --bench per_ray` (add `-- blobs` for one scene);
//! `scripts/benchmarks.sh --only criterion` turns the results into the
//! ratio table of BENCHMARKS.md. Compare lines of one group as ratios.

use boundtrace::tracer::scalis::{PrimitiveHit, trace_scalis_ray};
use boundtrace::tracer::scenes::{DEFAULT_SEED, NAMES, Scene, SceneField};
use boundtrace::tracer::stats::{RaySet, SCALIS_LIST_CAPACITY, enlarged};
use boundtrace::tracer::sync::empty_root;
use boundtrace::tracer::{Method, Mode, Params, Status, Trace, trace};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;
use std::time::{Duration, Instant};

mod timing;
use timing::times;

/// Rays per scene.
const RAYS: usize = 24;

/// Rays on `aggregate-3*` and `aggregate-4*`, whose full-tree methods cost
/// 10 ms to seconds per ray (1,110 and 11,110 primitives per evaluation).
const RAYS_LARGE: usize = 4;

/// A method whose first pass over the rays takes longer than this is left
/// out (reported on stderr): e.g. `sphere` on `molecule`, whose global
/// Lipschitz bound makes it take ~1 s per ray, would take minutes per
/// sample. The table shows such a method as "—".
const MAX_PASS: Duration = Duration::from_secs(2);

/// Traces one ray of `scene` with `method`, dispatching like the
/// statistics harness.
fn trace_one(
    scene: &Scene<f64>,
    ray: &boundtrace::inclusion::Ray<f64>,
    span: [f64; 2],
    method: Method,
    params: &Params<f64>,
    storage: &mut [PrimitiveHit<f64>],
) -> Trace<f64> {
    let mut roots = [empty_root(); 1];
    match scene.field() {
        SceneField::Scalis(w)
            if matches!(
                method,
                Method::ScalisQuadratic | Method::Sphere | Method::Interval
            ) =>
        {
            trace_scalis_ray(
                w.field(),
                ray,
                span,
                method,
                Mode::Opaque,
                params,
                &mut roots,
                storage,
            )
        }
        f => trace(f, ray, span, method, Mode::Opaque, params, &mut roots),
    }
}

fn bench(c: &mut Criterion) {
    let params = Params::new();
    let mut storage = vec![PrimitiveHit::empty(); SCALIS_LIST_CAPACITY];
    for &name in NAMES {
        let count = if name.starts_with("aggregate-3") || name.starts_with("aggregate-4") {
            RAYS_LARGE
        } else {
            RAYS
        };
        let scene: Scene<f64> = Scene::build(name, DEFAULT_SEED).unwrap();
        let rays = RaySet::new(enlarged(scene.bounds(), 1e-3), count, 1).unwrap();
        let mut g = c.benchmark_group(format!("per_ray/{name}"));
        g.sample_size(10)
            .warm_up_time(times(300, 1000).0)
            .measurement_time(times(300, 1000).1)
            .throughput(Throughput::Elements(count as u64));
        for method in Method::ALL {
            // one pass over the rays, stopped as soon as it is too slow
            let start = Instant::now();
            let mut supported = true;
            for r in rays.rays() {
                let tr = trace_one(&scene, &r.ray, r.span, method, &params, &mut storage);
                if tr.status == Status::Unsupported {
                    supported = false;
                    break;
                }
                if start.elapsed() > MAX_PASS {
                    break;
                }
            }
            if !supported {
                continue;
            }
            if start.elapsed() > MAX_PASS {
                eprintln!(
                    "per_ray/{name}/{method}: left out (one pass over the rays took {:.1} s > {} s)",
                    start.elapsed().as_secs_f64(),
                    MAX_PASS.as_secs()
                );
                continue;
            }
            g.bench_function(method.name(), |b| {
                b.iter(|| {
                    for r in rays.rays() {
                        black_box(trace_one(
                            &scene,
                            &r.ray,
                            r.span,
                            method,
                            black_box(&params),
                            &mut storage,
                        ));
                    }
                })
            });
        }
        g.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
