//! SCALIS segments (`boundtrace::fields::scalis`) and segment primitives
//! (`boundtrace::fields::homothetic`): closed forms against adaptive
//! quadrature, normalization, scale invariance, gradients, containment of
//! every bound kind, argmin along rays, parameter validation.

mod common;

use boundtrace::fields::homothetic::{Segment, SegmentKernel};
use boundtrace::fields::scalis::ScalisSegment;
use boundtrace::inclusion::{Field, Ray, gradient};
use proptest::prelude::*;

use common::scalis_cases::*;

/// A small deterministic generator (xorshift64*).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
    fn vec(&mut self, s: f64) -> [f64; 3] {
        [self.range(-s, s), self.range(-s, s), self.range(-s, s)]
    }
}

/// Gauss–Kronrod 7/15 nodes and weights on [−1, 1].
const XK: [f64; 8] = [
    0.991_455_371_120_812_6,
    0.949_107_912_342_758_5,
    0.864_864_423_359_769_1,
    0.741_531_185_599_394_4,
    0.586_087_235_467_691_1,
    0.405_845_151_377_397_2,
    0.207_784_955_007_898_5,
    0.0,
];
const WK: [f64; 8] = [
    0.022_935_322_010_529_22,
    0.063_092_092_629_978_55,
    0.104_790_010_322_250_2,
    0.140_653_259_715_525_9,
    0.169_004_726_639_267_9,
    0.190_350_578_064_785_4,
    0.204_432_940_075_298_9,
    0.209_482_141_084_728,
];
const WG: [f64; 4] = [
    0.129_484_966_168_869_7,
    0.279_705_391_489_276_7,
    0.381_830_050_505_118_9,
    0.417_959_183_673_469_4,
];

fn gk15(f: &dyn Fn(f64) -> f64, a: f64, b: f64) -> (f64, f64) {
    let c = 0.5 * (a + b);
    let h = 0.5 * (b - a);
    let fc = f(c);
    let mut k = WK[7] * fc;
    let mut g = WG[3] * fc;
    for i in 0..7 {
        let x = h * XK[i];
        let s = f(c - x) + f(c + x);
        k += WK[i] * s;
        if i % 2 == 1 {
            g += WG[i / 2] * s;
        }
    }
    (k * h, ((k - g) * h).abs())
}

/// Adaptive Gauss–Kronrod quadrature with an explicit stack (absolute
/// tolerance `tol`).
fn quad(f: &dyn Fn(f64) -> f64, a: f64, b: f64, tol: f64) -> f64 {
    let mut stack = vec![(a, b, tol)];
    let mut sum = 0.0;
    while let Some((a, b, tol)) = stack.pop() {
        let (v, err) = gk15(f, a, b);
        if err <= tol || (b - a) < 1e-12 * (1.0 + a.abs()) || stack.len() > 2000 {
            sum += v;
        } else {
            let m = 0.5 * (a + b);
            stack.push((a, m, tol * 0.5));
            stack.push((m, b, tol * 0.5));
        }
    }
    sum
}

