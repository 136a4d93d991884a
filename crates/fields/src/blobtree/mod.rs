//! Flat post-order blobtrees (synchronized-tracing paper §4–5, §6.2, §7):
//! a builder, the linearized encoding, ranges of interaction and augmented
//! bounding volumes, fast ancestor indices with a sparse bottom-up
//! traversal, pruned tree views, and the node-level interpreter that makes
//! all of them a [`Field`](boundtrace_inclusion::Field) for every number
//! type.
//!
//! # Pieces
//!
//! | item | what | paper |
//! | --- | --- | --- |
//! | [`Node`] (`alloc`) | nested builder tree | §5 |
//! | [`FlatBlobtree`] (`alloc`) | iterative linearization (optionally with Sethi–Ullman operand order), decoding | §5, §7 |
//! | [`BlobtreeRef`] | validated borrowed flat data, evaluated on CPU/GPU | §7 |
//! | [`NodeWord`] | `isLeaf(1) isLeft(1) type(8) ancestor(22)` | §7 |
//! | [`Roi`], [`Abv`] (`alloc`) | ROI propagation, ABVs, active sets | §4, eqs. 13–16 |
//! | [`sparse_traverse`], [`SparseVisitor`] | sparse bottom-up traversal | §5, Fig. 7, 10 |
//! | [`PrunedView`] | `B_view`, `B_offset`, `D_cache`, Alg. 4 | §6.2, Fig. 11 |
//!
//! # Local equivalence and missing operands
//!
//! For a query volume `𝒱`, a primitive is *active* when its ABV (its
//! 0-isosurface bound offset by `r⁺` of its ROI, eqs. 13–16 propagated from
//! the root's `[0, 0]`) meets `𝒱`. An inactive primitive has `f > r⁺` in
//! `𝒱`; it is treated as **missing**, i.e. as `+∞` (§4: "treating the
//! missing operand as having an infinite value"). Operators then act as
//! selectors:
//!
//! | class | only `f₀` present | only `f₁` present |
//! | --- | --- | --- |
//! | union-like (`min`) | `f₀` | `f₁` |
//! | intersection-like (`max`) | missing | missing |
//! | difference-like (`max(f₀, −f₁)`) | `f₀` | missing |
//!
//! Why this gives an equivalent field (each node's pruned value equals the
//! full one, or both lie above `r_n⁺`, or both below `r_n⁻`): for a union
//! with `f₁` missing, `f₁ > max(r_n⁺, r_o⁺)`, so the compact operator is in
//! its CSG regime and `min(f₀, f₁)` is `f₀` or, when `f₁ < f₀`, a value
//! above `r_n⁺` like `f₀`. For an intersection-like node a missing operand
//! has `f > r_n⁺` and the operator is `≥ max(f₀, f₁)` (smooth and compact
//! intersections only add `d ≥ 0`), so the node itself is above `r_n⁺`:
//! missing. A difference with `f₁` missing (`f₁ > max(−r_n⁻, r_o⁺)`) is in
//! its CSG regime and `max(f₀, −f₁)` equals `f₀` or lies, like `f₀`, below
//! `r_n⁻`; with `f₀` missing (`f₀ > r_n⁺`) the result is `≥ f₀`: missing.
//! A missing root means no active primitive shapes the surface in `𝒱`:
//! the local field is `+∞` there. The property test
//! `tests/blobtree.rs` checks sign equality (eq. 4) on random trees.
//!
//! # Fast ancestors (Fig. 10)
//!
//! Nodes are numbered `0‥n−1` in post-order (root `n−1`). A left child's
//! parent is not adjacent in post-order, a right child's is (`i + 1`).
//! Instead of the parent, the 22-bit `ancestor` field holds a *fast*
//! ancestor: following parents from `c` while the direction (left/right)
//! does not change **and** the skipped operator passes that side on (table
//! above: unions both sides, differences the left side, intersections
//! neither), `fast(c)` is the last node reached:
//!
//! ```text
//! fast(c) = fast(p)  if p = parent(c) is not the root, isLeft(p) = isLeft(c)
//!                    and p passes c's side;
//!           p        otherwise.
//! ```
//!
//! The nodes `c → c₁ → … → c_m = fast(c)` form a *chain*; every `cᵢ` with
//! `i < m` is a pass-through selector when only the chain operand is
//! active, so a jump over them needs no work and no output (this is what
//! restricts the paper's union-only fast indices to what is safe for the
//! other classes). All nodes of a chain share the same fast ancestor.
//! Post-order gives the key facts: the right subtrees hanging off a left
//! chain `c, c₁, …, c_m` cover exactly the index range `(c, c_m)`, and a
//! right chain is consecutive (`c + 1, c + 2, …`).
//!
//! # Sparse bottom-up traversal (§5, derived from Fig. 7/10)
//!
//! Input: the strictly increasing post-order indices `p₁ < … < p_k` of the
//! active primitives. State: a stack `S` of *pending left operands* (each a
//! node whose right sibling subtree still contains active primitives, with
//! its present/missing status) and the current node `b` with its status.
//! For each `p_j` (next active primitive `q = p_{j+1}`, `∞` after the
//! last): emit `p_j` (present), `b ← p_j`, then climb:
//!
//! 1. `b` is the root: done (`S` is empty).
//! 2. `b` is a left child: if `q < fast(b)` some right subtree of the chain
//!    contains `q`: push `b` on `S` and go to the next primitive (the
//!    chain nodes below the meeting point are pass-throughs, so waiting at
//!    `b` is the same as waiting at the meeting point). Otherwise all those
//!    right subtrees are inactive: jump to `t = fast(b)` and apply `t`'s
//!    selector with `b` on the left.
//! 3. `b` is a right child: `t = min(fast(b), fast(S.top()))` — the
//!    **clamping** of markers #1/#2 — so the jump cannot pass the node where
//!    the pending left operand waits. The two operands meet at `t` when
//!    `t = fast(S.top())` (*popRequiredA*) or `t` is a left child (or the
//!    root) with `fast(t) ≥ fast(S.top())` (*popRequiredB*: `t` is on the
//!    top's chain, whose members share its fast ancestor; a left child
//!    inside the right subtree hanging off that chain has a smaller fast
//!    ancestor, its chain ending at most at the subtree root). Then pop;
//!    both present → emit the operator; otherwise apply the selector with
//!    the present side. Without a meeting, `t`'s left subtree is inactive
//!    (anything active there would be on top of `S`): apply `t`'s selector
//!    with `b` on the right.
//!
//! Every step strictly increases `b`, so the traversal touches only active
//! nodes (primitives, and operators whose subtree holds an active
//! primitive), at most once each, and skips chain members. The emitted
//! primitives and operators, in emission order, are the post-order program
//! of the pruned tree; a *kill* (a present subtree becoming missing) drops
//! the subtree's emitted suffix. [`BlobtreeRef::eval_sparse`] runs that
//! program directly, [`PrunedView::build`] records it (Alg. 4 then
//! evaluates it for many points).
//!
//! # Lipschitz bound
//!
//! Primitives are 1-Lipschitz (as documented by [`crate::sdf`]), CSG and
//! smooth operators keep the operands' bound, compact ones multiply it by
//! [`Operator::lipschitz_factor`](crate::operator::Operator::lipschitz_factor)
//! (`6r_o/(6r_o − β)`). [`BlobtreeRef::lipschitz_bound`] combines
//! `max(L₀, L₁)·factor` bottom-up: at most the product of the factors
//! along the worst root–leaf path. The paper traces with 1.45 (§7).
//!
//! # Example
//!
//! ```
//! use boundtrace_fields::blobtree::{DefaultPrunedView, FlatBlobtree, Node};
//! use boundtrace_fields::bounding::Aabb;
//! use boundtrace_fields::operator::Operator;
//! use boundtrace_fields::sdf::Primitive;
//! use boundtrace_inclusion::Field;
//!
//! let s = |x: f64| Node::primitive(Primitive::sphere([x, 0.0, 0.0], 0.5).unwrap());
//! let u = Operator::compact_union(0.2, 0.25).unwrap();
//! let tree = Node::op(u, Node::op(u, s(0.0), s(0.8)), Node::op(u, s(4.0), s(8.0)));
//! let flat = FlatBlobtree::from_node(&tree).unwrap();
//! let abvs = flat.abvs::<f64>();
//! let query = Aabb::new([-1.0, -1.0, -1.0], [1.0, 1.0, 1.0]);
//! let active = FlatBlobtree::active_in_box(&abvs, &query);
//! assert_eq!(active, vec![0, 1]); // the two spheres near the origin
//! let view: DefaultPrunedView = DefaultPrunedView::build(flat.as_ref(), &active).unwrap();
//! assert_eq!(view.len(), 3); // two primitives and their union
//! let p = [0.3, 0.2, 0.0];
//! let full: f64 = flat.as_ref().eval(p);
//! let pruned: f64 = view.eval(p);
//! assert_eq!(full.signum(), pruned.signum());
//! ```

#[cfg(feature = "alloc")]
mod builder;
mod encoding;
mod eval;
#[cfg(feature = "alloc")]
mod roi;
mod traversal;
mod view;

#[cfg(feature = "alloc")]
pub use builder::{FlatBlobtree, Node};
pub use encoding::{
    BlobtreeRef, MAX_NODES, NO_ANCESTOR, NodeWord, STACK_CAPACITY, class_code, class_from_code,
    passes,
};
pub use eval::{BlobtreeAmong, BlobtreeWindow, TILE_TABLE_WORDS};
#[cfg(feature = "alloc")]
pub use roi::{Abv, Roi};
pub use traversal::{SparseVisitor, TRAVERSAL_STACK, sparse_traverse};
pub use view::{
    D_CACHE_FLOATS, DefaultPrunedView, M_OVERLAP, PrunedView, VIEW_CAPACITY, VIEW_STACK,
};
