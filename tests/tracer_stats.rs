//! The statistics harness on analytic fields (`boundtrace::tracer::stats`):
//! the dense reference finds the exact roots of spheres and thin slabs,
//! the classification rules on hand-made traces, ray-set determinism and
//! face coverage, and `run_method`/`markdown_table` end to end.

mod common;

use boundtrace::inclusion::{Field, FieldNum, Ray};
use boundtrace::tracer::stats::{
    RaySet, RefRoot, Reference, ReferenceParams, StatsError, Verdict, classify, markdown_table,
    reference_roots, run_method,
};
use boundtrace::tracer::{Method, Mode, Params, Root, Side, Status};
use common::shapes::Ball;

const EPS: f64 = 1e-4;

impl Ball {
    /// The exact entry and exit of a ray with a unit direction, if it hits.
    fn hits(&self, ray: &Ray<f64>) -> Option<(f64, f64)> {
        let oc: Vec<f64> = (0..3).map(|a| ray.origin[a] - self.c[a]).collect();
        let b: f64 = (0..3).map(|a| oc[a] * ray.dir[a]).sum();
        let c: f64 = oc.iter().map(|x| x * x).sum::<f64>() - self.r * self.r;
        let disc = b * b - c;
        (disc >= 0.0).then(|| (-b - disc.sqrt(), -b + disc.sqrt()))
    }
}

/// Two disjoint balls (union: the minimum of the distances).
struct TwoBalls(Ball, Ball);

impl Field<f64> for TwoBalls {
    fn eval<N: FieldNum<f64>>(&self, p: [N; 3]) -> N {
        self.0.eval(p).min(self.1.eval(p))
    }
    fn lipschitz(&self) -> Option<f64> {
        Some(1.0)
    }
}

/// The slab `|x − x0| ≤ w`.
struct Slab {
    x0: f64,
    w: f64,
}

impl Field<f64> for Slab {
    fn eval<N: FieldNum<f64>>(&self, p: [N; 3]) -> N {
        (p[0] - self.x0).abs() - self.w
    }
    fn lipschitz(&self) -> Option<f64> {
        Some(1.0)
    }
}

fn rp() -> ReferenceParams<f64> {
    ReferenceParams::new(EPS).unwrap()
}

const BOX: [[f64; 3]; 2] = [[-1.5, -1.25, -1.0], [1.5, 1.25, 1.0]];

#[test]
fn reference_finds_the_exact_roots_of_a_ball() {
    let ball = Ball {
        c: [0.1, -0.2, 0.05],
        r: 0.9,
    };
    let rays = RaySet::new(BOX, 3000, 11).unwrap();
    let p = rp();
    let (mut hits, mut misses) = (0, 0);
    for (i, r) in rays.rays().iter().enumerate() {
        let got = reference_roots(&ball, &r.ray, r.span, &p).unwrap();
        match ball.hits(&r.ray) {
            // Both roots clearly apart (not grazing): two certain groups.
            Some((t0, t1)) if t1 - t0 > 4.0 * EPS => {
                hits += 1;
                assert_eq!(got.len(), 2, "ray {i}: {got:?} vs {t0}, {t1}");
                assert!((got[0].t - t0).abs() <= p.tol, "ray {i}: {got:?} vs {t0}");
                assert!((got[1].t - t1).abs() <= p.tol, "ray {i}: {got:?} vs {t1}");
                assert_eq!((got[0].side, got[0].count), (Side::Entering, 1));
                assert_eq!((got[1].side, got[1].count), (Side::Leaving, 1));
            }
            Some(_) => {} // grazing: a merged group or an optional touch
            None => {
                // Clearly missing rays have no root, not even an optional one.
                let d = closest_distance(&ball, &r.ray);
                if d > ball.r + 1e-3 {
                    misses += 1;
                    assert!(got.is_empty(), "ray {i}: {got:?}");
                }
            }
        }
    }
    assert!(hits > 500 && misses > 500, "{hits} hits, {misses} misses");
}

