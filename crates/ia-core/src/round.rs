//! Portable outward rounding of the basic operations.
//!
//! Each function computes the operation in the default round-to-nearest mode
//! and steps the result one float outward ([`Real::next_down`] /
//! [`Real::next_up`]). Since a round-to-nearest result is within half a float
//! step of the exact value, the stepped value is a sound bound that is at
//! most one float wider than the directed-rounding result. Results known to
//! be exact (an operand is zero, an infinite operand, products of short
//! significands) are not stepped, and on
//! CPUs sums use the exact TwoSum residual to step only when needed (so they
//! equal directed rounding).
//! Nothing here touches the FPU rounding mode, so the same code is sound on
//! SPIR-V and WASM.

use crate::Real;
use crate::math::SQRT_ULPS;

/// The sign of the rounding error of `s = fl(a + b)`: `exact − s` as a float
/// (Knuth's TwoSum, exact for finite `a`, `b`, `s` in round-to-nearest).
///
/// Also on SPIR-V: a driver may reassociate or fuse float operations unless
/// they are decorated `NoContraction`, which the host (`boundtrace-gpu`)
/// adds to every float sum, difference and product of the module before
/// the driver sees it, so the expression is evaluated as written there too.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn sum_residual<T: Real>(a: T, b: T, s: T) -> T {
    let bb = s - a;
    (a - (s - bb)) + (b - bb)
}

/// A lower bound of `a + b`: the directed-rounding result (TwoSum tells
/// whether round-to-nearest rounded up), the same on CPUs and on SPIR-V.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn add_down<T: Real>(a: T, b: T) -> T {
    if a == T::ZERO {
        return b;
    }
    if b == T::ZERO {
        return a;
    }
    let s = a + b;
    // One `next_down` call site (a GPU driver inlines every call:
    // BENCHMARKS.md "GPU").
    let down = if !s.is_finite() {
        // Overflow of finite operands (+∞ → MAX; −∞ stays), or an exact ±∞.
        a.is_finite() && b.is_finite()
    } else {
        // A NaN residual (s − a overflowed on a tie near MAX) means inexact.
        let exact = sum_residual(a, b, s) >= T::ZERO;
        !exact
    };
    if down { s.next_down() } else { s }
}

/// An upper bound of `a + b` (see [`add_down`]).
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn add_up<T: Real>(a: T, b: T) -> T {
    -add_down(-a, -b)
}

/// A lower bound of `a − b`.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn sub_down<T: Real>(a: T, b: T) -> T {
    add_down(a, -b)
}

/// An upper bound of `a − b`.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn sub_up<T: Real>(a: T, b: T) -> T {
    add_up(a, -b)
}

/// Whether `p = fl(a · b)` is exact, by a cheap sufficient test: the
/// operands' significands fit in one (integer bit counts, no FMA needed) and
/// `p` is normal, or an operand is infinite.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn product_is_exact<T: Real>(a: T, b: T, p: T) -> bool {
    if a.is_infinite() || b.is_infinite() {
        return true;
    }
    p.is_finite()
        && p.abs() >= T::min_positive_value()
        && a.significant_bits() + b.significant_bits() <= T::MANTISSA_DIGITS
}

/// A lower bound of `a · b` (`0 · x = 0`, also for infinite `x`); see
/// [`Real::mul_down`] for how each type proves it.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn mul_down<T: Real>(a: T, b: T) -> T {
    a.mul_down(b)
}

/// [`mul_down`] by [`product_is_exact`]: the rounded product, stepped down
/// unless the test proves it exact (`f64`'s [`Real::mul_down`]).
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn mul_down_tested<T: Real>(a: T, b: T) -> T {
    if a == T::ZERO || b == T::ZERO {
        return T::ZERO;
    }
    let p = a * b;
    if product_is_exact(a, b, p) {
        p
    } else {
        p.next_down()
    }
}

