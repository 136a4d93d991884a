//! `scalis-tree`, `scalis-foam`, `scalis-random`: SCALIS skeletons (thesis
//! Part III ch. 1), the field `iso − Σ` of compact segments.

use super::rng::{Rng, add_scaled, dist, normalize, rotate};
use super::{Built, Frame, GenError, SceneField, WithLipschitz, box_union, grid_lipschitz};
use boundtrace_fields::homothetic::{Segment, SegmentKernel};
use boundtrace_fields::scalis::{ScalisSegment, ScalisSkeleton};
use boundtrace_ia_core::Real;
use boundtrace_inclusion::Field;
use std::collections::HashMap;

/// Kernel degree and scale of every SCALIS scene, and the iso-value.
const DEGREE: u32 = 6;
const SIGMA: f64 = 2.0;
const ISO: f64 = 1.0;

/// A segment in `f64`: `(a, r_a, b, r_b)`.
type Seg = ([f64; 3], f64, [f64; 3], f64);

fn make<T: Real>(s: &Seg) -> Result<ScalisSegment<T>, GenError> {
    let seg = Segment::new(
        s.0.map(T::from_f64),
        T::from_f64(s.1),
        s.2.map(T::from_f64),
        T::from_f64(s.3),
    )?;
    let k = SegmentKernel::compact_polynomial(DEGREE, T::from_f64(SIGMA))?;
    Ok(ScalisSegment::new(seg, k, T::from_f64(ISO))?)
}

/// Scales the skeleton into the unit box and builds the scene.
fn finish<T: Real>(mut segs: Vec<Seg>, what: &str) -> Result<Built<T>, GenError> {
    let support = |s: &Seg| {
        let r = SIGMA * s.1.max(s.3);
        [
            [0, 1, 2].map(|k| s.0[k].min(s.2[k]) - r),
            [0, 1, 2].map(|k| s.0[k].max(s.2[k]) + r),
        ]
    };
    let [lo, hi] = box_union(segs.iter().map(support));
    let frame = Frame::fit(lo, hi);
    for s in &mut segs {
        *s = (
            frame.point(s.0),
            frame.length(s.1),
            frame.point(s.2),
            frame.length(s.3),
        );
    }
    let bounds = frame.bounds(lo, hi, 0.02);
    // per-segment Lipschitz bounds and support boxes (f64, scaled frame)
    let f64_segs = segs
        .iter()
        .map(make::<f64>)
        .collect::<Result<Vec<_>, _>>()?;
    let items: Vec<([[f64; 3]; 2], f64)> = f64_segs
        .iter()
        .map(|s| {
            let b = s
                .support_box()
                .unwrap_or([[f64::NEG_INFINITY; 3], [f64::INFINITY; 3]]);
            (b, s.lipschitz_bound())
        })
        .collect();
    let lip = grid_lipschitz(bounds, 16, 0.0, |a, b| {
        items
            .iter()
            .filter(|(sb, _)| (0..3).all(|k| sb[0][k] <= b[k] && sb[1][k] >= a[k]))
            .map(|(_, l)| l)
            .sum()
    });
    let sk64 = ScalisSkeleton::new(f64_segs)?;
    let inside = segs
        .iter()
        .map(|s| [0, 1, 2].map(|k| 0.5 * (s.0[k] + s.2[k])))
        .find(|&p| sk64.eval(p) < -1e-3)
        .ok_or(GenError::Check(
            "no skeleton midpoint is inside the surface",
        ))?;
    let typed = segs.iter().map(make::<T>).collect::<Result<Vec<_>, _>>()?;
    let n = typed.len();
    Ok(Built {
        field: SceneField::Scalis(WithLipschitz {
            field: ScalisSkeleton::new(typed)?,
            lipschitz: T::from_f64(lip),
        }),
        bounds,
        inside,
        primitives: n,
        description: format!(
            "{what}: SCALIS sum of {n} segments (compact kernel degree {DEGREE}, sigma {SIGMA}); thesis Part III ch. 1"
        ),
    })
}

