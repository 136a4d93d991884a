//! Tracing in `f32` (the GPU's precision) agrees with `f64` on the same
//! standard scene: same hit/miss on every ray, first roots within the `f32`
//! run's `eps` (plus the `f64` run's), for every method that the scene
//! supports.

use boundtrace::inclusion::Ray;
use boundtrace::tracer::scenes::{DEFAULT_SEED, Scene};
use boundtrace::tracer::stats::RaySet;
use boundtrace::tracer::{Method, Params, Status, first_root};

#[test]
fn f32_tracing_agrees_with_f64_on_blobs() {
    let s64 = Scene::<f64>::build("blobs", DEFAULT_SEED).unwrap();
    let s32 = Scene::<f32>::build("blobs", DEFAULT_SEED).unwrap();
    let rays = RaySet::new(s64.bounds(), 200, 3).unwrap();
    let p64 = Params::<f64>::new();
    let p32 = Params::<f32>::new().with_eps(1e-3).unwrap();
    let tol = 1e-3 + 1e-4 + 1e-6;
    // `scalis-quadratic` needs a SCALIS skeleton (`tracer::scalis`)
    for m in Method::ALL
        .into_iter()
        .filter(|&m| m != Method::ScalisQuadratic)
    {
        let mut hits = 0;
        for (i, r) in rays.rays().iter().enumerate() {
            let (h64, t64) = first_root(s64.field(), &r.ray, r.span, m, &p64);
            let ray32 = Ray::new(r.ray.origin.map(|x| x as f32), r.ray.dir.map(|x| x as f32));
            let span32 = [r.span[0] as f32, r.span[1] as f32];
            let (h32, t32) = first_root(s32.field(), &ray32, span32, m, &p32);
            assert_eq!(t64.status, Status::Finished, "{m} ray {i} (f64)");
            assert_eq!(t32.status, Status::Finished, "{m} ray {i} (f32)");
            match (h64, h32) {
                (None, None) => {}
                (Some(a), Some(b)) => {
                    hits += 1;
                    assert!(
                        (a.t - f64::from(b.t)).abs() <= tol,
                        "{m} ray {i}: f64 root {} vs f32 root {}",
                        a.t,
                        b.t
                    );
                }
                (a, b) => panic!("{m} ray {i}: f64 {a:?} vs f32 {b:?}"),
            }
        }
        assert!(
            hits > 20,
            "{m}: only {hits} hits; the test would prove little"
        );
    }
}
