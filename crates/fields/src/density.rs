//! Blending operators on density fields (thesis Part II §1.1: blending by
//! summation, sharp union/intersection, Ricci blend), generic over the
//! number type.
//!
//! # Densities and fields
//!
//! A *density* `d ≥ 0` is large inside a shape (e.g. `Σ wᵢ kᵢ` of blobs);
//! the surface is `d = iso`. The tracer's [`Field`]s are `f = iso − d`
//! (positive outside). The operators are offered twice:
//!
//! - as plain functions on densities, over fixed arrays (`[N; K]`) and
//!   slices, in any [`FieldNum`] type: [`sum`], [`sum_slice`], [`max`],
//!   [`min`], [`ricci`];
//! - as small combinators over two child fields that share one iso-value:
//!   [`Sum`] (`d = d_a + d_b`, so `f = f_a + f_b − iso`), [`Union`]
//!   (`d = max(d_a, d_b)`, so `f = min(f_a, f_b)`), [`Intersection`]
//!   (`d = min`, `f = max`) and [`Ricci`]
//!   (`d = (d_aⁿ + d_bⁿ)^{1/n}` with `d = max(iso − f, 0)`);
//! - [`UnionAll`]: the n-ary sharp union `f = minᵢ fᵢ` over any storage of
//!   children of one type (forward-inclusion paper eq. 20: the maximum of
//!   blob groups' densities).
//!
//! # Bounds
//!
//! Every result is computed with the number type's own operations, so an
//! interval, affine or forward bound of the result is sound when the inputs'
//! are (bottom-up rules of the forward-inclusion paper §5.2/§6.2: sums,
//! `min`/`max` of bounds, `powf`). The combinators also combine their
//! children's Taylor bounds ([`Field::taylor_linear`],
//! [`Field::taylor_quadratic`]) by the same rules when both children have
//! one (not [`Ricci`]), and their Lipschitz bounds (sum: `L_a + L_b`;
//! union/intersection: `max(L_a, L_b)`; Ricci with `n ≥ 1`: `L_a + L_b`,
//! since each partial derivative of the `n`-norm is in `[0, 1]`).
//!
//! ```
//! use boundtrace_fields::density;
//! use boundtrace_ia_core::Interval;
//!
//! assert_eq!(density::sum([0.25f64, 0.5, 0.25]), 1.0);
//! assert_eq!(density::max([0.25f64, 0.5]), 0.5);
//! let r = density::ricci([Interval::point(3.0f64), Interval::point(4.0)], 2.0);
//! assert!(r.contains(5.0) && r.width() < 1e-14);
//! ```

use crate::FieldError;
use boundtrace_ia_core::Real;
use boundtrace_inclusion::{Field, FieldNum, ForwardLinear, ForwardQuadratic, Ray};
use core::marker::PhantomData;

/// `Σ xᵢ` over a fixed array (`0` for `K = 0`).
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn sum<T: Real, N: FieldNum<T>, const K: usize>(xs: [N; K]) -> N {
    sum_slice(&xs)
}

/// `Σ xᵢ` over a slice (`0` for an empty slice).
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn sum_slice<T: Real, N: FieldNum<T>>(xs: &[N]) -> N {
    let mut acc = N::constant(T::ZERO);
    for &x in xs {
        acc = acc + x;
    }
    acc
}

/// `max xᵢ` (sharp union of densities); `0` for an empty array (the
/// density of nothing).
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn max<T: Real, N: FieldNum<T>, const K: usize>(xs: [N; K]) -> N {
    max_slice(&xs)
}

/// `max xᵢ` over a slice; `0` when empty.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn max_slice<T: Real, N: FieldNum<T>>(xs: &[N]) -> N {
    let mut it = xs.iter();
    let Some(&first) = it.next() else {
        return N::constant(T::ZERO);
    };
    it.fold(first, |acc, &x| acc.max(x))
}

/// `min xᵢ` (sharp intersection of densities); `0` for an empty array.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn min<T: Real, N: FieldNum<T>, const K: usize>(xs: [N; K]) -> N {
    min_slice(&xs)
}