/// A unit vector orthogonal to `d`.
fn orthogonal(d: [f64; 3]) -> [f64; 3] {
    let a = if d[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    normalize([
        d[1] * a[2] - d[2] * a[1],
        d[2] * a[0] - d[0] * a[2],
        d[0] * a[1] - d[1] * a[0],
    ])
}

/// `d` turned by `angle` towards a random direction orthogonal to it.
fn turn(rng: &mut Rng, d: [f64; 3], angle: f64) -> [f64; 3] {
    let o = orthogonal(d);
    // rotate `o` around `d` by a random azimuth
    let phi = rng.range(0.0, std::f64::consts::TAU);
    let (s, c) = (0.5 * phi).sin_cos();
    let o = rotate([d[0] * s, d[1] * s, d[2] * s, c], o);
    normalize(add_scaled(d.map(|x| x * angle.cos()), angle.sin(), o))
}

/// Segments of the tree.
const TREE_SEGMENTS: usize = 200;

/// `scalis-tree`: breadth-first branching, decreasing lengths and radii.
pub(crate) fn tree<T: Real>(seed: u64) -> Result<Built<T>, GenError> {
    let mut rng = Rng::new(seed, 4);
    let mut segs: Vec<Seg> = Vec::with_capacity(TREE_SEGMENTS);
    // (start, direction, length, radius at start)
    let mut queue =
        std::collections::VecDeque::from([([0.0, 0.0, 0.0], [0.0, 1.0, 0.0], 1.0, 0.12)]);
    while let Some((a, d, len, ra)) = queue.pop_front() {
        if segs.len() >= TREE_SEGMENTS {
            break;
        }
        let b = add_scaled(a, len, d);
        let rb = ra * 0.72;
        segs.push((a, ra, b, rb));
        let children = if rng.unit() < 0.3 { 3 } else { 2 };
        for _ in 0..children {
            let angle = rng.range(0.35, 0.8);
            let nd = turn(&mut rng, d, angle);
            queue.push_back((b, nd, len * 0.78, rb));
        }
    }
    finish(segs, "procedural tree (thesis Fig. 1.9 left)")
}

/// `scalis-random`: 12 random polylines of 5 segments.
pub(crate) fn random<T: Real>(seed: u64) -> Result<Built<T>, GenError> {
    let mut rng = Rng::new(seed, 5);
    let mut segs: Vec<Seg> = Vec::with_capacity(60);
    for _ in 0..12 {
        let mut a = rng.in_ball(1.0);
        let mut d = rng.direction();
        let mut r = rng.range(0.06, 0.14);
        for _ in 0..5 {
            let len = rng.range(0.3, 0.6);
            let b = add_scaled(a, len, d);
            // |Δr| ≤ 0.4·L keeps σ·|Δr| < L (SCALIS' bounded variation)
            let rb = (r * rng.range(0.75, 1.3)).clamp(0.04, 0.16);
            let rb = rb.clamp(r - 0.4 * len, r + 0.4 * len);
            segs.push((a, r, b, rb));
            a = b;
            r = rb;
            d = normalize(add_scaled(d, 0.9, rng.direction()));
        }
    }
    finish(segs, "random polylines (thesis Fig. 1.9 right)")
}

/// Seeds per axis of the foam's Voronoi diagram, and the clip box of its
/// edges (in seed-grid units).
const FOAM_SEEDS: usize = 7;
const FOAM_CLIP: [f64; 2] = [0.6, 5.4];
const FOAM_RADIUS: f64 = 0.06;
/// Neighbourhood radius of the empty-circumsphere test (certifies
/// tetrahedra of circumradius ≤ 1.3).
const FOAM_REACH: f64 = 2.6;

/// The circumcenter of four points (`None` when degenerate).
fn circumcenter(p: [[f64; 3]; 4]) -> Option<[f64; 3]> {
    let r = |i: usize| [0, 1, 2].map(|k| p[i][k] - p[0][k]);
    let (a, b, c) = (r(1), r(2), r(3));
    let sq = |v: [f64; 3]| v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    let cross = |u: [f64; 3], v: [f64; 3]| {
        [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ]
    };
    let bc = cross(b, c);
    let det = 2.0 * (a[0] * bc[0] + a[1] * bc[1] + a[2] * bc[2]);
    if det.abs() < 1e-9 {
        return None;
    }
    let ca = cross(c, a);
    let ab = cross(a, b);
    let (la, lb, lc) = (sq(a), sq(b), sq(c));
    Some([0, 1, 2].map(|k| p[0][k] + (la * bc[k] + lb * ca[k] + lc * ab[k]) / det))
}

/// The Voronoi edges (pairs of vertices) of `seeds` whose Delaunay
/// tetrahedra have circumradius ≤ `reach/2` (module docs).
fn voronoi_edges(seeds: &[[f64; 3]], reach: f64) -> Vec<([f64; 3], [f64; 3])> {
    let n = seeds.len();
    let nb: Vec<Vec<usize>> = (0..n)
        .map(|i| {
            (0..n)
                .filter(|&m| m != i && dist(seeds[i], seeds[m]) < reach)
                .collect()
        })
        .collect();
    let mut centers: Vec<[f64; 3]> = Vec::new();
    let mut faces: HashMap<[usize; 3], Vec<usize>> = HashMap::new();
    for i in 0..n {
        let up: Vec<usize> = nb[i].iter().copied().filter(|&m| m > i).collect();
        for (x, &j) in up.iter().enumerate() {
            for (y, &k) in up.iter().enumerate().skip(x + 1) {
                for &l in up.iter().skip(y + 1) {
                    let Some(c) = circumcenter([seeds[i], seeds[j], seeds[k], seeds[l]]) else {
                        continue;
                    };
                    let r = dist(c, seeds[i]);
                    if r > 0.5 * reach {
                        continue;
                    }
                    // every seed closer than r to c is within 2r ≤ reach of i
                    let empty = nb[i].iter().all(|&m| {
                        m == j || m == k || m == l || dist(c, seeds[m]) >= r * (1.0 - 1e-12)
                    });
                    if !empty {
                        continue;
                    }
                    let t = centers.len();
                    centers.push(c);
                    let v = [i, j, k, l];
                    for skip in 0..4 {
                        let mut f = [0; 3];
                        let mut w = 0;
                        for (q, &s) in v.iter().enumerate() {
                            if q != skip {
                                f[w] = s;
                                w += 1;
                            }
                        }
                        f.sort_unstable();
                        faces.entry(f).or_default().push(t);
                    }
                }
            }
        }
    }
    let mut keys: Vec<&[usize; 3]> = faces.keys().collect();
    keys.sort_unstable();
    keys.into_iter()
        .filter_map(|f| match faces[f].as_slice() {
            [a, b] => Some((centers[*a], centers[*b])),
            _ => None,
        })
        .collect()
}

/// `scalis-foam`: edges of the Voronoi diagram of jittered grid seeds.
pub(crate) fn foam<T: Real>(seed: u64) -> Result<Built<T>, GenError> {
    let mut rng = Rng::new(seed, 6);
    let mut seeds = Vec::with_capacity(FOAM_SEEDS.pow(3));
    for i in 0..FOAM_SEEDS {
        for j in 0..FOAM_SEEDS {
            for k in 0..FOAM_SEEDS {
                let g = [i, j, k].map(|x| x as f64);
                seeds.push(g.map(|x| x + rng.range(-0.3, 0.3)));
            }
        }
    }
    let inside = |p: [f64; 3]| p.iter().all(|x| (FOAM_CLIP[0]..=FOAM_CLIP[1]).contains(x));
    let segs: Vec<Seg> = voronoi_edges(&seeds, FOAM_REACH)
        .into_iter()
        .filter(|&(a, b)| inside(a) && inside(b) && dist(a, b) >= 0.02)
        .map(|(a, b)| (a, FOAM_RADIUS, b, FOAM_RADIUS))
        .collect();
    if segs.is_empty() {
        return Err(GenError::Check(
            "the Voronoi diagram has no edge in the clip box",
        ));
    }
    finish(
        segs,
        "Voronoi foam (thesis Fig. 1.10: edges of the Voronoi diagram of a jittered 7^3 grid)",
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn circumcenter_is_equidistant() {
        let p = [
            [0.0, 0.0, 0.0],
            [1.0, 0.1, 0.0],
            [0.2, 1.0, 0.1],
            [0.1, 0.3, 1.2],
        ];
        let c = circumcenter(p).unwrap();
        let r = dist(c, p[0]);
        assert!(p.iter().all(|&q| (dist(c, q) - r).abs() < 1e-12));
        assert!(
            circumcenter([[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 1.0, 0.0]]).is_none()
        );
    }

    /// Each Voronoi vertex is equidistant from its four seeds and no seed is
    /// closer; each edge's points are equidistant from three seeds.
    #[test]
    fn voronoi_edges_are_equidistant_from_three_seeds() {
        let mut rng = Rng::new(5, 0);
        let seeds: Vec<[f64; 3]> = (0..4 * 4 * 4)
            .map(|i| [i % 4, (i / 4) % 4, i / 16].map(|x| x as f64 + rng.range(-0.3, 0.3)))
            .collect();
        let edges = voronoi_edges(&seeds, 2.0);
        assert!(edges.len() > 50);
        for (a, b) in edges {
            let m = [0, 1, 2].map(|k| 0.5 * (a[k] + b[k]));
            let mut d: Vec<f64> = seeds.iter().map(|&s| dist(s, m)).collect();
            d.sort_by(f64::total_cmp);
            // the three nearest seeds tie (the edge's dual face), the fourth is farther
            assert!(d[2] - d[0] < 1e-9 && d[3] > d[2] - 1e-12, "{:?}", &d[..4]);
        }
    }

    #[test]
    fn skeleton_sizes() {
        let t: Built<f64> = tree(1).ok().unwrap();
        assert_eq!(t.primitives, TREE_SEGMENTS);
        let f: Built<f64> = foam(1).ok().unwrap();
        assert!((700..=1500).contains(&f.primitives), "{}", f.primitives);
        let r: Built<f64> = random(1).ok().unwrap();
        assert_eq!(r.primitives, 60);
    }
}