/// Reference density and gradient by quadrature of eq. 1.14.
fn reference(s: &ScalisSegment<f64>, p: [f64; 3]) -> (f64, [f64; 3]) {
    let seg = s.segment();
    let (sig, kernel) = (s.kernel().sigma(), s.kernel());
    let l = seg.length();
    let kf = |h2: f64| -> (f64, f64) {
        // k(h²) and dk/d(h²)
        match kernel {
            SegmentKernel::CompactPolynomial { degree, .. } => {
                let m = (degree / 2) as i32;
                let u = 1.0 - h2 / (sig * sig);
                if u <= 0.0 {
                    (0.0, 0.0)
                } else {
                    (u.powi(m), -(m as f64) * u.powi(m - 1) / (sig * sig))
                }
            }
            SegmentKernel::Cauchy { .. } => {
                let b = 1.0 + h2 / (sig * sig);
                (b.powf(-1.5), -1.5 * b.powf(-2.5) / (sig * sig))
            }
        }
    };
    // split at the support roots for compact kernels
    let mut cuts = vec![0.0, l];
    let n = 4096;
    let mut prev = None;
    for i in 0..=n {
        let si = l * i as f64 / n as f64;
        let q = seg.point_at(si);
        let tau = seg.radius_at(si);
        let d2: f64 = (0..3).map(|k| (p[k] - q[k]).powi(2)).sum();
        let inside = d2 < sig * sig * tau * tau;
        if let Some(pv) = prev {
            if pv != inside {
                // bisect the root
                let (mut lo, mut hi) = (l * (i - 1) as f64 / n as f64, si);
                for _ in 0..80 {
                    let mid = 0.5 * (lo + hi);
                    let q = seg.point_at(mid);
                    let t = seg.radius_at(mid);
                    let d2: f64 = (0..3).map(|k| (p[k] - q[k]).powi(2)).sum();
                    if (d2 < sig * sig * t * t) == pv {
                        lo = mid
                    } else {
                        hi = mid
                    }
                }
                cuts.push(0.5 * (lo + hi));
            }
        }
        prev = Some(inside);
    }
    // and near the closest skeleton point (peaked integrands near the line)
    let (x, _) = seg.axial(p);
    if x > 0.0 && x < l {
        cuts.push(x);
    }
    cuts.sort_by(|a, b| a.partial_cmp(b).unwrap());
    let comp = |k: usize, s_: f64| -> f64 {
        let q = seg.point_at(s_);
        let tau = seg.radius_at(s_);
        let w = [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
        let h2 = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]) / (tau * tau);
        let (kv, dk) = kf(h2);
        if k == 3 {
            kv / tau
        } else {
            dk * 2.0 * w[k] / (tau * tau * tau)
        }
    };
    let mut out = [0.0; 4];
    for (k, o) in out.iter_mut().enumerate() {
        let kk = if k == 0 { 3 } else { k - 1 };
        let mut acc = 0.0;
        for w in cuts.windows(2) {
            if w[1] > w[0] {
                acc += quad(&|s_| comp(kk, s_), w[0], w[1], 1e-14);
            }
        }
        *o = acc * s.inv_normalization();
    }
    (out[0], [out[1], out[2], out[3]])
}

fn random_scalis(rng: &mut Rng, kernel: SegmentKernel<f64>) -> ScalisSegment<f64> {
    loop {
        let a = rng.vec(2.0);
        let b = rng.vec(2.0);
        let ra = rng.range(0.1, 1.0);
        let rb = if rng.next() < 0.3 {
            ra
        } else {
            rng.range(0.1, 1.0)
        };
        if let Ok(seg) = Segment::new(a, ra, b, rb) {
            if let Ok(s) = ScalisSegment::new(seg, kernel, 1.0) {
                return s;
            }
        }
    }
}

/// A query point: random near the segment, near its line, near an end-point.
fn random_point(rng: &mut Rng, s: &ScalisSegment<f64>) -> [f64; 3] {
    let seg = s.segment();
    let scale = seg.ra().max(seg.rb()) * s.kernel().sigma();
    match (rng.next() * 4.0) as u32 {
        0 => {
            // near the line
            let q = seg.point_at(rng.range(-0.2, 1.2) * seg.length());
            let e = rng.vec(1e-4 * scale);
            [q[0] + e[0], q[1] + e[1], q[2] + e[2]]
        }
        1 => {
            // near an end-point
            let q = if rng.next() < 0.5 { seg.a() } else { seg.b() };
            let e = rng.vec(0.3 * scale);
            [q[0] + e[0], q[1] + e[1], q[2] + e[2]]
        }
        _ => {
            let q = seg.point_at(rng.next() * seg.length());
            let e = rng.vec(scale);
            [q[0] + e[0], q[1] + e[1], q[2] + e[2]]
        }
    }
}

fn check_against_quadrature(kernel: SegmentKernel<f64>, cases: usize, seed: u64) {
    let mut rng = Rng(seed);
    let mut worst = (0.0f64, 0.0f64);
    for _ in 0..cases {
        let s = random_scalis(&mut rng, kernel);
        let p = random_point(&mut rng, &s);
        let (f, g) = s.density_gradient(p);
        let (fr, gr) = reference(&s, p);
        // relative to the value, with an absolute floor of 1e-9 of the
        // field's scale (the iso-value is 1)
        let ef = (f - fr).abs() / fr.abs().max(1e-3);
        let gn = (gr[0] * gr[0] + gr[1] * gr[1] + gr[2] * gr[2]).sqrt();
        // the gradient is a difference of terms of size ~f/r: where it
        // nearly cancels (the middle of a wide support) it is measured
        // relative to that scale
        let gscale = fr.abs().max(1e-3) / s.segment().ra().min(s.segment().rb());
        let eg = (0..3).map(|k| (g[k] - gr[k]).abs()).fold(0.0, f64::max) / gn.max(1e-3 * gscale);
        assert!(
            ef <= 1e-6 && eg <= 1e-6,
            "{s:?} at {p:?}: f {f} vs {fr} ({ef:e}), grad {g:?} vs {gr:?} ({eg:e})"
        );
        worst = (worst.0.max(ef), worst.1.max(eg));
    }
    println!(
        "worst relative errors: value {:e}, gradient {:e}",
        worst.0, worst.1
    );
}

