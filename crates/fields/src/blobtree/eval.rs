//! Node-level interpreters (paper Alg. 1) and the full-tree, sparse and
//! Lipschitz evaluations of a [`BlobtreeRef`].

use super::encoding::{BlobtreeRef, NodeWord, STACK_CAPACITY};
use super::traversal::{SparseVisitor, TRAVERSAL_STACK, sparse_traverse};
use crate::FieldError;
use crate::operator::{Operator, OperatorKind};
use crate::sdf::{AllPrimitives, Primitive, PrimitiveKind, PrimitiveKinds};
use boundtrace_ia_core::Real;
use boundtrace_inclusion::{Field, FieldNum};

/// The value returned for data that validation excludes (so never for a
/// tree accepted by [`BlobtreeRef::new`]): NaN, which a tracer treats as
/// "no information" rather than a confident wrong answer.
#[inline]
pub(crate) fn corrupt<T: Real, N: FieldNum<T>>() -> N {
    N::constant(T::nan())
}

/// A post-order program as the interpreters read it: node words and
/// parameter floats by index, without slices or `Option`s of them (the
/// GPU shader can build neither), out-of-range reads answered with NaN
/// rather than a panic. The full tree ([`BlobtreeRef`]) and the pruned
/// views are programs.
pub(crate) trait Program {
    /// The number of nodes.
    fn node_count(&self) -> usize;
    /// The node word of node `i` (`None` out of range).
    fn node_word(&self, i: usize) -> Option<NodeWord>;
    /// Parameter float `k` of node `i` (NaN out of range).
    fn param(&self, i: usize, k: usize) -> f32;
    /// The 12 parameter floats a node can have (3 slots of 4) of node
    /// `i`, `param(i, 0..12)` ([`twelve`]: no loop).
    #[inline]
    fn node_floats(&self, i: usize) -> [f32; 12] {
        twelve(|k| self.param(i, k))
    }
}

/// `PRIMITIVE(nodeop, D, p)` of Alg. 1: decodes node `i` of `prog` (a
/// leaf, word `w`) and evaluates it at `p`.
#[inline]
pub(crate) fn primitive_node<T: Real, N: FieldNum<T>, P: Program, K: PrimitiveKinds>(
    prog: &P,
    i: usize,
    w: NodeWord,
    p: [N; 3],
) -> N {
    match w.primitive_kind() {
        Some(kind) => eval_primitive::<T, N, K>(kind, prog.node_floats(i), p),
        None => corrupt(),
    }
}

/// `OPERATOR(nodeop, D, f₀, f₁)` of Alg. 1 for node `i` of `prog` (word
/// `w`).
#[inline]
pub(crate) fn operator_node<T: Real, N: FieldNum<T>, P: Program>(
    prog: &P,
    i: usize,
    w: NodeWord,
    f0: N,
    f1: N,
) -> N {
    match w.operator_kind() {
        Some(kind) => eval_operator::<T, N>(kind, prog.param(i, 0), prog.param(i, 1), f0, f1),
        None => corrupt(),
    }
}

/// A primitive of `kind` decoded from its parameter floats `d` and
/// evaluated at `p`. Arguments by value and, in the GPU shader, not
/// inlined: the interpreter's nodes then share one copy of every
/// primitive's code per number type (inlined at each evaluation of the
/// tracer, rust-gpu's build of the blobtree module ran out of this
/// machine's 24 GiB; BENCHMARKS.md "GPU", session 23).
#[cfg_attr(target_arch = "spirv", inline(never))]
#[cfg_attr(not(target_arch = "spirv"), inline)]
fn eval_primitive<T: Real, N: FieldNum<T>, K: PrimitiveKinds>(
    kind: PrimitiveKind,
    d: [f32; 12],
    p: [N; 3],
) -> N {
    Primitive::<T>::decode_with(kind, |k| d[k]).eval_among::<N, K>(p)
}

/// An operator of `kind` with parameters `b`, `r` (its first two floats)
/// applied to `f0`, `f1`; not inlined in the GPU shader, as
/// [`eval_primitive`].
#[cfg_attr(target_arch = "spirv", inline(never))]
#[cfg_attr(not(target_arch = "spirv"), inline)]
fn eval_operator<T: Real, N: FieldNum<T>>(kind: OperatorKind, b: f32, r: f32, f0: N, f1: N) -> N {
    Operator::<T>::decode_with(kind, |k| if k == 0 { b } else { r }).eval(f0, f1)
}

