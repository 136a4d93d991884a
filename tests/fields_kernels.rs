//! Kernels, point blobs, density operators and an HRBF term: containment of
//! every bound type, derivatives against finite differences, and the
//! analytic extrema of `k'`, `k''` against dense sampling.
//!
//! Containment: each case draws a random scene (1–4 blobs with random
//! kernels of every family, weights, scales, an iso-value; as a plain
//! [`Blobs`] sum, a [`Union`], [`Intersection`] or [`Ricci`] blend of two
//! sums, or a [`Sum`] with a fixed fitted [`Hrbf`]), a random ray and a random interval `[t0, t0 + h]` (dyadic, so
//! the 17 sample points `t0 + h·k/16` and their offsets are exact floats).
//! The reference at a sample is the field evaluated with point intervals (a
//! sound enclosure of the exact value); a violation is a bound that does not
//! intersect it. Checked: `Interval` and `Affine` over the whole interval,
//! `ForwardLinear`/`ForwardQuadratic` bottom-up, Taylor (both) and mixed, at
//! every sample within their validity. 10 000 cases per float type
//! (`PROPTEST_CASES` overrides).

mod common;

use boundtrace::fields::FieldError;
use boundtrace::fields::blob::{Blobs, PointBlob};
use boundtrace::fields::kernel::{Kernel, KernelKind};
use boundtrace::ia_core::Interval;
use boundtrace::inclusion::{Field, ForwardQuadratic, Ray, gradient, jet_at};
use proptest::prelude::*;

use common::kernel_cases::*;