#[test]
fn compact_closed_form_matches_quadrature() {
    for degree in [2, 4, 6, 8] {
        for sigma in [1.5, 2.0, 3.0] {
            let k = SegmentKernel::compact_polynomial(degree, sigma).unwrap();
            check_against_quadrature(k, 60, 0x5eed + degree as u64 * 7 + sigma as u64);
        }
    }
}

#[test]
fn cauchy_closed_form_matches_quadrature() {
    for sigma in [0.5, 1.0, 2.0] {
        let k = SegmentKernel::cauchy(3, sigma).unwrap();
        check_against_quadrature(k, 80, 0xcafe + sigma as u64);
    }
}

/// Long constant-radius segments along x through the origin.
fn long_segment(kernel: SegmentKernel<f64>, r: f64, iso: f64) -> ScalisSegment<f64> {
    let half = 2000.0 * r;
    let seg = Segment::new([-half, 0.0, 0.0], r, [half, 0.0, 0.0], r).unwrap();
    ScalisSegment::new(seg, kernel, iso).unwrap()
}

#[test]
fn normalization_puts_the_surface_at_the_radius() {
    let kernels = [
        compact(2, 1.5),
        compact(4, 2.0),
        compact(6, 1.5),
        compact(6, 2.0),
        compact(8, 3.0),
        cauchy(0.5),
        cauchy(1.0),
        cauchy(2.0),
    ];
    for k in kernels {
        for (r, iso) in [(1.0, 1.0), (0.3, 0.5), (2.5, 2.0)] {
            let s = long_segment(k, r, iso);
            let dir = [0.0, 0.6, 0.8];
            let f = |d: f64| s.eval([0.0, d * dir[1], d * dir[2]]);
            let (mut lo, mut hi) = (0.0, 3.0 * r);
            assert!(f(lo) < 0.0 && f(hi) > 0.0, "{k:?}: no sign change");
            for _ in 0..200 {
                let m = 0.5 * (lo + hi);
                if f(m) < 0.0 { lo = m } else { hi = m }
            }
            let root = 0.5 * (lo + hi);
            assert!((root - r).abs() <= 1e-4 * r, "{k:?} r={r}: root {root}");
        }
    }
}

#[test]
fn g_is_the_squared_homothetic_distance_of_a_line() {
    for k in [
        compact(6, 2.0),
        compact(4, 1.5),
        compact(8, 3.0),
        cauchy(1.0),
        cauchy(2.0),
    ] {
        let r = 0.7;
        let s = long_segment(k, r, 1.0);
        // inside the support for compact kernels: d/r < σ
        let dmax = if matches!(k, SegmentKernel::Cauchy { .. }) {
            5.0
        } else {
            0.95 * k.sigma()
        };
        for i in 0..40 {
            let dn = dmax * i as f64 / 40.0;
            let p = [0.3, dn * r, 0.0];
            let g: f64 = s.g(s.density(p));
            assert!(
                (g - dn * dn).abs() <= 1e-4 * (dn * dn).max(1.0),
                "{k:?}: g = {g}, (d/r)² = {}",
                dn * dn
            );
            let n: f64 = s.normalized(p);
            if (dn - 1.0).abs() > 1e-3 {
                assert_eq!(n > 0.0, dn > 1.0, "sign at {dn}");
            }
        }
        // beyond the support of a compact kernel g = σ²
        if let SegmentKernel::CompactPolynomial { sigma, .. } = k {
            let g: f64 = s.g(s.density([0.0, 1.1 * sigma * r, 0.0]));
            assert!((g - sigma * sigma).abs() < 1e-12);
        }
    }
}

