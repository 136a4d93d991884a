//! Random SCALIS skeletons and rays, and the containment check of every
//! bound kind on them, shared by the `fields_scalis` property tests and the
//! `field_bounds` fuzz target (`fuzz/`).

use boundtrace::fields::homothetic::{HomotheticPrimitive, Segment, SegmentKernel};
use boundtrace::fields::scalis::{Normalized, ScalisSegment, ScalisSkeleton};
use boundtrace::ia_core::{Affine, Interval};
use boundtrace::inclusion::{BoundKind, Field, ForwardLinear, Ray, linear_bound, quadratic_bound};
use proptest::prelude::*;
use proptest::test_runner::TestCaseError;

pub fn compact(n: u32, sigma: f64) -> SegmentKernel<f64> {
    SegmentKernel::compact_polynomial(n, sigma).unwrap()
}
pub fn cauchy(sigma: f64) -> SegmentKernel<f64> {
    SegmentKernel::cauchy(3, sigma).unwrap()
}
/// `((a, ra), (b, rb))`.
pub type SegSpec = (([f64; 3], f64), ([f64; 3], f64));

#[derive(Clone, Debug)]
pub struct Case {
    pub kernel: SegmentKernel<f64>,
    pub segs: Vec<SegSpec>,
    pub ray: Ray<f64>,
    pub t0: f64,
    pub h: f64,
    pub taus: [f64; 3],
}

pub fn v3(s: f64) -> impl Strategy<Value = [f64; 3]> {
    [-s..s, -s..s, -s..s]
}

pub fn case() -> impl Strategy<Value = Case> {
    let kernel = prop_oneof![
        (1u32..=4, 1.2f64..3.0).prop_map(|(m, s)| compact(2 * m, s)),
        (0.5f64..2.0).prop_map(cauchy),
    ];
    let seg = ((v3(1.5), 0.1f64..0.8), (v3(1.5), 0.1f64..0.8));
    (
        kernel,
        proptest::collection::vec(seg, 1..=2),
        v3(3.0),
        v3(1.0),
        0.0f64..4.0,
        prop_oneof![1e-3f64..0.05, 0.05f64..1.0, 1.0f64..4.0],
        [0.0f64..1.0, 0.0f64..1.0, 0.0f64..1.0],
    )
        .prop_map(|(kernel, segs, o, d, t0, h, taus)| Case {
            kernel,
            segs,
            ray: Ray::new(o, d),
            t0,
            h,
            taus,
        })
}

pub fn build<const M: usize>(c: &Case) -> Option<ScalisSkeleton<f64, [ScalisSegment<f64>; M]>> {
    let mk = |((a, ra), (b, rb)): SegSpec| {
        ScalisSegment::new(Segment::new(a, ra, b, rb).ok()?, c.kernel, 1.0).ok()
    };
    let v: Option<Vec<_>> = c.segs.iter().take(M).map(|&sp| mk(sp)).collect();
    ScalisSkeleton::new(v?.try_into().ok()?).ok()
}

/// A sound enclosure of the skeleton field at the ray point `t`.
pub fn exact<F: Field<f64>>(f: &F, ray: &Ray<f64>, t: f64) -> Interval<f64> {
    let p = [0, 1, 2]
        .map(|k| Interval::point(ray.origin[k]) + Interval::point(t) * Interval::point(ray.dir[k]));
    f.eval(p)
}

pub fn overlaps(a: Interval<f64>, b: Interval<f64>) -> bool {
    a.lo() <= b.hi() && b.lo() <= a.hi()
}
/// Every bound of `sk` on the case's ray interval against sound point
/// enclosures at sampled parameters.
pub fn check<const M: usize>(
    c: &Case,
    sk: &ScalisSkeleton<f64, [ScalisSegment<f64>; M]>,
) -> Result<(), TestCaseError> {
    if c.ray.speed() <= 1e-3 || c.ray.speed().is_nan() {
        return Ok(());
    }
    let (t0, t1) = (c.t0, c.t0 + c.h);
    let ray = c.ray;
    let iv: Interval<f64> = sk.eval(ray.at(t0, t1));
    let af: Affine<f64, 1> = sk.eval(ray.at(t0, t1));
    let fl = linear_bound(sk, &ray, t0, t1, BoundKind::BottomUp).unwrap();
    let fq = quadratic_bound(sk, &ray, t0, t1, BoundKind::BottomUp).unwrap();
    let tq = quadratic_bound(sk, &ray, t0, t1, BoundKind::Taylor);
    let mq = quadratic_bound(sk, &ray, t0, t1, BoundKind::Mixed).unwrap();
    let has_tq = matches!(c.kernel, SegmentKernel::CompactPolynomial { degree, .. } if degree >= 4);
    prop_assert_eq!(tq.is_some(), has_tq);
    let tl = linear_bound(sk, &ray, t0, t1, BoundKind::Taylor).unwrap();
    let ml = linear_bound(sk, &ray, t0, t1, BoundKind::Mixed).unwrap();
    let range = sk.density_range(&ray, t0, t1);
    let lip = sk.directional_lipschitz(&ray, t0, t1);
    let f0 = exact(sk, &ray, t0);
    let ll = ForwardLinear::lipschitz(f0, lip, t1 - t0);
    let norm = Normalized(*sk);
    let niv: Interval<f64> = norm.eval(ray.at(t0, t1));
    for (i, tau) in c.taus.iter().chain([0.0, 1.0].iter()).enumerate() {
        let t = (t0 + tau * c.h).min(t1);
        let r = exact(sk, &ray, t);
        let dens = Interval::point(1.0) - r;
        prop_assert!(overlaps(iv, r), "interval {iv:?} vs {r:?} at t={t} ({i})");
        prop_assert!(overlaps(af.to_interval(), r), "affine {af:?} vs {r:?}");
        prop_assert!(
            overlaps(range, dens),
            "per-primitive range {range:?} vs density {dens:?}"
        );
        let rn = exact(&norm, &ray, t);
        prop_assert!(overlaps(niv, rn), "normalized {niv:?} vs {rn:?}");
        let tt = t - t0;
        for (name, b) in [
            ("linear", fl),
            ("taylor", tl),
            ("mixed", ml),
            ("lipschitz", ll),
        ] {
            prop_assert!(b.is_valid() || name == "linear", "{name} bound invalid");
            if b.is_valid() && tt <= b.validity() {
                prop_assert!(
                    overlaps(b.bounds_at(tt), r),
                    "{name} {:?} vs {r:?} at τ={tt}",
                    b.bounds_at(tt)
                );
            }
        }
        for (name, b) in [
            ("quadratic", Some(fq)),
            ("taylor quadratic", tq),
            ("mixed quadratic", Some(mq)),
        ] {
            let Some(b) = b else { continue };
            if b.is_valid() && tt <= b.validity() {
                prop_assert!(
                    overlaps(b.bounds_at(tt), r),
                    "{name} {:?} vs {r:?} at τ={tt}",
                    b.bounds_at(tt)
                );
            }
        }
    }
    Ok(())
}
#[derive(Clone, Debug)]
pub struct HCase {
    pub kernel: SegmentKernel<f64>,
    pub seg: SegSpec,
    pub ray: Ray<f64>,
    pub t0: f64,
    pub h: f64,
    pub taus: [f64; 3],
}

