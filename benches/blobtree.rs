//! Flat blobtrees: linearization and ROI/ABV computation of 10⁵-primitive
//! trees, and full versus sparse evaluation for 10, 10², 10³ and 10⁴
//! primitives.
//!
//! Scenes: spheres on a jittered grid, merged by a balanced tree of compact
//! unions with a few compact differences (a modeling-like scene). The
//! query box covers a few grid cells, so a handful of primitives are
//! active whatever the tree size. Per iteration, 64 points of the box are
//! evaluated (f64):
//!
//! - `full`: the whole tree ([`Field::eval`] on [`BlobtreeRef`], Alg. 1);
//! - `sparse`: direct sparse traversal ([`BlobtreeRef::eval_sparse`]);
//! - `view`: a prebuilt pruned view (Alg. 4);
//! - `view_build`: building the pruned view once (per box, not per point).
//!
//! Run with `cargo bench --bench blobtree`; compare lines of one group as
//! ratios.
//!
//! Measured once (release, shared 2-core container, noisy): linearization
//! of 10⁵ primitives ≈ 29 ms, ROI + ABVs ≈ 15 ms, active set of a box
//! ≈ 2.2 ms. With ~12 active primitives, `full / sparse` ≈ 7× (n = 10,
//! 1 active), 6× (10²), 56× (10³), 500× (10⁴); `full / view` ≈ 12×, 8×,
//! 85×, 860×; building a view ≈ 1.2 µs.

use boundtrace::fields::blobtree::{BlobtreeRef, DefaultPrunedView, FlatBlobtree, Node};
use boundtrace::fields::bounding::Aabb;
use boundtrace::fields::operator::Operator;
use boundtrace::fields::sdf::Primitive;
use boundtrace::inclusion::Field;
use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use std::time::Duration;

/// Deterministic pseudo-random values in `[0, 1)` (xorshift).
struct Rng(u64);
impl Rng {
    fn unit(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// `n` spheres on a jittered grid of spacing 1 (row-major, so neighbours in
/// the list are neighbours in space), merged pairwise level by level (a
/// balanced tree: evaluation stack ⌈log₂ n⌉ + 1).
fn scene(n: usize) -> Node<f64> {
    let side = (n as f64).cbrt().ceil() as usize;
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let mut items: Vec<Node<f64>> = (0..n)
        .map(|i| {
            let (x, y, z) = (i % side, (i / side) % side, i / (side * side));
            let c = [
                x as f64 + 0.3 * rng.unit(),
                y as f64 + 0.3 * rng.unit(),
                z as f64 + 0.3 * rng.unit(),
            ];
            Node::primitive(Primitive::sphere(c, 0.45 + 0.2 * rng.unit()).unwrap())
        })
        .collect();
    let u = Operator::compact_union(0.2, 0.25).unwrap();
    let d = Operator::compact_difference(0.1, 0.125).unwrap();
    let mut level = 0;
    while items.len() > 1 {
        let mut next = Vec::with_capacity(items.len().div_ceil(2));
        let mut it = items.into_iter();
        let mut k = 0;
        while let Some(a) = it.next() {
            match it.next() {
                Some(b) => {
                    let op = if level == 0 && k % 7 == 3 { d } else { u };
                    next.push(Node::op(op, a, b));
                }
                None => next.push(a),
            }
            k += 1;
        }
        items = next;
        level += 1;
    }
    items.pop().unwrap()
}

fn build(c: &mut Criterion) {
    let tree = scene(100_000);
    let flat = FlatBlobtree::from_node(&tree).unwrap();
    let mut g = c.benchmark_group("blobtree_build_1e5");
    g.sample_size(10).measurement_time(Duration::from_secs(5));
    g.bench_function("linearize", |b| {
        b.iter(|| black_box(FlatBlobtree::from_node(black_box(&tree)).unwrap()))
    });
    g.bench_function("roi_abv", |b| {
        b.iter(|| black_box(black_box(&flat).abvs::<f64>()))
    });
    let abvs = flat.abvs::<f64>();
    let q = Aabb::new([10.0, 10.0, 10.0], [12.0, 12.0, 12.0]);
    g.bench_function("active_in_box", |b| {
        b.iter(|| black_box(FlatBlobtree::active_in_box(black_box(&abvs), &q)))
    });
    g.finish();
}

const POINTS: usize = 64;

fn eval(c: &mut Criterion) {
    for n in [10usize, 100, 1_000, 10_000] {
        let tree = scene(n);
        let flat = FlatBlobtree::from_node(&tree).unwrap();
        let r: BlobtreeRef<'_> = flat.as_ref();
        let abvs = flat.abvs::<f64>();
        // A box of about one cell near the middle of the grid.
        let side = (n as f64).cbrt().ceil();
        let m = (side / 2.0).floor().min(side - 1.0).max(0.0);
        let q = Aabb::new(
            [m, m, m.min(((n as f64) / (side * side)).floor())],
            [m + 1.0, m + 1.0, m + 1.0],
        );
        let active = FlatBlobtree::active_in_box(&abvs, &q);
        let view: DefaultPrunedView<'_> = DefaultPrunedView::build(r, &active).unwrap();
        let mut rng = Rng(12345);
        let pts: Vec<[f64; 3]> = (0..POINTS)
            .map(|_| {
                [
                    q.min[0] + rng.unit() * (q.max[0] - q.min[0]),
                    q.min[1] + rng.unit() * (q.max[1] - q.min[1]),
                    q.min[2] + rng.unit() * (q.max[2] - q.min[2]),
                ]
            })
            .collect();
        // Sanity: the pruned field has the full field's sign.
        for &p in &pts {
            let a: f64 = r.eval(p);
            let b: f64 = view.eval(p);
            assert_eq!(a > 0.0, b > 0.0);
        }
        eprintln!(
            "n = {n}: {} nodes, {} active primitives, view of {} nodes",
            flat.len(),
            active.len(),
            view.len()
        );
        let mut g = c.benchmark_group(format!("blobtree_eval_{n}"));
        g.sample_size(20)
            .measurement_time(Duration::from_secs(2))
            .warm_up_time(Duration::from_millis(500));
        g.bench_function("full", |b| {
            b.iter(|| {
                for &p in &pts {
                    let v: f64 = black_box(&r).eval(black_box(p));
                    black_box(v);
                }
            })
        });
        g.bench_function("sparse", |b| {
            b.iter(|| {
                for &p in &pts {
                    let v = black_box(&r)
                        .eval_sparse::<f64, f64>(black_box(&active), black_box(p))
                        .unwrap();
                    black_box(v);
                }
            })
        });
        g.bench_function("view", |b| {
            b.iter(|| {
                for &p in &pts {
                    let v: f64 = black_box(&view).eval(black_box(p));
                    black_box(v);
                }
            })
        });
        g.bench_function("view_build", |b| {
            b.iter(|| {
                black_box(DefaultPrunedView::build(black_box(r), black_box(&active)).unwrap())
            })
        });
        g.finish();
    }
}

criterion_group!(benches, build, eval);
criterion_main!(benches);