proptest! {
    #![proptest_config(common::config())]

    #[test]
    fn containment_f64(c in case()) {
        check_case::<f64>(&c)?;
    }

    #[test]
    fn containment_f32(c in case()) {
        check_case::<f32>(&c)?;
    }

    /// Kernel derivatives: the analytic `k'`, `k''` against central
    /// differences of `k` and `k'`, and the jet of `K(u)` against `K'`, `K''`.
    #[test]
    fn kernel_derivatives_match_finite_differences(k in kdesc(), s in 0.02f64..2.5) {
        let kern = make_kernel::<f64>(k);
        let d = s * k.sigma;
        let near_edge = k.kind == 0 && (d - k.sigma).abs() < 0.01 * k.sigma;
        prop_assume!(!near_edge);
        let h = 1e-5 * k.sigma;
        let fd1 = (kern.value(d + h) - kern.value(d - h)) / (2.0 * h);
        let fd2 = (kern.derivative(d + h) - kern.derivative(d - h)) / (2.0 * h);
        let (a1, a2) = (kern.derivative(d), kern.second_derivative(d));
        let tol = |a: f64| 1e-5 * (1.0 + a.abs()) * (1.0 + kern.value(d).abs());
        prop_assert!((a1 - fd1).abs() <= tol(a1), "k' {a1} vs {fd1}");
        prop_assert!((a2 - fd2).abs() <= 10.0 * tol(a2), "k'' {a2} vs {fd2}");
        let u = (d / k.sigma).powi(2);
        let j = kern.eval_u(boundtrace::inclusion::Jet::variable(u));
        let (du, d2u) = (kern.d_u(u), kern.d2_u(u));
        prop_assert!((j.d1 - du).abs() <= 1e-9 * (1.0 + du.abs()), "K' {} vs {du}", j.d1);
        prop_assert!((j.d2 - d2u).abs() <= 1e-9 * (1.0 + d2u.abs()), "K'' {} vs {d2u}", j.d2);
    }

    /// Blob-sum gradients (three jets) and second derivatives along rays
    /// (jets) against central differences of the field.
    #[test]
    fn blob_gradients_match_finite_differences(
        bs in prop::collection::vec(bdesc(), 1..4),
        p in prop::array::uniform3(-1.5f64..1.5),
        v in prop::array::uniform3(-1.0f64..1.0),
    ) {
        let f = make_blobs::<f64>(0.5, &bs);
        // stay away from compact support boundaries and inverse centers
        for b in &bs {
            let d = dist(p, b.c);
            prop_assume!((d - b.k.sigma).abs() > 1e-3 && d > 0.05);
        }
        let g = gradient(&f, p);
        let h = 1e-6;
        for k in 0..3 {
            let (mut a, mut b) = (p, p);
            a[k] += h;
            b[k] -= h;
            let fd = (f.eval(a) - f.eval(b)) / (2.0 * h);
            prop_assert!((g[k] - fd).abs() <= 1e-5 * (1.0 + fd.abs()), "∂{k}: {} vs {fd}", g[k]);
        }
        let ray = Ray::new(p, v);
        let j = jet_at(&f, &ray, 0.0);
        // Central differences at steps hh and hh/2, Richardson-extrapolated
        // (error O(hh⁴)); the step follows the nearest center (the inverse
        // kernels' derivatives grow like d^{-n-k}) and stays inside the
        // nearest compact support boundary.
        let dmin = bs
            .iter()
            .map(|b| {
                let d = dist(p, b.c);
                if b.k.kind == 0 { d.min(0.5 * (d - b.k.sigma).abs()) } else { d }
            })
            .fold(f64::MAX, f64::min);
        let vv = v.iter().map(|x| x * x).sum::<f64>();
        let hh = 1e-2 * dmin.min(1.0) / vv.sqrt().max(1e-3);
        let cd2 = |h: f64| {
            let fp = f.eval(ray.at::<f64>(h, h));
            let fm = f.eval(ray.at::<f64>(-h, -h));
            (fp - 2.0 * j.v + fm) / (h * h)
        };
        let fd2 = (4.0 * cd2(0.5 * hh) - cd2(hh)) / 3.0;
        // `f''` along the ray is a sum of terms that may cancel: the
        // difference error scales with the terms, not with the sum. Scale:
        // the blobs' Hessian norms `|w|·|v|²·(|k'|/d + |k''|)`.
        let scale: f64 = bs
            .iter()
            .map(|b| {
                let (kern, d) = (make_kernel::<f64>(b.k), dist(p, b.c));
                b.w.abs() * vv * (kern.derivative(d).abs() / d + kern.second_derivative(d).abs())
            })
            .sum();
        prop_assert!(
            (j.d2 - fd2).abs() <= 1e-3 * (1.0 + fd2.abs()) + 1e-6 * scale,
            "f'' {} vs {fd2} (Hessian scale {scale})",
            j.d2
        );
    }

    /// `derivative_range`, `second_derivative_range` contain densely sampled
    /// values and are not much wider than the sampled spread.
    #[test]
    fn kernel_extrema_match_dense_sampling(k in kdesc(), a in 0.0f64..2.0, w in 0.001f64..2.0) {
        let kern = make_kernel::<f64>(k);
        let (d0, d1) = (a * k.sigma, (a + w) * k.sigma);
        prop_assume!(!(k.kind == 3 && d0 < 1e-3));
        let r1 = kern.derivative_range(d0, d1);
        let r2 = kern.second_derivative_range(d0, d1);
        let (mut lo1, mut hi1, mut lo2, mut hi2) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for i in 0..=400 {
            let d = d0 + (d1 - d0) * f64::from(i) / 400.0;
            let (x, y) = (kern.derivative(d), kern.second_derivative(d));
            // (the float samples carry their own rounding error)
            let near = |r: Interval<f64>, x: f64| {
                r.lo() <= x + 1e-12 * (1.0 + x.abs()) && x - 1e-12 * (1.0 + x.abs()) <= r.hi()
            };
            prop_assert!(near(r1, x), "k'({d}) = {x} not in {r1:?}");
            lo1 = lo1.min(x);
            hi1 = hi1.max(x);
            if y.is_finite() {
                prop_assert!(near(r2, y), "k''({d}) = {y} not in {r2:?}");
                lo2 = lo2.min(y);
                hi2 = hi2.max(y);
            }
        }
        // Tightness: the sampling misses at most the peak between samples.
        let spread = |lo: f64, hi: f64| 0.01 * (hi - lo) + 1e-9 * (1.0 + hi.abs().max(lo.abs()));
        prop_assert!(r1.lo() >= lo1 - spread(lo1, hi1) && r1.hi() <= hi1 + spread(lo1, hi1),
            "k' range {r1:?} vs sampled [{lo1}, {hi1}]");
        let smooth = !(k.kind == 0 && (k.n <= 4 || d1 >= k.sigma));
        if smooth {
            prop_assert!(r2.lo() >= lo2 - spread(lo2, hi2) && r2.hi() <= hi2 + spread(lo2, hi2),
                "k'' range {r2:?} vs sampled [{lo2}, {hi2}]");
        }
    }
}

