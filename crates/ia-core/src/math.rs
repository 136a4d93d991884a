//! The one place where transcendental functions are called.
//!
//! `std` or `libm` is chosen here, once: with the `libm` feature the `libm`
//! crate is used (also when `std` is on, for the same results on every
//! platform); otherwise the standard library's float methods. Nothing else in
//! the crate calls `exp`, `ln`, `sin`, `cos`, `powf` or `sqrt` directly.
//!
//! Both back ends document an error below 1 ulp for every function used here
//! (musl-derived `libm`; glibc's and the platform libraries behind `std`), and
//! `sqrt` is correctly rounded (IEEE 754). The `f32` `exp`, `ln` and `pow`
//! are `ia-core`'s own on every target ([`exp_f32`], [`ln_f32`],
//! [`pow_f32`]: the GPU computes the same bits as the CPU), and on SPIR-V so
//! are the other `f32` functions (the driver's instructions are not precise
//! enough). The
//! interval code widens results by [`Math::TRANSCENDENTAL_STEPS`] resp.
//! [`SQRT_ULPS`] float steps outward.

/// Float steps an `f64` `exp`, `ln`, `sin`, `cos` or `pow` result is
/// widened by ([`Math::TRANSCENDENTAL_STEPS`] of `f64`; `f32`:
/// [`F32_TRANSCENDENTAL_STEPS`]).
///
/// An error below 1 ulp of the exact result is at most two float steps of the
/// returned value (the step halves just below a power of two).
#[cfg(not(target_arch = "spirv"))]
pub(crate) const TRANSCENDENTAL_ULPS: u32 = 2;
/// Float steps an `f64` `exp`, `ln`, `sin`, `cos` or `pow` result is
/// widened by on SPIR-V ([`Math::TRANSCENDENTAL_STEPS`] of `f64`).
///
/// There the `f64` functions are the driver's GLSL.std.450 instructions
/// (rust-gpu 0.11 replaces `libm`'s calls with them), whose Vulkan
/// precision is coarser than 8 steps in places (`Exp` 3 + 2·|x| ulp,
/// `Log` 3 ulp or 2⁻²¹ absolute, `Sin`/`Cos` 2⁻¹¹ absolute on [−π, π],
/// `Pow` what `exp2(y·log2 x)` gives): **not proven sound on every
/// driver**. The GPU tracer computes in `f32`, whose functions are
/// `ia-core`'s own on SPIR-V ([`exp_f32`], [`ln_f32`], [`pow_f32`] for
/// `x > 0`, [`sin_f32`] and [`cos_f32`] for `|x| < 2²⁸`, beyond which
/// `Interval::sin`/`cos` give `[−1, 1]`), within one step on any driver
/// with IEEE `f64` `+`, `×` (and a quotient within a few ulp).
#[cfg(target_arch = "spirv")]
pub(crate) const TRANSCENDENTAL_ULPS: u32 = 8;

/// [`Math::TRANSCENDENTAL_STEPS`] of `f32`: 2 on every target. On CPUs
/// `exp`, `ln` and `pow` are [`exp_f32`], [`ln_f32`] and [`pow_f32`] (the
/// GPU's own, within one step, so that both compute the same bounds and
/// field values bit for bit) and `sin`, `cos` the platform's or `libm`'s
/// (< 1 ulp); on SPIR-V all five are `ia-core`'s
/// own, within one step ([`exp_f32`], [`ln_f32`], [`sin_f32`],
/// [`cos_f32`], [`pow_f32`]). An error below one step of the exact result
/// is within two steps of the returned value.
const F32_TRANSCENDENTAL_STEPS: u32 = 2;

