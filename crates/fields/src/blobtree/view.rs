//! Pruned tree views (paper §6.2, Fig. 11, Alg. 4).

use super::encoding::{BlobtreeRef, NodeWord};
use super::eval::{Program, eval_program, floats_at, lipschitz_program, param_at, twelve};
use super::traversal::{SparseVisitor, sparse_traverse};
use crate::FieldError;
use crate::sdf::AllPrimitives;
use boundtrace_ia_core::Real;
use boundtrace_inclusion::{Field, FieldNum};

/// The paper's `M_overlap`: the default maximal number of active
/// primitives of a [`PrunedView`] (§7).
pub const M_OVERLAP: usize = 128;
/// Default capacity of `B_view` / `B_offset`: `2·M_overlap − 1` nodes.
pub const VIEW_CAPACITY: usize = 2 * M_OVERLAP - 1;
/// Default size of `D_cache` in floats: 3072 bytes (§7).
pub const D_CACHE_FLOATS: usize = 768;
/// Default evaluation stack of a pruned view: 8 entries (§7).
pub const VIEW_STACK: usize = 8;

/// `B_offset` flag: the offset is a 128-bit-unit offset into the tree's
/// parameter array (the node did not fit in `D_cache`), not a float index
/// into the cache.
const GLOBAL: u32 = 1 << 31;

/// A pruned blobtree view (paper §6.2, Fig. 11): the post-order program of
/// the local field `f_𝒜` for a set of active primitives, in fixed-capacity
/// arrays (no allocation):
///
/// * `B_view` (capacity `V`, default [`VIEW_CAPACITY`] `= 2·M_overlap − 1`):
///   the node words of the active primitives and of the operators with two
///   present operands, in post-order. Selectors are resolved while
///   building and do not appear.
/// * `B_offset` (capacity `V`): where each node's parameters are: a float
///   index into `D_cache`, or (when the cache is full, as in the paper) the
///   node's offset in the tree's parameter array.
/// * `D_cache` (`D` floats, default [`D_CACHE_FLOATS`] = 3072 bytes): the
///   parameters of the nodes, copied in view order.
///
/// Evaluation (Alg. 4, the [`Field`] impl) runs a bottom-up pass with a
/// fixed stack of `S` entries (default [`VIEW_STACK`] = 8). A view whose
/// program needs more stack, or more than `V` nodes, is **refused** by
/// [`build`](Self::build) with [`FieldError::TooLarge`] — never truncated.
///
/// When the root is missing (no active primitive can influence the surface
/// in the volume) the view evaluates to `+∞`.
#[derive(Clone, Debug)]
pub struct PrunedView<
    'a,
    const V: usize = VIEW_CAPACITY,
    const D: usize = D_CACHE_FLOATS,
    const S: usize = VIEW_STACK,
> {
    tree: BlobtreeRef<'a>,
    index: [u32; V],
    view: [u32; V],
    offset: [u32; V],
    cache: [f32; D],
    len: u32,
    cache_len: u32,
    root_present: bool,
    stack_need: u32,
}

/// A [`PrunedView`] with the paper's default capacities.
pub type DefaultPrunedView<'a> = PrunedView<'a, VIEW_CAPACITY, D_CACHE_FLOATS, VIEW_STACK>;

struct Recorder<'r, const V: usize> {
    index: &'r mut [u32; V],
    len: u32,
}

impl<const V: usize> Recorder<'_, V> {
    #[inline]
    fn push(&mut self, node: u32) -> Result<(), FieldError> {
        match self.index.get_mut(self.len as usize) {
            Some(slot) => {
                *slot = node;
                self.len += 1;
                Ok(())
            }
            None => Err(FieldError::TooLarge {
                what: "pruned view nodes",
                count: V + 1,
                max: V,
            }),
        }
    }
}

impl<const V: usize> SparseVisitor for Recorder<'_, V> {
    #[inline]
    fn primitive(&mut self, node: u32) -> Result<(), FieldError> {
        self.push(node)
    }
    #[inline]
    fn operator(&mut self, node: u32) -> Result<(), FieldError> {
        self.push(node)
    }
    #[inline]
    fn kill(&mut self, emitted: u32) -> Result<(), FieldError> {
        self.len = emitted.min(self.len);
        Ok(())
    }
}

