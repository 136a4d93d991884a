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
/// On SPIR-V the margin is wider, but **not proven sound on every
/// driver**: rust-gpu 0.11 replaces the calls to `libm`'s `expf`, `logf`,
/// `sinf`, `cosf`, `powf` (and their `f64` forms) with GLSL.std.450
/// instructions (`rustc_codegen_spirv`'s libm intrinsics), whose Vulkan
/// precision is coarser than 8 steps in places: `Exp` 3 + 2·|x| ulp, `Log`
/// 3 ulp or 2⁻²¹ absolute, `Sin`/`Cos` 2⁻¹¹ absolute on [−π, π], `Pow`
/// inherited from `exp2(y·log2 x)`. The blob scenes the GPU traces today
/// use compact polynomial kernels (no transcendental function in their
/// bounds); a Gaussian kernel's `exp` on the GPU is an open soundness gap
/// (issue 9, BENCHMARKS.md "GPU", session 11).
#[cfg(target_arch = "spirv")]
pub(crate) const TRANSCENDENTAL_ULPS: u32 = 8;

/// Float steps a `sqrt` result is widened by: it is correctly rounded on
/// CPUs (IEEE 754). On SPIR-V rust-gpu 0.11 replaces `libm`'s
/// `sqrtf`/`sqrt` with the driver's GLSL.std.450 `Sqrt`, whose Vulkan
/// precision is only inherited from `1 / inversesqrt(x)` (a few ulp): one
/// step is sound where the driver's square root is correctly rounded, as
/// on lavapipe (`boundtrace-gpu`'s `outward_probe` checks the bounds
/// against exact results), and an open soundness gap on other drivers
/// (issue 9).
pub(crate) const SQRT_ULPS: u32 = 1;

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
    /// Float steps a quotient [`m_div`](Self::m_div) is widened by.
    const DIV_STEPS: u32;
    /// `self / d`, correctly rounded where [`DIV_STEPS`](Self::DIV_STEPS)
    /// is `1`.
    ///
    /// On CPUs the division itself (IEEE 754). On SPIR-V, Vulkan only
    /// requires `÷` to 2.5 ulp: an `f32` quotient is computed in `f64` and
    /// rounded once to `f32`, which gives the correctly rounded `f32`
    /// quotient (a quotient of two 24-bit floats lies at least `2⁻⁴⁹`
    /// relatively from the midpoint of two `f32`s, far more than the
    /// `f64` division's 2.5 ulp of `2⁻⁵³`; the `f64` → `f32` conversion is
    /// correctly rounded), so the GPU's quotients equal the CPU's; an `f64`
    /// quotient keeps the device's division, widened by 3 steps.
    fn m_div(self, d: Self) -> Self;
}

macro_rules! impl_math {
    ($t:ty, $exp:ident, $ln:ident, $sin:ident, $cos:ident, $pow:ident, $sqrt:ident, $div:ident, $steps:ident) => {
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
            const DIV_STEPS: u32 = $steps;
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn m_div(self, d: Self) -> Self {
                $div(self, d)
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
            const DIV_STEPS: u32 = $steps;
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn m_div(self, d: Self) -> Self {
                $div(self, d)
            }
        }
    };
}

impl_math!(
    f32,
    expf,
    logf,
    sinf,
    cosf,
    powf,
    sqrtf,
    f32_div,
    F32_DIV_STEPS
);
impl_math!(f64, exp, log, sin, cos, pow, sqrt, f64_div, F64_DIV_STEPS);

/// [`Math::DIV_STEPS`] of `f32`: correctly rounded everywhere.
const F32_DIV_STEPS: u32 = 1;

/// [`Math::DIV_STEPS`] of `f64`: correctly rounded on CPUs.
#[cfg(not(target_arch = "spirv"))]
const F64_DIV_STEPS: u32 = 1;
/// [`Math::DIV_STEPS`] of `f64`: Vulkan's 2.5 ulp on SPIR-V.
#[cfg(target_arch = "spirv")]
const F64_DIV_STEPS: u32 = 3;

/// [`Math::m_div`] of `f32`.
#[cfg_attr(not(target_arch = "spirv"), inline)]
fn f32_div(n: f32, d: f32) -> f32 {
    #[cfg(not(target_arch = "spirv"))]
    {
        n / d
    }
    #[cfg(target_arch = "spirv")]
    {
        ((n as f64) / (d as f64)) as f32
    }
}

/// [`Math::m_div`] of `f64`.
#[cfg_attr(not(target_arch = "spirv"), inline)]
fn f64_div(n: f64, d: f64) -> f64 {
    n / d
}