/// Float steps a `sqrt` result is widened by: it is correctly rounded on
/// CPUs (IEEE 754), and for `f32` on SPIR-V too: there [`sqrt_f32`]
/// rounds a refined `f64` root itself instead of trusting the driver's
/// `f32` `Sqrt` (whose Vulkan precision is only inherited from
/// `1 / inversesqrt(x)`; NVIDIA's driver 580 was measured up to 0.92 ulp
/// off). `boundtrace-gpu`'s `outward_probe` test checks the bounds
/// against exact results on the driver in use. An `f64` square root on
/// SPIR-V is still the driver's GLSL.std.450 `Sqrt` (rust-gpu 0.11
/// replaces `libm::sqrt` with it): one step is unproven there; the GPU
/// tracer computes in `f32`.
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
    /// Float steps an `exp`, `ln`, `sin`, `cos` or `pow` result is
    /// widened by: [`TRANSCENDENTAL_ULPS`] for `f64`, and 2 for `f32`
    /// everywhere ([`F32_TRANSCENDENTAL_STEPS`]).
    const TRANSCENDENTAL_STEPS: u32;
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
    ($t:ty, $exp_cpu:path, $exp_std:path, $exp_spirv:path, $ln:path, $ln_std:path, $ln_spirv:path, $sin:ident, $sin_spirv:path, $cos:ident, $cos_spirv:path, $pow:path, $pow_std:path, $pow_spirv:path, $sqrt:ident, $sqrt_spirv:path, $div:ident, $steps:ident, $tsteps:ident) => {
        #[cfg(feature = "libm")]
        impl Math for $t {
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn m_exp(self) -> Self {
                #[cfg(target_arch = "spirv")]
                {
                    $exp_spirv(self)
                }
                #[cfg(not(target_arch = "spirv"))]
                {
                    $exp_cpu(self)
                }
            }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn m_ln(self) -> Self {
                #[cfg(target_arch = "spirv")]
                {
                    $ln_spirv(self)
                }
                #[cfg(not(target_arch = "spirv"))]
                {
                    $ln(self)
                }
            }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn m_sin(self) -> Self {
                #[cfg(target_arch = "spirv")]
                {
                    $sin_spirv(self)
                }
                #[cfg(not(target_arch = "spirv"))]
                {
                    libm::$sin(self)
                }
            }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn m_cos(self) -> Self {
                #[cfg(target_arch = "spirv")]
                {
                    $cos_spirv(self)
                }
                #[cfg(not(target_arch = "spirv"))]
                {
                    libm::$cos(self)
                }
            }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn m_pow(self, p: Self) -> Self {
                #[cfg(target_arch = "spirv")]
                {
                    $pow_spirv(self, p)
                }
                #[cfg(not(target_arch = "spirv"))]
                {
                    $pow(self, p)
                }
            }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn m_sqrt(self) -> Self {
                #[cfg(target_arch = "spirv")]
                {
                    $sqrt_spirv(self)
                }
                #[cfg(not(target_arch = "spirv"))]
                {
                    libm::$sqrt(self)
                }
            }
            const DIV_STEPS: u32 = $steps;
            const TRANSCENDENTAL_STEPS: u32 = $tsteps;
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn m_div(self, d: Self) -> Self {
                $div(self, d)
            }
        }

        #[cfg(all(feature = "std", not(feature = "libm")))]
        impl Math for $t {
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn m_exp(self) -> Self {
                $exp_std(self)
            }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn m_ln(self) -> Self {
                $ln_std(self)
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
                $pow_std(self, p)
            }
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn m_sqrt(self) -> Self {
                <$t>::sqrt(self)
            }
            const DIV_STEPS: u32 = $steps;
            const TRANSCENDENTAL_STEPS: u32 = $tsteps;
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn m_div(self, d: Self) -> Self {
                $div(self, d)
            }
        }
    };
}

impl_math!(
    f32,
    exp_f32,
    exp_f32,
    exp_f32,
    ln_f32,
    ln_f32,
    ln_f32,
    sinf,
    sin_f32,
    cosf,
    cos_f32,
    pow_f32,
    pow_f32,
    pow_f32,
    sqrtf,
    sqrt_f32,
    f32_div,
    F32_DIV_STEPS,
    F32_TRANSCENDENTAL_STEPS
);
impl_math!(
    f64,
    libm::exp,
    f64::exp,
    libm::exp,
    libm::log,
    f64::ln,
    libm::log,
    sin,
    libm::sin,
    cos,
    libm::cos,
    libm::pow,
    f64::powf,
    libm::pow,
    sqrt,
    libm::sqrt,
    f64_div,
    F64_DIV_STEPS,
    TRANSCENDENTAL_ULPS
);

/// The correctly rounded square root of an `f32`, computed in `f64`: what
/// [`Math::m_sqrt`] of `f32` is on SPIR-V.
///
/// rust-gpu 0.11 replaces `libm`'s `sqrtf` with the driver's GLSL.std.450
/// `Sqrt`, whose Vulkan precision is only inherited from
/// `1 / inversesqrt(x)` (NVIDIA's driver 580 was measured up to 0.92 ulp
/// off, BENCHMARKS.md "GPU", session 12). So the GPU rounds the root
/// itself, the same on every driver as on the CPU ([`sqrt_f32_from`]):
/// the driver's `f32` `Sqrt` (`libm::sqrtf`, Vulkan: a few ulp) as an
/// estimate, one Newton step in `f64`, then an exact correction to the
/// nearest `f32`. On the CPU `sqrtf` is already correctly rounded, so this
/// changes nothing there (the tests run it on the CPU).
#[cfg_attr(not(target_arch = "spirv"), allow(dead_code))]
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn sqrt_f32(x: f32) -> f32 {
    #[cfg(feature = "libm")]
    let estimate = libm::sqrtf(x);
    #[cfg(not(feature = "libm"))]
    let estimate = x.sqrt();
    sqrt_f32_from(x, estimate as f64)
}

/// The `f32` nearest to `√x` from an estimate `y` of it in `f64`, for any
/// estimate within a relative `2⁻¹²` of the root (about 2,000 `f32` steps;
/// Vulkan's `f32` `Sqrt` is within a few):
///
/// 1. one Newton step `y ← (y + x/y)/2` squares the relative error (below
///    `2⁻²⁵`, a quarter of an `f32` step), so `y` rounded to `f32` is the
///    rounded root or one of its neighbours;
/// 2. the correction: `s` is the rounded root exactly when the midpoints
///    `m±` between `s` and its neighbours bracket the root, `m₋² < x <
///    m₊²`. A midpoint of two `f32`s has 25 significant bits, its square
///    50, so the squares are exact in `f64` and the tests are exact (a
///    midpoint's square is never an `f32`: no ties). One step each way.
///
/// **No branches and no loops**: the choices are made by integer
/// arithmetic on the bits, so each of the ~160 inlined copies in a shader
/// stays one basic block (and llvmpipe counts loop iterations against a
/// budget). Exactness assumes correctly rounded `f64` `+`, `×` and `÷` and
/// conversions, as IEEE 754 and the drivers we know give (the quotient
/// [`Math::m_div`] relies on the same). `x` of `±0`, `+∞`, NaN or a
/// negative `x`, or an estimate that is not positive and finite, gives
/// `y` rounded to `f32` (the IEEE result when `y` is the IEEE root). A
/// driver that flushes subnormal `f32`s to zero (Vulkan allows it) makes
/// the root of a subnormal `x` zero: that case is not covered. Tested
/// against the correctly rounded root on the CPU; on the GPU by
/// `boundtrace-gpu`'s `outward_probe` test.
#[cfg_attr(not(target_arch = "spirv"), allow(dead_code))]
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn sqrt_f32_from(x: f32, y: f64) -> f32 {
    let xd = x as f64;
    // `&`, not `&&`: no branch
    let ok = (x > 0.0) & (x < f32::INFINITY) & (y > 0.0) & (y < f64::INFINITY);
    let refined = 0.5 * (y + xd / y);
    // `refined` where `ok`, else `y`
    let s = select_f32(ok, refined as f32, y as f32);
    correct_root(x, ok, s)
}