/// Parameter float `k` of the node at `offset` (128-bit units) in
/// `params`, NaN out of range.
#[inline]
pub(crate) fn param_at(params: &[f32], offset: u32, k: usize) -> f32 {
    // No `checked_mul` (rust-gpu lacks it): `offset ≤ len / 4` keeps
    // `4·offset + k` far from overflow (`k` < 16 for every node kind).
    let off = offset as usize;
    if off > params.len() / 4 || k >= 16 {
        return f32::NAN;
    }
    let at = 4 * off + k;
    if at < params.len() {
        params[at]
    } else {
        f32::NAN
    }
}

/// Alg. 1 over the post-order program `prog` with a fixed stack of `S`
/// entries: the interpreter shared by the full tree and the pruned views,
/// on the CPU and in the GPU shader. Nodes are decoded without the
/// constructors' checks (the program was validated when it was built); a
/// node word that does not decode or a stack overflow gives [`corrupt`]
/// (validated data never does).
#[inline]
pub(crate) fn eval_program<
    T: Real,
    N: FieldNum<T>,
    P: Program,
    K: PrimitiveKinds,
    const S: usize,
>(
    prog: &P,
    p: [N; 3],
) -> N {
    let mut stack = [N::constant(T::ZERO); S];
    let mut sp = 0usize;
    let mut i = 0usize;
    let len = prog.node_count();
    while i < len {
        let Some(w) = prog.node_word(i) else {
            return corrupt();
        };
        if w.is_leaf() {
            if sp >= S {
                return corrupt();
            }
            stack[sp] = primitive_node::<T, N, P, K>(prog, i, w, p);
            sp += 1;
        } else {
            if sp < 2 {
                return corrupt();
            }
            let f1 = stack[sp - 1];
            let f0 = stack[sp - 2];
            sp -= 1;
            stack[sp - 1] = operator_node::<T, N, P>(prog, i, w, f0, f1);
        }
        i += 1;
    }
    if sp == 1 { stack[0] } else { corrupt() }
}

