//! Random flat blobtrees and their checks, shared by the `blobtree`
//! property tests and the `field_bounds` / `sparse_equivalence` fuzz
//! targets (`fuzz/`): random trees (CSG, smooth and compact operators over
//! rigidly transformed primitives), large shared scenes, and one check
//! function per property, each drawing its case from an [`Rng`].

use std::sync::OnceLock;

use boundtrace::fields::FieldError;
use boundtrace::fields::blobtree::{
    FlatBlobtree, NO_ANCESTOR, Node, PrunedView, SparseVisitor, passes, sparse_traverse,
};
use boundtrace::fields::bounding::Aabb;
use boundtrace::fields::operator::Operator;
use boundtrace::fields::sdf::Primitive;
use boundtrace::fields::transform::Rigid;
use boundtrace::ia_core::{Affine, Interval, Real};
use boundtrace::inclusion::{Field, ForwardLinear, ForwardQuadratic, Ray};
use proptest::prelude::*;
use proptest::test_runner::TestCaseError;

/// SplitMix64: the random trees are derived from one proptest seed.
/// Draws from a fuzzer input's bytes first (8 per draw, little-endian)
/// when built with [`Rng::from_bytes`], then from SplitMix64.
pub struct Rng {
    state: u64,
    bytes: Vec<u8>,
    pos: usize,
}

impl Rng {
    /// SplitMix64 from `seed`.
    pub fn seeded(seed: u64) -> Self {
        Rng {
            state: seed,
            bytes: Vec::new(),
            pos: 0,
        }
    }
    /// The bytes of `data` first, then SplitMix64 seeded from them.
    pub fn from_bytes(data: &[u8]) -> Self {
        let seed = data.iter().fold(0xcbf2_9ce4_8422_2325_u64, |h, &b| {
            (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3)
        });
        Rng {
            state: seed,
            bytes: data.to_vec(),
            pos: 0,
        }
    }
    pub fn next(&mut self) -> u64 {
        if let Some(chunk) = self.bytes.get(self.pos..self.pos + 8) {
            self.pos += 8;
            return u64::from_le_bytes(chunk.try_into().expect("8 bytes"));
        }
        self.state = self.state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// Uniform in `[0, 1)`.
    pub fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unit()
    }
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    /// Rounded to f32 so that f32 round trips are exact.
    pub fn f(&mut self, a: f64, b: f64) -> f64 {
        self.range(a, b) as f32 as f64
    }
    pub fn point(&mut self, half: f64) -> [f64; 3] {
        [
            self.f(-half, half),
            self.f(-half, half),
            self.f(-half, half),
        ]
    }
}

pub fn t<T: Real>(x: f64) -> T {
    T::from_f64(x)
}

pub fn t3<T: Real>(p: [f64; 3]) -> [T; 3] {
    [t(p[0]), t(p[1]), t(p[2])]
}

/// A random primitive of any bounded kind (planes with probability
/// `plane_p`) near a random point of the cube `[−half, half]³`.
pub fn primitive<T: Real>(rng: &mut Rng, half: f64, plane_p: f64) -> Primitive<T> {
    let c = rng.point(half);
    primitive_at(rng, c, plane_p)
}

