//! Flat blobtrees: local equivalence of pruned fields (paper eq. 4), bound
//! containment for every number type, encoding round trips and refusals,
//! and the sparse traversal against a recursive reference.
//!
//! Each property runs 10 000 cases (`PROPTEST_CASES` overrides). Random
//! trees mix CSG, smooth and compact operators of all three classes over
//! random rigidly transformed primitives.

mod common;

use boundtrace::fields::FieldError;
use boundtrace::fields::blobtree::{
    BlobtreeRef, FlatBlobtree, MAX_NODES, Node, NodeWord, PrunedView, sparse_traverse,
};
use boundtrace::fields::operator::Operator;
use boundtrace::fields::sdf::Primitive;
use boundtrace::ia_core::Interval;
use boundtrace::inclusion::Field;
use proptest::prelude::*;
use proptest::test_runner::{Config, contextualize_config};

use common::blobtree::*;

fn config() -> Config {
    contextualize_config(Config {
        cases: 10_000,
        failure_persistence: None,
        ..Config::default()
    })
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn local_equivalence(seed in any::<u64>()) {
        check_local_equivalence(&mut common::blobtree::Rng::seeded(seed))?;
    }

    #[test]
    fn bound_containment(seed in any::<u64>()) {
        check_bound_containment(&mut common::blobtree::Rng::seeded(seed))?;
    }

    #[test]
    fn encoding_round_trip(seed in any::<u64>()) {
        check_encoding_round_trip(&mut common::blobtree::Rng::seeded(seed))?;
    }

    #[test]
    fn sparse_traversal_matches_reference(seed in any::<u64>()) {
        check_sparse_traversal_matches_reference(&mut common::blobtree::Rng::seeded(seed))?;
    }
}

// ---------------------------------------------------------------------
// Fixed cases.

fn sphere(x: f32) -> Node<f32> {
    Node::primitive(Primitive::sphere([x, 0.0, 0.0], 0.5).unwrap())
}

/// A left comb `((((s0 ∪ s1) ∪ s2) …) ∪ s_{n−1})`.
fn comb(n: usize, op: Operator<f32>) -> Node<f32> {
    let mut t = sphere(0.0);
    for i in 1..n {
        t = Node::op(op, t, sphere(i as f32));
    }
    t
}

/// A right comb `s0 ∪ (s1 ∪ (… ∪ s_{n−1}))`.
fn right_comb(n: usize, op: Operator<f32>) -> Node<f32> {
    let mut t = sphere((n - 1) as f32);
    for i in (0..n - 1).rev() {
        t = Node::op(op, sphere(i as f32), t);
    }
    t
}

#[test]
fn traversal_on_combs_and_fixed_shapes() {
    let ops = [
        Operator::union(),
        Operator::intersection(),
        Operator::difference(),
        Operator::compact_union(0.2, 0.3).unwrap(),
    ];
    for op in ops {
        for tree in [comb(9, op), right_comb(9, op)] {
            let flat = FlatBlobtree::from_node(&tree).unwrap();
            let prims = flat.primitive_indices();
            // Every subset of the 9 primitives.
            for mask in 0u32..(1 << prims.len()) {
                let active: Vec<u32> = prims
                    .iter()
                    .enumerate()
                    .filter(|(k, _)| mask & (1 << k) != 0)
                    .map(|(_, &p)| p)
                    .collect();
                assert_eq!(check_traversal(&flat, &active), Ok(()), "mask {mask:b}");
            }
        }
    }
}

#[test]
fn deep_comb_linearizes_and_evaluates() {
    // 200,000 nodes: iterative linearization, drop and comparison.
    let tree = comb(100_000, Operator::union());
    let flat = FlatBlobtree::from_node(&tree).unwrap();
    assert_eq!(flat.len(), 199_999);
    assert_eq!(flat.stack_need(), 2);
    let f: f32 = flat.as_ref().eval([0.0, 0.0, 0.0]);
    assert_eq!(f, -0.5);
    // Sparse: only the last primitive is active; the left chain is one jump.
    let last = *flat.primitive_indices().last().unwrap();
    let mut trace = Trace::default();
    assert!(sparse_traverse(&flat.as_ref(), &[last], &mut trace).unwrap());
    assert_eq!(
        trace.visited.len(),
        2,
        "primitive, then one jump to the root"
    );
    let first = flat.primitive_indices()[0];
    let mut trace = Trace::default();
    assert!(sparse_traverse(&flat.as_ref(), &[first], &mut trace).unwrap());
    assert_eq!(trace.visited.len(), 2, "the left spine is one chain");
    assert!(flat.to_node::<f32>().unwrap() == tree);
}

