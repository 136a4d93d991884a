//! HRBF fitting on random point clouds: interpolation of the points
//! (`|f| ≤ 10⁻⁶` of the scene scale), gradients aligned with the normals
//! (cosine > 0.99), the analytic gradient against jets, the sign convention
//! (negative at the center of the sampled ellipsoid), and degenerate input
//! (duplicates, NaN, too few points, zero normals) reported as errors,
//! never a panic. 10 000 cases (`PROPTEST_CASES` overrides).

mod common;

use boundtrace::fields::FieldError;
use boundtrace::fields::hrbf::Hrbf;
use boundtrace::inclusion::{Field, gradient};
use proptest::prelude::*;

/// Points of an ellipsoid (center `c`, radii `r`) in the given directions,
/// with outward normals (not normalized).
fn ellipsoid(c: [f64; 3], r: [f64; 3], dirs: &[[f64; 3]]) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let mut p = Vec::new();
    let mut q = Vec::new();
    for d in dirs {
        let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let u = d.map(|x| x / l);
        let x = [0, 1, 2].map(|k| r[k] * u[k]);
        p.push([0, 1, 2].map(|k| c[k] + x[k]));
        q.push([0, 1, 2].map(|k| x[k] / (r[k] * r[k])));
    }
    (p, q)
}

fn dirs() -> impl Strategy<Value = Vec<[f64; 3]>> {
    prop::collection::vec(
        prop::array::uniform3(-1.0f64..1.0).prop_filter("not near zero", |d| {
            d[0].abs() + d[1].abs() + d[2].abs() > 0.3
        }),
        2..14,
    )
}

fn min_dist(p: &[[f64; 3]]) -> f64 {
    let mut m = f64::MAX;
    for i in 0..p.len() {
        for j in 0..i {
            let d = [0, 1, 2].map(|k| p[i][k] - p[j][k]);
            m = m.min((d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt());
        }
    }
    m
}

proptest! {
    #![proptest_config(common::config())]

    #[test]
    fn fit_interpolates_points_and_normals(
        c in prop::array::uniform3(-10.0f64..10.0),
        r in prop::array::uniform3(0.5f64..3.0),
        d in dirs(),
    ) {
        let (p, q) = ellipsoid(c, r, &d);
        let scale = r[0].max(r[1]).max(r[2]);
        let h = match Hrbf::<f64, _>::fit(&p, &q) {
            Ok(h) => h,
            Err(FieldError::Singular { .. }) => {
                // only for (nearly) coincident random samples
                prop_assert!(min_dist(&p) < 1e-6 * scale, "singular with distinct points");
                return Ok(());
            }
            Err(e) => return Err(TestCaseError::fail(format!("{e}"))),
        };
        for (pj, nj) in p.iter().zip(&q) {
            let v = h.eval(*pj);
            prop_assert!(v.abs() <= 1e-6 * scale, "f(p) = {v}");
            let g = h.gradient_at(*pj);
            let gl = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
            let nl = (nj[0] * nj[0] + nj[1] * nj[1] + nj[2] * nj[2]).sqrt();
            let cos = (g[0] * nj[0] + g[1] * nj[1] + g[2] * nj[2]) / (gl * nl);
            prop_assert!(cos > 0.99, "cos = {cos}");
            let gj = gradient(&h, *pj);
            for k in 0..3 {
                prop_assert!((g[k] - gj[k]).abs() <= 1e-8 * (1.0 + gl), "∇ {g:?} vs jets {gj:?}");
            }
        }
        // f32 storage of the same fit still interpolates to f32 accuracy.
        let p32: Vec<[f32; 3]> = p.iter().map(|x| x.map(|v| v as f32)).collect();
        let q32: Vec<[f32; 3]> = q.iter().map(|x| x.map(|v| v as f32)).collect();
        if let Ok(h32) = Hrbf::<f32, _>::fit(&p32, &q32) {
            for pj in &p32 {
                let v = h32.eval(*pj);
                prop_assert!(f64::from(v.abs()) <= 1e-2 * scale, "f32 f(p) = {v}");
            }
        }
    }

    #[test]
    fn degenerate_input_is_an_error(
        d in dirs(),
        which in 0usize..64,
        k in 0usize..3,
        bad in prop_oneof![Just(f64::NAN), Just(f64::INFINITY), Just(f64::NEG_INFINITY)],
    ) {
        let (p, q) = ellipsoid([0.5, -0.25, 1.0], [1.0, 2.0, 1.5], &d);
        let i = which % p.len();
        // duplicate a point (with a different normal)
        let mut pd = p.clone();
        let mut qd = q.clone();
        pd.push(p[i]);
        qd.push([q[i][1], q[i][2], q[i][0] + 1.0]);
        let dup = Hrbf::<f64, _>::fit(&pd, &qd);
        prop_assert!(matches!(dup, Err(FieldError::Singular { .. })), "duplicate: {:?}", dup.err());
        // a NaN or infinite coordinate
        let mut pn = p.clone();
        pn[i][k] = bad;
        prop_assert!(Hrbf::<f64, _>::fit(&pn, &q).is_err());
        let mut qn = q.clone();
        qn[i][k] = bad;
        prop_assert!(Hrbf::<f64, _>::fit(&p, &qn).is_err());
        // a zero normal, a missing normal, a single point, no point
        let mut qz = q.clone();
        qz[i] = [0.0; 3];
        prop_assert!(Hrbf::<f64, _>::fit(&p, &qz).is_err());
        prop_assert!(Hrbf::<f64, _>::fit(&p, &q[1..]).is_err());
        let one = Hrbf::<f64, _>::fit(&p[i..=i], &q[i..=i]);
        prop_assert!(matches!(one, Err(FieldError::Singular { .. })), "one point: {:?}", one.err());
        prop_assert!(Hrbf::<f32, _>::fit(&[], &[]).is_err());
    }
}

#[test]
fn sign_convention_outside_positive() {
    let d: Vec<[f64; 3]> = (0..12)
        .map(|i| {
            let z = -0.9 + 0.15 * f64::from(i);
            let th = 2.4 * f64::from(i);
            let r = (1.0 - z * z).sqrt();
            [r * th.cos(), r * th.sin(), z]
        })
        .collect();
    let (p, q) = ellipsoid([1.0, 2.0, 3.0], [1.0, 1.5, 0.8], &d);
    let h = Hrbf::<f64, _>::fit(&p, &q).unwrap();
    assert!(h.eval([1.0f64, 2.0, 3.0]) < 0.0);
    for (pj, nj) in p.iter().zip(&q) {
        let out = [0, 1, 2].map(|k| pj[k] + 0.05 * nj[k]);
        let inn = [0, 1, 2].map(|k| pj[k] - 0.05 * nj[k]);
        assert!(h.eval(out) > 0.0 && h.eval(inn) < 0.0);
    }
    let too_many = vec![[0.0f64; 3]; 513];
    assert!(matches!(
        Hrbf::<f64, _>::fit(&too_many, &too_many),
        Err(FieldError::TooLarge { .. })
    ));
}