/// `f32`'s [`Real::mul_down`]: the exact product of two `f32` values is an
/// `f64` (48 significand bits, exponents far inside `f64`'s range), so the
/// rounded product `p` is a lower bound exactly when `p ≤` that `f64`
/// (compared exactly); otherwise the float below `p` is (round to nearest
/// is off by less than one step). Infinite operands give infinite `p`
/// equal to the `f64` product; an overflowed `p` (`+∞` above a finite
/// product) steps down to `f32::MAX`; NaN stays NaN.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn mul_down_f32(a: f32, b: f32) -> f32 {
    if a == 0.0 || b == 0.0 {
        return 0.0;
    }
    let p = a * b;
    if f64::from(p) <= f64::from(a) * f64::from(b) {
        p
    } else {
        Real::next_down(p)
    }
}

/// An upper bound of `a · b` (`0 · x = 0`, also for infinite `x`).
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn mul_up<T: Real>(a: T, b: T) -> T {
    -mul_down(-a, b)
}

/// A lower bound of `a / b` for `b ≠ 0` (`0 / x` and `x / ±∞` are exact zeros).
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn div_down<T: Real>(a: T, b: T) -> T {
    let q = a.m_div(b);
    if q == T::ZERO && (a == T::ZERO || b.is_infinite()) {
        return T::ZERO;
    }
    q.next_down_n(T::DIV_STEPS)
}

/// An upper bound of `a / b` for `b ≠ 0` (`0 / x` and `x / ±∞` are exact zeros).
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn div_up<T: Real>(a: T, b: T) -> T {
    let q = a.m_div(b);
    if q == T::ZERO && (a == T::ZERO || b.is_infinite()) {
        return T::ZERO;
    }
    q.next_up_n(T::DIV_STEPS)
}

/// A lower bound of `√a` for `a ≥ 0`, never negative.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn sqrt_down<T: Real>(a: T) -> T {
    let r = a.m_sqrt();
    if a == T::ZERO || r.is_infinite() {
        return r;
    }
    r.next_down_n(SQRT_ULPS).max(T::ZERO)
}

/// An upper bound of `√a` for `a ≥ 0`.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn sqrt_up<T: Real>(a: T) -> T {
    let r = a.m_sqrt();
    if a == T::ZERO || r.is_infinite() {
        return r;
    }
    r.next_up_n(SQRT_ULPS)
}

/// `x^n` for `x ≥ 0`, rounded down: binary powering with [`mul_down`].
///
/// Each of the at most 62 products is stepped once; squarings double the
/// relative error, so the bound is within a factor `(1 + ε_mach)^(n−1)`.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn powu_down<T: Real>(x: T, n: u32) -> T {
    powu_dir(x, n, false)
}

/// `x^n` for `x ≥ 0`, rounded up: binary powering with [`mul_up`].
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn powu_up<T: Real>(x: T, n: u32) -> T {
    powu_dir(x, n, true)
}

/// [`mul_down`] (`up = false`) or [`mul_up`] (`up = true`), with a single
/// call of [`mul_down`] (`mul_up(a, b) = −mul_down(−a, b)`; the sign flips
/// are exact): callers that need both directions call it from one place,
/// which keeps the shader small once a GPU driver inlines every call
/// (BENCHMARKS.md "GPU").
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn mul_dir<T: Real>(a: T, b: T, up: bool) -> T {
    let s = if up { -T::ONE } else { T::ONE };
    s * mul_down(s * a, b)
}

/// `x^n` for `x ≥ 0`, rounded down (`up = false`) or up: binary powering
/// with directed products ([`mul_dir`]).
///
/// Loop-free for `n < 16` (the exponents of the kernels): llvmpipe caps
/// the loop iterations of a whole shader invocation (65,535, shared by
/// every loop), which a loop per power would exhaust within a few dozen
/// sphere-tracing steps (BENCHMARKS.md "GPU"). Larger `n` use the loop of
/// [`powu_loop`], with the same products in the same order.
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub(crate) fn powu_dir<T: Real>(x: T, n: u32, up: bool) -> T {
    if n == 0 {
        return T::ONE;
    }
    if n >= 16 {
        return powu_loop(x, n, up);
    }
    let s = (x, T::ONE, false);
    let s = pow_bit(s, n, 0, up);
    let s = pow_bit(s, n, 1, up);
    let s = pow_bit(s, n, 2, up);
    let s = pow_bit(s, n, 3, up);
    // The exact power is ≥ 0; a stepped-down tiny product may be −0⁺.
    s.1.max(T::ZERO)
}