pub fn hcase() -> impl Strategy<Value = HCase> {
    let kernel = prop_oneof![
        (1u32..=4, 1.2f64..3.0).prop_map(|(m, s)| compact(2 * m, s)),
        (2u32..=5, 0.5f64..2.0).prop_map(|(n, s)| SegmentKernel::cauchy(n, s).unwrap()),
    ];
    (
        kernel,
        ((v3(1.5), 0.05f64..1.0), (v3(1.5), 0.05f64..1.0)),
        v3(3.0),
        v3(1.0),
        0.0f64..4.0,
        prop_oneof![1e-3f64..0.05, 0.05f64..1.0, 1.0f64..4.0],
        [0.0f64..1.0, 0.0f64..1.0, 0.0f64..1.0],
    )
        .prop_map(|(kernel, seg, o, d, t0, h, taus)| HCase {
            kernel,
            seg,
            ray: Ray::new(o, d),
            t0,
            h,
            taus,
        })
}

pub fn check_field<F: Field<f64>>(
    f: &F,
    ray: &Ray<f64>,
    t0: f64,
    h: f64,
    taus: &[f64; 3],
) -> Result<(), TestCaseError> {
    let t1 = t0 + h;
    let iv: Interval<f64> = f.eval(ray.at(t0, t1));
    let af: Affine<f64, 1> = f.eval(ray.at(t0, t1));
    let fl = linear_bound(f, ray, t0, t1, BoundKind::BottomUp).unwrap();
    let fq = quadratic_bound(f, ray, t0, t1, BoundKind::BottomUp).unwrap();
    for tau in taus.iter().chain([0.0, 1.0].iter()) {
        let t = (t0 + tau * h).min(t1);
        let r = exact(f, ray, t);
        prop_assert!(overlaps(iv, r), "interval {iv:?} vs {r:?} at t={t}");
        prop_assert!(overlaps(af.to_interval(), r), "affine {af:?} vs {r:?}");
        let tt = t - t0;
        if fl.is_valid() && tt <= fl.validity() {
            prop_assert!(
                overlaps(fl.bounds_at(tt), r),
                "linear {:?} vs {r:?}",
                fl.bounds_at(tt)
            );
        }
        if fq.is_valid() && tt <= fq.validity() {
            prop_assert!(
                overlaps(fq.bounds_at(tt), r),
                "quadratic {:?} vs {r:?}",
                fq.bounds_at(tt)
            );
        }
    }
    Ok(())
}

/// Every bound kind of the case's skeleton (1 or 2 segments) contains the
/// field (cases with invalid segments pass vacuously).
pub fn check_case(c: &Case) -> Result<(), TestCaseError> {
    if c.segs.len() == 1 {
        if let Some(sk) = build::<1>(c) {
            check(c, &sk)?
        }
    } else if let Some(sk) = build::<2>(c) {
        check(c, &sk)?
    }
    Ok(())
}

/// `k ∘ h_S` and `h_S − 1` (homothetic primitives): every bound kind
/// contains the field.
pub fn check_homothetic(c: &HCase) -> Result<(), TestCaseError> {
    let ((a, ra), (b, rb)) = c.seg;
    let Ok(seg) = Segment::new(a, ra, b, rb) else {
        return Ok(());
    };
    if c.ray.speed() <= 1e-3 || c.ray.speed().is_nan() {
        return Ok(());
    }
    let prim = HomotheticPrimitive::new(seg, c.kernel).unwrap();
    check_field(&prim, &c.ray, c.t0, c.h, &c.taus)?;
    check_field(&seg, &c.ray, c.t0, c.h, &c.taus)
}
