//! [`Jet`]: forward-mode value, first and second derivative along the ray.

use boundtrace_ia_core::Real;
use core::ops::{Add, Div, Mul, Neg, Sub};

/// A second-order jet `(f, f', f'')` of a function of one parameter,
/// propagated by forward-mode automatic differentiation.
///
/// Evaluating a field with `Jet`s along a ray (`t` =
/// [`Jet::variable`]) gives the value and the first two directional
/// derivatives at a point: the Hermite data of SCALIS tracing, Taylor
/// bounds at `t₀`, and (with axis directions) gradients for normals.
/// Plain floating point: no rounding control, no soundness claims.
///
/// At kinks (`abs`, `min`, `max`) the derivative of the selected branch is
/// used (ties: the first operand).
///
/// ```
/// use boundtrace_inclusion::Jet;
/// let t = Jet::variable(2.0f64);
/// let f = t * t * t; // t³
/// assert_eq!((f.v, f.d1, f.d2), (8.0, 12.0, 12.0));
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct Jet<T> {
    /// Value `f`.
    pub v: T,
    /// First derivative `f'`.
    pub d1: T,
    /// Second derivative `f''`.
    pub d2: T,
}

impl<T: Real> Jet<T> {
    /// A jet from its parts.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn new(v: T, d1: T, d2: T) -> Self {
        Self { v, d1, d2 }
    }

    /// The constant `c` (zero derivatives).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn constant(c: T) -> Self {
        Self::new(c, T::ZERO, T::ZERO)
    }

    /// The independent variable at `x` (`f' = 1`).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn variable(x: T) -> Self {
        Self::new(x, T::ONE, T::ZERO)
    }

    /// Applies a scalar function with value `g`, derivatives `g1`, `g2` at
    /// `self.v` (chain rule to second order).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn chain(self, g: T, g1: T, g2: T) -> Self {
        Self::new(g, g1 * self.d1, g2 * self.d1 * self.d1 + g1 * self.d2)
    }

    /// `x²`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    pub fn sqr(self) -> Self {
        self * self
    }

    /// `xⁿ`.
    pub fn powi(self, n: i32) -> Self {
        if n == 0 {
            return Self::constant(T::ONE);
        }
        let nf = T::from_f64(n as f64);
        // `powi_std`: no loop in a GPU shader (`Real::powi_std`).
        let g = self.v.powi_std(n);
        let g1 = nf * self.v.powi_std(n - 1);
        let g2 = nf * T::from_f64((n - 1) as f64) * self.v.powi_std(n - 2);
        self.chain(g, g1, g2)
    }

    /// `x^p` for real `p` (`x > 0`, else NaN parts as in `powf`).
    pub fn powf(self, p: T) -> Self {
        let g = self.v.powf_ia(p);
        let g1 = p * self.v.powf_ia(p - T::ONE);
        let g2 = p * (p - T::ONE) * self.v.powf_ia(p - T::TWO);
        self.chain(g, g1, g2)
    }

    /// `√x`.
    pub fn sqrt(self) -> Self {
        let g = self.v.sqrt();
        let g1 = T::HALF / g;
        let g2 = -g1 / (self.v + self.v);
        self.chain(g, g1, g2)
    }

    /// `1/x`.
    pub fn recip(self) -> Self {
        let g = T::ONE / self.v;
        let g1 = -g * g;
        let g2 = -(g1 + g1) * g;
        self.chain(g, g1, g2)
    }

    /// `eˣ`.
    pub fn exp(self) -> Self {
        let g = self.v.exp_ia();
        self.chain(g, g, g)
    }

    /// `ln x`.
    pub fn ln(self) -> Self {
        let g1 = T::ONE / self.v;
        self.chain(self.v.ln_ia(), g1, -g1 * g1)
    }

    /// `sin x`.
    pub fn sin(self) -> Self {
        let (sv, cv) = (self.v.sin(), self.v.cos());
        self.chain(sv, cv, -sv)
    }

    /// `cos x`.
    pub fn cos(self) -> Self {
        let (sv, cv) = (self.v.sin(), self.v.cos());
        self.chain(cv, -sv, -cv)
    }

    /// `|x|` (the derivative's sign follows the sign bit of `x`, so
    /// `|−0| = +0` as in `f64::abs`).
    pub fn abs(self) -> Self {
        if self.v.is_sign_negative() {
            -self
        } else {
            self
        }
    }

    /// `min(f, g)` by value (a NaN operand is ignored, as in `f64::min`).
    pub fn min(self, other: Self) -> Self {
        if other.v < self.v || self.v.is_nan() {
            other
        } else {
            self
        }
    }

    /// `max(f, g)` by value (a NaN operand is ignored, as in `f64::max`).
    pub fn max(self, other: Self) -> Self {
        if other.v > self.v || self.v.is_nan() {
            other
        } else {
            self
        }
    }
}

