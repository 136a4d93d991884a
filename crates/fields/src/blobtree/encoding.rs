//! The flat node word (paper §7) and the validated, borrowed view
//! [`BlobtreeRef`] that the CPU and the GPU evaluate.

use crate::FieldError;
use crate::operator::{OperatorClass, OperatorKind};
use crate::sdf::{Primitive, PrimitiveKind};

/// The largest number of nodes a flat blobtree may have: `2²² − 1 =
/// 4,194,303` (22-bit ancestor index, paper §7; the value `2²² − 1` itself
/// is reserved for "no ancestor").
pub const MAX_NODES: usize = (1 << 22) - 1;

/// The ancestor value of the root ("no ancestor"): `2²² − 1`.
pub const NO_ANCESTOR: u32 = (1 << 22) - 1;

/// Capacity of the fixed evaluation stack of the full-tree interpreter
/// ([`BlobtreeRef`]'s [`Field`](boundtrace_inclusion::Field) impl). Trees
/// whose post-order evaluation needs more are refused by
/// [`BlobtreeRef::new`] with [`FieldError::TooLarge`]. Left combs need 2;
/// a balanced tree of `n` primitives needs `⌈log₂ n⌉ + 1`.
pub const STACK_CAPACITY: usize = 32;

const LEAF_BIT: u32 = 1 << 31;
const LEFT_BIT: u32 = 1 << 30;
const TYPE_SHIFT: u32 = 22;
const TYPE_MASK: u32 = 0xff;
const ANCESTOR_MASK: u32 = (1 << 22) - 1;

/// `ignoreMod` code of an operator class (paper §7: operand selection
/// follows the operator's behaviour): 0 union-like, 1 intersection-like,
/// 2 difference-like (3 is invalid).
#[inline]
pub const fn class_code(class: OperatorClass) -> u32 {
    match class {
        OperatorClass::UnionLike => 0,
        OperatorClass::IntersectionLike => 1,
        OperatorClass::DifferenceLike => 2,
    }
}

/// The class of an `ignoreMod` code, `None` for 3.
#[inline]
pub const fn class_from_code(code: u32) -> Option<OperatorClass> {
    match code {
        0 => Some(OperatorClass::UnionLike),
        1 => Some(OperatorClass::IntersectionLike),
        2 => Some(OperatorClass::DifferenceLike),
        _ => None,
    }
}

/// Whether an operator of `class` whose only present operand is on the left
/// (`left = true`) or right side passes that operand on unchanged when the
/// other operand is missing (treated as `+∞`, paper §4):
///
/// | class | left only | right only |
/// | --- | --- | --- |
/// | union-like `min(f₀, +∞)` | `f₀` (pass) | `f₁` (pass) |
/// | intersection-like `max(f₀, +∞)` | `+∞` (missing) | `+∞` (missing) |
/// | difference-like `max(f₀, −(+∞))` / `max(+∞, −f₁)` | `f₀` (pass) | `+∞` (missing) |
///
/// See the [module docs](super) for why these selections give a locally
/// equivalent field.
#[inline]
pub const fn passes(class: OperatorClass, left: bool) -> bool {
    match class {
        OperatorClass::UnionLike => true,
        OperatorClass::IntersectionLike => false,
        OperatorClass::DifferenceLike => left,
    }
}

/// One 32-bit node word (paper §7), most significant bit first:
///
/// | bits | 31 | 30 | 29‥22 | 21‥0 |
/// | --- | --- | --- | --- | --- |
/// | field | `isLeaf` | `isLeft` | `type` | `ancestor` |
///
/// For a primitive `type` is its [`PrimitiveKind`] (< 256). For an operator
/// `type` is split, most significant first, into `ignoreMod` (bits 29‥28,
/// [`class_code`]), `isUnary` (bit 27, always 0: unary nodes are not
/// supported and refused) and `nodeop` (bits 26‥22, its [`OperatorKind`],
/// < 32). `ancestor` is the *fast* ancestor index (paper Fig. 10, see the
/// [module docs](super)), [`NO_ANCESTOR`] for the root. The root has
/// `isLeft = 0`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(transparent)]
pub struct NodeWord(pub u32);

