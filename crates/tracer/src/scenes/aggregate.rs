//! `aggregate-N`, `aggregate-N-smooth`: the recursive aggregates of the
//! synchronized-tracing paper (Fig. 16) as flat blobtrees.

use super::rng::{Rng, add_scaled, fibonacci_sphere, rotate};
use super::{Built, Frame, GenError, SceneField, box_union};
use boundtrace_fields::blobtree::{FlatBlobtree, Node};
use boundtrace_fields::transform::Rigid;
use boundtrace_fields::{FieldError, Operator, Primitive};
use boundtrace_inclusion::Field;

/// Primitives of the base aggregate and sub-objects per level.
const BASE: usize = 10;
const SUBS: usize = 10;
/// Scale of a sub-object relative to its parent, and its distance from the
/// parent's center (in parent scales).
const SUB_SCALE: f64 = 0.4;
const SUB_DISTANCE: f64 = 0.9;
/// Blend range `β` of the smooth variant, per unit of scale; `r_o = 2β`.
const BETA: f64 = 0.1;

/// A primitive in `f64`: kind (0‥6), center, size parameters, rotation,
/// scale level.
#[derive(Clone, Copy, Debug)]
struct Prim {
    kind: u8,
    center: [f64; 3],
    dims: [f64; 3],
    q: [f64; 4],
    level: usize,
}

impl Prim {
    fn build(&self) -> Result<Primitive<f64>, FieldError> {
        let [d0, d1, d2] = self.dims;
        let c = self.center;
        let axis = rotate(self.q, [0.0, 0.0, 1.0]);
        let at_center = |p: Primitive<f64>| -> Result<Primitive<f64>, FieldError> {
            Ok(p.with_transform(Rigid::new(self.q, c)?))
        };
        match self.kind {
            0 => Primitive::sphere(c, d0),
            1 => at_center(Primitive::cuboid([0.0; 3], [d0, d1, d2])?),
            2 => at_center(Primitive::rounded_box(
                [0.0; 3],
                [d0, d1, d2],
                0.3 * d0.min(d1).min(d2),
            )?),
            3 => Primitive::capsule(add_scaled(c, -d0, axis), add_scaled(c, d0, axis), d1),
            4 => Primitive::cylinder(add_scaled(c, -d0, axis), add_scaled(c, d0, axis), d1),
            5 => Primitive::torus(c, axis, d0, d1),
            _ => at_center(Primitive::ellipsoid([0.0; 3], [d0, d1, d2])?),
        }
    }
}

/// Appends the aggregate at `center` and `scale` with `depth` levels.
fn aggregate(
    rng: &mut Rng,
    center: [f64; 3],
    scale: f64,
    level: usize,
    depth: u32,
    out: &mut Vec<Prim>,
) {
    for i in 0..BASE {
        let kind = ((i + level) % 7) as u8;
        let c = add_scaled(center, scale, rng.in_ball(0.45));
        let mut dims = [0.0; 3].map(|_: f64| scale * rng.range(0.12, 0.25));
        match kind {
            0 => dims[0] = scale * rng.range(0.18, 0.3),
            3 | 4 => dims = [scale * 0.18, scale * rng.range(0.07, 0.12), 0.0],
            5 => dims = [scale * 0.18, scale * rng.range(0.05, 0.08), 0.0],
            _ => {}
        }
        out.push(Prim {
            kind,
            center: c,
            dims,
            q: rng.quaternion(),
            level,
        });
    }
    if depth > 1 {
        let q = rng.quaternion();
        for d in fibonacci_sphere(SUBS) {
            let sub = add_scaled(center, SUB_DISTANCE * scale, rotate(q, d));
            aggregate(rng, sub, scale * SUB_SCALE, level + 1, depth - 1, out);
        }
    }
}

/// A balanced union of `prims` with `op` (depth `⌈log₂ n⌉`).
fn balanced(prims: &[Primitive<f64>], op: Operator<f64>) -> Node<f64> {
    if prims.len() == 1 {
        return Node::primitive(prims[0]);
    }
    let mid = prims.len().div_ceil(2);
    Node::op(op, balanced(&prims[..mid], op), balanced(&prims[mid..], op))
}

/// The union operator adding objects of `scale`.
fn union_op(smooth: bool, scale: f64) -> Result<Operator<f64>, FieldError> {
    if smooth {
        let beta = BETA * scale;
        Operator::compact_union(beta, 2.0 * beta)
    } else {
        Ok(Operator::union())
    }
}