impl<T: Real> Neg for Jet<T> {
    type Output = Self;
    /// Negates every part.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn neg(self) -> Self {
        Self::new(-self.v, -self.d1, -self.d2)
    }
}

impl<T: Real> Add for Jet<T> {
    type Output = Self;
    /// Part-wise sum.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn add(self, r: Self) -> Self {
        Self::new(self.v + r.v, self.d1 + r.d1, self.d2 + r.d2)
    }
}

impl<T: Real> Sub for Jet<T> {
    type Output = Self;
    /// Part-wise difference.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn sub(self, r: Self) -> Self {
        Self::new(self.v - r.v, self.d1 - r.d1, self.d2 - r.d2)
    }
}

impl<T: Real> Mul for Jet<T> {
    type Output = Self;
    /// Leibniz rule: `(fg)'' = f''g + 2f'g' + fg''`.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn mul(self, r: Self) -> Self {
        Self::new(
            self.v * r.v,
            self.d1 * r.v + self.v * r.d1,
            self.d2 * r.v + (self.d1 * r.d1) * T::TWO + self.v * r.d2,
        )
    }
}

impl<T: Real> Div for Jet<T> {
    type Output = Self;
    /// Quotient rule: `q = f/g`, `q' = (f' − q g')/g`,
    /// `q'' = (f'' − 2q'g' − q g'')/g` (the value is the plain quotient).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn div(self, r: Self) -> Self {
        let q = self.v / r.v;
        let q1 = (self.d1 - q * r.d1) / r.v;
        let q2 = (self.d2 - (q1 * r.d1) * T::TWO - q * r.d2) / r.v;
        Self::new(q, q1, q2)
    }
}

impl<T: Real> Add<T> for Jet<T> {
    type Output = Self;
    /// Adds to the value.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn add(self, c: T) -> Self {
        Self::new(self.v + c, self.d1, self.d2)
    }
}

impl<T: Real> Sub<T> for Jet<T> {
    type Output = Self;
    /// Subtracts from the value.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn sub(self, c: T) -> Self {
        Self::new(self.v - c, self.d1, self.d2)
    }
}

impl<T: Real> Mul<T> for Jet<T> {
    type Output = Self;
    /// Scales every part.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn mul(self, c: T) -> Self {
        Self::new(self.v * c, self.d1 * c, self.d2 * c)
    }
}

impl<T: Real> Div<T> for Jet<T> {
    type Output = Self;
    /// Divides every part.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn div(self, c: T) -> Self {
        Self::new(self.v / c, self.d1 / c, self.d2 / c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn chain_rule_matches_closed_form() {
        // f(t) = exp(−t²)·√(1 + t) / (2 + t)
        let x = 0.7f64;
        let t = Jet::variable(x);
        let f = (-(t.sqr())).exp() * (t + 1.0).sqrt() / (t + 2.0);
        let g = |t: f64| (-t * t).exp() * (1.0 + t).sqrt() / (2.0 + t);
        let e = 1e-4;
        let d1 = (g(x + e) - g(x - e)) / (2.0 * e);
        let d2 = (g(x + e) - 2.0 * g(x) + g(x - e)) / (e * e);
        assert_relative_eq!(f.v, g(x), max_relative = 1e-14);
        assert_relative_eq!(f.d1, d1, max_relative = 1e-6);
        assert_relative_eq!(f.d2, d2, max_relative = 1e-4);
        let p = t.powi(-3);
        assert_relative_eq!(p.d2, 12.0 * x.powi(-5), max_relative = 1e-12);
        let q = t.powf(2.5) + t.ln();
        assert_relative_eq!(q.d1, 2.5 * x.powf(1.5) + 1.0 / x, max_relative = 1e-12);
    }
}