/// Bit `k` of binary powering: the state `(base, acc, have)` with `base`
/// squared (bits above the first) and multiplied into `acc` when bit `k`
/// of `n` is set; unchanged when `n` has no bit at or above `k`.
#[cfg_attr(not(target_arch = "spirv"), inline)]
fn pow_bit<T: Real>(state: (T, T, bool), n: u32, k: u32, up: bool) -> (T, T, bool) {
    let (mut base, mut acc, mut have) = state;
    if n >> k == 0 {
        return state;
    }
    if k > 0 {
        base = mul_dir(base, base, up);
    }
    if (n >> k) & 1 == 1 {
        acc = if have { mul_dir(acc, base, up) } else { base };
        have = true;
    }
    (base, acc, have)
}

/// `xⁿ` in round-to-nearest products, loop-free for `|n| < 16`: binary
/// powering from the lowest bit of `|n|` (`base` squared only while bits
/// remain, the first factor taken as is), then the quotient `1 / p`
/// ([`Math::m_div`](crate::Real), correctly rounded on SPIR-V too) for
/// `n < 0` — the products and order of the standard library's `powi`
/// (compiler-rt's `__powisf2` / `__powidf2`, and LLVM's expansion of a
/// constant exponent), so the same bits. `|n| ≥ 16` runs the same
/// powering in a loop. [`Real::powi_std`] is this function on every
/// target (num-traits' `powi` without `std` inverts before powering,
/// which rounds differently for `n < 0`).
///
/// ```
/// use boundtrace_ia_core::round::powi_unrolled;
/// for n in -15..16 {
///     assert_eq!(powi_unrolled(1.1f32, n), 1.1f32.powi(n));
/// }
/// ```
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn powi_unrolled<T: Real>(x: T, n: i32) -> T {
    let m = n.unsigned_abs();
    if m >= 16 {
        return powi_loop(x, n);
    }
    if m == 0 {
        return T::ONE;
    }
    let s = (x, T::ONE, false);
    let s = powi_bit(s, m, 0);
    let s = powi_bit(s, m, 1);
    let s = powi_bit(s, m, 2);
    let s = powi_bit(s, m, 3);
    if n < 0 { T::ONE.m_div(s.1) } else { s.1 }
}

/// [`powi_unrolled`] for any `n`, in a loop: compiler-rt's `__powisf2`
/// order (`r = 1`, then `r·a` for each set bit from the lowest, `a`
/// squared between bits; `1 / r` for `n < 0`).
#[cfg_attr(not(target_arch = "spirv"), inline)]
fn powi_loop<T: Real>(x: T, n: i32) -> T {
    let mut m = n.unsigned_abs();
    let (mut base, mut r) = (x, T::ONE);
    loop {
        if m & 1 == 1 {
            r = r * base;
        }
        m >>= 1;
        if m == 0 {
            break;
        }
        base = base * base;
    }
    if n < 0 { T::ONE.m_div(r) } else { r }
}

/// [`pow_bit`] with round-to-nearest products, for [`powi_unrolled`].
#[cfg_attr(not(target_arch = "spirv"), inline)]
fn powi_bit<T: Real>(state: (T, T, bool), m: u32, k: u32) -> (T, T, bool) {
    let (mut base, mut acc, mut have) = state;
    if m >> k == 0 {
        return state;
    }
    if k > 0 {
        base = base * base;
    }
    if (m >> k) & 1 == 1 {
        acc = if have { acc * base } else { base };
        have = true;
    }
    (base, acc, have)
}