/// `max(L₀, L₁) · factor` per operator, `L_prim` per primitive: a bound of
/// the Lipschitz constant of the post-order program `prog`. `None` when
/// the stack would overflow `S` or a node does not decode.
pub(crate) fn lipschitz_program<T: Real, P: Program, const S: usize>(prog: &P) -> Option<T> {
    let mut stack = [T::ZERO; S];
    let mut sp = 0usize;
    let mut i = 0usize;
    let len = prog.node_count();
    while i < len {
        let w = prog.node_word(i)?;
        if w.is_leaf() {
            let prim = Primitive::<T>::decode_with(w.primitive_kind()?, |k| prog.param(i, k));
            if sp >= S {
                return None;
            }
            stack[sp] = prim.lipschitz();
            sp += 1;
        } else {
            let op = Operator::<T>::decode_with(w.operator_kind()?, |k| prog.param(i, k));
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

impl Program for BlobtreeRef<'_> {
    #[inline]
    fn node_count(&self) -> usize {
        self.len()
    }
    #[inline]
    fn node_word(&self, i: usize) -> Option<NodeWord> {
        let nodes = self.nodes();
        if 2 * i < nodes.len() {
            Some(NodeWord(nodes[2 * i]))
        } else {
            None
        }
    }
    #[inline]
    fn param(&self, i: usize, k: usize) -> f32 {
        let nodes = self.nodes();
        if 2 * i + 1 < nodes.len() {
            param_at(self.params(), nodes[2 * i + 1], k)
        } else {
            f32::NAN
        }
    }
    /// The node's offset read once, and its 12 floats without a check
    /// each when they all lie in the buffer (a validated tree's do, but
    /// its last node may have fewer): [`floats_at`].
    #[inline]
    fn node_floats(&self, i: usize) -> [f32; 12] {
        let nodes = self.nodes();
        if 2 * i + 1 < nodes.len() {
            floats_at(self.params(), nodes[2 * i + 1])
        } else {
            [f32::NAN; 12]
        }
    }
}

/// The 12 parameter floats from `offset` (128-bit units) in `params`,
/// [`param_at`] of each, without a check each when all 12 lie in the
/// buffer.
#[inline]
pub(crate) fn floats_at(params: &[f32], offset: u32) -> [f32; 12] {
    let off = offset as usize;
    // `off ≤ len / 4` first: `4·off + 12` cannot overflow then.
    if off <= params.len() / 4 && 4 * off + 12 <= params.len() {
        let at = 4 * off;
        twelve(|k| params[at + k])
    } else {
        twelve(|k| param_at(params, offset, k))
    }
}

/// `[f(0), …, f(11)]`: a node's parameter floats, written out, not a
/// loop (a GPU driver with a loop limit, lavapipe, counts every loop
/// iteration, and this runs per primitive and evaluation).
#[inline]
pub(crate) fn twelve<F: Fn(usize) -> f32>(f: F) -> [f32; 12] {
    [
        f(0),
        f(1),
        f(2),
        f(3),
        f(4),
        f(5),
        f(6),
        f(7),
        f(8),
        f(9),
        f(10),
        f(11),
    ]
}

impl<'a> BlobtreeRef<'a> {
    /// The full-tree field at `p` (Alg. 1 over every node in post-order,
    /// fixed stack of [`STACK_CAPACITY`]); the same as
    /// [`Field::eval`].
    #[inline]
    pub fn eval_full<T: Real, N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        self.eval_among::<T, N, AllPrimitives>(p)
    }

    /// [`eval_full`](Self::eval_full) compiled for the primitive kinds of
    /// `K` only ([`Primitive::eval_among`]): a primitive of another kind
    /// evaluates to NaN; for a tree without them, the same values.
    #[inline]
    pub fn eval_among<T: Real, N: FieldNum<T>, K: PrimitiveKinds>(&self, p: [N; 3]) -> N {
        eval_program::<T, N, Self, K, STACK_CAPACITY>(self, p)
    }

    /// Whether every primitive of the tree is of a kind of `K`.
    pub fn primitives_among<K: PrimitiveKinds>(&self) -> bool {
        (0..self.len()).all(|i| {
            self.node_word(i)
                .and_then(NodeWord::primitive_kind)
                .is_none_or(K::contains)
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
        lipschitz_program::<T, Self, STACK_CAPACITY>(self)
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
        let v = primitive_node::<T, N, _, AllPrimitives>(&self.tree, node as usize, w, self.p);
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
        self.stack[self.sp - 1] = operator_node::<T, N, _>(&self.tree, node as usize, w, f0, f1);
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

/// A blobtree evaluated with the primitive kinds of `K` only
/// ([`BlobtreeRef::eval_among`]): the field of the GPU shader's blobtree
/// entry point, whose host checks [`BlobtreeRef::primitives_among`] before
/// upload. For such a tree it is the [`BlobtreeRef`] field, bit for bit.
#[derive(Clone, Copy, Debug)]
pub struct BlobtreeAmong<'a, K> {
    tree: BlobtreeRef<'a>,
    _kinds: core::marker::PhantomData<K>,
}

impl<'a, K: PrimitiveKinds> BlobtreeAmong<'a, K> {
    /// `tree`, evaluated with the kinds of `K` (a primitive of another
    /// kind gives NaN).
    ///
    /// ```
    /// use boundtrace_fields::blobtree::{BlobtreeAmong, FlatBlobtree, Node};
    /// use boundtrace_fields::{AlgebraicPrimitives, Primitive};
    /// use boundtrace_inclusion::Field;
    /// let ball = FlatBlobtree::from_node(&Node::primitive(Primitive::sphere([0.0; 3], 0.5)?))?;
    /// let t = ball.as_ref();
    /// assert!(t.primitives_among::<AlgebraicPrimitives>());
    /// let f = BlobtreeAmong::<AlgebraicPrimitives>::new(t);
    /// assert_eq!(f.eval([1.0f32, 0.0, 0.0]), t.eval([1.0f32, 0.0, 0.0]));
    /// // A gyroid is left out: NaN, and the check says so.
    /// let g = FlatBlobtree::from_node(&Node::primitive(Primitive::gyroid(1.0, 0.1)?))?;
    /// assert!(!g.as_ref().primitives_among::<AlgebraicPrimitives>());
    /// let f = BlobtreeAmong::<AlgebraicPrimitives>::new(g.as_ref());
    /// assert!(f.eval([0.1f32; 3]).is_nan());
    /// # Ok::<(), boundtrace_fields::FieldError>(())
    /// ```
    #[inline]
    pub fn new(tree: BlobtreeRef<'a>) -> Self {
        Self {
            tree,
            _kinds: core::marker::PhantomData,
        }
    }
}

impl<T: Real, K: PrimitiveKinds> Field<T> for BlobtreeAmong<'_, K> {
    #[inline]
    fn eval<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        self.tree.eval_among::<T, N, K>(p)
    }

    fn lipschitz(&self) -> Option<T> {
        self.tree.lipschitz_bound()
    }
}

/// Words per tile in the table that opens a tiled program buffer
/// ([`BlobtreeWindow::tile`]): the tile's first node, its node count and
/// the bits of its `f32` Lipschitz bound.
pub const TILE_TABLE_WORDS: usize = 3;

/// A post-order program that is a window of nodes of a larger node buffer,
/// with its own Lipschitz bound: the whole tree, or the program of one
/// image tile in a tiled buffer (a table of [`TILE_TABLE_WORDS`] words per
/// tile, then the tiles' node pairs `(word, parameter offset)`, the
/// offsets into the tree's own parameter buffer). The GPU shader's
/// blobtree field: one type for both, so that the shader holds the tracer
/// once. Primitives of kinds outside `K` evaluate to NaN
/// ([`BlobtreeAmong`]).
///
/// An empty window (a tile no primitive's ABV reaches) is the constant
/// largest finite value (no surface; a sparse evaluation without a root,
/// [`BlobtreeRef::eval_sparse`], gives `+∞`, which an interval cannot
/// hold as a point: a tracer would see an empty enclosure). Data the host
/// did not validate gives NaN values, never a panic or a read out of
/// bounds.
///
/// ```
/// use boundtrace_fields::blobtree::{BlobtreeWindow, FlatBlobtree, Node, TILE_TABLE_WORDS};
/// use boundtrace_fields::{AllPrimitives, Operator, Primitive};
/// use boundtrace_inclusion::Field;
/// let s = |x: f64| Node::primitive(Primitive::sphere([x, 0.0, 0.0], 0.3).unwrap());
/// let tree = FlatBlobtree::from_node(&Node::op(Operator::union(), s(-0.5), s(0.5)))?;
/// let t = tree.as_ref();
/// let whole = BlobtreeWindow::<AllPrimitives>::whole(t, 1.0);
/// assert_eq!(whole.eval([0.5f32, 0.0, 0.0]), t.eval([0.5f32, 0.0, 0.0]));
/// // Two tiles: the first sees the right sphere alone (node 1), the second nothing.
/// let n = t.nodes();
/// // Pair 3 (words 6, 7) is the first after the table.
/// let mut words = vec![3, 1, 1.0f32.to_bits(), 4, 0, 1.0f32.to_bits()];
/// words.extend_from_slice(&n[2..4]);
/// assert_eq!(words.len(), 2 * TILE_TABLE_WORDS + 2);
/// let right = BlobtreeWindow::<AllPrimitives>::tile(&words, t.params(), 0);
/// let p = [0.6f32, 0.0, 0.0];
/// assert_eq!(right.eval(p), t.eval(p));
/// assert_eq!(right.lipschitz(), Some(1.0));
/// let empty = BlobtreeWindow::<AllPrimitives>::tile(&words, t.params(), 1);
/// assert_eq!(empty.eval(p), f32::MAX);
/// // No such tile: NaN.
/// assert!(BlobtreeWindow::<AllPrimitives>::tile(&words, t.params(), 2).eval(p).is_nan());
/// # Ok::<(), boundtrace_fields::FieldError>(())
/// ```
#[derive(Clone, Copy, Debug)]
pub struct BlobtreeWindow<'a, K> {
    nodes: &'a [u32],
    params: &'a [f32],
    /// The first node (pair index into `nodes`).
    first: usize,
    /// The node count.
    len: usize,
    /// The Lipschitz bound (`≤ 0` or NaN: the program's own).
    lipschitz: f32,
    /// Whether the window's table entry was readable.
    valid: bool,
    _kinds: core::marker::PhantomData<K>,
}

impl<'a, K: PrimitiveKinds> BlobtreeWindow<'a, K> {
    /// The whole tree, with the Lipschitz bound `lipschitz` (`≤ 0` or NaN:
    /// [`BlobtreeRef::lipschitz_bound`], computed at every call).
    #[inline]
    pub fn whole(tree: BlobtreeRef<'a>, lipschitz: f32) -> Self {
        Self {
            nodes: tree.nodes(),
            params: tree.params(),
            first: 0,
            len: tree.len(),
            lipschitz,
            valid: true,
            _kinds: core::marker::PhantomData,
        }
    }

    /// Tile `tile` of the tiled buffer `words` (type docs), whose node
    /// pairs' offsets point into `params`. A tile past the table, or a
    /// window past the buffer, evaluates to NaN.
    #[inline]
    pub fn tile(words: &'a [u32], params: &'a [f32], tile: usize) -> Self {
        let at = tile.wrapping_mul(TILE_TABLE_WORDS);
        let valid = tile < words.len() / TILE_TABLE_WORDS;
        let (first, len, bits) = if valid {
            (words[at] as usize, words[at + 1] as usize, words[at + 2])
        } else {
            (0, 0, 0)
        };
        Self {
            nodes: words,
            params,
            first,
            len,
            lipschitz: f32::from_bits(bits),
            valid,
            _kinds: core::marker::PhantomData,
        }
    }

    /// The number of nodes.
    #[inline]
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether the window has no node (a constant: no surface).
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The Lipschitz bound of the window's program computed from its
    /// nodes ([`BlobtreeRef::lipschitz_bound`] for the whole tree); `None`
    /// for data validation excludes. An empty window (a constant) gives
    /// `1`: any positive bound holds, and a tracer needs one.
    pub fn program_lipschitz<T: Real>(&self) -> Option<T> {
        if !self.valid {
            return None;
        }
        if self.len == 0 {
            return Some(T::ONE);
        }
        lipschitz_program::<T, Self, STACK_CAPACITY>(self)
    }

    /// The node pair index of node `i`, if inside the window and buffer.
    #[inline]
    fn pair(&self, i: usize) -> Option<usize> {
        // `first ≤ len(nodes) / 2` keeps `first + i` from overflowing.
        if !self.valid || i >= self.len || self.first > self.nodes.len() / 2 {
            return None;
        }
        let j = self.first + i;
        if 2 * j + 1 < self.nodes.len() {
            Some(j)
        } else {
            None
        }
    }
}

impl<K: PrimitiveKinds> Program for BlobtreeWindow<'_, K> {
    #[inline]
    fn node_count(&self) -> usize {
        self.len
    }
    // A `match`, not `Option::map` with a closure: rust-gpu cannot build
    // closures that capture pointers.
    #[allow(clippy::manual_map)]
    #[inline]
    fn node_word(&self, i: usize) -> Option<NodeWord> {
        match self.pair(i) {
            Some(j) => Some(NodeWord(self.nodes[2 * j])),
            None => None,
        }
    }
    #[inline]
    fn param(&self, i: usize, k: usize) -> f32 {
        match self.pair(i) {
            Some(j) => param_at(self.params, self.nodes[2 * j + 1], k),
            None => f32::NAN,
        }
    }
    #[inline]
    fn node_floats(&self, i: usize) -> [f32; 12] {
        match self.pair(i) {
            Some(j) => floats_at(self.params, self.nodes[2 * j + 1]),
            None => [f32::NAN; 12],
        }
    }
}