/// `min xᵢ` over a slice; `0` when empty.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn min_slice<T: Real, N: FieldNum<T>>(xs: &[N]) -> N {
    let mut it = xs.iter();
    let Some(&first) = it.next() else {
        return N::constant(T::ZERO);
    };
    it.fold(first, |acc, &x| acc.min(x))
}

/// `x^n` for `x ≥ 0`: `powi` for a small integer `n`, `powf` otherwise.
#[cfg_attr(not(target_arch = "spirv"), inline)]
fn pow_pos<T: Real, N: FieldNum<T>>(x: N, n: T) -> N {
    if n == n.round() && n >= T::ONE && n <= T::from_f64(64.0) {
        let k = n.to_i32().unwrap_or(1);
        if k == 1 { x } else { x.powi(k) }
    } else {
        x.powf(n)
    }
}

/// The Ricci blend `(Σ max(xᵢ, 0)ⁿ)^{1/n}` of densities over a fixed array
/// (`n = 1`: the sum; `n → ∞`: the maximum). Negative inputs are clamped
/// to `0` (densities are non-negative).
///
/// The root uses the exponent `1/n` rounded to nearest: the function is
/// exactly `(Σ xᵢⁿ)^{fl(1/n)}`, and bounds are sound for that function.
/// For integer `n ≤ 64` the powers are `powi` (tighter).
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn ricci<T: Real, N: FieldNum<T>, const K: usize>(xs: [N; K], n: T) -> N {
    ricci_slice(&xs, n)
}

/// [`ricci`] over a slice (`0` when empty).
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn ricci_slice<T: Real, N: FieldNum<T>>(xs: &[N], n: T) -> N {
    let zero = N::constant(T::ZERO);
    let mut acc = zero;
    for &x in xs {
        acc = acc + pow_pos(x.max(zero), n);
    }
    if n == T::ONE {
        acc
    } else {
        acc.powf(T::ONE / n)
    }
}

/// Blending by summation of two fields sharing the iso-value `iso`:
/// densities add, `f = f_a + f_b − iso`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sum<T, A, B> {
    /// The shared iso-value.
    pub iso: T,
    /// First child.
    pub a: A,
    /// Second child.
    pub b: B,
}

/// Sharp union: `max` of densities, `f = min(f_a, f_b)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Union<A, B> {
    /// First child.
    pub a: A,
    /// Second child.
    pub b: B,
}

/// Sharp intersection: `min` of densities, `f = max(f_a, f_b)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Intersection<A, B> {
    /// First child.
    pub a: A,
    /// Second child.
    pub b: B,
}

/// Ricci blend of two fields sharing `iso`: `d = (d_aⁿ + d_bⁿ)^{1/n}` with
/// `d_x = max(iso − f_x, 0)`, `f = iso − d`. Build with [`Ricci::new`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ricci<T, A, B> {
    iso: T,
    n: T,
    a: A,
    b: B,
}

impl<T: Real, A, B> Ricci<T, A, B> {
    /// The blend with exponent `n ≥ 1`.
    ///
    /// # Errors
    /// [`FieldError::InvalidParameter`] when `n` is NaN, infinite or `< 1`,
    /// or `iso` is not finite.
    pub fn new(iso: T, n: T, a: A, b: B) -> Result<Self, FieldError> {
        if !iso.is_finite() {
            return Err(FieldError::InvalidParameter {
                name: "iso",
                reason: "must be finite",
            });
        }
        if !n.is_finite() || n < T::ONE {
            return Err(FieldError::InvalidParameter {
                name: "n",
                reason: "Ricci exponent must be finite and >= 1",
            });
        }
        Ok(Self { iso, n, a, b })
    }

    /// The exponent `n`.
    pub fn exponent(&self) -> T {
        self.n
    }
}

