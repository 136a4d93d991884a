//! Programmatic translation of a boundtrace blobtree into a fidget
//! expression, by evaluating our own field code with a *symbolic* number
//! type.
//!
//! Every boundtrace field is written once, generic over
//! [`FieldNum`] (ARCHITECTURE.md, "the one idea that keeps it small").
//! [`Sym`] is one more such number type: each arithmetic operation appends
//! the corresponding node to a fidget [`Context`] (held in a thread-local
//! while the translation runs). Evaluating
//! [`BlobtreeRef::eval_full`](boundtrace_fields::blobtree::BlobtreeRef::eval_full)
//! with `Sym` coordinates therefore yields exactly the expression our
//! interpreter computes — no hand-copied numbers or formulas.
//!
//! Branches: fields decide some branches with
//! [`FieldNum::enclosure`]. `Sym` answers "the whole real line", so the
//! fields take their general (branch-free) formula, which is exact for the
//! sharp (CSG) operators and the A-SDF primitives. A branch that the
//! fields can only *enclose* ([`FieldNum::join`], used by the smooth and
//! compact blend operators and the compact kernels) has no exact symbolic
//! form: the translation then fails with [`TranslateError::Undecided`]
//! rather than silently producing a different shape. Every translation is
//! also checked numerically ([`check_translation`]).

use boundtrace_fields::blobtree::FlatBlobtree;
use boundtrace_ia_core::Interval;
use boundtrace_inclusion::FieldNum;
use fidget::context::{Context, Node};
use std::cell::{Cell, RefCell};
use std::fmt;
use std::ops::{Add, Div, Mul, Neg, Sub};

thread_local! {
    static CTX: RefCell<Option<Context>> = const { RefCell::new(None) };
    static FAILURE: Cell<Option<TranslateError>> = const { Cell::new(None) };
}

/// Why a field could not be translated into a fidget expression.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TranslateError {
    /// The field used an operation fidget has no node for.
    Unsupported(&'static str),
    /// The field took a branch it could only enclose (`join`): the smooth
    /// and compact blend operators, compact kernels.
    Undecided,
    /// fidget rejected a node (a bug of this translator).
    Fidget,
    /// Translations do not nest (a bug of this translator).
    Nested,
}

impl fmt::Display for TranslateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TranslateError::Unsupported(op) => {
                write!(f, "the field uses `{op}`, which has no fidget node")
            }
            TranslateError::Undecided => f.write_str(
                "the field has a branch that is only enclosed (smooth/compact blend or compact \
                 kernel): no exact fidget expression; use sharp CSG operators",
            ),
            TranslateError::Fidget => f.write_str("fidget rejected a node"),
            TranslateError::Nested => f.write_str("nested translations are not supported"),
        }
    }
}

impl std::error::Error for TranslateError {}

fn fail(e: TranslateError) {
    FAILURE.with(|c| {
        if c.get().is_none() {
            c.set(Some(e));
        }
    });
}

/// A symbolic number: a node of the thread's current fidget [`Context`].
#[derive(Clone, Copy, Debug)]
pub struct Sym(Node);

/// Runs `f` on the current context; a missing context or a fidget error is
/// recorded and gives `fallback`.
fn with_ctx(fallback: Node, f: impl FnOnce(&mut Context) -> Option<Node>) -> Sym {
    CTX.with(|c| {
        let mut c = c.borrow_mut();
        let node = match c.as_mut() {
            Some(ctx) => f(ctx),
            None => None,
        };
        match node {
            Some(n) => Sym(n),
            None => {
                fail(TranslateError::Fidget);
                Sym(fallback)
            }
        }
    })
}

macro_rules! binary {
    ($tr:ident, $m:ident, $ctxop:ident) => {
        impl $tr for Sym {
            type Output = Sym;
            fn $m(self, rhs: Sym) -> Sym {
                with_ctx(self.0, |ctx| ctx.$ctxop(self.0, rhs.0).ok())
            }
        }
        impl $tr<f32> for Sym {
            type Output = Sym;
            fn $m(self, rhs: f32) -> Sym {
                self.$m(Sym::constant(rhs))
            }
        }
    };
}
binary!(Add, add, add);
binary!(Sub, sub, sub);
binary!(Mul, mul, mul);
binary!(Div, div, div);

