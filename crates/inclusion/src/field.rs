//! The [`Field`] trait and rays.

use crate::{FieldNum, ForwardLinear, ForwardQuadratic, Jet};
use boundtrace_ia_core::{Interval, Real};

/// A ray `o + t·d`.
///
/// The direction need not be unit length; a Lipschitz bound `L` of the field
/// then bounds `|df/dt|` by `L·|d|` (see [`Ray::speed`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct Ray<T> {
    /// Origin `o`.
    pub origin: [T; 3],
    /// Direction `d`.
    pub dir: [T; 3],
}

impl<T: Real> Ray<T> {
    /// A ray from origin and direction.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn new(origin: [T; 3], dir: [T; 3]) -> Self {
        Self { origin, dir }
    }

    /// `|d|`, rounded up.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn speed(&self) -> T {
        let [x, y, z] = self.dir;
        (Interval::point(x).sqr() + Interval::point(y).sqr() + Interval::point(z).sqr())
            .sqrt()
            .hi()
    }

    /// The point `o + t·d` with `t = N::ray_param(t0, t1)`, computed in the
    /// number type `N` (an enclosure of the segment for intervals, the
    /// identity bound for forward types, a jet in `t` for [`Jet`]).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn at<N: FieldNum<T>>(&self, t0: T, t1: T) -> [N; 3] {
        let t = N::ray_param(t0, t1);
        [
            t * self.dir[0] + self.origin[0],
            t * self.dir[1] + self.origin[1],
            t * self.dir[2] + self.origin[2],
        ]
    }
}

/// A scalar field `f: ℝ³ → ℝ` whose surface is `f = 0`, written once and
/// evaluated with every [`FieldNum`] type.
///
/// The convention is the tracer's: **`f > 0` outside, `f < 0` inside** (a
/// signed distance, or `iso − density` for blobs). `eval` must be
/// allocation- and recursion-free to run on the GPU; the trait has a generic
/// method, so it is used through generics, not trait objects.
///
/// ```
/// use boundtrace_inclusion::{Field, FieldNum, ForwardQuadratic, Ray};
///
/// /// The unit sphere as a signed distance.
/// struct Sphere;
/// impl Field<f64> for Sphere {
///     fn eval<N: FieldNum<f64>>(&self, p: [N; 3]) -> N {
///         (p[0].sqr() + p[1].sqr() + p[2].sqr()).sqrt() - 1.0
///     }
///     fn lipschitz(&self) -> Option<f64> { Some(1.0) }
/// }
///
/// let ray = Ray::new([-3.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
/// let b: ForwardQuadratic<f64> = Sphere.eval(ray.at(0.0, 1.5));
/// assert!(b.start().contains(2.0));
/// assert!(b.safe_step() <= 2.0); // the surface is at t = 2
/// ```
pub trait Field<T: Real> {
    /// The field at `p`, in any number type.
    fn eval<N: FieldNum<T>>(&self, p: [N; 3]) -> N;

    /// A global Lipschitz bound (`|f(p) − f(q)| ≤ L·|p − q|`) if known.
    fn lipschitz(&self) -> Option<T> {
        None
    }

    /// A tighter linear Taylor bound along `ray` on `[t0, t1]` (paper
    /// §5.1), when the field has analytic derivative bounds; `None` by
    /// default.
    fn taylor_linear(&self, _ray: &Ray<T>, _t0: T, _t1: T) -> Option<ForwardLinear<T>> {
        None
    }

    /// A tighter quadratic Taylor bound along `ray` on `[t0, t1]` (paper
    /// §6.1); `None` by default.
    fn taylor_quadratic(&self, _ray: &Ray<T>, _t0: T, _t1: T) -> Option<ForwardQuadratic<T>> {
        None
    }
}

/// How a forward bound of a field along a ray is obtained.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum BoundKind {
    /// Bottom-up from the arithmetic of [`Field::eval`] (paper §5.2, §6.2).
    BottomUp,
    /// The field's Taylor bound ([`Field::taylor_linear`] /
    /// [`Field::taylor_quadratic`]); unavailable when it has none.
    Taylor,
    /// Both, keeping the tighter side of each (paper "mixed"); bottom-up
    /// alone when the field has no Taylor bound.
    #[default]
    Mixed,
}