impl<T: Real, A: Field<T>, B: Field<T>> Field<T> for Sum<T, A, B> {
    fn eval<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        self.a.eval(p) + self.b.eval(p) - self.iso
    }
    fn lipschitz(&self) -> Option<T> {
        let s = boundtrace_ia_core::Interval::point(self.a.lipschitz()?) + self.b.lipschitz()?;
        Some(s.hi())
    }
    fn taylor_linear(&self, ray: &Ray<T>, t0: T, t1: T) -> Option<ForwardLinear<T>> {
        let a = self.a.taylor_linear(ray, t0, t1)?;
        let b = self.b.taylor_linear(ray, t0, t1)?;
        Some(a + b - self.iso)
    }
    fn taylor_quadratic(&self, ray: &Ray<T>, t0: T, t1: T) -> Option<ForwardQuadratic<T>> {
        let a = self.a.taylor_quadratic(ray, t0, t1)?;
        let b = self.b.taylor_quadratic(ray, t0, t1)?;
        Some(a + b - self.iso)
    }
}

impl<T: Real, A: Field<T>, B: Field<T>> Field<T> for Union<A, B> {
    fn eval<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        self.a.eval(p).min(self.b.eval(p))
    }
    fn lipschitz(&self) -> Option<T> {
        Some(self.a.lipschitz()?.max(self.b.lipschitz()?))
    }
    fn taylor_linear(&self, ray: &Ray<T>, t0: T, t1: T) -> Option<ForwardLinear<T>> {
        let a = self.a.taylor_linear(ray, t0, t1)?;
        Some(a.min(self.b.taylor_linear(ray, t0, t1)?))
    }
    fn taylor_quadratic(&self, ray: &Ray<T>, t0: T, t1: T) -> Option<ForwardQuadratic<T>> {
        let a = self.a.taylor_quadratic(ray, t0, t1)?;
        Some(a.min(self.b.taylor_quadratic(ray, t0, t1)?))
    }
}

impl<T: Real, A: Field<T>, B: Field<T>> Field<T> for Intersection<A, B> {
    fn eval<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        self.a.eval(p).max(self.b.eval(p))
    }
    fn lipschitz(&self) -> Option<T> {
        Some(self.a.lipschitz()?.max(self.b.lipschitz()?))
    }
    fn taylor_linear(&self, ray: &Ray<T>, t0: T, t1: T) -> Option<ForwardLinear<T>> {
        let a = self.a.taylor_linear(ray, t0, t1)?;
        Some(a.max(self.b.taylor_linear(ray, t0, t1)?))
    }
    fn taylor_quadratic(&self, ray: &Ray<T>, t0: T, t1: T) -> Option<ForwardQuadratic<T>> {
        let a = self.a.taylor_quadratic(ray, t0, t1)?;
        Some(a.max(self.b.taylor_quadratic(ray, t0, t1)?))
    }
}

impl<T: Real, A: Field<T>, B: Field<T>> Field<T> for Ricci<T, A, B> {
    fn eval<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        let da = -self.a.eval(p) + self.iso;
        let db = -self.b.eval(p) + self.iso;
        -ricci([da, db], self.n) + self.iso
    }
    fn lipschitz(&self) -> Option<T> {
        let s = boundtrace_ia_core::Interval::point(self.a.lipschitz()?) + self.b.lipschitz()?;
        Some(s.hi())
    }
}

/// The n-ary sharp union of fields of one type: `f = minᵢ fᵢ` (densities:
/// `d = maxᵢ dᵢ`, forward-inclusion paper eq. 20). `S` is any storage of
/// children (`[F; K]`, a slice, a `Vec`). Build with [`UnionAll::new`].
///
/// Bounds: bottom-up through `min`; Taylor bounds are the `min` of the
/// children's (paper §5.2/§6.2 rule for `min`), `None` when a child has
/// none; the Lipschitz bound is the largest child's.
///
/// ```
/// use boundtrace_fields::density::UnionAll;
/// use boundtrace_fields::{Blobs, Kernel, PointBlob};
/// use boundtrace_inclusion::{Field, Ray};
///
/// let k = Kernel::compact(6, 1.0).unwrap();
/// let group = |x: f64| Blobs::new(0.5, [PointBlob::new([x, 0.0, 0.0], 1.0, k).unwrap()]).unwrap();
/// let u = UnionAll::new([group(-1.0), group(1.0)]).unwrap();
/// assert_eq!(u.eval([1.0f64, 0.0, 0.0]), -0.5); // inside the second group
/// let ray = Ray::new([-3.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
/// assert!(u.taylor_quadratic(&ray, 0.0, 1.0).is_some());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UnionAll<F, S> {
    children: S,
    _child: PhantomData<F>,
}