#[test]
fn too_large_trees_are_refused() {
    // Raw data one node past the limit.
    let nodes = vec![0u32; 2 * (MAX_NODES + 1)];
    assert!(matches!(
        BlobtreeRef::new(&nodes, &[]),
        Err(FieldError::TooLarge { max: MAX_NODES, .. })
    ));
    assert!(matches!(
        FlatBlobtree::from_raw(nodes, vec![]),
        Err(FieldError::TooLarge { .. })
    ));
    // A right comb needs a stack as deep as the tree: refused past
    // STACK_CAPACITY (not silently truncated).
    let deep = right_comb(40, Operator::union());
    assert!(matches!(
        FlatBlobtree::from_node(&deep),
        Err(FieldError::TooLarge { .. })
    ));
    // Pruned view capacity and stack overflows are reported.
    let flat = FlatBlobtree::from_node(&right_comb(20, Operator::union())).unwrap();
    let all = flat.primitive_indices();
    assert!(matches!(
        PrunedView::<'_, 255, 768, 8>::build(flat.as_ref(), &all),
        Err(FieldError::TooLarge { .. })
    ));
    let flat = FlatBlobtree::from_node(&comb(20, Operator::union())).unwrap();
    let all = flat.primitive_indices();
    assert!(matches!(
        PrunedView::<'_, 15, 768, 8>::build(flat.as_ref(), &all),
        Err(FieldError::TooLarge { .. })
    ));
    let view = PrunedView::<'_, 39, 768, 2>::build(flat.as_ref(), &all).unwrap();
    assert_eq!(view.len(), 39);
    // D_cache overflow is not an error: the parameters stay global.
    let view = PrunedView::<'_, 39, 16, 2>::build(flat.as_ref(), &all).unwrap();
    assert!(view.uncached_nodes() > 0);
    let p = [0.3f32, 0.1, 0.0];
    let a: f32 = view.eval(p);
    let b: f32 = flat.as_ref().eval(p);
    assert_eq!(a, b);
}

#[test]
fn malformed_data_is_refused() {
    let tree = Node::op(
        Operator::compact_difference(0.2, 0.3).unwrap(),
        Node::op(
            Operator::smooth_union(0.3).unwrap(),
            sphere(0.0),
            sphere(1.0),
        ),
        Node::op(Operator::intersection(), sphere(0.5), sphere(0.7)),
    );
    let flat = FlatBlobtree::from_node(&tree).unwrap();
    let (nodes, params) = flat.clone().into_raw();
    let refused = |n: &[u32], p: &[f32]| BlobtreeRef::new(n, p).is_err();
    assert!(!refused(&nodes, &params));
    // Odd word count, empty tree, truncated parameters.
    assert!(refused(&nodes[..nodes.len() - 1], &params));
    assert!(refused(&[], &params));
    assert!(refused(&nodes, &params[..params.len() - 4]));
    // Unknown kinds, unary bit, wrong ignoreMod, isLeft, ancestors, offsets.
    let mutate = |i: usize, f: &dyn Fn(u32) -> u32| {
        let mut n = nodes.clone();
        n[i] = f(n[i]);
        n
    };
    for i in 0..flat.len() {
        let w = NodeWord(nodes[2 * i]);
        if w.is_leaf() {
            assert!(refused(&mutate(2 * i, &|x| x | (0xff << 22)), &params));
        } else {
            assert!(refused(&mutate(2 * i, &|x| x | (0x1f << 22)), &params));
            assert!(refused(&mutate(2 * i, &|x| x | (1 << 27)), &params));
            assert!(refused(&mutate(2 * i, &|x| x ^ (3 << 28)), &params));
            assert!(refused(&mutate(2 * i, &|x| x ^ (1 << 31)), &params));
        }
        assert!(refused(&mutate(2 * i, &|x| x ^ (1 << 30)), &params));
        assert!(refused(&mutate(2 * i, &|x| x ^ 1), &params));
        assert!(refused(&mutate(2 * i + 1, &|x| x + 1000), &params));
    }
    // Every single-bit flip of every word is refused or stays safe to
    // evaluate and traverse (no panic, no out-of-bounds).
    for i in 0..nodes.len() {
        for bit in 0..32 {
            let n = mutate(i, &|x| x ^ (1 << bit));
            if let Ok(r) = BlobtreeRef::new(&n, &params) {
                let _: f32 = r.eval([0.1, 0.2, 0.3]);
                let _: Interval<f32> = r.eval([Interval::new(0.0, 1.0); 3]);
                let prims: Vec<u32> = (0..r.len() as u32)
                    .filter(|&k| r.word(k).unwrap().is_leaf())
                    .collect();
                let _ = r.eval_sparse::<f32, f32>(&prims, [0.1, 0.2, 0.3]);
            }
        }
    }
    // Unsorted or non-leaf active lists.
    let r = flat.as_ref();
    assert!(r.eval_sparse::<f32, f32>(&[1, 0], [0.0; 3]).is_err());
    assert!(r.eval_sparse::<f32, f32>(&[2], [0.0; 3]).is_err());
    assert!(r.eval_sparse::<f32, f32>(&[0, 0], [0.0; 3]).is_err());
    assert!(r.eval_sparse::<f32, f32>(&[99], [0.0; 3]).is_err());
}