impl<'a, const V: usize, const D: usize, const S: usize> PrunedView<'a, V, D, S> {
    /// Builds the view of `tree` for the active primitives `active`
    /// (strictly increasing post-order indices of leaves) by the sparse
    /// traversal ([`sparse_traverse`]), then fills `D_cache` (§6.2: nodes
    /// that do not fit keep their global offset).
    ///
    /// # Errors
    /// [`FieldError::TooLarge`] when the view needs more than `V` nodes or
    /// more than `S` evaluation stack entries (or the traversal stack
    /// overflows); [`FieldError::Malformed`] for a bad `active` list.
    pub fn build(tree: BlobtreeRef<'a>, active: &[u32]) -> Result<Self, FieldError> {
        let mut index = [0u32; V];
        let mut rec = Recorder::<V> {
            index: &mut index,
            len: 0,
        };
        let root_present = sparse_traverse(&tree, active, &mut rec)?;
        let len = if root_present { rec.len } else { 0 };
        let mut out = Self {
            tree,
            index,
            view: [0; V],
            offset: [0; V],
            cache: [0.0; D],
            len,
            cache_len: 0,
            root_present,
            stack_need: 0,
        };
        // Node words, parameters, stack need.
        let mut depth = 0u32;
        let mut need = 0u32;
        let mut i = 0usize;
        while i < len as usize {
            let node = out.index[i];
            let w = tree.word(node).ok_or(FieldError::Malformed {
                reason: "view node out of range",
            })?;
            out.view[i] = w.0;
            let d = tree.node_params(node).ok_or(FieldError::Malformed {
                reason: "view node parameters out of range",
            })?;
            let start = out.cache_len as usize;
            match out.cache.get_mut(start..start + d.len()) {
                Some(dst) => {
                    dst.copy_from_slice(d);
                    out.offset[i] = start as u32;
                    out.cache_len += d.len() as u32;
                }
                None => {
                    out.offset[i] = GLOBAL | tree.offset(node).unwrap_or(0);
                }
            }
            if w.is_leaf() {
                depth += 1;
                need = need.max(depth);
            } else {
                depth = depth.saturating_sub(1);
            }
            i += 1;
        }
        if need as usize > S {
            return Err(FieldError::TooLarge {
                what: "pruned view evaluation stack entries",
                count: need as usize,
                max: S,
            });
        }
        out.stack_need = need;
        Ok(out)
    }

    /// Number of nodes in `B_view`.
    #[inline]
    pub fn len(&self) -> usize {
        self.len as usize
    }

    /// Whether the view has no node (the root is missing: the field is
    /// `+∞` in the volume).
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Whether the root is present (some active primitive reaches it).
    #[inline]
    pub fn root_present(&self) -> bool {
        self.root_present
    }

    /// The post-order indices (in the full tree) of the view's nodes.
    #[inline]
    pub fn node_indices(&self) -> &[u32] {
        &self.index[..self.len as usize]
    }

    /// The view's node words (`B_view`).
    #[inline]
    pub fn node_words(&self) -> &[u32] {
        &self.view[..self.len as usize]
    }

    /// Floats of `D_cache` in use.
    #[inline]
    pub fn cache_used(&self) -> usize {
        self.cache_len as usize
    }

    /// Number of view nodes whose parameters are read from the tree (did
    /// not fit in `D_cache`).
    pub fn uncached_nodes(&self) -> usize {
        self.offset[..self.len as usize]
            .iter()
            .filter(|&&o| o & GLOBAL != 0)
            .count()
    }

    /// The evaluation stack depth the view needs (≤ `S`).
    #[inline]
    pub fn stack_need(&self) -> usize {
        self.stack_need as usize
    }

    /// A Lipschitz bound of the pruned field (as
    /// [`BlobtreeRef::lipschitz_bound`], over the view's nodes; `0` for a
    /// missing root).
    pub fn lipschitz_bound<T: Real>(&self) -> Option<T> {
        if self.len == 0 {
            return Some(T::ZERO);
        }
        lipschitz_program::<T, Self, S>(self)
    }
}

/// The pruned field `f_𝒜` (Alg. 4), for every number type.
impl<T: Real, const V: usize, const D: usize, const S: usize> Field<T> for PrunedView<'_, V, D, S> {
    fn eval<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        if self.len == 0 {
            return N::constant(T::INFINITY);
        }
        eval_program::<T, N, Self, AllPrimitives, S>(self, p)
    }

    fn lipschitz(&self) -> Option<T> {
        self.lipschitz_bound()
    }
}

