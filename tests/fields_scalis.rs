//! SCALIS segments (`boundtrace::fields::scalis`) and segment primitives
//! (`boundtrace::fields::homothetic`): closed forms against adaptive
//! quadrature, normalization, scale invariance, gradients, containment of
//! every bound kind, argmin along rays, parameter validation.

mod common;

use boundtrace::fields::homothetic::{Segment, SegmentKernel};
use boundtrace::fields::scalis::{Normalized, ScalisSegment, ScalisSkeleton};
use boundtrace::ia_core::{Affine, Interval};
use boundtrace::inclusion::{
    BoundKind, Field, FieldNum, ForwardLinear, ForwardQuadratic, Jet, Ray, gradient, linear_bound,
    quadratic_bound,
};
use proptest::prelude::*;

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
    0.209_482_141_084_728_0,
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