impl Neg for Sym {
    type Output = Sym;
    fn neg(self) -> Sym {
        with_ctx(self.0, |ctx| ctx.neg(self.0).ok())
    }
}

impl Sym {
    fn constant(c: f32) -> Sym {
        CTX.with(|cell| {
            let mut cell = cell.borrow_mut();
            match cell.as_mut() {
                Some(ctx) => Sym(ctx.constant(c)),
                None => {
                    fail(TranslateError::Nested);
                    // An arbitrary node of a throw-away context: the
                    // failure is reported before it is used.
                    Sym(Context::new().x())
                }
            }
        })
    }
    fn unary(self, f: impl FnOnce(&mut Context, Node) -> Option<Node>) -> Sym {
        with_ctx(self.0, |ctx| f(ctx, self.0))
    }
}

impl FieldNum<f32> for Sym {
    fn constant(c: f32) -> Self {
        Sym::constant(c)
    }
    fn ray_param(_t0: f32, _t1: f32) -> Self {
        fail(TranslateError::Unsupported("ray_param"));
        Sym::constant(0.0)
    }
    fn sqr(self) -> Self {
        self.unary(|c, n| c.square(n).ok())
    }
    fn powi(self, n: i32) -> Self {
        if n == 0 {
            return Sym::constant(1.0);
        }
        let base = if n < 0 { self.recip() } else { self };
        // square-and-multiply (bounded by 32 iterations)
        let mut e = n.unsigned_abs();
        let mut acc: Option<Sym> = None;
        let mut b = base;
        while e > 0 {
            if e & 1 == 1 {
                acc = Some(match acc {
                    None => b,
                    Some(a) => a * b,
                });
            }
            e >>= 1;
            if e > 0 {
                b = b.sqr();
            }
        }
        acc.unwrap_or(base)
    }
    fn powf(self, p: f32) -> Self {
        if p == p.round() && p.abs() <= 64.0 {
            self.powi(p as i32)
        } else if p == 0.5 {
            self.sqrt()
        } else if p > 0.0 {
            // x^p = exp(p·ln x) for x > 0, and 0 at x = 0 (ln 0 = −∞);
            // the fields call powf only on values ≥ 0 (kernel densities)
            (self.ln() * p).exp()
        } else {
            fail(TranslateError::Unsupported(
                "powf with a negative non-integer exponent",
            ));
            self
        }
    }
    fn sqrt(self) -> Self {
        self.unary(|c, n| c.sqrt(n).ok())
    }
    fn recip(self) -> Self {
        self.unary(|c, n| c.recip(n).ok())
    }
    fn exp(self) -> Self {
        self.unary(|c, n| c.exp(n).ok())
    }
    fn ln(self) -> Self {
        self.unary(|c, n| c.ln(n).ok())
    }
    fn sin(self) -> Self {
        self.unary(|c, n| c.sin(n).ok())
    }
    fn cos(self) -> Self {
        self.unary(|c, n| c.cos(n).ok())
    }
    fn abs(self) -> Self {
        self.unary(|c, n| c.abs(n).ok())
    }
    fn min(self, other: Self) -> Self {
        with_ctx(self.0, |c| c.min(self.0, other.0).ok())
    }
    fn max(self, other: Self) -> Self {
        with_ctx(self.0, |c| c.max(self.0, other.0).ok())
    }
    fn enclosure(&self) -> Interval<f32> {
        Interval::ENTIRE
    }
    fn join(self, _other: Self) -> Self {
        fail(TranslateError::Undecided);
        self
    }
}

/// The fidget expression (context and root node) of `tree`'s field, with
/// the same `f32` parameters our interpreter reads.
///
/// # Errors
/// [`TranslateError`] when the tree uses something without an exact fidget
/// expression (smooth or compact blends, compact kernels, …).
pub fn blobtree_to_fidget(tree: &FlatBlobtree) -> Result<(Context, Node), TranslateError> {
    let nested = CTX.with(|c| c.borrow().is_some());
    if nested {
        return Err(TranslateError::Nested);
    }
    FAILURE.with(|c| c.set(None));
    let mut ctx = Context::new();
    let [x, y, z] = ctx.axes();
    CTX.with(|c| *c.borrow_mut() = Some(ctx));
    let root: Sym = tree
        .as_ref()
        .eval_full::<f32, Sym>([Sym(x), Sym(y), Sym(z)]);
    let ctx = CTX.with(|c| c.borrow_mut().take());
    if let Some(e) = FAILURE.with(|c| c.take()) {
        return Err(e);
    }
    ctx.map(|ctx| (ctx, root.0)).ok_or(TranslateError::Nested)
}