#[test]
fn scale_invariance() {
    let mut rng = Rng(77);
    for k in [compact(6, 2.0), compact(4, 1.5), cauchy(1.0)] {
        for _ in 0..300 {
            let s = random_scalis(&mut rng, k);
            let p = random_point(&mut rng, &s);
            let sc = rng.range(0.01, 100.0);
            let seg = s.segment();
            let m = |v: [f64; 3]| v.map(|x| x * sc);
            let ss = ScalisSegment::new(
                Segment::new(m(seg.a()), seg.ra() * sc, m(seg.b()), seg.rb() * sc).unwrap(),
                k,
                1.0,
            )
            .unwrap();
            let (f, fs): (f64, f64) = (s.density(p), ss.density(m(p)));
            assert!(
                (f - fs).abs() <= 1e-9 * f.abs().max(1e-3),
                "{f} vs {fs} at scale {sc}"
            );
            let (n, ns): (f64, f64) = (s.normalized(p), ss.normalized(m(p)));
            if n.abs() > 1e-6 {
                assert_eq!(n > 0.0, ns > 0.0);
            }
        }
    }
}

#[test]
fn gradients_match_finite_differences() {
    let mut rng = Rng(99);
    for k in [
        compact(2, 1.5),
        compact(6, 2.0),
        compact(8, 3.0),
        cauchy(0.5),
        cauchy(2.0),
    ] {
        for _ in 0..200 {
            let s = random_scalis(&mut rng, k);
            let p = random_point(&mut rng, &s);
            let (_, ga) = s.density_gradient(p);
            let gj = gradient(&s, p); // of iso − f
            let h = 1e-5 * s.segment().ra().min(s.segment().rb());
            for i in 0..3 {
                let (mut a, mut b) = (p, p);
                a[i] += h;
                b[i] -= h;
                let fd = (s.density(a) - s.density(b)) / (2.0 * h);
                let scale = s.density(p).abs().max(1e-2) / s.segment().ra().min(s.segment().rb());
                assert!(
                    (ga[i] - fd).abs() <= 1e-4 * scale,
                    "analytic {ga:?} vs fd {fd} ({k:?})"
                );
                assert!(
                    (ga[i] + gj[i]).abs() <= 1e-9 * scale,
                    "jet {gj:?} vs analytic {ga:?}"
                );
                assert!(
                    (-gj[i] - fd).abs() <= 1e-4 * scale,
                    "jet {gj:?} vs fd {fd} ({k:?})"
                );
            }
        }
    }
}

#[test]
fn second_derivatives_match_finite_differences() {
    let mut rng = Rng(101);
    for k in [compact(4, 1.5), compact(6, 2.0), compact(8, 3.0)] {
        for _ in 0..300 {
            let s = random_scalis(&mut rng, k);
            let p = random_point(&mut rng, &s);
            let d = rng.vec(1.0);
            let f2 = s.second_derivative_generic(p, d).unwrap();
            let r = s.segment().ra().min(s.segment().rb());
            // central difference of the closed-form directional derivative
            // (a second difference of values would amplify the ~1e-10
            // relative noise of the partial fractions by 1/h²)
            let h = 1e-4 * r;
            let at = |t: f64| -> f64 { s.density([0, 1, 2].map(|i| p[i] + t * d[i])) };
            let dir = |t: f64| -> f64 {
                let g = s.density_gradient([0, 1, 2].map(|i| p[i] + t * d[i])).1;
                g[0] * d[0] + g[1] * d[1] + g[2] * d[2]
            };
            let fd = (dir(h) - dir(-h)) / (2.0 * h);
            let scale = at(0.0).abs().max(1e-2) / (r * r);
            let jj = boundtrace::inclusion::jet_at(&s, &Ray::new(p, d), 0.0);
            assert!(
                (f2 - fd).abs() <= 1e-3 * scale,
                "f'' {f2} vs fd {fd}, jet {} ({k:?}) {s:?} at {p:?} along {d:?}",
                -jj.d2
            );
            // and the jet's second derivative along the same direction
            let ray = Ray::new(p, d);
            let j = boundtrace::inclusion::jet_at(&s, &ray, 0.0);
            assert!((-j.d2 - f2).abs() <= 1e-8 * scale, "jet {} vs {f2}", -j.d2);
        }
    }
    assert!(
        ScalisSegment::new(
            Segment::new([0.0; 3], 1.0, [1.0, 0.0, 0.0], 1.0).unwrap(),
            compact(2, 2.0),
            1.0
        )
        .unwrap()
        .second_derivative_generic([0.0; 3], [1.0, 0.0, 0.0])
        .is_none()
    );
}