/// `f(o + t·d)` at a point `t`, in plain floats.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn value_at<T: Real + FieldNum<T>, F: Field<T>>(field: &F, ray: &Ray<T>, t: T) -> T {
    field.eval(ray.at::<T>(t, t))
}

/// `(f, f', f'')` along the ray at `t`.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn jet_at<T: Real, F: Field<T>>(field: &F, ray: &Ray<T>, t: T) -> Jet<T> {
    field.eval(ray.at::<Jet<T>>(t, t))
}

/// The gradient `∇f(p)` by three forward-mode evaluations.
pub fn gradient<T: Real, F: Field<T>>(field: &F, p: [T; 3]) -> [T; 3] {
    let mut g = [T::ZERO; 3];
    let mut k = 0;
    while k < 3 {
        let mut q = [
            Jet::constant(p[0]),
            Jet::constant(p[1]),
            Jet::constant(p[2]),
        ];
        q[k] = Jet::variable(p[k]);
        g[k] = field.eval(q).d1;
        k += 1;
    }
    g
}

/// A linear forward bound of `field` along `ray` on `[t0, t1]`; `None` only
/// for [`BoundKind::Taylor`] when the field has no Taylor bound.
pub fn linear_bound<T: Real, F: Field<T>>(
    field: &F,
    ray: &Ray<T>,
    t0: T,
    t1: T,
    kind: BoundKind,
) -> Option<ForwardLinear<T>> {
    match kind {
        BoundKind::BottomUp => Some(field.eval(ray.at(t0, t1))),
        BoundKind::Taylor => field.taylor_linear(ray, t0, t1),
        BoundKind::Mixed => {
            let b: ForwardLinear<T> = field.eval(ray.at(t0, t1));
            Some(match field.taylor_linear(ray, t0, t1) {
                Some(t) => b.tighter(t),
                None => b,
            })
        }
    }
}

/// A quadratic forward bound of `field` along `ray` on `[t0, t1]`; `None`
/// only for [`BoundKind::Taylor`] when the field has no Taylor bound.
pub fn quadratic_bound<T: Real, F: Field<T>>(
    field: &F,
    ray: &Ray<T>,
    t0: T,
    t1: T,
    kind: BoundKind,
) -> Option<ForwardQuadratic<T>> {
    match kind {
        BoundKind::BottomUp => Some(field.eval(ray.at(t0, t1))),
        BoundKind::Taylor => field.taylor_quadratic(ray, t0, t1),
        BoundKind::Mixed => {
            let b: ForwardQuadratic<T> = field.eval(ray.at(t0, t1));
            Some(match field.taylor_quadratic(ray, t0, t1) {
                Some(t) => b.tighter(t),
                None => b,
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    struct Torus;
    impl Field<f64> for Torus {
        fn eval<N: FieldNum<f64>>(&self, p: [N; 3]) -> N {
            let q = (p[0].sqr() + p[1].sqr()).sqrt() - 1.0;
            (q.sqr() + p[2].sqr()).sqrt() - 0.25
        }
    }

    #[test]
    fn gradient_of_torus() {
        let g = gradient(&Torus, [1.25, 0.0, 0.0]);
        assert_relative_eq!(g[0], 1.0, epsilon = 1e-12);
        assert_relative_eq!(g[1], 0.0, epsilon = 1e-12);
    }

    #[test]
    fn bounds_agree_at_start() {
        let ray = Ray::new([-3.0, 0.1, 0.05], [1.0, 0.0, 0.0]);
        let v = value_at(&Torus, &ray, 0.5);
        let l = linear_bound(&Torus, &ray, 0.5, 1.0, BoundKind::Mixed).unwrap();
        let q = quadratic_bound(&Torus, &ray, 0.5, 1.0, BoundKind::BottomUp).unwrap();
        assert!(l.start().contains(v) && q.start().contains(v));
        assert!(linear_bound(&Torus, &ray, 0.5, 1.0, BoundKind::Taylor).is_none());
        let i: Interval<f64> = Torus.eval(ray.at(0.5, 1.0));
        assert!(i.contains(v));
    }
}