fn closest_distance(ball: &Ball, ray: &Ray<f64>) -> f64 {
    let oc: Vec<f64> = (0..3).map(|a| ball.c[a] - ray.origin[a]).collect();
    let t: f64 = (0..3).map(|a| oc[a] * ray.dir[a]).sum();
    (0..3)
        .map(|a| (oc[a] - t * ray.dir[a]).powi(2))
        .sum::<f64>()
        .sqrt()
}

#[test]
fn reference_finds_four_roots_through_two_balls() {
    let f = TwoBalls(
        Ball {
            c: [-0.7, 0.0, 0.0],
            r: 0.5,
        },
        Ball {
            c: [0.6, 0.1, 0.0],
            r: 0.4,
        },
    );
    let p = rp();
    for y in [0.0, 0.05, -0.2, 0.3] {
        let ray = Ray::new([-1.5, y, 0.01], [1.0, 0.0, 0.0]);
        let got = reference_roots(&f, &ray, [0.0, 3.0], &p).unwrap();
        let (a0, a1) = f.0.hits(&ray).unwrap();
        let (b0, b1) = f.1.hits(&ray).unwrap();
        let want = [a0, a1, b0, b1];
        assert_eq!(got.len(), 4, "y = {y}: {got:?}");
        for (g, w) in got.iter().zip(want) {
            assert!(
                (g.t - w).abs() <= p.tol && g.certain(),
                "y = {y}: {got:?} vs {want:?}"
            );
        }
        let sides: Vec<Side> = got.iter().map(|g| g.side).collect();
        use Side::{Entering as E, Leaving as L};
        assert_eq!(sides, [E, L, E, L]);
    }
}

#[test]
fn reference_sees_a_slab_thinner_than_a_grid_cell() {
    let p = rp();
    let ray = Ray::new([-1.5, 0.2, 0.3], [1.0, 0.0, 0.0]);
    // Thickness 4e-4 > ε, but under the grid spacing 3/4096 ≈ 7.3e-4.
    let slab = Slab {
        x0: 0.3001,
        w: 2e-4,
    };
    let got = reference_roots(&slab, &ray, [0.0, 3.0], &p).unwrap();
    assert_eq!(got.len(), 2, "{got:?}");
    assert!((got[0].t - 1.7999).abs() <= p.tol && got[0].side == Side::Entering);
    assert!((got[1].t - 1.8003).abs() <= p.tol && got[1].side == Side::Leaving);
    // Backwards: the same roots mirrored.
    let back = Ray::new([1.5, 0.2, 0.3], [-1.0, 0.0, 0.0]);
    let got = reference_roots(&slab, &back, [0.0, 3.0], &p).unwrap();
    assert_eq!(got.len(), 2, "{got:?}");
    assert!((got[0].t - 1.1997).abs() <= p.tol && (got[1].t - 1.2001).abs() <= p.tol);
    // Thinner than ε: one merged Touch group of two sign changes.
    let thin = Slab {
        x0: 0.3001,
        w: 3e-5,
    };
    let got = reference_roots(&thin, &ray, [0.0, 3.0], &p).unwrap();
    assert_eq!(got.len(), 1, "{got:?}");
    assert_eq!((got[0].side, got[0].count), (Side::Touch, 2));
    assert!((got[0].t - 1.80007).abs() <= p.tol && (got[0].t_end - 1.80013).abs() <= p.tol);
    // Rays parallel to the slab, outside it: nothing.
    let along = Ray::new([0.9, -1.25, 0.0], [0.0, 1.0, 0.0]);
    assert!(
        reference_roots(&slab, &along, [0.0, 2.5], &p)
            .unwrap()
            .is_empty()
    );
}

// --- classification on hand-made traces -----------------------------------

fn single(t: f64, side: Side) -> RefRoot<f64> {
    RefRoot {
        t,
        t_end: t,
        side,
        count: 1,
    }
}

