//! Node-level interpreters (paper Alg. 1) and the full-tree, sparse and
//! Lipschitz evaluations of a [`BlobtreeRef`].

use super::encoding::{BlobtreeRef, NodeWord, STACK_CAPACITY, param_slice};
use super::traversal::{SparseVisitor, TRAVERSAL_STACK, sparse_traverse};
use crate::FieldError;
use crate::operator::Operator;
use crate::sdf::Primitive;
use boundtrace_ia_core::Real;
use boundtrace_inclusion::{Field, FieldNum};

/// The value returned for data that validation excludes (so never for a
/// tree accepted by [`BlobtreeRef::new`]): NaN, which a tracer treats as
/// "no information" rather than a confident wrong answer.
#[inline]
pub(crate) fn corrupt<T: Real, N: FieldNum<T>>() -> N {
    N::constant(T::nan())
}

/// `PRIMITIVE(nodeop, D, p)` of Alg. 1: decodes `D` for the node's kind
/// and evaluates it at `p`.
#[inline]
pub(crate) fn primitive_node<T: Real, N: FieldNum<T>>(
    w: NodeWord,
    d: Option<&[f32]>,
    p: [N; 3],
) -> N {
    match (w.primitive_kind(), d) {
        (Some(kind), Some(d)) => match Primitive::<T>::read_params(kind, d) {
            Some(prim) => prim.eval(p),
            None => corrupt(),
        },
        _ => corrupt(),
    }
}

/// `OPERATOR(nodeop, D, f₀, f₁)` of Alg. 1.
#[inline]
pub(crate) fn operator_node<T: Real, N: FieldNum<T>>(
    w: NodeWord,
    d: Option<&[f32]>,
    f0: N,
    f1: N,
) -> N {
    match (w.operator_kind(), d) {
        (Some(kind), Some(d)) => match Operator::<T>::read_params(kind, d) {
            Some(op) => op.eval(f0, f1),
            None => corrupt(),
        },
        _ => corrupt(),
    }
}

/// The number of 128-bit parameter slots of node word `w`.
#[inline]
pub(crate) fn node_vec4s(w: NodeWord) -> Option<u32> {
    if w.is_leaf() {
        Some(w.primitive_kind()?.param_vec4s())
    } else {
        Some(w.operator_kind()?.param_vec4s())
    }
}

/// The parameter slice of node word `w` at `offset` (128-bit units) in
/// `params`.
#[inline]
pub(crate) fn node_data(params: &[f32], w: NodeWord, offset: u32) -> Option<&[f32]> {
    param_slice(params, offset, node_vec4s(w)?)
}

/// Alg. 1 over a post-order program of `len` nodes whose node words and
/// parameter slices are given by `node(i)`, with a fixed stack of `S`
/// entries: the interpreter shared by the full tree and the pruned views.
/// A node that does not decode or a stack overflow gives [`corrupt`]
/// (validated data never does).
#[inline]
pub(crate) fn eval_program<'d, T: Real, N: FieldNum<T>, const S: usize>(
    len: usize,
    p: [N; 3],
    node: impl Fn(usize) -> Option<(NodeWord, Option<&'d [f32]>)>,
) -> N {
    let mut stack = [N::constant(T::ZERO); S];
    let mut sp = 0usize;
    let mut i = 0usize;
    while i < len {
        let Some((w, d)) = node(i) else {
            return corrupt();
        };
        if w.is_leaf() {
            let v = primitive_node::<T, N>(w, d, p);
            match stack.get_mut(sp) {
                Some(slot) => *slot = v,
                None => return corrupt(),
            }
            sp += 1;
        } else {
            if sp < 2 {
                return corrupt();
            }
            let f1 = stack[sp - 1];
            let f0 = stack[sp - 2];
            sp -= 1;
            stack[sp - 1] = operator_node::<T, N>(w, d, f0, f1);
        }
        i += 1;
    }
    if sp == 1 { stack[0] } else { corrupt() }
}

/// `max(L₀, L₁) · factor` per operator, `L_prim` per primitive: a bound of
/// the Lipschitz constant of a post-order program whose node words and
/// parameter slices are given by `node(i)`, `i < len`. `None` when the
/// stack would overflow `S` or a node does not decode.
pub(crate) fn lipschitz_program<'d, T: Real, const S: usize>(
    len: usize,
    node: impl Fn(usize) -> Option<(NodeWord, &'d [f32])>,
) -> Option<T> {
    let mut stack = [T::ZERO; S];
    let mut sp = 0usize;
    let mut i = 0usize;
    while i < len {
        let (w, d) = node(i)?;
        if w.is_leaf() {
            let prim = Primitive::<T>::read_params(w.primitive_kind()?, d)?;
            *stack.get_mut(sp)? = prim.lipschitz();
            sp += 1;
        } else {
            let op = Operator::<T>::read_params(w.operator_kind()?, d)?;
            if sp < 2 {
                return None;
            }
            let l = stack[sp - 2].max(stack[sp - 1]) * op.lipschitz_factor();
            sp -= 1;
            stack[sp - 1] = l;
        }
        i += 1;
    }
    if sp == 1 { Some(stack[0]) } else { None }
}

