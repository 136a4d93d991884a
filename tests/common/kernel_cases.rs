//! Random kernels, blob sets and HRBF fits, and the containment check of
//! every bound kind on them, shared by the `fields_kernels` property tests and
//! the `field_bounds` fuzz target (`fuzz/`).

use super::Flt;
use boundtrace::fields::blob::{Blobs, PointBlob};
use boundtrace::fields::density::{Intersection, Ricci, Sum, Union};
use boundtrace::fields::hrbf::{Hrbf, HrbfCenter};
use boundtrace::fields::kernel::Kernel;
use boundtrace::ia_core::{Affine, Interval};
use boundtrace::inclusion::{
    BoundKind, Field, FieldNum, ForwardLinear, ForwardQuadratic, Ray, linear_bound, quadratic_bound,
};
use proptest::prelude::*;
use proptest::test_runner::TestCaseError;
use std::sync::OnceLock;

/// A kernel description: family tag, degree, scale.
#[derive(Clone, Copy, Debug)]
pub struct KDesc {
    pub kind: u32,
    pub n: u32,
    pub sigma: f64,
}

pub fn kdesc() -> impl Strategy<Value = KDesc> {
    (0u32..4, 2u32..9, 0.3f64..1.6).prop_map(|(kind, n, sigma)| KDesc {
        kind,
        // inverse kernels: degrees 2–3 (steep enough already)
        n: if kind == 3 { 2 + n % 2 } else { n },
        sigma,
    })
}

pub fn make_kernel<T: Flt>(k: KDesc) -> Kernel<T> {
    let s = T::from_f64(k.sigma);
    match k.kind {
        0 => Kernel::compact(k.n, s),
        1 => Kernel::cauchy(k.n, s),
        2 => Kernel::gaussian(s),
        _ => Kernel::inverse(k.n, s),
    }
    .unwrap()
}

/// A blob description: center, weight, kernel.
#[derive(Clone, Copy, Debug)]
pub struct BDesc {
    pub c: [f64; 3],
    pub w: f64,
    pub k: KDesc,
}

pub fn bdesc() -> impl Strategy<Value = BDesc> {
    (
        prop::array::uniform3(-1.0f64..1.0),
        prop_oneof![4 => 0.2f64..1.5, 1 => -0.5f64..-0.1],
        kdesc(),
    )
        .prop_map(|(c, w, k)| BDesc { c, w, k })
}

pub fn make_blobs<T: Flt>(iso: f64, bs: &[BDesc]) -> Blobs<T, Vec<PointBlob<T>>> {
    let v = bs
        .iter()
        .map(|b| {
            PointBlob::new(
                b.c.map(T::from_f64),
                T::from_f64(b.w),
                make_kernel::<T>(b.k),
            )
            .unwrap()
        })
        .collect();
    Blobs::new(T::from_f64(iso), v).unwrap()
}

/// A small HRBF fitted once (8 points of an ellipsoid), in `f64`.
pub fn hrbf_parts() -> &'static (Vec<HrbfCenter<f64>>, [f64; 4]) {
    static H: OnceLock<(Vec<HrbfCenter<f64>>, [f64; 4])> = OnceLock::new();
    H.get_or_init(|| {
        let mut p = Vec::new();
        let mut q = Vec::new();
        for i in 0..8 {
            let th = i as f64 * 0.8;
            let z = -0.9 + 0.25 * i as f64;
            let r = (1.0 - z * z).sqrt();
            let d = [r * th.cos(), r * th.sin(), z];
            p.push([0.8 * d[0], 0.5 * d[1], 0.6 * d[2]]);
            q.push([d[0] / 0.8, d[1] / 0.5, d[2] / 0.6]);
        }
        let h = Hrbf::<f64, _>::fit(&p, &q).unwrap();
        (h.centers().to_vec(), h.poly())
    })
}

pub fn make_hrbf<T: Flt>() -> Hrbf<T, Vec<HrbfCenter<T>>> {
    let (c, poly) = hrbf_parts();
    let c = c
        .iter()
        .map(|c| HrbfCenter {
            center: c.center.map(T::from_f64),
            alpha: T::from_f64(c.alpha),
            beta: c.beta.map(T::from_f64),
        })
        .collect();
    Hrbf::from_parts(c, poly.map(T::from_f64)).unwrap()
}

#[derive(Clone, Debug)]
pub struct Case {
    pub variant: u32,
    pub iso: f64,
    pub a: Vec<BDesc>,
    pub b: Vec<BDesc>,
    pub origin: [f64; 3],
    pub dir: [f64; 3],
    /// `t0 = t0_k / 1024`, `h = h_k / 1024`: dyadic, exact samples.
    pub t0_k: i32,
    pub h_k: i32,
}