fn touch(t: f64) -> RefRoot<f64> {
    RefRoot {
        t,
        t_end: t,
        side: Side::Touch,
        count: 0,
    }
}

fn root(t: f64, side: Side) -> Root<f64> {
    Root { t, side }
}

/// Reference: entering at 1, leaving at 2.
fn two() -> Vec<RefRoot<f64>> {
    vec![single(1.0, Side::Entering), single(2.0, Side::Leaving)]
}

fn opaque(reference: &[RefRoot<f64>], m: Option<Root<f64>>, status: Status, t: f64) -> Verdict {
    let roots: Vec<Root<f64>> = m.into_iter().collect();
    classify(Mode::Opaque, &rp(), reference, &roots, status, t)
}

fn transparent(reference: &[RefRoot<f64>], roots: &[Root<f64>], status: Status, t: f64) -> Verdict {
    classify(Mode::Transparent, &rp(), reference, roots, status, t)
}

const FIN: Status = Status::Finished;

#[test]
fn opaque_classification() {
    let r = two();
    let e = |t| Some(root(t, Side::Entering));
    // Within ε of the first root, on either side: agree.
    for t in [1.0, 1.0 + 0.9 * EPS, 1.0 - 0.9 * EPS] {
        let v = opaque(&r, e(t), FIN, t);
        assert!(
            v.agree && !v.far && !v.spurious && !v.stepped_past,
            "{t}: {v}"
        );
    }
    // A root past the first root: stepped past (far from it when between).
    let v = opaque(&r, e(1.01), FIN, 1.01);
    assert!(v.stepped_past && v.far && !v.agree && !v.spurious, "{v}");
    let v = opaque(&r, Some(root(2.0, Side::Leaving)), FIN, 2.0);
    assert!(v.stepped_past && !v.far && !v.agree, "the second root: {v}");
    // None although the whole span was processed: stepped past.
    let v = opaque(&r, None, FIN, 3.0);
    assert!(v.stepped_past && !v.missed && !v.agree, "{v}");
    // None, stopped before the root: missed, and gave up at max_steps.
    let v = opaque(&r, None, Status::MaxSteps, 0.5);
    assert!(v.missed && v.gave_up && !v.stepped_past && !v.agree, "{v}");
    // A root before the first: spurious and far.
    let v = opaque(&r, e(0.5), FIN, 0.5);
    assert!(v.spurious && v.far && !v.stepped_past && !v.agree, "{v}");
    // No reference root: none agrees whatever the status; a root is spurious.
    assert!(opaque(&[], None, FIN, 3.0).agree);
    assert!(opaque(&[], None, Status::MaxSteps, 1.0).agree);
    let v = opaque(&[], e(1.0), FIN, 1.0);
    assert!(v.spurious && v.far && !v.agree, "{v}");
    // An optional touch before the first root may be reported, or not.
    let with_touch = [touch(0.7), r[0], r[1]];
    assert!(opaque(&with_touch, Some(root(0.7, Side::Touch)), FIN, 0.7).agree);
    assert!(opaque(&with_touch, e(1.0), FIN, 1.0).agree);
    // The opposite side is flagged but still agrees.
    let v = opaque(&r, Some(root(1.0, Side::Leaving)), FIN, 1.0);
    assert!(v.agree && v.wrong_side, "{v}");
    // Unsupported: nothing compared.
    let v = opaque(&r, None, Status::Unsupported, 0.0);
    assert_eq!(
        v,
        Verdict {
            unsupported: true,
            ..Verdict::default()
        }
    );
}