impl NodeWord {
    /// A primitive node word.
    #[inline]
    pub const fn primitive(kind: PrimitiveKind, is_left: bool, ancestor: u32) -> Self {
        let mut w = LEAF_BIT | (((kind as u32) & TYPE_MASK) << TYPE_SHIFT);
        if is_left {
            w |= LEFT_BIT;
        }
        Self(w | (ancestor & ANCESTOR_MASK))
    }

    /// An operator node word (`isUnary = 0`).
    #[inline]
    pub const fn operator(kind: OperatorKind, is_left: bool, ancestor: u32) -> Self {
        let ty = (class_code(kind.class()) << 6) | ((kind as u32) & 0x1f);
        let mut w = ty << TYPE_SHIFT;
        if is_left {
            w |= LEFT_BIT;
        }
        Self(w | (ancestor & ANCESTOR_MASK))
    }

    /// `isLeaf`: a primitive.
    #[inline]
    pub const fn is_leaf(self) -> bool {
        self.0 & LEAF_BIT != 0
    }

    /// `isLeft`: the left operand of its parent.
    #[inline]
    pub const fn is_left(self) -> bool {
        self.0 & LEFT_BIT != 0
    }

    /// The 8-bit `type` field.
    #[inline]
    pub const fn node_type(self) -> u32 {
        (self.0 >> TYPE_SHIFT) & TYPE_MASK
    }

    /// The 5-bit `nodeop` of an operator (the low 5 bits of `type`).
    #[inline]
    pub const fn nodeop(self) -> u32 {
        self.node_type() & 0x1f
    }

    /// `isUnary` of an operator (bit 5 of `type`).
    #[inline]
    pub const fn is_unary(self) -> bool {
        self.node_type() & 0x20 != 0
    }

    /// `ignoreMod` of an operator (bits 7‥6 of `type`).
    #[inline]
    pub const fn ignore_mod(self) -> u32 {
        self.node_type() >> 6
    }

    /// The operator class encoded by `ignoreMod` (`None` for code 3).
    #[inline]
    pub const fn class(self) -> Option<OperatorClass> {
        class_from_code(self.ignore_mod())
    }

    /// The 22-bit (fast) ancestor index.
    #[inline]
    pub const fn ancestor(self) -> u32 {
        self.0 & ANCESTOR_MASK
    }

    /// Whether the node has an ancestor (is not the root).
    #[inline]
    pub const fn has_ancestor(self) -> bool {
        self.ancestor() != NO_ANCESTOR
    }

    /// The primitive kind of a leaf (`None` for operators or unknown kinds).
    #[inline]
    pub fn primitive_kind(self) -> Option<PrimitiveKind> {
        if self.is_leaf() {
            PrimitiveKind::from_u32(self.node_type())
        } else {
            None
        }
    }

    /// The operator kind of an inner node (`None` for leaves or unknown
    /// kinds).
    #[inline]
    pub fn operator_kind(self) -> Option<OperatorKind> {
        if self.is_leaf() {
            None
        } else {
            OperatorKind::from_u32(self.nodeop())
        }
    }
}

/// A validated, borrowed flat blobtree: what the CPU and the GPU evaluate
/// (paper §5, §7).
///
/// * `nodes`: two `u32` words per node in post-order (node `i` at
///   `nodes[2i]`, `nodes[2i + 1]`): the [`NodeWord`] and the offset of the
///   node's parameters `D_i` in `params`, **in 128-bit units** (`D_i`
///   starts at `params[4·offset]`, paper §7's 128-bit stride).
/// * `params`: the `f32` parameter array; a primitive uses
///   [`PrimitiveKind::param_vec4s`] 4-float slots (transform included), an
///   operator [`OperatorKind::param_vec4s`].
///
/// The root is the last node. Construction ([`BlobtreeRef::new`]) validates
/// everything evaluation relies on, so evaluation never indexes out of
/// bounds and never loops.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BlobtreeRef<'a> {
    nodes: &'a [u32],
    params: &'a [f32],
    stack_need: u32,
}