pub fn case() -> impl Strategy<Value = Case> {
    (
        0u32..6,
        0.1f64..1.0,
        prop::collection::vec(bdesc(), 1..4),
        prop::collection::vec(bdesc(), 1..3),
        prop::array::uniform3(-2.5f64..2.5),
        prop::array::uniform3(-1.0f64..1.0),
        -1024i32..4096,
        prop_oneof![1i32..64, 64i32..2048],
    )
        .prop_map(|(variant, iso, a, b, origin, dir, t0_k, h_k)| Case {
            variant,
            iso,
            a,
            b,
            origin,
            dir,
            t0_k,
            h_k,
        })
}

/// Checks every bound type of `f` on the case's ray and interval.
pub fn check_field<T: Flt, F: Field<T>>(f: &F, c: &Case, what: &str) -> Result<(), TestCaseError> {
    let ray = Ray::new(c.origin.map(T::from_f64), c.dir.map(T::from_f64));
    let scale = T::from_f64(1.0 / 1024.0);
    let t0 = T::from_f64(f64::from(c.t0_k)) * scale;
    let h = T::from_f64(f64::from(c.h_k)) * scale;
    let t1 = t0 + h;
    let iv: Interval<T> = f.eval(ray.at(t0, t1));
    let af: Affine<T, 4> = f.eval(ray.at(t0, t1));
    let afr = af.enclosure();
    let mut lin: Vec<(&str, ForwardLinear<T>)> = Vec::new();
    let mut quad: Vec<(&str, ForwardQuadratic<T>)> = Vec::new();
    for (name, kind) in [
        ("bottom-up", BoundKind::BottomUp),
        ("taylor", BoundKind::Taylor),
        ("mixed", BoundKind::Mixed),
    ] {
        if let Some(b) = linear_bound(f, &ray, t0, t1, kind) {
            lin.push((name, b));
        }
        if let Some(b) = quadratic_bound(f, &ray, t0, t1, kind) {
            quad.push((name, b));
        }
    }
    for k in 0..=16 {
        let tau = T::from_f64(f64::from(c.h_k) * f64::from(k) / 16.0) * scale;
        let t = t0 + tau; // exact: dyadic with few bits
        let r: Interval<T> = f.eval(ray.at(t, t));
        if r.is_empty() {
            continue; // undefined at t (inverse kernel at its center)
        }
        let meets = |b: Interval<T>| !b.intersection(r).is_empty();
        prop_assert!(meets(iv), "{what}: Interval {iv:?} misses {r:?} at t={t}");
        prop_assert!(meets(afr), "{what}: Affine {afr:?} misses {r:?} at t={t}");
        for (name, b) in &lin {
            if b.is_valid() && tau <= b.validity() {
                let v = b.bounds_at(tau);
                prop_assert!(
                    meets(v),
                    "{what}: linear {name} {v:?} misses {r:?} at t0={t0} τ={tau} ({b:?})"
                );
            }
        }
        for (name, b) in &quad {
            if b.is_valid() && tau <= b.validity() {
                let v = b.bounds_at(tau);
                prop_assert!(
                    meets(v),
                    "{what}: quadratic {name} {v:?} misses {r:?} at t0={t0} τ={tau} ({b:?})"
                );
            }
        }
    }
    Ok(())
}

pub fn check_case<T: Flt>(c: &Case) -> Result<(), TestCaseError> {
    let a = make_blobs::<T>(c.iso, &c.a);
    match c.variant {
        0 => {
            // one blob alone: every kernel on its own
            let one = make_blobs::<T>(c.iso, &c.a[..1]);
            check_field(&one, c, "single blob")
        }
        1 => check_field(&a, c, "blob sum"),
        2 => {
            let u = Union {
                a,
                b: make_blobs::<T>(c.iso, &c.b),
            };
            check_field(&u, c, "union (max of densities)")
        }
        4 => {
            let r =
                Ricci::new(T::from_f64(c.iso), T::TWO, a, make_blobs::<T>(c.iso, &c.b)).unwrap();
            check_field(&r, c, "Ricci blend (n = 2)")
        }
        5 => {
            let i = Intersection {
                a,
                b: make_blobs::<T>(c.iso, &c.b),
            };
            check_field(&i, c, "intersection (min of densities)")
        }
        _ => {
            let s = Sum {
                iso: T::ZERO,
                a,
                b: make_hrbf::<T>(),
            };
            check_field(&s, c, "blob sum + HRBF")
        }
    }
}