impl<'a> BlobtreeRef<'a> {
    /// The full-tree field at `p` (Alg. 1 over every node in post-order,
    /// fixed stack of [`STACK_CAPACITY`]); the same as
    /// [`Field::eval`].
    #[inline]
    pub fn eval_full<T: Real, N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        let nodes = self.nodes();
        let params = self.params();
        eval_program::<T, N, STACK_CAPACITY>(self.len(), p, |i| {
            let w = NodeWord(*nodes.get(2 * i)?);
            Some((w, node_data(params, w, *nodes.get(2 * i + 1)?)))
        })
    }

    /// The local field `f_𝒜` at `p` by a direct sparse traversal (paper
    /// §5): only the active primitives `active` (strictly increasing
    /// post-order indices, e.g. from
    /// [`FlatBlobtree::active_in_box`](super::FlatBlobtree::active_in_box))
    /// and the operators joining them are evaluated; selectors pass or drop
    /// operands (module docs). `+∞` when the root is missing (no active
    /// primitive influences the surface: no surface in the volume).
    ///
    /// # Errors
    /// As [`sparse_traverse`]; in particular [`FieldError::Malformed`] for
    /// an unsorted or non-leaf `active`.
    pub fn eval_sparse<T: Real, N: FieldNum<T>>(
        &self,
        active: &[u32],
        p: [N; 3],
    ) -> Result<N, FieldError> {
        let mut ev = SparseEval::<T, N> {
            tree: *self,
            p,
            stack: [N::constant(T::ZERO); TRAVERSAL_STACK],
            sp: 0,
            _t: core::marker::PhantomData,
        };
        let present = sparse_traverse(self, active, &mut ev)?;
        if !present {
            return Ok(N::constant(T::INFINITY));
        }
        if ev.sp == 1 {
            Ok(ev.stack[0])
        } else {
            Err(FieldError::Malformed {
                reason: "sparse evaluation left an unbalanced stack",
            })
        }
    }

    /// A Lipschitz bound of the full field: primitives' bounds combined
    /// bottom-up by `max(L₀, L₁) · lipschitz_factor` (so at most the
    /// product of the operator factors along the worst root–leaf path;
    /// compact operators compress the field, paper §7 traces with 1.45).
    /// `None` only for data validation excludes.
    pub fn lipschitz_bound<T: Real>(&self) -> Option<T> {
        let nodes = self.nodes();
        let params = self.params();
        lipschitz_program::<T, STACK_CAPACITY>(self.len(), |i| {
            let w = NodeWord(*nodes.get(2 * i)?);
            let d = node_data(params, w, *nodes.get(2 * i + 1)?)?;
            Some((w, d))
        })
    }
}

struct SparseEval<'a, T: Real, N: FieldNum<T>> {
    tree: BlobtreeRef<'a>,
    p: [N; 3],
    stack: [N; TRAVERSAL_STACK],
    sp: usize,
    _t: core::marker::PhantomData<T>,
}

const OVERFLOW: FieldError = FieldError::TooLarge {
    what: "sparse evaluation stack entries",
    count: TRAVERSAL_STACK + 1,
    max: TRAVERSAL_STACK,
};

const UNBALANCED: FieldError = FieldError::Malformed {
    reason: "sparse evaluation stack underflow",
};

impl<T: Real, N: FieldNum<T>> SparseVisitor for SparseEval<'_, T, N> {
    #[inline]
    fn primitive(&mut self, node: u32) -> Result<(), FieldError> {
        let w = self.tree.word(node).ok_or(UNBALANCED)?;
        let v = primitive_node::<T, N>(w, self.tree.node_params(node), self.p);
        *self.stack.get_mut(self.sp).ok_or(OVERFLOW)? = v;
        self.sp += 1;
        Ok(())
    }

    #[inline]
    fn operator(&mut self, node: u32) -> Result<(), FieldError> {
        if self.sp < 2 {
            return Err(UNBALANCED);
        }
        let w = self.tree.word(node).ok_or(UNBALANCED)?;
        let f1 = self.stack[self.sp - 1];
        let f0 = self.stack[self.sp - 2];
        self.sp -= 1;
        self.stack[self.sp - 1] = operator_node::<T, N>(w, self.tree.node_params(node), f0, f1);
        Ok(())
    }

    #[inline]
    fn kill(&mut self, _emitted: u32) -> Result<(), FieldError> {
        if self.sp == 0 {
            return Err(UNBALANCED);
        }
        self.sp -= 1;
        Ok(())
    }
}

/// The full blobtree field (Alg. 1), for every number type.
impl<T: Real> Field<T> for BlobtreeRef<'_> {
    #[inline]
    fn eval<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        self.eval_full::<T, N>(p)
    }

    fn lipschitz(&self) -> Option<T> {
        self.lipschitz_bound()
    }
}