/// `a` where `c`, else `b`, selected on the bits: rust-gpu compiles an
/// `if` into a branch (a basic block per inlined copy).
#[cfg_attr(not(target_arch = "spirv"), allow(dead_code))]
#[cfg_attr(not(target_arch = "spirv"), inline)]
fn select_f32(c: bool, a: f32, b: f32) -> f32 {
    let mask = 0u32.wrapping_sub(u32::from(c));
    f32::from_bits((a.to_bits() & mask) | (b.to_bits() & !mask))
}

/// `s` (within one `f32` step of `√x`) moved to the `f32` nearest to `√x`
/// when `ok` (`x` positive and finite), by the exact midpoint tests of
/// [`sqrt_f32_from`]; `s` itself otherwise.
#[cfg_attr(not(target_arch = "spirv"), allow(dead_code))]
#[cfg_attr(not(target_arch = "spirv"), inline)]
fn correct_root(x: f32, ok: bool, s: f32) -> f32 {
    let xd = x as f64;
    let bits = s.to_bits();
    let sd = s as f64;
    // For a positive finite `s` (where `ok`), `bits ± 1` are its neighbours.
    let up = f32::from_bits(bits.wrapping_add(1)) as f64;
    let down = f32::from_bits(bits.wrapping_sub(1)) as f64;
    let m_up = (sd + up) * 0.5;
    let m_down = (sd + down) * 0.5;
    let inc = (ok & (m_up * m_up < xd)) as u32;
    let dec = (ok & (m_down * m_down > xd)) as u32;
    f32::from_bits(bits.wrapping_add(inc).wrapping_sub(dec))
}

/// `e^x` of an `f32` within one `f32` step of the exact value, computed
/// with `f64` `+`, `×` and conversions only: what [`Math::m_exp`] of `f32`
/// is on SPIR-V.
///
/// rust-gpu 0.11 replaces `libm`'s `expf` with the driver's GLSL.std.450
/// `Exp`, which Vulkan only requires to `3 + 2·|x|` ulp (far beyond
/// [`TRANSCENDENTAL_ULPS`] for `|x| > 2`), so the GPU computes it itself:
///
/// 1. `x` is clamped to `[−110, 100]` (beyond, the `f32` result is `0` or
///    `+∞` either way) and reduced, `x = k·ln 2 + r` with
///    `k = ⌊x·log₂e + ½⌋` (by a truncating conversion of a positive value:
///    no rounding-mode or `floor` dependence) and `r = (x − k·ln2_hi) −
///    k·ln2_lo` (`ln2_hi` has 32 significant bits, so `k·ln2_hi` is exact),
///    `|r| ≤ 0.3466`;
/// 2. `e^r` by its degree-11 Taylor polynomial in Horner form: truncation
///    below `9·10⁻¹⁵` relative, rounding a few `f64` ulps;
/// 3. the scaling by `2^k` as two exact `f32` powers of two (`|k| ≤ 160`
///    does not fit one `f32` exponent), multiplied in `f64` (exact), then
///    one rounding to `f32`.
///
/// So the result is the exact `e^x` with a relative error below `10⁻¹⁴`,
/// rounded once to `f32`: within one `f32` step of `e^x` (correctly rounded
/// except within `10⁻¹⁴` of a midpoint), `+∞` from `x ≈ 88.7228` up, `0`
/// below about `−103.97`, NaN for NaN. **No branches and no loops**
/// (choices by integer arithmetic on the bits, as in [`sqrt_f32_from`]).
/// Assumes correctly rounded `f64` `+`, `×` and conversions (IEEE 754,
/// Vulkan); a driver flushing subnormal `f32`s to zero flushes results
/// below `2⁻¹²⁶` (not covered). Tested against `f64` `exp` on the CPU.
#[cfg_attr(not(target_arch = "spirv"), allow(dead_code))]
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn exp_f32(x: f32) -> f32 {
    // clamped by bit selects; NaN compares false and stays NaN (replaced
    // by `x` at the end)
    let c = select_f32(x > 100.0, 100.0, select_f32(x < -110.0, -110.0, x)) as f64;
    let y = exp_to_f32(c);
    select_f32(x.is_nan(), x, y)
}