/// `aggregate-{depth}` (`-smooth`).
pub(crate) fn build<T: boundtrace_ia_core::Real>(
    seed: u64,
    depth: u32,
    smooth: bool,
) -> Result<Built<T>, GenError> {
    if !(1..=4).contains(&depth) {
        return Err(GenError::Check("aggregate levels are 1 to 4"));
    }
    let mut rng = Rng::new(seed, 10 + u64::from(depth));
    let mut prims = Vec::new();
    aggregate(&mut rng, [0.0; 3], 1.0, 0, depth, &mut prims);
    let levels = depth as usize;
    let scale_of = |j: usize, unit: f64| unit * SUB_SCALE.powi(j as i32);
    // δ_j: the largest total blend β/6 on a root path of a level-j primitive
    let counts: Vec<usize> = (0..levels)
        .map(|j| prims.iter().filter(|p| p.level == j).count())
        .collect();
    // (the smooth variant's δ for both variants: they share one frame, so
    // `aggregate-N` and `aggregate-N-smooth` are the same shapes)
    let delta = |j: usize, unit: f64| -> f64 {
        let b = |m: usize| BETA * scale_of(m, unit) / 6.0;
        let inner = (counts[j].max(1) as f64).log2().ceil() * b(j);
        let join = if j >= 1 { b(j) } else { 0.0 };
        inner + join + (j + 1..levels).map(b).sum::<f64>()
    };
    let boxes = |prims: &[Prim], unit: f64| -> Result<Vec<[[f64; 3]; 2]>, GenError> {
        prims
            .iter()
            .map(|p| {
                let bv = p
                    .build()?
                    .abv(delta(p.level, unit))
                    .ok_or(GenError::Check("a primitive has no bounded ABV"))?;
                let a = bv.aabb();
                Ok([a.min, a.max])
            })
            .collect()
    };
    let [lo, hi] = box_union(boxes(&prims, 1.0)?);
    let frame = Frame::fit(lo, hi);
    for p in &mut prims {
        p.center = frame.point(p.center);
        p.dims = p.dims.map(|d| frame.length(d));
    }
    let unit = frame.length(1.0);
    let bounds = frame.bounds(lo, hi, 0.02);
    // groups by scale, combined from the largest to the smallest
    let mut tree: Option<Node<f64>> = None;
    for j in 0..levels {
        let group = prims
            .iter()
            .filter(|p| p.level == j)
            .map(Prim::build)
            .collect::<Result<Vec<_>, _>>()?;
        let op = union_op(smooth, scale_of(j, unit))?;
        let g = balanced(&group, op);
        tree = Some(match tree {
            None => g,
            Some(t) => Node::op(op, t, g),
        });
    }
    let tree = tree.ok_or(GenError::Check("empty aggregate"))?;
    let flat = FlatBlobtree::from_node_reordered(&tree)?;
    let inside = prims
        .iter()
        .find(|p| p.kind != 5)
        .map(|p| p.center)
        .ok_or(GenError::Check("no solid primitive"))?;
    let v: f64 = flat.as_ref().eval(inside);
    if v.is_nan() || v >= 0.0 {
        return Err(GenError::Check("the chosen inside point is not inside"));
    }
    let n = prims.len();
    let (variant, op) = if smooth {
        (
            "-smooth",
            "compact smooth union G_U (beta = 0.1 x scale, r_o = 2 beta)",
        )
    } else {
        ("", "CSG union")
    };
    Ok(Built {
        field: SceneField::Blobtree(flat),
        bounds,
        inside,
        primitives: n,
        description: format!(
            "aggregate-{depth}{variant}: recursive aggregate of {n} A-SDF primitives ({depth} levels of 10 sub-objects), {op}, flat blobtree built largest to smallest; synchronized-tracing paper Fig. 16"
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn primitive_counts_follow_the_paper() {
        for (d, n) in [(1, 10), (2, 110), (3, 1110)] {
            let mut prims = Vec::new();
            aggregate(&mut Rng::new(1, 0), [0.0; 3], 1.0, 0, d, &mut prims);
            assert_eq!(prims.len(), n);
            assert!(prims.iter().all(|p| p.build().is_ok()));
        }
        assert!(build::<f64>(1, 5, false).is_err());
    }

    #[test]
    fn smooth_variant_blends() {
        let s: Built<f64> = build(7, 2, true).ok().unwrap();
        let c: Built<f64> = build(7, 2, false).ok().unwrap();
        let (SceneField::Blobtree(a), SceneField::Blobtree(b)) = (&s.field, &c.field) else {
            unreachable!()
        };
        // the compact union never exceeds the CSG union, and differs somewhere
        let mut rng = Rng::new(3, 0);
        let mut differs = false;
        for _ in 0..2000 {
            let p = rng.in_ball(0.9);
            let (fs, fc): (f64, f64) = (a.as_ref().eval(p), b.as_ref().eval(p));
            assert!(fs <= fc + 1e-6);
            differs |= fs < fc - 1e-4;
        }
        assert!(differs);
    }
}