/// A random primitive near `c`.
pub fn primitive_at<T: Real>(rng: &mut Rng, c: [f64; 3], plane_p: f64) -> Primitive<T> {
    let s = |rng: &mut Rng| rng.f(0.3, 1.2);
    if rng.unit() < plane_p {
        let n = rng.point(1.0);
        let n = if n.iter().all(|x| x.abs() < 0.1) {
            [0.0, 0.0, 1.0]
        } else {
            n
        };
        return Primitive::plane(t3(c), t3(n)).unwrap();
    }
    let prim = match rng.below(9) {
        0 => Primitive::sphere(t3(c), t(s(rng))),
        1 => Primitive::cuboid(t3(c), [t(s(rng)), t(s(rng)), t(s(rng))]),
        2 => {
            let h = [s(rng), s(rng), s(rng)];
            let r = h[0].min(h[1]).min(h[2]) * 0.5;
            Primitive::rounded_box(t3(c), t3(h), t(r as f32 as f64))
        }
        3 => {
            let d = rng.point(1.0);
            let b = [c[0] + d[0], c[1] + d[1], c[2] + d[2] + 0.5];
            Primitive::capsule(t3(c), t3(b), t(s(rng) * 0.5))
        }
        4 => {
            let d = rng.point(1.0);
            let b = [c[0] + d[0], c[1] + d[1] + 0.5, c[2] + d[2]];
            Primitive::cylinder(t3(c), t3(b), t(s(rng) * 0.5))
        }
        5 => {
            let axis = [rng.f(-1.0, 1.0), rng.f(-1.0, 1.0), 1.0];
            let big = s(rng);
            Primitive::torus(t3(c), t3(axis), t(big), t(big * 0.3))
        }
        6 => {
            let d = rng.point(1.0);
            let b = [c[0] + d[0] + 0.5, c[1] + d[1], c[2] + d[2]];
            Primitive::cone(t3(c), t(s(rng) * 0.6), t3(b), t(s(rng) * 0.3))
        }
        7 => Primitive::ellipsoid(t3(c), [t(s(rng)), t(s(rng)), t(s(rng))]),
        _ => Primitive::blob(t3(c), t(s(rng) * 1.5), t(0.5)),
    }
    .unwrap();
    if rng.unit() < 0.5 {
        let q = [rng.f(-1.0, 1.0), rng.f(-1.0, 1.0), rng.f(-1.0, 1.0), 1.0];
        // Rotate about the primitive's own center.
        let rot = Rigid::new([t(q[0]), t(q[1]), t(q[2]), t(q[3])], [T::ZERO; 3]).unwrap();
        let back = Rigid::translation(t3(c)).unwrap();
        let to = Rigid::translation(t3([-c[0], -c[1], -c[2]])).unwrap();
        return prim
            .with_transform(to)
            .with_transform(rot)
            .with_transform(back);
    }
    prim
}

/// A random operator: CSG, smooth (rarely: their ROI is unbounded) and
/// compact, of every class.
pub fn operator<T: Real>(rng: &mut Rng, smooth_p: f64) -> Operator<T> {
    let beta = rng.f(0.1, 0.6);
    let r_o = (beta * rng.range(1.2, 2.0)) as f32 as f64;
    let class = rng.below(10);
    if rng.unit() < smooth_p {
        return match class {
            0..=5 => Operator::smooth_union(t(beta)),
            6..=7 => Operator::smooth_intersection(t(beta)),
            _ => Operator::smooth_difference(t(beta)),
        }
        .unwrap();
    }
    let compact = rng.unit() < 0.6;
    match (class, compact) {
        (0..=5, false) => Ok(Operator::union()),
        (6..=7, false) => Ok(Operator::intersection()),
        (_, false) => Ok(Operator::difference()),
        (0..=5, true) => Operator::compact_union(t(beta), t(r_o)),
        (6..=7, true) => Operator::compact_intersection(t(beta), t(r_o)),
        (_, true) => Operator::compact_difference(t(beta), t(r_o)),
    }
    .unwrap()
}

/// A random tree over `n` primitives: adjacent items of a list are merged
/// at random positions (a random binary tree shape, shallow enough for the
/// evaluation stack).
pub fn random_tree<T: Real>(
    rng: &mut Rng,
    n: usize,
    half: f64,
    plane_p: f64,
    smooth_p: f64,
) -> Node<T> {
    let items: Vec<Node<T>> = (0..n)
        .map(|_| Node::primitive(primitive(rng, half, plane_p)))
        .collect();
    merge_randomly(rng, items, smooth_p, false)
}

/// Merges adjacent items at random positions until one is left. With
/// `coherent`, operators joining subtrees of more than 3 primitives are
/// mostly unions (a modeling-like scene: blends and cuts are local).
pub fn merge_randomly<T: Real>(
    rng: &mut Rng,
    mut items: Vec<Node<T>>,
    smooth_p: f64,
    coherent: bool,
) -> Node<T> {
    let mut sizes = vec![1usize; items.len()];
    while items.len() > 1 {
        let i = rng.below(items.len() - 1);
        let r = items.remove(i + 1);
        let l = items.remove(i);
        let size = sizes.remove(i + 1) + sizes[i];
        sizes[i] = size;
        let mut op = operator(rng, smooth_p);
        if coherent && size > 3 && rng.unit() < 0.85 {
            op = match rng.below(3) {
                0 => Operator::union(),
                _ => {
                    let beta = rng.f(0.1, 0.6);
                    Operator::compact_union(t(beta), t((beta * 1.5) as f32 as f64)).unwrap()
                }
            };
        }
        items.insert(i, Node::op(op, l, r));
    }
    items.pop().unwrap()
}