/// `e^c` rounded once to `f32`, for `c ∈ [−110, 100]` (steps 1–3 of
/// [`exp_f32`]; a NaN `c` gives some number): within one `f32` step of the
/// exact `e^c` (relative error below `10⁻¹⁴` before the rounding).
#[cfg_attr(not(target_arch = "spirv"), allow(dead_code))]
#[cfg_attr(not(target_arch = "spirv"), inline)]
fn exp_to_f32(c: f64) -> f32 {
    // k = ⌊c·log₂e + ½⌋: the argument is ≥ 200.5 − 158.7 > 0, so the
    // truncating conversion is the floor (a NaN converts to some integer:
    // its result is replaced below)
    let k = (c * core::f64::consts::LOG2_E + 200.5) as i32 - 200;
    let kd = k as f64;
    let r = (c - kd * LN2_HI) - kd * LN2_LO;
    // e^r, Taylor to degree 11
    let mut p = 1.0 / 39_916_800.0;
    p = p * r + 1.0 / 3_628_800.0;
    p = p * r + 1.0 / 362_880.0;
    p = p * r + 1.0 / 40_320.0;
    p = p * r + 1.0 / 5_040.0;
    p = p * r + 1.0 / 720.0;
    p = p * r + 1.0 / 120.0;
    p = p * r + 1.0 / 24.0;
    p = p * r + 1.0 / 6.0;
    p = p * r + 0.5;
    p = p * r + 1.0;
    p = p * r + 1.0;
    // 2^k = 2^k1 · 2^k2, both within f32's normal exponents
    let k1 = k / 2;
    let k2 = k - k1;
    let pow2 = |e: i32| f32::from_bits(((e + 127) as u32) << 23) as f64;
    (p * pow2(k1) * pow2(k2)) as f32
}

/// `ln 2` to 32 significant bits (fdlibm's `ln2_hi`, low 21 bits of the
/// significand zero): `k·ln2_hi` is exact for `|k| < 2²¹`.
const LN2_HI: f64 = f64::from_bits(0x3FE6_2E42_FEE0_0000);
/// `ln 2 − ln2_hi` (fdlibm's `ln2_lo`).
const LN2_LO: f64 = f64::from_bits(0x3DEA_39EF_3579_3C76);

/// `a` where `c`, else `b` (`f64`), selected on the bits as
/// [`select_f32`].
#[cfg_attr(not(target_arch = "spirv"), allow(dead_code))]
#[cfg_attr(not(target_arch = "spirv"), inline)]
fn select_f64(c: bool, a: f64, b: f64) -> f64 {
    let mask = 0u64.wrapping_sub(u64::from(c));
    f64::from_bits((a.to_bits() & mask) | (b.to_bits() & !mask))
}

/// `ln x` in `f64` for a positive finite `f32` `x` (subnormals included),
/// with a relative error of a few `10⁻¹⁶` (any other `x` gives some
/// number): `x = 2^e·m`, `m ∈ [√½, √2)` from the bits (subnormals scaled
/// by `2²⁴` first, exactly), `ln m = 2 atanh s`, `s = (m − 1)/(m + 1)`,
/// `|s| ≤ 0.1716`, by its odd series to `s²¹` (truncation below
/// `10⁻¹⁸` relative), and `e·ln 2` with `ln2_hi` exact in the product.
/// No cancellation: `|ln m| ≤ 0.347 < ln 2 ≤ |e·ln 2|` when `e ≠ 0`.
/// Assumes correctly rounded `f64` `+`, `×` and a quotient within a few
/// ulp (Vulkan: 2.5 ulp). No branches and no loops.
#[cfg_attr(not(target_arch = "spirv"), allow(dead_code))]
#[cfg_attr(not(target_arch = "spirv"), inline)]
fn ln_f64_of_f32(x: f32) -> f64 {
    let sub = x < f32::MIN_POSITIVE;
    let xs = select_f32(sub, x * 16_777_216.0, x);
    let bits = xs.to_bits();
    let e = ((bits >> 23) & 0xFF) as i32 - 127 - 24 * i32::from(sub);
    // m ∈ [1, 2), halved (exactly) above √2
    let m = f32::from_bits((bits & 0x007F_FFFF) | 0x3F80_0000) as f64;
    let big = m > core::f64::consts::SQRT_2;
    let m = select_f64(big, m * 0.5, m);
    let e = e + i32::from(big);
    let s = (m - 1.0) / (m + 1.0);
    let s2 = s * s;
    let mut q = 1.0 / 21.0;
    q = q * s2 + 1.0 / 19.0;
    q = q * s2 + 1.0 / 17.0;
    q = q * s2 + 1.0 / 15.0;
    q = q * s2 + 1.0 / 13.0;
    q = q * s2 + 1.0 / 11.0;
    q = q * s2 + 1.0 / 9.0;
    q = q * s2 + 1.0 / 7.0;
    q = q * s2 + 1.0 / 5.0;
    q = q * s2 + 1.0 / 3.0;
    q = q * s2 + 1.0;
    let ln_m = 2.0 * s * q;
    let ed = e as f64;
    ed * LN2_HI + (ed * LN2_LO + ln_m)
}

/// `π/2` in three parts: 24 significant bits, the next 24 bits, and the
/// rest rounded to `f64` (`k·P1` and `k·P2` are exact for `|k| < 2²⁹`;
/// the parts sum to `π/2` within `10⁻³¹`).
const PIO2_1: f64 = f64::from_bits(0x3FF9_21FB_4000_0000);
/// See [`PIO2_1`].
const PIO2_2: f64 = f64::from_bits(0x3E74_442D_0000_0000);
/// See [`PIO2_1`].
const PIO2_3: f64 = f64::from_bits(0x3CF8_4698_98CC_5170);

