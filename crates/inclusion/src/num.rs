//! [`FieldNum`]: the arithmetic every number type of boundtrace offers, so a
//! field is written once and evaluated with all of them.

use crate::{ForwardLinear, ForwardQuadratic, Jet};
use boundtrace_ia_core::{Affine, Interval, Real};
use core::ops::{Add, Div, Mul, Neg, Sub};
use num_traits::Float;

/// The number types a [`Field`](crate::Field) is evaluated with: plain
/// floats `T`, [`Jet<T>`], [`Interval<T>`], [`Affine<T, N>`],
/// [`ForwardLinear<T>`] and [`ForwardQuadratic<T>`].
///
/// Each type implements the operations with its own semantics (exact-ish
/// float, derivatives, sound enclosures, forward bounds). The ray parameter
/// is [`ray_param`](Self::ray_param), the identity on `[t₀, t₁]`; a point
/// `o + t·d` is then `t * d + o` computed in the number type (see
/// [`Ray::at`](crate::Ray::at)).
///
/// Scalars: `x + c`, `x - c`, `x * c`, `x / c` with `c: T`; write `c − x` as
/// `-x + c`.
///
/// ```
/// use boundtrace_inclusion::{FieldNum, ForwardQuadratic, Jet};
/// use boundtrace_ia_core::Interval;
///
/// fn blob<N: FieldNum<f64>>(t: N) -> N {
///     (-(t - 0.5).sqr()).exp() - 0.5
/// }
/// let at = blob(0.0f64);
/// assert!(blob(Interval::ray_param(0.0, 0.0)).contains(at));
/// assert_eq!(blob(Jet::ray_param(0.0, 1.0)).v, at);
/// assert!(blob(ForwardQuadratic::ray_param(0.0, 1.0)).start().contains(at));
/// ```
pub trait FieldNum<T: Real>:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Add<T, Output = Self>
    + Sub<T, Output = Self>
    + Mul<T, Output = Self>
    + Div<T, Output = Self>
{
    /// Whether `Self` is a *form* (affine, forward linear or quadratic):
    /// a number whose range can be unbounded where the interval evaluation
    /// of the same expression is bounded (e.g. after a division by an
    /// enclosure of a small positive quantity), so that a field may replace
    /// such a result by an interval enclosure. `false` (the default) for
    /// points, jets and intervals: a field can then leave that fallback out
    /// at compile time (a GPU driver inlines every call, so code that can
    /// never run still costs memory: BENCHMARKS.md "GPU", session 35).
    const IS_FORM: bool = false;
    /// The constant `c`.
    fn constant(c: T) -> Self;
    /// The ray parameter `t` on `[t0, t1]`: the point `t0` for `T` (and
    /// `Jet` with `f' = 1`), the interval for `Interval`/`Affine`, the
    /// identity bound for the forward types.
    fn ray_param(t0: T, t1: T) -> Self;
    /// `x²`.
    fn sqr(self) -> Self;
    /// `xⁿ` for an integer `n`.
    fn powi(self, n: i32) -> Self;
    /// `x^p` for a real `p`.
    fn powf(self, p: T) -> Self;
    /// `√x`.
    fn sqrt(self) -> Self;
    /// `1/x`.
    fn recip(self) -> Self;
    /// `eˣ`.
    fn exp(self) -> Self;
    /// `ln x`.
    fn ln(self) -> Self;
    /// `sin x`.
    fn sin(self) -> Self;
    /// `cos x`.
    fn cos(self) -> Self;
    /// `|x|`.
    fn abs(self) -> Self;
    /// `min(x, y)`.
    fn min(self, other: Self) -> Self;
    /// `max(x, y)`.
    fn max(self, other: Self) -> Self;
    /// A sound enclosure of every value `self` stands for on its interval:
    /// the point itself for `T` and [`Jet`] (its value), the interval, the
    /// affine form's range, the forward bound's range over its validity.
    /// Fields use it to decide branches (e.g. a compact operator's range of
    /// interaction).
    fn enclosure(&self) -> Interval<T>;
    /// A number enclosing both `self` and `other`, for a branch that
    /// [`enclosure`](Self::enclosure) cannot decide: the hull for
    /// `Interval`/`Affine`, the lower side of the minimum and the upper side
    /// of the maximum for the forward types.
    ///
    /// Point types (`T`, [`Jet`]) always decide their branch, so for them
    /// `join` returns `self`: call it only when the branches agree at the
    /// point (e.g. on the boundary of a continuous piecewise definition).
    fn join(self, other: Self) -> Self;
    /// `max(1 − x, 0)`: the clamped `1 − x` of compact kernels.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn one_minus_clamped(self) -> Self {
        (-self + T::ONE).max(Self::constant(T::ZERO))
    }
}

macro_rules! float_num {
    ($($t:ty),*) => {$(
        impl FieldNum<$t> for $t {
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn constant(c: $t) -> Self { c }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn ray_param(t0: $t, _t1: $t) -> Self { t0 }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn sqr(self) -> Self { self * self }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn powi(self, n: i32) -> Self { Real::powi_std(self, n) }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn powf(self, p: $t) -> Self { Real::powf_ia(self, p) }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn sqrt(self) -> Self { Float::sqrt(self) }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn recip(self) -> Self { 1.0 / self }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn exp(self) -> Self { Real::exp_ia(self) }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn ln(self) -> Self { Real::ln_ia(self) }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn sin(self) -> Self { Float::sin(self) }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn cos(self) -> Self { Float::cos(self) }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn abs(self) -> Self { Float::abs(self) }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn min(self, o: Self) -> Self { Float::min(self, o) }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn max(self, o: Self) -> Self { Float::max(self, o) }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn enclosure(&self) -> Interval<$t> { Interval::point(*self) }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn join(self, _o: Self) -> Self { self }
        }
    )*};
}
float_num!(f32, f64);