/// A spatially coherent scene: primitive centers in Morton order of a
/// 4×4×4 grid over `[−half, half]³`, so that merged neighbours are close.
pub fn coherent_tree<T: Real>(
    rng: &mut Rng,
    n: usize,
    half: f64,
    plane_p: f64,
    smooth_p: f64,
) -> Node<T> {
    let mut centers: Vec<(u32, [f64; 3])> = (0..n)
        .map(|_| {
            let c = rng.point(half);
            let cell = |x: f64| (((x + half) / (2.0 * half) * 4.0) as u32).min(3);
            let (a, b, d) = (cell(c[0]), cell(c[1]), cell(c[2]));
            let mut key = 0;
            for bit in 0..2 {
                key |= ((a >> bit) & 1) << (3 * bit)
                    | ((b >> bit) & 1) << (3 * bit + 1)
                    | ((d >> bit) & 1) << (3 * bit + 2);
            }
            (key, c)
        })
        .collect();
    centers.sort_by_key(|x| x.0);
    let items = centers
        .into_iter()
        .map(|(_, c)| Node::primitive(primitive_at(rng, c, plane_p)))
        .collect();
    merge_randomly(rng, items, smooth_p, true)
}

// ---------------------------------------------------------------------
// Reference (recursive) pruning.

/// Children of every operator, from the true parents.
pub fn children(flat: &FlatBlobtree) -> Vec<Option<(u32, u32)>> {
    let parent = flat.parents();
    let mut ch: Vec<(Option<u32>, Option<u32>)> = vec![(None, None); flat.len()];
    for (c, &p) in parent.iter().enumerate() {
        if p != NO_ANCESTOR {
            if flat.word(c as u32).unwrap().is_left() {
                ch[p as usize].0 = Some(c as u32);
            } else {
                ch[p as usize].1 = Some(c as u32);
            }
        }
    }
    ch.into_iter().map(|(l, r)| l.zip(r)).collect()
}

/// Recursive reference: (present, post-order program, active nodes).
pub fn reference(
    flat: &FlatBlobtree,
    ch: &[Option<(u32, u32)>],
    is_active: &[bool],
    node: u32,
    active_nodes: &mut Vec<u32>,
) -> (bool, Vec<u32>, bool) {
    match ch[node as usize] {
        None => {
            let a = is_active[node as usize];
            if a {
                active_nodes.push(node);
                (true, vec![node], true)
            } else {
                (false, vec![], false)
            }
        }
        Some((l, r)) => {
            let (pl, mut gl, al) = reference(flat, ch, is_active, l, active_nodes);
            let (pr, gr, ar) = reference(flat, ch, is_active, r, active_nodes);
            let any = al || ar;
            if any {
                active_nodes.push(node);
            }
            let class = flat.word(node).unwrap().class().unwrap();
            let out = match (pl, pr) {
                (true, true) => {
                    gl.extend(gr);
                    gl.push(node);
                    (true, gl)
                }
                (true, false) if passes(class, true) => (true, gl),
                (false, true) if passes(class, false) => (true, gr),
                _ => (false, vec![]),
            };
            (out.0, out.1, any)
        }
    }
}

#[derive(Default)]
pub struct Trace {
    pub visited: Vec<u32>,
    pub jumps: Vec<(u32, u32)>,
    pub program: Vec<u32>,
}

impl SparseVisitor for Trace {
    fn visit(&mut self, node: u32) {
        self.visited.push(node);
    }
    fn jump(&mut self, from: u32, to: u32) {
        self.jumps.push((from, to));
    }
    fn primitive(&mut self, node: u32) -> Result<(), FieldError> {
        self.program.push(node);
        Ok(())
    }
    fn operator(&mut self, node: u32) -> Result<(), FieldError> {
        self.program.push(node);
        Ok(())
    }
    fn kill(&mut self, emitted: u32) -> Result<(), FieldError> {
        self.program.truncate(emitted as usize);
        Ok(())
    }
}

