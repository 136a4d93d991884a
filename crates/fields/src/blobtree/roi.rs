//! Ranges of interaction (paper §4, eqs. 13–16) and augmented bounding
//! volumes (Fig. 4d).

use super::builder::FlatBlobtree;
use super::encoding::NO_ANCESTOR;
use crate::bounding::{Aabb, Bounding};
use crate::operator::{Operator, OperatorClass};
use alloc::vec;
use alloc::vec::Vec;
use boundtrace_ia_core::Real;

/// A range of interaction `R_n = [r⁻, r⁺]` (eq. 5, `r⁻ ≤ 0 ≤ r⁺`; either
/// end may be infinite): the field values where an equivalent field must
/// equal the node's field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Roi<T> {
    /// `r⁻ ≤ 0`.
    pub lo: T,
    /// `r⁺ ≥ 0`.
    pub hi: T,
}

impl<T: Real> Roi<T> {
    /// The root's ROI `[0, 0]` (eq. 4: only the sign matters).
    pub const fn root() -> Self {
        Self {
            lo: T::ZERO,
            hi: T::ZERO,
        }
    }

    /// The ROI of an operand of `op` whose parent has ROI `self`
    /// (`left`: the operand `f₀`), eqs. 13–16 with `R_o = op.range()`:
    ///
    /// * union-like: `[r_n⁻, max(r_n⁺, r_o⁺)]` (13);
    /// * intersection-like: `[min(r_n⁻, r_o⁻), r_n⁺]` (14);
    /// * difference-like, left: `[min(r_n⁻, r_o⁻), r_n⁺]` (15); right:
    ///   `[−r_n⁺, max(−r_n⁻, r_o⁺)]` (16, inside and outside swap since
    ///   `f₁` enters negated).
    pub fn child(&self, op: &Operator<T>, left: bool) -> Self {
        let (ro_lo, ro_hi) = op.range();
        match (op.kind().class(), left) {
            (OperatorClass::UnionLike, _) => Self {
                lo: self.lo,
                hi: self.hi.max(ro_hi),
            },
            (OperatorClass::IntersectionLike, _) | (OperatorClass::DifferenceLike, true) => Self {
                lo: self.lo.min(ro_lo),
                hi: self.hi,
            },
            (OperatorClass::DifferenceLike, false) => Self {
                lo: -self.hi,
                hi: (-self.lo).max(ro_hi),
            },
        }
    }
}

/// The augmented bounding volume of one primitive (paper §4, Fig. 4d):
/// outside `volume` the primitive's field exceeds `r_plus`, the upper end
/// of its ROI, so it cannot influence the root's 0-isosurface there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Abv<T> {
    /// The primitive's post-order index.
    pub node: u32,
    /// `r⁺` of its ROI.
    pub r_plus: T,
    /// `Primitive::abv(r⁺)`; `None`: unbounded, the primitive is always
    /// active.
    pub volume: Option<Bounding<T>>,
}

impl<T: Real> Abv<T> {
    /// Whether the primitive is active for the query box `b` (its ABV meets
    /// `b`, conservatively; always for an unbounded ABV).
    #[inline]
    pub fn overlaps_aabb(&self, b: &Aabb<T>) -> bool {
        match &self.volume {
            Some(v) => v.overlaps_aabb(b),
            None => true,
        }
    }
}

impl FlatBlobtree {
    /// The ROI of every node (post-order), propagated from the root
    /// (`[0, 0]`) in one top-down pass (reverse post-order, parents before
    /// children; iterative).
    pub fn rois<T: Real>(&self) -> Vec<Roi<T>> {
        let n = self.len();
        let parent = self.parents();
        let tree = self.as_ref();
        let mut roi = vec![Roi::root(); n];
        for c in (0..n).rev() {
            let p = parent[c];
            if p == NO_ANCESTOR {
                continue;
            }
            let left = tree.word(c as u32).is_some_and(|w| w.is_left());
            roi[c] = match tree.operator::<T>(p) {
                Some(op) => roi[p as usize].child(&op, left),
                // Cannot happen for validated data; unbounded is safe.
                None => Roi {
                    lo: T::NEG_INFINITY,
                    hi: T::INFINITY,
                },
            };
        }
        roi
    }

    /// The ABV of every primitive, in post-order: ROI propagation
    /// ([`rois`](Self::rois)) then `Primitive::abv(r⁺)` (a non-finite `r⁺`
    /// gives an unbounded ABV).
    pub fn abvs<T: Real>(&self) -> Vec<Abv<T>> {
        let rois = self.rois::<T>();
        let tree = self.as_ref();
        let mut out = Vec::new();
        for (i, roi) in rois.iter().enumerate() {
            let i = i as u32;
            if let Some(prim) = tree.primitive::<T>(i) {
                let volume = if roi.hi.is_finite() {
                    prim.abv(roi.hi)
                } else {
                    None
                };
                out.push(Abv {
                    node: i,
                    r_plus: roi.hi,
                    volume,
                });
            }
        }
        out
    }

    /// The active primitives for the query box `b`: the post-order indices
    /// (increasing) of the primitives whose ABV meets `b` — the input of
    /// [`sparse_traverse`](super::sparse_traverse) and
    /// [`PrunedView::build`](super::PrunedView::build).
    pub fn active_in_box<T: Real>(abvs: &[Abv<T>], b: &Aabb<T>) -> Vec<u32> {
        abvs.iter()
            .filter(|a| a.overlaps_aabb(b))
            .map(|a| a.node)
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::blobtree::Node;
    use crate::sdf::Primitive;

    #[test]
    fn abvs_follow_rois() {
        let s = |x: f64| Node::primitive(Primitive::sphere([x, 0.0, 0.0], 0.5).unwrap());
        let cu = Operator::compact_union(0.2, 0.25).unwrap();
        let ci = Operator::compact_intersection(0.2, 0.25).unwrap();
        // ci(cu(s0, s1), s2): the union's operands get r⁺ = 0.25, the
        // intersection's right operand keeps r⁺ = 0.
        let tree = Node::op(ci, Node::op(cu, s(0.0), s(5.0)), s(0.2));
        let flat = FlatBlobtree::from_node(&tree).unwrap();
        let rois = flat.rois::<f64>();
        assert_eq!(rois[4], Roi::root());
        assert_eq!(rois[3], Roi { lo: -0.25, hi: 0.0 });
        assert_eq!(rois[2], Roi { lo: -0.25, hi: 0.0 });
        assert_eq!(
            rois[0],
            Roi {
                lo: -0.25,
                hi: 0.25
            }
        );
        let abvs = flat.abvs::<f64>();
        assert_eq!(abvs.len(), 3);
        let q = Aabb::new([4.0, -0.1, -0.1], [4.3, 0.1, 0.1]);
        // Only s1 (at x = 5, radius 0.5 + 0.25) reaches the box.
        assert_eq!(FlatBlobtree::active_in_box(&abvs, &q), [1]);
    }
}