/// The parameter slice of a node, `None` when out of range.
#[inline]
pub(crate) fn param_slice(params: &[f32], offset: u32, vec4s: u32) -> Option<&[f32]> {
    let start = (offset as usize).checked_mul(4)?;
    let len = (vec4s as usize).checked_mul(4)?;
    let end = start.checked_add(len)?;
    params.get(start..end)
}

const fn malformed(reason: &'static str) -> FieldError {
    FieldError::Malformed { reason }
}

impl<'a> BlobtreeRef<'a> {
    /// Validates flat data and borrows it.
    ///
    /// Checks, in one pass without allocation: an even, non-zero word count
    /// with at most [`MAX_NODES`] nodes ([`FieldError::TooLarge`] above);
    /// known primitive and operator kinds, `ignoreMod` equal to the
    /// operator's class, `isUnary = 0`; parameter ranges inside `params`
    /// and decodable; a well-formed post-order (every operator has two
    /// operands, one root at the end); an evaluation stack of at most
    /// [`STACK_CAPACITY`] ([`FieldError::TooLarge`] above); and the links:
    /// `isLeft` bits and fast ancestor indices equal those recomputed from
    /// the structure (the root has [`NO_ANCESTOR`] and `isLeft = 0`).
    ///
    /// ```
    /// use boundtrace_fields::blobtree::BlobtreeRef;
    /// assert!(BlobtreeRef::new(&[1, 2, 3], &[]).is_err());
    /// ```
    pub fn new(nodes: &'a [u32], params: &'a [f32]) -> Result<Self, FieldError> {
        if nodes.len() % 2 != 0 {
            return Err(malformed("odd number of node words"));
        }
        let n = nodes.len() / 2;
        if n == 0 {
            return Err(malformed("empty blobtree"));
        }
        if n > MAX_NODES {
            return Err(FieldError::TooLarge {
                what: "blobtree nodes",
                count: n,
                max: MAX_NODES,
            });
        }
        // Stack of completed subtree roots: its depth is the evaluation
        // stack depth, so it is bounded by STACK_CAPACITY.
        let mut stack = [0u32; STACK_CAPACITY];
        let mut sp = 0usize;
        let mut need = 0usize;
        let mut i = 0usize;
        while i < n {
            let w = NodeWord(nodes[2 * i]);
            let off = nodes[2 * i + 1];
            let is_root = i + 1 == n;
            if is_root {
                if w.has_ancestor() || w.is_left() {
                    return Err(malformed("root has an ancestor or isLeft set"));
                }
            } else {
                let a = w.ancestor() as usize;
                if !w.has_ancestor() || a <= i || a >= n {
                    return Err(malformed("ancestor index out of range"));
                }
            }
            if w.is_leaf() {
                let kind = w
                    .primitive_kind()
                    .ok_or(malformed("unknown primitive kind"))?;
                let d = param_slice(params, off, kind.param_vec4s())
                    .ok_or(malformed("primitive parameters out of range"))?;
                if Primitive::<f32>::read_params(kind, d).is_none() {
                    return Err(malformed("primitive parameters not decodable"));
                }
                if sp == STACK_CAPACITY {
                    return Err(FieldError::TooLarge {
                        what: "evaluation stack entries",
                        count: STACK_CAPACITY + 1,
                        max: STACK_CAPACITY,
                    });
                }
                stack[sp] = i as u32;
                sp += 1;
                if sp > need {
                    need = sp;
                }
            } else {
                let kind = w
                    .operator_kind()
                    .ok_or(malformed("unknown operator kind"))?;
                if w.is_unary() {
                    return Err(malformed("unary operators are not supported"));
                }
                if w.ignore_mod() != class_code(kind.class()) {
                    return Err(malformed("ignoreMod does not match the operator class"));
                }
                let d = param_slice(params, off, kind.param_vec4s())
                    .ok_or(malformed("operator parameters out of range"))?;
                if crate::operator::Operator::<f32>::read_params(kind, d).is_none() {
                    return Err(malformed("operator parameters not decodable"));
                }
                if sp < 2 {
                    return Err(malformed("operator with fewer than two operands"));
                }
                let r = stack[sp - 1] as usize;
                let l = stack[sp - 2] as usize;
                sp -= 2;
                let p = i;
                let wr = NodeWord(nodes[2 * r]);
                let wl = NodeWord(nodes[2 * l]);
                if wr.is_left() || !wl.is_left() {
                    return Err(malformed("isLeft bits do not match the structure"));
                }
                // Fast ancestors (module docs): fast(c) = fast(p) when the
                // chain continues through p, else p.
                let class = kind.class();
                for (wc, left) in [(wl, true), (wr, false)] {
                    let cont = !is_root && w.is_left() == left && passes(class, left);
                    let expect = if cont { w.ancestor() } else { p as u32 };
                    if wc.ancestor() != expect {
                        return Err(malformed(
                            "fast ancestor index does not match the structure",
                        ));
                    }
                }
                stack[sp] = p as u32;
                sp += 1;
            }
            i += 1;
        }
        if sp != 1 {
            return Err(malformed("post-order sequence does not form one tree"));
        }
        Ok(Self {
            nodes,
            params,
            stack_need: need as u32,
        })
    }