/// Checks the sparse traversal of `flat` for `active` against the
/// recursive reference; returns an error message on mismatch.
pub fn check_traversal(flat: &FlatBlobtree, active: &[u32]) -> Result<(), String> {
    let ch = children(flat);
    let parent = flat.parents();
    let mut is_active = vec![false; flat.len()];
    for &a in active {
        is_active[a as usize] = true;
    }
    let mut active_nodes = vec![];
    let root = flat.len() as u32 - 1;
    let (present, program, _) = reference(flat, &ch, &is_active, root, &mut active_nodes);
    let mut trace = Trace::default();
    let got = sparse_traverse(&flat.as_ref(), active, &mut trace).map_err(|e| e.to_string())?;
    if got != present || trace.program != program {
        return Err(format!(
            "pruned program differs: got ({got}, {:?}), want ({present}, {program:?})",
            trace.program
        ));
    }
    // Visited nodes plus the nodes skipped inside jumps are exactly the
    // active nodes, each once.
    let mut seen = trace.visited.clone();
    for &(from, to) in &trace.jumps {
        let mut x = parent[from as usize];
        while x != to {
            if x == NO_ANCESTOR || x > to {
                return Err(format!("jump {from} -> {to} is not along the ancestors"));
            }
            seen.push(x);
            x = parent[x as usize];
        }
    }
    let n_seen = seen.len();
    seen.sort_unstable();
    seen.dedup();
    if seen.len() != n_seen {
        return Err("a node was visited twice".into());
    }
    active_nodes.sort_unstable();
    if seen != active_nodes {
        return Err(format!("visited {seen:?}, active nodes {active_nodes:?}"));
    }
    Ok(())
}

// ---------------------------------------------------------------------
// Shared random scenes.

pub struct Scene {
    flat: FlatBlobtree,
    abvs: Vec<boundtrace::fields::blobtree::Abv<f64>>,
    half: f64,
}

/// A few large trees (≥ 200 nodes), built once: mixed sharp, smooth and
/// compact operators.
pub fn scenes() -> &'static [Scene] {
    static SCENES: OnceLock<Vec<Scene>> = OnceLock::new();
    SCENES.get_or_init(|| {
        let mut out = vec![];
        for (seed, smooth_p, plane_p) in [
            (1u64, 0.0, 0.0),
            (2, 0.03, 0.01),
            (3, 0.0, 0.02),
            (4, 0.05, 0.0),
        ] {
            let mut rng = Rng::seeded(seed);
            // Three modeling-like scenes, one dense fully random one
            // (intersections and differences at every level).
            let (half, tree) = if seed < 4 {
                (
                    4.0,
                    coherent_tree::<f64>(&mut rng, 120, 4.0, plane_p, smooth_p),
                )
            } else {
                (
                    2.0,
                    random_tree::<f64>(&mut rng, 120, 2.0, plane_p, smooth_p),
                )
            };
            let flat = FlatBlobtree::from_node(&tree).unwrap();
            assert!(flat.len() >= 200);
            let abvs = flat.abvs::<f64>();
            out.push(Scene { flat, abvs, half });
        }
        out
    })
}

pub type BigView<'a> = PrunedView<'a, 511, 4096, 32>;

/// Paper eq. 4: for random query boxes, the pruned field built from the
/// primitives whose ABV meets the box has the sign of the full field at
/// random points of the box; the direct sparse evaluation equals the
/// pruned view's value.
pub fn check_local_equivalence(rng: &mut Rng) -> Result<(), TestCaseError> {
    let scenes = scenes();
    let sc = &scenes[rng.below(scenes.len())];
    let c = rng.point(sc.half + 1.0);
    let e = [
        rng.range(0.05, 2.5),
        rng.range(0.05, 2.5),
        rng.range(0.05, 2.5),
    ];
    let b = Aabb::new(
        [c[0] - e[0], c[1] - e[1], c[2] - e[2]],
        [c[0] + e[0], c[1] + e[1], c[2] + e[2]],
    );
    let active = FlatBlobtree::active_in_box(&sc.abvs, &b);
    let tree = sc.flat.as_ref();
    let view = BigView::build(tree, &active).unwrap();
    for _ in 0..4 {
        let p = [
            rng.range(b.min[0], b.max[0]),
            rng.range(b.min[1], b.max[1]),
            rng.range(b.min[2], b.max[2]),
        ];
        let full: f64 = tree.eval(p);
        let pruned: f64 = view.eval(p);
        let direct: f64 = tree.eval_sparse::<f64, f64>(&active, p).unwrap();
        prop_assert!(pruned == direct || (pruned.is_nan() && direct.is_nan()));
        prop_assert!(!full.is_nan() && !pruned.is_nan());
        prop_assert_eq!(
            full > 0.0,
            pruned > 0.0,
            "sign mismatch at {:?}: full {} pruned {} ({} active of {})",
            p,
            full,
            pruned,
            active.len(),
            sc.abvs.len()
        );
        prop_assert_eq!(full < 0.0, pruned < 0.0);
    }
    Ok(())
}