impl<F, S: AsRef<[F]>> UnionAll<F, S> {
    /// The union of `children`.
    ///
    /// # Errors
    /// [`FieldError::InvalidParameter`] when there is no child (the union
    /// of nothing has no finite field).
    pub fn new(children: S) -> Result<Self, FieldError> {
        if children.as_ref().is_empty() {
            return Err(FieldError::InvalidParameter {
                name: "children",
                reason: "a union needs at least one child",
            });
        }
        Ok(Self {
            children,
            _child: PhantomData,
        })
    }

    /// The children.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn children(&self) -> &[F] {
        self.children.as_ref()
    }
}

impl<T: Real, F: Field<T>, S: AsRef<[F]>> Field<T> for UnionAll<F, S> {
    fn eval<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        let mut it = self.children.as_ref().iter();
        let Some(first) = it.next() else {
            return N::constant(T::INFINITY);
        };
        it.fold(first.eval(p), |acc, c| acc.min(c.eval(p)))
    }
    fn lipschitz(&self) -> Option<T> {
        let mut l = T::ZERO;
        for c in self.children.as_ref() {
            l = l.max(c.lipschitz()?);
        }
        Some(l)
    }
    fn taylor_linear(&self, ray: &Ray<T>, t0: T, t1: T) -> Option<ForwardLinear<T>> {
        let mut it = self.children.as_ref().iter();
        let mut acc = it.next()?.taylor_linear(ray, t0, t1)?;
        for c in it {
            acc = acc.min(c.taylor_linear(ray, t0, t1)?);
        }
        Some(acc)
    }
    fn taylor_quadratic(&self, ray: &Ray<T>, t0: T, t1: T) -> Option<ForwardQuadratic<T>> {
        let mut it = self.children.as_ref().iter();
        let mut acc = it.next()?.taylor_quadratic(ray, t0, t1)?;
        for c in it {
            acc = acc.min(c.taylor_quadratic(ray, t0, t1)?);
        }
        Some(acc)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use boundtrace_ia_core::Interval;
    use boundtrace_inclusion::Jet;

    /// `iso − density` of a ball: `f = |p|² − r²` shifted, density `r² − |p − c|²`.
    struct Ball(f64, [f64; 3]);
    impl Field<f64> for Ball {
        fn eval<N: FieldNum<f64>>(&self, p: [N; 3]) -> N {
            let c = self.1;
            (p[0] - c[0]).sqr() + (p[1] - c[1]).sqr() + (p[2] - c[2]).sqr() - self.0 * self.0 + 1.0
        }
        fn lipschitz(&self) -> Option<f64> {
            Some(10.0)
        }
    }

    #[test]
    fn plain_functions() {
        assert_eq!(sum::<f64, f64, 0>([]), 0.0);
        assert_eq!(max::<f64, f64, 0>([]), 0.0);
        assert_eq!(min([3.0f64, -1.0, 2.0]), -1.0);
        assert_eq!(max_slice(&[3.0f64, -1.0, 2.0]), 3.0);
        assert!((ricci([3.0f64, 4.0], 2.0) - 5.0).abs() < 1e-12);
        assert_eq!(ricci([3.0f64, 4.0], 1.0), 7.0);
        assert!((ricci([1.0f64, 1.0], 2.5) - 2f64.powf(0.4)).abs() < 1e-12);
        // Large n approaches the max.
        assert!((ricci([1.0f64, 0.9], 60.0) - 1.0).abs() < 1e-3);
        // negative densities are clamped
        assert_eq!(ricci([-1.0f64, 2.0], 3.0), 2.0f64.powi(3).powf(1.0 / 3.0));
    }

    #[test]
    fn interval_ricci_contains_points() {
        let a = Interval::new(0.5f64, 1.5);
        let b = Interval::new(0.0, 2.0);
        let r = ricci([a, b], 3.0);
        for &(x, y) in &[(0.5, 0.0), (1.5, 2.0), (1.0, 1.0), (0.7, 1.9)] {
            assert!(r.contains(ricci([x, y], 3.0)));
        }
        let j = ricci([Jet::variable(3.0f64), Jet::constant(4.0)], 2.0);
        assert!((j.d1 - 0.6).abs() < 1e-12);
    }

    #[test]
    fn combinators() {
        let (a, b) = (Ball(1.0, [0.0; 3]), Ball(1.0, [1.5, 0.0, 0.0]));
        let p = [0.75f64, 0.0, 0.0];
        let s = Sum {
            iso: 1.0,
            a: Ball(1.0, [0.0; 3]),
            b: Ball(1.0, [1.5, 0.0, 0.0]),
        };
        assert!((s.eval(p) - (a.eval(p) + b.eval(p) - 1.0)).abs() < 1e-15);
        let u = Union {
            a: Ball(1.0, [0.0; 3]),
            b: Ball(1.0, [1.5, 0.0, 0.0]),
        };
        assert_eq!(u.eval([0.0f64, 0.0, 0.0]), a.eval([0.0, 0.0, 0.0]));
        let i = Intersection {
            a: Ball(1.0, [0.0; 3]),
            b: Ball(1.0, [1.5, 0.0, 0.0]),
        };
        assert_eq!(i.eval([0.0f64, 0.0, 0.0]), b.eval([0.0, 0.0, 0.0]));
        assert_eq!(s.lipschitz(), Some(20.0));
        assert_eq!(u.lipschitz(), Some(10.0));
        let r = Ricci::new(1.0, 2.0, Ball(1.0, [0.0; 3]), Ball(1.0, [1.5, 0.0, 0.0])).unwrap();
        let v = r.eval(p);
        let (da, db) = (1.0 - a.eval(p), 1.0 - b.eval(p));
        assert!((v - (1.0 - (da * da + db * db).sqrt())).abs() < 1e-12);
        assert!(Ricci::new(1.0, 0.5, Ball(1.0, [0.0; 3]), Ball(1.0, [0.0; 3])).is_err());
        assert!(Ricci::new(f64::NAN, 2.0, Ball(1.0, [0.0; 3]), Ball(1.0, [0.0; 3])).is_err());
        let iv: Interval<f64> = r.eval([
            Interval::new(0.7, 0.8),
            Interval::point(0.0),
            Interval::point(0.0),
        ]);
        assert!(iv.contains(v));
    }

    #[test]
    fn union_all_is_the_minimum_with_bounds() {
        use crate::blob::{Blobs, PointBlob};
        use crate::kernel::Kernel;
        let k = Kernel::compact(6, 1.0f64).unwrap();
        let g = |c: [f64; 3]| Blobs::new(0.4, [PointBlob::new(c, 1.0, k).unwrap()]).unwrap();
        let kids = [g([-0.5, 0.0, 0.0]), g([0.5, 0.1, 0.0]), g([0.0, 0.6, 0.1])];
        let u = UnionAll::new(kids).unwrap();
        let ray = Ray::new([-2.0, 0.05, 0.02], [1.0, 0.1, 0.0]);
        let lip = u.lipschitz().unwrap();
        assert_eq!(lip, kids[0].lipschitz().unwrap());
        for i in 0..30 {
            let t0 = 0.12 * f64::from(i);
            let t1 = t0 + 0.3;
            let lq = u.taylor_quadratic(&ray, t0, t1).unwrap();
            let ll = u.taylor_linear(&ray, t0, t1).unwrap();
            for j in 0..=10 {
                let tau = 0.03 * f64::from(j);
                let p: [f64; 3] = ray.at(t0 + tau, t0 + tau);
                let v = u.eval(p);
                let m = kids.iter().map(|c| c.eval(p)).fold(f64::INFINITY, f64::min);
                assert_eq!(v, m);
                assert!(lq.bounds_at(tau).contains(v) && ll.bounds_at(tau).contains(v));
            }
        }
        assert!(UnionAll::<Ball, [Ball; 0]>::new([]).is_err());
        // a child without Taylor bounds gives none
        let balls = UnionAll::new([Ball(1.0, [0.0; 3])]).unwrap();
        assert!(balls.taylor_linear(&ray, 0.0, 1.0).is_none());
        assert_eq!(balls.lipschitz(), Some(10.0));
    }
}