#[test]
fn argmin_along_ray_matches_dense_sampling() {
    let mut rng = Rng(5);
    for _ in 0..300 {
        let (a, b) = (rng.vec(2.0), rng.vec(2.0));
        let seg = Segment::new(a, rng.range(0.05, 1.0), b, rng.range(0.05, 1.0)).unwrap();
        let ray = Ray::new(rng.vec(4.0), rng.vec(1.0));
        let (t, s_min, h2) = seg.argmin_along_ray(&ray).unwrap();
        let at = |t: f64| -> [f64; 3] { [0, 1, 2].map(|k| ray.origin[k] + t * ray.dir[k]) };
        // the minimum over the line of h_S(δ(t))², sampled densely around t
        let mut best = f64::INFINITY;
        for i in 0..=20000 {
            let ti = t - 20.0 + 40.0 * i as f64 / 20000.0;
            best = best.min(seg.homothetic_sq(at(ti)));
        }
        let here: f64 = seg.homothetic_sq(at(t));
        assert!(
            here <= best + 1e-9 * best.max(1.0),
            "{here} > sampled {best}"
        );
        assert!(
            (here - h2).abs() <= 1e-9 * h2.max(1.0),
            "{here} vs reported {h2}"
        );
        assert!((0.0..=seg.length()).contains(&s_min));
    }
}

#[test]
fn bad_parameters_are_rejected() {
    let o = [0.0; 3];
    let x = [1.0, 0.0, 0.0];
    for (ra, rb) in [
        (0.0, 1.0),
        (1.0, -0.5),
        (f64::NAN, 1.0),
        (1.0, f64::INFINITY),
    ] {
        assert!(Segment::new(o, ra, x, rb).is_err());
    }
    assert!(Segment::new(o, 1.0, o, 1.0).is_err());
    assert!(Segment::new([f64::NAN, 0.0, 0.0], 1.0, x, 1.0).is_err());
    assert!(SegmentKernel::compact_polynomial(0, 2.0).is_err());
    assert!(SegmentKernel::compact_polynomial(1, 2.0).is_err());
    assert!(SegmentKernel::cauchy(1, 2.0).is_err());
    assert!(SegmentKernel::compact_polynomial(6, f64::NAN).is_err());
    let seg = Segment::new(o, 0.2, [4.0, 0.0, 0.0], 0.2).unwrap();
    // unsupported degrees, σ ≤ 1, iso ≤ 0, too steep radius variation
    assert!(ScalisSegment::new(seg, compact(10, 2.0), 1.0).is_err());
    assert!(ScalisSegment::new(seg, cauchy(1.0), 1.0).is_ok());
    assert!(ScalisSegment::new(seg, SegmentKernel::cauchy(4, 1.0).unwrap(), 1.0).is_err());
    assert!(ScalisSegment::new(seg, compact(6, 1.0), 1.0).is_err());
    assert!(ScalisSegment::new(seg, compact(6, 2.0), 0.0).is_err());
    assert!(ScalisSegment::new(seg, compact(6, 2.0), f64::NAN).is_err());
    let steep = Segment::new(o, 0.1, [1.0, 0.0, 0.0], 0.9).unwrap();
    assert!(ScalisSegment::new(steep, compact(6, 2.0), 1.0).is_err());
    let msg = ScalisSegment::new(seg, compact(6, 0.5), 1.0)
        .unwrap_err()
        .to_string();
    assert!(msg.contains("sigma"), "{msg}");
}

#[test]
fn cauchy_clipping_bounds_the_field() {
    let mut rng = Rng(1234);
    for _ in 0..200 {
        let k = cauchy(rng.range(0.5, 2.0));
        let s = random_scalis(&mut rng, k);
        let eps = 10f64.powf(rng.range(-6.0, -1.0));
        let scale = s.cauchy_clip_scale(eps);
        let cone = s.support(eps);
        assert_eq!(cone.ra, s.segment().ra() * scale);
        for _ in 0..20 {
            let q = s.segment().point_at(rng.next() * s.segment().length());
            let v = rng.vec(1.0);
            let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            let dist = rng.range(0.0, 3.0 * scale * s.segment().ra().max(s.segment().rb()));
            let p = [0, 1, 2].map(|k| q[k] + v[k] / n * dist);
            let h = s.segment().homothetic_distance(p);
            let f: f64 = s.density(p);
            if h > scale {
                assert!(f < eps, "f = {f} ≥ ε = {eps} at h = {h} > S = {scale}");
            }
        }
    }
    // compact kernels: the support is exact
    let s = long_segment(compact(6, 2.0), 1.0, 1.0);
    assert_eq!(s.support(0.1).ra, 2.0);
    assert_eq!(s.density([0.0, 2.0 + 1e-12, 0.0]), 0.0);
    assert!(s.density([0.0, 2.0 - 1e-3, 0.0]) > 0.0);
}

