//! Sparse bottom-up traversal with fast ancestor indices (paper §5, Fig.
//! 7 and 10); the algorithm and its invariants are in the
//! [module docs](super).

use super::encoding::{BlobtreeRef, NodeWord, passes};
use crate::FieldError;
use crate::operator::OperatorClass;

/// Capacity of the traversal stack used by [`BlobtreeRef::eval_sparse`]
/// and the [pruned view](super::PrunedView) builder (pending left operands
/// waiting for their right sibling; at most the tree's evaluation stack
/// depth, so ≤ [`STACK_CAPACITY`](super::STACK_CAPACITY) for a validated
/// tree).
pub const TRAVERSAL_STACK: usize = super::STACK_CAPACITY;

/// What a sparse traversal reports, in post-order (see the
/// [module docs](super)).
///
/// A *present* subtree has exactly one value; the events describe a
/// post-order program on a value stack: [`primitive`](Self::primitive)
/// pushes, [`operator`](Self::operator) pops two and pushes one,
/// [`kill`](Self::kill) pops one. Selectors that pass an operand on emit
/// nothing.
pub trait SparseVisitor {
    /// Every node the traversal touches (active primitives and the active
    /// operators it lands on); for tests and statistics. Default: nothing.
    #[inline]
    fn visit(&mut self, _node: u32) {}
    /// The traversal jumps from `from` to its (clamped) fast ancestor
    /// `to`; the nodes strictly between them on the path are pass-through
    /// selectors that are skipped (for tests). Default: nothing.
    #[inline]
    fn jump(&mut self, _from: u32, _to: u32) {}
    /// An active primitive: push its value.
    fn primitive(&mut self, node: u32) -> Result<(), FieldError>;
    /// An operator with two present operands: pop `f₁`, pop `f₀`, push
    /// `op(f₀, f₁)`.
    fn operator(&mut self, node: u32) -> Result<(), FieldError>;
    /// The present subtree on top became missing (an intersection-like
    /// operator, or a difference with only its right operand): pop its
    /// value. `emitted` is the number of [`primitive`](Self::primitive) and
    /// [`operator`](Self::operator) events still in effect once the killed
    /// subtree's events are discarded (a program recorder truncates to it).
    fn kill(&mut self, emitted: u32) -> Result<(), FieldError>;
}

#[derive(Clone, Copy)]
struct Entry {
    node: u32,
    present: bool,
    start: u32,
}

const EMPTY: Entry = Entry {
    node: 0,
    present: false,
    start: 0,
};

#[inline]
fn malformed(reason: &'static str) -> FieldError {
    FieldError::Malformed { reason }
}

#[inline]
fn class_of(w: NodeWord) -> Result<OperatorClass, FieldError> {
    if w.is_leaf() {
        return Err(malformed("a primitive has operands"));
    }
    w.class().ok_or(malformed("bad ignoreMod"))
}