#[test]
fn transparent_classification() {
    let r = two();
    let (e1, l2) = (root(1.0, Side::Entering), root(2.0, Side::Leaving));
    assert!(transparent(&r, &[e1, l2], FIN, 3.0).agree);
    // A root skipped while processing past it: stepped past.
    let v = transparent(&r, &[e1], FIN, 3.0);
    assert!(v.stepped_past && !v.missed && !v.agree, "{v}");
    let v = transparent(&r, &[l2], FIN, 3.0);
    assert!(v.stepped_past && !v.spurious, "{v}");
    // Stopped before the second root: missed (gave up).
    let v = transparent(&r, &[e1], Status::MaxSteps, 1.5);
    assert!(v.missed && v.gave_up && !v.stepped_past && !v.agree, "{v}");
    // A root reported twice is spurious (not far); an extra one is far.
    let v = transparent(&r, &[e1, e1, l2], FIN, 3.0);
    assert!(v.spurious && !v.far && !v.agree, "{v}");
    let v = transparent(&r, &[e1, root(1.5, Side::Touch), l2], FIN, 3.0);
    assert!(v.spurious && v.far && !v.agree, "{v}");
    // Everything matched but stopped early: not agree, no other flag.
    let v = transparent(&r, &[e1, l2], Status::MaxSteps, 2.5);
    assert!(
        !v.agree && !v.missed && !v.spurious && !v.stepped_past,
        "{v}"
    );
    // A merged pair: one Touch root or both roots agree, three do not.
    let pair = [RefRoot {
        t: 1.0,
        t_end: 1.00005,
        side: Side::Touch,
        count: 2,
    }];
    let tch = root(1.00002, Side::Touch);
    assert!(transparent(&pair, &[tch], FIN, 3.0).agree);
    let both = [root(1.0, Side::Entering), root(1.00005, Side::Leaving)];
    assert!(transparent(&pair, &both, FIN, 3.0).agree);
    let v = transparent(&pair, &[both[0], tch, both[1]], FIN, 3.0);
    assert!(v.spurious && !v.agree, "{v}");
    // Optional touches: any number of roots there, or none.
    let opt = [touch(0.5), r[0], r[1]];
    assert!(transparent(&opt, &[e1, l2], FIN, 3.0).agree);
    let t5 = root(0.5, Side::Touch);
    assert!(transparent(&opt, &[t5, t5, e1, l2], FIN, 3.0).agree);
    // Wrong side flagged, still agrees.
    let v = transparent(&r, &[root(1.0, Side::Leaving), l2], FIN, 3.0);
    assert!(v.agree && v.wrong_side, "{v}");
}

// --- ray sets ----------------------------------------------------------------

#[test]
fn ray_sets_are_deterministic_prefixes() {
    let a = RaySet::new(BOX, 1000, 5).unwrap();
    assert_eq!(a, RaySet::new(BOX, 1000, 5).unwrap());
    let b = RaySet::new(BOX, 400, 5).unwrap();
    assert_eq!(&a.rays()[..400], b.rays());
    let c = RaySet::new(BOX, 1000, 6).unwrap();
    let same = a
        .rays()
        .iter()
        .zip(c.rays())
        .filter(|(x, y)| x == y)
        .count();
    assert_eq!(same, 0, "another seed gives other origins");
    assert_eq!((a.seed(), a.bounds(), a.len()), (5, BOX, 1000));
}

