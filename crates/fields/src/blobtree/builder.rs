//! The nested builder tree ([`Node`]) and its linearized post-order
//! encoding ([`FlatBlobtree`]), both behind the `alloc` feature. Every
//! walk is iterative (explicit stacks): trees can be deeper than the call
//! stack.

use super::encoding::{BlobtreeRef, MAX_NODES, NO_ANCESTOR, NodeWord, passes};
use crate::FieldError;
use crate::operator::Operator;
use crate::sdf::Primitive;
use alloc::collections::BTreeMap;
use alloc::vec;
use alloc::vec::Vec;
use boundtrace_ia_core::Real;
use core::fmt;

/// A blobtree node in nested (builder) form: a primitive leaf or a binary
/// operator with its two operands.
///
/// Dropping, comparing and linearizing are iterative, so arbitrarily deep
/// trees (long combs) are fine.
///
/// ```
/// use boundtrace_fields::blobtree::{FlatBlobtree, Node};
/// use boundtrace_fields::operator::Operator;
/// use boundtrace_fields::sdf::Primitive;
///
/// let a = Node::primitive(Primitive::sphere([0.0f32, 0.0, 0.0], 1.0).unwrap());
/// let b = Node::primitive(Primitive::sphere([1.5f32, 0.0, 0.0], 1.0).unwrap());
/// let tree = Node::op(Operator::compact_union(0.5, 0.625).unwrap(), a, b);
/// let flat = FlatBlobtree::from_node(&tree).unwrap();
/// assert_eq!(flat.len(), 3);
/// assert_eq!(flat.to_node::<f32>().unwrap(), tree);
/// ```
pub struct Node<T> {
    inner: Inner<T>,
}

enum Inner<T> {
    Primitive(Primitive<T>),
    // Exactly two children [left, right]; a Vec so that Drop can move
    // them out without recursion.
    Operator(Operator<T>, Vec<Node<T>>),
}

impl<T> Drop for Node<T> {
    fn drop(&mut self) {
        let mut stack: Vec<Node<T>> = Vec::new();
        if let Inner::Operator(_, ch) = &mut self.inner {
            stack.append(ch);
        }
        while let Some(mut n) = stack.pop() {
            if let Inner::Operator(_, ch) = &mut n.inner {
                stack.append(ch);
            }
            // `n` drops here with no children left.
        }
    }
}

impl<T: Real> Node<T> {
    /// A primitive leaf.
    #[inline]
    pub fn primitive(p: Primitive<T>) -> Self {
        Self {
            inner: Inner::Primitive(p),
        }
    }

    /// An operator node `op(left, right)`.
    #[inline]
    pub fn op(op: Operator<T>, left: Node<T>, right: Node<T>) -> Self {
        Self {
            inner: Inner::Operator(op, vec![left, right]),
        }
    }

    /// The primitive of a leaf.
    #[inline]
    pub fn as_primitive(&self) -> Option<&Primitive<T>> {
        match &self.inner {
            Inner::Primitive(p) => Some(p),
            Inner::Operator(..) => None,
        }
    }

    /// The operator and operands of an inner node.
    #[inline]
    pub fn as_operator(&self) -> Option<(&Operator<T>, &Node<T>, &Node<T>)> {
        match &self.inner {
            Inner::Operator(op, ch) => match ch.as_slice() {
                [l, r] => Some((op, l, r)),
                _ => None,
            },
            Inner::Primitive(_) => None,
        }
    }

    /// The number of nodes (iterative).
    pub fn node_count(&self) -> usize {
        let mut count = 0usize;
        let mut stack = vec![self];
        while let Some(n) = stack.pop() {
            count += 1;
            if let Some((_, l, r)) = n.as_operator() {
                stack.push(l);
                stack.push(r);
            }
        }
        count
    }

    /// The nodes in post-order (iterative).
    pub fn post_order(&self) -> Vec<&Node<T>> {
        self.post_order_with(|_| false)
    }

    /// Post-order where the operands of the nodes for which `swap` holds
    /// are visited right first.
    fn post_order_with(&self, swap: impl Fn(&Node<T>) -> bool) -> Vec<&Node<T>> {
        let mut out = Vec::new();
        // (node, children pushed)
        let mut stack = vec![(self, false)];
        while let Some((n, expanded)) = stack.pop() {
            match n.as_operator() {
                Some((_, l, r)) if !expanded => {
                    let (first, second) = if swap(n) { (r, l) } else { (l, r) };
                    stack.push((n, true));
                    stack.push((second, false));
                    stack.push((first, false));
                }
                _ => out.push(n),
            }
        }
        out
    }