/// The largest `|x|` whose sine and cosine [`sin_f32`]/[`cos_f32`]
/// compute (`2²⁸`); beyond, they answer NaN and the interval code takes
/// `[−1, 1]`.
const TRIG_LIMIT: f32 = 268_435_456.0;

/// `(sin r, cos r, k mod 4)` for `x = k·π/2 + r`, `|r| ≤ π/4` (plus a
/// rounding), of an `f32` `x` with `|x| < 2²⁸`, in `f64` (any other `x`
/// gives some numbers): `k = ⌊x·2/π + ½⌋` by a truncating conversion of a
/// positive value, `r = ((x − k·P1) − k·P2) − k·P3` (the first two
/// products and the first difference exact), then the Taylor polynomials
/// of `sin` to `r¹⁷` and `cos` to `r¹⁸` (truncation below `10⁻¹⁹`). The
/// relative error of `r` stays a few `10⁻¹⁶` even at the `f32`s closest to
/// a multiple of `π/2`: the exact parts leave only the last rounding and
/// `k·(π/2 − P1 − P2 − P3) < 10⁻²²`. No branches, no loops.
#[cfg_attr(not(target_arch = "spirv"), allow(dead_code))]
#[cfg_attr(not(target_arch = "spirv"), inline)]
fn sin_cos_f64_of_f32(x: f32) -> (f64, f64, u32) {
    let xd = f64::from(select_f32(x.abs() < TRIG_LIMIT, x, 0.0));
    let k = (xd * core::f64::consts::FRAC_2_PI + 268_435_456.5) as i32 - 268_435_456;
    let kd = f64::from(k);
    let r = ((xd - kd * PIO2_1) - kd * PIO2_2) - kd * PIO2_3;
    let r2 = r * r;
    // sin r = r·(1 − r²/3! + … + r¹⁶/17!), cos r = 1 − r²/2! + … + r¹⁸/18!
    let mut ps = 1.0 / 355_687_428_096_000.0;
    ps = ps * r2 - 1.0 / 1_307_674_368_000.0;
    ps = ps * r2 + 1.0 / 6_227_020_800.0;
    ps = ps * r2 - 1.0 / 39_916_800.0;
    ps = ps * r2 + 1.0 / 362_880.0;
    ps = ps * r2 - 1.0 / 5_040.0;
    ps = ps * r2 + 1.0 / 120.0;
    ps = ps * r2 - 1.0 / 6.0;
    ps = ps * r2 + 1.0;
    let mut pc = -1.0 / 6_402_373_705_728_000.0;
    pc = pc * r2 + 1.0 / 20_922_789_888_000.0;
    pc = pc * r2 - 1.0 / 87_178_291_200.0;
    pc = pc * r2 + 1.0 / 479_001_600.0;
    pc = pc * r2 - 1.0 / 3_628_800.0;
    pc = pc * r2 + 1.0 / 40_320.0;
    pc = pc * r2 - 1.0 / 720.0;
    pc = pc * r2 + 1.0 / 24.0;
    pc = pc * r2 - 0.5;
    pc = pc * r2 + 1.0;
    (r * ps, pc, (k & 3) as u32)
}

/// The sine of an `f32` without the driver's `Sin` (Vulkan: `2⁻¹¹`
/// absolute on `[−π, π]`, nothing outside): what [`Math::m_sin`] of `f32`
/// is on SPIR-V. [`sin_cos_f64_of_f32`] and the quadrant, rounded once:
/// within one `f32` step of `sin x` for `|x| < 2²⁸`; `sin(±0) = ±0`; NaN
/// for a larger `|x|`, an infinity or NaN (which `Interval::sin` answers
/// with `[−1, 1]`). No branches. Tested against `f64` `sin` on the CPU.
#[cfg_attr(not(target_arch = "spirv"), allow(dead_code))]
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn sin_f32(x: f32) -> f32 {
    let (s, c, q) = sin_cos_f64_of_f32(x);
    // q: 0 → s, 1 → c, 2 → −s, 3 → −c
    let v = select_f64(q & 1 == 1, c, s);
    let v = select_f64(q & 2 == 2, -v, v) as f32;
    select_f32(x.abs() < TRIG_LIMIT, v, f32::NAN)
}

/// The cosine of an `f32` without the driver's `Cos`: as [`sin_f32`]
/// (`cos(±0) = 1`).
#[cfg_attr(not(target_arch = "spirv"), allow(dead_code))]
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn cos_f32(x: f32) -> f32 {
    let (s, c, q) = sin_cos_f64_of_f32(x);
    // q: 0 → c, 1 → −s, 2 → −c, 3 → s
    let v = select_f64(q & 1 == 1, s, c);
    let v = select_f64(q == 1 || q == 2, -v, v) as f32;
    select_f32(x.abs() < TRIG_LIMIT, v, f32::NAN)
}