/// Bounds of every number type over a ray segment contain the sound
/// point enclosure (`Interval::point` inputs) at sample points, for
/// random trees whose primitives overlap (compact blends active).
pub fn check_bound_containment(rng: &mut Rng) -> Result<(), TestCaseError> {
    let n = 2 + rng.below(10);
    let tree = random_tree::<f64>(rng, n, 1.0, 0.05, 0.15);
    let flat = FlatBlobtree::from_node(&tree).unwrap();
    let f = flat.as_ref();
    let o = rng.point(3.0);
    let d = rng.point(1.0);
    let ray = Ray::new(o, d);
    let t1 = rng.range(0.01, 1.5);
    let iv: Interval<f64> = f.eval(ray.at(0.0, t1));
    let af: Affine<f64, 4> = f.eval(ray.at(0.0, t1));
    let fl: ForwardLinear<f64> = f.eval(ray.at(0.0, t1));
    let fq: ForwardQuadratic<f64> = f.eval(ray.at(0.0, t1));
    let af = af.to_interval();
    for k in 0..3 {
        let tt = match k {
            0 => 0.0,
            1 => t1,
            _ => rng.range(0.0, t1),
        };
        let exact: Interval<f64> = f.eval(ray.at(tt, tt));
        let meets = |b: Interval<f64>| !b.intersection(exact).is_empty();
        prop_assert!(
            meets(iv),
            "Interval {:?} misses {:?} at t = {}",
            iv,
            exact,
            tt
        );
        prop_assert!(
            meets(af),
            "Affine {:?} misses {:?} at t = {}",
            af,
            exact,
            tt
        );
        if fl.is_valid() && tt <= fl.validity() {
            prop_assert!(
                meets(fl.bounds_at(tt)),
                "ForwardLinear {:?} misses {:?} at t = {}",
                fl,
                exact,
                tt
            );
        }
        if fq.is_valid() && tt <= fq.validity() {
            prop_assert!(
                meets(fq.bounds_at(tt)),
                "ForwardQuadratic {:?} misses {:?} at t = {}",
                fq,
                exact,
                tt
            );
        }
    }
    Ok(())
}

/// Build → flat → decode gives the builder's tree (f32 parameters), and
/// re-encoding gives the same data.
pub fn check_encoding_round_trip(rng: &mut Rng) -> Result<(), TestCaseError> {
    let n = 1 + rng.below(24);
    let tree = random_tree::<f32>(rng, n, 4.0, 0.05, 0.2);
    let flat = FlatBlobtree::from_node(&tree).unwrap();
    prop_assert_eq!(flat.len(), 2 * n - 1);
    let back = flat.to_node::<f32>().unwrap();
    prop_assert!(back == tree);
    let again = FlatBlobtree::from_node(&back).unwrap();
    prop_assert_eq!(&again, &flat);
    let (nodes, params) = flat.clone().into_raw();
    prop_assert_eq!(FlatBlobtree::from_raw(nodes, params).unwrap(), flat.clone());
    // Reordering symmetric operands: same field, no more stack.
    let re = FlatBlobtree::from_node_reordered(&tree).unwrap();
    prop_assert!(re.stack_need() <= flat.stack_need());
    for _ in 0..4 {
        let p = [
            rng.f(-5.0, 5.0) as f32,
            rng.f(-5.0, 5.0) as f32,
            rng.f(-5.0, 5.0) as f32,
        ];
        let a: f32 = flat.as_ref().eval(p);
        let b: f32 = re.as_ref().eval(p);
        prop_assert!(a == b || (a.is_nan() && b.is_nan()), "{} vs {}", a, b);
    }
    Ok(())
}

/// The fast-ancestor sparse traversal visits exactly the active nodes
/// (visited + skipped pass-through chain members, each once) and emits
/// the program of the recursive reference, for random active sets.
pub fn check_sparse_traversal_matches_reference(rng: &mut Rng) -> Result<(), TestCaseError> {
    let n = 1 + rng.below(40);
    let tree = random_tree::<f32>(rng, n, 4.0, 0.0, 0.1);
    let flat = FlatBlobtree::from_node(&tree).unwrap();
    let density = rng.unit();
    let active: Vec<u32> = flat
        .primitive_indices()
        .into_iter()
        .filter(|_| rng.unit() < density)
        .collect();
    prop_assert_eq!(check_traversal(&flat, &active), Ok(()));
    let view = BigView::build(flat.as_ref(), &active).unwrap();
    let mut trace = Trace::default();
    let present = sparse_traverse(&flat.as_ref(), &active, &mut trace).unwrap();
    prop_assert_eq!(view.node_indices(), &trace.program[..]);
    prop_assert_eq!(view.root_present(), present);
    Ok(())
}