    /// Borrows flat data **without validating it**, for data that
    /// [`BlobtreeRef::new`] accepted before: a GPU shader gets the
    /// buffers its host validated, and cannot build the error values of
    /// `new`. Evaluation decodes every node without the constructors'
    /// checks (as it does for validated data), so on data `new` would
    /// reject it never panics and never reads out of bounds, but its
    /// values are unspecified (NaN where a node does not decode or the
    /// stack would overflow). [`stack_need`](Self::stack_need) reports
    /// [`STACK_CAPACITY`].
    ///
    /// ```
    /// use boundtrace_fields::blobtree::{BlobtreeRef, FlatBlobtree, Node};
    /// use boundtrace_fields::Primitive;
    /// use boundtrace_inclusion::Field;
    /// let s = Node::primitive(Primitive::sphere([0.0, 0.0, 0.0], 0.5).unwrap());
    /// let tree = FlatBlobtree::from_node(&s)?;
    /// let t = tree.as_ref();
    /// let u = BlobtreeRef::new_unchecked(t.nodes(), t.params());
    /// assert_eq!(u.eval([1.0f32, 0.0, 0.0]), t.eval([1.0f32, 0.0, 0.0]));
    /// // Garbage in, NaN out: no panic.
    /// assert!(BlobtreeRef::new_unchecked(&[7, 7, 7], &[]).eval([0.0f32; 3]).is_nan());
    /// # Ok::<(), boundtrace_fields::FieldError>(())
    /// ```
    #[inline]
    pub fn new_unchecked(nodes: &'a [u32], params: &'a [f32]) -> Self {
        Self {
            nodes,
            params,
            stack_need: STACK_CAPACITY as u32,
        }
    }

    /// Data that [`BlobtreeRef::new`] accepted before (owned, immutable
    /// storage of [`FlatBlobtree`](super::FlatBlobtree)).
    #[cfg(feature = "alloc")]
    #[inline]
    pub(crate) fn from_validated(nodes: &'a [u32], params: &'a [f32], stack_need: usize) -> Self {
        Self {
            nodes,
            params,
            stack_need: stack_need as u32,
        }
    }

    /// The number of nodes.
    #[inline]
    pub fn len(&self) -> usize {
        self.nodes.len() / 2
    }