#[test]
fn roi_rules() {
    use boundtrace::fields::blobtree::Roi;
    let root = Roi::<f64>::root();
    let cu = Operator::compact_union(0.2, 0.3).unwrap();
    let ci = Operator::compact_intersection(0.2, 0.3).unwrap();
    let cd = Operator::compact_difference(0.2, 0.3).unwrap();
    assert_eq!(root.child(&cu, true), Roi { lo: 0.0, hi: 0.3 });
    assert_eq!(root.child(&ci, false), Roi { lo: -0.3, hi: 0.0 });
    assert_eq!(root.child(&cd, true), Roi { lo: -0.3, hi: 0.0 });
    assert_eq!(root.child(&cd, false), Roi { lo: 0.0, hi: 0.3 });
    let csg = Operator::union();
    assert_eq!(root.child(&csg, true), root);
    let su = Operator::smooth_union(0.2).unwrap();
    assert_eq!(root.child(&su, true).hi, f64::INFINITY);
    // Nested: a union under a difference's right operand.
    let r = root.child(&cd, false).child(&cu, true);
    assert_eq!(r, Roi { lo: 0.0, hi: 0.3 });
    // ABVs: a smooth union makes its primitives always active.
    let su32 = Operator::<f32>::smooth_union(0.2).unwrap();
    let tree = Node::op(su32, sphere(0.0), sphere(1.0));
    let flat = FlatBlobtree::from_node(&tree).unwrap();
    assert!(flat.abvs::<f64>().iter().all(|a| a.volume.is_none()));
    let cu32 = Operator::<f32>::compact_union(0.2, 0.3).unwrap();
    let tree = Node::op(cu32, sphere(0.0), sphere(1.0));
    let flat = FlatBlobtree::from_node(&tree).unwrap();
    assert!(
        flat.abvs::<f64>()
            .iter()
            .all(|a| a.volume.is_some() && a.r_plus == 0.3f32 as f64)
    );
}

#[test]
fn lipschitz_bound_is_product_of_factors() {
    let cu = Operator::<f32>::compact_union(0.3, 0.4).unwrap();
    let flat = FlatBlobtree::from_node(&comb(5, cu)).unwrap();
    let l: f64 = flat.as_ref().lipschitz().unwrap();
    let k = cu.lipschitz_factor() as f64;
    assert!((l - k.powi(4)).abs() < 1e-5, "{l} vs {}", k.powi(4));
    let view = PrunedView::<'_, 255, 768, 8>::build(flat.as_ref(), &flat.primitive_indices()[..2])
        .unwrap();
    let lv: f64 = view.lipschitz().unwrap();
    assert!((lv - k).abs() < 1e-6);
}