/// The largest `|f_fidget − f_ours| / max(1, |f_ours|)` over `points`,
/// evaluated with fidget's VM point evaluator and our `f32` interpreter,
/// and the number of points where the two signs differ (away from
/// `|f| ≤ tol`).
///
/// # Errors
/// fidget's evaluation errors.
pub fn check_translation(
    tree: &FlatBlobtree,
    ctx: &Context,
    root: Node,
    points: &[[f32; 3]],
    tol: f32,
) -> Result<(f32, usize), Box<dyn std::error::Error>> {
    use fidget::shape::EzShape;
    use fidget::vm::VmShape;
    let shape = VmShape::new(ctx, root)?;
    let tape = shape.ez_point_tape();
    let mut eval = VmShape::new_point_eval();
    let mut worst = 0.0f32;
    let mut sign_differs = 0;
    for p in points {
        let (v, _) = eval.eval(&tape, p[0], p[1], p[2])?;
        let ours: f32 = tree.as_ref().eval_full::<f32, f32>(*p);
        let err = (v - ours).abs() / ours.abs().max(1.0);
        if err.is_nan() || err > worst {
            worst = err;
        }
        if ours.abs() > tol && (v < 0.0) != (ours < 0.0) {
            sign_differs += 1;
        }
    }
    Ok((worst, sign_differs))
}

#[cfg(test)]
mod tests {
    use super::*;
    use boundtrace_fields::blobtree::Node as TreeNode;
    use boundtrace_fields::{Operator, Primitive};

    fn tree(op: Operator<f64>) -> FlatBlobtree {
        let s = TreeNode::primitive(Primitive::sphere([0.2, 0.0, 0.0], 0.3).unwrap());
        let b = TreeNode::primitive(Primitive::cuboid([-0.2, 0.1, 0.0], [0.2, 0.1, 0.3]).unwrap());
        FlatBlobtree::from_node(&TreeNode::op(op, s, b)).unwrap()
    }

    fn grid() -> Vec<[f32; 3]> {
        let mut pts = Vec::new();
        for i in 0..9 {
            for j in 0..9 {
                for k in 0..9 {
                    let c = |n: i32| -0.6 + 0.15 * n as f32;
                    pts.push([c(i), c(j), c(k)]);
                }
            }
        }
        pts
    }

    #[test]
    fn sharp_csg_translates_exactly() {
        for op in [
            Operator::union(),
            Operator::intersection(),
            Operator::difference(),
        ] {
            let t = tree(op);
            let (ctx, root) = blobtree_to_fidget(&t).unwrap();
            let (worst, signs) = check_translation(&t, &ctx, root, &grid(), 0.0).unwrap();
            assert!(worst < 1e-5, "{worst}");
            assert_eq!(signs, 0);
        }
    }

    #[test]
    fn compact_blends_are_refused() {
        let t = tree(Operator::compact_union(0.1, 0.2).unwrap());
        assert_eq!(
            blobtree_to_fidget(&t).err(),
            Some(TranslateError::Undecided)
        );
        // and the thread's state is clean afterwards
        assert!(blobtree_to_fidget(&tree(Operator::union())).is_ok());
    }

    #[test]
    fn powi_matches_floats() {
        let mut ctx = Context::new();
        let x = ctx.x();
        CTX.with(|c| *c.borrow_mut() = Some(ctx));
        let nodes: Vec<(i32, Sym)> = [-3, -1, 0, 1, 2, 5, 7]
            .into_iter()
            .map(|n| (n, Sym(x).powi(n)))
            .collect();
        let ctx = CTX.with(|c| c.borrow_mut().take()).unwrap();
        for (n, s) in nodes {
            let v = ctx.eval_xyz(s.0, 1.3, 0.0, 0.0).unwrap();
            let want = 1.3f32.powi(n);
            assert!(
                (v - want).abs() <= 1e-5 * want.abs().max(1.0),
                "{n}: {v} vs {want}"
            );
        }
    }
}