/// [`powu_dir`] by a loop with one product per iteration (`acc · base`
/// when the current bit of `n` is pending, else the squaring `base ·
/// base`), so the product is written once.
#[cfg_attr(not(target_arch = "spirv"), inline)]
fn powu_loop<T: Real>(x: T, mut n: u32, up: bool) -> T {
    let mut base = x;
    let mut acc = T::ONE;
    let mut have = false;
    let mut pending = n & 1 == 1;
    loop {
        if pending && !have {
            acc = base;
            have = true;
            pending = false;
        }
        let into_acc = pending;
        if !into_acc {
            n >>= 1;
            if n == 0 {
                break;
            }
        }
        let (x, y) = if into_acc { (acc, base) } else { (base, base) };
        let p = mul_dir(x, y, up);
        if into_acc {
            acc = p;
            pending = false;
        } else {
            base = p;
            pending = n & 1 == 1;
        }
    }
    acc.max(T::ZERO)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `f32`'s product bound against the exact product (an `f64`): never
    /// above it, less than one float step below it, and never below the
    /// bit-count test's bound; zeros, infinities, overflow, subnormals and
    /// NaN included.
    #[test]
    fn f32_mul_down_is_the_tightest_lower_bound() {
        let special = [
            0.0f32,
            -0.0,
            1.0,
            -1.0,
            3.0,
            0.1,
            -0.7,
            f32::MAX,
            -f32::MAX,
            f32::MIN_POSITIVE,
            f32::from_bits(1),
            -f32::from_bits(3),
            1.0 + f32::EPSILON,
            f32::INFINITY,
            f32::NEG_INFINITY,
        ];
        // A fixed buffer: the test also runs without `std` (libm back end).
        let mut vals = [0.0f32; 415];
        vals[..special.len()].copy_from_slice(&special);
        let mut x = 0x2545_f491u32;
        for v in &mut vals[special.len()..] {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            let f = f32::from_bits(x);
            *v = if f.is_finite() { f } else { 1.5 };
        }
        for &a in &vals {
            for &b in &vals {
                let lo = mul_down_f32(a, b);
                let hi = -mul_down_f32(-a, b);
                if a == 0.0 || b == 0.0 {
                    assert_eq!((lo, hi), (0.0, 0.0));
                    continue;
                }
                let exact = f64::from(a) * f64::from(b);
                assert!(f64::from(lo) <= exact && exact <= f64::from(hi), "{a} {b}");
                if lo.is_finite() {
                    assert!(
                        f64::from(Real::next_up(lo)) > exact,
                        "{a} {b}: {lo} not tight"
                    );
                }
                assert!(lo >= mul_down_tested(a, b), "{a} {b}");
            }
        }
        assert!(mul_down_f32(f32::NAN, 2.0).is_nan());
        // Exact, but beyond the bit-count test (2 + 23 significant bits):
        // 3·(1 + 2⁻²²) = 3 + 3·2⁻²².
        let (a, b) = (3.0f32, 1.0 + 2.0 * f32::EPSILON);
        assert_eq!(f64::from(a * b), f64::from(a) * f64::from(b));
        assert_eq!(mul_down_f32(a, b), a * b);
        assert!(mul_down_tested(a, b) < a * b);
    }

    /// The GPU's power ([`powi_unrolled`]) against the standard library's
    /// `powi` (compiler-rt), bit for bit, over signs, magnitudes from
    /// subnormal to overflow, the special values and every `|n| < 16`
    /// (and a few beyond, where it falls back to `Float::powi`).
    #[test]
    fn unrolled_powi_equals_std_powi() {
        fn same<T: Real + core::fmt::Debug>(a: T, b: T) -> bool {
            (a.is_nan() && b.is_nan()) || a.as_f64().to_bits() == b.as_f64().to_bits()
        }
        // Special values, then many significands (where the products'
        // roundings differ by order). No `Vec`: the crate's tests also run
        // without `std`.
        let mut xs64 = [0.0f64; 216];
        let special = [
            0.0f64,
            -0.0,
            1e-310,
            1e-300,
            0.3,
            -0.7,
            0.999_999_9,
            1.0,
            -1.0,
            1.1,
            -7.5,
            1e30,
            -1e200,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ];
        xs64[..16].copy_from_slice(&special);
        let mut v = 0.123_456_789_f64;
        for x in &mut xs64[16..] {
            v = (v * 3.7 + 0.31) % 5.0 - 2.5;
            *x = v;
        }
        let ns = (-15..16).chain([16, -16, 17, 31, -40, i32::MIN]);
        for n in ns {
            for &x in &xs64 {
                let (a, b) = (powi_unrolled(x, n), x.powi(n));
                assert!(same(a, b), "{x:e}^{n}: {a:e} vs {b:e}");
                let x = x as f32;
                // Through a variable exponent, as the shader computes it.
                let (a, b) = (powi_unrolled(x, n), x.powi(core::hint::black_box(n)));
                assert!(same(a, b), "{x:e}^{n} (f32): {a:e} vs {b:e}");
                assert!(same(x.powi_std(n), b), "{x:e}^{n} powi_std");
            }
        }
    }

    #[test]
    fn unrolled_powers_equal_the_loop() {
        for x in [
            0.0f64,
            1e-300,
            0.3,
            0.999_999_9,
            1.0,
            1.1,
            7.5,
            1e30,
            f64::INFINITY,
        ] {
            for n in 1..16 {
                for up in [false, true] {
                    let (a, b) = (powu_dir(x, n, up), powu_loop(x, n, up));
                    assert_eq!(a.to_bits(), b.to_bits(), "{x:e}^{n} up {up}");
                }
            }
        }
        for x in [0.3f32, 1.7, 3.0e5] {
            for n in 1..16 {
                assert_eq!(powu_dir(x, n, true), powu_loop(x, n, true), "{x:e}^{n}");
            }
        }
        assert!(powu_down(1.1f64, 40) <= powu_up(1.1f64, 40));
    }

    #[test]
    fn exact_cases_are_not_widened() {
        assert_eq!(add_down(1.5f64, 0.0), 1.5);
        assert_eq!(mul_up(0.0f64, f64::INFINITY), 0.0);
        assert_eq!(div_down(0.0f64, 3.0), 0.0);
        assert_eq!(div_up(3.0f64, f64::INFINITY), 0.0);
        assert_eq!(sqrt_down(0.0f64), 0.0);
        assert_eq!(powu_up(3.0f64, 1), 3.0);
    }

    #[test]
    fn inexact_cases_bracket() {
        let (lo, hi) = (add_down(0.1f64, 0.2), add_up(0.1f64, 0.2));
        assert!(lo <= 0.1 + 0.2 && 0.1 + 0.2 <= hi && lo.next_up() == hi);
        assert_eq!(add_down(1.0f64, 2.0), 3.0);
        assert_eq!(add_down(f64::MAX, f64::MAX), f64::MAX);
        assert_eq!(add_up(f64::MAX, f64::MAX), f64::INFINITY);
        // Exact sum MAX − 1.5·2^971 is a tie: TwoSum's s − a overflows (NaN).
        let a = f64::from_bits(0xfca8000000000000);
        assert!(add_down(a, f64::MAX) < f64::from_bits(0x7feffffffffffffe));
        assert!(div_down(1.0f64, 3.0) < 1.0 / 3.0 && 1.0 / 3.0 < div_up(1.0f64, 3.0));
        assert_eq!(mul_down(f64::MAX, 2.0), f64::MAX);
        assert_eq!(mul_up(f64::MAX, 2.0), f64::INFINITY);
        assert!(powu_down(1.1f64, 10) <= powu_up(1.1f64, 10));
        assert!(sqrt_down(2.0f32) * sqrt_down(2.0f32) < 2.0);
    }
}