// ---------------------------------------------------------------------------
// Containment of every bound kind (property tests).

proptest! {
    #![proptest_config(common::config())]

    /// Interval, affine, forward linear/quadratic (bottom-up, Taylor,
    /// mixed), the per-primitive ranges and the directional-Lipschitz line
    /// contain the field at sampled points of the ray interval.
    #[test]
    fn bounds_contain_the_field(c in case()) {
        check_case(&c)?;
    }
}

/// The thesis' end-point monotony test (`density_range_unimodal`) on single
/// segments with varying radius: no violation on 2000 random rays (it
/// relies on the unimodality the thesis observes; a violation on a ray
/// without an interior local minimum would be a bug of the code).
#[test]
fn unimodal_range_contains_the_field() {
    let mut rng = Rng(4242);
    let (mut bad, mut explained) = (0, 0);
    let n = 2000;
    for _ in 0..n {
        let k = compact(6, rng.range(1.2, 3.0));
        let s = random_scalis(&mut rng, k);
        let ray = Ray::new(rng.vec(3.0), rng.vec(1.0));
        let t0 = rng.range(0.0, 4.0);
        let t1 = t0 + rng.range(0.01, 3.0);
        let r = s.density_range_unimodal(&ray, t0, t1);
        let full = s.density_range(&ray, t0, t1);
        let samples: Vec<f64> = (0..=400)
            .map(|i| s.density(ray.at(t0 + (t1 - t0) * i as f64 / 400.0, 0.0)))
            .collect();
        let mut violated = false;
        for &f in &samples {
            assert!(full.contains(f), "sound range {full:?} misses {f}");
            violated |= !r.contains(f);
        }
        if violated {
            bad += 1;
            // interior local minimum: some sample below both an earlier and
            // a later one by a clear margin
            let scale = samples.iter().cloned().fold(0.0, f64::max);
            let dip = (1..400).any(|i| {
                let before = samples[..i].iter().cloned().fold(0.0, f64::max);
                let after = samples[i + 1..].iter().cloned().fold(0.0, f64::max);
                samples[i] < before.min(after) - 1e-9 * scale
            });
            explained += dip as usize;
        }
    }
    println!("unimodal range: {bad} violations in {n} rays, {explained} on non-unimodal rays");
    assert_eq!(bad, explained, "violations on unimodal rays");
    assert_eq!(
        bad, 0,
        "non-unimodal rays found: the thesis' assumption fails"
    );
}

#[test]
fn f32_path_agrees_with_f64() {
    let mut rng = Rng(31);
    for k in [compact(6, 2.0), cauchy(1.0)] {
        for _ in 0..300 {
            let s = random_scalis(&mut rng, k);
            let p = random_point(&mut rng, &s);
            let seg = s.segment();
            let f = |v: [f64; 3]| v.map(|x| x as f32);
            let k32 = match k {
                SegmentKernel::CompactPolynomial { degree, sigma } => {
                    SegmentKernel::compact_polynomial(degree, sigma as f32).unwrap()
                }
                SegmentKernel::Cauchy { degree, sigma } => {
                    SegmentKernel::cauchy(degree, sigma as f32).unwrap()
                }
            };
            let s32 = ScalisSegment::new(
                Segment::new(f(seg.a()), seg.ra() as f32, f(seg.b()), seg.rb() as f32).unwrap(),
                k32,
                1.0f32,
            )
            .unwrap();
            let (d64, d32): (f64, f32) = (s.density(p), s32.density(f(p)));
            let (v32, g32) = s32.density_gradient(f(p));
            assert_eq!(v32, d32);
            assert!(g32.iter().all(|g| g.is_finite()));
            // f32 inputs are perturbed by ~1e-7 relative; the field's
            // gradient scale is ~f/r
            let tol = 1e-3 * d64.abs().max(1e-2) / seg.ra().min(seg.rb()).min(1.0);
            assert!(
                (d64 - d32 as f64).abs() <= tol,
                "f64 {d64} vs f32 {d32}: {s:?} at {p:?}"
            );
        }
    }
}

// ---------------------------------------------------------------------------
// Homothetic-distance primitives (eq. 1.13): containment of every bound kind.

proptest! {
    #![proptest_config(common::config())]

    /// `k ∘ h_S` and `h_S − 1`: interval, affine and forward bottom-up bounds
    /// contain the field at sampled ray points.
    #[test]
    fn homothetic_bounds_contain_the_field(c in hcase()) {
        check_homothetic(&c)?;
    }
}
