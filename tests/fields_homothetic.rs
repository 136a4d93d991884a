//! Homothetic-distance skeletons (`boundtrace::fields::homothetic_skeleton`):
//! every bound kind (interval, affine, forward bottom-up linear and
//! quadratic, the directional Lipschitz line used by segment tracing, the
//! global Lipschitz bound) contains the field on random skeletons and rays.

mod common;

use boundtrace::fields::homothetic::{Segment, SegmentKernel};
use boundtrace::fields::homothetic_skeleton::HomotheticSkeleton;
use boundtrace::inclusion::{BoundKind, Field, Ray, linear_bound};
use proptest::prelude::*;

use common::scalis_cases::{SegSpec, check_field, exact, overlaps, v3};

#[derive(Clone, Debug)]
struct Case {
    kernel: SegmentKernel<f64>,
    iso: f64,
    segs: Vec<SegSpec>,
    ray: Ray<f64>,
    t0: f64,
    h: f64,
    taus: [f64; 3],
}

fn case() -> impl Strategy<Value = Case> {
    let kernel = prop_oneof![
        (1u32..=4, 1.2f64..3.0)
            .prop_map(|(m, s)| SegmentKernel::compact_polynomial(2 * m, s).unwrap()),
        (2u32..=5, 0.5f64..2.0).prop_map(|(n, s)| SegmentKernel::cauchy(n, s).unwrap()),
    ];
    let seg = ((v3(1.5), 0.05f64..1.0), (v3(1.5), 0.05f64..1.0));
    (
        kernel,
        0.2f64..2.0,
        proptest::collection::vec(seg, 1..=3),
        v3(3.0),
        v3(1.0),
        0.0f64..4.0,
        prop_oneof![1e-3f64..0.05, 0.05f64..1.0, 1.0f64..4.0],
        [0.0f64..1.0, 0.0f64..1.0, 0.0f64..1.0],
    )
        .prop_map(|(kernel, iso, segs, o, d, t0, h, taus)| Case {
            kernel,
            iso,
            segs,
            ray: Ray::new(o, d),
            t0,
            h,
            taus,
        })
}

fn build(c: &Case) -> Option<HomotheticSkeleton<f64, Vec<Segment<f64>>>> {
    let segs: Option<Vec<_>> = c
        .segs
        .iter()
        .map(|&((a, ra), (b, rb))| Segment::new(a, ra, b, rb).ok())
        .collect();
    HomotheticSkeleton::new(segs?, c.kernel, c.iso).ok()
}

fn check(c: &Case) -> Result<(), TestCaseError> {
    let Some(sk) = build(c) else { return Ok(()) };
    if c.ray.speed() <= 1e-3 || c.ray.speed().is_nan() {
        return Ok(());
    }
    // interval, affine, bottom-up linear and quadratic
    check_field(&sk, &c.ray, c.t0, c.h, &c.taus)?;
    let (t0, t1) = (c.t0, c.t0 + c.h);
    let ray = c.ray;
    let tl = linear_bound(&sk, &ray, t0, t1, BoundKind::Taylor).unwrap();
    let ml = linear_bound(&sk, &ray, t0, t1, BoundKind::Mixed).unwrap();
    prop_assert!(tl.is_valid(), "the Lipschitz line is always valid");
    let global = sk.lipschitz().unwrap() * ray.speed() * (1.0 + 1e-12);
    let lip = sk.directional_lipschitz(&ray, t0, t1);
    prop_assert!(lip <= global + 1e-12, "local {lip} > global {global}");
    let r0 = exact(&sk, &ray, t0);
    for tau in c.taus.iter().chain([0.0, 1.0].iter()) {
        let t = (t0 + tau * c.h).min(t1);
        let tt = t - t0;
        let r = exact(&sk, &ray, t);
        for (name, b) in [("taylor", tl), ("mixed", ml)] {
            if b.is_valid() && tt <= b.validity() {
                prop_assert!(
                    overlaps(b.bounds_at(tt), r),
                    "{name} {:?} vs {r:?} at τ={tt}",
                    b.bounds_at(tt)
                );
            }
        }
        // |f(t) − f(t0)| ≤ L·(t − t0) for both Lipschitz bounds
        let gap = (r.lo() - r0.hi()).max(r0.lo() - r.hi()).max(0.0);
        prop_assert!(
            gap <= lip * tt * (1.0 + 1e-9) + 1e-12,
            "local {lip}: gap {gap}"
        );
    }
    Ok(())
}

proptest! {
    #![proptest_config(common::config())]

    /// Every bound kind of a random 1–3 segment skeleton contains the field
    /// at sampled ray points.
    #[test]
    fn homothetic_skeleton_bounds_contain_the_field(c in case()) {
        check(&c)?;
    }
}

/// A skeleton crossing the ray with the worst case for `|k'|` (the ray
/// passes at `h ≈ h*`): the directional bound is at least the sampled
/// slope, and at most the global bound.
#[test]
fn directional_bound_is_tight_enough_and_sound() {
    let k = SegmentKernel::compact_polynomial(4, 2.0).unwrap();
    let s = Segment::new([0.0, 0.0, 0.0], 0.5, [2.0, 0.0, 0.0], 0.5).unwrap();
    let sk = HomotheticSkeleton::new(vec![s], k, 1.0).unwrap();
    let ray = Ray::new([1.0, -2.0, 0.0], [0.0, 1.0, 0.0]);
    let (t0, t1) = (0.0, 4.0);
    let l = sk.directional_lipschitz(&ray, t0, t1);
    let mut steepest: f64 = 0.0;
    let n = 4000;
    for i in 0..n {
        let (a, b) = (
            t0 + (t1 - t0) * f64::from(i) / f64::from(n),
            t0 + (t1 - t0) * f64::from(i + 1) / f64::from(n),
        );
        let (fa, fb): (f64, f64) = (sk.eval(ray.at(a, a)), sk.eval(ray.at(b, b)));
        steepest = steepest.max((fb - fa).abs() / (b - a));
    }
    assert!(steepest <= l, "{steepest} > {l}");
    // the bound is attained here up to sampling (constant radius, the ray
    // crosses the axis orthogonally): within 1 %
    assert!(l <= steepest * 1.01, "{l} vs {steepest}");
    assert!(l <= sk.lipschitz().unwrap() * (1.0 + 1e-12));
}