    /// The evaluation stack need of every node, keyed by address, when the
    /// operands of symmetric operators are ordered larger-need first
    /// (Sethi–Ullman; iterative).
    fn stack_needs(&self) -> BTreeMap<usize, u32> {
        let mut needs: BTreeMap<usize, u32> = BTreeMap::new();
        for n in self.post_order() {
            let v = match n.as_operator() {
                None => 1,
                Some((op, l, r)) => {
                    let get = |c: &Node<T>| {
                        needs
                            .get(&(c as *const Node<T> as usize))
                            .copied()
                            .unwrap_or(1)
                    };
                    let (a, b): (u32, u32) = (get(l), get(r));
                    if swappable(op) {
                        a.max(b).max(a.min(b) + 1)
                    } else {
                        a.max(b + 1)
                    }
                }
            };
            needs.insert(n as *const Node<T> as usize, v);
        }
        needs
    }
}

/// Whether the operator is symmetric in its operands (union- and
/// intersection-like: CSG, smooth and compact).
fn swappable<T: Real>(op: &Operator<T>) -> bool {
    op.kind().class() != crate::operator::OperatorClass::DifferenceLike
}

impl<T: Real> PartialEq for Node<T> {
    /// Structural equality (same shape, kinds and parameters), iterative.
    fn eq(&self, other: &Self) -> bool {
        let mut stack = vec![(self, other)];
        while let Some((a, b)) = stack.pop() {
            match (&a.inner, &b.inner) {
                (Inner::Primitive(x), Inner::Primitive(y)) => {
                    if x != y {
                        return false;
                    }
                }
                (Inner::Operator(..), Inner::Operator(..)) => {
                    let (Some((oa, la, ra)), Some((ob, lb, rb))) =
                        (a.as_operator(), b.as_operator())
                    else {
                        return false;
                    };
                    if oa != ob {
                        return false;
                    }
                    stack.push((la, lb));
                    stack.push((ra, rb));
                }
                _ => return false,
            }
        }
        true
    }
}

impl<T: Real + fmt::Debug> fmt::Debug for Node<T> {
    /// The post-order node list (not nested, so deep trees print fine).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut l = f.debug_list();
        for n in self.post_order() {
            match &n.inner {
                Inner::Primitive(p) => l.entry(p),
                Inner::Operator(op, _) => l.entry(op),
            };
        }
        l.finish()
    }
}

/// A linearized blobtree (paper §5, §7): node words and parameter offsets
/// in post-order, and the `f32` parameter array with a 128-bit stride. See
/// [`BlobtreeRef`] for the layout; [`as_ref`](Self::as_ref) gives the
/// validated borrowed view that is evaluated.
#[derive(Clone, Debug, PartialEq)]
pub struct FlatBlobtree {
    nodes: Vec<u32>,
    params: Vec<f32>,
    stack_need: usize,
}

impl FlatBlobtree {
    /// Linearizes `root` in post-order (iteratively), computing `isLeft`,
    /// the fast ancestor indices (module docs) and the parameter layout.
    ///
    /// # Errors
    /// [`FieldError::TooLarge`] above [`MAX_NODES`] nodes or when the tree
    /// needs more evaluation stack than
    /// [`STACK_CAPACITY`](super::STACK_CAPACITY) (rebalance it: put deep
    /// subtrees on the left); [`FieldError::InvalidParameter`] when a
    /// parameter does not fit `f32`.
    pub fn from_node<T: Real>(root: &Node<T>) -> Result<Self, FieldError> {
        Self::linearize(root, |_| false)
    }