/// The sparse bottom-up traversal of `tree` restricted to the active
/// primitives `active` (post-order indices, strictly increasing, leaves):
/// reports the active primitives, the operators that have two present
/// operands and the kills to `visitor`, and returns whether the root is
/// present (`false`: the local field is `+∞`, no surface in the volume).
///
/// Allocation-free; the stack of pending left operands has fixed capacity
/// [`TRAVERSAL_STACK`]. Every step strictly increases the current node
/// index, so it ends after at most `|active| + |tree|` steps even on
/// inconsistent input.
///
/// # Errors
/// [`FieldError::Malformed`] when `active` is not strictly increasing or
/// names a non-leaf, [`FieldError::TooLarge`] when the pending stack would
/// overflow, and any error of the visitor.
pub fn sparse_traverse<V: SparseVisitor>(
    tree: &BlobtreeRef<'_>,
    active: &[u32],
    visitor: &mut V,
) -> Result<bool, FieldError> {
    let n = tree.len() as u32;
    let mut stack = [EMPTY; TRAVERSAL_STACK];
    let mut sp = 0usize;
    let mut emitted = 0u32;
    let mut root_present = false;
    let mut prev: Option<u32> = None;
    let mut reached_root = false;
    let mut k = 0usize;
    while k < active.len() {
        let p = active[k];
        if p >= n || prev.is_some_and(|q| p <= q) {
            return Err(malformed("active primitives not strictly increasing"));
        }
        if reached_root {
            return Err(malformed("active primitive after the root was reached"));
        }
        prev = Some(p);
        // The next active primitive (u32::MAX: none).
        let q = match active.get(k + 1) {
            Some(&x) => x,
            None => u32::MAX,
        };
        let pw = tree.word(p).ok_or(malformed("index out of range"))?;
        if !pw.is_leaf() {
            return Err(malformed("active index is not a primitive"));
        }
        visitor.visit(p);
        visitor.primitive(p)?;
        let mut cur = p;
        let mut present = true;
        let mut start = emitted;
        emitted += 1;
        loop {
            let w = tree.word(cur).ok_or(malformed("index out of range"))?;
            if !w.has_ancestor() {
                // The root: everything must have merged into it.
                if sp != 0 {
                    return Err(malformed("pending operands at the root"));
                }
                root_present = present;
                reached_root = true;
                break;
            }
            let fast = w.ancestor();
            if w.is_left() {
                // Left operand. Its chain cur → … → fast has right
                // subtrees covering (cur, fast): if the next active
                // primitive lies there, wait for it (push), else every
                // chain node up to `fast` is a selector on the left.
                if q < fast {
                    if sp == TRAVERSAL_STACK {
                        return Err(FieldError::TooLarge {
                            what: "sparse traversal stack entries",
                            count: TRAVERSAL_STACK + 1,
                            max: TRAVERSAL_STACK,
                        });
                    }
                    stack[sp] = Entry {
                        node: cur,
                        present,
                        start,
                    };
                    sp += 1;
                    break;
                }
                if fast <= cur {
                    return Err(malformed("ancestor does not increase"));
                }
                visitor.jump(cur, fast);
                cur = fast;
                visitor.visit(cur);
                let tw = tree.word(cur).ok_or(malformed("index out of range"))?;
                if present && !passes(class_of(tw)?, true) {
                    present = false;
                    emitted = start;
                    visitor.kill(start)?;
                }
            } else {
                // Right operand: jump along the right chain, clamped to the
                // fast ancestor of the pending left operand on top (#1/#2).
                let top = if sp > 0 { Some(stack[sp - 1]) } else { None };
                let mut t = fast;
                let mut fy = u32::MAX;
                if let Some(y) = top {
                    let yw = tree.word(y.node).ok_or(malformed("index out of range"))?;
                    fy = yw.ancestor();
                    if fy < t {
                        t = fy;
                    }
                }
                if t <= cur {
                    return Err(malformed("ancestor does not increase"));
                }
                visitor.jump(cur, t);
                cur = t;
                visitor.visit(cur);
                let tw = tree.word(cur).ok_or(malformed("index out of range"))?;
                let class = class_of(tw)?;
                // Two operands meet at t (popRequiredA: t is the top's
                // fast ancestor; popRequiredB: t is a left child, or the
                // root, on the top's chain).
                let merge = match top {
                    Some(_) => {
                        t == fy || ((tw.is_left() || !tw.has_ancestor()) && tw.ancestor() >= fy)
                    }
                    None => false,
                };
                if merge {
                    sp -= 1;
                    let y = stack[sp];
                    // The pending left operand's chain up to `t` was
                    // skipped (pass-throughs).
                    visitor.jump(y.node, cur);
                    match (y.present, present) {
                        (true, true) => {
                            visitor.operator(cur)?;
                            emitted += 1;
                        }
                        (true, false) => {
                            if !passes(class, true) {
                                present = false;
                                emitted = y.start;
                                visitor.kill(y.start)?;
                            } else {
                                present = true;
                            }
                        }
                        (false, true) => {
                            if !passes(class, false) {
                                present = false;
                                emitted = y.start;
                                visitor.kill(y.start)?;
                            }
                        }
                        (false, false) => {}
                    }
                    start = y.start;
                } else if present && !passes(class, false) {
                    present = false;
                    emitted = start;
                    visitor.kill(start)?;
                }
            }
        }
        k += 1;
    }
    if !active.is_empty() && !reached_root {
        return Err(malformed("traversal did not reach the root"));
    }
    Ok(root_present)
}

#[cfg(all(test, feature = "alloc"))]
mod tests {
    use super::*;
    use crate::blobtree::{FlatBlobtree, Node};
    use crate::operator::Operator;
    use crate::sdf::Primitive;
    use alloc::vec::Vec;

    struct Program(Vec<u32>);
    impl SparseVisitor for Program {
        fn primitive(&mut self, node: u32) -> Result<(), FieldError> {
            self.0.push(node);
            Ok(())
        }
        fn operator(&mut self, node: u32) -> Result<(), FieldError> {
            self.0.push(node);
            Ok(())
        }
        fn kill(&mut self, emitted: u32) -> Result<(), FieldError> {
            self.0.truncate(emitted as usize);
            Ok(())
        }
    }

    fn s(x: f64) -> Node<f64> {
        Node::primitive(Primitive::sphere([x, 0.0, 0.0], 0.5).unwrap())
    }

    #[test]
    fn selectors_per_class() {
        // op(op2(s0, s1), s2): post-order 0, 1, 2 = op2, 3, 4 = root.
        let cases = [
            // (root, inner, active, expected program, root present)
            (
                Operator::union(),
                Operator::union(),
                &[0u32, 3][..],
                &[0u32, 3, 4][..],
                true,
            ),
            (
                Operator::union(),
                Operator::intersection(),
                &[0, 3],
                &[3],
                true,
            ),
            (
                Operator::union(),
                Operator::difference(),
                &[0, 3],
                &[0, 3, 4],
                true,
            ),
            (
                Operator::union(),
                Operator::difference(),
                &[1, 3],
                &[3],
                true,
            ),
            (
                Operator::intersection(),
                Operator::union(),
                &[3],
                &[],
                false,
            ),
            (Operator::difference(), Operator::union(), &[1], &[1], true),
            (Operator::difference(), Operator::union(), &[3], &[], false),
            (Operator::union(), Operator::union(), &[], &[], false),
        ];
        for (root, inner, active, want, present) in cases {
            let tree = Node::op(root, Node::op(inner, s(0.0), s(1.0)), s(2.0));
            let flat = FlatBlobtree::from_node(&tree).unwrap();
            let mut prog = Program(Vec::new());
            let got = sparse_traverse(&flat.as_ref(), active, &mut prog).unwrap();
            assert_eq!(
                (got, &prog.0[..]),
                (present, want),
                "{root:?} {inner:?} {active:?}"
            );
        }
    }
}
