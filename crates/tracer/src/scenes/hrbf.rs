//! `hrbf-8`, `hrbf-17`: HRBF fits (forward-inclusion paper Fig. 13).

use super::rng::{Rng, fibonacci_sphere, normalize, rotate};
use super::{Built, Frame, GenError, SceneField};
use boundtrace_fields::hrbf::{Hrbf, HrbfCenter};
use boundtrace_ia_core::Real;
use boundtrace_inclusion::Field;

/// The ellipsoid the points are sampled on.
const RADII: [f64; 3] = [1.0, 0.75, 0.55];
/// Half-extent of the natural-frame bounds (the ellipsoid's bounding ball
/// grown by 50 %).
const HALF: f64 = 1.5;
/// Samples per face side in the build-time check.
const FACE_SAMPLES: usize = 33;

/// The smallest field value on a `FACE_SAMPLES²` grid of each face.
fn min_on_faces<F: Field<f64>>(f: &F, lo: [f64; 3], hi: [f64; 3]) -> f64 {
    let mut m = f64::INFINITY;
    let n = FACE_SAMPLES - 1;
    for axis in 0..3 {
        for side in [lo[axis], hi[axis]] {
            for i in 0..=n {
                for j in 0..=n {
                    let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                    let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
                    let mut p = [0.0; 3];
                    p[axis] = side;
                    p[a] = lo[a] + u * (hi[a] - lo[a]);
                    p[b] = lo[b] + v * (hi[b] - lo[b]);
                    m = m.min(f.eval(p));
                }
            }
        }
    }
    m
}

/// An HRBF through `n` points of a (rotated, jittered) ellipsoid.
pub(crate) fn build<T: Real>(seed: u64, n: usize) -> Result<Built<T>, GenError> {
    let mut rng = Rng::new(seed, 3 + n as u64);
    let q = rng.quaternion();
    let mut pts = Vec::with_capacity(n);
    let mut nrm = Vec::with_capacity(n);
    for s in fibonacci_sphere(n) {
        let s = normalize([0, 1, 2].map(|k| s[k] + rng.range(-0.05, 0.05)));
        let p = [0, 1, 2].map(|k| RADII[k] * s[k]);
        let g = [0, 1, 2].map(|k| s[k] / RADII[k]);
        pts.push(rotate(q, p));
        nrm.push(rotate(q, normalize(g)));
    }
    let lo = [-HALF; 3];
    let hi = [HALF; 3];
    let frame = Frame::fit(lo, hi);
    let bounds = frame.bounds(lo, hi, 0.0);
    let mut shrink = 1.0;
    for _ in 0..8 {
        let scaled: Vec<[f64; 3]> = pts
            .iter()
            .map(|&p| frame.point(p).map(|x| x * shrink))
            .collect();
        let fit = Hrbf::<f64, _>::fit(&scaled, &nrm)?;
        if min_on_faces(&fit, bounds[0], bounds[1]) > 1e-3 && fit.eval([0.0f64; 3]) < 0.0 {
            let centers: Vec<HrbfCenter<T>> = fit
                .centers()
                .iter()
                .map(|c| HrbfCenter {
                    center: c.center.map(T::from_f64),
                    alpha: T::from_f64(c.alpha),
                    beta: c.beta.map(T::from_f64),
                })
                .collect();
            let field = Hrbf::from_parts(centers, fit.poly().map(T::from_f64))?;
            return Ok(Built {
                field: SceneField::Hrbf(field),
                bounds,
                inside: [0.0; 3],
                primitives: n,
                description: format!(
                    "HRBF (phi = r^3) fitted to {n} points with normals on an ellipsoid (1, 0.75, 0.55); forward-inclusion paper Fig. 13"
                ),
            });
        }
        shrink *= 0.85;
    }
    Err(GenError::Check(
        "the HRBF fit is not positive on the faces of its bounds",
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fits_interpolate_and_are_positive_on_faces() {
        for n in [8, 17] {
            for seed in [1, 2, 2023] {
                let b: Built<f64> = build(seed, n).ok().unwrap();
                let SceneField::Hrbf(h) = &b.field else {
                    unreachable!()
                };
                assert_eq!(h.centers().len(), n);
                // zero at every center (the fitted points)
                for c in h.centers() {
                    assert!(h.eval(c.center).abs() < 1e-6);
                }
                assert!(min_on_faces(h, b.bounds[0], b.bounds[1]) > 0.0);
            }
        }
    }
}