    /// As [`from_node`](Self::from_node), but the operands of union- and
    /// intersection-like operators (symmetric in `f₀, f₁`: CSG, smooth and
    /// compact) are swapped where that lowers the evaluation stack
    /// (Sethi–Ullman order: the operand needing more stack first; paper §7
    /// rebalances right-heavy trees the same way). The field is unchanged;
    /// the flat operand order may differ from the builder's. With only
    /// symmetric operators the need is at most `⌊log₂ n⌋ + 1` for `n`
    /// primitives, so right combs of any length fit.
    ///
    /// # Errors
    /// As [`from_node`](Self::from_node).
    pub fn from_node_reordered<T: Real>(root: &Node<T>) -> Result<Self, FieldError> {
        let count = root.node_count();
        if count > MAX_NODES {
            return Err(FieldError::TooLarge {
                what: "blobtree nodes",
                count,
                max: MAX_NODES,
            });
        }
        let needs = root.stack_needs();
        let need = |n: &Node<T>| {
            needs
                .get(&(n as *const Node<T> as usize))
                .copied()
                .unwrap_or(0)
        };
        Self::linearize(root, |n| match n.as_operator() {
            Some((op, l, r)) => swappable(op) && need(r) > need(l),
            None => false,
        })
    }

    fn linearize<T: Real>(
        root: &Node<T>,
        swap: impl Fn(&Node<T>) -> bool,
    ) -> Result<Self, FieldError> {
        let count = root.node_count();
        if count > MAX_NODES {
            return Err(FieldError::TooLarge {
                what: "blobtree nodes",
                count,
                max: MAX_NODES,
            });
        }
        let order = root.post_order_with(swap);
        let n = order.len();
        let mut words: Vec<NodeWord> = Vec::with_capacity(n);
        let mut offsets: Vec<u32> = Vec::with_capacity(n);
        let mut parent: Vec<u32> = vec![NO_ANCESTOR; n];
        let mut is_left: Vec<bool> = vec![false; n];
        let mut params: Vec<f32> = Vec::new();
        let mut done: Vec<u32> = Vec::new();
        for (i, node) in order.iter().enumerate() {
            let off = (params.len() / 4) as u32;
            match &node.inner {
                Inner::Primitive(p) => {
                    let len = p.kind().param_vec4s() as usize * 4;
                    let start = params.len();
                    params.resize(start + len, 0.0);
                    p.write_params(&mut params[start..])?;
                    words.push(NodeWord::primitive(p.kind(), false, NO_ANCESTOR));
                    done.push(i as u32);
                }
                Inner::Operator(op, _) => {
                    let len = op.kind().param_vec4s() as usize * 4;
                    let start = params.len();
                    params.resize(start + len, 0.0);
                    op.write_params(&mut params[start..])?;
                    words.push(NodeWord::operator(op.kind(), false, NO_ANCESTOR));
                    let (Some(r), Some(l)) = (done.pop(), done.pop()) else {
                        return Err(FieldError::Malformed {
                            reason: "operator without two operands",
                        });
                    };
                    parent[r as usize] = i as u32;
                    parent[l as usize] = i as u32;
                    is_left[l as usize] = true;
                    done.push(i as u32);
                }
            }
            offsets.push(off);
        }
        // Fast ancestors, root first (parents precede children in reverse
        // post-order): fast(c) = fast(p) if the chain goes on through p
        // (p not the root, same side as c, p passes c's side), else p.
        let mut fast: Vec<u32> = vec![NO_ANCESTOR; n];
        for c in (0..n.saturating_sub(1)).rev() {
            let p = parent[c] as usize;
            let class = words[p]
                .class()
                .unwrap_or(crate::operator::OperatorClass::IntersectionLike);
            let cont = p + 1 != n && is_left[p] == is_left[c] && passes(class, is_left[c]);
            fast[c] = if cont { fast[p] } else { p as u32 };
        }
        let mut nodes = Vec::with_capacity(2 * n);
        for i in 0..n {
            let w = words[i].0 & !((1 << 30) | NO_ANCESTOR);
            let w = w | if is_left[i] { 1 << 30 } else { 0 } | fast[i];
            nodes.push(w);
            nodes.push(offsets[i]);
        }
        Self::from_raw(nodes, params)
    }

    /// Takes flat data and validates it ([`BlobtreeRef::new`]).
    ///
    /// # Errors
    /// As [`BlobtreeRef::new`].
    pub fn from_raw(nodes: Vec<u32>, params: Vec<f32>) -> Result<Self, FieldError> {
        let stack_need = BlobtreeRef::new(&nodes, &params)?.stack_need();
        Ok(Self {
            nodes,
            params,
            stack_need,
        })
    }