/// Forwards the trait to inherent methods of the same names.
macro_rules! forward_num {
    ($ty:ty, [$($gen:tt)*], $form:expr, $ray:expr, $encl:expr, $join:expr) => {
        impl<$($gen)*> FieldNum<T> for $ty {
            const IS_FORM: bool = $form;
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn constant(c: T) -> Self { <$ty>::constant(c) }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn ray_param(t0: T, t1: T) -> Self { ($ray)(t0, t1) }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn sqr(self) -> Self { <$ty>::sqr(self) }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn powi(self, n: i32) -> Self { <$ty>::powi(self, n) }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn powf(self, p: T) -> Self { <$ty>::powf(self, p) }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn sqrt(self) -> Self { <$ty>::sqrt(self) }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn recip(self) -> Self { <$ty>::recip(self) }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn exp(self) -> Self { <$ty>::exp(self) }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn ln(self) -> Self { <$ty>::ln(self) }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn sin(self) -> Self { <$ty>::sin(self) }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn cos(self) -> Self { <$ty>::cos(self) }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn abs(self) -> Self { <$ty>::abs(self) }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn min(self, o: Self) -> Self { <$ty>::min(self, o) }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn max(self, o: Self) -> Self { <$ty>::max(self, o) }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn enclosure(&self) -> Interval<T> { ($encl)(self) }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn join(self, o: Self) -> Self { ($join)(self, o) }
        }
    };
}

forward_num!(
    Jet<T>,
    [T: Real],
    false,
    |t0, _t1| Jet::variable(t0),
    |j: &Jet<T>| Interval::point(j.v),
    |a, _b| a
);
forward_num!(
    ForwardLinear<T>,
    [T: Real],
    true,
    ForwardLinear::ray_param,
    ForwardLinear::range,
    ForwardLinear::join
);
forward_num!(
    ForwardQuadratic<T>,
    [T: Real],
    true,
    ForwardQuadratic::ray_param,
    ForwardQuadratic::range,
    ForwardQuadratic::join
);

impl<T: Real> FieldNum<T> for Interval<T> {
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn constant(c: T) -> Self {
        Interval::point(c)
    }
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn ray_param(t0: T, t1: T) -> Self {
        Interval::new(t0, t1)
    }
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn sqr(self) -> Self {
        Interval::sqr(self)
    }
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn powi(self, n: i32) -> Self {
        Interval::powi(self, n)
    }
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn powf(self, p: T) -> Self {
        Interval::pow(self, p)
    }
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn sqrt(self) -> Self {
        Interval::sqrt(self)
    }
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn recip(self) -> Self {
        Interval::recip(self)
    }
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn exp(self) -> Self {
        Interval::exp(self)
    }
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn ln(self) -> Self {
        Interval::ln(self)
    }
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn sin(self) -> Self {
        Interval::sin(self)
    }
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn cos(self) -> Self {
        Interval::cos(self)
    }
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn abs(self) -> Self {
        Interval::abs(self)
    }
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn min(self, o: Self) -> Self {
        Interval::min(self, o)
    }
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn max(self, o: Self) -> Self {
        Interval::max(self, o)
    }
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn enclosure(&self) -> Interval<T> {
        *self
    }
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn join(self, o: Self) -> Self {
        self.hull(o)
    }
}

/// Affine forms: the ray parameter is noise symbol `0`. `powi` is binary
/// powering with [`Affine::sqr`] and products; `powf` goes through an
/// interval (`Interval::pow` of the form's range, which forgets the
/// correlation but stays sound).
impl<T: Real, const N: usize> FieldNum<T> for Affine<T, N> {
    const IS_FORM: bool = true;
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn constant(c: T) -> Self {
        Affine::constant(c)
    }
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn ray_param(t0: T, t1: T) -> Self {
        Affine::variable(Interval::new(t0, t1), 0)
    }
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn sqr(self) -> Self {
        Affine::sqr(self)
    }
    fn powi(self, n: i32) -> Self {
        if n == 0 {
            return Affine::constant(T::ONE);
        }
        let mut e = n.unsigned_abs();
        let mut base = self;
        let mut acc: Option<Self> = None;
        loop {
            if e & 1 == 1 {
                acc = Some(match acc {
                    None => base,
                    Some(a) => a * base,
                });
            }
            e >>= 1;
            if e == 0 {
                break;
            }
            base = base.sqr();
        }
        let p = acc.unwrap_or(self);
        if n < 0 { p.recip() } else { p }
    }
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn powf(self, p: T) -> Self {
        Affine::from_interval(self.to_interval().pow(p))
    }
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn sqrt(self) -> Self {
        Affine::sqrt(self)
    }
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn recip(self) -> Self {
        Affine::recip(self)
    }
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn exp(self) -> Self {
        Affine::exp(self)
    }
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn ln(self) -> Self {
        Affine::ln(self)
    }
    /// Through the range (sound, forgets the correlation).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn sin(self) -> Self {
        Affine::from_interval(self.to_interval().sin())
    }
    /// Through the range (sound, forgets the correlation).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn cos(self) -> Self {
        Affine::from_interval(self.to_interval().cos())
    }
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn abs(self) -> Self {
        Affine::abs(self)
    }
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn min(self, o: Self) -> Self {
        Affine::min(self, o)
    }
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn max(self, o: Self) -> Self {
        Affine::max(self, o)
    }
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn enclosure(&self) -> Interval<T> {
        self.to_interval()
    }
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn join(self, o: Self) -> Self {
        Affine::from_interval(self.to_interval().hull(o.to_interval()))
    }
}