impl<const V: usize, const D: usize, const S: usize> Program for PrunedView<'_, V, D, S> {
    #[inline]
    fn node_count(&self) -> usize {
        self.len as usize
    }
    #[inline]
    fn node_word(&self, i: usize) -> Option<NodeWord> {
        self.view.get(i).map(|&w| NodeWord(w))
    }
    #[inline]
    fn param(&self, i: usize, k: usize) -> f32 {
        match self.offset.get(i) {
            Some(&off) if off & GLOBAL != 0 => param_at(self.tree.params(), off & !GLOBAL, k),
            Some(&off) => self
                .cache
                .get(off as usize + k)
                .copied()
                .unwrap_or(f32::NAN),
            None => f32::NAN,
        }
    }
    /// The node's offset read once ([`floats_at`] for a node read from
    /// the full tree; the cache's 12 floats without a check each when they
    /// all lie in it).
    #[inline]
    fn node_floats(&self, i: usize) -> [f32; 12] {
        match self.offset.get(i) {
            Some(&off) if off & GLOBAL != 0 => floats_at(self.tree.params(), off & !GLOBAL),
            Some(&off) => {
                let (at, c) = (off as usize, &self.cache);
                if at + 12 <= c.len() {
                    twelve(|k| c[at + k])
                } else {
                    twelve(|k| c.get(at + k).copied().unwrap_or(f32::NAN))
                }
            }
            None => [f32::NAN; 12],
        }
    }
}

#[cfg(all(test, feature = "alloc"))]
mod tests {
    use super::*;
    use crate::blobtree::{FlatBlobtree, Node};
    use crate::operator::Operator;
    use crate::sdf::Primitive;

    #[test]
    fn view_matches_full_tree_when_all_active() {
        let s = |x: f64| Node::primitive(Primitive::sphere([x, 0.2, 0.0], 0.6).unwrap());
        let u = Operator::compact_union(0.3, 0.4).unwrap();
        let d = Operator::compact_difference(0.2, 0.3).unwrap();
        let tree = Node::op(d, Node::op(u, s(0.0), s(0.9)), Node::op(u, s(0.5), s(3.0)));
        let flat = FlatBlobtree::from_node(&tree).unwrap();
        let all = flat.primitive_indices();
        let view: DefaultPrunedView = DefaultPrunedView::build(flat.as_ref(), &all).unwrap();
        assert_eq!(view.len(), flat.len());
        assert_eq!(view.uncached_nodes(), 0);
        for k in 0..50 {
            let p = [k as f64 * 0.1 - 1.0, 0.1, -0.05];
            let a: f64 = flat.as_ref().eval(p);
            let b: f64 = view.eval(p);
            assert_eq!(a, b);
        }
        // No active primitive: +∞, empty view.
        let empty: DefaultPrunedView = DefaultPrunedView::build(flat.as_ref(), &[]).unwrap();
        assert!(empty.is_empty() && !empty.root_present());
        let v: f64 = empty.eval([0.0; 3]);
        assert_eq!(v, f64::INFINITY);
    }

    /// `node_floats` (offset read once) equals `param` float by float, for
    /// cached nodes, nodes read from the full tree (a cache too small for
    /// them) and indices past the view.
    #[test]
    fn node_floats_equal_param_by_param() {
        let s = |x: f64| Node::primitive(Primitive::sphere([x, 0.2, 0.0], 0.6).unwrap());
        let c =
            |x: f64| Node::primitive(Primitive::cuboid([x, 0.0, 0.0], [0.3, 0.2, 0.1]).unwrap());
        let u = Operator::compact_union(0.3, 0.4).unwrap();
        let tree = Node::op(u, Node::op(u, s(0.0), c(0.9)), Node::op(u, c(0.5), s(3.0)));
        let flat = FlatBlobtree::from_node(&tree).unwrap();
        let all = flat.primitive_indices();
        fn check<const D: usize>(view: &PrunedView<'_, VIEW_CAPACITY, D, VIEW_STACK>) {
            for i in 0..view.len() + 2 {
                let a = Program::node_floats(view, i);
                let b: [f32; 12] = core::array::from_fn(|k| view.param(i, k));
                let same = a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits());
                assert!(same, "node {i}, cache {D}: {a:?} vs {b:?}");
            }
        }
        let big: PrunedView<'_, VIEW_CAPACITY, 256, VIEW_STACK> =
            PrunedView::build(flat.as_ref(), &all).unwrap();
        assert_eq!(big.uncached_nodes(), 0);
        check(&big);
        let small: PrunedView<'_, VIEW_CAPACITY, 14, VIEW_STACK> =
            PrunedView::build(flat.as_ref(), &all).unwrap();
        assert!(small.uncached_nodes() > 0);
        check(&small);
    }
}
