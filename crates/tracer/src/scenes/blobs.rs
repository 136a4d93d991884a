//! `blobs`, `blobs-sum` (forward-inclusion paper eq. 20) and `molecule`
//! (§7.1): point-blob scenes.

use super::rng::{Rng, add_scaled, dist, normalize};
use super::{Built, Frame, GenError, SceneField, WithLipschitz, box_union, grid_lipschitz};
use boundtrace_fields::density::UnionAll;
use boundtrace_fields::{Blobs, Kernel, PointBlob};
use boundtrace_ia_core::Real;

/// Blob groups and blobs per group (paper eq. 20).
const GROUPS: usize = 4;
const PER_GROUP: usize = 8;
/// The compact kernel degree of the blob scenes.
const DEGREE: u32 = 6;
const BLOB_ISO: f64 = 0.5;

/// One blob in `f64`: center, support radius `σ`, weight.
#[derive(Clone, Copy)]
struct Spec {
    c: [f64; 3],
    sigma: f64,
    w: f64,
}

fn blob_set<T: Real>(
    iso: f64,
    specs: &[Spec],
    kernel: impl Fn(T) -> Result<Kernel<T>, boundtrace_fields::FieldError>,
) -> Result<Blobs<T, Vec<PointBlob<T>>>, GenError> {
    let blobs = specs
        .iter()
        .map(|s| {
            PointBlob::new(
                s.c.map(T::from_f64),
                T::from_f64(s.w),
                kernel(T::from_f64(s.sigma))?,
            )
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Blobs::new(T::from_f64(iso), blobs)?)
}

/// `blobs` (`sum = false`: sharp union of the groups) and `blobs-sum`.
pub(crate) fn groups<T: Real>(seed: u64, sum: bool) -> Result<Built<T>, GenError> {
    let mut rng = Rng::new(seed, 1);
    let mut groups: Vec<Vec<Spec>> = Vec::with_capacity(GROUPS);
    for _ in 0..GROUPS {
        let center = rng.in_ball(0.6);
        let g = (0..PER_GROUP)
            .map(|_| Spec {
                c: add_scaled(center, 1.0, rng.in_ball(0.3)),
                sigma: rng.range(0.3, 0.45),
                w: 1.0,
            })
            .collect();
        groups.push(g);
    }
    let [lo, hi] = box_union(
        groups
            .iter()
            .flatten()
            .map(|s| [s.c.map(|x| x - s.sigma), s.c.map(|x| x + s.sigma)]),
    );
    let frame = Frame::fit(lo, hi);
    for s in groups.iter_mut().flatten() {
        s.c = frame.point(s.c);
        s.sigma = frame.length(s.sigma);
    }
    let bounds = frame.bounds(lo, hi, 0.02);
    let inside = groups[0][0].c;
    let kernel = |s: T| Kernel::compact(DEGREE, s);
    let field = if sum {
        let all: Vec<Spec> = groups.iter().flatten().copied().collect();
        SceneField::Blobs(blob_set(BLOB_ISO, &all, kernel)?)
    } else {
        let sets = groups
            .iter()
            .map(|g| blob_set(BLOB_ISO, g, kernel))
            .collect::<Result<Vec<_>, _>>()?;
        SceneField::BlobGroups(UnionAll::new(sets)?)
    };
    let what = if sum {
        "sum of 32 compact (degree 6) point blobs (the `blobs` layout blended for transparency); forward-inclusion paper §7.2"
    } else {
        "sharp union (max of densities) of 4 groups of 8 summed compact (degree 6) point blobs; forward-inclusion paper eq. 20"
    };
    Ok(Built {
        field,
        bounds,
        inside,
        primitives: GROUPS * PER_GROUP,
        description: format!("{what}; 32 primitives"),
    })
}

/// Atoms of the molecule.
const ATOMS: usize = 500;
const BOND: f64 = 1.5;
/// Gaussian sharpness `s` of `e^{−s(d/r)²}` (paper eq. 6).
const SHARPNESS: f64 = 2.0;
const MOL_ISO: f64 = 1.0;

/// `max_{d ≥ dmin} |k'(d)|` of `k(d) = e^{−d²/σ²}` (`k'` peaks at
/// `d = σ/√2`), slightly rounded up.
fn gaussian_slope(sigma: f64, dmin: f64) -> f64 {
    let peak = sigma * std::f64::consts::FRAC_1_SQRT_2;
    let d = dmin.max(peak);
    2.0 * d / (sigma * sigma) * (-(d * d) / (sigma * sigma)).exp() * (1.0 + 1e-9)
}

/// The distance from `p` to the box `[a, b]`.
fn box_distance(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let q = [0, 1, 2].map(|k| (a[k] - p[k]).max(p[k] - b[k]).max(0.0));
    dist(q, [0.0; 3])
}

/// `molecule`: Gaussian atoms on a compact self-avoiding random walk.
pub(crate) fn molecule<T: Real>(seed: u64) -> Result<Built<T>, GenError> {
    let mut rng = Rng::new(seed, 2);
    let mut atoms: Vec<Spec> = Vec::with_capacity(ATOMS);
    let weight = SHARPNESS.exp();
    let mut pos = [0.0; 3];
    for i in 0..ATOMS {
        if i > 0 {
            let mut best = pos;
            for _ in 0..24 {
                // a random step pulled towards the origin folds the chain
                let pull = pos.map(|x| -0.05 * x);
                let d = normalize(add_scaled(rng.direction(), 1.0, pull));
                let cand = add_scaled(pos, BOND, d);
                best = cand;
                let n = atoms.len();
                if atoms[..n.saturating_sub(1)]
                    .iter()
                    .all(|a| dist(a.c, cand) >= 1.2 * BOND)
                {
                    break;
                }
            }
            pos = best;
        }
        let u = rng.unit();
        let r = if u < 0.6 {
            1.7 // C
        } else if u < 0.77 {
            1.55 // N
        } else if u < 0.97 {
            1.52 // O
        } else {
            1.8 // S
        };
        atoms.push(Spec {
            c: pos,
            sigma: r / SHARPNESS.sqrt(),
            w: weight,
        });
    }
    // N·w·e^{−m²/σ²} ≤ iso/4 beyond the margin m
    let smax = atoms.iter().map(|a| a.sigma).fold(0.0, f64::max);
    let margin = smax * (4.0 * ATOMS as f64 * weight / MOL_ISO).ln().sqrt();
    let [clo, chi] = box_union(atoms.iter().map(|a| [a.c, a.c]));
    let lo = clo.map(|x| x - margin);
    let hi = chi.map(|x| x + margin);
    let frame = Frame::fit(lo, hi);
    for a in &mut atoms {
        a.c = frame.point(a.c);
        a.sigma = frame.length(a.sigma);
    }
    let bounds = frame.bounds(lo, hi, 0.0);
    let [blo, bhi] = bounds;
    // Lipschitz on a grid (module docs)
    let outside: f64 = atoms
        .iter()
        .map(|a| {
            let d = (0..3)
                .map(|k| (a.c[k] - blo[k]).min(bhi[k] - a.c[k]))
                .fold(f64::INFINITY, f64::min)
                .max(0.0);
            a.w * gaussian_slope(a.sigma, d)
        })
        .sum();
    let lip = grid_lipschitz(bounds, 16, outside, |a, b| {
        atoms
            .iter()
            .map(|s| s.w * gaussian_slope(s.sigma, box_distance(s.c, a, b)))
            .sum()
    });
    let inside = atoms[ATOMS / 2].c;
    let field = blob_set(MOL_ISO, &atoms, |s: T| Kernel::gaussian(s))?;
    Ok(Built {
        field: SceneField::Molecule(WithLipschitz {
            field,
            lipschitz: T::from_f64(lip),
        }),
        bounds,
        inside,
        primitives: ATOMS,
        description: format!(
            "molecule: {ATOMS} Gaussian atoms (e^(-2(d/r)^2), C/N/O/S radii) on a compact random-walk chain, summed; forward-inclusion paper §7.1, Fig. 14-15"
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use boundtrace_inclusion::Field;

    #[test]
    fn gaussian_slope_bounds_the_derivative() {
        let s = 0.7;
        for i in 0..200 {
            let d = 0.01 * f64::from(i);
            let k1 = 2.0 * d / (s * s) * (-(d * d) / (s * s)).exp();
            // the bound from any smaller distance covers it
            assert!(gaussian_slope(s, d * 0.5) >= k1 && gaussian_slope(s, d) >= k1);
        }
        assert!(box_distance([2.0, 0.5, 0.5], [0.0; 3], [1.0; 3]) == 1.0);
    }

    #[test]
    fn molecule_lipschitz_holds_on_samples() {
        let b: Built<f64> = molecule(3).ok().unwrap();
        let l = b.field.lipschitz().unwrap();
        let mut rng = Rng::new(99, 0);
        for _ in 0..300 {
            let p = rng.in_ball(0.9);
            let q = add_scaled(p, 0.01, rng.direction());
            let (fp, fq): (f64, f64) = (b.field.eval(p), b.field.eval(q));
            assert!((fp - fq).abs() <= l * dist(p, q) * (1.0 + 1e-9));
        }
        // much tighter than the sum over all atoms
        let SceneField::Molecule(m) = &b.field else {
            unreachable!()
        };
        assert!(l < 0.2 * m.field().lipschitz().unwrap());
    }
}