    /// Always `false` (a validated tree has at least one node).
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The node words (two per node).
    #[inline]
    pub fn nodes(&self) -> &'a [u32] {
        self.nodes
    }

    /// The parameter array.
    #[inline]
    pub fn params(&self) -> &'a [f32] {
        self.params
    }

    /// The evaluation stack depth the full post-order interpreter needs
    /// (≤ [`STACK_CAPACITY`]).
    #[inline]
    pub fn stack_need(&self) -> usize {
        self.stack_need as usize
    }

    /// The node word of node `i` (`None` out of range).
    #[inline]
    pub fn word(&self, i: u32) -> Option<NodeWord> {
        self.nodes.get(2 * i as usize).map(|&w| NodeWord(w))
    }

    /// The parameter offset (128-bit units) of node `i`.
    #[inline]
    pub fn offset(&self, i: u32) -> Option<u32> {
        self.nodes.get(2 * i as usize + 1).copied()
    }

    /// The parameters `D_i` of node `i` (`None` out of range).
    #[inline]
    pub fn node_params(&self, i: u32) -> Option<&'a [f32]> {
        let w = self.word(i)?;
        let vec4s = if w.is_leaf() {
            w.primitive_kind()?.param_vec4s()
        } else {
            w.operator_kind()?.param_vec4s()
        };
        param_slice(self.params, self.offset(i)?, vec4s)
    }

    /// The primitive at node `i` (`None` if it is not a leaf).
    #[inline]
    pub fn primitive<T: boundtrace_ia_core::Real>(&self, i: u32) -> Option<Primitive<T>> {
        let kind = self.word(i)?.primitive_kind()?;
        Primitive::read_params(kind, self.node_params(i)?)
    }

    /// The operator at node `i` (`None` if it is a leaf).
    #[inline]
    pub fn operator<T: boundtrace_ia_core::Real>(
        &self,
        i: u32,
    ) -> Option<crate::operator::Operator<T>> {
        let kind = self.word(i)?.operator_kind()?;
        crate::operator::Operator::read_params(kind, self.node_params(i)?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sdf::Primitive;

    #[test]
    fn node_word_layout() {
        let w = NodeWord::primitive(PrimitiveKind::Torus, true, 12345);
        assert_eq!(w.0 >> 31, 1);
        assert_eq!((w.0 >> 30) & 1, 1);
        assert_eq!((w.0 >> 22) & 0xff, PrimitiveKind::Torus as u32);
        assert_eq!(w.0 & 0x3f_ffff, 12345);
        assert_eq!(w.primitive_kind(), Some(PrimitiveKind::Torus));
        assert!(w.operator_kind().is_none());
        let w = NodeWord::operator(OperatorKind::CompactDifference, false, NO_ANCESTOR);
        assert!(!w.is_leaf() && !w.is_left() && !w.has_ancestor() && !w.is_unary());
        assert_eq!(w.ignore_mod(), 2);
        assert_eq!(w.nodeop(), OperatorKind::CompactDifference as u32);
        assert_eq!(w.class(), Some(OperatorClass::DifferenceLike));
        for k in OperatorKind::ALL {
            let w = NodeWord::operator(k, true, 7);
            assert_eq!(w.operator_kind(), Some(k));
            assert_eq!(w.class(), Some(k.class()));
            assert_eq!(w.ancestor(), 7);
        }
    }

    #[test]
    fn hand_built_tree_validates() {
        // union(sphere, sphere): nodes 0 (left), 1 (right), 2 (root).
        let s = Primitive::sphere([0.0f32, 0.0, 0.0], 1.0).unwrap();
        let v = s.kind().param_vec4s();
        let mut params = [0.0f32; 64];
        s.write_params(&mut params[..4 * v as usize]).unwrap();
        s.write_params(&mut params[4 * v as usize..8 * v as usize])
            .unwrap();
        let nodes = [
            NodeWord::primitive(s.kind(), true, 2).0,
            0,
            NodeWord::primitive(s.kind(), false, 2).0,
            v,
            NodeWord::operator(OperatorKind::Union, false, NO_ANCESTOR).0,
            2 * v,
        ];
        let r = BlobtreeRef::new(&nodes, &params).unwrap();
        assert_eq!(r.len(), 3);
        assert_eq!(r.stack_need(), 2);
        // Swapped isLeft bits, wrong ancestor, out-of-range offset.
        let mut bad = nodes;
        bad[0] = NodeWord::primitive(s.kind(), false, 2).0;
        assert!(BlobtreeRef::new(&bad, &params).is_err());
        let mut bad = nodes;
        bad[0] = NodeWord::primitive(s.kind(), true, 1).0;
        assert!(BlobtreeRef::new(&bad, &params).is_err());
        let mut bad = nodes;
        bad[3] = 1000;
        assert!(BlobtreeRef::new(&bad, &params).is_err());
    }
}