impl<T: Real, K: PrimitiveKinds> Field<T> for BlobtreeWindow<'_, K> {
    #[inline]
    fn eval<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        if self.valid && self.len == 0 {
            return N::constant(T::MAX);
        }
        eval_program::<T, N, Self, K, STACK_CAPACITY>(self, p)
    }

    fn lipschitz(&self) -> Option<T> {
        if self.lipschitz > 0.0 && self.lipschitz.is_finite() {
            Some(T::from_f64(self.lipschitz as f64))
        } else {
            self.program_lipschitz()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `param(i, 0..12)` one by one, as the trait's default reads them.
    fn one_by_one<P: Program>(prog: &P, i: usize) -> [f32; 12] {
        core::array::from_fn(|k| prog.param(i, k))
    }

    fn same(a: [f32; 12], b: [f32; 12]) -> bool {
        a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits())
    }

    /// The full tree's `node_floats` (offset read once, no per-float
    /// check when all 12 lie in the buffer) equals `param` float by float:
    /// on a valid tree, on buffers cut short (the last floats missing),
    /// on offsets out of range (one near `u32::MAX`) and past the last node.
    #[test]
    fn node_floats_equal_param_by_param() {
        let params: [f32; 40] = core::array::from_fn(|k| k as f32 * 0.5 + 0.25);
        let word = |leaf: bool| if leaf { 0x8000_0000u32 } else { 0 };
        let nodes = [
            word(true),
            0,
            word(true),
            3,
            word(false),
            7,
            word(true),
            9,
            word(true),
            u32::MAX,
            word(true),
            u32::MAX / 4,
        ];
        for cut in [40, 39, 36, 30, 12, 0] {
            let t = BlobtreeRef::new_unchecked(&nodes, &params[..cut]);
            for i in 0..nodes.len() / 2 + 2 {
                let (a, b) = (Program::node_floats(&t, i), one_by_one(&t, i));
                assert!(same(a, b), "node {i}, {cut} floats: {a:?} vs {b:?}");
            }
        }
    }
}