#[test]
fn bad_parameters_are_rejected() {
    let bad = |r: Result<Kernel<f64>, FieldError>| {
        assert!(
            matches!(r, Err(FieldError::InvalidParameter { .. })),
            "{r:?}"
        );
    };
    bad(Kernel::compact(6, 0.0));
    bad(Kernel::compact(6, -1.0));
    bad(Kernel::compact(6, f64::NAN));
    bad(Kernel::compact(1, 1.0));
    bad(Kernel::cauchy(0, 1.0));
    bad(Kernel::inverse(1, 1.0));
    bad(Kernel::gaussian(f64::INFINITY));
    bad(Kernel::gaussian_scaled(-1.0, 1.0));
    let k = Kernel::gaussian(1.0).unwrap();
    assert!(PointBlob::new([0.0, f64::NAN, 0.0], 1.0, k).is_err());
    assert!(PointBlob::new([0.0; 3], f64::NAN, k).is_err());
    assert!(Blobs::new(f64::INFINITY, [PointBlob::new([0.0; 3], 1.0, k).unwrap()]).is_err());
    assert_eq!(KernelKind::from_u32(2), Some(KernelKind::Gaussian));
    assert_eq!(KernelKind::from_u32(9), None);
}

/// The test can fail: a wrong curvature (the blob Taylor bound built with
/// `f'' = 0`) is caught on a curved stretch of a Gaussian blob.
#[test]
fn containment_check_detects_a_wrong_bound() {
    let f = Blobs::new(
        0.5,
        [PointBlob::new([0.0; 3], 1.0, Kernel::gaussian(1.0).unwrap()).unwrap()],
    )
    .unwrap();
    let ray = Ray::new([-2.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
    let good = f.taylor_quadratic(&ray, 1.5, 2.5).unwrap();
    let j = jet_at(&f, &ray, 1.5);
    let wrong = ForwardQuadratic::taylor(
        Interval::point(j.v),
        Interval::point(j.d1),
        Interval::point(0.0),
        1.0,
    );
    let r: Interval<f64> = f.eval(ray.at(2.5, 2.5));
    assert!(!good.bounds_at(1.0).intersection(r).is_empty());
    assert!(wrong.bounds_at(1.0).intersection(r).is_empty());
}

/// The random cases do exercise the Taylor bounds: on a fixed-seed run,
/// most cases without the HRBF term get a valid quadratic Taylor bound
/// that is strictly tighter than bottom-up somewhere.
#[test]
fn taylor_bounds_are_exercised() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    let mut runner = TestRunner::deterministic();
    let (mut cases, mut valid, mut blob_cases) = (0, 0, 0);
    while cases < 2000 {
        let c = case().new_tree(&mut runner).unwrap().current();
        cases += 1;
        if c.variant == 3 {
            continue;
        }
        blob_cases += 1;
        let f = make_blobs::<f64>(c.iso, &c.a);
        let ray = Ray::new(c.origin, c.dir);
        let t0 = f64::from(c.t0_k) / 1024.0;
        let t1 = t0 + f64::from(c.h_k) / 1024.0;
        if let Some(q) = f.taylor_quadratic(&ray, t0, t1) {
            if q.is_valid() && q.validity() > 0.0 {
                valid += 1;
            }
        }
    }
    assert!(valid * 10 >= blob_cases * 8, "{valid} of {blob_cases}");
}

/// Euclidean distance of two points.
fn dist(p: [f64; 3], c: [f64; 3]) -> f64 {
    ((p[0] - c[0]).powi(2) + (p[1] - c[1]).powi(2) + (p[2] - c[2]).powi(2)).sqrt()
}