#[test]
fn ray_sets_cover_the_six_faces_uniformly() {
    let n = 6000;
    let set = RaySet::new(BOX, n, 42).unwrap();
    let [lo, hi] = BOX;
    let mut per_face = [0usize; 6];
    let mut sums = [[0.0f64; 3]; 6];
    for (i, r) in set.rays().iter().enumerate() {
        let f = usize::from(r.face);
        assert_eq!(f, i % 6);
        per_face[f] += 1;
        let axis = f / 2;
        let sign = if f % 2 == 0 { 1.0 } else { -1.0 };
        let mut dir = [0.0; 3];
        dir[axis] = sign;
        assert_eq!(r.ray.dir, dir, "unit axis direction into the box");
        let start = if f % 2 == 0 { lo[axis] } else { hi[axis] };
        assert_eq!(r.ray.origin[axis], start, "ray {i} starts on its face");
        assert_eq!(r.span, [0.0, hi[axis] - lo[axis]]);
        for a in 0..3 {
            assert!(lo[a] <= r.ray.origin[a] && r.ray.origin[a] <= hi[a]);
            sums[f][a] += r.ray.origin[a];
        }
    }
    assert_eq!(per_face, [n / 6; 6]);
    // Uniform on each face: the mean of each free coordinate is near the
    // face centre (5 standard errors; the set is fixed, so this is exact
    // and reproducible).
    for (f, s) in sums.iter().enumerate() {
        for a in (0..3).filter(|&a| a != f / 2) {
            let mean = s[a] / (n / 6) as f64;
            let centre = 0.5 * (lo[a] + hi[a]);
            let se = (hi[a] - lo[a]) / (12.0 * (n / 6) as f64).sqrt();
            assert!(
                (mean - centre).abs() < 5.0 * se,
                "face {f} axis {a}: {mean}"
            );
        }
    }
}

// --- run_method and the table -------------------------------------------------

#[test]
fn run_method_counts_every_ray_and_checks_its_inputs() {
    let ball = Ball {
        c: [0.0; 3],
        r: 0.8,
    };
    let rays = RaySet::new(BOX, 300, 3).unwrap();
    let reference = Reference::compute(&ball, &rays, &rp()).unwrap();
    assert_eq!(reference.len(), 300);
    assert!(reference.hits() > 50 && reference.hits() < 250);
    let params = Params::new();
    let mut rows = Vec::new();
    for method in [Method::Segment, Method::Interval, Method::LinearTaylor] {
        for mode in [Mode::Opaque, Mode::Transparent] {
            let s = run_method(&ball, &rays, &reference, method, mode, &params).unwrap();
            assert_eq!(s.rays, 300);
            assert_eq!(
                s.finished + s.max_steps + s.buffer_full + s.unsupported,
                300
            );
            assert!(s.agree <= s.traced() && s.failures.len() <= 8);
            if method == Method::LinearTaylor {
                // The ball has no Taylor bound.
                assert_eq!(s.unsupported, 300, "{method} {mode:?}");
                assert_eq!(s.agree_ratio(), None);
            }
            if s.traced() > 0 {
                // A robust method on a ball: every ray right.
                assert_eq!(s.stepped_past, 0, "{method} {mode:?}: {:?}", s.failures);
                assert_eq!(s.agree, s.traced(), "{method} {mode:?}: {:?}", s.failures);
                assert!(s.steps_avg >= 1.0 && f64::from(s.steps_max) >= s.steps_median);
            }
            if mode == Mode::Opaque {
                rows.push(s);
            }
        }
    }
    let table = markdown_table(&rows, Some(Method::Segment));
    let lines: Vec<&str> = table.lines().collect();
    assert_eq!(lines.len(), 2 + rows.len(), "{table}");
    let cols = lines[0].matches('|').count();
    assert!(
        lines.iter().all(|l| l.matches('|').count() == cols),
        "{table}"
    );
    assert!(lines[4].starts_with("| linear-taylor | n/a |"), "{table}");
    if rows[0].traced() > 0 {
        assert!(
            lines[2].contains("| 1.00 | 1.00 |"),
            "baseline ratios: {table}"
        );
    }
    // Input errors, not panics.
    let p5 = params.with_eps(1e-5).unwrap();
    let err = run_method(&ball, &rays, &reference, Method::Segment, Mode::Opaque, &p5);
    assert_eq!(err.unwrap_err(), StatsError::EpsMismatch);
    let other = RaySet::new(BOX, 30, 3).unwrap();
    let err = run_method(
        &ball,
        &other,
        &reference,
        Method::Segment,
        Mode::Opaque,
        &params,
    );
    assert!(matches!(
        err,
        Err(StatsError::RayCountMismatch {
            rays: 30,
            reference: 300
        })
    ));
}
