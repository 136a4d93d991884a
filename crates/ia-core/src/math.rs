//! The one place where transcendental functions are called.
//!
//! `std` or `libm` is chosen here, once: with the `libm` feature the `libm`
//! crate is used (also when `std` is on, for the same results on every
//! platform); otherwise the standard library's float methods. Nothing else in
//! the crate calls `exp`, `ln`, `sin`, `cos`, `powf` or `sqrt` directly.
//!
//! Both back ends document an error below 1 ulp for every function used here
//! (musl-derived `libm`; glibc's and the platform libraries behind `std`), and
//! `sqrt` is correctly rounded (IEEE 754). The interval and affine code widens
//! results by [`TRANSCENDENTAL_ULPS`] resp. [`SQRT_ULPS`] float steps outward.

/// Float steps an `exp`, `ln`, `sin`, `cos` or `pow` result is widened by.
///
/// An error below 1 ulp of the exact result is at most two float steps of the
/// returned value (the step halves just below a power of two).
#[cfg(not(target_arch = "spirv"))]
pub(crate) const TRANSCENDENTAL_ULPS: u32 = 2;
/// Float steps an `exp`, `ln`, `sin`, `cos` or `pow` result is widened by.
///
/// On SPIR-V the `libm` code runs on the device's arithmetic, whose division
/// is only accurate to 2.5 ulp (Vulkan precision table), so the margin is wider.
#[cfg(target_arch = "spirv")]
pub(crate) const TRANSCENDENTAL_ULPS: u32 = 8;

/// Float steps a `sqrt` result is widened by (correctly rounded on CPUs).
#[cfg(not(target_arch = "spirv"))]
pub(crate) const SQRT_ULPS: u32 = 1;
/// Float steps a `sqrt` result is widened by (Vulkan allows `sqrt` as
/// `1/inversesqrt`, a few ulp).
#[cfg(target_arch = "spirv")]
pub(crate) const SQRT_ULPS: u32 = 4;

/// Float steps a quotient is widened by (correctly rounded on CPUs).
#[cfg(not(target_arch = "spirv"))]
pub(crate) const DIV_ULPS: u32 = 1;
/// Float steps a quotient is widened by (Vulkan: 2.5 ulp).
#[cfg(target_arch = "spirv")]
pub(crate) const DIV_ULPS: u32 = 3;

/// Transcendental functions of a float type, selected by feature once.
///
/// Sealed: only `f32` and `f64` implement it (it is a supertrait of
/// [`Real`](crate::Real) but cannot be named outside the crate).
pub trait Math: Copy {
    /// `e^self`, error < 1 ulp.
    fn m_exp(self) -> Self;
    /// Natural logarithm, error < 1 ulp.
    fn m_ln(self) -> Self;
    /// Sine, error < 1 ulp (full argument reduction).
    fn m_sin(self) -> Self;
    /// Cosine, error < 1 ulp (full argument reduction).
    fn m_cos(self) -> Self;
    /// `self^p`, error < 1 ulp.
    fn m_pow(self, p: Self) -> Self;
    /// Square root, correctly rounded.
    fn m_sqrt(self) -> Self;
}

macro_rules! impl_math {
    ($t:ty, $exp:ident, $ln:ident, $sin:ident, $cos:ident, $pow:ident, $sqrt:ident) => {
        #[cfg(feature = "libm")]
        impl Math for $t {
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn m_exp(self) -> Self {
                libm::$exp(self)
            }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn m_ln(self) -> Self {
                libm::$ln(self)
            }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn m_sin(self) -> Self {
                libm::$sin(self)
            }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn m_cos(self) -> Self {
                libm::$cos(self)
            }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn m_pow(self, p: Self) -> Self {
                libm::$pow(self, p)
            }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn m_sqrt(self) -> Self {
                libm::$sqrt(self)
            }
        }

        #[cfg(all(feature = "std", not(feature = "libm")))]
        impl Math for $t {
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn m_exp(self) -> Self {
                <$t>::exp(self)
            }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn m_ln(self) -> Self {
                <$t>::ln(self)
            }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn m_sin(self) -> Self {
                <$t>::sin(self)
            }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn m_cos(self) -> Self {
                <$t>::cos(self)
            }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn m_pow(self, p: Self) -> Self {
                <$t>::powf(self, p)
            }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn m_sqrt(self) -> Self {
                <$t>::sqrt(self)
            }
        }
    };
}

impl_math!(f32, expf, logf, sinf, cosf, powf, sqrtf);
impl_math!(f64, exp, log, sin, cos, pow, sqrt);