    /// The validated borrowed view.
    #[inline]
    pub fn as_ref(&self) -> BlobtreeRef<'_> {
        // Validated at construction and immutable since.
        BlobtreeRef::from_validated(&self.nodes, &self.params, self.stack_need)
    }

    /// The node words (two per node).
    #[inline]
    pub fn nodes(&self) -> &[u32] {
        &self.nodes
    }

    /// The parameter array.
    #[inline]
    pub fn params(&self) -> &[f32] {
        &self.params
    }

    /// The data, for upload.
    #[inline]
    pub fn into_raw(self) -> (Vec<u32>, Vec<f32>) {
        (self.nodes, self.params)
    }

    /// Number of nodes.
    #[inline]
    pub fn len(&self) -> usize {
        self.nodes.len() / 2
    }

    /// Always `false`.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The evaluation stack the full interpreter needs.
    #[inline]
    pub fn stack_need(&self) -> usize {
        self.stack_need
    }

    /// The node word of node `i`.
    #[inline]
    pub fn word(&self, i: u32) -> Option<NodeWord> {
        self.nodes.get(2 * i as usize).map(|&w| NodeWord(w))
    }

    /// The post-order indices of the primitives.
    pub fn primitive_indices(&self) -> Vec<u32> {
        (0..self.len() as u32)
            .filter(|&i| self.word(i).is_some_and(|w| w.is_leaf()))
            .collect()
    }

    /// The true parent of every node ([`NO_ANCESTOR`] for the root),
    /// recomputed from the post-order structure.
    pub fn parents(&self) -> Vec<u32> {
        let n = self.len();
        let mut parent = vec![NO_ANCESTOR; n];
        let mut done: Vec<u32> = Vec::new();
        for i in 0..n as u32 {
            if self.word(i).is_some_and(|w| w.is_leaf()) {
                done.push(i);
            } else {
                if let Some(r) = done.pop() {
                    parent[r as usize] = i;
                }
                if let Some(l) = done.pop() {
                    parent[l as usize] = i;
                }
                done.push(i);
            }
        }
        parent
    }

    /// Decodes back into a nested [`Node`] (iterative); parameters go
    /// through `f32`, so the result equals the builder's tree exactly when
    /// its parameters are `f32` values.
    ///
    /// # Errors
    /// [`FieldError::Malformed`] when a node does not decode (cannot
    /// happen for validated data).
    pub fn to_node<T: Real>(&self) -> Result<Node<T>, FieldError> {
        let tree = self.as_ref();
        let mut stack: Vec<Node<T>> = Vec::new();
        for i in 0..self.len() as u32 {
            let w = tree.word(i).ok_or(FieldError::Malformed {
                reason: "node out of range",
            })?;
            if w.is_leaf() {
                let p = tree.primitive::<T>(i).ok_or(FieldError::Malformed {
                    reason: "primitive does not decode",
                })?;
                stack.push(Node::primitive(p));
            } else {
                let op = tree.operator::<T>(i).ok_or(FieldError::Malformed {
                    reason: "operator does not decode",
                })?;
                let (Some(r), Some(l)) = (stack.pop(), stack.pop()) else {
                    return Err(FieldError::Malformed {
                        reason: "operator without two operands",
                    });
                };
                stack.push(Node::op(op, l, r));
            }
        }
        match (stack.pop(), stack.is_empty()) {
            (Some(root), true) => Ok(root),
            _ => Err(FieldError::Malformed {
                reason: "post-order sequence does not form one tree",
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deep_trees_drop_compare_and_count_iteratively() {
        let s = || Node::primitive(Primitive::sphere([0.0f64, 0.0, 0.0], 1.0).unwrap());
        let mut a = s();
        let mut b = s();
        for _ in 0..300_000 {
            a = Node::op(Operator::union(), s(), a);
            b = Node::op(Operator::union(), s(), b);
        }
        assert_eq!(a.node_count(), 600_001);
        assert!(a == b);
        // Too deep a right comb for the evaluation stack: refused.
        assert!(matches!(
            FlatBlobtree::from_node(&a),
            Err(FieldError::TooLarge { .. })
        ));
        // Reordered (Sethi–Ullman), it is a left comb.
        let flat = FlatBlobtree::from_node_reordered(&a).unwrap();
        assert_eq!(flat.stack_need(), 2);
        drop(a);
        drop(b);
    }
}