/// The natural logarithm of an `f32` without the driver's `Log`: what
/// [`Math::m_ln`] of `f32` is on SPIR-V (Vulkan requires `Log` only to
/// 3 ulp outside `[0.5, 2]` and to `2⁻²¹` absolute inside).
///
/// [`ln_f64_of_f32`] rounded once to `f32`: within one `f32` step of
/// `ln x` (correctly rounded except within `10⁻¹⁵` relative of a
/// midpoint); `ln 1 = 0`, `ln 0 = −∞`, `ln ∞ = ∞`, NaN for a negative `x`
/// or NaN. No branches. Tested against `f64` `ln` on the CPU.
#[cfg_attr(not(target_arch = "spirv"), allow(dead_code))]
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn ln_f32(x: f32) -> f32 {
    let y = ln_f64_of_f32(x) as f32;
    let y = select_f32(x == 0.0, f32::NEG_INFINITY, y);
    let y = select_f32(x == f32::INFINITY, x, y);
    select_f32(x >= 0.0, y, f32::NAN)
}

/// `x^p` of `f32`s without the driver's `Pow`: what [`Math::m_pow`] of
/// `f32` is on SPIR-V (Vulkan: inherited from `exp2(p·log2 x)`, no ulp
/// bound).
///
/// For a positive finite `x` and a finite `p` (what `Interval::powf` asks
/// for: `x ≥ 0`, with `0`, `1` and `∞` taken exactly there),
/// `e^{p·ln x}` in `f64`: [`ln_f64_of_f32`], the product (`|p·ln x|` is
/// clamped to `[−110, 100]`, beyond which the `f32` result is `0` resp.
/// `+∞` either way: the absolute error of the exponent stays below
/// `2·10⁻¹³`, a relative `2·10⁻¹³` of the result), and [`exp_to_f32`]:
/// within one `f32` step of `x^p`. Other arguments (`x ≤ 0`, infinities,
/// NaNs) keep `libm`'s `powf`, which rust-gpu makes the driver's `Pow`.
/// No branches. Tested against `f64` `powf` on the CPU.
#[cfg(any(feature = "std", feature = "libm"))]
#[cfg_attr(not(target_arch = "spirv"), allow(dead_code))]
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn pow_f32(x: f32, p: f32) -> f32 {
    let ok = x > 0.0 && x < f32::INFINITY && p.is_finite();
    let y = f64::from(p) * ln_f64_of_f32(x);
    let c = select_f64(y > 100.0, 100.0, select_f64(y < -110.0, -110.0, y));
    #[cfg(feature = "libm")]
    let other = libm::powf(x, p);
    #[cfg(all(feature = "std", not(feature = "libm")))]
    let other = f32::powf(x, p);
    select_f32(ok, exp_to_f32(c), other)
}

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Real;

    /// The correctly rounded `f32` square root: `f64`'s (IEEE) rounded to
    /// `f32`, which is exact for square roots (53 ≥ 2·24 + 2 bits).
    fn reference(x: f32) -> f32 {
        (x as f64).sqrt() as f32
    }

    /// `n` positive finite `f32`s over every binade (a fixed LCG).
    fn spread(n: usize) -> impl Iterator<Item = f32> {
        let mut state = 0x2545_F491_4F6C_DD1Du64;
        (0..n).map(move |_| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            // bits above +0, below +∞
            f32::from_bits(1 + ((state >> 33) as u32) % 0x7F7F_FFFF)
        })
    }

    const EDGES: [f32; 12] = [
        f32::MIN_POSITIVE,
        f32::from_bits(1),
        f32::from_bits(0x007F_FFFF),
        f32::MAX,
        1.0,
        2.0,
        4.0,
        16_777_215.0,
        16_777_216.0,
        0.1,
        1.0 - f32::EPSILON / 2.0,
        1.0 + f32::EPSILON,
    ];

    /// `exp_f32` is within one `f32` step of `e^x` (the `f64` `exp`,
    /// within `10⁻¹⁵` of it, lies strictly between its neighbours) on a
    /// million spread arguments, a fine sweep of `[−104, 89]` and the
    /// edges, and correctly rounded on nearly all of them.
    #[test]
    fn exp_f32_is_within_one_step() {
        // spread() covers every binade: most arguments are huge, so they
        // are folded into [-120, 120) (keeping their low bits)
        let spread_args = spread(1_000_000).map(|x| {
            let x = x % 240.0;
            if x < 120.0 { x } else { x - 240.0 }
        });
        let sweep = (0..=193_000).map(|i| -104.0 + i as f32 * 0.001);
        let edges = [
            0.0f32,
            -0.0,
            1.0,
            -1.0,
            88.722_83,
            88.722_84,
            88.8,
            -87.336_55,
            -103.97,
            -103.98,
            -104.0,
            -150.0,
            100.0,
            1e-8,
            -1e-8,
            f32::MIN_POSITIVE,
            0.5,
            0.346_57,
        ];
        let (mut checked, mut rounded) = (0u32, 0u32);
        for x in spread_args.chain(sweep).chain(edges) {
            let y = exp_f32(x);
            let e = f64::from(x).exp();
            if e > f64::from(f32::MAX) * (1.0 + 1e-7) {
                assert_eq!(y, f32::INFINITY, "{x}");
                continue;
            }
            assert!(
                f64::from(y.next_down_n(1)) < e && e < f64::from(y.next_up_n(1)),
                "exp({x}) = {y}, exact {e}"
            );
            checked += 1;
            rounded += u32::from(y == e as f32);
        }
        assert!(checked > 1_000_000);
        assert!(
            f64::from(rounded) >= 0.9999 * f64::from(checked),
            "{rounded}/{checked}"
        );
        assert!(exp_f32(f32::NAN).is_nan());
        assert_eq!(exp_f32(f32::INFINITY), f32::INFINITY);
        assert_eq!(exp_f32(f32::NEG_INFINITY), 0.0);
        assert_eq!(exp_f32(-200.0), 0.0);
        assert_eq!(exp_f32(0.0), 1.0);
    }

    /// Whether `y` lies within one `f32` step of the exact `e` (given in
    /// `f64`, itself within `10⁻¹⁵` relative of the exact value): `e`
    /// strictly between `y`'s neighbours.
    fn within_one_step(y: f32, e: f64) -> bool {
        f64::from(y.next_down_n(1)) < e && e < f64::from(y.next_up_n(1))
    }

    /// `ln_f32` is within one `f32` step of `ln x` (the `f64` `ln`) on a
    /// million spread positive `f32`s (every binade, subnormals
    /// included), a fine sweep around `1` and the edges, and correctly
    /// rounded on nearly all of them.
    #[test]
    fn ln_f32_is_within_one_step() {
        let sweep = (0..=200_000).map(|i| 0.5 + i as f32 * 1e-5);
        let (mut checked, mut rounded) = (0u32, 0u32);
        for x in spread(1_000_000).chain(sweep).chain(EDGES) {
            let y = ln_f32(x);
            let e = f64::from(x).ln();
            assert!(within_one_step(y, e), "ln({x:e}) = {y}, exact {e}");
            checked += 1;
            rounded += u32::from(y == e as f32);
        }
        assert!(
            f64::from(rounded) >= 0.9999 * f64::from(checked),
            "{rounded}/{checked}"
        );
        assert_eq!(ln_f32(1.0).to_bits(), 0.0f32.to_bits());
        assert_eq!(ln_f32(0.0), f32::NEG_INFINITY);
        assert_eq!(ln_f32(-0.0), f32::NEG_INFINITY);
        assert_eq!(ln_f32(f32::INFINITY), f32::INFINITY);
        assert!(ln_f32(-1.0).is_nan());
        assert!(ln_f32(f32::NEG_INFINITY).is_nan());
        assert!(ln_f32(f32::NAN).is_nan());
    }

    /// `sin_f32` and `cos_f32` are within one `f32` step of `sin x` and
    /// `cos x` (the `f64` functions, with `libm`'s full argument
    /// reduction) on a million spread arguments below `2²⁸` (every binade;
    /// both signs), a fine sweep of `[−20, 20]`, the `f32`s nearest to
    /// multiples of `π/2` (where the reduction cancels most) and the
    /// edges; correctly rounded on nearly all; NaN from `2²⁸` on.
    #[test]
    fn sin_f32_and_cos_f32_are_within_one_step() {
        let spread_args = spread(1_000_000).enumerate().map(|(i, x)| {
            let x = if x < TRIG_LIMIT { x } else { x % TRIG_LIMIT };
            if i % 2 == 0 { x } else { -x }
        });
        let sweep = (0..=400_000).map(|i| -20.0 + i as f32 * 1e-4);
        // the f32s around k·π/2 for k up to 10⁸
        let near = (1..2000u64).flat_map(|i| {
            let k = (i * i * 25) as f64;
            let x = (k * core::f64::consts::FRAC_PI_2) as f32;
            [x.next_down_n(1), x, x.next_up_n(1)]
        });
        let edges = [
            0.0f32,
            -0.0,
            1.0,
            -1.0,
            1e-30,
            f32::MIN_POSITIVE,
            core::f32::consts::FRAC_PI_2,
            core::f32::consts::PI,
            268_435_440.0,
        ];
        let (mut checked, mut rounded) = (0u32, 0u32);
        for x in spread_args.chain(sweep).chain(near).chain(edges) {
            for (y, e, name) in [
                (sin_f32(x), f64::from(x).sin(), "sin"),
                (cos_f32(x), f64::from(x).cos(), "cos"),
            ] {
                assert!(within_one_step(y, e), "{name}({x:e}) = {y:e}, exact {e:e}");
                checked += 1;
                rounded += u32::from(y == e as f32);
            }
        }
        assert!(
            f64::from(rounded) >= 0.9999 * f64::from(checked),
            "{rounded}/{checked}"
        );
        assert_eq!(sin_f32(-0.0).to_bits(), (-0.0f32).to_bits());
        assert_eq!(cos_f32(0.0), 1.0);
        for x in [TRIG_LIMIT, -TRIG_LIMIT, 1e30, f32::INFINITY, f32::NAN] {
            assert!(sin_f32(x).is_nan() && cos_f32(x).is_nan(), "{x}");
        }
    }

    /// `pow_f32` is within one `f32` step of `x^p` (the `f64` `powf`) for
    /// positive finite `x` and finite `p` whose result is finite and not
    /// subnormal, and takes `powf` for the other arguments.
    #[test]
    fn pow_f32_is_within_one_step() {
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut checked, mut rounded) = (0u32, 0u32);
        for _ in 0..500_000 {
            // x over 2^-40 .. 2^40, p over -12 .. 12
            let x = (2.0f64.powf(80.0 * next() - 40.0)) as f32;
            let p = (24.0 * next() - 12.0) as f32;
            let e = f64::from(x).powf(f64::from(p));
            let y = pow_f32(x, p);
            if e > f64::from(f32::MAX) {
                assert_eq!(y, f32::INFINITY, "{x}^{p}");
                continue;
            }
            if e < f64::from(f32::MIN_POSITIVE) {
                continue; // subnormal results: not covered below
            }
            assert!(within_one_step(y, e), "{x:e}^{p} = {y:e}, exact {e:e}");
            checked += 1;
            rounded += u32::from(y == e as f32);
        }
        assert!(checked > 250_000, "{checked}");
        assert!(
            f64::from(rounded) >= 0.9999 * f64::from(checked),
            "{rounded}/{checked}"
        );
        for (x, p) in [(2.0f32, 0.5f32), (10.0, -2.5), (1.0e-3, 1.7), (3.0, 80.5)] {
            let e = f64::from(x).powf(f64::from(p));
            assert!(within_one_step(pow_f32(x, p), e), "{x}^{p}");
        }
        // beyond f32's range: 0 and ∞, as the exact result rounds
        assert_eq!(pow_f32(1.0e-30, 5.5), 0.0);
        assert_eq!(pow_f32(1.0e30, 5.5), f32::INFINITY);
        assert_eq!(pow_f32(1.0, 0.5), 1.0);
        // the other arguments: `powf`'s
        for (x, p) in [
            (0.0f32, 0.5f32),
            (-2.0, 0.5),
            (f32::INFINITY, 0.5),
            (2.0, f32::NAN),
        ] {
            let (a, b) = (pow_f32(x, p), x.powf(p));
            assert!(
                a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()),
                "{x}^{p}"
            );
        }
    }

    #[test]
    fn sqrt_f32_is_correctly_rounded() {
        for x in EDGES.into_iter().chain(spread(1_000_000)) {
            assert_eq!(sqrt_f32(x).to_bits(), reference(x).to_bits(), "√{x:e}");
        }
        for r in [1.5f32, 3.0, 1234.5, 1.0e-20, 1.0e19] {
            assert_eq!(sqrt_f32(r * r), reference(r * r));
        }
        assert_eq!(sqrt_f32(0.0).to_bits(), 0.0f32.to_bits());
        assert_eq!(sqrt_f32(-0.0).to_bits(), (-0.0f32).to_bits());
        assert_eq!(sqrt_f32(f32::INFINITY), f32::INFINITY);
        assert!(sqrt_f32(f32::NAN).is_nan());
        assert!(sqrt_f32(-1.0).is_nan());
    }

    /// Every 97th `f32` of `[1, 4)`, a whole period of the exponent's
    /// parity.
    #[test]
    fn sqrt_f32_over_two_binades() {
        for bits in (1.0f32.to_bits()..4.0f32.to_bits()).step_by(97) {
            let x = f32::from_bits(bits);
            assert_eq!(sqrt_f32(x).to_bits(), reference(x).to_bits(), "√{x:e}");
        }
    }

    /// Estimates off by a relative `±2⁻¹²` and less (a driver's `Sqrt`
    /// with single precision only is within about `2⁻²¹`) still give the
    /// rounded root; `±2⁻⁸` does not on every value, so the test can fail.
    #[test]
    fn estimates_within_the_documented_error_are_corrected() {
        let rel = [
            0.0,
            2f64.powi(-40),
            2f64.powi(-24),
            2f64.powi(-21),
            2f64.powi(-16),
            2f64.powi(-12),
        ];
        for x in EDGES.into_iter().chain(spread(100_000)) {
            let (r, exact) = (reference(x), (x as f64).sqrt());
            for e in rel {
                for y in [exact * (1.0 + e), exact * (1.0 - e)] {
                    assert_eq!(
                        sqrt_f32_from(x, y).to_bits(),
                        r.to_bits(),
                        "√{x:e} from {y:e}"
                    );
                }
            }
        }
        let too_far = spread(1000)
            .filter(|&x| {
                let y = (x as f64).sqrt() * (1.0 + 2f64.powi(-8));
                sqrt_f32_from(x, y) != reference(x)
            })
            .count();
        assert!(too_far > 0, "a 2⁻⁸ estimate was always corrected");
        // A flushed (zero) or broken estimate is not "corrected" into a
        // huge root: it is returned as it is.
        let x = f32::from_bits(1);
        assert_eq!(sqrt_f32_from(x, 0.0), 0.0);
        assert_eq!(sqrt_f32_from(2.0, f64::INFINITY), f32::INFINITY);
        assert!(sqrt_f32_from(2.0, f64::NAN).is_nan());
    }

    /// The correction alone moves a root one `f32` step off either way
    /// back, and cannot repair two steps (so the Newton step is needed).
    #[test]
    fn the_correction_repairs_one_step() {
        let mut two_steps_repaired = 0;
        for x in EDGES.into_iter().chain(spread(20_000)) {
            let r = reference(x);
            assert_eq!(correct_root(x, true, r).to_bits(), r.to_bits(), "√{x:e}");
            for s in [r.next_up_n(1), r.next_down_n(1)] {
                assert_eq!(
                    correct_root(x, true, s).to_bits(),
                    r.to_bits(),
                    "√{x:e} from {s:e}"
                );
            }
            for s in [r.next_up_n(2), r.next_down_n(2)] {
                two_steps_repaired += usize::from(correct_root(x, true, s) == r);
            }
        }
        assert_eq!(two_steps_repaired, 0);
        // Not positive and finite: left alone.
        assert_eq!(correct_root(0.0, false, 0.0).to_bits(), 0.0f32.to_bits());
        assert!(correct_root(-1.0, false, f32::NAN).is_nan());
    }
}
